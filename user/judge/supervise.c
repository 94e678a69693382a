// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* supervise.c - rules, checks and verdicts for every supervised component */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "judge/supervise.h"
#include "model/syscalls.h"
#include "rtfollow.h"

void supervise_init(struct supervisor *s, struct config *cfg)
{
	memset(s, 0, sizeof(*s));
	s->cfg = *cfg;
	s->gen = 1;
	s->loop = s->loop_run = SELF_SPAN_UNKNOWN;
	status_reset(&s->self);
}

void supervise_reload(struct supervisor *s, struct config *cfg)
{
	config_free(&s->cfg);
	s->cfg = *cfg;
	s->gen++;
}

const struct rule *supervise_rule(const struct supervisor *s, const struct thread_model *tm)
{
	if (tm->rule_gen == s->gen && tm->rule >= 0 && tm->rule < s->cfg.nrules)
		return &s->cfg.rules[tm->rule];
	return &s->cfg.defaults;
}

void component_name(const struct thread_model *tm, char *buf, size_t len)
{
	snprintf(buf, len, "%s[%u]", tm->comm, tm->tid);
}

/* fmt_wall - wall-clock time of a monotonic timestamp */
static void fmt_wall(const struct supervisor *s, __u64 mono, char *buf, size_t len)
{
	/* unsigned: a damaged trace's times wrap instead of overflowing (fuzz_record) */
	__s64 real = (__s64)(mono + (__u64)s->real_off);
	time_t t = real / 1000000000LL;
	struct tm tm;

	gmtime_r(&t, &tm);
	strftime(buf, len, "%Y-%m-%dT%H:%M:%S", &tm);
	snprintf(buf + strlen(buf), len - strlen(buf), ".%03lldZ",
		 (long long)(real % 1000000000LL) / 1000000);
}

/* log_change - one line per level change: time, component, old -> new, why */
static void log_change(struct supervisor *s, const char *comp, enum level from,
		       enum level to, const struct status *st, __u64 now,
		       const struct thread_model *tm)
{
	char when[40], msgs[1024], line[1200];

	fmt_wall(s, now, when, sizeof(when));
	status_join(st, msgs, sizeof(msgs));
	snprintf(line, sizeof(line), "%s %s: %s -> %s%s%s", when, comp, level_name(from),
		 level_name(to), msgs[0] ? ": " : "", msgs);
	if (s->log)
		s->log(comp, from, to, line);
	else
		fprintf(stderr, "rtsup-trace: %s\n", line);
	if (s->on_change) {
		struct level_change c = {
			.component = comp, .from = from, .to = to, .mono_ns = now,
			.when = when, .st = st,
			.tid = tm ? tm->tid : 0, .pid = tm ? tm->tgid : 0,
		};

		s->on_change(s->on_change_ctx, &c);
	}
}

/* add_violation - remember a WARN/ERROR verdict for the summary */
static void add_violation(struct supervisor *s, const char *comp, const struct status *st,
			  __u64 now)
{
	struct violation *v;

	if (s->nv == SUPERVISE_MAX_VIOLATIONS) {
		s->v_dropped++;
		return;
	}
	if (!s->v) {
		s->v = calloc(SUPERVISE_MAX_VIOLATIONS, sizeof(*s->v));
		if (!s->v) {
			s->v_dropped++;
			return;
		}
	}
	v = &s->v[s->nv++];
	v->mono_ns = now;
	snprintf(v->component, sizeof(v->component), "%s", comp);
	v->level = st->level;
	status_join(st, v->what, sizeof(v->what));
	v->nfact = st->nmsg;
	memcpy(v->fact, st->fact, st->nmsg * sizeof(st->fact[0]));
	memcpy(v->text, st->msg, st->nmsg * sizeof(st->msg[0]));
}

/*
 * judge_comp - comp, or when NULL thread tm's component name: made only
 * for a log line or a violation (a thousand snprintf an interval else)
 */
static const char *judge_comp(const char *comp, const struct thread_model *tm, char *buf,
			      size_t len)
{
	if (comp)
		return comp;
	component_name(tm, buf, len);
	return buf;
}

/* judge - a component's new status (comp NULL: thread tm's): log a change, keep violations */
static void judge(struct supervisor *s, const char *comp, const struct status *old,
		  const struct status *st, enum level *worst, __u64 now,
		  const struct thread_model *tm)
{
	char name[48];

	if (st->level != old->level)
		log_change(s, judge_comp(comp, tm, name, sizeof(name)), old->level, st->level, st,
			   now, tm);
	/*
	 * the same complaint interval after interval is one violation, also when
	 * its numbers grow ("no frame for 30 ms", then "for 40 ms")
	 */
	if (st->level >= LEVEL_WARN && !status_same_kind(st, old))
		add_violation(s, judge_comp(comp, tm, name, sizeof(name)), st, now);
	if (st->level > *worst)
		*worst = st->level;
}

/* match_rule - the rule of a thread, once per configuration generation */
static void match_rule(struct supervisor *s, struct thread_model *tm)
{
	struct rule eff;

	if (tm->rule_gen == s->gen)
		return;
	tm->rule = config_match(&s->cfg, tm->pcomm, tm->comm, tm->cgroup, &eff);
	tm->rule_gen = s->gen;
}

/* find_restart - a new thread named like a dead one is its restart */
static void find_restart(struct model *m, struct thread_model *tm)
{
	int i;

	if (tm->restarted_from || tm->judged)
		return;
	for (i = 0; i < m->n; i++) {
		struct thread_model *d = m->t[i];

		if (d != tm && !d->alive && !d->replaced && d->tid != tm->tid &&
		    !strcmp(d->comm, tm->comm) && !strcmp(d->pcomm, tm->pcomm)) {
			d->replaced = true;
			tm->restarted_from = d->tid;
			return;
		}
	}
}

/* unsafe_names - the window's unsafe syscalls, "mmap 1, munmap 1" */
static void unsafe_names(const struct thread_model *tm, char *buf, size_t len)
{
	size_t off = 0;
	int i;

	buf[0] = '\0';
	for (i = 0; i < tm->nsys && off < len; i++) {
		__u64 n = tm->sys[i].total - tm->sys[i].prev;
		const char *name = syscall_name(tm->sys[i].nr);

		if (n)
			off += snprintf(buf + off, len - off, "%s%s %llu", off ? ", " : "",
					name ? name : "?", (unsigned long long)n);
	}
}

void supervise_interval(struct supervisor *s, struct model *m, __u32 bank,
			const struct self_in *self, __u64 now)
{
	struct status st, old;
	char names[256];
	unsigned key;
	bool judged;
	int i;

	for (i = 0; i < m->n; i++) {
		struct thread_model *tm = m->t[i];
		const struct rule *r;
		struct check_in in;

		if (tm->reported_exit)
			continue;	/* judged in the interval it died */
		match_rule(s, tm);
		if (tm->alive)
			find_restart(m, tm);
		tm->judged = true;
		r = supervise_rule(s, tm);
		if (r->th.lifetime)
			model_life_settle(tm);	/* the totals' percentiles checked too */
		/*
		 * RT threads of programs and threads a rule names are held to the
		 * cycle checks; kernel threads (--rt finds watchdogd, irq/N-...)
		 * only when a rule names them
		 */
		if (tm->policy == 1 || tm->policy == 2 || tm->policy == 6)
			tm->was_rt = true;
		judged = tm->rule >= 0 || (tm->was_rt && !tm->kthread);
		/* only shown, and shown as last time: its status is the same */
		key = check_shown_key(judged, tm->kthread, tm->alive);
		if (key && key == tm->shown_key) {
			tm->level_changed = false;
			continue;
		}
		tm->shown_key = key;
		unsafe_names(tm, names, sizeof(names));
		memset(&in, 0, sizeof(in));
		in.win = &tm->win;
		in.life = &tm->life;
		in.rule = r;
		in.judged = judged;
		in.expect_run = tm->rule >= 0;
		in.kthread = tm->kthread;
		in.alive = tm->alive;
		in.left_rt = tm->cur.rt & RTSUP_RT_LEFT;
		in.policy = tm->policy;
		in.prio = tm->prio;
		in.now_ns = now;
		in.first_seen_ns = tm->cur.first_seen;
		in.last_cycle_ns = tm->cur.last_cycle;
		in.nominal_ns = tm->cur.cs.nominal;
		in.exit_expected = s->cmd_mode;
		in.exit_code = tm->cur.exit_code;
		in.exit_mid_cycle = tm->cur.exit_mid_cycle;
		in.process_ended = tm->cur.exit_group;
		in.compat_sys = tm->cur.compat_sys;
		in.restarted_from = tm->restarted_from;
		in.unsafe_names = names;
		in.why_win = tm->why_win[0] ? tm->why_win : NULL;
		in.why_life = tm->why_life[0] ? tm->why_life : NULL;
		check_thread(&in, &st);
		status_copy(&old, &tm->st);
		status_copy(&tm->st, &st);
		tm->level_changed = st.level != old.level;
		judge(s, NULL, &old, &st, &tm->worst, now, tm);
	}
	s->overhead_pct = self->overhead_pct;
	s->stats = self->stats;
	s->loop = self->loop;
	s->loop_run = self->loop_run;
	old = s->self;
	check_self(self, &s->self);
	judge(s, "rtsup-trace", &old, &s->self, &s->self_worst, now, NULL);
}

/* can_judge - the CAN model's verdicts through the same log and violations */
static void can_judge(void *ctx, const char *comp, const struct status *old,
		      const struct status *st, enum level *worst)
{
	struct supervisor *s = ctx;

	judge(s, comp, old, st, worst, s->now, NULL);
}

void supervise_can(struct supervisor *s, __u64 now, double interval_s)
{
	if (!s->can)
		return;
	s->now = now;
	can_model_judge(s->can, &s->cfg, now, interval_s, can_judge, s);
}

enum level supervise_worst(const struct supervisor *s, const struct model *m)
{
	enum level w = s->self_worst;
	int i;

	if (s->can && can_worst(s->can) > w)
		w = can_worst(s->can);

	for (i = 0; i < m->n; i++)
		if (m->t[i]->worst > w)
			w = m->t[i]->worst;
	return w;
}

void supervise_free(struct supervisor *s)
{
	config_free(&s->cfg);
	free(s->v);
	s->v = NULL;
}
