// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* service.c - sd_notify (ready, status, watchdog) and structured journal entries */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/stat.h>
#include <systemd/sd-daemon.h>
#include <systemd/sd-journal.h>
#include "robot/service.h"

/* stderr_is_journal - JOURNAL_STREAM names stderr's device and inode */
static bool stderr_is_journal(void)
{
	const char *js = getenv("JOURNAL_STREAM");
	unsigned long long dev, ino;
	struct stat st;

	if (!js || sscanf(js, "%llu:%llu", &dev, &ino) != 2 || fstat(STDERR_FILENO, &st))
		return false;
	return (unsigned long long)st.st_dev == dev && (unsigned long long)st.st_ino == ino;
}

void service_init(struct service *sv)
{
	uint64_t usec = 0;

	memset(sv, 0, sizeof(*sv));
	sv->notify = getenv("NOTIFY_SOCKET") != NULL;
	if (sd_watchdog_enabled(0, &usec) > 0)
		sv->wd_usec = usec;
	sv->journal = stderr_is_journal();
}

void service_ready(struct service *sv, const char *status)
{
	if (!sv->notify)
		return;
	snprintf(sv->status, sizeof(sv->status), "%s", status);
	sd_notifyf(0, "READY=1\nSTATUS=%s", status);
}

void service_status(struct service *sv, const char *status)
{
	if (!sv->notify || !strcmp(status, sv->status))
		return;
	snprintf(sv->status, sizeof(sv->status), "%s", status);
	sd_notifyf(0, "STATUS=%s", status);
}

__u64 service_tick_ms(const struct service *sv)
{
	return sv->wd_usec ? (sv->wd_usec / 4 + 999) / 1000 : 0;
}

void service_tick(struct service *sv, __u64 now_ns)
{
	if (!sv->wd_usec || now_ns - sv->wd_last < sv->wd_usec * 1000 / 4)
		return;
	sv->wd_last = now_ns;
	sd_notify(0, "WATCHDOG=1");
}

void service_reloading(struct service *sv, bool done)
{
	if (sv->notify)
		sd_notify(0, done ? "READY=1" : "RELOADING=1");
}

void service_stopping(struct service *sv)
{
	if (sv->notify)
		sd_notify(0, "STOPPING=1\nSTATUS=stopping");
}

void service_status_line(const struct model *m, const struct supervisor *s, char *buf,
			 size_t len)
{
	/* in the order of the line; indexed by enum level */
	static const enum level order[] = { LEVEL_OK, LEVEL_WARN, LEVEL_ERROR, LEVEL_STALE };
	int n[4] = { 0 }, total = 0, i;
	size_t off;

	for (i = 0; i < m->n; i++) {
		const struct thread_model *tm = m->t[i];

		if (!tm->alive && (tm->replaced || !(tm->was_rt || tm->rule >= 0)))
			continue;
		n[tm->st.level]++;
		total++;
	}
	off = snprintf(buf, len, "%d thread%s OK", n[LEVEL_OK], n[LEVEL_OK] == 1 ? "" : "s");
	if (!total)
		off = snprintf(buf, len, "0 threads");
	for (i = 1; i < 4 && off < len; i++)
		if (n[order[i]])
			off += snprintf(buf + off, len - off, ", %d %s", n[order[i]],
					level_name(order[i]));
	if (s->self.level != LEVEL_OK && off < len)
		snprintf(buf + off, len - off, "; rtsup-trace %s", level_name(s->self.level));
}

/* priority - syslog priority of a new level */
static int priority(enum level to)
{
	switch (to) {
	case LEVEL_ERROR: return 3;	/* err */
	case LEVEL_WARN: return 4;	/* warning */
	default: return 5;		/* notice: back to OK, or gone */
	}
}

int service_journal_fields(const char *component, enum level from, enum level to,
			   const char *line, struct iovec *iov, char *buf, size_t len)
{
	const char *msg = strchr(line, ' '), *msgs = "", *p;
	char arrow[32], comm[64] = "", tid[16] = "";
	size_t off = 0;
	int n = 0;

	/* "TIME COMP: FROM -> TO: messages": the journal has its own time */
	msg = msg ? msg + 1 : line;
	snprintf(arrow, sizeof(arrow), " -> %s: ", level_name(to));
	p = strstr(msg, arrow);
	if (p)
		msgs = p + strlen(arrow);
	/* a thread's component is "comm[tid]" */
	p = strrchr(component, '[');
	if (p && p != component && p[strlen(p) - 1] == ']') {
		snprintf(comm, sizeof(comm), "%.*s", (int)(p - component), component);
		snprintf(tid, sizeof(tid), "%.*s", (int)strlen(p) - 2, p + 1);
	}
#define FIELD(...)                                                                   \
	do {                                                                         \
		int w = snprintf(buf + off, off < len ? len - off : 0, __VA_ARGS__); \
		if (w < 0 || off + w >= len)                                         \
			return n;                                                    \
		iov[n].iov_base = buf + off;                                         \
		iov[n++].iov_len = w;                                                \
		off += w + 1;                                                        \
	} while (0)
	FIELD("MESSAGE=%s", msg);
	FIELD("PRIORITY=%d", priority(to));
	FIELD("SYSLOG_IDENTIFIER=rtsup-trace");
	FIELD("RTSUP_COMPONENT=%s", component);
	FIELD("RTSUP_LEVEL=%s", level_name(to));
	FIELD("RTSUP_PREVIOUS_LEVEL=%s", level_name(from));
	FIELD("RTSUP_MESSAGES=%s", msgs);
	if (comm[0]) {
		FIELD("RTSUP_COMM=%s", comm);
		FIELD("RTSUP_TID=%s", tid);
	}
#undef FIELD
	return n;
}

void service_journal_log(const char *component, enum level from, enum level to,
			 const char *line)
{
	struct iovec iov[SERVICE_JOURNAL_FIELDS];
	char buf[4096];
	int n = service_journal_fields(component, from, to, line, iov, buf, sizeof(buf));

	/* the journal gone: the line still reaches stderr */
	if (sd_journal_sendv(iov, n) < 0)
		fprintf(stderr, "rtsup-trace: %s\n", line);
}
