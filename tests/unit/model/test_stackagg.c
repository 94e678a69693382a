// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_stackagg.c - stacks of RT-unsafe events: counted per thread, reason, stack; the text */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "model/stackagg.h"

/* frame - a frame with a function and line, or module+offset only */
static struct stack_frame frame(const char *func, const char *file, int line,
				const char *module, __u64 offset)
{
	struct stack_frame f;

	memset(&f, 0, sizeof(f));
	snprintf(f.func, sizeof(f.func), "%s", func);
	snprintf(f.file, sizeof(f.file), "%s", file);
	f.line = line;
	snprintf(f.module, sizeof(f.module), "%s", module);
	f.offset = offset;
	f.pc = 0x55550000 + offset;
	return f;
}

static void ctrl_stack(struct stack_frame *f)
{
	f[0] = frame("ctrl_update", "/src/ctrl.c", 88, "/usr/bin/ctrl", 0x1234);
	f[1] = frame("ctrl_loop", "/src/ctrl.c", 41, "/usr/bin/ctrl", 0x1300);
	f[2] = frame("start_thread", "", 0, "/usr/lib/x86_64-linux-gnu/libc.so.6", 0x89134);
}

/* the line: "mmap 12x ... from ctrl_update() ctrl.c:88 <- ctrl_loop() ..." */
static void test_stackagg_same_stack_counts_once(void **state)
{
	struct stackagg a = { 0 };
	struct stack_frame f[3];
	char buf[512];
	int i;

	ctrl_stack(f);
	for (i = 0; i < 12; i++)
		assert_int_equal(stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3), 0);
	assert_int_equal(a.n, 1);
	assert_int_equal(a.e[0].total, 12);
	assert_int_equal(stack_entry_interval(&a.e[0]), 12);
	stack_format(a.e[0].frames, a.e[0].nframes, " <- ", buf, sizeof(buf));
	assert_string_equal(buf, "ctrl_update() ctrl.c:88 <- ctrl_loop() ctrl.c:41 <- "
				 "start_thread() (libc.so.6+0x89134)");
	stackagg_free(&a);
}

/* thread, reason, syscall and any frame tell entries apart */
/* auto and rules: one stack may be taken by either unwinder; each is noted, not counted apart */
static void test_stackagg_kinds(void **state)
{
	struct stackagg a = { 0 };
	struct stack_frame f[3];

	(void)state;
	ctrl_stack(f);
	assert_int_equal(stackagg_add_kind(&a, 7, 7, "ctrl", RTSUP_U_SYSCALL, 9,
					   RTSUP_STACKS_DWARF, f, 3), 0);
	assert_int_equal(a.e[0].kinds, 1u << RTSUP_STACKS_DWARF);
	stackagg_add_kind(&a, 7, 7, "ctrl", RTSUP_U_SYSCALL, 9, RTSUP_STACKS_FP, f, 3);
	assert_int_equal(a.n, 1);
	assert_int_equal(a.e[0].total, 2);
	assert_int_equal(a.e[0].kinds, (1u << RTSUP_STACKS_DWARF) | (1u << RTSUP_STACKS_FP));
	/* unknown (an older recording): nothing noted */
	stackagg_add(&a, 8, 8, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	assert_int_equal(a.e[1].kinds, 0);
	stackagg_free(&a);
}

static void test_stackagg_keys(void **state)
{
	struct stackagg a = { 0 };
	struct stack_frame f[3], g[3];

	ctrl_stack(f);
	ctrl_stack(g);
	g[1].offset = 0x1310;	/* another call site in ctrl_loop */
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	stackagg_add(&a, 8, 5, "ctrl2", RTSUP_U_SYSCALL, 9, f, 3);	/* thread */
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 11, f, 3);	/* syscall */
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_BLOCK, 0, f, 3);		/* reason */
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, g, 3);	/* stack */
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 2);	/* depth */
	assert_int_equal(a.n, 6);
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	assert_int_equal(a.n, 6);
	assert_int_equal(a.e[0].total, 2);
	stackagg_free(&a);
}

/* the same code at another address (ASLR, another run) is the same stack */
static void test_stackagg_hash_by_module_offset(void **state)
{
	struct stack_frame f[3], g[3];

	ctrl_stack(f);
	ctrl_stack(g);
	g[0].pc += 0x100000;
	g[1].pc += 0x100000;
	assert_true(stack_hash(f, 3) == stack_hash(g, 3));
	/* outside any module only the address tells frames apart */
	f[2].module[0] = g[2].module[0] = '\0';
	g[2].pc++;
	assert_false(stack_hash(f, 3) == stack_hash(g, 3));
}

/* each interval counts its own events; the run's total goes on */
static void test_stackagg_interval(void **state)
{
	struct stackagg a = { 0 };
	struct stack_frame f[3];

	ctrl_stack(f);
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	stackagg_interval_end(&a);
	assert_int_equal(stack_entry_interval(&a.e[0]), 0);
	stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	assert_int_equal(stack_entry_interval(&a.e[0]), 1);
	assert_int_equal(a.e[0].total, 3);
	stackagg_free(&a);
}

/* beyond STACKAGG_MAX distinct stacks, events are counted, not lost */
static void test_stackagg_full_counts(void **state)
{
	struct stackagg a = { 0 };
	struct stack_frame f[3];
	int i;

	ctrl_stack(f);
	for (i = 0; i < STACKAGG_MAX + 10; i++) {
		f[0].offset = i;
		stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3);
	}
	assert_int_equal(a.n, STACKAGG_MAX);
	assert_int_equal(a.not_kept, 10);
	/* a stack already kept still counts */
	f[0].offset = 0;
	assert_int_equal(stackagg_add(&a, 7, 5, "ctrl", RTSUP_U_SYSCALL, 9, f, 3), 0);
	assert_int_equal(a.e[0].total, 2);
	stackagg_free(&a);
}

/* what is known is shown, nothing is made up */
static void test_frame_format_known_and_unknown(void **state)
{
	struct stack_frame f = frame("", "", 0, "/opt/x/libfoo.so", 0x1234);
	char buf[256];

	frame_format(&f, buf, sizeof(buf));
	assert_string_equal(buf, "libfoo.so+0x1234");
	strcpy(f.build_id, "0123456789abcdef0123456789abcdef01234567");
	frame_format(&f, buf, sizeof(buf));
	assert_string_equal(buf, "libfoo.so+0x1234 (build-id 0123456789ab)");
	f.flags = FRAME_REPLACED;
	frame_format(&f, buf, sizeof(buf));
	assert_string_equal(buf, "libfoo.so+0x1234 (build-id 0123456789ab) [replaced on disk]");
	f = frame("", "", 0, "", 0);
	f.pc = 0x7f0012345678;
	frame_format(&f, buf, sizeof(buf));
	assert_string_equal(buf, "[unknown] 0x7f0012345678");
	f.pc = 0;
	frame_format(&f, buf, sizeof(buf));
	assert_string_equal(buf, "[unknown]");
	stack_format(&f, 0, " <- ", buf, sizeof(buf));
	assert_string_equal(buf, "[no user stack]");
}

/* a demangled C++ name carries its parameters: no second "()" */
static void test_frame_format_cpp(void **state)
{
	struct stack_frame f = frame("ctrl::Loop::update(long)", "/src/loop.cpp", 36,
				     "/usr/bin/loop", 0x1234);
	char buf[256];

	frame_format(&f, buf, sizeof(buf));
	assert_string_equal(buf, "ctrl::Loop::update(long) loop.cpp:36");
}

/* a long stack is cut at the buffer, never overruns it */
static void test_stack_format_truncates(void **state)
{
	struct stack_frame f[STACK_MAX_FRAMES];
	char buf[64];
	int i;

	for (i = 0; i < STACK_MAX_FRAMES; i++)
		f[i] = frame("a_rather_long_function_name", "/src/x.c", i + 1, "/bin/x", i);
	memset(buf, 'Z', sizeof(buf));
	stack_format(f, STACK_MAX_FRAMES, " <- ", buf, 40);
	assert_int_equal(strlen(buf), 39);
	assert_int_equal(buf[41], 'Z');
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stackagg_same_stack_counts_once),
		cmocka_unit_test(test_stackagg_keys),
		cmocka_unit_test(test_stackagg_kinds),
		cmocka_unit_test(test_stackagg_hash_by_module_offset),
		cmocka_unit_test(test_stackagg_interval),
		cmocka_unit_test(test_stackagg_full_counts),
		cmocka_unit_test(test_frame_format_known_and_unknown),
		cmocka_unit_test(test_stack_format_truncates),
		cmocka_unit_test(test_frame_format_cpp),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
