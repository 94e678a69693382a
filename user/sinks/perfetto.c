// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * perfetto.c - a Chrome JSON trace for the Perfetto UI (see perfetto.h).
 *
 * The file is streamed: {"displayTimeUnit":"ns","traceEvents":[ then one
 * event per line, a comma ending every line but the last, and ]} at close;
 * nothing is kept in memory but the set of processes already named.
 *
 * jansson builds every event, so strings are escaped (and invalid UTF-8 is
 * replaced by U+FFFD). Timestamps and durations are the one exception: the
 * format wants microseconds, and a double printed by jansson shows either
 * too few digits or binary noise, so "ts" and "dur" are printed exactly as
 * ns / 1000 with three decimals and spliced in front of jansson's text.
 *
 * A late cycle is explained where it shows (issue 14): its miss carries
 * its cause and parts in its args; the longest wait or preemption of that
 * cycle is a slice on a track per CPU ("CPUs", below), named after the
 * task that held the CPU; the longest block's wakeup is a flow arrow from
 * a small slice on the waker's track to the target's cycle.
 */
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <jansson.h>
#include "sinks/errline.h"
#include "sinks/jsonstr.h"
#include "sinks/perfetto.h"
#include "model/causes.h"

#define WRITE_BUF	(256 * 1024)
/* args in microseconds: 15 digits give 3 decimals below 10^12 us, no noise */
#define DUMP_FLAGS	(JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(15))

struct perfetto {
	FILE *f;
	char *path;
	int err;		/* first error (errno), sticky */
	unsigned long events;	/* events written: a comma before every later one */
	__u32 *pids;		/* processes named already (and CPU tracks, waker threads) */
	size_t npids, cap;
	unsigned long flows;	/* flow ids given */
};

/*
 * The CPU tracks: one pseudo process "CPUs" whose threads are the CPUs.
 * Above any pid (pid_max is at most 2^22): no real process is named so.
 */
#define CPU_PID		0x7ff00000U
#define CPU_TID(cpu)	(CPU_PID + 1 + (cpu))
/* a waker's thread named once: its tid in another key space than tgids */
#define WAKER_KEY(tid)	(0x80000000U | (tid))

static const char *const unsafe_names[RTSUP_U_NR] = {
	[RTSUP_U_SYSCALL] = "syscall",
	[RTSUP_U_MINFLT] = "minor_fault",
	[RTSUP_U_MAJFLT] = "major_fault",
	[RTSUP_U_BLOCK] = "block",
	[RTSUP_U_MIGRATE] = "migration",
};

/* fmt_us - nanoseconds as exact microseconds with three decimals */
static int fmt_us(char *buf, size_t len, __u64 ns)
{
	return snprintf(buf, len, "%llu.%03llu", (unsigned long long)(ns / 1000),
			(unsigned long long)(ns % 1000));
}

static json_t *json_us(__u64 ns)
{
	return json_real(ns / 1000.0);
}

static void fail(struct perfetto *p, int e)
{
	if (!p->err)
		p->err = e ? e : EIO;
}

/*
 * emit - write one event: prefix (e.g. "\"ts\":1.000,") goes right after
 * the opening brace of the object; o is consumed.
 */
static void emit(struct perfetto *p, const char *prefix, json_t *o)
{
	char sbuf[2048], *buf = sbuf;
	size_t n;

	if (!o) {
		fail(p, ENOMEM);
		return;
	}
	if (p->err)
		goto out;
	n = json_dumpb(o, sbuf, sizeof(sbuf), DUMP_FLAGS);
	if (n > sizeof(sbuf)) {
		buf = malloc(n);
		if (!buf) {
			fail(p, ENOMEM);
			goto out;
		}
		n = json_dumpb(o, buf, n, DUMP_FLAGS);
	}
	if (n < 2 || buf[0] != '{') {	/* an event always has fields */
		fail(p, EINVAL);
		goto out;
	}
	errno = 0;
	if ((p->events && fputs(",\n", p->f) == EOF) ||
	    (prefix && (fputc('{', p->f) == EOF || fputs(prefix, p->f) == EOF ||
			fwrite(buf + 1, 1, n - 1, p->f) != n - 1)) ||
	    (!prefix && fwrite(buf, 1, n, p->f) != n))
		fail(p, errno);
	else
		p->events++;
out:
	if (buf != sbuf)
		free(buf);
	json_decref(o);
}

int perfetto_open(struct perfetto **pp, const char *path, char *err, size_t errlen)
{
	static const char head[] = "{\"displayTimeUnit\":\"ns\",\"traceEvents\":[\n";
	struct perfetto *p;

	*pp = NULL;
	p = calloc(1, sizeof(*p));
	if (!p || !(p->path = strdup(path))) {
		seterr(err, errlen, "%s: %s", path, strerror(ENOMEM));
		free(p);
		return -1;
	}
	p->f = fopen(path, "we");
	if (!p->f) {
		seterr(err, errlen, "%s: %s", path, strerror(errno));
		free(p->path);
		free(p);
		return -1;
	}
	setvbuf(p->f, NULL, _IOFBF, WRITE_BUF);
	errno = 0;
	if (fputs(head, p->f) == EOF)
		fail(p, errno);
	*pp = p;
	return 0;
}

/* named - true if the process was named already, else remember it */
static bool named(struct perfetto *p, __u32 tgid)
{
	size_t i;
	__u32 *n;

	for (i = p->npids; i-- > 0;)
		if (p->pids[i] == tgid)
			return true;
	if (p->npids == p->cap) {
		n = realloc(p->pids, (p->cap ? p->cap * 2 : 16) * sizeof(*n));
		if (!n)
			return false;	/* named twice is harmless */
		p->pids = n;
		p->cap = p->cap ? p->cap * 2 : 16;
	}
	p->pids[p->npids++] = tgid;
	return false;
}

void perfetto_thread(struct perfetto *p, __u32 tgid, __u32 tid, const char *comm,
		     const char *pcomm)
{
	if (!p || p->err)
		return;
	if (pcomm && !named(p, tgid))
		emit(p, NULL, json_pack("{s:s,s:s,s:I,s:{s:o}}", "ph", "M", "name",
					"process_name", "pid", (json_int_t)tgid, "args",
					"name", json_str(pcomm, SIZE_MAX)));
	if (comm)
		emit(p, NULL, json_pack("{s:s,s:s,s:I,s:I,s:{s:o}}", "ph", "M", "name",
					"thread_name", "pid", (json_int_t)tgid, "tid",
					(json_int_t)tid, "args", "name",
					json_str(comm, SIZE_MAX)));
}

void perfetto_cycle(struct perfetto *p, __u32 tgid, __u32 tid, const struct rtsup_cycle *c)
{
	char ts[32], dur[32], prefix[96];
	json_t *a;

	if (!p || p->err)
		return;
	a = json_object();
	if (!a) {
		fail(p, ENOMEM);
		return;
	}
	/* period and latency are unknown (omitted) until flagged as known */
	if (c->flags & RTSUP_CF_HAS_PERIOD)
		json_object_set_new(a, "period_us", json_us(c->period));
	json_object_set_new(a, "exec_us", json_us(c->exec));
	json_object_set_new(a, "cpu_us", json_us(c->cpu));
	if (c->flags & RTSUP_CF_HAS_LATENCY)
		json_object_set_new(a, "latency_us", json_us(c->latency));
	if (c->nominal)
		json_object_set_new(a, "nominal_us", json_us(c->nominal));
	json_object_set_new(a, "preempt", json_integer(c->preempt));
	json_object_set_new(a, "blocks", json_integer(c->blocks));
	json_object_set_new(a, "migrations", json_integer(c->migrations));
	json_object_set_new(a, "syscalls", json_integer(c->syscalls));
	json_object_set_new(a, "unsafe_syscalls", json_integer(c->unsafe_sys));
	json_object_set_new(a, "minflt", json_integer(c->minflt));
	json_object_set_new(a, "majflt", json_integer(c->majflt));
	json_object_set_new(a, "miss", json_boolean(c->flags & RTSUP_CF_MISS));
	json_object_set_new(a, "overrun", json_boolean(c->flags & RTSUP_CF_OVERRUN));
	fmt_us(ts, sizeof(ts), c->start);
	fmt_us(dur, sizeof(dur), c->exec);
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,\"dur\":%s,", ts, dur);
	emit(p, prefix, json_pack("{s:s,s:s,s:s,s:I,s:I,s:o}", "ph", "X", "name", "cycle",
				  "cat", "cycle", "pid", (json_int_t)tgid, "tid",
				  (json_int_t)tid, "args", a));
}

/* cause_args - a late cycle's parts (us) and culprits in a miss's args */
static void cause_args(json_t *a, const struct rtsup_cause *c)
{
	json_t *parts = json_object(), *top = json_array();
	char w[64];
	int i;

	json_object_set_new(parts, "timer_us", json_us(c->timer_ns));
	json_object_set_new(parts, "wait_us", json_us(c->wait_ns));
	json_object_set_new(parts, "preempt_us", json_us(c->preempt_ns));
	json_object_set_new(parts, "block_us", json_us(c->block_ns));
	json_object_set_new(parts, "backlog_us", json_us(c->backlog_ns));
	json_object_set_new(parts, "cpu_us", json_us(c->cpu_ns));
	json_object_set_new(parts, "steal_us", json_us(c->steal_ns));
	json_object_set_new(a, "parts", parts);
	for (i = 0; i < RTSUP_CAUSE_TOP; i++) {
		if (!c->top[i].ns)
			continue;
		cause_who_text(w, sizeof(w), &c->top[i].who, 0);
		json_array_append_new(top, json_pack("{s:o,s:I,s:o}", "who", json_str(w, sizeof(w)),
						     "tid", (json_int_t)c->top[i].who.tid, "us",
						     json_us(c->top[i].ns)));
	}
	json_object_set_new(a, "culprits", top);
}

/*
 * held_slice - the late cycle's longest wait (or preemption) on its CPU's
 * track, named after the task that held the CPU longest in it (cause.h)
 */
static void held_slice(struct perfetto *p, const struct rtsup_event *e)
{
	const struct rtsup_cause *c = &e->cause;
	const struct rtsup_who *holder = NULL;
	char ts[32], dur[32], prefix[96], name[96], w[64], cpu[32];
	int i;

	if (c->held_to <= c->held_from)
		return;
	for (i = 0; i < RTSUP_CAUSE_TOP; i++)
		if (c->top[i].ns && c->top[i].who.tid == c->held_tid)
			holder = &c->top[i].who;
	if (!named(p, CPU_PID))
		emit(p, NULL, json_pack("{s:s,s:s,s:I,s:{s:s}}", "ph", "M", "name", "process_name",
					"pid", (json_int_t)CPU_PID, "args", "name", "CPUs"));
	if (!named(p, CPU_TID(c->held_cpu))) {
		snprintf(cpu, sizeof(cpu), "CPU %u", c->held_cpu);
		emit(p, NULL, json_pack("{s:s,s:s,s:I,s:I,s:{s:s}}", "ph", "M", "name",
					"thread_name", "pid", (json_int_t)CPU_PID, "tid",
					(json_int_t)CPU_TID(c->held_cpu), "args", "name", cpu));
	}
	if (holder)
		cause_who_text(w, sizeof(w), holder, 0);
	else
		snprintf(w, sizeof(w), "%s", c->held_tid ? "another task" : "nothing (idle)");
	snprintf(name, sizeof(name), "held by %s", w);
	fmt_us(ts, sizeof(ts), c->held_from);
	fmt_us(dur, sizeof(dur), c->held_to - c->held_from);
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,\"dur\":%s,", ts, dur);
	emit(p, prefix, json_pack("{s:s,s:o,s:s,s:I,s:I,s:{s:I,s:o,s:I}}", "ph", "X", "name",
				  json_str(name, sizeof(name)), "cat", "cause", "pid",
				  (json_int_t)CPU_PID, "tid", (json_int_t)CPU_TID(c->held_cpu),
				  "args", "waiting_tid", (json_int_t)e->tid, "waiting",
				  json_str(e->comm, sizeof(e->comm)), "holder_tid",
				  (json_int_t)c->held_tid));
}

/*
 * wake_flow - the late cycle's longest block: an arrow from its waker (a
 * 1 us slice "wakes X" on the waker's track, where the flow starts) to the
 * target's cycle at the switch-in that ended the block
 */
static void wake_flow(struct perfetto *p, const struct rtsup_event *e)
{
	const struct rtsup_cause *c = &e->cause;
	char ts[32], te[32], prefix[96], name[64];
	unsigned long id;

	if (!c->block_max || !c->waker.tid || !c->block_woke || c->block_ran < c->block_woke)
		return;
	if (!named(p, WAKER_KEY(c->waker.tid)))
		perfetto_thread(p, c->waker.tgid, c->waker.tid, c->waker.comm, NULL);
	id = ++p->flows;
	snprintf(name, sizeof(name), "wakes %.15s[%u]", e->comm, e->tid);
	fmt_us(ts, sizeof(ts), c->block_woke);
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,\"dur\":1.000,", ts);
	emit(p, prefix, json_pack("{s:s,s:o,s:s,s:I,s:I}", "ph", "X", "name",
				  json_str(name, sizeof(name)), "cat", "wakeup", "pid",
				  (json_int_t)c->waker.tgid, "tid", (json_int_t)c->waker.tid));
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,", ts);
	emit(p, prefix, json_pack("{s:s,s:s,s:s,s:I,s:I,s:I}", "ph", "s", "name", "wakeup",
				  "cat", "wakeup", "id", (json_int_t)id, "pid",
				  (json_int_t)c->waker.tgid, "tid", (json_int_t)c->waker.tid));
	fmt_us(te, sizeof(te), c->block_ran);
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,", te);
	emit(p, prefix, json_pack("{s:s,s:s,s:s,s:s,s:I,s:I,s:I}", "ph", "f", "bp", "e", "name",
				  "wakeup", "cat", "wakeup", "id", (json_int_t)id, "pid",
				  (json_int_t)e->tgid, "tid", (json_int_t)e->tid));
}

void perfetto_event(struct perfetto *p, const struct rtsup_event *e)
{
	const char *sys = unsafe_event_syscall(e);
	char ts[32], prefix[64], name[64], why[200];
	json_t *a;

	if (!p || p->err)
		return;
	a = json_object();
	if (!a) {
		fail(p, ENOMEM);
		return;
	}
	switch (e->type) {
	case RTSUP_EV_MISS:
		/* the late cycle annotated with its cause (model/causes.h) */
		snprintf(name, sizeof(name), "deadline miss");
		json_object_set_new(a, "late_us", json_us(e->arg));
		json_object_set_new(a, "kind", json_string(cause_kind_name(e->cause.kind)));
		causes_text(why, sizeof(why), e->cause.kind, e->cause.flags, e->cause.ns,
			    &e->cause.who, &e->cause, 0);
		json_object_set_new(a, "cause", json_str(why, sizeof(why)));
		if (e->cause.who.tid)
			json_object_set_new(a, "culprit_tid", json_integer(e->cause.who.tid));
		cause_args(a, &e->cause);
		break;
	case RTSUP_EV_UNSAFE:
		snprintf(name, sizeof(name), "unsafe: %s",
			 e->arg < RTSUP_U_NR ? unsafe_names[e->arg] : "unknown");
		if (e->arg == RTSUP_U_SYSCALL)
			json_object_set_new(a, "nr", json_integer((json_int_t)e->arg2));
		else if (e->arg == RTSUP_U_BLOCK && sys)
			json_object_set_new(a, "syscall", json_string(sys));
		else if (e->arg == RTSUP_U_MINFLT || e->arg == RTSUP_U_MAJFLT)
			json_object_set_new(a, "count", json_integer((json_int_t)e->arg2));
		else if (e->arg == RTSUP_U_MIGRATE) {
			if (RTSUP_MIG_FROM(e->arg2) != RTSUP_MIG_NOCPU)
				json_object_set_new(a, "from_cpu",
						    json_integer(RTSUP_MIG_FROM(e->arg2)));
			json_object_set_new(a, "to_cpu", json_integer(RTSUP_MIG_TO(e->arg2)));
			json_object_set_new(a, "why",
					    json_string(mig_why_name(RTSUP_MIG_WHY(e->arg2))));
		} else if (e->arg >= RTSUP_U_NR)
			json_object_set_new(a, "reason", json_integer((json_int_t)e->arg));
		break;
	case RTSUP_EV_EXIT:
		snprintf(name, sizeof(name), "exit");
		json_object_set_new(a, "mid_cycle", json_boolean(e->arg));
		break;
	case RTSUP_EV_SIGNAL:
		snprintf(name, sizeof(name), "signal");
		json_object_set_new(a, "signo", json_integer((json_int_t)e->arg));
		break;
	case RTSUP_EV_NEW:
		snprintf(name, sizeof(name), "new thread");
		json_object_set_new(a, "comm", json_str(e->comm, sizeof(e->comm)));
		break;
	default:
		snprintf(name, sizeof(name), "event %u", e->type);
		json_object_set_new(a, "arg", json_integer((json_int_t)e->arg));
		json_object_set_new(a, "arg2", json_integer((json_int_t)e->arg2));
		break;
	}
	json_object_set_new(a, "cpu", json_integer(e->cpu));
	fmt_us(ts, sizeof(ts), e->ts);
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,", ts);
	emit(p, prefix, json_pack("{s:s,s:s,s:s,s:I,s:I,s:o}", "ph", "i", "s", "t", "name",
				  name, "pid", (json_int_t)e->tgid, "tid",
				  (json_int_t)e->tid, "args", a));
	if (e->type == RTSUP_EV_MISS) {
		held_slice(p, e);
		wake_flow(p, e);
	}
}

void perfetto_stack(struct perfetto *p, __u64 ts, __u32 tgid, __u32 tid, const char *what,
		    const char *stack)
{
	char t[32], prefix[64], name[96];

	if (!p || p->err)
		return;
	snprintf(name, sizeof(name), "where: %s", what);
	fmt_us(t, sizeof(t), ts);
	snprintf(prefix, sizeof(prefix), "\"ts\":%s,", t);
	emit(p, prefix, json_pack("{s:s,s:s,s:s,s:I,s:I,s:{s:s}}", "ph", "i", "s", "t", "name",
				  name, "pid", (json_int_t)tgid, "tid", (json_int_t)tid, "args",
				  "stack", stack));
}

int perfetto_close(struct perfetto *p, char *err, size_t errlen)
{
	int e;

	if (!p)
		return 0;
	errno = 0;
	if (!p->err && fputs(p->events ? "\n]}\n" : "]}\n", p->f) == EOF)
		fail(p, errno);
	errno = 0;
	if (!p->err && fflush(p->f))
		fail(p, errno);
	errno = 0;
	if (fclose(p->f) && !p->err)
		fail(p, errno);
	e = p->err;
	if (e)
		seterr(err, errlen, "%s: write: %s", p->path, strerror(e));
	free(p->pids);
	free(p->path);
	free(p);
	return e ? -1 : 0;
}
