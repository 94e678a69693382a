// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * replay.c - rebuild the kernel's per-thread statistics from recorded cycles
 * with the same state-machine code (include/cycle.h), and judge them again.
 * Counters that are not per cycle (context switches, unsafe events) come
 * from the per-interval thread records.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "collect/collector.h"
#include "cycle.h"
#include "sinks/output.h"
#include "sinks/perfetto.h"
#include "sinks/progress.h"
#include "sinks/record.h"
#include "offline/replay.h"
#include "sinks/sinks.h"
#include "collect/targets.h"
#include "collect/procmaps.h"
#include "collect/unwind.h"
#include "sinks/output_stacks.h"

struct replay {
	struct collector c;	/* the data the outputs read; no kernel behind it */
	struct supervisor *s;
	struct perfetto *pf;
	__u32 *named;
	int nnamed, cap;
	__u32 epoch;
	__u64 start, last;
	bool ended;
	struct progress pg;	/* on stderr, cleared before each report */
};

/* thread_of - the model of a recorded thread */
static struct thread_model *thread_of(struct replay *r, __u32 tid, __u32 tgid)
{
	struct thread_model *tm = model_get(&r->c.model, tid, true);

	if (tm && !tm->cur.tid) {
		tm->cur.tid = tid;
		tm->cur.tgid = tgid;
		tm->tgid = tgid;
		tm->rule = -1;
		tm->alive = true;
		tm->cur.epoch = ~0U;
	}
	return tm;
}

/* on_thread - identity and counters as the kernel had them */
static void on_thread(struct replay *r, const struct rec_thread *rt)
{
	struct thread_model *tm = thread_of(r, rt->tid, rt->tgid);
	struct rtsup_thread *t;
	__u32 i;

	if (!tm)
		return;
	t = &tm->cur;
	memcpy(tm->comm, rt->comm, sizeof(tm->comm));
	memcpy(t->comm, rt->comm, sizeof(t->comm));
	memcpy(tm->pcomm, rt->pcomm, sizeof(tm->pcomm));
	/* the file may come from anywhere: names stay printable and terminated */
	tm->comm[RTSUP_COMM_LEN - 1] = tm->pcomm[RTSUP_COMM_LEN - 1] = '\0';
	comm_sanitize(tm->comm, RTSUP_COMM_LEN);
	comm_sanitize(tm->pcomm, RTSUP_COMM_LEN);
	tm->policy = rt->exited ? -1 : rt->policy;
	tm->prio = rt->prio;
	tm->alive = !rt->exited;
	t->first_seen = rt->first_seen;
	t->vol_cs = rt->vol_cs;
	t->invol_cs = rt->invol_cs;
	t->migrations = rt->migrations;
	t->signals = rt->signals;
	t->exited = rt->exited;
	t->exit_code = rt->exit_code;
	t->exit_mid_cycle = rt->exit_mid_cycle;
	t->exit_group = rt->exit_group;
	t->cs.mode = rt->mode;
	t->cs.nominal = rt->nominal;
	t->syscalls = rt->syscalls;
	t->minflt = rt->minflt;
	t->majflt = rt->majflt;
	memcpy(t->unsafe, rt->unsafe, sizeof(t->unsafe));
	for (i = 0; i < rt->nsys && i < 16; i++)
		model_sys_set(tm, rt->sys[i].nr, rt->sys[i].total);
}

/* on_cycle - one recorded cycle, accounted like the kernel did */
static void on_cycle(struct replay *r, const struct rec_cycle *rc)
{
	struct thread_model *tm = thread_of(r, rc->r.tid, rc->r.tgid);
	struct cycle_cfg cf = {
		.ewma_w = (__u32)(r->s->cfg.defaults.ewma_weight * RTSUP_EWMA_ONE + 0.5),
		.epoch = r->epoch,
	};

	if (!tm)
		return;
	if (rc->r.resets != tm->cur.resets) {
		/* the kernel dropped the start-up stats before this cycle: so do we */
		cycle_reset_stats(&tm->cur);
		tm->cur.resets = rc->r.resets;
	}
	cycle_account(&tm->cur, &cf, &rc->r.c);
	/* counters come from the thread records, not from the cycles */
	tm->cur.minflt -= rc->r.c.minflt;
	tm->cur.majflt -= rc->r.c.majflt;
	tm->cur.unsafe[RTSUP_U_MINFLT] -= rc->r.c.minflt;
	tm->cur.unsafe[RTSUP_U_MAJFLT] -= rc->r.c.majflt;
	if (r->pf)
		perfetto_cycle(r->pf, rc->r.tgid, rc->r.tid, &rc->r.c);
}

/* on_event - a rare event for the interval's list */
static void on_event(struct replay *r, const struct rtsup_event *e)
{
	struct collector *c = &r->c;

	if (r->pf && e->type != RTSUP_EV_NEW)
		perfetto_event(r->pf, e);
	collector_take_event(c, e);
}

/* unwinder_of - replay's symbolizer, made when the trace has stacks */
static struct unwinder *unwinder_of(struct replay *r)
{
	if (!r->c.unwinder)
		r->c.unwinder = unwinder_new();
	return r->c.unwinder;
}

/* on_module - a recorded mapping of a process, for the stacks that follow */
static void on_module(struct replay *r, const struct rec_module *rm)
{
	struct unwinder *u = unwinder_of(r);
	struct procmap m = { .start = rm->start, .end = rm->end, .pgoff = rm->pgoff };
	char bid[sizeof(rm->build_id) + 1];

	if (!u)
		return;
	memcpy(m.path, rm->path, sizeof(m.path) - 1);
	memcpy(bid, rm->build_id, sizeof(rm->build_id));
	bid[sizeof(rm->build_id)] = '\0';
	unwind_offline_map(u, rm->tgid, rm->gen, &m, rm->flags, bid);
}

/* on_stack - a recorded stack: symbolized here, from the same binaries */
static void on_stack(struct replay *r, const struct rec_stack *rs)
{
	static struct stack_frame frames[STACK_MAX_FRAMES];
	struct unwinder *u = unwinder_of(r);
	struct stack_entry e = { .reason = rs->reason, .nr = rs->nr };
	char what[64], text[4096];
	int n;

	if (!u)
		return;
	n = unwind_offline_pcs(u, rs->tgid, rs->pcs, rs->npcs < RTSUP_STACK_DEPTH ?
			       rs->npcs : RTSUP_STACK_DEPTH, frames, STACK_MAX_FRAMES);
	r->c.stacks.records++;
	stackagg_add_kind(&r->c.stacks, rs->tid, rs->tgid, NULL, rs->reason, rs->nr, rs->kind,
			  frames, n);
	if (!r->pf)
		return;
	stack_what(&e, what, sizeof(what));
	stack_format(frames, n, "\n<- ", text, sizeof(text));
	perfetto_stack(r->pf, rs->ts, rs->tgid, rs->tid, what, text);
}

/* on_mark - an interval (or the run) ended: judge and report it */
static void on_mark(struct replay *r, const struct rec_interval *ri, bool end)
{
	struct collector *c = &r->c;
	struct self_in self = {
		.overhead_pct = ri->overhead_pct,
		.th = &r->s->cfg.defaults.th,
		.untracked_threads = ri->counters[RTSUP_C_MAP_FULL],
		/* the live loop's own time is not recorded: unknown */
		.loop = SELF_SPAN_UNKNOWN,
		.loop_run = SELF_SPAN_UNKNOWN,
	};
	int i;

	model_sort(&c->model);	/* the reports list threads by tid */
	self.lost_events = lost_records(ri->counters) - lost_records(c->counters);
	memcpy(c->counters, ri->counters, sizeof(c->counters));
	/* the recorded counters; map fills were not recorded (capacity 0: unknown) */
	health_counters(&r->s->health, ri->counters);
	for (i = 0; r->pf && i < c->model.n; i++)
		perfetto_name(r->pf, &r->named, &r->nnamed, &r->cap, c->model.t[i]->tgid,
			      c->model.t[i]->tid, c->model.t[i]->comm, c->model.t[i]->pcomm);
	c->bank = RTSUP_BANK(r->epoch);
	r->epoch++;
	/* what the live collector computes per sample: the change since the last mark */
	for (i = 0; i < c->model.n; i++)
		model_views(c->model.t[i], &c->model.t[i]->cur, c->model.t[i]->snap, c->bank);
	/* as collector_sample: the checks name this interval's causes, not the last's */
	eventlog_finish(&c->events);
	causes_sort(&c->causes_win);
	causes_sort(&c->causes_life);
	causes_to_model(&c->causes_win, &c->causes_life, &c->model);
	supervise_interval(r->s, &c->model, c->bank, &self, ri->mono_ns);
	r->s->health.events_not_kept += c->events.dropped;
	/* like a live run: the last, partial interval, then the summary */
	progress_end(&r->pg);
	output_interval(c, r->s, (ri->mono_ns - r->start) / 1e9, (ri->mono_ns - r->last) / 1e9);
	if (end) {
		output_summary(c, r->s, (ri->mono_ns - r->start) / 1e9);
		r->ended = true;
		return;
	}
	r->last = ri->mono_ns;
	collector_clear_events(c);
	for (i = 0; i < c->model.n; i++) {
		struct thread_model *tm = c->model.t[i];
		int j;

		for (j = 0; j < tm->nsys; j++)
			tm->sys[j].prev = tm->sys[j].total;
		if (!tm->alive)
			tm->reported_exit = true;
		if (!tm->snap)
			tm->snap = malloc(sizeof(*tm->snap));
		if (!tm->snap) {
			fprintf(stderr, "rtsup-trace: replay: out of memory\n");
			exit(1);
		}
		*tm->snap = tm->cur;
	}
}

int replay_run(const struct options *o, struct supervisor *s)
{
	static union {
		struct rec_thread t;
		struct rec_cycle c;
		struct rtsup_event e;
		struct rec_interval i;
		struct rec_stack st;
		struct rec_module m;
		char raw[REC_MAX_PAYLOAD];
	} buf;
	struct replay r;
	struct rec_reader *rd;
	struct rec_header h;
	enum rec_type type;
	char err[512];
	size_t len;
	__u64 done, total;
	int n, ret = 1;

	memset(&r, 0, sizeof(r));
	r.s = s;
	r.c.o = o;
	if (rec_open(&rd, o->replay_path, &h, err, sizeof(err))) {
		output_error(o, err);
		return 1;
	}
	free(h.config_text);
	r.c.real_off = (__s64)(h.start_real_ns - h.start_mono_ns);
	s->real_off = r.c.real_off;
	r.start = r.last = h.start_mono_ns;
	if (o->perfetto_path && perfetto_open(&r.pf, o->perfetto_path, err, sizeof(err))) {
		output_error(o, err);
		goto out;
	}
	rec_tell(rd, &done, &total);
	progress_start(&r.pg, stderr, total, !o->quiet && isatty(STDERR_FILENO));
	while ((n = rec_next(rd, &type, &buf, &len, err, sizeof(err))) > 0 && !r.ended) {
		if (progress_due(&r.pg)) {
			rec_tell(rd, &done, &total);
			progress_draw(&r.pg, done);
		}
		switch (type) {
		case REC_THREAD:
			on_thread(&r, &buf.t);
			break;
		case REC_CYCLE:
			on_cycle(&r, &buf.c);
			break;
		case REC_EVENT:
			on_event(&r, &buf.e);
			break;
		case REC_INTERVAL:
		case REC_END:
			on_mark(&r, &buf.i, type == REC_END);
			break;
		case REC_STACK:
			on_stack(&r, &buf.st);
			break;
		case REC_MODULE:
			on_module(&r, &buf.m);
			break;
		}
	}
	progress_end(&r.pg);
	if (!r.ended && n >= 0)
		snprintf(err, sizeof(err), "%s: the trace ends without its end record "
			 "(the recording was cut short)", o->replay_path);
	if (!r.ended) {
		/* a damaged or cut trace: what its whole intervals said is not lost */
		if (r.epoch)
			output_summary(&r.c, s, (r.last - r.start) / 1e9);
		output_error(o, err);
		goto out;
	}
	ret = 0;
out:
	if (r.pf && perfetto_close(r.pf, err, sizeof(err))) {
		output_error(o, err);
		ret = 1;
	}
	if (!ret && o->check && level_fails(supervise_worst(s, &r.c.model), o->fail_on))
		ret = 2;
	free(r.named);
	rec_free(rd);
	collector_free(&r.c);	/* no ring buffer here: the model and the events */
	return ret;
}
