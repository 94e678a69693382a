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
	__u32 *pids;		/* processes named already */
	size_t npids, cap;
};

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

void perfetto_event(struct perfetto *p, const struct rtsup_event *e)
{
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
		break;
	case RTSUP_EV_UNSAFE:
		snprintf(name, sizeof(name), "unsafe: %s",
			 e->arg < RTSUP_U_NR ? unsafe_names[e->arg] : "unknown");
		if (e->arg == RTSUP_U_SYSCALL)
			json_object_set_new(a, "nr", json_integer((json_int_t)e->arg2));
		else if (e->arg == RTSUP_U_MINFLT || e->arg == RTSUP_U_MAJFLT)
			json_object_set_new(a, "count", json_integer((json_int_t)e->arg2));
		else if (e->arg >= RTSUP_U_NR)
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
