// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_causes.c - deadline misses grouped by cause and culprit
 * (user/model/causes.c), their text, and the verdict's short form.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "model/causes.h"
#include "model/model.h"
#include "model/syscalls.h"

#define MS 1000000ULL

static struct rtsup_cause cause(__u32 kind, __u32 who_tid, const char *comm, __u64 ns)
{
	struct rtsup_cause c;

	memset(&c, 0, sizeof(c));
	c.kind = kind;
	c.ns = ns;
	c.who.tid = who_tid;
	c.who.tgid = who_tid;
	c.who.policy = 1;
	c.who.prio = 99;
	strncpy(c.who.comm, comm, sizeof(c.who.comm) - 1);
	return c;
}

/* every miss counted in its group: by thread, kind and culprit, longest first */
static void test_causes_grouped_by_thread_kind_culprit(void **state)
{
	struct causes cs = { 0 };
	struct rtsup_cause w = cause(RTSUP_CAUSE_WAIT, 812, "noise-hog", 3 * MS);
	struct rtsup_cause b = cause(RTSUP_CAUSE_BACKLOG, 812, "noise-hog", 2 * MS);
	struct rtsup_cause t = cause(RTSUP_CAUSE_TIMER, 0, "", 1 * MS);
	const struct cause_group *g;
	size_t n;

	causes_add(&cs, 100, &t);
	causes_add(&cs, 100, &w);
	causes_add(&cs, 100, &b);
	w.ns = 2 * MS;
	causes_add(&cs, 100, &w);
	causes_add(&cs, 7, &w);	/* another thread: its own group */
	causes_sort(&cs);
	g = causes_of(&cs, 100, &n);
	assert_int_equal(n, 3);
	assert_int_equal(g[0].kind, RTSUP_CAUSE_WAIT);
	assert_int_equal(g[0].count, 2);
	assert_int_equal(g[0].total_ns, 5 * MS);
	assert_int_equal(g[0].max_ns, 3 * MS);
	assert_int_equal(g[1].kind, RTSUP_CAUSE_BACKLOG);
	assert_int_equal(g[2].kind, RTSUP_CAUSE_TIMER);
	g = causes_of(&cs, 7, &n);
	assert_int_equal(n, 1);
	assert_null(causes_of(&cs, 8, &n));
	assert_int_equal(n, 0);
	causes_free(&cs);
}

/* the text a person reads first: the cause, then the numbers */
static void test_causes_text(void **state)
{
	struct rtsup_cause c = cause(RTSUP_CAUSE_WAIT, 812, "noise-hog", 3100000);
	char buf[200];

	causes_text(buf, sizeof(buf), c.kind, 0, c.ns, &c.who, &c, 0);
	assert_string_equal(buf, "woken, then waited 3.100 ms for the CPU behind "
				 "noise-hog[812] FIFO/99");
	/* our own threads say so */
	causes_text(buf, sizeof(buf), c.kind, 0, c.ns, &c.who, &c, 812);
	assert_non_null(strstr(buf, "(rtsup-trace itself)"));
	c = cause(RTSUP_CAUSE_BLOCK, 900, "owner", 2 * MS);
	c.who.prio = 10;
	c.block_op = 1;	/* FUTEX_WAIT + 1 */
	causes_text(buf, sizeof(buf), c.kind, RTSUP_CAUSE_F_INVERSION, c.ns, &c.who, &c, 0);
	assert_string_equal(buf, "blocked 2.000 ms in futex FUTEX_WAIT, woken by owner[900] "
				 "FIFO/10: priority inversion");
	c = cause(RTSUP_CAUSE_TIMER, 0, "", 4600000);
	causes_text(buf, sizeof(buf), c.kind, RTSUP_CAUSE_F_IDLE, c.ns, &c.who, &c, 0);
	assert_string_equal(buf, "woken 4.600 ms after its release: machine / timer latency "
				 "(idle CPU: idle exit)");
	/* a wait behind no task: the idle task held the CPU, the machine's */
	c = cause(RTSUP_CAUSE_WAIT, 0, "", 90 * MS);
	causes_text(buf, sizeof(buf), c.kind, RTSUP_CAUSE_F_IDLE, c.ns, &c.who, &c, 0);
	assert_string_equal(buf, "woken, then waited 90.000 ms for its idle CPU: machine latency "
				 "(idle exit, interrupts or hypervisor)");
	c = cause(RTSUP_CAUSE_STEAL, 0, "", 2500000);
	causes_text(buf, sizeof(buf), c.kind, 0, c.ns, &c.who, &c, 0);
	assert_string_equal(buf, "the hypervisor ran something else on its vCPU for 2.500 ms "
				 "while it ran: machine latency (steal)");
	assert_string_equal(cause_kind_name(RTSUP_CAUSE_STEAL), "steal");
}

/*
 * a run's table of thousands of groups (2000 threads, 5 culprits each):
 * every miss finds its group through the index, before and after a sort
 * moved the groups, and causes_of finds each thread's by its search; the
 * counts are what the misses were (no group twice, none lost)
 */
static void test_causes_many_groups_indexed(void **state)
{
	enum { THREADS = 2000, CULPRITS = 5, ROUNDS = 3 };
	struct causes cs = { 0 };
	const struct cause_group *g;
	__u32 tid, who, r;
	size_t n, k;

	for (r = 0; r < ROUNDS; r++) {
		for (k = 0; k < THREADS * CULPRITS; k++) {
			/* a stride coprime with the count: every pair once a round, shuffled */
			size_t x = (k * 7919) % (THREADS * CULPRITS);
			struct rtsup_cause c = cause(RTSUP_CAUSE_PREEMPT, 0, "hog", (x % 97 + 1) * MS);

			tid = 1000 + (__u32)(x / CULPRITS);
			who = 50 + (__u32)(x % CULPRITS);
			c.who.tid = who;
			causes_add(&cs, tid, &c);
		}
		causes_sort(&cs);	/* the groups move: the index follows */
		assert_int_equal(cs.n, THREADS * CULPRITS);
	}
	for (tid = 1000; tid < 1000 + THREADS; tid++) {
		g = causes_of(&cs, tid, &n);
		assert_non_null(g);
		assert_int_equal(n, CULPRITS);
		for (k = 0; k < n; k++) {
			assert_int_equal(g[k].tid, tid);
			assert_int_equal(g[k].count, ROUNDS);
		}
	}
	assert_null(causes_of(&cs, 999, &n));
	assert_int_equal(n, 0);
	assert_null(causes_of(&cs, 1000 + THREADS, &n));
	causes_clear(&cs);	/* an interval's table: empty, its index too */
	assert_null(causes_of(&cs, 1000, &n));
	{
		struct rtsup_cause c = cause(RTSUP_CAUSE_WAIT, 9, "x", MS);

		causes_add(&cs, 1000, &c);
		causes_add(&cs, 1000, &c);
		assert_int_equal(cs.n, 1);
		assert_int_equal(cs.g[0].count, 2);
	}
	causes_free(&cs);
}

/* the verdict's short form: the top group of each thread, interval and life */
static void test_causes_to_model(void **state)
{
	struct causes win = { 0 }, life = { 0 };
	struct rtsup_cause c = cause(RTSUP_CAUSE_PREEMPT, 812, "noise-hog", 3100000);
	struct thread_model t[2];
	struct thread_model *pt[2] = { &t[0], &t[1] };
	struct model m;

	memset(&m, 0, sizeof(m));
	memset(t, 0, sizeof(t));
	t[0].tid = 100;
	t[1].tid = 101;
	strcpy(t[1].why_win, "stale");
	m.t = pt;
	m.n = 2;
	causes_add(&win, 100, &c);
	causes_add(&life, 100, &c);
	causes_add(&life, 100, &c);
	causes_sort(&win);
	causes_sort(&life);
	causes_to_model(&win, &life, &m);
	assert_string_equal(t[0].why_win, "1 caused by noise-hog[812] FIFO/99 (preemption, "
					  "3.1 ms max)");
	assert_string_equal(t[0].why_life, "2 caused by noise-hog[812] FIFO/99 (preemption, "
					   "3.1 ms max)");
	assert_string_equal(t[1].why_win, "");
	causes_free(&win);
	causes_free(&life);
}

/*
 * a hypervisor's late wakeups and the releases they swallowed: the
 * backlogs behind no task say what they follow, group apart by it, and
 * count with the late wakeups in the verdict
 */
static void test_causes_backlog_after_the_machine(void **state)
{
	struct causes cs = { 0 };
	struct rtsup_cause t = cause(RTSUP_CAUSE_TIMER, 0, "", 90 * MS);
	struct rtsup_cause b = cause(RTSUP_CAUSE_BACKLOG, 0, "", 60 * MS);
	struct rtsup_cause e = cause(RTSUP_CAUSE_BACKLOG, 0, "", 1 * MS);
	const struct cause_group *g;
	struct thread_model tm, *ptm = &tm;
	struct model m;
	char buf[200];
	size_t n;
	int i;

	b.after = RTSUP_CAUSE_TIMER;
	e.after = RTSUP_CAUSE_EXEC;
	causes_add(&cs, 100, &t);
	for (i = 0; i < 4; i++)
		causes_add(&cs, 100, &b);
	causes_add(&cs, 100, &e);
	causes_sort(&cs);
	g = causes_of(&cs, 100, &n);
	assert_int_equal(n, 3);
	assert_int_equal(g[0].kind, RTSUP_CAUSE_BACKLOG);
	assert_int_equal(g[0].after, RTSUP_CAUSE_TIMER);
	assert_int_equal(g[0].count, 4);
	causes_group_text(buf, sizeof(buf), &g[0], 0);
	assert_string_equal(buf, "released 60.000 ms late: the cycle before ended late "
				 "(machine / timer latency)");
	causes_group_text(buf, sizeof(buf), &g[2], 0);
	assert_string_equal(buf, "released 1.000 ms late: the cycle before ended late "
				 "(its own CPU time)");
	memset(&m, 0, sizeof(m));
	memset(&tm, 0, sizeof(tm));
	tm.tid = 100;
	m.t = &ptm;
	m.n = 1;
	causes_to_model(&cs, &cs, &m);
	/* the timer's 1 and the 4 backlogs after it; not the one after its own CPU time */
	assert_string_equal(tm.why_win, "5 caused by machine / timer latency (90.0 ms max)");
	causes_free(&cs);
}

/* the syscall an unsafe event names: made, or waited in by a block (+ 1), or none */
static void test_unsafe_event_syscall(void **state)
{
	struct rtsup_event e = { .type = RTSUP_EV_UNSAFE, .arg = RTSUP_U_SYSCALL };

	(void)state;
	e.arg2 = syscall_nr("mmap");
	assert_string_equal(unsafe_event_syscall(&e), "mmap");
	e.arg = RTSUP_U_BLOCK;
	e.arg2 = syscall_nr("futex") + 1;
	assert_string_equal(unsafe_event_syscall(&e), "futex");
	e.arg2 = 0;	/* a page fault's, or not known */
	assert_null(unsafe_event_syscall(&e));
	e.arg = RTSUP_U_MINFLT;
	e.arg2 = 3;	/* a count, no syscall */
	assert_null(unsafe_event_syscall(&e));
	e.type = RTSUP_EV_MISS;
	assert_null(unsafe_event_syscall(&e));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_causes_grouped_by_thread_kind_culprit),
		cmocka_unit_test(test_causes_text),
		cmocka_unit_test(test_causes_many_groups_indexed),
		cmocka_unit_test(test_causes_to_model),
		cmocka_unit_test(test_causes_backlog_after_the_machine),
		cmocka_unit_test(test_unsafe_event_syscall),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
