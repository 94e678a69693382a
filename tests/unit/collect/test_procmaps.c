// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_procmaps.c - /proc/PID/maps lines: code of files and the vDSO, deleted noticed */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "collect/procmaps.h"

static void test_procmaps_code_of_a_file(void **state)
{
	struct procmap m;

	assert_int_equal(procmaps_parse_line("7f3a1c028000-7f3a1c19d000 r-xp 00028000 fe:01 "
					     "1835533                    /usr/lib/x86_64-linux-gnu/"
					     "libc.so.6\n", &m), 1);
	assert_true(m.start == 0x7f3a1c028000ULL);
	assert_true(m.end == 0x7f3a1c19d000ULL);
	assert_true(m.pgoff == 0x28000);
	assert_string_equal(m.path, "/usr/lib/x86_64-linux-gnu/libc.so.6");
	assert_false(m.deleted);
}

/* data, anonymous code (JIT) and [stack] are no module */
static void test_procmaps_not_modules(void **state)
{
	struct procmap m;

	assert_int_equal(procmaps_parse_line("55d0c2a3c000-55d0c2a3d000 rw-p 00003000 fe:01 "
					     "123 /usr/bin/ctrl\n", &m), 0);
	assert_int_equal(procmaps_parse_line("7f0000000000-7f0000001000 rwxp 00000000 00:00 0 \n",
					     &m), 0);
	assert_int_equal(procmaps_parse_line("garbage\n", &m), -1);
	assert_int_equal(procmaps_parse_line("2000-1000 r-xp 0 0:0 0 /x\n", &m), -1);
}

/* the vDSO: a module without a file (its image is in the process) */
static void test_procmaps_vdso(void **state)
{
	struct procmap m;

	assert_int_equal(procmaps_parse_line("7ffd5e1e5000-7ffd5e1e7000 r-xp 00000000 00:00 0"
					     "                          [vdso]\n", &m), 1);
	assert_true(procmap_is_vdso(&m));
	assert_true(m.start == 0x7ffd5e1e5000ULL && m.pgoff == 0);
	/* without a newline at the end too; [vvar] (data) and [vsyscall] are not it */
	assert_int_equal(procmaps_parse_line("7ffd5e1e5000-7ffd5e1e7000 r-xp 00000000 00:00 0 "
					     "[vdso]", &m), 1);
	assert_int_equal(procmaps_parse_line("7ffd5e1e1000-7ffd5e1e5000 r--p 00000000 00:00 0 "
					     "[vvar]\n", &m), 0);
	assert_int_equal(procmaps_parse_line("ffffffffff600000-ffffffffff601000 --xp 00000000 "
					     "00:00 0 [vsyscall]\n", &m), 0);
	assert_int_equal(procmaps_parse_line("7ffd5e1e5000-7ffd5e1e7000 r-xp 00000000 00:00 0 "
					     "[vdso]x\n", &m), 0);
}

/* a file deleted (or replaced by a new inode) while mapped */
static void test_procmaps_deleted(void **state)
{
	struct procmap m;

	assert_int_equal(procmaps_parse_line("400000-401000 r-xp 00001000 fe:01 77 "
					     "/opt/ctrl/bin/ctrl (deleted)\n", &m), 1);
	assert_true(m.deleted);
	assert_string_equal(m.path, "/opt/ctrl/bin/ctrl");
}

static void test_procmaps_read_keeps_code_only(void **state)
{
	const char text[] =
		"55d0c2a39000-55d0c2a3a000 r--p 00000000 fe:01 123 /usr/bin/ctrl\n"
		"55d0c2a3a000-55d0c2a3b000 r-xp 00001000 fe:01 123 /usr/bin/ctrl\n"
		"7f3a1c028000-7f3a1c19d000 r-xp 00028000 fe:01 99 /usr/lib/libc.so.6\n"
		"7ffd5e1e5000-7ffd5e1e7000 r-xp 00000000 00:00 0 [vdso]\n";
	FILE *f = fmemopen((void *)text, sizeof(text) - 1, "r");
	struct procmap *v = NULL;

	assert_non_null(f);
	assert_int_equal(procmaps_read(f, &v), 3);
	assert_string_equal(v[0].path, "/usr/bin/ctrl");
	assert_true(v[0].start - v[0].pgoff == 0x55d0c2a39000ULL);	/* the load base */
	assert_string_equal(v[1].path, "/usr/lib/libc.so.6");
	assert_string_equal(v[2].path, "[vdso]");
	free(v);
	fclose(f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_procmaps_code_of_a_file),
		cmocka_unit_test(test_procmaps_not_modules),
		cmocka_unit_test(test_procmaps_vdso),
		cmocka_unit_test(test_procmaps_deleted),
		cmocka_unit_test(test_procmaps_read_keeps_code_only),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
