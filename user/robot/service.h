/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * service.h - running as a systemd service: readiness, status line and
 * watchdog through sd_notify, and level changes to the journal with
 * structured fields. Outside systemd every call is a no-op and level
 * changes stay on stderr.
 */
#ifndef RTSUP_SERVICE_H
#define RTSUP_SERVICE_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/uio.h>
#include <linux/types.h>
#include "model/model.h"
#include "judge/supervise.h"

struct service {
	bool notify;		/* NOTIFY_SOCKET is set */
	bool journal;		/* stderr is connected to the journal */
	__u64 wd_usec;		/* WatchdogSec, 0 = off */
	__u64 wd_last;		/* monotonic ns of the last ping */
	char status[256];	/* the last STATUS= sent */
};

/* service_init - what systemd gave us: notify socket, watchdog, journal stream */
void service_init(struct service *sv);
/* service_ready - READY=1 with the first status line */
void service_ready(struct service *sv, const char *status);
/* service_status - STATUS=line, sent only when it changed */
void service_status(struct service *sv, const char *status);
/* service_tick - from the main loop: a watchdog ping every quarter of WatchdogSec */
void service_tick(struct service *sv, __u64 now_ns);
/* service_tick_ms - how often service_tick must run: a quarter of WatchdogSec, 0 = off */
__u64 service_tick_ms(const struct service *sv);
/* service_reloading - RELOADING=1 (begin) or READY=1 (done) */
void service_reloading(struct service *sv, bool done);
/* service_stopping - STOPPING=1 */
void service_stopping(struct service *sv);
/* service_journal_log - the supervisor's log hook: one journal entry per level change */
void service_journal_log(const char *component, enum level from, enum level to,
			 const char *line);

/*
 * service_status_line - "12 threads OK, 1 WARN": alive threads and dead
 * judged ones not replaced by a restart, by level; the supervisor only when
 * it is not OK ("; rtsup-trace WARN")
 */
void service_status_line(const struct model *m, const struct supervisor *s, char *buf,
			 size_t len);

#define SERVICE_JOURNAL_FIELDS 9
/*
 * service_journal_fields - the journal fields of one level change into
 * iov (SERVICE_JOURNAL_FIELDS entries, text in buf); returns their number.
 * MESSAGE, PRIORITY, SYSLOG_IDENTIFIER, RTSUP_COMPONENT, RTSUP_LEVEL,
 * RTSUP_PREVIOUS_LEVEL, RTSUP_MESSAGES and, for a thread, RTSUP_COMM and RTSUP_TID.
 */
int service_journal_fields(const char *component, enum level from, enum level to,
			   const char *line, struct iovec *iov, char *buf, size_t len);

#endif
