// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* prom.c - Prometheus text exposition of threads, verdicts and the supervisor */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "hist.h"
#include "sinks/prom.h"
#include "model/syscalls.h"

/* Histogram bucket bounds in ns: 1 us .. 1 s, then +Inf. */
static const __u64 le_ns[] = {
	1000, 2500, 5000, 10000, 25000, 50000, 100000, 250000, 500000,
	1000000, 2500000, 5000000, 10000000, 25000000, 50000000,
	100000000, 250000000, 500000000, 1000000000,
};
#define NLE (sizeof(le_ns) / sizeof(le_ns[0]))

int prom_level_value(enum level l)
{
	switch (l) {
	case LEVEL_OK: return 0;
	case LEVEL_WARN: return 1;
	case LEVEL_ERROR: return 2;
	case LEVEL_STALE: return 3;
	}
	return 2;
}

static void puts_(struct textbuf *b, const char *s)
{
	textbuf_put(b, s, strlen(s));
}

void prom_printf(struct textbuf *b, const char *fmt, ...)
{
	va_list ap;
	int n;

	/* once into the room there is; again only when it did not fit */
	if (!textbuf_room(b, 64))
		return;
	va_start(ap, fmt);
	n = vsnprintf(b->p + b->len, b->cap - b->len, fmt, ap);
	va_end(ap);
	if (n < 0)
		return;
	if ((size_t)n >= b->cap - b->len) {
		if (!textbuf_room(b, n))
			return;
		va_start(ap, fmt);
		vsnprintf(b->p + b->len, n + 1, fmt, ap);
		va_end(ap);
	}
	b->len += n;
}

/* put_escaped - a label value: backslash, double quote and newline escaped */
static void put_escaped(struct textbuf *b, const char *s)
{
	size_t n;

	for (;;) {
		n = strcspn(s, "\\\"\n");
		textbuf_put(b, s, n);
		s += n;
		if (!*s)
			return;
		textbuf_put(b, *s == '\n' ? "\\n" : *s == '"' ? "\\\"" : "\\\\", 2);
		s++;
	}
}

/* put_kv - one label, k="v", its value escaped */
static void put_kv(struct textbuf *b, const char *k, const char *v)
{
	puts_(b, k);
	textbuf_put(b, "=\"", 2);
	put_escaped(b, v);
	textbuf_put(b, "\"", 1);
}

void prom_family(struct textbuf *b, const char *name, const char *type, const char *help)
{
	prom_printf(b, "# HELP %s %s\n# TYPE %s %s\n", name, help, name, type);
}

/* put_labels - {k="v",...} from a NULL-terminated list */
static void put_labels(struct textbuf *b, const char *const *labels)
{
	int i;

	if (!labels || !labels[0])
		return;
	textbuf_put(b, "{", 1);
	for (i = 0; labels[i] && labels[i + 1]; i += 2) {
		if (i)
			textbuf_put(b, ",", 1);
		put_kv(b, labels[i], labels[i + 1]);
	}
	textbuf_put(b, "}", 1);
}

/* put_value - integers exactly, other numbers with full precision */
static void put_value(struct textbuf *b, double v)
{
	if (v >= 0 && v < 9007199254740992.0 && v == (double)(unsigned long long)v) {
		textbuf_put(b, " ", 1);
		textbuf_u64(b, (unsigned long long)v);
		textbuf_put(b, "\n", 1);
	} else {
		prom_printf(b, " %.17g\n", v);
	}
}

/*
 * put_seconds - ns as seconds, the exact decimal: it reads back as the
 * same double as ns / 1e9 (both are that decimal, correctly rounded)
 */
static void put_seconds(struct textbuf *b, __u64 ns)
{
	textbuf_put(b, " ", 1);
	textbuf_u64(b, ns / 1000000000);
	textbuf_fraction(b, ns % 1000000000, 9, false);
	textbuf_put(b, "\n", 1);
}

void prom_sample(struct textbuf *b, const char *name, double value, const char *const *labels)
{
	puts_(b, name);
	put_labels(b, labels);
	put_value(b, value);
}

/*
 * A thread's labels, rendered once per exposition (every family repeats
 * them): 'lab' is comm="..",tid="..",tgid="..",process="..", 'comp' is
 * component="comm[tid]"; both escaped, offsets into one text.
 */
struct tlab {
	size_t lab, lab_len, comp, comp_len;
};

struct tlabels {
	struct textbuf text;
	struct tlab *t;	/* per model thread */
};

static void put_thread_labels(struct textbuf *b, const struct thread_model *tm,
			      struct tlab *t)
{
	char comp[48];

	t->lab = b->len;
	textbuf_put(b, "comm=\"", 6);
	put_escaped(b, tm->comm);
	textbuf_put(b, "\",tid=\"", 7);
	textbuf_u64(b, tm->tid);
	textbuf_put(b, "\",tgid=\"", 8);
	textbuf_u64(b, tm->tgid);
	textbuf_put(b, "\",process=\"", 11);
	put_escaped(b, tm->pcomm[0] ? tm->pcomm : tm->comm);
	textbuf_put(b, "\"", 1);
	t->lab_len = b->len - t->lab;
	t->comp = b->len;
	snprintf(comp, sizeof(comp), "%s[%u]", tm->comm, tm->tid);
	put_kv(b, "component", comp);
	t->comp_len = b->len - t->comp;
}

static int tlabels_make(struct tlabels *tl, const struct model *m)
{
	int i;

	memset(tl, 0, sizeof(*tl));
	tl->t = calloc(m->n ? m->n : 1, sizeof(*tl->t));
	if (!tl->t)
		return -1;
	for (i = 0; i < m->n; i++)
		put_thread_labels(&tl->text, m->t[i], &tl->t[i]);
	return tl->text.oom ? -1 : 0;
}

static void tlabels_free(struct tlabels *tl)
{
	textbuf_free(&tl->text);
	free(tl->t);
}

/*
 * t_open - name and suffix, '{' and thread i's labels (the component label
 * first when 'comp'); the caller adds more labels, then '}' and the value
 */
static void t_open(struct textbuf *b, const char *name, const char *suffix,
		   const struct tlabels *tl, int i, bool comp)
{
	puts_(b, name);
	puts_(b, suffix);
	textbuf_put(b, "{", 1);
	if (comp) {
		textbuf_put(b, tl->text.p + tl->t[i].comp, tl->t[i].comp_len);
		textbuf_put(b, ",", 1);
	}
	textbuf_put(b, tl->text.p + tl->t[i].lab, tl->t[i].lab_len);
}

/* sample_t - one sample of thread i, its labels (and the component one when 'comp') */
static void sample_t(struct textbuf *b, const char *name, double value,
		     const struct tlabels *tl, int i, bool comp)
{
	t_open(b, name, "", tl, i, comp);
	textbuf_put(b, "}", 1);
	put_value(b, value);
}

/* kv_open - name{thread i's labels,k="v"} (the value left to the caller) */
static void kv_open(struct textbuf *b, const char *name, const struct tlabels *tl, int i,
		    const char *k, const char *v)
{
	t_open(b, name, "", tl, i, false);
	textbuf_put(b, ",", 1);
	put_kv(b, k, v);
	textbuf_put(b, "}", 1);
}

/* sample_kv - one sample of thread i with one more label than the thread's */
static void sample_kv(struct textbuf *b, const char *name, double value,
		      const struct tlabels *tl, int i, const char *k, const char *v)
{
	kv_open(b, name, tl, i, k, v);
	put_value(b, value);
}

/* le_text - the "le" label of bound k, as "%g" of seconds writes it */
static const char *le_text(size_t k)
{
	static char text[NLE][16];

	if (!text[k][0])
		snprintf(text[k], sizeof(text[k]), "%g", le_ns[k] / 1e9);
	return text[k];
}

/*
 * le_below - the kernel buckets wholly at or below bound k are those before
 * this one (HIST_BUCKETS: all of them)
 */
static int le_below(size_t k)
{
	static int first[NLE];
	static bool done;

	if (!done) {
		for (size_t j = 0; j < NLE; j++) {
			int i = 0;

			while (i < HIST_BUCKETS && hist_bucket_high(i) <= le_ns[j])
				i++;
			first[j] = i;
		}
		done = true;
	}
	return first[k];
}

/*
 * put_histogram - a cumulative histogram from the thread's lifetime one
 * (metric 'metric'). A kernel bucket counts below a bound only when all of
 * it is below, so a bucket may lag by up to 1/8 of its bound (the kernel's
 * resolution). The counts are the model's lifetime ones (u64: the kernel's
 * plus their wraps), not the __u32 buckets alone: those wrap, and a
 * Prometheus histogram never decreases.
 */
static void put_histogram(struct textbuf *b, const char *name, const struct thread_model *tm,
			  int metric, const struct tlabels *tl, int ti)
{
	const struct rtsup_metric_stats *st = &tm->cur.m[metric];
	__u64 h[HIST_BUCKETS], cum = 0;
	char bucket[96];
	int i, lo = 0, hi = HIST_BUCKETS - 1;
	size_t k;

	/* its counts outside [lo, hi] are 0 */
	if (!model_life_counts(tm, metric, h, &lo, &hi))
		hist_delta(st->hist, NULL, h);

	snprintf(bucket, sizeof(bucket), "%s_bucket", name);
	for (k = 0, i = lo; k < NLE; k++) {
		for (; i < le_below(k) && i <= hi; i++)
			cum += h[i];
		sample_kv(b, bucket, cum < st->count ? cum : st->count, tl, ti, "le", le_text(k));
	}
	sample_kv(b, bucket, st->count, tl, ti, "le", "+Inf");
	t_open(b, name, "_sum", tl, ti, false);
	prom_printf(b, "} %.9f\n", st->sum / 1e9);
	t_open(b, name, "_count", tl, ti, false);
	textbuf_put(b, "}", 1);
	put_value(b, st->count);
}

/*
 * exported - alive threads, and dead judged threads (RT or named by a rule:
 * STALE) until a restarted instance replaces them. Other threads leave with
 * their death, so a churning thread pool does not pile up series.
 */
static bool exported(const struct thread_model *tm)
{
	return tm->alive || (!tm->replaced && (tm->was_rt || tm->rule >= 0));
}

/* Per-thread counter families: name, help, and where the value is. */
enum tcounter {
	TC_CYCLES, TC_MISSES, TC_OVERRUNS, TC_SYSCALLS, TC_MIGRATIONS, TC_SIGNALS, TC_NR
};

static const struct {
	const char *name;
	const char *help;
} tcounters[TC_NR] = {
	[TC_CYCLES] = { "rtsup_thread_cycles_total", "Finished cycles of the thread." },
	[TC_MISSES] = { "rtsup_thread_deadline_misses_total",
			"Cycles whose requested absolute release was already past." },
	[TC_OVERRUNS] = { "rtsup_thread_overruns_total",
			  "Cycles whose execution time exceeded the nominal period." },
	[TC_SYSCALLS] = { "rtsup_thread_syscalls_total",
			  "Syscalls inside cycles, the cycle delimiter excluded." },
	[TC_MIGRATIONS] = { "rtsup_thread_migrations_total", "CPU changes of the thread." },
	[TC_SIGNALS] = { "rtsup_thread_signals_total", "Signals delivered to the thread." },
};

static __u64 tcounter_value(const struct span_view *s, enum tcounter c)
{
	switch (c) {
	case TC_CYCLES: return s->cycles;
	case TC_MISSES: return s->misses;
	case TC_OVERRUNS: return s->overruns;
	case TC_SYSCALLS: return s->syscalls;
	case TC_MIGRATIONS: return s->migrations;
	case TC_SIGNALS: return s->signals;
	default: return 0;
	}
}

/* put_info - rtsup_thread_info of thread i: its labels, then policy, priority, cpus, rule */
static void put_info(struct textbuf *b, const struct prom_in *in, const struct tlabels *tl,
		     int i)
{
	const struct thread_model *tm = in->m->t[i];
	const char *rule = "";
	char prio[16];

	snprintf(prio, sizeof(prio), "%d", tm->prio);
	if (tm->rule >= 0 && tm->rule_gen == in->s->gen && tm->rule < in->s->cfg.nrules)
		rule = in->s->cfg.rules[tm->rule].name;
	t_open(b, "rtsup_thread_info", "", tl, i, false);
	textbuf_put(b, ",", 1);
	put_kv(b, "policy", policy_name(tm->policy));
	textbuf_put(b, ",", 1);
	put_kv(b, "priority", prio);
	textbuf_put(b, ",", 1);
	put_kv(b, "cpus", tm->cpus[0] ? tm->cpus : "-");
	textbuf_put(b, ",", 1);
	put_kv(b, "rule", rule);
	textbuf_put(b, "}", 1);
	put_value(b, 1);
}

/* render_threads - every per-thread family, one family at a time */
static void render_threads(const struct prom_in *in, struct textbuf *b)
{
	static const char *const mnames[RTSUP_M_NR] = {
		[RTSUP_M_PERIOD] = "period", [RTSUP_M_EXEC] = "exec",
		[RTSUP_M_CPU] = "cpu", [RTSUP_M_LATENCY] = "latency",
	};
	const struct model *m = in->m;
	struct tlabels tl;
	int i, k, c;

	if (tlabels_make(&tl, m)) {
		tlabels_free(&tl);
		b->oom = true;
		return;
	}
	prom_family(b, "rtsup_component_status", "gauge",
		    "Verdict of the last interval: 0 OK, 1 WARN, 2 ERROR, 3 STALE.");
	prom_sample(b, "rtsup_component_status", prom_level_value(in->s->self.level),
		    (const char *const[]){ "component", "rtsup-trace", NULL });
	for (i = 0; i < m->n; i++)
		if (exported(m->t[i]))
			sample_t(b, "rtsup_component_status", prom_level_value(m->t[i]->st.level),
				 &tl, i, true);
	prom_family(b, "rtsup_component_worst_status", "gauge",
		    "Worst verdict since the start: 0 OK, 1 WARN, 2 ERROR, 3 STALE.");
	prom_sample(b, "rtsup_component_worst_status", prom_level_value(in->s->self_worst),
		    (const char *const[]){ "component", "rtsup-trace", NULL });
	for (i = 0; i < m->n; i++)
		if (exported(m->t[i]))
			sample_t(b, "rtsup_component_worst_status", prom_level_value(m->t[i]->worst),
				 &tl, i, true);

	prom_family(b, "rtsup_thread_info", "gauge",
		    "Always 1: scheduling policy, RT priority, allowed CPUs and rule of a thread.");
	for (i = 0; i < m->n; i++)
		if (exported(m->t[i]))
			put_info(b, in, &tl, i);

	for (c = 0; c < TC_NR; c++) {
		prom_family(b, tcounters[c].name, "counter", tcounters[c].help);
		for (i = 0; i < m->n; i++)
			if (exported(m->t[i]))
				sample_t(b, tcounters[c].name, tcounter_value(&m->t[i]->life, c), &tl,
					 i, false);
	}

	prom_family(b, "rtsup_thread_unsafe_events_total", "counter",
		    "RT-unsafe events inside cycles, by reason.");
	for (i = 0; i < m->n; i++) {
		if (!exported(m->t[i]))
			continue;
		for (k = 0; k < RTSUP_U_NR; k++)
			sample_kv(b, "rtsup_thread_unsafe_events_total", m->t[i]->life.unsafe[k], &tl,
				  i, "reason", unsafe_reason_name(k));
	}
	prom_family(b, "rtsup_thread_unsafe_syscalls_total", "counter",
		    "RT-unsafe syscalls inside cycles, by name.");
	for (i = 0; i < m->n; i++) {
		const struct thread_model *tm = m->t[i];

		if (!exported(tm))
			continue;
		for (k = 0; k < tm->nsys; k++) {
			const char *name = syscall_name(tm->sys[k].nr);
			char buf[16];

			if (!name) {
				snprintf(buf, sizeof(buf), "sys_%d", tm->sys[k].nr);
				name = buf;
			}
			sample_kv(b, "rtsup_thread_unsafe_syscalls_total", tm->sys[k].total, &tl, i,
				  "syscall", name);
		}
	}
	prom_family(b, "rtsup_thread_context_switches_total", "counter",
		    "Context switches of the thread: voluntary (blocks, sleeps) and involuntary (preemptions).");
	for (i = 0; i < m->n; i++) {
		if (!exported(m->t[i]))
			continue;
		sample_kv(b, "rtsup_thread_context_switches_total", m->t[i]->life.vol_cs, &tl, i,
			  "kind", "voluntary");
		sample_kv(b, "rtsup_thread_context_switches_total", m->t[i]->life.invol_cs, &tl, i,
			  "kind", "involuntary");
	}
	prom_family(b, "rtsup_thread_page_faults_total", "counter",
		    "Page faults inside cycles, minor and major.");
	for (i = 0; i < m->n; i++) {
		if (!exported(m->t[i]))
			continue;
		sample_kv(b, "rtsup_thread_page_faults_total", m->t[i]->life.minflt, &tl, i, "kind",
			  "minor");
		sample_kv(b, "rtsup_thread_page_faults_total", m->t[i]->life.majflt, &tl, i, "kind",
			  "major");
	}

	prom_family(b, "rtsup_thread_latency_seconds", "histogram",
		    "Wakeup latency per cycle: switch-in minus the expected release.");
	for (i = 0; i < m->n; i++)
		if (exported(m->t[i]))
			put_histogram(b, "rtsup_thread_latency_seconds", m->t[i], RTSUP_M_LATENCY,
				      &tl, i);
	prom_family(b, "rtsup_thread_exec_seconds", "histogram",
		    "Execution time per cycle (wall clock): release to the next delimiter call.");
	for (i = 0; i < m->n; i++)
		if (exported(m->t[i]))
			put_histogram(b, "rtsup_thread_exec_seconds", m->t[i], RTSUP_M_EXEC, &tl, i);

	prom_family(b, "rtsup_thread_ewma_seconds", "gauge",
		    "Exponentially weighted mean per cycle metric (period, exec, cpu, latency).");
	for (i = 0; i < m->n; i++) {
		if (!exported(m->t[i]))
			continue;
		for (k = 0; k < RTSUP_M_NR; k++)
			if (m->t[i]->life.m[k].count)
				sample_kv(b, "rtsup_thread_ewma_seconds", m->t[i]->life.m[k].ewma / 1e9,
					  &tl, i, "metric", mnames[k]);
	}
	prom_family(b, "rtsup_thread_interval_max_seconds", "gauge",
		    "Largest value per cycle metric in the last interval (absent: no cycle).");
	for (i = 0; i < m->n; i++) {
		const struct thread_model *tm = m->t[i];

		if (!exported(tm))
			continue;
		for (k = 0; k < RTSUP_M_NR; k++) {
			if (!tm->win.m[k].count)
				continue;
			kv_open(b, "rtsup_thread_interval_max_seconds", &tl, i, "metric", mnames[k]);
			put_seconds(b, tm->win.m[k].max);
		}
	}
	tlabels_free(&tl);
}

/* render_self - the supervisor's own numbers */
static void render_self(const struct prom_in *in, struct textbuf *b)
{
	const struct model *m = in->m;
	int i, alive = 0;

	for (i = 0; i < m->n; i++)
		alive += m->t[i]->alive;
	prom_family(b, "rtsup_build_info", "gauge", "Always 1: the rtsup-trace version.");
	prom_sample(b, "rtsup_build_info", 1, (const char *const[]){ "version", "0.1", NULL });
	prom_family(b, "rtsup_uptime_seconds", "gauge", "Seconds since the BPF programs were attached.");
	prom_sample(b, "rtsup_uptime_seconds", in->elapsed, NULL);
	prom_family(b, "rtsup_threads", "gauge",
		    "Threads in the model: alive, and exited ones kept for the summary.");
	prom_sample(b, "rtsup_threads", alive, (const char *const[]){ "state", "alive", NULL });
	prom_sample(b, "rtsup_threads", m->n - alive,
		    (const char *const[]){ "state", "exited", NULL });
	prom_family(b, "rtsup_thread_map_entries", "gauge", "Entries in the kernel's thread map.");
	prom_sample(b, "rtsup_thread_map_entries", in->map_entries, NULL);
	prom_family(b, "rtsup_thread_map_capacity", "gauge",
		    "Capacity of the kernel's thread map (--max-threads).");
	prom_sample(b, "rtsup_thread_map_capacity", in->map_capacity, NULL);
	prom_family(b, "rtsup_untracked_threads_total", "counter",
		    "Target threads that did not fit into the thread map.");
	prom_sample(b, "rtsup_untracked_threads_total", in->counters[RTSUP_C_MAP_FULL], NULL);
	prom_family(b, "rtsup_untracked_syscall_counts_total", "counter",
		    "Per-syscall unsafe counts that did not fit into their map.");
	prom_sample(b, "rtsup_untracked_syscall_counts_total", in->counters[RTSUP_C_SYS_FULL],
		    NULL);
	prom_family(b, "rtsup_lost_events_total", "counter",
		    "Rare events the ring buffer had no room for (statistics are not affected).");
	prom_sample(b, "rtsup_lost_events_total", in->counters[RTSUP_C_RB_DROPS], NULL);
	prom_family(b, "rtsup_lost_cycle_records_total", "counter",
		    "Cycle records the recording buffer had no room for (--record, --perfetto).");
	prom_sample(b, "rtsup_lost_cycle_records_total", in->counters[RTSUP_C_CYC_DROPS], NULL);
	prom_family(b, "rtsup_waits_not_attributed_total", "counter",
		    "Target waits for a CPU not attributed: other targets held its wait slots.");
	prom_sample(b, "rtsup_waits_not_attributed_total", in->counters[RTSUP_C_WHY_BUSY], NULL);
	/* the rest of the tool's own health (health.h) */
	prom_family(b, "rtsup_events_not_kept_total", "counter",
		    "Rare events the interval's list had no memory for.");
	prom_sample(b, "rtsup_events_not_kept_total", in->s->health.events_not_kept, NULL);
	prom_family(b, "rtsup_hook_runs_missed_total", "counter",
		    "Runs of rtsup's BPF programs the kernel skipped: the same program was running on that CPU.");
	prom_sample(b, "rtsup_hook_runs_missed_total", in->s->health.hook_runs_missed, NULL);
	prom_family(b, "rtsup_hook_runs_recovered_total", "counter",
		    "Of the runs missed, the delimiter returns of targets rtsup-trace found otherwise.");
	prom_sample(b, "rtsup_hook_runs_recovered_total", in->s->health.hook_runs_recovered,
		    NULL);
	prom_family(b, "rtsup_parse_errors_total", "counter",
		    "/proc and cgroup text that did not parse and was skipped.");
	prom_sample(b, "rtsup_parse_errors_total", in->s->health.parse_errors, NULL);
	prom_family(b, "rtsup_actions_dropped_total", "counter",
		    "Actions not run: the rate limit, or too many commands running.");
	prom_sample(b, "rtsup_actions_dropped_total", in->s->health.actions_dropped, NULL);
	prom_family(b, "rtsup_forgotten_threads_total", "counter",
		    "Exited threads dropped from the model to keep memory bounded.");
	prom_sample(b, "rtsup_forgotten_threads_total", in->forgotten, NULL);
	prom_family(b, "rtsup_violations_total", "counter",
		    "WARN and ERROR verdicts (a verdict repeated unchanged counts once).");
	prom_sample(b, "rtsup_violations_total", in->s->nv + in->s->v_dropped, NULL);
}

int prom_render(const struct prom_in *in, struct textbuf *b)
{
	b->len = 0;
	b->oom = false;
	if (b->p)
		b->p[0] = '\0';
	render_self(in, b);
	render_threads(in, b);
	if (in->extra)
		in->extra(b, in->extra_ctx);
	if (!textbuf_room(b, 0))
		return -1;
	b->p[b->len] = '\0';
	return 0;
}

