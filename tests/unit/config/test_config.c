// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_config.c - the YAML configuration: defaults, parsing, matching, errors */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sched.h>
#include <signal.h>
#include <unistd.h>
#include <cmocka.h>

#include "config/config.h"
#include "config/stackopt.h"
#include "config/strict.h"
#include "model/syscalls.h"
#include "can.h"

/* test files, relative to the project root (make unit runs from there) */
#define DIR	"tests/unit/config/"
#define ALL_SET	(RF_PERIOD | RF_EWMA | RF_DELIMS | RF_POLICY | RF_PRIO | RF_ALLOW | \
		 RF_FORBID)

/* load_ok - load a file that must be valid */
static void load_ok(const char *path, struct config *c)
{
	char err[512] = "";
	int ret;

	config_defaults(c);
	ret = config_load(path, c, err, sizeof(err));
	if (ret)
		print_error("%s\n", err);
	assert_int_equal(ret, 0);
}

/* expect_bad - a file that must fail with exactly this message */
static void expect_bad(const char *path, const char *msg)
{
	struct config c;
	char err[512] = "";

	config_defaults(&c);
	assert_int_equal(config_load(path, &c, err, sizeof(err)), -1);
	assert_string_equal(err, msg);
	/* untouched: still the built-in defaults, no rules, no nodes */
	assert_null(c.rules);
	assert_int_equal(c.nrules, 0);
	assert_null(c.can.nodes);
	assert_int_equal(c.can.nnodes, 0);
	assert_null(c.actions);
	assert_string_equal(c.path, "");
}

/* th_equal - two threshold sets are the same */
static void th_equal(const struct thresholds *a, const struct thresholds *b)
{
	int i;

	assert_true(a->init_timeout_s == b->init_timeout_s);
	assert_int_equal(a->miss_warn, b->miss_warn);
	assert_true(a->miss_error_rate == b->miss_error_rate);
	assert_true(a->exec_warn_ratio == b->exec_warn_ratio);
	assert_int_equal(a->exec_stat, b->exec_stat);
	assert_true(a->starve_warn_periods == b->starve_warn_periods);
	assert_true(a->starve_error_periods == b->starve_error_periods);
	assert_int_equal(a->unsafe_warn, b->unsafe_warn);
	for (i = 0; i < RTSUP_U_NR; i++)
		assert_int_equal(a->unsafe_error[i], b->unsafe_error[i]);
	assert_int_equal(a->latency_p99_warn_ns, b->latency_p99_warn_ns);
	assert_int_equal(a->latency_max_warn_ns, b->latency_max_warn_ns);
	assert_int_equal(a->latency_max_error_ns, b->latency_max_error_ns);
	assert_int_equal(a->jitter_warn_ns, b->jitter_warn_ns);
	assert_int_equal(a->jitter_error_ns, b->jitter_error_ns);
	assert_true(a->overhead_warn_pct == b->overhead_warn_pct);
	assert_true(a->overhead_error_pct == b->overhead_error_pct);
	assert_int_equal(a->lifetime, b->lifetime);
}

/* rule_equal - two rules are the same (line aside: where it was written) */
static void rule_equal(const struct rule *a, const struct rule *b)
{
	int i;

	assert_string_equal(a->name, b->name);
	assert_string_equal(a->match_process, b->match_process);
	assert_string_equal(a->match_thread, b->match_thread);
	assert_string_equal(a->match_cgroup, b->match_cgroup);
	assert_int_equal(a->set, b->set);
	assert_int_equal(a->period_ns, b->period_ns);
	assert_true(a->ewma_weight == b->ewma_weight);
	assert_int_equal(a->ndelims, b->ndelims);
	for (i = 0; i < a->ndelims; i++)
		assert_string_equal(a->delims[i], b->delims[i]);
	assert_int_equal(a->policy, b->policy);
	assert_int_equal(a->prio, b->prio);
	assert_int_equal(a->stacks, b->stacks);
	assert_int_equal(a->stack_size, b->stack_size);
	assert_int_equal(a->nallow, b->nallow);
	for (i = 0; i < a->nallow; i++)
		assert_string_equal(a->allow[i], b->allow[i]);
	assert_int_equal(a->nforbid, b->nforbid);
	for (i = 0; i < a->nforbid; i++)
		assert_string_equal(a->forbid[i], b->forbid[i]);
	th_equal(&a->th, &b->th);
}

/* can_th_equal - two CAN threshold sets are the same */
static void can_th_equal(const struct can_thresholds *a, const struct can_thresholds *b)
{
	assert_true(a->warn_periods == b->warn_periods);
	assert_true(a->error_periods == b->error_periods);
	assert_int_equal(a->jitter_warn_ns, b->jitter_warn_ns);
	assert_int_equal(a->jitter_error_ns, b->jitter_error_ns);
	assert_true(a->learn_s == b->learn_s);
	assert_true(a->init_timeout_s == b->init_timeout_s);
}

/* can_equal - two can: sections are the same (node lines aside) */
static void can_equal(const struct can_config *a, const struct can_config *b)
{
	int i;

	assert_int_equal(a->canopen, b->canopen);
	assert_int_equal(a->bitrate, b->bitrate);
	assert_true(a->busload_warn == b->busload_warn);
	assert_true(a->busload_error == b->busload_error);
	assert_int_equal(a->err_warn, b->err_warn);
	assert_int_equal(a->err_error, b->err_error);
	assert_int_equal(a->heartbeat_timeout_ns, b->heartbeat_timeout_ns);
	can_th_equal(&a->defaults, &b->defaults);
	assert_int_equal(a->nnodes, b->nnodes);
	for (i = 0; i < a->nnodes; i++) {
		const struct can_node *x = &a->nodes[i], *y = &b->nodes[i];

		assert_string_equal(x->name, y->name);
		assert_string_equal(x->iface, y->iface);
		assert_int_equal(x->id_lo, y->id_lo);
		assert_int_equal(x->id_hi, y->id_hi);
		assert_int_equal(x->dir, y->dir);
		assert_int_equal(x->period_ns, y->period_ns);
		assert_string_equal(x->group, y->group);
		can_th_equal(&x->th, &y->th);
	}
}

/* the built-in defaults, as documented */
static void test_config_defaults(void **state)
{
	struct config c;
	const struct rule *d = &c.defaults;

	config_defaults(&c);
	assert_string_equal(c.path, "");
	assert_null(c.rules);
	assert_int_equal(c.nrules, 0);
	assert_int_equal(d->set, 0);
	assert_int_equal(d->period_ns, 0);
	assert_true(d->ewma_weight == 0.1);
	assert_int_equal(d->ndelims, 2);
	assert_string_equal(d->delims[0], "clock_nanosleep");
	assert_string_equal(d->delims[1], "nanosleep");
	assert_int_equal(d->policy, -1);
	assert_int_equal(d->prio, -1);
	assert_int_equal(d->nallow, 0);
	assert_int_equal(d->nforbid, 0);
	assert_true(d->th.init_timeout_s == 5);
	assert_int_equal(d->th.miss_warn, 1);
	assert_true(d->th.miss_error_rate == 0.01);
	assert_true(d->th.exec_warn_ratio == 0.8);
	assert_int_equal(d->th.exec_stat, EXEC_STAT_P99);
	assert_true(d->th.starve_warn_periods == 10);
	assert_true(d->th.starve_error_periods == 100);
	assert_int_equal(d->th.unsafe_warn, 1);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_SYSCALL], 0);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_MINFLT], 0);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_MAJFLT], 1);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_BLOCK], 0);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_MIGRATE], 0);
	assert_int_equal(d->th.latency_p99_warn_ns, 0);
	assert_int_equal(d->th.latency_max_warn_ns, 0);
	assert_int_equal(d->th.latency_max_error_ns, 0);
	assert_int_equal(d->th.jitter_warn_ns, 0);
	assert_int_equal(d->th.jitter_error_ns, 0);
	assert_true(d->th.overhead_warn_pct == 1);
	assert_true(d->th.overhead_error_pct == 5);
	assert_false(d->th.lifetime);
}

/* the built-in can: section, as documented */
static void test_config_can_defaults(void **state)
{
	struct config c, e;
	const struct can_config *cc = &c.can;

	config_defaults(&c);
	assert_false(cc->canopen);
	assert_int_equal(cc->bitrate, 0);
	assert_true(cc->busload_warn == 0.7);
	assert_true(cc->busload_error == 0.9);
	assert_int_equal(cc->err_warn, 1);
	assert_int_equal(cc->err_error, 100);
	assert_int_equal(cc->heartbeat_timeout_ns, 1000000000);
	assert_true(cc->defaults.warn_periods == 3);
	assert_true(cc->defaults.error_periods == 10);
	assert_int_equal(cc->defaults.jitter_warn_ns, 0);
	assert_int_equal(cc->defaults.jitter_error_ns, 0);
	assert_true(cc->defaults.learn_s == 2);
	assert_true(cc->defaults.init_timeout_s == 5);
	assert_null(cc->nodes);
	assert_int_equal(cc->nnodes, 0);
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_RX), -1);
	/* "can:" with nothing under it, or only the other keys: the same */
	load_ok(DIR "can-empty.yaml", &e);
	can_equal(&e.can, cc);
	load_ok(DIR "good-full.yaml", &e);
	can_equal(&e.can, cc);
	config_free(&e);
}

/* warmup: per rule or inherited; cycle_syscalls keeps more than 4 names */
static void test_config_warmup(void **state)
{
	struct config c;

	(void)state;
	load_ok(DIR "warmup.yaml", &c);
	assert_int_equal(c.defaults.warmup_ns, 2000000000ULL);
	assert_int_equal(c.nrules, 2);
	assert_int_equal(c.rules[0].warmup_ns, 500000000ULL);
	assert_int_equal(c.rules[0].ndelims, 5);
	assert_string_equal(c.rules[0].delims[4], "futex");
	assert_int_equal(c.rules[1].warmup_ns, 2000000000ULL);
	config_free(&c);
}

static void round_trip(const char *path);

/* in_list - is nr among v's n numbers, once? */
static bool once_in(const __u16 *v, int n, int nr)
{
	int i, k = 0;

	for (i = 0; i < n; i++)
		k += v[i] == nr;
	return k == 1;
}

/* the syscalls every rule names, for the per-syscall hooks: each once */
static void test_config_sys_names(void **state)
{
	struct sys_rule_names n;
	struct config c;
	int i, k;

	(void)state;
	load_ok(DIR "good-full.yaml", &c);
	config_sys_names(&c, &n);
	for (i = -1; i < c.nrules; i++) {
		const struct rule *r = i < 0 ? &c.defaults : &c.rules[i];

		for (k = 0; k < r->ndelims; k++)
			assert_true(once_in(n.delims, n.ndelims, syscall_nr(r->delims[k])));
		for (k = 0; k < r->nforbid; k++)
			assert_true(once_in(n.forbid, n.nforbid, syscall_nr(r->forbid[k])));
	}
	/* the file's: clock_nanosleep, nanosleep, epoll_pwait; ioctl and the rules' */
	assert_true(once_in(n.delims, n.ndelims, syscall_nr("epoll_pwait")));
	assert_true(once_in(n.forbid, n.nforbid, syscall_nr("ioctl")));
	assert_true(once_in(n.forbid, n.nforbid, syscall_nr("mmap")));
	/* an allowed name needs no hook of its own */
	assert_false(once_in(n.forbid, n.nforbid, syscall_nr("writev")));
	config_free(&c);
}

/* stacks: and stack_size: per rule, over the defaults' (issue 15) */
static void test_config_stacks(void **state)
{
	struct config c;
	struct stack_plan p;

	(void)state;
	load_ok(DIR "stacks.yaml", &c);
	assert_int_equal(c.defaults.stacks, RTSUP_STACKS_FP);
	assert_int_equal(c.defaults.stack_size, 8192);
	assert_int_equal(c.rules[0].stacks, RTSUP_STACKS_DWARF);
	assert_int_equal(c.rules[0].stack_size, 16384);
	assert_true(c.rules[0].set & RF_STACKS && c.rules[0].set & RF_STACK_SIZE);
	assert_int_equal(c.rules[1].stacks, RTSUP_STACKS_OFF);
	assert_int_equal(c.rules[2].stacks, RTSUP_STACKS_AUTO);
	assert_int_equal(c.rules[2].stack_size, 4096);
	/* a rule that says nothing of stacks has the defaults' */
	assert_int_equal(c.rules[3].stacks, RTSUP_STACKS_FP);
	assert_false(c.rules[3].set & (RF_STACKS | RF_STACK_SIZE));
	/* what the kernel side is loaded with: the largest DWARF size, auto, rules */
	config_stack_plan(&c, &p);
	assert_int_equal(p.kind, RTSUP_STACKS_FP);
	assert_int_equal(p.size, 8192);
	assert_true(p.any && p.rules && p.dwarf && p.autos);
	assert_int_equal(p.size_max, 16384);
	config_free(&c);
	round_trip(DIR "stacks.yaml");
}

/* the built-in defaults: stacks off, no rule asks for any */
static void test_config_stack_plan_off(void **state)
{
	struct config c;
	struct stack_plan p;

	(void)state;
	config_defaults(&c);
	config_stack_plan(&c, &p);
	assert_int_equal(p.kind, RTSUP_STACKS_OFF);
	assert_false(p.any || p.rules || p.dwarf || p.autos);
	assert_int_equal(p.size_max, 0);
	/* fp everywhere: no DWARF room, nothing per thread */
	c.defaults.stacks = RTSUP_STACKS_FP;
	config_stack_plan(&c, &p);
	assert_true(p.any);
	assert_false(p.rules || p.dwarf);
	config_free(&c);
}

/* every key of can-full.yaml lands in its field */
static void test_config_can_full(void **state)
{
	struct config c;
	const struct can_config *cc = &c.can;
	const struct can_node *n;

	load_ok(DIR "can-full.yaml", &c);
	assert_int_equal(c.defaults.period_ns, 1000000);	/* the rest still works */
	assert_true(cc->canopen);
	assert_int_equal(cc->bitrate, 500000);
	assert_true(cc->busload_warn == 60.0 / 100);
	assert_true(cc->busload_error == 0.85);
	assert_int_equal(cc->err_warn, 2);
	assert_int_equal(cc->err_error, 50);
	assert_int_equal(cc->heartbeat_timeout_ns, 1500000000);
	assert_true(cc->defaults.warn_periods == 4);
	assert_true(cc->defaults.error_periods == 12.5);
	assert_int_equal(cc->defaults.jitter_warn_ns, 1000000);
	assert_int_equal(cc->defaults.jitter_error_ns, 3000000);
	assert_true(cc->defaults.learn_s == 3);
	assert_true(cc->defaults.init_timeout_s == 10);
	assert_int_equal(cc->nnodes, 6);

	n = &cc->nodes[0];
	assert_string_equal(n->name, "shoulder");
	assert_int_equal(n->line, 16);
	assert_string_equal(n->iface, "can0");
	assert_int_equal(n->id_lo, 0x181);
	assert_int_equal(n->id_hi, 0x181);
	assert_int_equal(n->dir, RTSUP_CAN_RX);
	assert_int_equal(n->period_ns, 10000000);
	assert_string_equal(n->group, "left_arm");
	assert_true(n->th.warn_periods == 2);
	assert_true(n->th.error_periods == 5);
	assert_int_equal(n->th.jitter_warn_ns, 2000000);
	assert_int_equal(n->th.jitter_error_ns, 5000000);
	assert_true(n->th.learn_s == 1);
	assert_true(n->th.init_timeout_s == 2);

	/* a range; TX in any case; the rest from can.defaults */
	n = &cc->nodes[1];
	assert_string_equal(n->name, "pdo-range");
	assert_string_equal(n->iface, "");
	assert_int_equal(n->id_lo, 0x180);
	assert_int_equal(n->id_hi, 0x1ff);
	assert_int_equal(n->dir, RTSUP_CAN_TX);
	assert_int_equal(n->period_ns, 0);
	assert_string_equal(n->group, "");
	can_th_equal(&n->th, &cc->defaults);

	/* above 0x7FF: 29-bit; interface any is "" */
	n = &cc->nodes[2];
	assert_string_equal(n->iface, "");
	assert_int_equal(n->id_lo, 0x18FEF100 | RTSUP_CAN_EFF_FLAG);
	assert_int_equal(n->id_hi, 0x18FEF100 | RTSUP_CAN_EFF_FLAG);
	assert_int_equal(n->dir, CAN_DIR_ANY);
	assert_int_equal(n->period_ns, 100000000);
	assert_string_equal(n->group, "engine \"1\"");

	/* eight hex digits: 29-bit even when small, as candump writes it */
	n = &cc->nodes[3];
	assert_string_equal(n->iface, "vcan10");
	assert_int_equal(n->id_lo, 0x123 | RTSUP_CAN_EFF_FLAG);
	assert_int_equal(n->id_hi, 0x123 | RTSUP_CAN_EFF_FLAG);

	/* decimal */
	n = &cc->nodes[4];
	assert_int_equal(n->id_lo, 385);
	assert_int_equal(n->id_hi, 390);

	/* the largest identifier */
	n = &cc->nodes[5];
	assert_int_equal(n->id_lo, 0x1FFFFFFF | RTSUP_CAN_EFF_FLAG);
	config_free(&c);
	assert_null(c.can.nodes);
	assert_int_equal(c.can.nnodes, 0);
}

/* a node giving one key of a group keeps can.defaults' others */
static void test_config_can_merge(void **state)
{
	struct config c;
	const struct can_node *n;

	load_ok(DIR "can-merge.yaml", &c);
	assert_int_equal(c.can.nnodes, 3);
	/* can.defaults over the built-in ones, key by key too */
	assert_true(c.can.defaults.warn_periods == 5);
	assert_true(c.can.defaults.error_periods == 10);
	assert_int_equal(c.can.defaults.jitter_warn_ns, 0);
	assert_int_equal(c.can.defaults.jitter_error_ns, 4000000);

	/* nodes come before defaults in the file: they still start from them */
	n = &c.can.nodes[0];
	assert_string_equal(n->name, "elbow");
	assert_true(n->th.warn_periods == 5);		/* can.defaults */
	assert_true(n->th.error_periods == 20);		/* its own */
	assert_int_equal(n->th.jitter_warn_ns, 1000000);	/* its own */
	assert_int_equal(n->th.jitter_error_ns, 4000000);	/* can.defaults */
	assert_true(n->th.learn_s == 2);		/* built in */
	assert_true(n->th.init_timeout_s == 5);		/* built in */

	n = &c.can.nodes[1];
	assert_string_equal(n->name, "plain");
	can_th_equal(&n->th, &c.can.defaults);

	n = &c.can.nodes[2];
	assert_true(n->th.learn_s == 0.5);
	assert_true(n->th.init_timeout_s == 0);
	assert_true(n->th.warn_periods == 5);
	config_free(&c);
}

/* config_can_node: interface "" matches any, a name only itself */
static void test_config_can_node_interface(void **state)
{
	struct config c;

	load_ok(DIR "can-match.yaml", &c);
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_RX), 0);
	/* can0-rx wants can0; range takes any interface, even an unknown one */
	assert_int_equal(config_can_node(&c, "can1", 0x181, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, NULL, 0x181, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, "can00", 0x181, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, "vcan0", 0x1FFFFFFF | RTSUP_CAN_EFF_FLAG,
					 RTSUP_CAN_RX), 4);
	assert_int_equal(config_can_node(&c, "vcan1", 0x1FFFFFFF | RTSUP_CAN_EFF_FLAG,
					 RTSUP_CAN_RX), -1);
	config_free(&c);
}

/* config_can_node: the range's edges are in it, their neighbours not */
static void test_config_can_node_range(void **state)
{
	struct config c;
	__u32 e = RTSUP_CAN_EFF_FLAG;

	load_ok(DIR "can-match.yaml", &c);
	assert_int_equal(config_can_node(&c, "can1", 0x180, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, "can1", 0x1ff, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, "can1", 0x17f, RTSUP_CAN_RX), -1);
	assert_int_equal(config_can_node(&c, "can1", 0x200, RTSUP_CAN_RX), -1);
	assert_int_equal(config_can_node(&c, "vcan0", 0x1FFFFF00 | e, RTSUP_CAN_RX), 4);
	assert_int_equal(config_can_node(&c, "vcan0", 0x1FFFFEFF | e, RTSUP_CAN_RX), -1);
	/* an RTR frame of an identifier is that identifier */
	assert_int_equal(config_can_node(&c, "can0", 0x181 | RTSUP_CAN_RTR_FLAG,
					 RTSUP_CAN_RX), 0);
	/* an error frame's class bits are not an identifier */
	assert_int_equal(config_can_node(&c, "can0", 0x181 | RTSUP_CAN_ERR_FLAG,
					 RTSUP_CAN_RX), -1);
	config_free(&c);
}

/* config_can_node: a node's direction, or any */
static void test_config_can_node_direction(void **state)
{
	struct config c;

	load_ok(DIR "can-match.yaml", &c);
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_RX), 0);
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_TX), 1);
	assert_int_equal(config_can_node(&c, "can1", 0x181, RTSUP_CAN_TX), 1);
	/* a direction the caller does not know only matches "any" nodes */
	assert_int_equal(config_can_node(&c, "can0", 0x181, CAN_DIR_ANY), 2);
	assert_int_equal(config_can_node(&c, "vcan0", 0x1FFFFFFF | RTSUP_CAN_EFF_FLAG,
					 RTSUP_CAN_TX), -1);
	config_free(&c);
}

/* config_can_node: 11-bit and 29-bit identifiers never name each other */
static void test_config_can_node_eff(void **state)
{
	struct config c;
	__u32 e = RTSUP_CAN_EFF_FLAG;

	load_ok(DIR "can-match.yaml", &c);
	assert_int_equal(config_can_node(&c, "can1", 0x1f0, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, "can1", 0x1f0 | e, RTSUP_CAN_RX), 3);
	assert_int_equal(config_can_node(&c, "can0", 0x181 | e, RTSUP_CAN_RX), 3);
	assert_int_equal(config_can_node(&c, "can0", 0x180 | e, RTSUP_CAN_TX), 3);
	assert_int_equal(config_can_node(&c, "can0", 0x1ff | e, RTSUP_CAN_TX), 3);
	assert_int_equal(config_can_node(&c, "can0", 0x200 | e, RTSUP_CAN_TX), -1);
	assert_int_equal(config_can_node(&c, "can0", 0x17f | e, RTSUP_CAN_TX), -1);
	/* an 11-bit id above 0x1ff: neither range, nor the 29-bit high one */
	assert_int_equal(config_can_node(&c, "vcan0", 0x7ff, RTSUP_CAN_RX), -1);
	config_free(&c);
}

/* config_can_node: the first node that fits wins, in file order */
static void test_config_can_node_first_wins(void **state)
{
	struct config c;

	load_ok(DIR "can-match.yaml", &c);
	/* can0-rx, any-tx and range all name 0x181 */
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_RX), 0);
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_TX), 1);
	assert_int_equal(config_can_node(&c, "can0", 0x182, RTSUP_CAN_TX), 2);
	config_free(&c);
}

/* every key of good-full.yaml lands in its field */
static void test_config_full(void **state)
{
	struct config c;
	const struct rule *d, *r, *a;

	load_ok(DIR "good-full.yaml", &c);
	assert_string_equal(c.path, DIR "good-full.yaml");
	assert_int_equal(c.nrules, 2);
	d = &c.defaults;
	assert_int_equal(d->set, ALL_SET);
	assert_int_equal(d->period_ns, 2000000);
	assert_true(d->ewma_weight == 0.25);
	assert_int_equal(d->ndelims, 1);
	assert_string_equal(d->delims[0], "clock_nanosleep");
	assert_int_equal(d->policy, SCHED_RR);
	assert_int_equal(d->prio, 10);
	assert_int_equal(d->nallow, 2);
	assert_string_equal(d->allow[0], "write");
	assert_string_equal(d->allow[1], "writev");
	assert_int_equal(d->nforbid, 1);
	assert_string_equal(d->forbid[0], "ioctl");
	assert_true(d->th.init_timeout_s == 3);
	assert_int_equal(d->th.miss_warn, 2);
	assert_true(d->th.miss_error_rate == 2.0 / 100);
	assert_true(d->th.exec_warn_ratio == 0.9);
	assert_int_equal(d->th.exec_stat, EXEC_STAT_EWMA);
	assert_true(d->th.starve_warn_periods == 20);
	assert_true(d->th.starve_error_periods == 200);
	assert_int_equal(d->th.unsafe_warn, 3);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_SYSCALL], 4);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_MINFLT], 5);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_MAJFLT], 6);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_BLOCK], 7);
	assert_int_equal(d->th.unsafe_error[RTSUP_U_MIGRATE], 8);
	assert_int_equal(d->th.latency_p99_warn_ns, 100000);
	assert_int_equal(d->th.latency_max_warn_ns, 200000);
	assert_int_equal(d->th.latency_max_error_ns, 1000000);
	assert_int_equal(d->th.jitter_warn_ns, 50000);
	assert_int_equal(d->th.jitter_error_ns, 200000);
	assert_true(d->th.overhead_warn_pct == 2);
	assert_true(d->th.overhead_error_pct == 0.1 * 100);	/* a plain ratio */
	assert_true(d->th.lifetime);

	r = &c.rules[0];
	assert_string_equal(r->name, "controller");
	assert_int_equal(r->line, 21);
	assert_string_equal(r->match_process, "ros2_control_*");
	assert_string_equal(r->match_thread, "rt_*");
	assert_string_equal(r->match_cgroup, "/robot.slice");	/* trailing / dropped */
	assert_int_equal(r->set, ALL_SET);
	assert_int_equal(r->period_ns, 1000000);
	assert_true(r->ewma_weight == 1);
	assert_int_equal(r->ndelims, 2);
	assert_string_equal(r->delims[0], "nanosleep");
	assert_string_equal(r->delims[1], "epoll_pwait");
	assert_int_equal(r->policy, SCHED_FIFO);
	assert_int_equal(r->prio, 80);
	assert_int_equal(r->nallow, 0);			/* [] clears the defaults' list */
	assert_int_equal(r->nforbid, 2);
	assert_string_equal(r->forbid[1], "mmap");
	assert_true(r->th.init_timeout_s == 1.5);
	assert_int_equal(r->th.miss_warn, 1);
	assert_true(r->th.miss_error_rate == 0.5 / 100);
	assert_true(r->th.exec_warn_ratio == 120.0 / 100);
	assert_int_equal(r->th.exec_stat, EXEC_STAT_P99);
	assert_true(r->th.starve_warn_periods == 2.5);
	assert_true(r->th.starve_error_periods == 50);
	assert_int_equal(r->th.unsafe_warn, 1);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_SYSCALL], 1);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_MINFLT], 2);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_MAJFLT], 1);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_BLOCK], 10);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_MIGRATE], 0);
	assert_int_equal(r->th.latency_p99_warn_ns, 50000);
	assert_int_equal(r->th.latency_max_warn_ns, 100000);
	assert_int_equal(r->th.latency_max_error_ns, 250000);
	assert_int_equal(r->th.jitter_warn_ns, 20000);
	assert_int_equal(r->th.jitter_error_ns, 0);
	assert_true(r->th.overhead_warn_pct == 0.5);
	assert_true(r->th.overhead_error_pct == 100);
	assert_false(r->th.lifetime);

	/* a rule giving only policy and priority takes the rest from defaults */
	a = &c.rules[1];
	assert_string_equal(a->name, "any-policy");
	assert_int_equal(a->set, RF_POLICY | RF_PRIO);
	assert_int_equal(a->policy, -1);
	assert_int_equal(a->prio, -1);
	assert_string_equal(a->match_process, "");
	assert_int_equal(a->period_ns, d->period_ns);
	assert_int_equal(a->nallow, 2);
	th_equal(&a->th, &d->th);
	config_free(&c);
	assert_null(c.rules);
	assert_int_equal(c.nrules, 0);
}

/* a rule giving one nested threshold keeps the defaults' others */
static void test_config_nested_override(void **state)
{
	struct config c;
	const struct rule *r;

	load_ok(DIR "good-nested.yaml", &c);
	assert_int_equal(c.nrules, 1);
	r = &c.rules[0];
	assert_int_equal(r->set, 0);
	assert_int_equal(r->th.latency_p99_warn_ns, 100000);
	assert_int_equal(r->th.latency_max_warn_ns, 200000);
	assert_int_equal(r->th.latency_max_error_ns, 2000000);
	assert_int_equal(r->th.unsafe_warn, 2);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_SYSCALL], 3);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_BLOCK], 10);
	assert_int_equal(r->th.unsafe_error[RTSUP_U_MAJFLT], 1);	/* built in */
	assert_true(r->th.init_timeout_s == 5);
	/* the defaults themselves keep their max_error */
	assert_int_equal(c.defaults.th.latency_max_error_ns, 1000000);
	config_free(&c);
}

/* match - config_match's index and the period of the effective rule */
static int match(const struct config *c, const char *proc, const char *thread,
		 const char *cgroup, __u64 *period)
{
	struct rule eff;
	int i = config_match(c, proc, thread, cgroup, &eff);

	*period = eff.period_ns;
	return i;
}

static void test_config_match_thread_glob(void **state)
{
	struct config c;
	__u64 p;

	load_ok(DIR "good-match.yaml", &c);
	assert_int_equal(match(&c, "app", "rt_loop", NULL, &p), 0);
	assert_int_equal(p, 1000000);
	assert_int_equal(match(&c, "app", "rt_", NULL, &p), 0);
	assert_int_equal(match(&c, "app", "xrt_loop", NULL, &p), -1);
	config_free(&c);
}

static void test_config_match_process_glob(void **state)
{
	struct config c;
	__u64 p;

	load_ok(DIR "good-match.yaml", &c);
	assert_int_equal(match(&c, "ros2_control_node", "main", NULL, &p), 1);
	assert_int_equal(p, 2000000);
	assert_int_equal(match(&c, "ros2_contro", "main", NULL, &p), -1);
	/* an unknown name never matches a rule that asks for one */
	assert_int_equal(match(&c, NULL, "main", NULL, &p), -1);
	config_free(&c);
}

static void test_config_match_cgroup_prefix(void **state)
{
	struct config c;
	__u64 p;

	load_ok(DIR "good-match.yaml", &c);
	assert_int_equal(match(&c, "a", "b", "/robot.slice", &p), 2);
	assert_int_equal(p, 3000000);
	assert_int_equal(match(&c, "a", "b", "/robot.slice/ctrl.service", &p), 2);
	/* a sibling with the same prefix is not below it */
	assert_int_equal(match(&c, "a", "b", "/robot.slice2", &p), -1);
	assert_int_equal(match(&c, "a", "b", "/robot.slice2/x", &p), -1);
	assert_int_equal(match(&c, "a", "b", "/", &p), -1);
	assert_int_equal(match(&c, "a", "b", NULL, &p), -1);
	config_free(&c);
}

/* a rule with several keys needs all of them */
static void test_config_match_all_keys(void **state)
{
	struct config c;
	__u64 p;

	load_ok(DIR "good-match.yaml", &c);
	assert_int_equal(match(&c, "planner", "plan_1", "/other.slice/x", &p), 3);
	assert_int_equal(p, 4000000);
	assert_int_equal(match(&c, "planner", "plan_1", "/robot2.slice", &p), -1);
	assert_int_equal(match(&c, "planner2", "plan_1", "/other.slice", &p), -1);
	assert_int_equal(match(&c, "planner", "x", "/other.slice", &p), -1);
	config_free(&c);
}

static void test_config_match_first_wins(void **state)
{
	struct config c;
	__u64 p;

	load_ok(DIR "good-match.yaml", &c);
	assert_int_equal(match(&c, "ros2_control_node", "rt_1", "/robot.slice", &p), 0);
	assert_int_equal(p, 1000000);
	assert_int_equal(match(&c, "ros2_control_node", "main", "/robot.slice", &p), 1);
	assert_int_equal(p, 2000000);
	config_free(&c);
}

/* nothing matches: the defaults, index -1 */
static void test_config_match_none(void **state)
{
	struct config c;
	struct rule eff;

	load_ok(DIR "good-match.yaml", &c);
	assert_int_equal(config_match(&c, "bash", "bash", "/user.slice", &eff), -1);
	rule_equal(&eff, &c.defaults);
	assert_string_equal(eff.name, "defaults");
	config_free(&c);
}

/* a rule without match: matches every thread */
static void test_config_match_no_keys(void **state)
{
	struct config c;
	struct rule eff;

	load_ok(DIR "good-full.yaml", &c);
	assert_int_equal(config_match(&c, "bash", "bash", NULL, &eff), 1);
	rule_equal(&eff, &c.rules[1]);
	config_free(&c);
}

/* print_file - config_print into a temporary file; returns its path */
static void print_file(const struct config *c, char *path, size_t len)
{
	FILE *f;
	int fd;

	snprintf(path, len, "/tmp/test_config.XXXXXX");
	fd = mkstemp(path);
	assert_true(fd >= 0);
	f = fdopen(fd, "w");
	assert_non_null(f);
	config_print(c, f);
	assert_int_equal(fclose(f), 0);
}

/* slurp - a file's text after its first line (the header names the file) */
static char *slurp(const char *path)
{
	static char buf[2][16384];
	static int n;
	char *b = buf[n++ & 1];
	FILE *f = fopen(path, "r");
	size_t len;

	assert_non_null(f);
	len = fread(b, 1, sizeof(buf[0]) - 1, f);
	fclose(f);
	b[len] = '\0';
	return strchr(b, '\n');
}

/* round_trip - load, print, load the print: the same configuration */
static void round_trip(const char *path)
{
	struct config a, b;
	char p1[64], p2[64], first[16384];
	int i;

	load_ok(path, &a);
	print_file(&a, p1, sizeof(p1));
	load_ok(p1, &b);
	rule_equal(&a.defaults, &b.defaults);
	assert_int_equal(a.nrules, b.nrules);
	for (i = 0; i < a.nrules; i++) {
		rule_equal(&a.rules[i], &b.rules[i]);
	}
	can_equal(&a.can, &b.can);
	assert_int_equal(a.nactions, b.nactions);
	for (i = 0; i < a.nactions; i++) {
		b.actions[i].line = a.actions[i].line;
		assert_memory_equal(&a.actions[i], &b.actions[i], sizeof(a.actions[i]));
	}
	/* and printing again gives the same text */
	print_file(&b, p2, sizeof(p2));
	snprintf(first, sizeof(first), "%s", slurp(p1));
	assert_string_equal(first, slurp(p2));
	unlink(p1);
	unlink(p2);
	config_free(&a);
	config_free(&b);
}

static void test_config_round_trip(void **state)
{
	round_trip(DIR "good-full.yaml");
	round_trip(DIR "good-nested.yaml");
	round_trip(DIR "good-match.yaml");
	round_trip(DIR "good-empty.yaml");
	round_trip(DIR "can-full.yaml");
	round_trip(DIR "can-merge.yaml");
	round_trip(DIR "can-match.yaml");
	round_trip(DIR "can-empty.yaml");
	round_trip(DIR "actions-full.yaml");
	round_trip("examples/rtsup-1khz.yaml");
}

/* actions: every kind, enter and leave, the pid of a signal or none */
static void test_config_actions(void **state)
{
	struct config c;
	const struct action *a;

	load_ok(DIR "actions-full.yaml", &c);
	assert_int_equal(c.nactions, 5);
	a = c.actions;
	assert_int_equal(a[0].level, LEVEL_ERROR);
	assert_false(a[0].leave);
	assert_int_equal(a[0].kind, ACTION_RUN);
	assert_string_equal(a[0].arg,
			    "logger -t rtsup \"$RTSUP_COMPONENT $RTSUP_FROM -> $RTSUP_LEVEL\"");
	assert_int_equal(a[0].line, 3);
	assert_int_equal(a[1].level, LEVEL_WARN);
	assert_true(a[1].leave);
	assert_int_equal(a[1].kind, ACTION_SIGNAL);
	assert_int_equal(a[1].sig, SIGUSR1);
	assert_int_equal(a[1].pid, 0);
	assert_int_equal(a[2].kind, ACTION_SIGNAL);
	assert_int_equal(a[2].sig, SIGTERM);
	assert_int_equal(a[2].pid, 4321);
	assert_int_equal(a[3].kind, ACTION_FIFO);
	assert_false(a[3].leave);
	assert_string_equal(a[3].arg, "/run/rtsup/alarm.fifo");
	assert_int_equal(a[4].level, LEVEL_STALE);
	assert_int_equal(a[4].kind, ACTION_UNIX);
	assert_string_equal(a[4].arg, "/run/rtsup/alarm.sock");
	config_free(&c);
	/* none by default */
	config_defaults(&c);
	assert_int_equal(c.nactions, 0);
	assert_null(c.actions);
}

/* ros2_diagnostics: a boolean, off by default, printed back */
static void test_config_ros2_diagnostics(void **state)
{
	struct config c;
	char *buf = NULL;
	size_t len = 0;
	FILE *f;

	config_defaults(&c);
	assert_false(c.ros2_diagnostics);
	load_ok(DIR "ros2-diagnostics.yaml", &c);
	assert_true(c.ros2_diagnostics);
	f = open_memstream(&buf, &len);
	config_print(&c, f);
	fclose(f);
	assert_non_null(strstr(buf, "\nros2_diagnostics: true\n"));
	free(buf);
	config_free(&c);
}

/* --on-level adds after the file's actions, up to ACTION_MAX in all */
static void test_config_add_action(void **state)
{
	struct config c;
	struct action x = { .level = LEVEL_WARN, .kind = ACTION_RUN, .arg = "true" };
	int i;

	load_ok(DIR "actions-full.yaml", &c);
	for (i = 5; i < ACTION_MAX; i++)
		assert_int_equal(config_add_action(&c, &x), 0);
	assert_int_equal(c.nactions, ACTION_MAX);
	assert_string_equal(c.actions[ACTION_MAX - 1].arg, "true");
	assert_int_equal(c.actions[0].kind, ACTION_RUN);
	assert_int_equal(config_add_action(&c, &x), -1);
	assert_int_equal(c.nactions, ACTION_MAX);
	config_free(&c);
	config_defaults(&c);
	assert_int_equal(config_add_action(&c, &x), 0);
	assert_int_equal(c.nactions, 1);
	config_free(&c);
}

/* numbers that %g would shorten must still read back exactly */
static void test_config_round_trip_odd_numbers(void **state)
{
	struct config a, b;
	char p[64];

	config_defaults(&a);
	a.defaults.ewma_weight = 1.0 / 3;
	a.defaults.th.miss_error_rate = 0.123456789012345;
	a.defaults.th.exec_warn_ratio = 2.0 / 3;
	a.defaults.th.starve_warn_periods = 1e-7;
	a.defaults.th.overhead_warn_pct = 0.1 + 0.2;
	a.defaults.th.init_timeout_s = 1.000001;
	a.defaults.period_ns = 1234567;
	a.defaults.th.jitter_warn_ns = 3600ULL * 1000000000;
	a.defaults.set = RF_EWMA | RF_PERIOD;
	a.can.busload_warn = 1.0 / 3;
	a.can.busload_error = 0.1 + 0.2;
	a.can.defaults.error_periods = 2.0 / 3;
	a.can.defaults.learn_s = 0.123456789;
	a.can.heartbeat_timeout_ns = 1234567891;
	print_file(&a, p, sizeof(p));
	load_ok(p, &b);
	unlink(p);
	rule_equal(&a.defaults, &b.defaults);
	can_equal(&a.can, &b.can);
	config_free(&b);
}

/* an empty file, or only comments: the built-in defaults */
static void test_config_empty_file(void **state)
{
	struct config c, d;

	config_defaults(&d);
	load_ok(DIR "good-empty.yaml", &c);
	assert_int_equal(c.nrules, 0);
	assert_null(c.rules);
	rule_equal(&c.defaults, &d.defaults);
	load_ok(DIR "good-comment.yaml", &c);
	assert_int_equal(c.nrules, 0);
	rule_equal(&c.defaults, &d.defaults);
}

/* the example of the documentation loads, and its rules apply */
static void test_config_example(void **state)
{
	struct config c;
	struct rule eff;

	load_ok("examples/rtsup-1khz.yaml", &c);
	assert_int_equal(c.nrules, 3);
	assert_int_equal(config_match(&c, "ros2_control_node", "rt_loop",
				      "/robot.slice/ctrl.service", &eff), 0);
	assert_int_equal(eff.period_ns, 1000000);
	assert_int_equal(eff.policy, SCHED_FIFO);
	assert_int_equal(eff.prio, 80);
	assert_int_equal(config_match(&c, "ros2_control_node", "planner", NULL, &eff), 1);
	assert_int_equal(eff.period_ns, 10000000);
	/* the RT thread outside its cgroup is only "another thread" */
	assert_int_equal(config_match(&c, "ros2_control_node", "rt_loop", "/user.slice",
				      &eff), 2);
	assert_int_equal(config_match(&c, "bash", "bash", NULL, &eff), -1);
	/* its can: section */
	assert_true(c.can.canopen);
	assert_int_equal(c.can.bitrate, 1000000);
	assert_int_equal(c.can.heartbeat_timeout_ns, 300000000);
	assert_int_equal(c.can.nnodes, 5);
	assert_int_equal(config_can_node(&c, "can0", 0x080, RTSUP_CAN_TX), 0);
	assert_int_equal(config_can_node(&c, "can0", 0x181, RTSUP_CAN_RX), 1);
	assert_int_equal(config_can_node(&c, "can0", 0x182, RTSUP_CAN_RX), 2);
	assert_int_equal(config_can_node(&c, "can0", 0x202, RTSUP_CAN_TX), 3);
	assert_int_equal(config_can_node(&c, "can1", 0x18FEF100 | RTSUP_CAN_EFF_FLAG,
					 RTSUP_CAN_RX), 4);
	/* a drive's heartbeat is no node: can.defaults judge it */
	assert_int_equal(config_can_node(&c, "can0", 0x701, RTSUP_CAN_RX), -1);
	assert_int_equal(c.can.nodes[1].period_ns, 1000000);
	assert_int_equal(c.can.nodes[1].th.jitter_error_ns, 500000);
	assert_true(c.can.nodes[4].th.warn_periods == 5);
	assert_true(c.can.nodes[4].th.init_timeout_s == 10);
	assert_true(c.can.nodes[3].th.init_timeout_s == 5);
	config_free(&c);
}

/* a bad file after a good one: the good one stays (SIGHUP reload) */
static void test_config_bad_keeps_old(void **state)
{
	struct config c;
	struct rule *rules;
	char err[256];

	load_ok(DIR "good-full.yaml", &c);
	rules = c.rules;
	assert_int_equal(config_load(DIR "bad-duration.yaml", &c, err, sizeof(err)), -1);
	assert_ptr_equal(c.rules, rules);
	assert_int_equal(c.nrules, 2);
	assert_string_equal(c.path, DIR "good-full.yaml");
	assert_int_equal(c.defaults.period_ns, 2000000);
	assert_string_equal(c.rules[0].name, "controller");
	config_free(&c);
}

/* a bad can: section after a good one: the nodes stay too */
static void test_config_bad_can_keeps_old(void **state)
{
	static const char *const bad[] = {
		DIR "bad-can-dup-name.yaml",	/* nodes allocated, then an error */
		DIR "bad-can-busload.yaml",
		DIR "bad-can-no-id.yaml",
	};
	struct can_node *nodes;
	struct config c;
	char err[256];
	size_t i;

	load_ok(DIR "can-full.yaml", &c);
	nodes = c.can.nodes;
	for (i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		assert_int_equal(config_load(bad[i], &c, err, sizeof(err)), -1);
		assert_ptr_equal(c.can.nodes, nodes);
		assert_int_equal(c.can.nnodes, 6);
		assert_true(c.can.busload_warn == 0.6);
		assert_string_equal(c.can.nodes[0].name, "shoulder");
		assert_string_equal(c.path, DIR "can-full.yaml");
	}
	config_free(&c);
}

static void test_config_missing_file(void **state)
{
	expect_bad(DIR "does-not-exist.yaml",
		   DIR "does-not-exist.yaml: cannot read: No such file or directory");
	expect_bad("tests/unit/config", "tests/unit/config: cannot read: Is a directory");
}

/* one test per bad file, with its exact message */
#define BAD(name, file, msg)						\
	static void test_config_bad_##name(void **state)		\
	{								\
		expect_bad(DIR file, DIR file ":" msg);			\
	}

BAD(syntax, "bad-syntax.yaml",
    "3:2: did not find expected key (while parsing a block mapping at line 1)")
BAD(utf8, "bad-utf8.yaml", "2:13: invalid leading UTF-8 octet")
BAD(two_docs, "bad-two-docs.yaml", "2:1: more than one YAML document")
BAD(unknown_key, "bad-unknown-key.yaml", "3:5: unknown key 'perod' in rule 'controller'")
BAD(unknown_top, "bad-unknown-top.yaml",
    "1:1: unknown key 'default' at top level (want defaults, rules, can, actions or ros2_diagnostics)")
BAD(action_two_kinds, "bad-action-two-kinds.yaml",
    "2:5: action 1: give one of run, signal, fifo or unix")
BAD(action_no_kind, "bad-action-no-kind.yaml",
    "2:5: action 1: give one of run, signal, fifo or unix")
BAD(action_no_level, "bad-action-no-level.yaml", "2:5: action 1 has no level")
BAD(action_pid_no_signal, "bad-action-pid-no-signal.yaml",
    "2:5: action 1: pid goes with signal only")
BAD(ros2_diagnostics, "bad-ros2-diagnostics.yaml",
    "1:19: bad boolean 'sometimes' (want true or false)")
BAD(action_signal, "bad-action-signal.yaml",
    "3:13: unknown signal 'USR7' (want e.g. USR1, TERM or 10)")
BAD(action_when, "bad-action-when.yaml", "3:11: unknown when 'later' (want enter or leave)")
BAD(action_level, "bad-action-level.yaml",
    "2:12: unknown level 'FATAL' (want OK, WARN, ERROR or STALE)")
BAD(action_unknown_key, "bad-action-unknown-key.yaml",
    "3:5: unknown key 'command' in action 1 (want level, when, run, signal, pid, fifo or unix)")
BAD(action_not_list, "bad-action-not-list.yaml", "2:3: actions must be a list, not a map")
BAD(unknown_nested, "bad-unknown-nested.yaml",
    "3:30: unknown key 'max_warm' in thresholds.latency of defaults")
BAD(unknown_match, "bad-unknown-match.yaml", "3:13: unknown key 'user' in match of rule 'x'")
BAD(map_not_list, "bad-map-not-list.yaml", "2:15: thresholds must be a map, not a list")
BAD(list_not_scalar, "bad-list-not-scalar.yaml",
    "2:19: cycle_syscalls must be a list, not a scalar")
BAD(scalar_not_map, "bad-scalar-not-map.yaml", "2:11: period must be a scalar, not a map")
BAD(rules_not_list, "bad-rules-not-list.yaml", "2:3: rules must be a list, not a map")
BAD(top_list, "bad-top-list.yaml", "1:1: the file must be a map, not a list")
BAD(duration, "bad-duration.yaml", "2:11: bad duration 'fast' (want e.g. 1ms)")
BAD(duration_no_unit, "bad-duration-no-unit.yaml", "4:22: bad duration '50' (want e.g. 1ms)")
BAD(ewma_zero, "bad-ewma-zero.yaml", "2:16: ewma_weight '0' out of range (want 0 < w <= 1)")
BAD(ewma_two, "bad-ewma-two.yaml", "2:16: ewma_weight '2' out of range (want 0 < w <= 1)")
BAD(priority_zero, "bad-priority-zero.yaml",
    "3:15: priority '0' out of range (want 1..99 or any)")
BAD(priority_100, "bad-priority-100.yaml",
    "3:15: priority '100' out of range (want 1..99 or any)")
BAD(percent, "bad-percent.yaml",
    "3:42: thresholds.deadline_miss.error_rate '150%' out of range (want 0..100%)")
BAD(exec_percent, "bad-exec-percent.yaml",
    "3:30: thresholds.exec_near_period.warn '1001%' out of range (want 0..1000%)")
BAD(percent_text, "bad-percent-text.yaml", "3:22: bad percentage 'lots' (want e.g. 80% or 0.8)")
BAD(count, "bad-count.yaml", "3:20: bad count '-1' (want a whole number >= 0)")
BAD(stat, "bad-stat.yaml", "3:30: unknown stat 'p95' (want p99 or ewma)")
BAD(bool, "bad-bool.yaml", "3:15: bad boolean 'maybe' (want true or false)")
BAD(syscall, "bad-syscall.yaml", "3:30: unknown syscall 'frobnicate' in forbid_syscalls")
/* a blank line in a plain scalar is a newline in it: the error stays one line */
BAD(syscall_newline, "bad-syscall-newline.yaml",
    "2:20: unknown syscall 'clock_na\\nnosleep' in cycle_syscalls")
BAD(cycle_syscall, "bad-cycle-syscall.yaml",
    "2:37: unknown syscall 'sleep_forever' in cycle_syscalls")
BAD(too_many_delims, "bad-too-many-delims.yaml",
    "2:98: too many syscalls in cycle_syscalls (at most 8)")
BAD(too_many_allow, "bad-too-many-allow.yaml",
    "2:85: too many syscalls in allow_syscalls (at most 8)")
BAD(empty_delims, "bad-empty-delims.yaml", "2:19: cycle_syscalls must not be empty")
BAD(stacks, "bad-stacks.yaml", "3:13: unknown stacks 'lbr' (want off, fp, dwarf or auto)")
BAD(stack_size, "bad-stack-size.yaml",
    "4:17: bad stack_size '100' (want bytes, a multiple of 8 from 512 to 64K, e.g. 8K)")
BAD(stack_size_text, "bad-stack-size-text.yaml",
    "2:15: bad stack_size '8K1' (want bytes, a multiple of 8 from 512 to 64K, e.g. 8K)")
BAD(policy, "bad-policy.yaml",
    "2:11: unknown policy 'SCHED_FAST' (want SCHED_FIFO, SCHED_RR, SCHED_DEADLINE, "
    "SCHED_OTHER, SCHED_BATCH, SCHED_IDLE or any)")
BAD(unsafe_reason, "bad-unsafe-reason.yaml",
    "3:22: unknown unsafe reason 'page_fault' in thresholds.unsafe.error of defaults "
    "(want syscall, minor_fault, major_fault, block or migration)")
BAD(no_name, "bad-no-name.yaml", "3:5: rule 2 has no name")
BAD(dup_name, "bad-dup-name.yaml", "4:11: duplicate rule name 'controller' (first at line 2)")
BAD(dup_key, "bad-dup-key.yaml", "4:5: duplicate key 'period' in rule 'controller'")
BAD(cgroup, "bad-cgroup.yaml",
    "3:21: cgroup 'robot.slice' is not a path (want e.g. /robot.slice)")
BAD(cgroup_fs, "bad-cgroup-fs.yaml",
    "3:21: cgroup '/sys/fs/cgroup/robot.slice' is a file system path (want the path "
    "below /sys/fs/cgroup, e.g. /robot.slice)")
BAD(conflict, "bad-conflict.yaml",
    "5:22: syscall 'write' is in both allow_syscalls and forbid_syscalls of rule 'strict'")
BAD(can_unknown_key, "bad-can-unknown-key.yaml", "2:3: unknown key 'bitrat' in can")
BAD(can_unknown_node_key, "bad-can-unknown-node-key.yaml",
    "5:7: unknown key 'perod' in can node 'x'")
BAD(can_unknown_nested, "bad-can-unknown-nested.yaml",
    "3:25: unknown key 'warm' in can.defaults.jitter")
BAD(can_defaults_period, "bad-can-defaults-period.yaml",
    "3:5: unknown key 'period' in can.defaults")
BAD(can_node_match, "bad-can-node-match.yaml", "5:7: unknown key 'match' in can node 'x'")
BAD(can_id_out_of_range, "bad-can-id-out-of-range.yaml",
    "4:11: id '0x800000000' out of range (want 0..0x1FFFFFFF)")
BAD(can_id_err_flag, "bad-can-id-err-flag.yaml",
    "4:11: id '0x20000000' out of range (want 0..0x1FFFFFFF)")
BAD(can_id, "bad-can-id.yaml", "4:11: bad id '0x18G' (want e.g. 0x181, or a range 0x180-0x1ff)")
BAD(can_id_negative, "bad-can-id-negative.yaml",
    "4:11: bad id '-5' (want e.g. 0x181, or a range 0x180-0x1ff)")
BAD(can_id_empty_end, "bad-can-id-empty-end.yaml",
    "4:11: bad id '0x180-' (want e.g. 0x181, or a range 0x180-0x1ff)")
BAD(can_id_reversed, "bad-can-id-reversed.yaml",
    "4:11: id range '0x1ff-0x180' is reversed (want low-high)")
BAD(can_id_mixed, "bad-can-id-mixed.yaml",
    "4:11: id range '0x700-0x800' mixes 11-bit and 29-bit ids")
BAD(can_id_list, "bad-can-id-list.yaml", "4:11: id must be a scalar, not a list")
BAD(can_direction, "bad-can-direction.yaml",
    "5:18: unknown direction 'both' (want rx, tx or any)")
BAD(can_dup_name, "bad-can-dup-name.yaml",
    "5:13: duplicate node name 'shoulder' (first at line 3)")
BAD(can_no_name, "bad-can-no-name.yaml", "5:7: can node 2 has no name")
BAD(can_no_id, "bad-can-no-id.yaml", "3:7: can node 'a' has no id")
BAD(can_busload, "bad-can-busload.yaml",
    "2:20: can.bus_load.warn '150%' out of range (want 0..100%)")
BAD(can_busload_text, "bad-can-busload-text.yaml",
    "2:21: bad percentage 'high' (want e.g. 80% or 0.8)")
BAD(can_bitrate, "bad-can-bitrate.yaml", "2:12: bad count '500k' (want a whole number >= 0)")
BAD(can_bool, "bad-can-bool.yaml", "2:12: bad boolean 'maybe' (want true or false)")
BAD(can_duration, "bad-can-duration.yaml", "2:22: bad duration '1' (want e.g. 1ms)")
BAD(can_learn, "bad-can-learn.yaml", "3:12: bad duration 'soon' (want e.g. 1ms)")
BAD(can_periods, "bad-can-periods.yaml", "3:36: bad number '-1' (want a number >= 0)")
BAD(can_nodes_not_list, "bad-can-nodes-not-list.yaml",
    "2:10: can.nodes must be a list, not a map")
BAD(can_not_map, "bad-can-not-map.yaml", "1:6: can must be a map, not a list")
BAD(can_node_not_map, "bad-can-node-not-map.yaml",
    "3:7: a can node must be a map, not a scalar")
BAD(can_iface_long, "bad-can-iface-long.yaml",
    "4:18: interface too long (at most 15 characters)")
BAD(can_iface_name, "bad-can-iface-name.yaml", "4:18: bad interface name 'can/0'")
BAD(can_dup_key, "bad-can-dup-key.yaml", "5:7: duplicate key 'id' in can node 'x'")
BAD(can_group_empty, "bad-can-group-empty.yaml", "5:14: group must not be empty")

/* strict_size: the one size parser of --event-buffer and --stack-size */
static void test_config_strict_size(void **state)
{
	static const struct { const char *s; long min, max, want; } cases[] = {
		{ "64K", 1, 1L << 28, 65536 }, { "64k", 1, 1L << 28, 65536 },
		{ "2M", 1, 1L << 28, 2L << 20 }, { "4194304", 1, 1L << 28, 4194304 },
		{ "256M", 1, 1L << 28, 1L << 28 }, { "257M", 1, 1L << 28, -1 },
		{ "63K", 1L << 16, 1L << 28, -1 }, { "", 1, 100, -1 }, { "K", 1, 1L << 20, -1 },
		{ "1KK", 1, 1L << 20, -1 }, { "-1K", 1, 1L << 20, -1 }, { "1G", 1, 1L << 40, -1 },
		{ " 1K", 1, 1L << 20, -1 }, { "99999999999999999K", 1, 1L << 40, -1 },
		{ "12345678901234567", 1, 1L << 40, -1 },
	};
	__u32 u;
	size_t i;

	for (i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		long v = -1;
		int r = strict_size(cases[i].s, cases[i].min, cases[i].max, &v);

		if ((cases[i].want < 0) != (r < 0) || (r == 0 && v != cases[i].want))
			fail_msg("'%s': %d, %ld", cases[i].s, r, v);
	}
	/* --stack-size: 512 to 64K, 8-aligned */
	assert_int_equal(stack_size_parse("8K", &u), 0);
	assert_int_equal(u, 8192);
	assert_int_equal(stack_size_parse("512", &u), 0);
	assert_int_equal(stack_size_parse("504", &u), -1);
	assert_int_equal(stack_size_parse("513", &u), -1);
	assert_int_equal(stack_size_parse("65K", &u), -1);
	assert_int_equal(stack_size_parse("1M", &u), -1);
	(void)state;
}

#define T(name) cmocka_unit_test(test_config_##name)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(defaults),
		T(strict_size),
		T(can_defaults),
		T(full),
		T(can_full),
		T(can_merge),
		T(can_node_interface),
		T(can_node_range),
		T(can_node_direction),
		T(can_node_eff),
		T(can_node_first_wins),
		T(nested_override),
		T(match_thread_glob),
		T(match_process_glob),
		T(match_cgroup_prefix),
		T(match_all_keys),
		T(match_first_wins),
		T(match_none),
		T(match_no_keys),
		T(round_trip),
		T(round_trip_odd_numbers),
		T(empty_file),
		T(example),
		T(bad_keeps_old),
		T(bad_can_keeps_old),
		T(missing_file),
		T(bad_syntax),
		T(bad_utf8),
		T(bad_two_docs),
		T(bad_unknown_key),
		T(bad_unknown_top),
		T(bad_unknown_nested),
		T(bad_unknown_match),
		T(bad_map_not_list),
		T(bad_list_not_scalar),
		T(bad_scalar_not_map),
		T(bad_rules_not_list),
		T(bad_top_list),
		T(bad_duration),
		T(bad_duration_no_unit),
		T(bad_ewma_zero),
		T(bad_ewma_two),
		T(bad_priority_zero),
		T(bad_priority_100),
		T(bad_percent),
		T(bad_exec_percent),
		T(bad_percent_text),
		T(bad_count),
		T(bad_stat),
		T(bad_bool),
		T(bad_syscall),
		T(bad_syscall_newline),
		T(bad_cycle_syscall),
		cmocka_unit_test(test_config_warmup),
		cmocka_unit_test(test_config_stacks),
		cmocka_unit_test(test_config_sys_names),
		cmocka_unit_test(test_config_stack_plan_off),
		T(bad_too_many_delims),
		T(bad_too_many_allow),
		T(bad_empty_delims),
		T(bad_stacks),
		T(bad_stack_size),
		T(bad_stack_size_text),
		T(bad_policy),
		T(bad_unsafe_reason),
		T(bad_no_name),
		T(bad_dup_name),
		T(bad_dup_key),
		T(bad_cgroup),
		T(bad_cgroup_fs),
		T(bad_conflict),
		T(bad_can_unknown_key),
		T(bad_can_unknown_node_key),
		T(bad_can_unknown_nested),
		T(bad_can_defaults_period),
		T(bad_can_node_match),
		T(bad_can_id_out_of_range),
		T(bad_can_id_err_flag),
		T(bad_can_id),
		T(bad_can_id_negative),
		T(bad_can_id_empty_end),
		T(bad_can_id_reversed),
		T(bad_can_id_mixed),
		T(bad_can_id_list),
		T(bad_can_direction),
		T(bad_can_dup_name),
		T(bad_can_no_name),
		T(bad_can_no_id),
		T(bad_can_busload),
		T(bad_can_busload_text),
		T(bad_can_bitrate),
		T(bad_can_bool),
		T(bad_can_duration),
		T(bad_can_learn),
		T(bad_can_periods),
		T(bad_can_nodes_not_list),
		T(bad_can_not_map),
		T(bad_can_node_not_map),
		T(bad_can_iface_long),
		T(bad_can_iface_name),
		T(bad_can_dup_key),
		T(bad_can_group_empty),
		T(actions),
		T(ros2_diagnostics),
		T(bad_ros2_diagnostics),
		T(add_action),
		T(bad_action_two_kinds),
		T(bad_action_no_kind),
		T(bad_action_no_level),
		T(bad_action_pid_no_signal),
		T(bad_action_signal),
		T(bad_action_when),
		T(bad_action_level),
		T(bad_action_unknown_key),
		T(bad_action_not_list),
	};

	return cmocka_run_group_tests_name("config", tests, NULL, NULL);
}
