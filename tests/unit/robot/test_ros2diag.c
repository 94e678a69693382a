// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_ros2diag.c - user/robot/ros2diag.c without DDS: ROS's level bytes,
 * ROS_DOMAIN_ID, and the DiagnosticArray made of a model and a supervisor
 * (which threads, their names, levels, messages and key numbers, rtsup-trace
 * itself, a CAN interface, the stamp). The wire is the integration test's.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "robot/ros2diag.h"

/* ROS's bytes: OK 0, WARN 1, ERROR 2, STALE 3, whatever our enum's order */
static void test_ros2diag_level_bytes(void **state)
{
	assert_int_equal(ros2diag_level(LEVEL_OK), 0);
	assert_int_equal(ros2diag_level(LEVEL_WARN), 1);
	assert_int_equal(ros2diag_level(LEVEL_ERROR), 2);
	assert_int_equal(ros2diag_level(LEVEL_STALE), 3);
}

static void test_ros2diag_domain(void **state)
{
	static const char *const bad[] = { "233", "-1", "abc", "1x", " 1", "+3",
					   "99999999999999999999" };
	uint32_t d = 7;
	size_t i;

	assert_int_equal(ros2diag_domain(NULL, &d), 0);
	assert_int_equal(d, 0);
	assert_int_equal(ros2diag_domain("", &d), 0);
	assert_int_equal(d, 0);
	assert_int_equal(ros2diag_domain("42", &d), 0);
	assert_int_equal(d, 42);
	assert_int_equal(ros2diag_domain("232", &d), 0);
	assert_int_equal(d, 232);
	for (i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
		assert_int_equal(ros2diag_domain(bad[i], &d), -1);
}

/* find - the status of that name, or fail */
static const diagnostic_msgs_msg_dds__DiagnosticStatus_ *find(const ros2diag_msg *msg,
							       const char *name)
{
	uint32_t i;

	for (i = 0; i < msg->status._length; i++)
		if (!strcmp(msg->status._buffer[i].name, name))
			return &msg->status._buffer[i];
	fail_msg("no status named %s", name);
	return NULL;
}

/* value - the value of a key, NULL when absent */
static const char *value(const diagnostic_msgs_msg_dds__DiagnosticStatus_ *d, const char *key)
{
	uint32_t i;

	for (i = 0; i < d->values._length; i++)
		if (!strcmp(d->values._buffer[i].key, key))
			return d->values._buffer[i].value;
	return NULL;
}

static struct thread_model *thread(struct model *m, __u32 tid, const char *comm)
{
	struct thread_model *tm = model_get(m, tid, true);

	tm->tgid = 100;
	snprintf(tm->comm, sizeof(tm->comm), "%s", comm);
	snprintf(tm->pcomm, sizeof(tm->pcomm), "ctrl");
	tm->rule = -1;
	tm->policy = 1;
	tm->prio = 80;
	status_reset(&tm->st);
	return tm;
}

/*
 * alive threads and judged dead ones are listed, a dead unjudged one not;
 * the verdict's messages, level and numbers are the thread's
 */
static void test_ros2diag_fill_threads(void **state)
{
	struct model m = { 0 };
	struct supervisor s;
	struct thread_model *a, *b, *c;
	const diagnostic_msgs_msg_dds__DiagnosticStatus_ *d;
	ros2diag_msg msg;
	char key[48];

	memset(&s, 0, sizeof(s));
	status_reset(&s.self);
	s.overhead_pct = -1;
	s.real_off = 1700000000LL * 1000000000LL;
	a = thread(&m, 101, "ctl/loop");
	a->alive = true;
	status_add(&a->st, LEVEL_WARN, "latency p99 120 us > 100 us");
	status_add(&a->st, LEVEL_ERROR, "2 deadline misses");
	a->worst = LEVEL_ERROR;
	a->win.cycles = 1000;
	a->win.m[RTSUP_M_EXEC].count = 1000;
	a->win.m[RTSUP_M_EXEC].p99 = 52000;
	a->win.m[RTSUP_M_PERIOD].count = 1000;
	a->win.m[RTSUP_M_PERIOD].mean = 1000000;
	a->life.misses = 2;
	a->life.unsafe_total = 3;
	a->life.unsafe[0] = 3;
	b = thread(&m, 102, "rt-gone");
	b->was_rt = true;
	status_add(&b->st, LEVEL_STALE, "exited");
	c = thread(&m, 103, "helper");	/* dead, neither RT nor named by a rule */
	(void)c;
	status_add(&s.self, LEVEL_WARN, "BPF overhead 1.5 %% of a CPU > 1.00 %%");

	assert_int_equal(ros2diag_fill(&msg, &m, &s, "robot1", 5000000123ULL), 0);
	assert_int_equal(msg.header.stamp.sec, 1700000005);
	assert_int_equal(msg.header.stamp.nanosec, 123);
	assert_string_equal(msg.header.frame_id, "");
	assert_int_equal(msg.status._length, 3);	/* rtsup-trace, 101, 102 */

	d = find(&msg, "rtsup/robot1/rtsup-trace");
	assert_int_equal(d->level, 1);
	assert_string_equal(d->message, "BPF overhead 1.5 % of a CPU > 1.00 %");
	assert_string_equal(value(d, "threads"), "2");
	assert_null(value(d, "bpf_overhead_pct"));	/* not measured */

	d = find(&msg, "rtsup/robot1/ctl_loop[101]");	/* no '/' inside a level */
	assert_int_equal(d->level, 2);
	assert_string_equal(d->hardware_id, "robot1");
	assert_string_equal(d->message, "latency p99 120 us > 100 us; 2 deadline misses");
	assert_string_equal(value(d, "process"), "ctrl");
	assert_string_equal(value(d, "tid"), "101");
	assert_string_equal(value(d, "pid"), "100");
	assert_string_equal(value(d, "cycles"), "1000");
	assert_string_equal(value(d, "exec_p99_us"), "52.0");
	assert_string_equal(value(d, "period_mean_us"), "1000.0");
	assert_string_equal(value(d, "latency_p99_us"), "-");	/* no sample */
	assert_string_equal(value(d, "misses_total"), "2");
	assert_string_equal(value(d, "unsafe_total"), "3");
	snprintf(key, sizeof(key), "unsafe_%s", unsafe_reason_name(0));
	assert_string_equal(value(d, key), "3");	/* only the reasons that happened */
	snprintf(key, sizeof(key), "unsafe_%s", unsafe_reason_name(1));
	assert_null(value(d, key));
	assert_string_equal(value(d, "worst_level"), "ERROR");

	d = find(&msg, "rtsup/robot1/rt-gone[102]");
	assert_int_equal(d->level, 3);
	assert_string_equal(d->message, "exited");
	ros2diag_msg_free(&msg);
	assert_int_equal(msg.status._length, 0);
	model_free(&m);
}

/* an OK component says OK: an empty message reads as a missing one in rqt */
static void test_ros2diag_ok_message(void **state)
{
	struct model m = { 0 };
	struct supervisor s;
	ros2diag_msg msg;

	memset(&s, 0, sizeof(s));
	status_reset(&s.self);
	s.overhead_pct = 0.25;
	assert_int_equal(ros2diag_fill(&msg, &m, &s, "h", 0), 0);
	assert_int_equal(msg.status._length, 1);
	assert_int_equal(msg.status._buffer[0].level, 0);
	assert_string_equal(msg.status._buffer[0].message, "OK");
	assert_string_equal(value(&msg.status._buffer[0], "bpf_overhead_pct"), "0.250");
	assert_string_equal(value(&msg.status._buffer[0], "threads"), "0");
	ros2diag_msg_free(&msg);
}

/* a CAN interface: its verdict, bus load and controller state */
static void test_ros2diag_fill_can(void **state)
{
	struct model m = { 0 };
	struct supervisor s;
	struct can_model *cm = calloc(1, sizeof(*cm));
	const diagnostic_msgs_msg_dds__DiagnosticStatus_ *d;
	ros2diag_msg msg;

	assert_non_null(cm);
	memset(&s, 0, sizeof(s));
	status_reset(&s.self);
	s.overhead_pct = -1;
	s.can = cm;
	cm->nifs = 1;
	snprintf(cm->ifs[0].name, sizeof(cm->ifs[0].name), "can0");
	cm->ifs[0].load = 0.425;
	cm->ifs[0].ctrl_state = -1;
	cm->ifs[0].link_known = true;
	cm->ifs[0].link_up = false;
	status_reset(&cm->ifs[0].st);
	status_add(&cm->ifs[0].st, LEVEL_ERROR, "link down");
	assert_int_equal(ros2diag_fill(&msg, &m, &s, "h", 0), 0);
	assert_int_equal(msg.status._length, 2);
	d = find(&msg, "rtsup/h/can/can0");
	assert_int_equal(d->level, 2);
	assert_string_equal(d->message, "link down");
	assert_string_equal(value(d, "bus_load_pct"), "42.5");
	assert_string_equal(value(d, "controller"), "down");
	ros2diag_msg_free(&msg);
	free(cm);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_ros2diag_level_bytes),
		cmocka_unit_test(test_ros2diag_domain),
		cmocka_unit_test(test_ros2diag_fill_threads),
		cmocka_unit_test(test_ros2diag_ok_message),
		cmocka_unit_test(test_ros2diag_fill_can),
	};

	return cmocka_run_group_tests_name("ros2diag", tests, NULL, NULL);
}
