/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * cycle.h - the cycle state machine, shared by BPF and userspace.
 *
 * A periodic RT thread works, then sleeps until its next release. The
 * kernel side calls these functions from the scheduler and syscall hooks;
 * the unit tests call them with synthetic event sequences. Each function
 * takes the event's one timestamp and returns CYC_EV_* bits telling the
 * caller which rare events to report; a finished cycle is folded into the
 * thread's statistics here and copied to *out.
 *
 * Delimiter mode: a cycle runs from a release (the first switch-in after
 * the delimiter syscall slept, or its exit if it did not sleep) to the next
 * delimiter entry. Activation mode, for threads that never call a
 * delimiter: from a switch-in after a voluntary block to the next one.
 *
 * Real loops bend this model; docs/cycle-model.md has the table. A
 * delimiter interrupted by a signal releases a cycle only tentatively: if
 * the thread goes back to the same wait, the wait goes on and what ran in
 * between (a signal handler) belongs to no cycle. Once a thread has slept
 * to absolute releases, its relative sleeps are sleeps inside the cycle.
 * Start-up ends when the period settles (CYC_SETTLE_RUNS equal distances
 * between absolute releases, and the configured warmup is over): cycles
 * counted before, through start-up sleeps, are dropped then.
 */
#ifndef RTSUP_CYCLE_H
#define RTSUP_CYCLE_H

#include "rtsup.h"
#include "stats.h"

/* BPF has no memset for large blocks: it brings its own RTSUP_ZERO. */
#ifndef RTSUP_ZERO
#define RTSUP_ZERO(p, n) __builtin_memset(p, 0, n)
#endif

#define CYC_EV_CLOSED	0x01	/* a cycle finished, *out is valid */
#define CYC_EV_MISS	0x02	/* the requested release is already past */
#define CYC_EV_BLOCK	0x04	/* voluntary block inside a cycle */
#define CYC_EV_MIGRATE	0x08	/* migration inside a cycle */
#define CYC_EV_UNSAFE	0x10	/* unsafe syscall inside a cycle */
#define CYC_EV_FAULTS	0x20	/* the finished cycle had page faults */
#define CYC_EV_RESET	0x40	/* first delimiter or settled period: start-up dropped */

/* Equal distances between absolute releases that make a settled period. */
#define CYC_SETTLE_RUNS	3
/*
 * Relative sleeps in a row, with no absolute one, that make a thread a
 * relative loop again (it slept to an absolute release once, in start-up):
 * more than any cycle sleeps inside itself.
 */
#define CYC_REL_LOOP	64
/*
 * A relative sleep re-entered after an interruption resumes the wait when
 * it asks for no later release than the interrupted one, give or take
 * this: our entry time is read a few us before the kernel arms its timer.
 */
#define CYC_REL_SLACK	20000ULL

/*
 * An absolute release given again after a signal (the program's EINTR
 * loop) is the same wait within this: the offset of its clock, written by
 * userspace each interval, moves by the time between two clock reads
 * (~100 ns) and by NTP's slew. Two cycles' releases are a period apart.
 */
#define CYC_ABS_SAME	10000ULL

/*
 * A clock's offset to CLOCK_MONOTONIC moves by at most 0.05 % with an NTP
 * slew (500 ppm); a release moved earlier by more than this and 1/1024 of
 * the period was a step forward (cycle_clock_moved).
 */
#define CYC_SLEW_SLACK	1000000ULL

/* Settings the state machine needs; rodata on the BPF side. */
struct cycle_cfg {
	__u32 ewma_w;		/* EWMA weight, per RTSUP_EWMA_ONE */
	__u32 epoch;		/* interval bank selector */
	__u64 period;		/* nominal period when none can be derived */
	__u64 warmup;		/* start-up lasts at least this after first_seen */
};

/*
 * cycle_ret_interrupted - did a syscall return because of a signal? EINTR,
 * or the ERESTART* codes (512..516) the sys_exit hook sees before the
 * kernel restarts the call or turns them into EINTR.
 */
RTSUP_INLINE int cycle_ret_interrupted(long ret)
{
	return ret == -4 || (ret <= -512 && ret >= -516);
}

/* cycle_sys_mode - the unsafe_sys key's mode: counts dropped at settling stay apart */
RTSUP_INLINE __u16 cycle_sys_mode(const struct rtsup_cycle_state *cs)
{
	int dropped = (cs->flags & RTSUP_CS_SETTLED) && (cs->flags & RTSUP_CS_DIRTY);

	return cs->mode | (dropped ? RTSUP_MODE_SETTLED : 0);
}

/*
 * cycle_rel_sleep_in_loop - a relative sleep of a thread that sleeps to
 * absolute releases: a sleep inside its cycle (RT-unsafe), no delimiter.
 * CYC_REL_LOOP of them in a row make it a relative loop again.
 */
RTSUP_INLINE int cycle_rel_sleep_in_loop(struct rtsup_thread *t, __u32 cls, int absolute)
{
	struct rtsup_cycle_state *cs = &t->cs;

	if (!(cls & (RTSUP_SC_ABSSLEEP | RTSUP_SC_RELSLEEP)) || absolute ||
	    !(cs->flags & RTSUP_CS_ABS_SEEN))
		return 0;
	if (++cs->rel_sleeps < CYC_REL_LOOP)
		return 1;
	cs->flags &= ~RTSUP_CS_ABS_SEEN;
	return 0;
}

/*
 * cycle_delim_key - is this call of a keyed delimiter (a wait on an fd or
 * a futex: key != 0) the thread's cycle boundary? Only the wait it first
 * slept in is (learned at its switch-out); others are plain syscalls.
 */
RTSUP_INLINE int cycle_delim_key(struct rtsup_cycle_state *cs, __u64 key)
{
	if (key && cs->delim_key && key != cs->delim_key)
		return 0;
	cs->cand_key = key;
	return 1;
}

/* cycle_thread_init - fresh thread entry (all-zero memory assumed) */
RTSUP_INLINE void cycle_thread_init(struct rtsup_thread *t, __u32 tid,
				    __u32 tgid, __u64 now)
{
	t->tid = tid;
	t->tgid = tgid;
	t->first_seen = now;
	t->cs.last_cpu = -1;
	t->epoch = ~0U;	/* forces the interval banks to be reset */
}

/* cycle_reset_stats - drop what was measured before the first delimiter */
RTSUP_SUBPROG void cycle_reset_stats(struct rtsup_thread *t)
{
	__u32 i;

	RTSUP_ZERO(t->m, sizeof(t->m));
	t->resets++;
	t->epoch = ~0U;
	t->cycles = 0;
	t->misses = 0;
	t->overruns = 0;
	t->syscalls = 0;
	t->minflt = 0;
	t->majflt = 0;
	for (i = 0; i < RTSUP_U_NR; i++)
		t->unsafe[i] = 0;
}

/* cycle_epoch - reset the interval banks once per interval */
RTSUP_INLINE void cycle_epoch(struct rtsup_thread *t, __u32 epoch)
{
	__u32 i;

	if (t->epoch == epoch)
		return;
	t->epoch = epoch;
	for (i = 0; i < RTSUP_M_NR; i++)
		minmax_reset(&t->m[i].win[RTSUP_BANK(epoch)]);
}

/* cycle_pend_clear - forget the running cycle's unsafe syscalls by number */
RTSUP_INLINE void cycle_pend_clear(struct rtsup_cycle_state *cs)
{
	__u32 i;

	for (i = 0; i < RTSUP_PEND_SYS; i++) {
		cs->pend_nr[i] = 0;
		cs->pend_cnt[i] = 0;
	}
}

/*
 * cycle_pend_sys - hold an unsafe syscall until its cycle ends; 0 when held,
 * 1 when every slot is taken (the caller counts it at once).
 */
RTSUP_INLINE int cycle_pend_sys(struct rtsup_cycle_state *cs, __u16 nr)
{
	__u32 i;

	for (i = 0; i < RTSUP_PEND_SYS; i++) {
		if (cs->pend_cnt[i] && cs->pend_nr[i] != nr)
			continue;
		cs->pend_nr[i] = nr;
		cs->pend_cnt[i]++;
		return 0;
	}
	return 1;
}

/* cycle_begin - a new cycle starts at 'start' */
RTSUP_INLINE void cycle_begin(struct rtsup_cycle_state *cs, __u64 start,
			      __u64 minflt, __u64 majflt)
{
	cs->start = start;
	cs->run_since = start;
	cs->cpu_acc = 0;
	cs->minflt0 = minflt;
	cs->majflt0 = majflt;
	cs->preempt = 0;
	cs->blocks = 0;
	cs->migrations = 0;
	cs->syscalls = 0;
	cs->unsafe_sys = 0;
	cycle_pend_clear(cs);
}

/*
 * cycle_close - finish the running cycle at 'now', account it. 'released'
 * is the distance between the requested releases that released it, its
 * own period (0: none known, the thread's last, cs->nominal).
 */
RTSUP_INLINE __u32 cycle_close(struct rtsup_thread *t, const struct cycle_cfg *cfg,
			       __u64 now, __u64 minflt, __u64 majflt, __u64 released,
			       struct rtsup_cycle *out)
{
	struct rtsup_cycle_state *cs = &t->cs;
	__u32 ev = CYC_EV_CLOSED;

	if (cs->run_since && now > cs->run_since)
		cs->cpu_acc += now - cs->run_since;
	out->start = cs->start;
	out->exec = now - cs->start;
	out->cpu = cs->cpu_acc;
	out->flags = 0;
	out->period = 0;
	out->latency = 0;
	if (cs->last_start && cs->start > cs->last_start) {
		out->period = cs->start - cs->last_start;
		out->flags |= RTSUP_CF_HAS_PERIOD;
	}
	if (cs->last_expected) {
		out->latency = cs->start > cs->last_expected ?
			       cs->start - cs->last_expected : 0;
		out->flags |= RTSUP_CF_HAS_LATENCY;
	}
	out->nominal = released ? released : cs->nominal ? cs->nominal : cfg->period;
	if (out->nominal && out->exec > out->nominal)
		out->flags |= RTSUP_CF_OVERRUN;
	out->preempt = cs->preempt;
	out->blocks = cs->blocks;
	out->migrations = cs->migrations;
	out->syscalls = cs->syscalls;
	out->unsafe_sys = cs->unsafe_sys;
	out->minflt = (__u32)(minflt - cs->minflt0);
	out->majflt = (__u32)(majflt - cs->majflt0);
	if (out->minflt || out->majflt)
		ev |= CYC_EV_FAULTS;
	cs->last_start = cs->start;
	cs->start = 0;
	cs->run_since = 0;
	return ev;
}

/* cycle_account - fold a closed cycle into the thread's statistics */
RTSUP_SUBPROG void cycle_account(struct rtsup_thread *t, const struct cycle_cfg *cfg,
				const struct rtsup_cycle *c)
{
	cycle_epoch(t, cfg->epoch);
	thread_account_cycle(t, c, cfg->ewma_w, cfg->epoch);
}

/*
 * cycle_delim_resumes - does this delimiter entry go back to the wait that
 * a signal interrupted (same absolute release, or a relative one that
 * ends no later), or does the thread start a new one?
 */
RTSUP_INLINE int cycle_delim_resumes(const struct rtsup_cycle_state *cs, __u64 now,
				     __u64 expected, int absolute)
{
	if (!(cs->flags & RTSUP_CS_INTR))
		return 0;
	if (absolute)
		return expected && cs->abs_expected &&
		       (expected > cs->abs_expected ? expected - cs->abs_expected :
						      cs->abs_expected - expected) <= CYC_ABS_SAME;
	if (cs->abs_expected || !expected || !cs->expected)
		return !cs->abs_expected && !expected && !cs->expected;
	/* the time since the interrupted return is not part of the remainder */
	return expected - (now > cs->start ? now - cs->start : 0) <=
	       cs->expected + CYC_REL_SLACK;
}

/*
 * cycle_clock_moved - the release of an absolute sleep on a clock other
 * than CLOCK_MONOTONIC (CLOCK_REALTIME, TAI, BOOTTIME), converted at the
 * entry with that clock's offset then ('off_in'), and seen again at the
 * return with its offset now ('off_now'). The kernel's timer follows the
 * sleep's own clock: a slew or a step back moves the release, which is
 * where the new offset puts it (a step back of a second is a second more
 * of sleep, not a second of latency). A step forward beyond what a slew
 * does (CYC_SLEW_SLACK, plus 1/1024 of the period) released the thread at
 * the step, a time no hook saw: no latency (0), as for a sleep a signal cut
 * short; so is a release moved before the clock's start.
 */
RTSUP_INLINE __u64 cycle_clock_moved(__u64 expected, __s64 off_in, __s64 off_now, __u64 period)
{
	__s64 shift = off_in - off_now;	/* > 0: a step back, the release came later */

	if (!expected || (shift < 0 && ((__u64)-shift > CYC_SLEW_SLACK + (period >> 10) ||
					(__u64)-shift >= expected)))
		return 0;
	return expected + shift;
}

/*
 * cycle_sleep_clock - the delimiter entered sleeps until 'expected', an
 * absolute time on clock 'clk' converted with offset 'off' (absolute), or
 * not. Kept for cycle_clock_at_exit.
 */
RTSUP_INLINE void cycle_sleep_clock(struct rtsup_cycle_state *cs, int absolute, __u32 clk,
				    __s64 off)
{
	cs->clk = absolute ? clk + 1 : 0;
	cs->clk_off = absolute ? off : 0;
}

/*
 * cycle_clock_at_exit - the delimiter returns and its clock's offset is
 * 'off_now': the pending release (cycle_clock_moved) and the last
 * requested one, from which the next distance is taken, move with it.
 * Called before cycle_delim_exit.
 */
RTSUP_INLINE void cycle_clock_at_exit(struct rtsup_cycle_state *cs, __s64 off_now)
{
	__s64 shift = cs->clk_off - off_now;

	if (!cs->in_delim || !cs->clk || !shift)
		return;
	cs->expected = cycle_clock_moved(cs->expected, cs->clk_off, off_now, cs->nominal);
	if (cs->abs_expected && (shift > 0 || (__u64)-shift < cs->abs_expected))
		cs->abs_expected += shift;
	cs->clk_off = off_now;
}

/* cycle_same_dist - two distances between releases equal within 1/64 (rounding of the program) */
RTSUP_INLINE int cycle_same_dist(__u64 a, __u64 b)
{
	__u64 d = a > b ? a - b : b - a;

	return d <= (b >> 6);
}

/*
 * cycle_settle_period - learn the nominal period from the requested
 * releases and end start-up once it settled: CYC_EV_RESET when the cycles
 * counted so far were start-up's (a start-up sleep, a changed distance)
 * or a warmup was configured.
 */
RTSUP_INLINE __u32 cycle_settle_period(struct rtsup_thread *t, const struct cycle_cfg *cfg,
				       __u64 now, __u64 expected, int absolute)
{
	struct rtsup_cycle_state *cs = &t->cs;
	int startup = 0;	/* a cycle of start-up was counted */
	__u64 d;

	if (absolute && expected) {
		cs->flags |= RTSUP_CS_ABS_SEEN;
		cs->rel_sleeps = 0;
		if (cs->abs_expected && expected > cs->abs_expected) {
			/* nominal period: distance between two requested releases */
			d = expected - cs->abs_expected;
			cs->nominal = d;
			if (cs->dist && cycle_same_dist(d, cs->dist)) {
				cs->run++;
			} else {
				startup = t->cycles != 0;
				cs->run = 1;
				cs->dist = d;
			}
		} else {
			startup = cs->start != 0;
			cs->run = 0;
		}
	} else {
		startup = cs->start != 0;
	}
	/* settled once: a later skipped release changes nothing (cycle_sys_mode) */
	if (cs->flags & RTSUP_CS_SETTLED)
		return 0;
	if (startup)
		cs->flags |= RTSUP_CS_DIRTY;
	if (now < t->first_seen + cfg->warmup)
		return 0;
	if (cs->run < CYC_SETTLE_RUNS && (cs->flags & RTSUP_CS_ABS_SEEN || !cfg->warmup))
		return 0;
	cs->flags |= RTSUP_CS_SETTLED;
	if (cfg->warmup)
		cs->flags |= RTSUP_CS_DIRTY;
	if (!(cs->flags & RTSUP_CS_DIRTY))
		return 0;
	/* the cycle that ends now is the settled loop's: dropped before it is counted */
	cycle_reset_stats(t);
	return CYC_EV_RESET;
}

/*
 * cycle_delim_enter - the thread enters its delimiter syscall. 'expected'
 * is the requested release in CLOCK_MONOTONIC ns (0 when unknown);
 * 'absolute' when the thread asked for that time itself (TIMER_ABSTIME):
 * only then is a past release a deadline miss and the distance between two
 * releases the nominal period.
 */
RTSUP_INLINE __u32 cycle_delim_enter(struct rtsup_thread *t, const struct cycle_cfg *cfg,
				     __u64 now, __u64 expected, int absolute,
				     __u64 minflt, __u64 majflt, struct rtsup_cycle *out)
{
	struct rtsup_cycle_state *cs = &t->cs;
	/*
	 * the ending cycle's own period, before settling learns the next one:
	 * a loop's last cycle, followed by a long sleep, is judged by its own
	 * (the first cycle, released by no known distance, by the next)
	 */
	__u64 released = cs->nominal;
	__u32 ev = 0;

	if (cs->mode != RTSUP_MODE_DELIM) {
		/* start-up is not the loop: forget it, activations too */
		if (cs->mode == RTSUP_MODE_ACT)
			ev |= CYC_EV_RESET;
		cycle_reset_stats(t);
		cs->mode = RTSUP_MODE_DELIM;
		cs->start = 0;
		cs->last_start = 0;
		cs->last_expected = 0;
	}
	if (cycle_delim_resumes(cs, now, expected, absolute)) {
		/* the same wait goes on: the signal handler was no cycle */
		cs->start = 0;
	} else {
		ev |= cycle_settle_period(t, cfg, now, expected, absolute);
		cs->abs_expected = absolute ? expected : 0;
	}
	cs->flags &= ~RTSUP_CS_INTR;
	if (cs->start) {
		ev |= cycle_close(t, cfg, now, minflt, majflt, released, out);
		if (absolute && expected && expected <= now) {
			out->flags |= RTSUP_CF_MISS;
			ev |= CYC_EV_MISS;
		}
		cycle_account(t, cfg, out);
	}
	cs->in_delim = 1;
	cs->in_ts = 0;
	cs->wake_ts = 0;
	cs->expected = expected;
	/* CPU time and preemptions after the release, before the syscall returns */
	cs->cpu_acc = 0;
	cs->preempt = 0;
	return ev;
}

/*
 * The hooks read the clock only where a state function uses 'now'. Each
 * such function decides its path once, in its *_path() function, and acts
 * on that path; the *_timed() predicate the hooks ask is the same decision
 * looked up in the paths' CYC_*_TIMED mask. A path added to one is in
 * the other, and the mask says which paths use the time.
 */
#define CYC_PATH_TIMED(mask, path)	(((mask) >> (path)) & 1)

/*
 * cycle_delim_switched_in - in_ts, the first switch-in since the thread
 * entered its delimiter or last slept in it: the release of the next
 * cycle (then also "released, not yet returned"); 0 = none yet
 */
RTSUP_INLINE __u64 cycle_delim_switched_in(const struct rtsup_cycle_state *cs)
{
	return cs->in_delim ? cs->in_ts : 0;
}

/* The paths of cycle_delim_exit. */
enum cycle_exit_path {
	CYC_EXIT_NONE,		/* no delimiter entered: nothing released */
	CYC_EXIT_SWITCHED_IN,	/* released at cycle_delim_switched_in() */
	CYC_EXIT_NO_SLEEP,	/* not switched in since entry: released now */
	CYC_EXIT_WOKEN_EARLY,	/* switched in before its release: released now */
};
#define CYC_EXIT_TIMED	(1u << CYC_EXIT_NO_SLEEP | 1u << CYC_EXIT_WOKEN_EARLY)

/*
 * cycle_woken_early - a sleep that returns done ('interrupted' clear) but
 * whose first switch-in came before its requested release: a signal woke
 * it, and the timer expired before the kernel saw the signal, so the
 * sleep ends with 0 (do_nanosleep: "!t->task"). That switch-in is no
 * release: a sleep is never released before its time.
 */
RTSUP_INLINE int cycle_woken_early(const struct rtsup_cycle_state *cs, int interrupted)
{
	__u64 in = cycle_delim_switched_in(cs);

	return !interrupted && in && cs->expected && in < cs->expected;
}

/* cycle_delim_exit_path - which path cycle_delim_exit takes */
RTSUP_INLINE enum cycle_exit_path cycle_delim_exit_path(const struct rtsup_cycle_state *cs,
							int interrupted)
{
	if (!cs->in_delim)
		return CYC_EXIT_NONE;
	if (cycle_woken_early(cs, interrupted))
		return CYC_EXIT_WOKEN_EARLY;
	return cycle_delim_switched_in(cs) ? CYC_EXIT_SWITCHED_IN : CYC_EXIT_NO_SLEEP;
}

/* cycle_delim_exit_timed - will cycle_delim_exit read 'now'? */
RTSUP_INLINE int cycle_delim_exit_timed(const struct rtsup_thread *t, int interrupted)
{
	return CYC_PATH_TIMED(CYC_EXIT_TIMED, cycle_delim_exit_path(&t->cs, interrupted));
}

/*
 * cycle_delim_exit - the delimiter returns: the next cycle is released.
 * 'interrupted' (cycle_ret_interrupted): only tentatively, until the
 * thread's next delimiter entry tells whether it resumes the same wait.
 */
RTSUP_INLINE void cycle_delim_exit(struct rtsup_thread *t, __u64 now, int interrupted,
				   __u64 minflt, __u64 majflt)
{
	struct rtsup_cycle_state *cs = &t->cs;
	enum cycle_exit_path path = cycle_delim_exit_path(cs, interrupted);
	__u64 start = path == CYC_EXIT_SWITCHED_IN ? cs->in_ts : now;

	if (path == CYC_EXIT_NONE)
		return;
	if (cs->flags & RTSUP_CS_ENTRY_LATE) {
		/* taken for an entry (cycle_entry_skipped), never closed: that cycle is lost */
		cs->flags &= ~RTSUP_CS_ENTRY_LATE;
		cs->last_start = 0;
	}
	cs->in_delim = 0;
	if (interrupted)
		cs->flags |= RTSUP_CS_INTR;
	/* no requested release (epoll, read): latency counts from wakeup */
	if (interrupted)
		cs->last_expected = 0;	/* released before its time: no latency */
	else if (cs->expected)
		cs->last_expected = cs->expected;
	else if (cs->wake_ts && cs->wake_ts <= start)
		cs->last_expected = cs->wake_ts;
	else
		cs->last_expected = 0;
	if (path == CYC_EXIT_SWITCHED_IN) {
		/* released at a switch-in: keep what ran since, not what waited */
		__u64 cpu = cs->cpu_acc, since = cs->run_since;
		__u32 preempt = cs->preempt;

		cycle_begin(cs, start, minflt, majflt);
		cs->cpu_acc = cpu;
		cs->preempt = preempt;
		cs->run_since = since;
		return;
	}
	cycle_begin(cs, start, minflt, majflt);
}

/*
 * cycle_exit_missed - the thread enters a syscall while still in its
 * delimiter: that delimiter returned unseen (per-syscall hooks, whose runs
 * the kernel may skip: docs/design.md, "Runs the kernel skips"). Released
 * at its first switch-in after its release, as cycle_delim_exit would have
 * said; without such a switch-in the release time is unknown: that cycle
 * is not counted, nor the next one's period, which would span two. Its
 * faults count from here. 1 when the return was missed.
 */
RTSUP_INLINE int cycle_exit_missed(struct rtsup_thread *t, __u64 minflt, __u64 majflt)
{
	struct rtsup_cycle_state *cs = &t->cs;

	if (!cs->in_delim)
		return 0;
	if (cycle_delim_exit_path(cs, 0) == CYC_EXIT_SWITCHED_IN) {
		cycle_delim_exit(t, cs->in_ts, 0, minflt, majflt);
	} else {
		cs->flags &= ~RTSUP_CS_ENTRY_LATE;
		cs->in_delim = 0;
		cs->last_start = 0;
	}
	return 1;
}

/*
 * cycle_sys_seen - per-syscall hooks: the thread enters syscall nr, its
 * delimiter when 'delim'. What cycle_entry_skipped compares a sleep with.
 */
RTSUP_INLINE void cycle_sys_seen(struct rtsup_cycle_state *cs, __u32 nr, int delim)
{
	cs->cur_sys = nr + 1;
	if (delim)
		cs->delim_sys = nr + 1;
}

/*
 * cycle_entry_skipped - per-syscall hooks: the thread leaves its CPU to
 * wait (a block inside its cycle, by its state) in syscall 'sys' (+ 1,
 * read from its registers), its own delimiter, whose entry no hook saw:
 * the kernel skipped that run (docs/design.md, "Runs the kernel skips").
 * That wait is the delimiter's sleep, not a block: the cycle ends here.
 * Its close needs the requested release, read at the return
 * (cycle_late_entry): until then the cycle as it is now is kept, and the
 * thread is in its delimiter, asleep. 1 when so taken.
 */
RTSUP_INLINE int cycle_entry_skipped(struct rtsup_thread *t, __u32 sys, __u64 now,
				     __u64 minflt, __u64 majflt)
{
	struct rtsup_cycle_state *cs = &t->cs;

	if (!sys || sys != cs->delim_sys || sys == cs->cur_sys || cs->in_delim || !cs->start ||
	    cs->mode != RTSUP_MODE_DELIM || !now)
		return 0;
	if (cs->run_since && now > cs->run_since)
		cs->cpu_acc += now - cs->run_since;
	cs->late_ts = now;
	cs->late_cpu = cs->cpu_acc;
	cs->late_preempt = cs->preempt;
	cs->late_minflt = minflt;
	cs->late_majflt = majflt;
	cs->flags |= RTSUP_CS_ENTRY_LATE;
	cs->cur_sys = sys;
	cs->in_delim = 1;
	cs->in_ts = 0;
	cs->wake_ts = 0;
	cs->expected = 0;
	return 1;
}

/*
 * cycle_late_swap - before the late entry (cycle_late_entry), whose time
 * and fault counts its caller took from late_ts, late_minflt and
 * late_majflt: the cycle as it was at the sleep comes back, and what came
 * since (its release at a switch-in, the CPU time after it) goes to the
 * late_* fields. No stack: 6.1 allows 512 bytes for the deepest chain of
 * calls, and delim_cycle is in one (a 40-byte copy there made it 544).
 */
RTSUP_INLINE void cycle_late_swap(struct rtsup_cycle_state *cs)
{
	__u64 cpu = cs->cpu_acc;
	__u32 preempt = cs->preempt;

	cs->flags &= ~RTSUP_CS_ENTRY_LATE;
	cs->cpu_acc = cs->late_cpu;
	cs->late_cpu = cpu;
	cs->preempt = cs->late_preempt;
	cs->late_preempt = preempt;
	cs->late_ts = cs->in_ts;
	cs->late_minflt = cs->wake_ts;
	cs->late_majflt = cs->run_since;
	cs->run_since = 0;
}

/* cycle_late_restore - after the late entry: what came since the sleep again */
RTSUP_INLINE void cycle_late_restore(struct rtsup_cycle_state *cs)
{
	cs->in_ts = cs->late_ts;
	cs->cpu_acc = cs->late_cpu;
	cs->preempt = cs->late_preempt;
	cs->run_since = cs->late_majflt;
	cs->wake_ts = cs->late_minflt;
}

/*
 * cycle_late_entry - the delimiter whose entry went unseen returns (before
 * cycle_delim_exit): its entry now, as it was at the switch-out
 * cycle_entry_skipped took, with the requested release read from its
 * arguments. What came since is kept for cycle_delim_exit. CYC_EV_* as
 * cycle_delim_enter. The kernel side calls the parts from delim_cycle,
 * which holds the only copy of cycle_delim_enter.
 */
RTSUP_INLINE __u32 cycle_late_entry(struct rtsup_thread *t, const struct cycle_cfg *cfg,
				    __u64 expected, int absolute, struct rtsup_cycle *out)
{
	struct rtsup_cycle_state *cs = &t->cs;
	__u64 at = cs->late_ts, minflt = cs->late_minflt, majflt = cs->late_majflt;
	__u32 ev;

	cycle_late_swap(cs);
	ev = cycle_delim_enter(t, cfg, at, expected, absolute, minflt, majflt, out);
	cycle_late_restore(cs);
	return ev;
}

/*
 * cycle_late_block - the syscall cycle_entry_skipped took for the
 * delimiter is no boundary after all (a relative sleep inside an absolute
 * loop): its sleep was a block inside the cycle, counted now. CYC_EV_BLOCK.
 */
RTSUP_INLINE __u32 cycle_late_block(struct rtsup_thread *t)
{
	struct rtsup_cycle_state *cs = &t->cs;

	cs->flags &= ~RTSUP_CS_ENTRY_LATE;
	cs->in_delim = 0;
	cs->cpu_acc += cs->late_cpu;
	cs->preempt += cs->late_preempt;
	cs->blocks++;
	return CYC_EV_BLOCK;
}

/*
 * cycle_wakeup_read - will the time of a wakeup now ever be read? Only by
 * activations and by a delimiter without a requested release: a periodic
 * thread sleeping until a requested release needs no clock read here.
 */
RTSUP_INLINE int cycle_wakeup_read(const struct rtsup_thread *t)
{
	return t->cs.mode != RTSUP_MODE_DELIM || (t->cs.in_delim && !t->cs.expected);
}

/* cycle_wakeup - sched_wakeup of the thread */
RTSUP_INLINE void cycle_wakeup(struct rtsup_thread *t, __u64 now)
{
	t->cs.wake_ts = now;
}

/*
 * cycle_wake_fresh - is the last wakeup this activation's? One that came
 * before the previous activation began is stale: its own wakeup went unseen.
 */
RTSUP_INLINE int cycle_wake_fresh(const struct rtsup_cycle_state *cs, __u64 now)
{
	return cs->wake_ts && cs->wake_ts <= now && cs->wake_ts > cs->last_start;
}

/*
 * cycle_on_cpu - the thread runs on 'cpu': another CPU than the last one
 * seen is a migration, an unsafe one inside a cycle (CYC_EV_MIGRATE). At a
 * switch-in, and at a syscall of its own once its held switch-in is
 * settled: there another CPU means a switch-in no hook saw (docs/design.md,
 * "Unseen events") moved it, which its next seen switch-in would count
 * late, in a later cycle or in none (a CI run lost 1 move of 19 so).
 */
RTSUP_INLINE __u32 cycle_on_cpu(struct rtsup_thread *t, __s32 cpu)
{
	struct rtsup_cycle_state *cs = &t->cs;
	__u32 ev = 0;

	if (cs->last_cpu >= 0 && cpu != cs->last_cpu) {
		t->migrations++;
		if (cs->start && !cs->in_delim) {
			cs->migrations++;
			ev |= CYC_EV_MIGRATE;
		}
	}
	cs->last_cpu = cpu;
	return ev;
}

/* cycle_switch_in - the thread gets a CPU */
RTSUP_INLINE __u32 cycle_switch_in(struct rtsup_thread *t, __u64 now, __s32 cpu,
				   __u64 minflt, __u64 majflt)
{
	struct rtsup_cycle_state *cs = &t->cs;
	__u32 ev = cycle_on_cpu(t, cpu);

	cs->run_since = now;
	if (cs->in_delim) {
		if (!cycle_delim_switched_in(cs))
			cs->in_ts = now;
		return ev;
	}
	if (cs->mode != RTSUP_MODE_DELIM && !cs->start) {
		/* activation: the wakeup is the expected release */
		cs->mode = RTSUP_MODE_ACT;
		cs->last_expected = cycle_wake_fresh(cs, now) ? cs->wake_ts : 0;
		cycle_begin(cs, now, minflt, majflt);
	}
	return ev;
}

/*
 * cycle_switch_in_unseen - does a thread that runs (a syscall of its own)
 * look off CPU? Only then does cycle_running read the clock and the faults.
 */
RTSUP_INLINE int cycle_switch_in_unseen(const struct rtsup_thread *t)
{
	return t->cs.mode == RTSUP_MODE_ACT && !t->cs.run_since;
}

/*
 * cycle_running - the thread is in a syscall of its own, so it has a CPU.
 * Tracepoints do not fire while some tasks are current (docs/design.md,
 * "Unseen events"): a target woken and switched in from such a task has
 * no sched_wakeup nor sched_switch, only its own syscalls. Between a block
 * and such a syscall there was a switch-in: the activation begins here,
 * without a latency (neither the wakeup nor the switch-in was seen).
 */
RTSUP_INLINE void cycle_running(struct rtsup_thread *t, __u64 now, __u64 minflt,
				__u64 majflt)
{
	struct rtsup_cycle_state *cs = &t->cs;

	if (!cycle_switch_in_unseen(t))
		return;
	cs->run_since = now;
	if (cs->start)
		return;	/* preempted, then switched in unseen: only its CPU time */
	t->unseen_in++;
	cs->last_expected = 0;
	cycle_begin(cs, now, minflt, majflt);
}

/*
 * A switch-in held on its CPU, applied at the thread's next event there.
 * A thread in delimiter mode whose wakeup nobody reads (!cycle_wakeup_read)
 * needs nothing at its switch-in but the time and the CPU; its next event
 * (the delimiter's return, a syscall, its switch-out, its exit) comes on
 * the same CPU and looks its entry up anyway. So the switch-in writes this
 * per-CPU record instead of looking up a cache-cold entry.
 */
struct cycle_switch_rec {
	__u32 tid;		/* 0: nothing held (tid 0 is the idle task) */
	__s32 cpu;
	__u64 now;
	__u64 minflt;
	__u64 majflt;
	__u64 steal;		/* the CPU's steal counter then (cause.h, why_steal_in) */
};

/* cycle_switch_in_later - hold a switch-in until the thread's next event */
RTSUP_INLINE void cycle_switch_in_later(struct cycle_switch_rec *r, __u32 tid, __u64 now,
					__s32 cpu, __u64 minflt, __u64 majflt)
{
	r->tid = tid;
	r->cpu = cpu;
	r->now = now;
	r->minflt = minflt;
	r->majflt = majflt;
}

/* cycle_settle - apply the held switch-in if it is this thread's: CYC_EV_* */
RTSUP_INLINE __u32 cycle_settle(struct rtsup_thread *t, struct cycle_switch_rec *r)
{
	if (!r->tid || r->tid != t->tid)
		return 0;
	r->tid = 0;
	return cycle_switch_in(t, r->now, r->cpu, r->minflt, r->majflt);
}

/* a PREEMPT_RT sleeping spinlock's wait (include/linux/sched.h, since 5.15) */
#define CYC_TASK_RTLOCK_WAIT	0x1000

/*
 * cycle_switch_voluntary - did a thread that left its CPU, not preempted,
 * in scheduler state 'state', go to wait? Not in state 0 (a preemption the
 * tracepoint does not flag: lazy preemption at the return to user), nor
 * waiting for a kernel spinlock on PREEMPT_RT: an rtmutex with priority
 * inheritance, its owner boosted to ours, which the kernel's rtapp monitor
 * counts as an RT-friendly wait. A getrusage inside a cycle waited so for
 * task_lock, taken by a /proc read of the thread (ours, each interval):
 * counted as an RT-unsafe block, it was a false one.
 */
RTSUP_INLINE int cycle_switch_voluntary(__u32 state)
{
	return state != 0 && state != CYC_TASK_RTLOCK_WAIT;
}

/* The paths of cycle_switch_out. */
enum cycle_out_path {
	CYC_OUT_DELIM_SLEEP,	/* in the delimiter, it sleeps: that is its wait */
	CYC_OUT_DELIM_EARLY,	/* preempted in the delimiter, not released yet */
	CYC_OUT_DELIM_RUNNING,	/* preempted after its release, before the return */
	CYC_OUT_DELIM_UNSEEN,	/* the same, its switch-in unseen: no CPU time */
	CYC_OUT_IDLE,		/* no cycle running */
	CYC_OUT_PREEMPT,	/* preempted inside a cycle */
	CYC_OUT_BLOCK,		/* blocks inside a delimiter-mode cycle */
	CYC_OUT_ACT_END,	/* blocks: its activation ends */
};
/* the common switch-out of a periodic thread (into its sleep) reads no clock */
#define CYC_OUT_TIMED	((1u << CYC_OUT_DELIM_RUNNING) | (1u << CYC_OUT_PREEMPT) | \
			 (1u << CYC_OUT_BLOCK) | (1u << CYC_OUT_ACT_END))

/* cycle_switch_out_path - which path cycle_switch_out takes */
RTSUP_INLINE enum cycle_out_path cycle_switch_out_path(const struct rtsup_cycle_state *cs,
							int voluntary)
{
	if (cs->in_delim) {
		if (voluntary)
			return CYC_OUT_DELIM_SLEEP;
		if (!cycle_delim_switched_in(cs))
			return CYC_OUT_DELIM_EARLY;
		return cs->run_since ? CYC_OUT_DELIM_RUNNING : CYC_OUT_DELIM_UNSEEN;
	}
	if (!cs->start)
		return CYC_OUT_IDLE;
	if (!voluntary)
		return CYC_OUT_PREEMPT;
	return cs->mode == RTSUP_MODE_DELIM ? CYC_OUT_BLOCK : CYC_OUT_ACT_END;
}

/* cycle_switch_out_timed - will cycle_switch_out read 'now'? */
RTSUP_INLINE int cycle_switch_out_timed(const struct rtsup_thread *t, int voluntary)
{
	return CYC_PATH_TIMED(CYC_OUT_TIMED, cycle_switch_out_path(&t->cs, voluntary));
}

/* cycle_add_cpu - CPU time since the switch-in, if it was seen */
RTSUP_INLINE void cycle_add_cpu(struct rtsup_cycle_state *cs, __u64 now)
{
	if (cs->run_since && now > cs->run_since)
		cs->cpu_acc += now - cs->run_since;
}

/*
 * cycle_switch_out_on - cycle_switch_out on the path its caller decided
 * already: path is cycle_switch_out_path(&t->cs, voluntary)
 */
RTSUP_INLINE __u32 cycle_switch_out_on(struct rtsup_thread *t, const struct cycle_cfg *cfg,
				       enum cycle_out_path path, __u64 now, int voluntary,
				       __u64 minflt, __u64 majflt, struct rtsup_cycle *out)
{
	struct rtsup_cycle_state *cs = &t->cs;
	__u32 ev = 0;

	if (voluntary)
		t->vol_cs++;
	else
		t->invol_cs++;
	switch (path) {
	case CYC_OUT_DELIM_SLEEP:
		/* it sleeps: the release comes later, and this is its wait */
		if (!cs->delim_key)
			cs->delim_key = cs->cand_key;
		cs->in_ts = 0;
		cs->cpu_acc = 0;
		cs->preempt = 0;
		break;
	case CYC_OUT_DELIM_EARLY:
	case CYC_OUT_IDLE:
		break;
	case CYC_OUT_DELIM_RUNNING:	/* after its release, before the syscall returned */
	case CYC_OUT_DELIM_UNSEEN:
	case CYC_OUT_PREEMPT:
		cs->preempt++;
		cycle_add_cpu(cs, now);
		break;
	case CYC_OUT_BLOCK:
		cs->blocks++;
		/* a stop or a handler after an interrupted sleep: reported if no resume */
		if (!(cs->flags & RTSUP_CS_INTR))
			ev |= CYC_EV_BLOCK;
		cycle_add_cpu(cs, now);
		break;
	case CYC_OUT_ACT_END:
		ev |= cycle_close(t, cfg, now, minflt, majflt, 0, out);
		cycle_account(t, cfg, out);
		return ev;
	}
	cs->run_since = 0;
	return ev;
}

/*
 * cycle_switch_out - the thread leaves its CPU; 'voluntary' is a block
 * (it is no longer runnable), otherwise a preemption.
 */
RTSUP_INLINE __u32 cycle_switch_out(struct rtsup_thread *t, const struct cycle_cfg *cfg,
				    __u64 now, int voluntary, __u64 minflt,
				    __u64 majflt, struct rtsup_cycle *out)
{
	return cycle_switch_out_on(t, cfg, cycle_switch_out_path(&t->cs, voluntary), now,
				   voluntary, minflt, majflt, out);
}

/* cycle_syscall - a syscall other than the delimiter; 'unsafe' per class */
RTSUP_INLINE __u32 cycle_syscall(struct rtsup_thread *t, int unsafe)
{
	struct rtsup_cycle_state *cs = &t->cs;

	if (!cs->start || cs->in_delim)
		return 0;
	cs->syscalls++;
	if (!unsafe)
		return 0;
	cs->unsafe_sys++;
	return CYC_EV_UNSAFE;
}

/* cycle_exit - the thread exits; a running cycle is not accounted */
RTSUP_INLINE void cycle_exit(struct rtsup_thread *t, __u64 now, __u64 minflt,
			     __u64 majflt)
{
	struct rtsup_cycle_state *cs = &t->cs;

	t->exited = now;
	if (cs->start && !cs->in_delim && cs->mode == RTSUP_MODE_DELIM) {
		/* shown apart: a thread's teardown is not its loop */
		t->exit_mid_cycle = 1;
		t->exit_unsafe[RTSUP_U_SYSCALL] += cs->unsafe_sys;
		t->exit_unsafe[RTSUP_U_MINFLT] += minflt - cs->minflt0;
		t->exit_unsafe[RTSUP_U_MAJFLT] += majflt - cs->majflt0;
		t->exit_unsafe[RTSUP_U_BLOCK] += cs->blocks;
		t->exit_unsafe[RTSUP_U_MIGRATE] += cs->migrations;
	}
	cs->start = 0;
	cs->in_delim = 0;
}

#endif /* RTSUP_CYCLE_H */
