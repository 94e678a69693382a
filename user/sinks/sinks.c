// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* sinks.c - --record and --perfetto during a live run */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>
#include "sinks/sinks.h"
#include "sinks/output_stacks.h"
#include "collect/procmaps.h"
#include "collect/unwind.h"

/* read_file - a whole small text file, malloc'd; NULL if unreadable */
static char *read_file(const char *path)
{
	FILE *f = fopen(path, "re");
	char *buf = NULL;
	size_t n = 0, cap = 0, r;

	if (!f)
		return NULL;
	do {
		if (n + 4096 + 1 > cap) {
			char *nb = realloc(buf, cap = n + 65536);

			if (!nb)
				break;
			buf = nb;
		}
		r = fread(buf + n, 1, cap - n - 1, f);
		n += r;
	} while (r > 0);
	fclose(f);
	if (buf)
		buf[n] = '\0';
	return buf;
}

void perfetto_name(struct perfetto *pf, __u32 **named, int *n, int *cap, __u32 tgid,
		   __u32 tid, const char *comm, const char *pcomm)
{
	int lo = 0, hi = *n;

	while (lo < hi) {
		int mid = (lo + hi) / 2;

		if ((*named)[mid] == tid)
			return;
		if ((*named)[mid] < tid)
			lo = mid + 1;
		else
			hi = mid;
	}
	if (*n == *cap) {
		__u32 *nn = realloc(*named, (*cap ? *cap * 2 : 64) * sizeof(**named));

		if (!nn)
			return;
		*named = nn;
		*cap = *cap ? *cap * 2 : 64;
	}
	memmove(*named + lo + 1, *named + lo, (*n - lo) * sizeof(**named));
	(*named)[lo] = tid;
	(*n)++;
	perfetto_thread(pf, tgid, tid, comm, pcomm);
}

/* sink_cycle - collector callback: one finished cycle */
static void sink_cycle(void *ctx, const struct rtsup_cycle_rec *r)
{
	struct sinks *sk = ctx;
	struct rec_cycle rc;

	/* tracks are named at the interval, when the model knows the names */
	if (sk->pf)
		perfetto_cycle(sk->pf, r->tgid, r->tid, &r->c);
	if (!sk->rec || sk->failed)
		return;
	rc.end = r->c.start + r->c.exec;
	rc.r = *r;
	if (rec_write(sk->rec, REC_CYCLE, &rc, sizeof(rc), sk->err, sizeof(sk->err)))
		sk->failed = true;
}

/* sink_event - collector callback: one rare event */
static void sink_event(void *ctx, const struct rtsup_event *e)
{
	struct sinks *sk = ctx;

	if (sk->pf && e->type != RTSUP_EV_NEW)
		perfetto_event(sk->pf, e);
	if (sk->rec && !sk->failed &&
	    rec_write(sk->rec, REC_EVENT, e, sizeof(*e), sk->err, sizeof(sk->err)))
		sk->failed = true;
}

/* maps_new - has this set of the process's mappings not been written yet? */
static bool maps_new(struct sinks *sk, __u32 tgid, __u32 gen)
{
	void *nm;
	int i;

	for (i = 0; i < sk->nmaps_written; i++) {
		if (sk->maps_written[i].tgid != tgid)
			continue;
		if (sk->maps_written[i].gen == gen)
			return false;
		sk->maps_written[i].gen = gen;
		return true;
	}
	nm = realloc(sk->maps_written, (i + 1) * sizeof(*sk->maps_written));
	if (!nm)
		return true;
	sk->maps_written = nm;
	sk->maps_written[i].tgid = tgid;
	sk->maps_written[i].gen = gen;
	sk->nmaps_written++;
	return true;
}

/*
 * record_stack - the stack's pcs for replay, after its process's mappings
 * (REC_MODULE) whenever they were read again
 */
static int record_stack(struct sinks *sk, const struct rtsup_stack_rec *r,
			const struct stack_frame *f, int n, const struct stack_maps *m)
{
	struct rec_module rm;
	struct rec_stack rs;
	int i;

	if (maps_new(sk, r->tgid, m->gen)) {
		for (i = 0; i < m->n; i++) {
			memset(&rm, 0, sizeof(rm));
			rm.start = m->maps[i].start;
			rm.end = m->maps[i].end;
			rm.pgoff = m->maps[i].pgoff;
			rm.tgid = r->tgid;
			rm.gen = m->gen;
			rm.flags = m->flags[i];
			snprintf(rm.path, sizeof(rm.path), "%s", m->maps[i].path);
			snprintf(rm.build_id, sizeof(rm.build_id), "%s", m->bids[i]);
			if (rec_write(sk->rec, REC_MODULE, &rm, sizeof(rm), sk->err, sizeof(sk->err)))
				return -1;
		}
	}
	memset(&rs, 0, sizeof(rs));
	rs.ts = r->ts;
	rs.tid = r->tid;
	rs.tgid = r->tgid;
	rs.reason = r->reason;
	rs.nr = r->nr;
	rs.kind = r->kind;
	for (i = 0; i < n && i < RTSUP_STACK_DEPTH; i++)
		rs.pcs[i] = f[i].pc;
	rs.npcs = i;
	return rec_write(sk->rec, REC_STACK, &rs, sizeof(rs), sk->err, sizeof(sk->err));
}

/* sink_stack - collector callback: a symbolized stack, to Perfetto and the record */
static void sink_stack(void *ctx, const struct rtsup_stack_rec *r, const struct stack_frame *f,
		       int n, const struct stack_maps *m)
{
	struct sinks *sk = ctx;
	struct stack_entry e = { .reason = r->reason, .nr = r->nr };
	char what[64], text[4096];

	if (sk->rec && !sk->failed && record_stack(sk, r, f, n, m))
		sk->failed = true;
	if (!sk->pf)
		return;
	stack_what(&e, what, sizeof(what));
	stack_format(f, n, "\n<- ", text, sizeof(text));
	perfetto_stack(sk->pf, r->ts, r->tgid, r->tid, what, text);
}

/* header - where and when, and the configuration */
static void header(struct rec_header *h, const struct options *o, const struct supervisor *s,
		   const struct collector *c)
{
	struct utsname u;

	memset(h, 0, sizeof(*h));
	if (!uname(&u)) {
		snprintf(h->kernel, sizeof(h->kernel), "%.60s %.60s", u.release, u.version);
		snprintf(h->host, sizeof(h->host), "%.63s", u.nodename);
	}
	if (o->config_path) {
		snprintf(h->config_path, sizeof(h->config_path), "%s", o->config_path);
		h->config_text = read_file(o->config_path);
	}
	h->start_mono_ns = c->start_ns;
	h->start_real_ns = c->start_ns + c->real_off;
	h->interval_s = o->interval;
	h->ewma_w = (__u32)(s->cfg.defaults.ewma_weight * RTSUP_EWMA_ONE + 0.5);
}

int sinks_open(struct sinks *sk, const struct options *o, const struct supervisor *s,
	       struct collector *c)
{
	struct rec_header h;
	int err = 0;

	memset(sk, 0, sizeof(*sk));
	sk->o = o;
	sk->model = &c->model;
	if (o->record_path) {
		header(&h, o, s, c);
		err = rec_create(&sk->rec, o->record_path, &h, sk->err, sizeof(sk->err));
		free(h.config_text);
	}
	if (!err && o->perfetto_path)
		err = perfetto_open(&sk->pf, o->perfetto_path, sk->err, sizeof(sk->err));
	if (err) {
		fprintf(stderr, "rtsup-trace: %s\n", sk->err);
		return -1;
	}
	c->on_cycle = sink_cycle;
	c->on_rare = sink_event;
	c->on_stack = sink_stack;
	c->sink_ctx = sk;
	return 0;
}

void rec_thread_from(struct rec_thread *r, const struct thread_model *tm)
{
	const struct rtsup_thread *t = &tm->cur;
	int i;

	memset(r, 0, sizeof(*r));
	r->tid = tm->tid;
	r->tgid = tm->tgid;
	memcpy(r->comm, tm->comm, sizeof(r->comm));
	memcpy(r->pcomm, tm->pcomm, sizeof(r->pcomm));
	r->policy = tm->policy;
	r->prio = tm->prio;
	r->first_seen = t->first_seen;
	r->vol_cs = t->vol_cs;
	r->invol_cs = t->invol_cs;
	r->migrations = t->migrations;
	r->signals = t->signals;
	r->exited = t->exited;
	r->exit_code = t->exit_code;
	r->exit_mid_cycle = t->exit_mid_cycle;
	r->exit_group = t->exit_group;
	r->mode = t->cs.mode;
	r->resets = t->resets;
	r->nominal = t->cs.nominal;
	r->last_cycle = t->last_cycle;
	r->syscalls = t->syscalls;
	r->minflt = t->minflt;
	r->majflt = t->majflt;
	memcpy(r->unsafe, t->unsafe, sizeof(r->unsafe));
	for (i = 0; i < tm->nsys && i < 16; i++) {
		r->sys[i].nr = tm->sys[i].nr;
		r->sys[i].total = tm->sys[i].total;
	}
	r->nsys = i;
}

/* write_states - every thread's state, then the mark */
static int write_states(struct sinks *sk, const struct collector *c, const struct self_in *self,
			__u64 now, enum rec_type mark)
{
	struct rec_interval ri = {};
	struct rec_thread rt;
	int i;

	if (!sk->rec)
		return 0;
	for (i = 0; i < c->model.n; i++) {
		const struct thread_model *tm = c->model.t[i];

		if (tm->reported_exit)
			continue;
		rec_thread_from(&rt, tm);
		if (rec_write(sk->rec, REC_THREAD, &rt, sizeof(rt), sk->err, sizeof(sk->err)))
			return -1;
	}
	ri.mono_ns = now;
	memcpy(ri.counters, c->counters, sizeof(ri.counters));
	ri.overhead_pct = self->overhead_pct;
	return rec_write(sk->rec, mark, &ri, sizeof(ri), sk->err, sizeof(sk->err));
}

/* name_tracks - a Perfetto track name for every thread the model knows */
static void name_tracks(struct sinks *sk, const struct model *m)
{
	int i;

	for (i = 0; sk->pf && i < m->n; i++)
		perfetto_name(sk->pf, &sk->named, &sk->nnamed, &sk->cap, m->t[i]->tgid,
			      m->t[i]->tid, m->t[i]->comm, m->t[i]->pcomm);
}

/*
 * stop_recording - a write failed (disk full, I/O error): the file keeps its
 * whole records, the supervision goes on without it, the run ends with 1
 */
static void stop_recording(struct sinks *sk)
{
	char err[sizeof(sk->err)];

	sk->failed = true;
	fprintf(stderr, "rtsup-trace: --record: %s: recording stopped, supervision goes on\n",
		sk->err);
	rec_close(sk->rec, err, sizeof(err));	/* it failed already: said once */
	sk->rec = NULL;
}

int sinks_interval(struct sinks *sk, const struct collector *c, const struct self_in *self,
		   __u64 now)
{
	name_tracks(sk, &c->model);
	if (sk->rec && (sk->failed || write_states(sk, c, self, now, REC_INTERVAL)))
		stop_recording(sk);
	return 0;
}

int sinks_close(struct sinks *sk, const struct collector *c, const struct self_in *self,
		__u64 now)
{
	int err = 0;

	name_tracks(sk, &c->model);
	if (sk->rec && (sk->failed || write_states(sk, c, self, now, REC_END))) {
		stop_recording(sk);
	} else if (sk->rec) {
		if (rec_close(sk->rec, sk->err, sizeof(sk->err))) {
			fprintf(stderr, "rtsup-trace: --record: %s\n", sk->err);
			err = -1;
		}
		sk->rec = NULL;
	}
	if (sk->failed)
		err = -1;	/* the recording was cut: an error of the run */
	if (sk->pf) {
		if (perfetto_close(sk->pf, sk->err, sizeof(sk->err))) {
			fprintf(stderr, "rtsup-trace: --perfetto: %s\n", sk->err);
			err = -1;
		}
		sk->pf = NULL;
	}
	free(sk->named);
	sk->named = NULL;
	free(sk->maps_written);
	sk->maps_written = NULL;
	return err;
}
