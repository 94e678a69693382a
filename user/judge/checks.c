// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * checks.c - initialization, overrun/deadline miss, starvation, RT-safety
 * loss, latency and jitter, exceptions, scheduling, and the supervisor's
 * overhead: numbers in, messages out.
 */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include "judge/checks.h"
#include "collect/since.h"

#define NS_PER_US 1000.0

/* us - nanoseconds as microseconds for a message */
static double us(__u64 ns)
{
	return ns / NS_PER_US;
}

__u64 check_period(const struct check_in *in)
{
	const struct metric_view *p = &in->life->m[RTSUP_M_PERIOD];

	if (in->rule->period_ns)
		return in->rule->period_ns;
	if (in->nominal_ns)
		return in->nominal_ns;
	/* a relative sleeper: its own mean, once there is enough of it */
	return p->count >= 8 ? (__u64)p->mean : 0;
}

/*
 * check_init - seen, but no cycle within the timeout. Only a thread a rule
 * expects to run is late: an RT thread that waits for work (a watchdog, an
 * interrupt thread, a program's spare worker) is idle, not broken.
 */
static void check_init(const struct check_in *in, struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	__u64 age = ns_since(in->now_ns, in->first_seen_ns);

	if (!th->init_timeout_s || in->life->cycles || !in->alive)
		return;
	if (age < th->init_timeout_s * 1e9)
		return;
	if (in->expect_run)
		status_add(s, LEVEL_WARN, "not initialized: no cycle %.1f s after it appeared",
			   age / 1e9);
	else
		status_add(s, LEVEL_OK, "idle: no cycle %.1f s after it appeared", age / 1e9);
}

/* check_overrun - deadline misses and overruns of one span */
static void check_overrun(const struct check_in *in, const struct span_view *v,
			  const char *span, struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	__u64 bad = v->misses > v->overruns ? v->misses : v->overruns;
	double rate = v->cycles ? (double)bad / v->cycles : 0;
	const char *why = v == in->win ? in->why_win : in->why_life;

	if (!bad || !th->miss_warn || bad < th->miss_warn)
		return;
	/* the cause first in the reader's eye: "..., 11 caused by noise-hog[812] FIFO/99" */
	status_add(s, th->miss_error_rate && rate > th->miss_error_rate ? LEVEL_ERROR : LEVEL_WARN,
		   "%llu deadline misses, %llu overruns in %llu cycles %s (%.2f %%)%s%s",
		   (unsigned long long)v->misses, (unsigned long long)v->overruns,
		   (unsigned long long)v->cycles, span, rate * 100, why && v->misses ? ", " : "",
		   why && v->misses ? why : "");
	status_count(s, "deadline_misses", v->misses);
	status_count(s, "overruns", v->overruns);
	status_count(s, "cycles", v->cycles);
}

/* check_exec_near - execution time coming near its period (the seed's warning) */
static void check_exec_near(const struct check_in *in, const struct span_view *v,
			    __u64 period, struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	const struct metric_view *e = &v->m[RTSUP_M_EXEC];
	double x = th->exec_stat == EXEC_STAT_EWMA ? e->ewma : (double)e->p99;

	if (!th->exec_warn_ratio || !period || !e->count)
		return;
	if (x > th->exec_warn_ratio * period)
		status_add(s, LEVEL_WARN, "execution %s %.1f us is %.0f %% of the %.1f us period",
			   th->exec_stat == EXEC_STAT_EWMA ? "EWMA" : "p99", x / NS_PER_US,
			   x * 100.0 / period, us(period));
}

/* check_starvation - no new cycle for k periods while the thread lives */
static void check_starvation(const struct check_in *in, __u64 period, struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	double k;

	if (!period || !in->last_cycle_ns || !in->alive)
		return;
	k = (double)ns_since(in->now_ns, in->last_cycle_ns) / period;
	if (th->starve_error_periods && k >= th->starve_error_periods)
		status_add(s, LEVEL_ERROR, "starving: no new cycle for %.1f ms (%.0f periods)",
			   ns_since(in->now_ns, in->last_cycle_ns) / 1e6, k);
	else if (th->starve_warn_periods && k >= th->starve_warn_periods)
		status_add(s, LEVEL_WARN, "starving: no new cycle for %.1f ms (%.0f periods)",
			   ns_since(in->now_ns, in->last_cycle_ns) / 1e6, k);
}

/* check_unsafe - RT-safety loss, by reason, naming the syscalls */
static void check_unsafe(const struct check_in *in, const struct span_view *v,
			 const char *span, const char *names, struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	enum level l = LEVEL_WARN;
	char what[128] = "";
	size_t off = 0;
	int r;

	if (!v->unsafe_total || !th->unsafe_warn || v->unsafe_total < th->unsafe_warn)
		return;
	for (r = 0; r < RTSUP_U_NR; r++) {
		if (!v->unsafe[r])
			continue;
		if (th->unsafe_error[r] && v->unsafe[r] >= th->unsafe_error[r])
			l = LEVEL_ERROR;
		if (off < sizeof(what))
			off += snprintf(what + off, sizeof(what) - off, "%s%s %llu", off ? ", " : "",
					unsafe_reason_name(r), (unsigned long long)v->unsafe[r]);
	}
	if (names && *names)
		status_add(s, l, "RT-unsafe %s: %s (syscalls: %s)", span, what, names);
	else
		status_add(s, l, "RT-unsafe %s: %s", span, what);
	for (r = 0; r < RTSUP_U_NR; r++)
		if (v->unsafe[r])
			status_count(s, unsafe_reason_name(r), v->unsafe[r]);
}

/* check_latency - wakeup latency p99 and max */
static void check_latency(const struct check_in *in, const struct span_view *v,
			  struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	const struct metric_view *l = &v->m[RTSUP_M_LATENCY];

	if (!l->count)
		return;
	if (th->latency_max_error_ns && l->max > th->latency_max_error_ns)
		status_add(s, LEVEL_ERROR, "wakeup latency max %.1f us > %.1f us", us(l->max),
			   us(th->latency_max_error_ns));
	else if (th->latency_max_warn_ns && l->max > th->latency_max_warn_ns)
		status_add(s, LEVEL_WARN, "wakeup latency max %.1f us > %.1f us", us(l->max),
			   us(th->latency_max_warn_ns));
	if (th->latency_p99_warn_ns && l->p99 > th->latency_p99_warn_ns)
		status_add(s, LEVEL_WARN, "wakeup latency p99 %.1f us > %.1f us", us(l->p99),
			   us(th->latency_p99_warn_ns));
}

/* check_jitter - the largest distance of a period from the nominal one */
static void check_jitter(const struct check_in *in, const struct span_view *v,
			 __u64 period, struct status *s)
{
	const struct thresholds *th = &in->rule->th;
	const struct metric_view *p = &v->m[RTSUP_M_PERIOD];
	__u64 j;

	if (!period || !p->count || (!th->jitter_warn_ns && !th->jitter_error_ns))
		return;
	j = p->max > period ? p->max - period : 0;
	if (p->min < period && period - p->min > j)
		j = period - p->min;
	if (th->jitter_error_ns && j > th->jitter_error_ns)
		status_add(s, LEVEL_ERROR, "period jitter %.1f us > %.1f us", us(j),
			   us(th->jitter_error_ns));
	else if (th->jitter_warn_ns && j > th->jitter_warn_ns)
		status_add(s, LEVEL_WARN, "period jitter %.1f us > %.1f us", us(j),
			   us(th->jitter_warn_ns));
}

/*
 * exit_is_normal_end - an exit with nothing wrong in it: the supervised
 * command ended, or the thread's whole process ended with status 0
 * (exit_group(0): main returned, exit(0), a service stopped cleanly). A
 * thread that ends alone while its process goes on is a death, whatever its
 * status: the control loop it ran has stopped.
 */
static bool exit_is_normal_end(const struct check_in *in)
{
	return in->exit_expected || (in->process_ended && in->exit_code == 0);
}

/* check_exceptions - fatal signals and deaths; a restart says so */
static void check_exceptions(const struct check_in *in, struct status *s)
{
	int sig = in->exit_code & 0x7f, code = (in->exit_code >> 8) & 0xff;

	if (in->restarted_from)
		status_add(s, LEVEL_OK, "restarted: replaces tid %u, which died",
			   in->restarted_from);
	/* alive, but not followed any more: reported once, like an exit */
	if (in->left_rt && in->alive)
		status_add(s, LEVEL_STALE, "left RT (policy %s): no longer a --rt target",
			   policy_name(in->policy));
	if (in->alive)
		return;
	if (sig)
		status_add(s, LEVEL_ERROR, "killed by signal %d (%s)%s", sig, strsignal(sig),
			   in->exit_mid_cycle ? " inside a cycle" : "");
	else if (code)
		status_add(s, LEVEL_ERROR, "exited with status %d%s", code,
			   in->exit_mid_cycle ? " inside a cycle" : "");
	else if (!exit_is_normal_end(in))
		status_add(s, LEVEL_ERROR, "thread exited%s",
			   in->exit_mid_cycle ? " inside a cycle" : "");
	else if (in->process_ended)
		status_add(s, LEVEL_STALE, "exited: its process ended with status 0");
	else
		status_add(s, LEVEL_STALE, "exited");
}

/* check_abi - a 32-bit program's syscalls are not classified: say so, never misjudge */
static void check_abi(const struct check_in *in, struct status *s)
{
	if (in->compat_sys) {
		status_add(s, LEVEL_WARN, "32-bit program: %llu syscalls not classified "
			   "(not supported; cycles from activations)",
			   (unsigned long long)in->compat_sys);
		status_count(s, "compat_syscalls", in->compat_sys);
	}
}

/* check_sched - policy and priority as the configuration expects */
static void check_sched(const struct check_in *in, struct status *s)
{
	const struct rule *r = in->rule;

	if (!in->alive)
		return;
	if (r->policy >= 0 && in->policy != r->policy)
		status_add(s, LEVEL_ERROR, "policy %s, expected %s", policy_name(in->policy),
			   policy_name(r->policy));
	else if (r->prio >= 0 && in->prio != r->prio)
		status_add(s, LEVEL_WARN, "priority %d, expected %d", in->prio, r->prio);
}

unsigned check_shown_key(bool judged, bool kthread, bool alive)
{
	/* what the branch of check_thread below reads: nothing else */
	return judged ? 0 : 1u | (unsigned)(kthread && alive) << 1;
}

void check_thread(const struct check_in *in, struct status *out)
{
	__u64 period = check_period(in);

	status_reset(out);
	/* threads that are neither a program's RT thread nor named by a rule are only shown */
	if (!in->judged) {	/* only what check_shown_key keys */
		status_check(out, "not_judged");
		if (in->kthread && in->alive)
			status_add(out, LEVEL_OK, "kernel thread: judged when a rule names it");
		return;
	}
	/* every message says which check made it (CHECK_* names, docs/json.md) */
	status_check(out, CHECK_EXCEPTION);
	check_exceptions(in, out);
	status_check(out, CHECK_SCHED);
	check_sched(in, out);
	status_check(out, CHECK_ABI);
	check_abi(in, out);
	status_check(out, CHECK_INIT);
	check_init(in, out);
	status_check(out, CHECK_STARVATION);
	check_starvation(in, period, out);
	if (in->win) {
		status_check(out, CHECK_MISS);
		check_overrun(in, in->win, "in the last interval", out);
		status_check(out, CHECK_EXEC_NEAR);
		check_exec_near(in, in->win, period, out);
		status_check(out, CHECK_UNSAFE);
		check_unsafe(in, in->win, "in the last interval", in->unsafe_names, out);
		status_check(out, CHECK_LATENCY);
		check_latency(in, in->win, out);
		status_check(out, CHECK_JITTER);
		check_jitter(in, in->win, period, out);
	}
	if (in->rule->th.lifetime) {
		status_check(out, CHECK_MISS);
		check_overrun(in, in->life, "in total", out);
		/* the names are the window's: not for the totals */
		status_check(out, CHECK_UNSAFE);
		check_unsafe(in, in->life, "in total", NULL, out);
		status_check(out, CHECK_LATENCY);
		check_latency(in, in->life, out);
		status_check(out, CHECK_JITTER);
		check_jitter(in, in->life, period, out);
	}
	/* a dead thread has no data any more: STALE unless it is worse */
	if ((!in->alive || in->left_rt) && out->level == LEVEL_OK)
		out->level = LEVEL_STALE;
}

void check_self(const struct self_in *in, struct status *out)
{
	const struct thresholds *th = in->th;

	status_reset(out);
	status_check(out, CHECK_OVERHEAD);
	if (in->overhead_pct >= 0) {
		if (th->overhead_error_pct && in->overhead_pct > th->overhead_error_pct)
			status_add(out, LEVEL_ERROR, "BPF overhead %.2f %% of a CPU > %.2f %%",
				   in->overhead_pct, th->overhead_error_pct);
		else if (th->overhead_warn_pct && in->overhead_pct > th->overhead_warn_pct)
			status_add(out, LEVEL_WARN, "BPF overhead %.2f %% of a CPU > %.2f %%",
				   in->overhead_pct, th->overhead_warn_pct);
	}
	status_check(out, CHECK_LOSS);
	if (in->lost_events) {
		status_add(out, LEVEL_WARN, "%llu rare events lost (ring buffer full)",
			   (unsigned long long)in->lost_events);
		status_count(out, "lost_events", in->lost_events);
	}
	if (in->untracked_threads) {
		status_add(out, LEVEL_WARN, "%llu threads not tracked: the thread map is full "
			   "(--max-threads)", (unsigned long long)in->untracked_threads);
		status_count(out, "untracked_threads", in->untracked_threads);
	}
}
