/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * rtsup.h - types shared by the BPF programs and userspace.
 *
 * Fixed-width fields and fixed arrays only: the same bytes are read by the
 * kernel side (vmlinux.h types) and by userspace (linux/types.h).
 */
#ifndef RTSUP_H
#define RTSUP_H

#ifndef __VMLINUX_H__
#include <linux/types.h>
#endif

#define RTSUP_COMM_LEN		16
#define RTSUP_MAX_COMMS		8	/* --comm names matched in the kernel */
#define RTSUP_MAX_SYSCALLS	1024	/* size of the syscall class table */
/*
 * --syscall-hooks per-syscall: fentry stubs, one per hooked syscall, and
 * fexit stubs, one per syscall that may end a cycle (docs/design.md,
 * "Syscall hooks"). The stubs are compiled in: 10 to a row (rtsup.bpf.c).
 */
#define RTSUP_SYS_IN_SLOTS	80	/* syscalls with arguments: sys_in_NN */
#define RTSUP_SYS_OUT_SLOTS	30	/* sys_out_NN */
#define RTSUP_SYS_IN_SLOTS_Z	20	/* syscalls without (fork, restart_syscall): sys_in_z_NN */
#define RTSUP_SYS_OUT_SLOTS_Z	4	/* sys_out_z_NN */
#define RTSUP_DEFAULT_THREADS	4096	/* default capacity of the thread map */
#define RTSUP_UNTRACKED_MAX	16384	/* untracked threads counted at once */
/*
 * The tid bitmaps: the hooks' first test, one load and no lookup, so that
 * a thread that is no target costs nothing more. One bit per thread id
 * (PID_MAX_LIMIT is 2^22), in .bss (rtsup.bpf.c), read and set by the
 * hooks and the collector; changed atomically, since the hooks on other
 * CPUs and the collector change other bits of the same word.
 *
 * tidmask: the thread may have an entry in the thread map; a hook looks a
 *   thread up only when its bit is set. Set before the entry is added
 *   (tid_mark_new), so no entry is ever missed. Never cleared: a stale
 *   bit costs one failed lookup, and clearing it would race with another
 *   CPU adding the same tid.
 * wakemask: the thread's next wakeup time may be read (cycle_wakeup_read).
 *   sched_wakeup looks the thread up only when it is set; sched_switch
 *   looks it up at its switch-in when set and holds the switch-in in a
 *   per-CPU record when clear (cycle_switch_in_later). A set bit is
 *   always safe (one lookup more); a clear bit only while the entry's
 *   wakeups are not read (cycle_wakeup_read() false, or it exited). So it
 *   is set with tidmask for a new thread, and after every event that
 *   changes what that reads kept equal to it (note_wake: wake_bit_sync).
 *   It is set only with or after the tidmask bit, which stays: a set
 *   wakemask bit implies a set tidmask bit; a clear tidmask bit answers both.
 *   Under --rt's per-switch fallback the collector sets it when it drops
 *   an entry (tid_release): a held switch-in reads no policy.
 */
#define RTSUP_TIDMASK_WORDS	((1U << 22) / 64)
#define RTSUP_TIDMASK_WORD(tid)	(((tid) >> 6) & (RTSUP_TIDMASK_WORDS - 1))
#define RTSUP_TIDMASK_BIT(tid)	(1ULL << ((tid) & 63))

/* Userspace inlines; the BPF side defines its own before including this. */
#ifndef RTSUP_INLINE
#define RTSUP_INLINE static inline __attribute__((always_inline))
#endif

/* tid_bit, tid_bit_set, tid_bit_clear - a thread's bit in a tid bitmap */
RTSUP_INLINE int tid_bit(const __u64 *mask, __u32 tid)
{
	return (mask[RTSUP_TIDMASK_WORD(tid)] & RTSUP_TIDMASK_BIT(tid)) != 0;
}

RTSUP_INLINE void tid_bit_set(__u64 *mask, __u32 tid)
{
	__sync_fetch_and_or(&mask[RTSUP_TIDMASK_WORD(tid)], RTSUP_TIDMASK_BIT(tid));
}

RTSUP_INLINE void tid_bit_clear(__u64 *mask, __u32 tid)
{
	__sync_fetch_and_and(&mask[RTSUP_TIDMASK_WORD(tid)], ~RTSUP_TIDMASK_BIT(tid));
}

/* tid_mark_new - before a thread's entry is added: a target, its wakeups read */
RTSUP_INLINE void tid_mark_new(__u64 *tidmask, __u64 *wakemask, __u32 tid)
{
	tid_bit_set(tidmask, tid);
	/* a new thread's wakeups are read until it shows a delimiter */
	tid_bit_set(wakemask, tid);
}

/* wake_bit_sync - the thread's wakemask bit set to 'want'; no atomic when it is */
RTSUP_INLINE void wake_bit_sync(__u64 *wakemask, __u32 tid, int want)
{
	if (tid_bit(wakemask, tid) == want)
		return;
	if (want)
		tid_bit_set(wakemask, tid);
	else
		tid_bit_clear(wakemask, tid);
}

/* Metrics measured once per cycle. */
enum rtsup_metric {
	RTSUP_M_PERIOD,		/* release to release */
	RTSUP_M_EXEC,		/* release to next delimiter entry (wall) */
	RTSUP_M_CPU,		/* CPU time inside the cycle */
	RTSUP_M_LATENCY,	/* switch-in minus expected release */
	RTSUP_M_NR,
};

/* Why a cycle lost real-time safety (a Xenomai "mode switch" analogue). */
enum rtsup_unsafe {
	RTSUP_U_SYSCALL,	/* a syscall of an unsafe class */
	RTSUP_U_MINFLT,		/* minor page fault */
	RTSUP_U_MAJFLT,		/* major page fault */
	RTSUP_U_BLOCK,		/* voluntary block that is not the delimiter */
	RTSUP_U_MIGRATE,	/* moved to another CPU */
	RTSUP_U_NR,
};

/* Bits of the per-syscall class table (map sysclass). */
#define RTSUP_SC_UNSAFE		0x01	/* unsafe inside a cycle */
#define RTSUP_SC_DELIM		0x02	/* cycle delimiter */
#define RTSUP_SC_FDCHECK	0x04	/* unsafe only on a regular file or tty */
#define RTSUP_SC_ABSSLEEP	0x08	/* clock_nanosleep: (clk, flags, req, rem) */
#define RTSUP_SC_RELSLEEP	0x10	/* nanosleep: (req, rem) */
#define RTSUP_SC_RESTART	0x20	/* restart_syscall: resumes an interrupted sleep */
#define RTSUP_SC_KEYED		0x40	/* a wait on its first argument (fd, futex) */
#define RTSUP_SC_OPKEY		0x80	/* and on its operation (futex) */

/* Cycle modes: how a thread's cycles are delimited. */
enum rtsup_mode {
	RTSUP_MODE_NONE,	/* nothing seen yet */
	RTSUP_MODE_ACT,		/* activations: wakeup to next block */
	RTSUP_MODE_DELIM,	/* delimiter syscall */
};

/*
 * Bit of the unsafe_sys key's mode once a delimiter thread's period has
 * settled (cycle_sys_mode): what start-up counted stays apart.
 */
#define RTSUP_MODE_SETTLED	0x100

/* Flags of the cycle state (rtsup_cycle_state.flags). */
#define RTSUP_CS_INTR		0x01	/* the delimiter was interrupted: maybe resumed */
#define RTSUP_CS_ABS_SEEN	0x02	/* the thread has slept to absolute releases */
#define RTSUP_CS_SETTLED	0x04	/* the period settled: start-up is over */
#define RTSUP_CS_DIRTY		0x08	/* start-up cycles were counted: drop them at settling */
/* the delimiter's entry went unseen, its sleep taken as the entry: replayed at its return */
#define RTSUP_CS_ENTRY_LATE	0x10

/*
 * Log-linear histogram: values below 2^HIST_SUB_BITS get a bucket each,
 * every power of two above is split in 2^HIST_SUB_BITS linear buckets, so
 * a bucket is at most 1/8 wide relative to its value. Values above
 * 2^HIST_MAX_EXP ns (about 69 s) land in the last bucket.
 */
#define HIST_SUB_BITS	3
#define HIST_SUB	(1 << HIST_SUB_BITS)
#define HIST_MAX_EXP	36
#define HIST_BUCKETS	((HIST_MAX_EXP - HIST_SUB_BITS + 2) * HIST_SUB)

struct rtsup_minmax {
	__u64 min;
	__u64 max;
};

/* Lifetime statistics of one metric; min/max also per interval bank. */
/*
 * Interval windows. Counts, sums and histograms in the maps only grow: an
 * interval's are the difference of two snapshots (model.c). Min and max
 * cannot be subtracted: they go into one of two banks, win[RTSUP_BANK(epoch)].
 * Userspace increments epoch when an interval ends, then reads the bank of
 * the epoch that ended, which the hooks no longer write; a hook resets a
 * bank the first time it writes it in a new epoch (cycle_epoch, can.h).
 * Nothing is reset from userspace, so nothing is lost between read and reset.
 */
#define RTSUP_BANK(epoch)	((epoch) & 1)

struct rtsup_metric_stats {
	__u64 count;
	__u64 sum;
	__u64 min;
	__u64 max;
	__s64 ewma;		/* fixed point, RTSUP_EWMA_SHIFT fraction bits */
	struct rtsup_minmax win[2];	/* per-interval min/max, by RTSUP_BANK(epoch) */
	__u32 hist[HIST_BUCKETS];
};

#define RTSUP_EWMA_SHIFT	8
#define RTSUP_EWMA_ONE		1024	/* weight unit: weight = w / 1024 */

/* Flags of one finished cycle. */
#define RTSUP_CF_MISS		0x01	/* requested release already past */
#define RTSUP_CF_OVERRUN	0x02	/* exec > nominal period */
#define RTSUP_CF_HAS_PERIOD	0x04	/* a previous release exists */
#define RTSUP_CF_HAS_LATENCY	0x08	/* expected release known */

/* One finished cycle, as produced by the cycle state machine. */
struct rtsup_cycle {
	__u64 start;		/* release (switch-in) time */
	__u64 period;
	__u64 exec;
	__u64 cpu;
	__u64 latency;
	__u64 nominal;		/* nominal period, 0 if unknown */
	__u32 preempt;		/* involuntary switches inside the cycle */
	__u32 blocks;		/* voluntary blocks inside the cycle */
	__u32 migrations;
	__u32 syscalls;
	__u32 unsafe_sys;
	__u32 minflt;
	__u32 majflt;
	__u32 flags;
};

#define RTSUP_PEND_SYS	4	/* distinct unsafe syscalls held per cycle */

/* Cycle state machine: everything needed between two events. */
struct rtsup_cycle_state {
	__u64 start;		/* release of the running cycle, 0 = none */
	__u64 last_start;	/* release of the previous cycle */
	__u64 run_since;	/* switch-in time while on CPU, 0 = off CPU */
	__u64 cpu_acc;		/* CPU time of the cycle so far */
	__u64 expected;		/* expected release of the pending sleep */
	__u64 abs_expected;	/* same, when requested as an absolute time */
	__u64 last_expected;	/* expected release of the running cycle */
	__u64 nominal;		/* last nominal period (expected deltas) */
	__u64 wake_ts;		/* last wakeup while sleeping */
	__u64 in_ts;		/* in the delimiter: cycle_delim_switched_in() */
	__u64 minflt0;		/* fault counters at cycle start */
	__u64 majflt0;
	__u32 mode;		/* enum rtsup_mode */
	__u32 in_delim;		/* inside a delimiter syscall */
	__u32 cur_sys;		/* per-syscall hooks: last syscall entered + 1, 0 = returned */
	__s32 last_cpu;
	__u32 preempt;
	__u32 blocks;
	__u32 migrations;
	__u32 syscalls;
	__u32 unsafe_sys;
	__u32 flags;		/* RTSUP_CS_* */
	__u64 dist;		/* last distance between two absolute releases */
	__u32 run;		/* consecutive absolute releases at distance 'dist' */
	__u32 rel_sleeps;	/* relative sleeps since the last absolute one */
	__s64 clk_off;		/* the sleep's clock - CLOCK_MONOTONIC at its entry (cycle_clock_moved) */
	__u32 clk;		/* that clock's id + 1 for an absolute sleep, 0 = none */
	__u32 pad_clk;
	__u64 delim_key;	/* the wait that ends a cycle (keyed delimiters), 0 = not learned */
	__u64 cand_key;		/* the key of the delimiter call in progress */
	/* unsafe syscalls of the running cycle, by number, counted at its end */
	__u16 pend_nr[RTSUP_PEND_SYS];
	__u16 pend_cnt[RTSUP_PEND_SYS];
	/*
	 * per-syscall hooks: the thread's delimiter syscall + 1 (0 = none seen),
	 * and a sleep in it whose entry went unseen (RTSUP_CS_ENTRY_LATE): the
	 * cycle as it was at that switch-out, closed at the return; while it
	 * closes, what came since (cycle_late_swap in cycle.h)
	 */
	__u32 delim_sys;
	__u32 late_preempt;
	__u64 late_ts;
	__u64 late_cpu;
	__u64 late_minflt;
	__u64 late_majflt;
};

/*
 * Cause attribution (include/cause.h): why a cycle ended late. A task
 * named in a cause: who held the CPU, preempted the target or woke it.
 * tid 0 is the idle task (the CPU was idle).
 */
struct rtsup_who {
	__u32 tid;
	__u32 tgid;
	__u32 policy;		/* SCHED_* */
	__s32 prio;		/* rt_priority for FIFO/RR/DEADLINE, nice otherwise */
	char comm[RTSUP_COMM_LEN];
};

/* A culprit of one cycle: a task that held the target's CPU, for how long. */
struct rtsup_culprit {
	struct rtsup_who who;
	__u64 ns;
	__u32 count;		/* waits it caused */
	__u32 pad;
};

#define RTSUP_CAUSE_TOP	3	/* culprits kept per cycle */

/* The part of a late cycle that took longest: its cause. */
enum rtsup_cause_kind {
	RTSUP_CAUSE_NONE,
	RTSUP_CAUSE_TIMER,	/* the wakeup came late: the machine held the CPU */
	RTSUP_CAUSE_WAIT,	/* woken, then waited for the CPU behind 'who' */
	RTSUP_CAUSE_PREEMPT,	/* preempted inside the cycle by 'who' */
	RTSUP_CAUSE_BLOCK,	/* blocked inside the cycle, woken by 'who' */
	RTSUP_CAUSE_BACKLOG,	/* released late: the previous cycle ended late */
	RTSUP_CAUSE_EXEC,	/* its own CPU time */
	RTSUP_CAUSE_STEAL,	/* a hypervisor ran another vCPU while it ran (steal) */
	RTSUP_CAUSE_NR,
};

/* Flags of a cause. */
#define RTSUP_CAUSE_F_IDLE	0x01	/* the late wakeup came to an idle CPU */
#define RTSUP_CAUSE_F_INVERSION	0x02	/* the block was ended by a lower priority task */
#define RTSUP_CAUSE_F_DSTATE	0x04	/* the block was uninterruptible (D state) */
#define RTSUP_CAUSE_F_INHERIT	0x08	/* backlog: 'who' is the previous cycle's culprit */
#define RTSUP_CAUSE_F_BELOW	0x10	/* the longest holder was below the target's priority */

/*
 * Why a target moved to another CPU, as far as the kernel tells at
 * sched_migrate_task (cause.h, why_migrate).
 */
enum rtsup_mig_why {
	RTSUP_MIG_UNKNOWN,	/* the hook did not see it */
	RTSUP_MIG_WAKEUP,	/* placed at its wakeup (TASK_WAKING) */
	RTSUP_MIG_AFFINITY,	/* its CPU left its affinity mask */
	RTSUP_MIG_BALANCE,	/* load balance, RT push/pull: allowed where it was */
	RTSUP_MIG_NR,
};

/* arg2 of an RTSUP_U_MIGRATE event: from which CPU (RTSUP_MIG_NOCPU: unknown), to which, why */
#define RTSUP_MIG_NOCPU		0xffffU
#define RTSUP_MIG_ARG(from, to, why)	((__u64)(to) | (__u64)(from) << 16 | (__u64)(why) << 32)
#define RTSUP_MIG_TO(a)		((__u32)((a) & 0xffff))
#define RTSUP_MIG_FROM(a)	((__u32)(((a) >> 16) & 0xffff))
#define RTSUP_MIG_WHY(a)	((__u32)(((a) >> 32) & 0xffff))

/* Why one cycle was late, in parts (ns), and the one that won. */
struct rtsup_cause {
	__u32 kind;		/* enum rtsup_cause_kind */
	__u32 flags;		/* RTSUP_CAUSE_F_* */
	__u64 ns;		/* the winning part's time */
	__u64 timer_ns;		/* expected release to wakeup */
	__u64 wait_ns;		/* woken (release or block) to running */
	__u64 preempt_ns;	/* preempted inside the cycle */
	__u64 block_ns;		/* blocked inside the cycle */
	__u64 backlog_ns;	/* released after its time without sleeping */
	__u64 cpu_ns;		/* its own CPU time */
	__u32 preempts;		/* preemptions inside the cycle */
	__u32 blocks;		/* blocks inside the cycle */
	__u32 block_nr;		/* syscall of the longest block (+1, 0 = none) */
	__u32 block_op;		/* its futex operation, without flags */
	__u64 block_max;	/* the longest block */
	struct rtsup_who who;	/* the culprit of the winning part */
	struct rtsup_who waker;	/* ended the longest block (or the late release's timer) */
	struct rtsup_culprit top[RTSUP_CAUSE_TOP];	/* held the CPU, longest first */
	/* when and where (Perfetto: culprit slices on CPU tracks, wakeup flows) */
	__u64 held_from;	/* the longest wait or preemption: its wakeup or preemption */
	__u64 held_to;		/* its switch-in */
	__u32 held_cpu;		/* the CPU it waited for */
	__u32 held_tid;		/* held longest by this task in that wait (0: none, idle) */
	__u64 block_woke;	/* the longest block's wakeup, by 'waker' */
	__u64 block_ran;	/* its switch-in after it */
	__u32 migrations;	/* inside the cycle */
	__u16 mig_from;		/* the last of them: from CPU (RTSUP_MIG_NOCPU: unknown) */
	__u16 mig_to;
	__u32 mig_why;		/* enum rtsup_mig_why */
	__u32 after;		/* a backlog: the kind of the late cycle it follows */
	/* last, so that a recording made before it reads with it zero (record.h) */
	__u64 steal_ns;		/* stolen by the hypervisor while it ran (not in cpu_ns) */
};

/* Per-thread attribution state of the running cycle (include/cause.h). */
struct rtsup_why {
	struct rtsup_cause cur;	/* the running cycle so far */
	struct rtsup_cause out;	/* the last closed cycle, sent with its miss */
	__u64 out_ts;		/* voluntary switch-out inside the cycle, 0 = none */
	__u32 out_dstate;	/* that block is uninterruptible */
	__u32 sys_nr;		/* syscall in progress inside the cycle + 1 */
	__u32 sys_op;		/* and its futex operation */
	__u16 mig_from;		/* its last sched_migrate_task: from CPU */
	__u16 mig_to;		/* to CPU */
	__u32 mig_why;		/* enum rtsup_mig_why, 0 = taken (why_migrated) */
	__u32 steal_cpu;	/* on CPU since a switch-in on this CPU + 1, 0 = off CPU */
	__u64 steal_in;		/* that CPU's steal counter at that switch-in (why_steal_in) */
};

#define WHY_WOKEN	1	/* the target was woken and waits for the CPU */
#define WHY_PREEMPTED	2	/* the target was preempted and waits for the CPU */
#define WHY_RAN		4	/* it runs again: the slot waits for why_take */

/*
 * Targets that may wait for one CPU at once, each in its slot: two woken
 * by one timer tick (a hog and its victim) both keep their wait whole.
 */
#define WHY_WAITERS	2

/* One waiting target of a CPU (WHY_WAITERS per CPU on the BPF side). */
struct why_slot {
	__u32 tid;		/* the target waiting for this CPU, 0 = none */
	__u32 state;		/* WHY_WOKEN or WHY_PREEMPTED, | WHY_RAN */
	__u64 armed;		/* wakeup or preemption time */
	__u64 since;		/* the running task's start on this CPU */
	__u64 ran;		/* the target's switch-in */
	__u64 top_ns;		/* the longest holder's time */
	__s32 prio;		/* the target's priority at its wakeup (inversion) */
	__u32 policy;
	struct rtsup_who top;	/* held the CPU longest while the target waited */
	struct rtsup_who waker;	/* the task current at the wakeup (idle: tid 0) */
};

/* Per-thread value of the map "threads", keyed by tid. */
struct rtsup_thread {
	/*
	 * First: all the thread map's iterator reads of a parked thread's
	 * entry, mostly in the cache line of the map's key, which it reads
	 * anyway (0.43 -> 0.37 us a visit, docs/performance.md)
	 */
	__u32 gen;		/* moved by every hook that may write it (threadread.h) */
	__u32 read_seen;	/* the collector's iterator's: gen + 1 as last copied */
	__u32 read_again;	/* ... and the second copy of a change is due */
	__u32 moved_seq;	/* the read it was sent to the ring "moved" for (threadread.h) */
	struct rtsup_cycle_state cs;
	__u32 tid;
	__u32 tgid;
	char comm[RTSUP_COMM_LEN];
	__u64 first_seen;
	__u64 last_cycle;	/* start of the last finished cycle */
	__u64 cycles;
	__u64 misses;
	__u64 overruns;
	__u64 vol_cs;
	__u64 invol_cs;
	__u64 migrations;
	__u64 syscalls;
	__u64 signals;
	__u64 minflt;		/* inside cycles */
	__u64 majflt;
	__u64 unsafe[RTSUP_U_NR];	/* inside finished cycles */
	/* inside the cycle cut by the thread's exit: its teardown, not its loop */
	__u64 exit_unsafe[RTSUP_U_NR];
	__u64 exited;		/* exit time, 0 while alive */
	__u32 exit_mid_cycle;
	__u32 last_signal;
	__u32 epoch;		/* interval whose bank the stats write to */
	__u32 resets;		/* times the stats restarted (first delimiter) */
	__s32 exit_code;	/* task exit code: signal in bits 0-6, status in 8-15 */
	__u32 unseen_in;	/* activations begun with no switch-in seen (cycle_running) */
	__u32 rt;		/* --rt: RTSUP_RT_ONLY, RTSUP_RT_LEFT (rtfollow.h) */
	__u32 exit_group;	/* its process ended with it (exit_group, a fatal signal) */
	__u32 setsched;		/* attribute changes seen (thread_sched_seen): read them again */
	__u32 sched_seen;	/* policy, RT priority, CPUs allowed at its last switch-out */
	__u64 compat_sys;	/* 32-bit syscalls (ia32, arm32): other numbers, not classified */
	struct rtsup_metric_stats m[RTSUP_M_NR];
	struct rtsup_why why;	/* cause attribution (cause.h) */
};

#define RTSUP_CFG_DELIMS	8	/* as many as --cycle-syscall takes */
#define RTSUP_CFG_SYSCALLS	8

/*
 * Per-thread settings from the configuration's rules (map "thread_cfg",
 * written by userspace only): they override the global ones.
 */
struct rtsup_thread_cfg {
	__u64 period;			/* nominal period, 0 = global */
	__u64 warmup;			/* start-up lasts at least this, ns (config warmup:) */
	__u32 ewma_w;			/* 0 = global */
	__u32 ndelims;			/* 0 = the global delimiters */
	__u16 delims[RTSUP_CFG_DELIMS];
	__u16 allow[RTSUP_CFG_SYSCALLS];	/* never unsafe for this thread */
	__u16 forbid[RTSUP_CFG_SYSCALLS];	/* unsafe for this thread too */
	__u32 nallow;
	__u32 nforbid;
};

/* One finished cycle, sent only when recording (--record, --perfetto). */
struct rtsup_cycle_rec {
	__u32 tid;
	__u32 tgid;
	__u32 resets;		/* the thread's reset generation (see cycle_reset_stats) */
	__u32 pad;
	struct rtsup_cycle c;
};

/*
 * One target's scheduling attributes and cgroup, as the task iterator
 * (attrs_task) writes them at a sample (user/collect/taskattrs.h).
 */
#define RTSUP_ATTR_CPU_WORDS	16	/* 1024 CPUs, glibc's CPU_SETSIZE */
struct rtsup_task_attrs {
	__u32 tid;
	__s32 policy;			/* SCHED_* without SCHED_RESET_ON_FORK */
	__u32 rt_priority;		/* 0 unless an RT policy */
	__u32 cpu_words;		/* words of 'cpus' the kernel's mask filled */
	__u64 cgroup_id;		/* its cgroup v2 directory's id */
	__u64 cpus[RTSUP_ATTR_CPU_WORDS];	/* allowed CPUs */
};

/* Key of the map "unsafe_sys": unsafe syscalls counted per thread. */
struct rtsup_sys_key {
	__u32 tid;
	__u16 nr;
	__u16 mode;	/* enum rtsup_mode when counted: start-up is apart */
};

/* Rare events sent through the ring buffer. */
enum rtsup_event_type {
	RTSUP_EV_MISS = 1,	/* deadline miss: arg = lateness ns */
	RTSUP_EV_UNSAFE,	/* arg = reason, arg2 = syscall nr or count */
	RTSUP_EV_EXIT,		/* thread exit: arg = 1 if mid-cycle */
	RTSUP_EV_NEW,		/* a new target thread */
	RTSUP_EV_SIGNAL,	/* arg = signal number */
};

struct rtsup_event {
	__u64 ts;
	__u32 type;
	__u32 tid;
	__u32 tgid;
	__u32 cpu;
	__u64 arg;
	__u64 arg2;
	char comm[RTSUP_COMM_LEN];
	struct rtsup_cause cause;	/* RTSUP_EV_MISS: why; zero otherwise */
};

/* Counters kept by the BPF side about itself (array "counters"). */
enum rtsup_counter {
	RTSUP_C_RB_DROPS,	/* ring buffer full */
	RTSUP_C_MAP_FULL,	/* threads we could not track, each once (map untracked) */
	RTSUP_C_SYS_FULL,	/* unsafe_sys entries we could not add */
	RTSUP_C_NEW,		/* threads added by the kernel side */
	RTSUP_C_CYC_DROPS,	/* cycle records the recording buffer had no room for */
	RTSUP_C_CAN_FULL,	/* CAN frames whose identifier did not fit the id map */
	RTSUP_C_WHY_BUSY,	/* target wakeups not attributed: another target waited there */
	RTSUP_C_DELIM_UNSEEN,	/* delimiter entries and returns the hooks skipped, recovered */
	RTSUP_C_NR,
};

/*
 * Where in the code (--stacks): the user stack of a target at an RT-unsafe
 * event, one record in the ring buffer "stacks". Frame pointers: the
 * kernel walks them (ips). DWARF: the user registers and the top of the
 * user stack are copied (regs, dump) and unwound in userspace (libdwfl).
 */
enum rtsup_stacks {
	RTSUP_STACKS_OFF,
	RTSUP_STACKS_FP,
	RTSUP_STACKS_DWARF,
	/*
	 * per process: frame pointers when every module it maps keeps them
	 * (userspace's verdict in map "stack_auto"), DWARF until there is one
	 */
	RTSUP_STACKS_AUTO,
};

/*
 * A thread's unwinder when its configuration rule gives one (map
 * "stack_cfg", by tid; written by userspace only): it overrides --stacks.
 */
struct rtsup_stack_cfg {
	__u32 kind;		/* enum rtsup_stacks */
	__u32 size;		/* DWARF: bytes of user stack copied */
};

#define RTSUP_STACK_DEPTH	32	/* frames walked by frame pointers */
#define RTSUP_STACK_REGS	33	/* DWARF numbering: x86_64 0-16, arm64 0-32 */
#define RTSUP_STACK_DUMP_MAX	(64 * 1024)	/* --stack-size at most */
#define RTSUP_STACK_BUDGET	256	/* default records per thread per interval */

struct rtsup_stack_rec {
	__u64 ts;
	__u32 tid;
	__u32 tgid;
	__u32 reason;		/* enum rtsup_unsafe */
	__u32 nr;		/* the syscall, RTSUP_U_SYSCALL only */
	__u32 kind;		/* enum rtsup_stacks: FP or DWARF */
	__u32 nips;		/* frame pointers: entries of ips */
	__u32 dump_len;		/* DWARF: bytes of dump, from the stack pointer up */
	__u32 exec_id;		/* the process's exec generation: its mappings changed */
	__u64 sp;		/* DWARF: the user stack pointer, where dump starts */
	__u64 regs[RTSUP_STACK_REGS];	/* DWARF: the user registers at the event */
	__u64 ips[RTSUP_STACK_DEPTH];	/* frame pointers: innermost first */
	/* DWARF: dump follows, cfg_stack_size_max bytes (dump_len used) */
};

/* reason of a record without a stack: the process ran a new program (exec) */
#define RTSUP_STACK_EXEC	RTSUP_U_NR
/*
 * reason of a user page fault inside a cycle (x86 exceptions:page_fault_user):
 * minor or major is known only at the cycle's end, from the task's counters
 */
#define RTSUP_STACK_FAULT	(RTSUP_U_NR + 1)

/* A thread's stack records in the current interval (map "stack_budget"). */
struct rtsup_stack_budget {
	__u32 epoch;
	__u32 n;
};

/* Counters of the stack records (array "stack_counters"): none is silent. */
enum rtsup_stack_counter {
	RTSUP_STK_LOST,		/* the ring buffer "stacks" was full */
	RTSUP_STK_OVER_BUDGET,	/* beyond the thread's budget in the interval */
	RTSUP_STK_NO_STACK,	/* the kernel could not read the user stack */
	RTSUP_STK_NR,
};

#endif /* RTSUP_H */
