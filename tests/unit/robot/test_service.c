// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_service.c - user/robot/service.c: the STATUS= line systemd shows, the
 * structured journal fields of a level change, and that nothing is sent
 * (and nothing fails) outside systemd.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "robot/service.h"

static struct thread_model *add(struct model *m, int i, enum level l, bool alive, bool rt)
{
	memset(m->t[i], 0, sizeof(*m->t[i]));
	m->t[i]->tid = 100 + i;
	m->t[i]->st.level = l;
	m->t[i]->alive = alive;
	m->t[i]->was_rt = rt;
	m->t[i]->rule = -1;
	return m->t[i];
}

static void test_service_status_line(void **state)
{
	static struct thread_model t[16];
	static struct thread_model *pt[16];
	struct model m = { .t = pt, .n = 0, .cap = 16 };
	struct supervisor s;
	char line[256];
	int i;

	for (i = 0; i < 16; i++)
		pt[i] = &t[i];
	memset(&s, 0, sizeof(s));
	service_status_line(&m, &s, line, sizeof(line));
	assert_string_equal(line, "0 threads");
	for (i = 0; i < 12; i++)
		add(&m, m.n++, LEVEL_OK, true, true);
	add(&m, m.n++, LEVEL_WARN, true, true);
	service_status_line(&m, &s, line, sizeof(line));
	assert_string_equal(line, "12 threads OK, 1 WARN");
	/* a dead RT thread counts (STALE) until a restart replaces it */
	add(&m, m.n++, LEVEL_STALE, false, true);
	/* a dead non-RT thread without a rule does not */
	add(&m, m.n++, LEVEL_OK, false, false);
	add(&m, m.n++, LEVEL_ERROR, true, false);
	s.self.level = LEVEL_WARN;
	service_status_line(&m, &s, line, sizeof(line));
	assert_string_equal(line, "12 threads OK, 1 WARN, 1 ERROR, 1 STALE; rtsup-trace WARN");
	m.t[13]->replaced = true;
	s.self.level = LEVEL_OK;
	service_status_line(&m, &s, line, sizeof(line));
	assert_string_equal(line, "12 threads OK, 1 WARN, 1 ERROR");
	m.n = 1;
	service_status_line(&m, &s, line, sizeof(line));
	assert_string_equal(line, "1 thread OK");
}

/* field - the value of KEY in the iovecs, or NULL */
static const char *field(const struct iovec *iov, int n, const char *key, char *buf,
			 size_t len)
{
	size_t k = strlen(key);
	int i;

	for (i = 0; i < n; i++) {
		if (iov[i].iov_len > k && !memcmp(iov[i].iov_base, key, k) &&
		    ((char *)iov[i].iov_base)[k] == '=') {
			snprintf(buf, len, "%.*s", (int)(iov[i].iov_len - k - 1),
				 (char *)iov[i].iov_base + k + 1);
			return buf;
		}
	}
	return NULL;
}

static void test_service_journal_fields_thread(void **state)
{
	struct iovec iov[SERVICE_JOURNAL_FIELDS];
	char buf[2048], v[512];
	int n;

	n = service_journal_fields("lg-0[18969]", LEVEL_OK, LEVEL_WARN,
				   "2026-11-22T17:57:01.584Z lg-0[18969]: OK -> WARN: RT-unsafe "
				   "in the last interval: syscall 2 (syscalls: munmap 1, mmap 1)",
				   iov, buf, sizeof(buf));
	assert_int_equal(n, 9);
	assert_string_equal(field(iov, n, "MESSAGE", v, sizeof(v)),
			    "lg-0[18969]: OK -> WARN: RT-unsafe in the last interval: syscall 2 "
			    "(syscalls: munmap 1, mmap 1)");
	assert_string_equal(field(iov, n, "PRIORITY", v, sizeof(v)), "4");
	assert_string_equal(field(iov, n, "SYSLOG_IDENTIFIER", v, sizeof(v)), "rtsup-trace");
	assert_string_equal(field(iov, n, "RTSUP_COMPONENT", v, sizeof(v)), "lg-0[18969]");
	assert_string_equal(field(iov, n, "RTSUP_LEVEL", v, sizeof(v)), "WARN");
	assert_string_equal(field(iov, n, "RTSUP_PREVIOUS_LEVEL", v, sizeof(v)), "OK");
	assert_string_equal(field(iov, n, "RTSUP_MESSAGES", v, sizeof(v)),
			    "RT-unsafe in the last interval: syscall 2 (syscalls: munmap 1, mmap 1)");
	assert_string_equal(field(iov, n, "RTSUP_COMM", v, sizeof(v)), "lg-0");
	assert_string_equal(field(iov, n, "RTSUP_TID", v, sizeof(v)), "18969");
}

static void test_service_journal_fields_self(void **state)
{
	struct iovec iov[SERVICE_JOURNAL_FIELDS];
	char buf[2048], v[512];
	int n;

	/* back to OK: no messages, a notice; the supervisor has no tid */
	n = service_journal_fields("rtsup-trace", LEVEL_ERROR, LEVEL_OK,
				   "2026-11-22T17:57:01.584Z rtsup-trace: ERROR -> OK", iov, buf,
				   sizeof(buf));
	assert_int_equal(n, 7);
	assert_string_equal(field(iov, n, "RTSUP_MESSAGES", v, sizeof(v)), "");
	assert_string_equal(field(iov, n, "PRIORITY", v, sizeof(v)), "5");
	assert_null(field(iov, n, "RTSUP_TID", v, sizeof(v)));
	n = service_journal_fields("x[1]", LEVEL_OK, LEVEL_ERROR, "t x[1]: OK -> ERROR: died",
				   iov, buf, sizeof(buf));
	assert_string_equal(field(iov, n, "PRIORITY", v, sizeof(v)), "3");
	/* a buffer too small cuts fields, never overflows */
	n = service_journal_fields("x[1]", LEVEL_OK, LEVEL_ERROR, "t x[1]: OK -> ERROR: died",
				   iov, buf, 40);
	assert_true(n < 9);
}

/* outside systemd: no socket, no watchdog, stderr not the journal; calls do nothing */
static void test_service_outside_systemd(void **state)
{
	struct service sv;

	unsetenv("NOTIFY_SOCKET");
	unsetenv("WATCHDOG_USEC");
	setenv("JOURNAL_STREAM", "1:1", 1);
	service_init(&sv);
	assert_false(sv.notify);
	assert_false(sv.journal);
	assert_int_equal(sv.wd_usec, 0);
	service_ready(&sv, "x");
	service_status(&sv, "y");
	service_tick(&sv, 1000000000ULL);
	service_stopping(&sv);
	assert_int_equal(sv.wd_last, 0);
	assert_int_equal(service_tick_ms(&sv), 0);	/* the loop may wait as long as it likes */
}

/* the loop wakes for the watchdog's ping: a quarter of WatchdogSec, rounded up to a ms */
static void test_service_tick_ms(void **state)
{
	struct service sv;

	(void)state;
	memset(&sv, 0, sizeof(sv));
	sv.wd_usec = 10000000;	/* WatchdogSec=10s */
	assert_int_equal(service_tick_ms(&sv), 2500);
	sv.wd_usec = 1000000;	/* 1 s: shorter than the loop's quiet poll */
	assert_int_equal(service_tick_ms(&sv), 250);
	sv.wd_usec = 1001;
	assert_int_equal(service_tick_ms(&sv), 1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_service_status_line),
		cmocka_unit_test(test_service_journal_fields_thread),
		cmocka_unit_test(test_service_journal_fields_self),
		cmocka_unit_test(test_service_outside_systemd),
		cmocka_unit_test(test_service_tick_ms),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
