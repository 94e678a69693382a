// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_supervise.c - supervise_interval gives the checks what they read:
 * the lifetime's percentiles, which model_set leaves due, settled for a
 * rule that checks the totals (lifetime: true), and left due otherwise.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "judge/supervise.h"
#include "stats.h"

#define US 1000ULL
#define MS 1000000ULL

struct fx {
	struct config cfg;
	struct supervisor s;
	struct model m;
	struct thread_model *tm;
	struct rtsup_thread t;
	struct self_in self;
};

/* cycles - n cycles of the thread, each with a wakeup latency of 'lat' ns */
static void cycles(struct rtsup_thread *t, int n, __u64 lat, __u32 epoch)
{
	struct rtsup_cycle c;
	int i;

	memset(&c, 0, sizeof(c));
	c.flags = RTSUP_CF_HAS_LATENCY;
	c.exec = c.cpu = 50 * US;
	c.latency = lat;
	for (i = 0; i < n; i++)
		thread_account_cycle(t, &c, 102, epoch);
}

static int setup(void **state)
{
	struct fx *f = calloc(1, sizeof(*f));
	int i;

	if (!f)
		return -1;
	config_defaults(&f->cfg);
	f->cfg.defaults.th.latency_p99_warn_ns = 100 * US;
	f->cfg.defaults.th.latency_max_warn_ns = 0;
	f->cfg.defaults.th.latency_max_error_ns = 0;
	for (i = 0; i < RTSUP_M_NR; i++)
		metric_init(&f->t.m[i]);
	f->t.first_seen = 1;
	f->self.overhead_pct = -1;
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	struct fx *f = *state;

	model_free(&f->m);
	supervise_free(&f->s);
	free(f);
	return 0;
}

/* start - the supervisor with its configuration, one SCHED_FIFO thread */
static void start(struct fx *f, bool lifetime)
{
	f->cfg.defaults.th.lifetime = lifetime;
	supervise_init(&f->s, &f->cfg);
	f->tm = model_get(&f->m, 42, true);
	assert_non_null(f->tm);
	f->tm->rule = -1;
	f->tm->policy = 1;
	f->tm->alive = true;
	strcpy(f->tm->comm, "ctl");
}

/* interval - the snapshot taken, the interval judged at 'now' */
static void interval(struct fx *f, __u32 bank, __u64 now)
{
	model_set(f->tm, &f->t, bank);
	supervise_interval(&f->s, &f->m, bank, &f->self, now);
}

/*
 * 200 cycles woken 500 us late, then 10 on time: the interval's p99 is
 * fine, the lifetime's is not. With lifetime: true the totals' check says
 * so, from percentiles model_set did not compute.
 */
static void test_supervise_lifetime_checks_read_settled_percentiles(void **state)
{
	struct fx *f = *state;

	start(f, true);
	cycles(&f->t, 200, 500 * US, 0);
	interval(f, 0, 1 * MS);
	assert_int_equal(f->tm->st.level, LEVEL_WARN);
	assert_int_equal(f->tm->st.nmsg, 2);	/* the interval's, and the totals' */

	cycles(&f->t, 10, 10 * US, 1);
	interval(f, 1, 2 * MS);
	assert_int_equal(f->tm->life_due, 0);
	assert_int_equal(f->tm->win.m[RTSUP_M_LATENCY].count, 10);
	assert_true(f->tm->win.m[RTSUP_M_LATENCY].p99 < 100 * US);
	assert_int_equal(f->tm->st.level, LEVEL_WARN);
	assert_int_equal(f->tm->st.nmsg, 1);
	assert_non_null(strstr(f->tm->st.msg[0], "wakeup latency p99 5"));
}

/* without lifetime checks the same run leaves the lifetime's percentiles due */
static void test_supervise_window_checks_leave_life_due(void **state)
{
	struct fx *f = *state;

	start(f, false);
	cycles(&f->t, 200, 500 * US, 0);
	interval(f, 0, 1 * MS);
	cycles(&f->t, 10, 10 * US, 1);
	interval(f, 1, 2 * MS);
	assert_int_equal(f->tm->st.level, LEVEL_OK);
	assert_true(f->tm->life_due & (1u << RTSUP_M_LATENCY));
	assert_int_equal(f->tm->life.m[RTSUP_M_LATENCY].p99, 0);
	model_life_settle(f->tm);
	assert_int_equal(f->tm->life.m[RTSUP_M_LATENCY].p99 / (100 * US), 5);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_supervise_lifetime_checks_read_settled_percentiles,
						setup, teardown),
		cmocka_unit_test_setup_teardown(test_supervise_window_checks_leave_life_due, setup,
						teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
