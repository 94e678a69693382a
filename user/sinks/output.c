// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* output.c - table and JSON sinks */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <jansson.h>
#include "sinks/jsonw.h"
#include "sinks/output.h"
#include "sinks/output_hist.h"
#include "model/causes.h"
#include "model/syscalls.h"
#include "sinks/output_can.h"
#include "sinks/output_stacks.h"
#include "rtfollow.h"
#include "sinks/rowcut.h"

#define MAX_EVENT_LINES 10

/* stacks_shown - --stacks live, or a replayed trace that has stacks */
static bool stacks_shown(const struct collector *c)
{
	return c->o->stack_any || c->unwinder;
}

static const char *const event_names[] = {
	[RTSUP_EV_MISS] = "deadline_miss",
	[RTSUP_EV_UNSAFE] = "unsafe",
	[RTSUP_EV_EXIT] = "exit",
	[RTSUP_EV_NEW] = "new_thread",
	[RTSUP_EV_SIGNAL] = "signal",
};

/* use_color - colour only on a terminal, unless told */
static bool use_color(const struct options *o)
{
	return o->color < 0 ? isatty(STDOUT_FILENO) : o->color;
}

/* fmt_time - wall-clock time of a monotonic timestamp, ISO 8601 UTC */
static void fmt_time(const struct collector *c, __u64 mono, char *buf, size_t len)
{
	/* unsigned: a damaged trace's times wrap instead of overflowing (fuzz_record) */
	__s64 real = (__s64)(mono + (__u64)c->real_off);
	time_t s = real / 1000000000LL;
	struct tm tm;

	gmtime_r(&s, &tm);
	strftime(buf, len, "%Y-%m-%dT%H:%M:%S", &tm);
	snprintf(buf + strlen(buf), len - strlen(buf), ".%03lldZ",
		 (long long)(real % 1000000000LL) / 1000000);
}

/* ---- JSON ---- */

/* json_checks - per message, for machines: check, level, text and numbers */
static json_t *json_checks(const struct status_fact *f, int n, const char *const *text)
{
	json_t *a = json_array(), *counts;
	int i, j;

	for (i = 0; i < n; i++) {
		counts = json_object();
		for (j = 0; j < f[i].ncounts; j++)
			json_object_set_new(counts, f[i].counts[j].key,
					    json_integer(f[i].counts[j].val));
		json_array_append_new(a, json_pack("{s:s,s:s,s:s,s:o}", "check", f[i].check,
						   "level", level_name(f[i].level),
						   "text", text[i], "counts", counts));
	}
	return a;
}

/* json_status - a component's level and messages */
static json_t *json_status(const struct status *st)
{
	const char *text[STATUS_MAX_MSGS];
	json_t *m = json_array();
	int i;

	for (i = 0; i < st->nmsg; i++) {
		json_array_append_new(m, json_string(st->msg[i]));
		text[i] = st->msg[i];
	}
	return json_pack("{s:s,s:o,s:o}", "level", level_name(st->level), "messages", m,
			 "checks", json_checks(st->fact, st->nmsg, text));
}

/* self_pid - our own process, to name our cost in causes; unknown in a replay */
static __u32 self_pid(const struct collector *c)
{
	return c->skel ? (__u32)getpid() : 0;
}

/* json_who - a task named in a cause */
static json_t *json_who(const struct rtsup_who *w, __u32 self)
{
	return json_pack("{s:i,s:i,s:s,s:s,s:i,s:b}", "tid", w->tid, "tgid", w->tgid, "comm",
			 w->comm, "policy", policy_name(w->policy), "prio", w->prio, "self",
			 self && w->tgid == self);
}

/* json_cause - why a deadline miss happened (docs/json.md, "cause") */
static json_t *json_cause(const struct rtsup_cause *k, __u32 self)
{
	json_t *o, *top = json_array(), *b = json_null();
	const char *sys;
	char text[200];
	int i;

	causes_text(text, sizeof(text), k->kind, k->flags, k->ns, &k->who, k, self);
	for (i = 0; i < RTSUP_CAUSE_TOP; i++) {
		json_t *w;

		if (!k->top[i].ns)
			continue;
		w = json_who(&k->top[i].who, self);
		json_object_set_new(w, "ns", json_integer(k->top[i].ns));
		json_object_set_new(w, "count", json_integer(k->top[i].count));
		json_array_append_new(top, w);
	}
	if (k->block_max) {
		sys = k->block_nr ? syscall_name(k->block_nr - 1) : NULL;
		b = json_pack("{s:I,s:s?,s:o,s:b,s:b}", "ns", (json_int_t)k->block_max,
			      "syscall", sys, "waker", json_who(&k->waker, self), "inversion",
			      !!(k->flags & RTSUP_CAUSE_F_INVERSION), "uninterruptible",
			      !!(k->flags & RTSUP_CAUSE_F_DSTATE));
		if (k->block_op)
			json_object_set_new(b, "futex_op", json_integer(k->block_op - 1));
	}
	o = json_pack("{s:s,s:s,s:I,s:o}", "kind", cause_kind_name(k->kind), "text", text,
		      "ns", (json_int_t)k->ns, "who",
		      k->who.tid || k->who.comm[0] ? json_who(&k->who, self) : json_null());
	json_object_set_new(o, "parts", json_pack("{s:I,s:I,s:I,s:I,s:I,s:I,s:I}",
		"timer_ns", (json_int_t)k->timer_ns, "wait_ns", (json_int_t)k->wait_ns,
		"preempt_ns", (json_int_t)k->preempt_ns, "block_ns", (json_int_t)k->block_ns,
		"backlog_ns", (json_int_t)k->backlog_ns, "cpu_ns", (json_int_t)k->cpu_ns,
		"steal_ns", (json_int_t)k->steal_ns));
	json_object_set_new(o, "preemptions", json_integer(k->preempts));
	json_object_set_new(o, "blocks", json_integer(k->blocks));
	json_object_set_new(o, "idle_cpu", json_boolean(k->flags & RTSUP_CAUSE_F_IDLE));
	json_object_set_new(o, "inherited", json_boolean(k->flags & RTSUP_CAUSE_F_INHERIT));
	json_object_set_new(o, "after", k->kind == RTSUP_CAUSE_BACKLOG ?
			    json_string(cause_kind_name(k->after)) : json_null());
	json_object_set_new(o, "holder_below", json_boolean(k->flags & RTSUP_CAUSE_F_BELOW));
	json_object_set_new(o, "block", b);
	json_object_set_new(o, "culprits", top);
	json_object_set_new(o, "migration", k->migrations ? json_pack("{s:i,s:o,s:i,s:s}",
		"count", k->migrations, "from", k->mig_from == RTSUP_MIG_NOCPU ? json_null() :
		json_integer(k->mig_from), "to", k->mig_to, "why", mig_why_name(k->mig_why)) :
		json_null());
	return o;
}

/* json_causes - a thread's misses grouped by cause, longest total first */
static json_t *json_causes(const struct causes *cs, __u32 tid, __u32 self)
{
	const struct cause_group *g;
	json_t *a = json_array();
	char text[200];
	size_t n, i;

	g = causes_of(cs, tid, &n);
	for (i = 0; i < n; i++) {
		causes_group_text(text, sizeof(text), &g[i], self);
		json_array_append_new(a, json_pack("{s:s,s:o,s:I,s:I,s:I,s:b,s:b,s:s}", "kind",
			cause_kind_name(g[i].kind), "who",
			g[i].who.tid || g[i].who.comm[0] ? json_who(&g[i].who, self) : json_null(),
			"count", (json_int_t)g[i].count, "total_ns", (json_int_t)g[i].total_ns,
			"max_ns", (json_int_t)g[i].max_ns, "inversion",
			!!(g[i].flags & RTSUP_CAUSE_F_INVERSION), "idle_cpu",
			!!(g[i].flags & RTSUP_CAUSE_F_IDLE), "text", text));
		if (g[i].kind == RTSUP_CAUSE_BACKLOG)
			json_object_set_new(json_array_get(a, json_array_size(a) - 1), "after",
					    json_string(cause_kind_name(g[i].after)));
	}
	return a;
}

/*
 * ---- A thread, written straight (jsonw.h): every thread goes out every
 * interval, and built as jansson trees that was most of -j's cost ----
 */

/* jw_metric - one metric view */
static void jw_metric(struct jw *w, const char *key, const struct metric_view *v)
{
	jw_obj(w, key);
	jw_int(w, "count", (long long)v->count);
	if (v->count) {
		jw_int(w, "min", (long long)v->min);
		jw_int(w, "max", (long long)v->max);
		jw_ns(w, "mean", v->mean);
		/* the kernel's fixed point, exactly */
		jw_fixed(w, "ewma", llround(v->ewma * (1 << RTSUP_EWMA_SHIFT)), RTSUP_EWMA_SHIFT);
		jw_int(w, "p50", (long long)v->p50);
		jw_int(w, "p99", (long long)v->p99);
		jw_int(w, "p999", (long long)v->p999);
	}
	jw_end_obj(w);
}

/* jw_unsafe - RT-unsafe counts by reason, and their total when given */
static void jw_unsafe(struct jw *w, const char *key, const __u64 *n, const __u64 *total)
{
	int i;

	jw_obj(w, key);
	for (i = 0; i < RTSUP_U_NR; i++)
		jw_int(w, unsafe_reason_name(i), (long long)n[i]);
	if (total)
		jw_int(w, "total", (long long)*total);
	jw_end_obj(w);
}

/* jw_span - counters and metrics over one span, left open for causes and hist */
static void jw_span(struct jw *w, const char *key, const struct span_view *s,
		    const struct thread_model *tm, bool window)
{
	char buf[16];
	int i;

	jw_obj(w, key);
	jw_int(w, "cycles", (long long)s->cycles);
	jw_int(w, "deadline_misses", (long long)s->misses);
	jw_int(w, "overruns", (long long)s->overruns);
	for (i = 0; i < RTSUP_M_NR; i++)
		jw_metric(w, metric_name(i), &s->m[i]);
	jw_unsafe(w, "unsafe", s->unsafe, &s->unsafe_total);
	jw_obj(w, "unsafe_syscalls");
	for (i = 0; i < tm->nsys; i++) {
		const char *name = syscall_name(tm->sys[i].nr);
		__u64 n = tm->sys[i].total - (window ? tm->sys[i].prev : 0);

		if (!name) {
			snprintf(buf, sizeof(buf), "sys_%d", tm->sys[i].nr);
			name = buf;
		}
		if (n)
			jw_int(w, name, (long long)n);
	}
	jw_end_obj(w);
	jw_obj(w, "context_switches");
	jw_int(w, "voluntary", (long long)s->vol_cs);
	jw_int(w, "involuntary", (long long)s->invol_cs);
	jw_int(w, "unseen_switch_ins", (long long)s->unseen_in);
	jw_end_obj(w);
	jw_obj(w, "page_faults");
	jw_int(w, "minor", (long long)s->minflt);
	jw_int(w, "major", (long long)s->majflt);
	jw_end_obj(w);
	jw_int(w, "migrations", (long long)s->migrations);
	jw_int(w, "syscalls", (long long)s->syscalls);
	jw_int(w, "compat_syscalls", (long long)s->compat_sys);
	jw_int(w, "signals", (long long)s->signals);
}

/* jw_status - a thread's level and messages, as json_status writes a component's */
static void jw_status(struct jw *w, const struct status *st)
{
	int i, j;

	jw_obj(w, "status");
	jw_str(w, "level", level_name(st->level), SIZE_MAX);
	jw_arr(w, "messages");
	for (i = 0; i < st->nmsg; i++)
		jw_str(w, NULL, st->msg[i], sizeof(st->msg[i]));
	jw_end_arr(w);
	jw_arr(w, "checks");
	for (i = 0; i < st->nmsg; i++) {
		const struct status_fact *f = &st->fact[i];

		jw_obj(w, NULL);
		jw_str(w, "check", f->check, SIZE_MAX);
		jw_str(w, "level", level_name(f->level), SIZE_MAX);
		jw_str(w, "text", st->msg[i], sizeof(st->msg[i]));
		jw_obj(w, "counts");
		for (j = 0; j < f->ncounts; j++)
			jw_int(w, f->counts[j].key, (long long)f->counts[j].val);
		jw_end_obj(w);
		jw_end_obj(w);
	}
	jw_end_arr(w);
	jw_end_obj(w);
}

/* jw_span_tail - a span's deadline misses by cause and --hist, then its end */
static void jw_span_tail(struct jw *w, const struct collector *c,
			 const struct thread_model *tm, bool window)
{
	const struct causes *cs = window ? &c->causes_win : &c->causes_life;
	size_t n;

	/* deadline misses by cause: the interval's, or the run's in the summary */
	if (causes_of(cs, tm->tid, &n) && n) {
		jw_json(w, "causes", json_causes(cs, tm->tid, self_pid(c)));
	} else {
		jw_arr(w, "causes");
		jw_end_arr(w);
	}
	/* --hist: the summary's lifetime ones, and each interval's with --hist-interval */
	if (c->o->hist && hist_shown(tm) && (!window || c->o->hist_interval))
		jw_json(w, "hist", hist_json(tm, c->o->hist, window));
	jw_end_obj(w);
}

/* jw_thread - identity of a thread plus the requested spans */
static void jw_thread(struct jw *w, const struct collector *c, const struct supervisor *sv,
		      const struct thread_model *tm, bool window)
{
	static const char *const modes[] = { "none", "activation", "delimiter" };

	jw_obj(w, NULL);
	jw_int(w, "tid", tm->tid);
	jw_int(w, "tgid", tm->tgid);
	jw_str(w, "comm", tm->comm, sizeof(tm->comm));
	jw_str(w, "policy", policy_name(tm->policy), SIZE_MAX);
	jw_int(w, "prio", tm->prio);
	jw_str(w, "cpus", tm->cpus[0] ? tm->cpus : "-", sizeof(tm->cpus));
	jw_bool(w, "alive", tm->alive);
	jw_str(w, "mode", modes[tm->cur.cs.mode < 3 ? tm->cur.cs.mode : 0], SIZE_MAX);
	if (tm->cur.exited) {
		jw_bool(w, "exit_mid_cycle", tm->cur.exit_mid_cycle);
		jw_int(w, "exit_code", tm->cur.exit_code);
		jw_bool(w, "process_ended", tm->cur.exit_group);
		/* the teardown inside the cut cycle, kept out of the totals */
		if (tm->cur.exit_mid_cycle)
			jw_unsafe(w, "exit_cycle_unsafe", tm->cur.exit_unsafe, NULL);
	}
	/* --rt let it go: it left RT (rtfollow.h) */
	if (tm->cur.rt & RTSUP_RT_LEFT)
		jw_bool(w, "left_rt", true);
	jw_str(w, "process", tm->pcomm, sizeof(tm->pcomm));
	jw_bool(w, "kernel_thread", tm->kthread);
	jw_status(w, &tm->st);
	jw_str(w, "worst_level", level_name(tm->worst), SIZE_MAX);
	if (tm->rule >= 0 && tm->rule_gen == sv->gen)
		jw_str(w, "rule", supervise_rule(sv, tm)->name, SIZE_MAX);
	if (window) {
		jw_span(w, "interval", &tm->win, tm, true);
		jw_span_tail(w, c, tm, true);
	}
	jw_span(w, "total", &tm->life, tm, false);
	if (!window)
		jw_span_tail(w, c, tm, false);
	else
		jw_end_obj(w);
	/* --stacks: where in the code its RT-unsafe events came from */
	if (stacks_shown(c))
		jw_json(w, "stacks", stacks_json(&c->stacks, tm->tid, window));
	jw_end_obj(w);
}

/* json_event - one rare event */
static json_t *json_event(const struct collector *c, const struct rtsup_event *e)
{
	const char *sys = unsafe_event_syscall(e);
	char when[40];
	json_t *o;

	fmt_time(c, e->ts, when, sizeof(when));
	o = json_pack("{s:s,s:s,s:i,s:i,s:s,s:i}", "time", when, "event",
		      e->type < sizeof(event_names) / sizeof(event_names[0]) &&
		      event_names[e->type] ? event_names[e->type] : "unknown",
		      "tid", e->tid, "tgid", e->tgid, "comm", e->comm, "cpu", e->cpu);
	switch (e->type) {
	case RTSUP_EV_MISS:
		json_object_set_new(o, "late_ns", json_integer(e->arg));
		json_object_set_new(o, "cause", json_cause(&e->cause, self_pid(c)));
		break;
	case RTSUP_EV_UNSAFE:
		json_object_set_new(o, "reason", json_string(unsafe_reason_name(e->arg)));
		if (e->arg == RTSUP_U_SYSCALL && sys)
			json_object_set_new(o, "syscall", json_string(sys));
		else if (e->arg == RTSUP_U_BLOCK)	/* null: a page fault, or unknown */
			json_object_set_new(o, "syscall", sys ? json_string(sys) : json_null());
		else if (e->arg == RTSUP_U_MINFLT || e->arg == RTSUP_U_MAJFLT)
			json_object_set_new(o, "count", json_integer(e->arg2));
		else if (e->arg == RTSUP_U_MIGRATE)
			json_object_set_new(o, "migration", json_pack("{s:o,s:i,s:s}", "from",
				RTSUP_MIG_FROM(e->arg2) == RTSUP_MIG_NOCPU ? json_null() :
				json_integer(RTSUP_MIG_FROM(e->arg2)), "to", RTSUP_MIG_TO(e->arg2),
				"why", mig_why_name(RTSUP_MIG_WHY(e->arg2))));
		break;
	case RTSUP_EV_EXIT:
		json_object_set_new(o, "mid_cycle", json_boolean(e->arg));
		break;
	case RTSUP_EV_SIGNAL:
		json_object_set_new(o, "signal", json_integer(e->arg));
		break;
	}
	return o;
}

/*
 * json_fold - a flood of one kind for one thread: how many of its events
 * are not in "events" (the first and last EVENTLOG_KEEP are)
 */
static json_t *json_fold(const struct collector *c, const struct event_fold *f)
{
	static const char *const per_event[] = { "time", "cpu", "tgid", "late_ns", "cause", "count",
						 "migration" };
	struct rtsup_event e = { .ts = f->first_ts, .type = f->type, .tid = f->tid };
	char first[40], last[40];
	size_t i;
	json_t *o;

	/* the kind's fields as json_event writes them */
	if (f->type == RTSUP_EV_UNSAFE) {
		e.arg = f->kind >> 32;
		e.arg2 = f->kind & 0xffffffff;
	} else {
		e.arg = f->kind;
	}
	memcpy(e.comm, f->comm, sizeof(e.comm));
	o = json_event(c, &e);
	for (i = 0; i < sizeof(per_event) / sizeof(per_event[0]); i++)
		json_object_del(o, per_event[i]);
	if (f->type == RTSUP_EV_MISS)
		json_object_set_new(o, "cause", json_pack("{s:s}", "kind", cause_kind_name(f->kind)));
	fmt_time(c, f->first_ts, first, sizeof(first));
	fmt_time(c, f->last_ts, last, sizeof(last));
	json_object_update_new(o, json_pack("{s:I,s:I,s:s,s:s}", "seen", (json_int_t)f->seen,
					    "folded", (json_int_t)f->folded, "first", first,
					    "last", last));
	return o;
}

/* json_map_fill - one kernel map's entries, capacity and fill; null when unknown */
static json_t *json_map_fill(const struct health_map *m)
{
	if (!m->capacity)
		return json_null();
	return json_pack("{s:I,s:I,s:f,s:b}", "entries", (json_int_t)m->entries, "capacity",
			 (json_int_t)m->capacity, "fill_pct", health_fill_pct(m), "near_full",
			 health_near_full(m));
}

/*
 * json_thread_map - the thread map's fill, and how many entries the last
 * read looked at and copied, whether it walked the whole map (in batches
 * or not) and how many tasks it read
 */
static json_t *json_thread_map(const struct health *h)
{
	json_t *o = json_map_fill(&h->thread_map);

	if (json_is_object(o)) {
		json_object_set_new(o, "copied", json_integer(h->thread_map_copied));
		json_object_set_new(o, "short", json_integer(h->thread_map_short));
		json_object_set_new(o, "short_refused", json_integer(h->thread_map_short_refused));
		json_object_set_new(o, "visited", json_integer(h->thread_map_visited));
		json_object_set_new(o, "whole", json_boolean(h->thread_map_whole));
		json_object_set_new(o, "batch", json_boolean(h->thread_map_batch));
		json_object_set_new(o, "tasks", json_integer(h->thread_map_tasks));
		json_object_set_new(o, "task_walk", json_boolean(h->task_walk));
		json_object_set_new(o, "tasks_asked", json_integer(h->tasks_asked));
	}
	return o;
}

/* json_stats_window - the numbers behind bpf_overhead_pct (overhead.h); null: none */
static json_t *json_stats_window(const struct stats_window *w)
{
	if (!w->wall_ns)
		return json_null();
	return json_pack("{s:f,s:I,s:f,s:o}", "window_s", w->wall_ns / 1e9,
			 "runs", (json_int_t)w->runs, "run_s", w->run_ns / 1e9, "floor_ns",
			 w->floor_ns >= 0 ? json_real(w->floor_ns) : json_null());
}

/* json_health - rtsup-trace's own health (health.h, docs/json.md) */
static json_t *json_health(const struct health *h)
{
	return json_pack("{s:b,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:o,s:o}", "ok",
			 !health_problems(h), "lost_events", (json_int_t)h->lost_events,
			 "lost_cycle_records", (json_int_t)h->lost_cycle_records,
			 "untracked_threads", (json_int_t)h->untracked_threads,
			 "untracked_syscall_counts", (json_int_t)h->untracked_syscall_counts,
			 "can_frames_not_counted", (json_int_t)h->can_frames_not_counted,
			 "events_not_kept", (json_int_t)h->events_not_kept,
			 "parse_errors", (json_int_t)h->parse_errors,
			 "actions_dropped", (json_int_t)h->actions_dropped,
			 "hook_runs_missed", (json_int_t)h->hook_runs_missed,
			 "hook_runs_recovered", (json_int_t)h->hook_runs_recovered,
			 "thread_map", json_thread_map(h),
			 "can_id_map", json_map_fill(&h->can_id_map));
}

/* json_common - the fields every report carries */
static json_t *json_common(const struct collector *c, const struct supervisor *sv,
			   const char *type, double elapsed)
{
	char when[40];
	json_t *o;

	fmt_time(c, mono_now(), when, sizeof(when));
	o = json_pack("{s:s,s:s,s:f,s:I,s:I,s:I,s:I,s:{s:o,s:s,s:o}}", "type", type, "time", when,
			 "elapsed_s", elapsed,
			 "lost_events", (json_int_t)c->counters[RTSUP_C_RB_DROPS],
			 "lost_cycle_records", (json_int_t)c->counters[RTSUP_C_CYC_DROPS],
			 "untracked_threads", (json_int_t)c->counters[RTSUP_C_MAP_FULL],
			 "untracked_syscall_counts", (json_int_t)c->counters[RTSUP_C_SYS_FULL],
			 "supervisor", "status", json_status(&sv->self), "worst_level",
			 level_name(sv->self_worst), "bpf_overhead_pct",
			 sv->overhead_pct >= 0 ? json_real(sv->overhead_pct) : json_null());
	if (o) {
		/* the report's span: the interval's, or the whole run's in the summary */
		const struct self_span *sp = strcmp(type, "summary") ? &sv->loop : &sv->loop_run;
		json_t *su = json_object_get(o, "supervisor");

		json_object_set_new(su, "loop_cpu_s", sp->cpu_s >= 0 ? json_real(sp->cpu_s) :
				    json_null());
		json_object_set_new(su, "loop_wait_s", sp->wait_s >= 0 ? json_real(sp->wait_s) :
				    json_null());
		json_object_set_new(su, "bpf_stats", json_stats_window(&sv->stats));
		/* per-syscall: the syscall counts leave out what no hook watches (design.md) */
		if (c->sys_hooks)
			json_object_set_new(su, "syscall_hooks", json_string(c->sys_hooks));
		if (c->task_attrs)
			json_object_set_new(su, "task_attrs", json_string(c->task_attrs));
		json_object_set_new(o, "health", json_health(&sv->health));
		/* cause attribution's limit (design.md): waits it had no slot for */
		json_object_set_new(o, "waits_not_attributed",
				    json_integer((json_int_t)c->counters[RTSUP_C_WHY_BUSY]));
	}
	return o;
}

/*
 * A report is one line of JSON, written piece by piece: a document holding
 * a thousand threads at once cost tens of MiB and most of the CPU time.
 * Written in pairs, json_begin .. json_end and json_list_begin .. _end;
 * every piece in between is a jansson value given to json_field, json_item.
 */

/*
 * json_put - one value, compact (freed). Encoded into a buffer kept across
 * calls and written at once: json_dumpf writes token by token, and those
 * small locked writes were a quarter of the CPU time.
 */
static void json_put(json_t *v)
{
	static char *buf;
	static size_t cap;
	size_t n;

	if (!v) {
		fputs("null", stdout);
		return;
	}
	n = json_dumpb(v, buf, cap, JSON_COMPACT | JSON_ENCODE_ANY);
	if (n > cap) {
		char *b = realloc(buf, n * 2);

		if (b) {
			buf = b;
			cap = n * 2;
			n = json_dumpb(v, buf, cap, JSON_COMPACT | JSON_ENCODE_ANY);
		}
	}
	if (n <= cap)
		fwrite(buf, 1, n, stdout);
	else	/* no memory for the buffer: slower, still whole */
		json_dumpf(v, stdout, JSON_COMPACT | JSON_ENCODE_ANY);
	json_decref(v);
}

/* json_fields - an object's fields without its braces (freed), after a comma */
static void json_fields(json_t *o, bool comma)
{
	char *s = json_dumps(o, JSON_COMPACT);
	size_t n = s ? strlen(s) : 0;

	if (n > 2)
		printf("%s%.*s", comma ? "," : "", (int)(n - 2), s + 1);
	free(s);
	json_decref(o);
}

/* json_begin - a report, its first fields (json_common: never empty), left open */
static void json_begin(json_t *o)
{
	putchar('{');
	json_fields(o, false);
}

/* json_field - ,"key":value into the open report (value freed) */
static void json_field(const char *key, json_t *v)
{
	printf(",\"%s\":", key);
	json_put(v);
}

/* json_end - the report's end, the end of the line, flushed */
static void json_end(void)
{
	fputs("}\n", stdout);
	fflush(stdout);
}

/* json_list_begin - ,"key":[ an array streamed item by item */
static void json_list_begin(const char *key, int *n)
{
	printf(",\"%s\":[", key);
	*n = 0;
}

/* json_item - the next item of the open array (freed) */
static void json_item(int *n, json_t *v)
{
	if ((*n)++)
		putchar(',');
	json_put(v);
}

/* json_list_end - ] */
static void json_list_end(void)
{
	putchar(']');
}

/*
 * json_active - does --json-threads active list tm this interval? A parked
 * thread's win is known zero (model_win_empty): its lines, two pages past
 * the head, are not fetched for 900 parked threads an interval
 */
static bool json_active(const struct thread_model *tm)
{
	if (model_win_empty(tm))
		return rowcut_active(0, 0, tm->level_changed);
	return rowcut_active(tm->win.cycles, tm->win.vol_cs + tm->win.invol_cs, tm->level_changed);
}

/*
 * json_threads - the threads array, one thread object at a time; an
 * interval with --json-threads active lists the active ones and counts
 * the others (rowcut.h)
 */
static void json_threads(const struct collector *c, const struct supervisor *sv, bool window)
{
	static struct jw thread_jw;
	bool active = window && c->o->json_active;
	int i, n, quiet = 0;

	json_list_begin("threads", &n);
	for (i = 0; i < c->model.n; i++) {
		const struct thread_model *tm = c->model.t[i];

		if (window && tm->reported_exit)
			continue;
		if (active && !json_active(tm)) {
			quiet++;
			continue;
		}
		/* written straight, one buffer kept across threads and intervals */
		if (n++)
			putchar(',');
		jw_reset(&thread_jw);
		jw_thread(&thread_jw, c, sv, tm, window);
		if (thread_jw.t.oom)	/* no memory for the buffer: the thread is null */
			fputs("null", stdout);
		else
			fwrite(thread_jw.t.p, 1, thread_jw.t.len, stdout);
	}
	json_list_end();
	if (active)
		json_field("threads_not_listed", json_integer(quiet));
}

static void json_interval(const struct collector *c, const struct supervisor *sv,
			  double elapsed, double interval)
{
	json_t *o = json_common(c, sv, "interval", elapsed);
	int i, n;

	json_object_set_new(o, "interval_s", json_real(interval));
	json_begin(o);
	json_threads(c, sv, true);
	if (sv->can)
		json_field("can", can_json(sv->can, &sv->cfg, sv->now, interval, false));
	if (stacks_shown(c))
		json_field("stack_records", stacks_health_json(&c->stacks));
	json_list_begin("events", &n);
	for (i = 0; i < (int)c->events.n; i++)
		json_item(&n, json_event(c, &c->events.ev[i]));
	json_list_end();
	json_list_begin("events_folded", &n);
	for (i = 0; i < (int)c->events.nflood; i++)
		json_item(&n, json_fold(c, &c->events.fold[i]));
	json_list_end();
	json_field("events_not_shown", json_integer(c->events.folded + c->events.dropped));
	json_end();
}

static void json_summary(const struct collector *c, const struct supervisor *sv,
			 double elapsed)
{
	json_t *o = json_common(c, sv, "summary", elapsed), *vs = json_array();
	char when[40];
	int i;

	json_object_set_new(o, "events_total", json_integer(c->events_total));
	json_begin(o);
	json_threads(c, sv, false);
	o = json_object();
	if (sv->can) {
		json_t *can = can_json(sv->can, &sv->cfg, sv->now, 0, true);

		if (c->o->hist)
			hist_can_json(can, sv->can);
		json_object_set_new(o, "can", can);
	}
	for (i = 0; i < sv->nv; i++) {
		const struct violation *v = &sv->v[i];
		const char *text[STATUS_MAX_MSGS];
		int k;

		/* the joined "what" holds the texts; each check lists its facts */
		for (k = 0; k < v->nfact; k++)
			text[k] = v->text[k];
		fmt_time(c, v->mono_ns, when, sizeof(when));
		json_array_append_new(vs, json_pack("{s:s,s:s,s:s,s:s,s:o}", "time", when,
						    "component", v->component, "level",
						    level_name(v->level), "what", v->what, "checks",
						    json_checks(v->fact, v->nfact, text)));
	}
	if (stacks_shown(c))
		json_object_set_new(o, "stack_records", stacks_health_json(&c->stacks));
	json_object_set_new(o, "violations", vs);
	json_object_set_new(o, "violations_not_listed", json_integer(sv->v_dropped));
	json_fields(o, true);	/* the small rest, after the threads */
	json_field("worst_level", json_string(level_name(supervise_worst(sv, &c->model))));
	json_end();
}

/* ---- table ---- */

/* us - a time cell in microseconds, '-' when empty */
static void us(char *buf, size_t len, __u64 count, double ns)
{
	if (!count)
		snprintf(buf, len, "-");
	else
		snprintf(buf, len, "%.1f", ns / 1000.0);
}

static void table_header(const char *title)
{
	printf("%s\n", title);
	printf("%7s %-15s %-9s %7s %17s %26s %26s %5s %6s %13s %s\n", "", "", "", "",
	       "PERIOD (us)", "EXEC (us)", "LATENCY (us)", "", "", "", "");
	printf("%7s %-15s %-9s %7s %8s %8s %8s %8s %8s %8s %8s %8s %5s %6s %13s %s\n", "TID",
	       "COMM", "POL/PRI", "CYCLES", "avg", "max", "avg", "p99", "max", "avg", "p99",
	       "max", "MISS", "UNSAFE", "CSW vol/inv", "STATUS");
}

static void table_row(const struct thread_model *tm, const struct span_view *s,
		      enum level level, bool color)
{
	char pol[16], c[9][16], csw[32];
	const struct metric_view *p = &s->m[RTSUP_M_PERIOD], *e = &s->m[RTSUP_M_EXEC],
				 *l = &s->m[RTSUP_M_LATENCY];
	const char *on = !color ? "" : level == LEVEL_ERROR ? "\033[31m" :
			 level == LEVEL_WARN ? "\033[33m" : "", *off = *on ? "\033[0m" : "";

	if (tm->policy >= 0)
		snprintf(pol, sizeof(pol), "%.5s/%d",
			 policy_name(tm->policy) + (tm->policy <= 7 ? 6 : 0), tm->prio);
	else
		snprintf(pol, sizeof(pol), "exited");
	us(c[0], 16, p->count, p->mean);
	us(c[1], 16, p->count, p->max);
	us(c[2], 16, e->count, e->mean);
	us(c[3], 16, e->count, e->p99);
	us(c[4], 16, e->count, e->max);
	us(c[5], 16, l->count, l->mean);
	us(c[6], 16, l->count, l->p99);
	us(c[7], 16, l->count, l->max);
	snprintf(csw, sizeof(csw), "%llu/%llu", (unsigned long long)s->vol_cs,
		 (unsigned long long)s->invol_cs);
	printf("%s%7u %-15.15s %-9s %7llu %8s %8s %8s %8s %8s %8s %8s %8s %5llu %6llu %13s %s%s\n",
	       on, tm->tid, tm->comm, pol, (unsigned long long)s->cycles, c[0], c[1], c[2],
	       c[3], c[4], c[5], c[6], c[7], (unsigned long long)s->misses,
	       (unsigned long long)s->unsafe_total, csw, level_name(level), off);
}

/*
 * table_pick - the rows of a table (rowcut.h): the interval's by its
 * verdict and window, the summary's by the worst level and the lifetime.
 * Returns their model indices (kept until the next call), *n and *cut.
 */
static const int *table_pick(const struct collector *c, bool window, int *n, int *cut)
{
	static struct rowcut_row *rows;
	static int *idx, cap;
	int i, m = c->model.n;

	*n = *cut = 0;
	if (!m)		/* no thread (yet): no rows, and no buffer to index */
		return idx;
	if (m > cap) {
		struct rowcut_row *r = realloc(rows, m * sizeof(*r));
		int *x = r ? realloc(idx, 2 * m * sizeof(*x)) : NULL;

		if (r)
			rows = r;
		if (!x) {	/* no memory for the cut: none */
			*n = *cut = 0;
			return NULL;
		}
		idx = x;
		cap = m;
	}
	for (i = 0; i < m; i++) {
		const struct thread_model *tm = c->model.t[i];
		const struct span_view *s = window ? &tm->win : &tm->life;

		rows[i] = (struct rowcut_row){ .level = window ? tm->st.level : tm->worst,
			.skip = window && tm->reported_exit };
		if (!window || !model_win_empty(tm)) {
			rows[i].misses = s->misses;
			rows[i].unsafe = s->unsafe_total;
			rows[i].lat_max_ns = s->m[RTSUP_M_LATENCY].max;
		}
	}
	*n = rowcut_pick(rows, m, c->o->top, c->o->all, idx, idx + m, cut);
	return idx;
}

/* table_cut_line - what the table left out, if anything */
static void table_cut_line(int cut)
{
	if (cut)
		printf("%7s ... %d more threads, all OK (--all shows every thread)\n", "", cut);
}

/* table_event - one line per rare event */
static void table_event(const struct collector *c, const struct rtsup_event *e)
{
	char when[40], what[320], why[240];
	const char *sys;

	fmt_time(c, e->ts, when, sizeof(when));
	switch (e->type) {
	case RTSUP_EV_MISS:
		causes_text(why, sizeof(why), e->cause.kind, e->cause.flags, e->cause.ns,
			    &e->cause.who, &e->cause, self_pid(c));
		snprintf(what, sizeof(what), "deadline miss, %.1f us late: %s", e->arg / 1000.0,
			 why);
		break;
	case RTSUP_EV_UNSAFE:
		sys = unsafe_event_syscall(e);
		snprintf(what, sizeof(what), "RT-unsafe: %s%s%s", unsafe_reason_name(e->arg),
			 !sys ? "" : e->arg == RTSUP_U_BLOCK ? " in " : " ", sys ? sys : "");
		if (e->arg == RTSUP_U_MIGRATE && RTSUP_MIG_FROM(e->arg2) != RTSUP_MIG_NOCPU)
			snprintf(what, sizeof(what), "RT-unsafe: migration CPU %u -> %u (%s)",
				 RTSUP_MIG_FROM(e->arg2), RTSUP_MIG_TO(e->arg2),
				 mig_why_name(RTSUP_MIG_WHY(e->arg2)));
		break;
	case RTSUP_EV_EXIT:
		snprintf(what, sizeof(what), "exited%s", e->arg ? " mid-cycle" : "");
		break;
	case RTSUP_EV_NEW:
		snprintf(what, sizeof(what), "new target thread");
		break;
	case RTSUP_EV_SIGNAL:
		snprintf(what, sizeof(what), "signal %llu", (unsigned long long)e->arg);
		break;
	default:
		snprintf(what, sizeof(what), "event %u", e->type);
	}
	printf("  %s %7u %-15.15s %s\n", when + 11, e->tid, e->comm, what);
}

/* table_messages - why each component is not OK, under the table */
static void table_messages(const struct collector *c, const struct supervisor *sv)
{
	int i, j;

	for (i = 0; i < c->model.n; i++) {
		const struct thread_model *tm = c->model.t[i];

		if (tm->reported_exit || !tm->st.nmsg)
			continue;
		for (j = 0; j < tm->st.nmsg; j++)
			printf("  %-5s %s[%u]: %s\n", level_name(tm->st.level), tm->comm, tm->tid,
			       tm->st.msg[j]);
	}
	for (j = 0; j < sv->self.nmsg; j++)
		printf("  %-5s rtsup-trace: %s\n", level_name(sv->self.level), sv->self.msg[j]);
}

static void table_interval(const struct collector *c, const struct supervisor *sv,
			   double elapsed, double interval)
{
	bool color = use_color(c->o);
	char title[160];
	int i, shown = 0, live = 0, nrows, cut;
	const int *rows;
	__u64 hidden = 0;

	for (i = 0; i < c->model.n; i++)
		live += c->model.t[i]->alive;
	snprintf(title, sizeof(title),
		 "rtsup-trace  %.0f s  interval %.2f s  threads %d  lost events %llu%s",
		 elapsed, interval, live, (unsigned long long)c->counters[RTSUP_C_RB_DROPS],
		 c->counters[RTSUP_C_MAP_FULL] ? "  (thread map full!)" : "");
	/* a CAN-only run has no thread table */
	if (c->model.n || !sv->can)
		table_header(title);
	else
		printf("%s\n", title);
	rows = table_pick(c, true, &nrows, &cut);
	for (i = 0; rows && i < nrows; i++) {
		const struct thread_model *tm = c->model.t[rows[i]];

		table_row(tm, &tm->win, tm->st.level, color);
	}
	/* no memory for the cut: every row, as --all */
	for (i = 0; !rows && i < c->model.n; i++)
		if (!c->model.t[i]->reported_exit)
			table_row(c->model.t[i], &c->model.t[i]->win, c->model.t[i]->st.level,
				  color);
	table_cut_line(cut);
	table_messages(c, sv);
	if (sv->can)
		can_table(sv->can, &sv->cfg, sv->now, interval, false);
	for (i = 0; i < (int)c->events.n; i++) {
		const struct rtsup_event *e = &c->events.ev[i];

		/* new-thread notices are noise in a live table; exits always show */
		if (e->type == RTSUP_EV_NEW)
			continue;
		if (shown >= MAX_EVENT_LINES && !eventlog_never_folded(e->type)) {
			hidden++;
			continue;
		}
		table_event(c, e);
		shown++;
	}
	hidden += c->events.folded + c->events.dropped;
	if (hidden)
		printf("  ... %llu more events\n", (unsigned long long)hidden);
	if (stacks_shown(c))
		stacks_table(stdout, &c->stacks, &c->model, true);
	printf("\n");
	if (c->o->hist_interval)
		hist_table(c, sv, true);
	fflush(stdout);
}

/* table_causes - a thread's misses by cause, the cause first, numbers after */
static void table_causes(const struct causes *cs, const struct thread_model *tm, __u32 self)
{
	const struct cause_group *g;
	char text[200];
	size_t n, i;

	g = causes_of(cs, tm->tid, &n);
	for (i = 0; i < n && i < 5; i++) {
		causes_group_text(text, sizeof(text), &g[i], self);
		printf("    %llu miss%s: %s (max); %.3f ms in all\n",
		       (unsigned long long)g[i].count, g[i].count == 1 ? "" : "es", text,
		       g[i].total_ns / 1e6);
	}
	if (n > 5)
		printf("    ... %zu other causes\n", n - 5);
}

/* table_map_fill - " thread map 12/1024 (1 %)", nothing when unknown */
static void table_map_fill(const char *name, const struct health_map *m)
{
	if (m->capacity)
		printf(", %s %u/%u (%.0f %%%s)", name, m->entries, m->capacity,
		       health_fill_pct(m), health_near_full(m) ? ", near full" : "");
}

/* table_health - one line of the tool's own health in the summary */
static void table_health(const struct health *h)
{
	printf("health: %s: %llu events lost, %llu cycle records lost, %llu threads not "
	       "tracked, %llu syscall counts not tracked, %llu events not kept, %llu parse "
	       "errors skipped, %llu actions dropped",
	       health_problems(h) ? "DEGRADED" : "ok", (unsigned long long)h->lost_events,
	       (unsigned long long)h->lost_cycle_records,
	       (unsigned long long)h->untracked_threads,
	       (unsigned long long)h->untracked_syscall_counts,
	       (unsigned long long)h->events_not_kept, (unsigned long long)h->parse_errors,
	       (unsigned long long)h->actions_dropped);
	if (h->can_frames_not_counted)
		printf(", %llu CAN frames not counted by id",
		       (unsigned long long)h->can_frames_not_counted);
	if (h->hook_runs_missed)
		printf(", %llu hook runs missed", (unsigned long long)h->hook_runs_missed);
	if (h->hook_runs_recovered)
		printf(" (%llu delimiter runs recovered)",
		       (unsigned long long)h->hook_runs_recovered);
	table_map_fill("thread map", &h->thread_map);
	table_map_fill("CAN id map", &h->can_id_map);
	printf("\n");
}

static void table_summary(const struct collector *c, const struct supervisor *sv,
			  double elapsed)
{
	char when[40];
	struct span_view s;
	char title[200];
	int i, j, nrows, cut;
	const int *rows;

	snprintf(title, sizeof(title),
		 "rtsup-trace summary over %.1f s: %d threads, %llu rare events, %llu lost, "
		 "%llu threads not tracked (map full)",
		 elapsed, c->model.n, (unsigned long long)c->events_total,
		 (unsigned long long)c->counters[RTSUP_C_RB_DROPS],
		 (unsigned long long)c->counters[RTSUP_C_MAP_FULL]);
	if (c->model.n || !sv->can)
		table_header(title);
	else
		printf("%s\n", title);
	rows = table_pick(c, false, &nrows, &cut);
	for (i = 0; i < (rows ? nrows : c->model.n); i++) {
		const struct thread_model *tm = c->model.t[rows ? rows[i] : i];

		table_row(tm, &tm->life, tm->worst, use_color(c->o));
	}
	table_cut_line(cut);
	/* why each thread lost RT safety, by reason and by syscall */
	for (i = 0; i < c->model.n; i++) {
		const struct thread_model *tm = c->model.t[i];

		span_life(&tm->cur, &s);
		if (!s.unsafe_total && !s.misses)
			continue;
		printf("  %u %s: %llu deadline misses, %llu overruns; unsafe:", tm->tid, tm->comm,
		       (unsigned long long)s.misses, (unsigned long long)s.overruns);
		for (j = 0; j < RTSUP_U_NR; j++)
			if (s.unsafe[j])
				printf(" %s %llu", unsafe_reason_name(j),
				       (unsigned long long)s.unsafe[j]);
		for (j = 0; j < tm->nsys; j++)
			printf(" %s=%llu", syscall_name(tm->sys[j].nr) ?: "?",
			       (unsigned long long)tm->sys[j].total);
		printf("\n");
		table_causes(&c->causes_life, tm, self_pid(c));
	}
	if (stacks_shown(c))
		stacks_table(stdout, &c->stacks, &c->model, false);
	if (sv->can)
		can_table(sv->can, &sv->cfg, sv->now, elapsed, true);
	table_health(&sv->health);
	/* every violation, with when and what */
	printf("verdict: %s", level_name(supervise_worst(sv, &c->model)));
	printf(" (%d violations%s)\n", sv->nv + (int)sv->v_dropped,
	       sv->v_dropped ? ", not all listed" : "");
	for (i = 0; i < sv->nv; i++) {
		fmt_time(c, sv->v[i].mono_ns, when, sizeof(when));
		printf("  %s %-5s %s: %s\n", when + 11, level_name(sv->v[i].level),
		       sv->v[i].component, sv->v[i].what);
	}
	if (c->o->hist) {
		printf("\n");
		hist_table(c, sv, false);
		if (sv->can)
			hist_can_table(sv->can, c->o);
	}
	fflush(stdout);
}

void output_interval(struct collector *c, const struct supervisor *s, double elapsed,
		     double interval)
{
	if (c->o->json) {
		model_settle_all(&c->model);	/* each thread's "total" */
		json_interval(c, s, elapsed, interval);
	} else {
		table_interval(c, s, elapsed, interval);	/* the interval's views only */
	}
}

void output_summary(struct collector *c, const struct supervisor *s, double elapsed)
{
	model_settle_all(&c->model);	/* the totals, and --hist's */
	if (c->o->json)
		json_summary(c, s, elapsed);
	else
		table_summary(c, s, elapsed);
}

void output_error(const struct options *o, const char *msg)
{
	fprintf(stderr, "rtsup-trace: %s\n", msg);
	if (o && o->json) {
		json_put(json_pack("{s:s}", "error", msg));
		fputc('\n', stdout);
		fflush(stdout);
	}
}
