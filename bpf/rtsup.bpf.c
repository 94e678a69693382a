// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * rtsup.bpf.c - kernel side of rtsup-trace: per-thread cycle statistics.
 *
 * Every hook starts with one lookup of the current (or switched) thread in
 * the map "threads"; a thread that is not a target returns right there.
 * One exception: the switch-in of a thread sleeping until a requested
 * release is held in a per-CPU record and applied at the thread's next
 * event (cycle_switch_in_later), which looks the entry up anyway.
 * Statistics are aggregated here; the ring buffer carries only rare events.
 * Each program exists as tp_btf and as raw_tp: userspace keeps one set.
 */
#include <vmlinux.h>
#include <bpf/bpf_helpers.h>
#include <bpf/bpf_tracing.h>
#include <bpf/bpf_core_read.h>
#include <bpf/bpf_endian.h>
#include "core_fixes.bpf.h"

#define RTSUP_INLINE static __always_inline
#define RTSUP_SUBPROG static __noinline
#define RTSUP_GLOBAL __noinline
#define RTSUP_ZERO(p, n) zero_mem(p, n)
#include "rtsup.h"

static __always_inline void zero_mem(void *p, __u32 n);

#include "cycle.h"
#include "cause.h"
#include "can.h"
#include "stackcfg.h"
#include "rtfollow.h"
#include "threadread.bpf.h"

/*
 * TREAD - a field of a task_struct or sk_buff argument: tp_btf programs get
 * BTF pointers and read with a plain load; raw_tp programs need
 * bpf_probe_read (a helper call per field, per event). 'btf' is a
 * constant, so each program keeps one of the two.
 */
#define TREAD(btf, t, f) ((btf) ? (t)->f : BPF_CORE_READ(t, f))

/* CURRENT - the current task, a BTF pointer (plain loads) in tp_btf programs */
#define CURRENT(btf) ((btf) ? bpf_get_current_task_btf() : \
		      (struct task_struct *)bpf_get_current_task())

/* SYSARG - argument n of the syscall being entered, plain load in tp_btf */
#define SYSARG(btf, regs, n) ((btf) ? PT_REGS_PARM##n##_SYSCALL(regs) : \
			      PT_REGS_PARM##n##_CORE_SYSCALL(regs))

/*
 * SYSCALL_NR - the number of the syscall a task is in, from its saved
 * registers: what raw_syscalls:sys_enter gets as 'id' (-1 outside a syscall)
 */
#if defined(__TARGET_ARCH_x86)
#define SYSCALL_NR(regs) ((long)BPF_CORE_READ(regs, orig_ax))
#elif defined(__TARGET_ARCH_arm64)
#define SYSCALL_NR(regs) ((long)BPF_CORE_READ(regs, syscallno))
#else
#define SYSCALL_NR(regs) (-1L)
#endif

#define TIMER_ABSTIME	1
#define S_IFMT		00170000
#define S_IFREG		0100000
#define S_IFCHR		0020000
#define EEXIST		17
#define E2BIG		7
#define PF_KTHREAD	0x00200000
#define SIGNAL_GROUP_EXIT	0x00000004	/* include/linux/sched/signal.h, since 2.6 */

/* Settings, written by userspace between open and load. */
const volatile __u32 cfg_ewma_w = 102;	/* 0.1 of RTSUP_EWMA_ONE */
const volatile __u64 cfg_period;	/* nominal period fallback, ns */
const volatile __u64 cfg_warmup;	/* defaults' warmup: until a rule's is applied */
const volatile __u32 cfg_rt;		/* --rt: every RT thread */
/* --rt without the policy hooks (rt_setsched): a new RT thread is found at its switch-in */
const volatile __u32 cfg_rt_at_switch;
const volatile __u32 cfg_cgroup;	/* --cgroup: match map cgroup */
const volatile __u32 cfg_ncomm;
const volatile __u32 cfg_record;	/* send every finished cycle (--record) */
const volatile __u32 cfg_follow;	/* -- CMD: child processes are targets too */
const volatile __u32 cfg_can_nif;	/* --can IFACE: how many; 0 = every CAN interface */
const volatile __u32 cfg_netns;		/* inode of rtsup-trace's network namespace */
const volatile __u32 cfg_canopen;	/* match CANopen SDO requests and responses */
/* per-syscall hooks: no hook saw every syscall, a block's is read at its switch-out */
const volatile __u32 cfg_sys_per;
/* bpf_task_pt_regs (5.15): a block's syscall read where it blocks (block_syscall) */
const volatile __u32 cfg_block_sys;
const volatile __s64 cfg_steal_off;	/* KVM's steal_time from a run queue (cpu_steal) */
const volatile char cfg_comms[RTSUP_MAX_COMMS][RTSUP_COMM_LEN];
const volatile __u32 cfg_stacks;	/* --stacks: enum rtsup_stacks */
const volatile __u32 cfg_stack_size = 8192;	/* --stack-size: DWARF bytes copied */
const volatile __u32 cfg_stack_any;	/* stacks for some thread: --stacks or a rule's */
const volatile __u32 cfg_stack_rules;	/* a rule gives stacks: look stack_cfg up */
const volatile __u32 cfg_stack_size_max = 8192;	/* room of a DWARF record: the largest size */
const volatile __u32 cfg_stack_budget = RTSUP_STACK_BUDGET;	/* per thread, interval */

/* Written by userspace while running. */
__u32 epoch;			/* flipped every interval */
__u32 thread_cfg_used;		/* a rule's settings may be in thread_cfg */
__s64 clock_off[16];		/* clock id -> its offset to CLOCK_MONOTONIC */
/* The tid bitmaps and their rules: include/rtsup.h */
__u64 tidmask[RTSUP_TIDMASK_WORDS];	/* may have an entry in threads */
__u64 wakemask[RTSUP_TIDMASK_WORDS];	/* its next wakeup time may be read */
/* The thread map's reads: the ring "moved" says which entries (threadread.h) */
__u32 threads_moved_seq;	/* moved at the start of each read (0: none yet, whole) */
__u32 threads_moved_lost;	/* a send failed: the next read walks the whole map */
__u32 threads_attrs_moved;	/* a task changed cgroups: the same, its tasks read too */
/* moves at each write of unsafe_sys: the collector walks that map only then */
__u32 unsafe_sys_gen;
/* The --can interfaces, followed by userspace when one comes back (can.h) */
struct rtsup_can_watch can_watch[RTSUP_CAN_WATCH];

/*
 * The full syscall programs the per-syscall stubs tail-call, one each:
 * the stubs are a few instructions to verify, the bodies are verified once.
 * The kernel keeps a tail call between programs of one attach type (fentry,
 * fexit) and one function prototype: a syscall with arguments has one
 * (__x64_sys_read(const struct pt_regs *regs)), one without has another
 * (its parameter is named __unused), so each has its arrays and bodies.
 */
#define SYS_BODY_ARRAY(name)							\
struct {									\
	__uint(type, BPF_MAP_TYPE_PROG_ARRAY);					\
	__uint(max_entries, 1);							\
	__type(key, __u32);							\
	__type(value, __u32);							\
} name SEC(".maps");
SYS_BODY_ARRAY(sys_in_body)
SYS_BODY_ARRAY(sys_out_body)
SYS_BODY_ARRAY(sys_in_body_z)
SYS_BODY_ARRAY(sys_out_body_z)

/* The thread map: tid -> its entry's slot in thread_mem (threadread.h). */
struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);	/* --max-threads */
	__type(key, __u32);
	__type(value, __u32);
} threads SEC(".maps");

/* The entries, read in place by the collector; sized as threads. */
struct {
	__uint(type, BPF_MAP_TYPE_ARRAY);
	__uint(map_flags, BPF_F_MMAPABLE);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);	/* --max-threads */
	__type(key, __u32);
	__type(value, struct rtsup_thread);
} thread_mem SEC(".maps");

/* The slots of thread_mem not in use; filled by userspace at load. */
struct {
	__uint(type, BPF_MAP_TYPE_QUEUE);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);	/* --max-threads */
	__type(value, __u32);
} thread_free SEC(".maps");

/*
 * One wait slot per CPU: the target waiting for that CPU, woken or
 * preempted (cause.h). Written at a target's wakeup by the waking CPU and
 * at every switch of the slot's CPU while armed: both hold that CPU's
 * run-queue lock. A plain array: its CPU's slot is one address.
 */
#define WHY_CPUS	512
struct why_slot why_cpu[WHY_CPUS][WHY_WAITERS];
_Static_assert(WHY_WAITERS == 2, "on_switch checks the two slots of its CPU");

struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, 1024);
	__type(key, __u32);
	__type(value, __u32);
} tgids SEC(".maps");

/*
 * Targets the full thread map could not hold, tid -> tgid: each is counted
 * once in RTSUP_C_MAP_FULL, not at each of its switch-ins. Userspace drops
 * the entries of threads that are gone, so a reused tid counts again.
 */
struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, RTSUP_UNTRACKED_MAX);
	__type(key, __u32);
	__type(value, __u32);
} untracked SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_ARRAY);
	__uint(max_entries, RTSUP_MAX_SYSCALLS);
	__type(key, __u32);
	__type(value, __u32);
} sysclass SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);	/* --max-threads */
	__type(key, __u32);
	__type(value, struct rtsup_thread_cfg);
} thread_cfg SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, 16384);
	__type(key, struct rtsup_sys_key);
	__type(value, __u64);
} unsafe_sys SEC(".maps");

/* A target's switch-in held on its CPU until its next event (cycle.h). */
struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, struct cycle_switch_rec);
} switch_rec SEC(".maps");

/* An all-zero thread entry to copy from: too big for the BPF stack. */
struct {
	__uint(type, BPF_MAP_TYPE_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, struct rtsup_thread);
} zero_thread SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, RTSUP_C_NR);
	__type(key, __u32);
	__type(value, __u64);
} counters SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_CGROUP_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, __u32);
} cgroup SEC(".maps");

/*
 * Rare events. A miss carries its cause (376 bytes an event): 2 MiB hold
 * about 5500, the seconds of a flood of misses on CPUs that RT threads
 * keep busy, while rtsup-trace waits for a CPU to read them.
 */
struct {
	__uint(type, BPF_MAP_TYPE_RINGBUF);
	__uint(max_entries, 2 * 1024 * 1024);
} events SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, 4096);	/* --can-max-ids */
	__type(key, struct rtsup_can_key);
	__type(value, struct rtsup_can_id);
} can_ids SEC(".maps");

/* Interfaces of other namespaces, or whose ifindex has no slot in can_if_slot. */
struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, 64);
	__type(key, struct rtsup_can_ifkey);
	__type(value, struct rtsup_can_if);
} can_ifs SEC(".maps");

/*
 * Per-interface counters by ifindex, for the small ifindexes CAN interfaces
 * have: a global array is a plain address, where a hash lookup per frame
 * (tx and its echo) cost as much as the rest of the accounting. Userspace
 * reads it through the skeleton's mapping of .bss. Slots are for the
 * interfaces of rtsup-trace's own network namespace.
 */
struct rtsup_can_if can_if_slot[RTSUP_CAN_IF_SLOTS];

/*
 * The task each CPU serves a softirq in, 0: none. Softirqs run in whatever
 * task was current (at irq exit, at local_bh_enable(); on PREEMPT_RT in the
 * task that enabled bottom halves again), and a CAN frame sent there is the
 * kernel's own: a BCM or ISO-TP timer, can-gw forwarding a received frame.
 */
struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, __u32);
} softirq_task SEC(".maps");

/* The frame each CPU has offered to a driver, until the driver answers. */
struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, struct rtsup_can_tx);
} can_tx_stash SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, struct rtsup_can_id);
} zero_can SEC(".maps");

/* Every finished cycle, only when recording; sized by userspace. */
struct {
	__uint(type, BPF_MAP_TYPE_RINGBUF);
	__uint(max_entries, 4096);
} cycles SEC(".maps");

/*
 * The tids of the entries hooks looked up since the collector's last read,
 * each once a read (threadread.h): 4096 threads fill 64 KiB of it at most
 * between two reads. Never wakes the loop: read at each sample. Sized by
 * userspace for --max-threads.
 */
struct {
	__uint(type, BPF_MAP_TYPE_RINGBUF);
	__uint(max_entries, 128 * 1024);
} moved SEC(".maps");

/* User stacks at RT-unsafe events (--stacks); sized by userspace when on. */
struct {
	__uint(type, BPF_MAP_TYPE_RINGBUF);
	__uint(max_entries, 4096);
} stacks SEC(".maps");

/* Stack records per thread in the interval: LRU, a dead thread's goes by itself. */
struct {
	__uint(type, BPF_MAP_TYPE_LRU_HASH);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);	/* --max-threads */
	__type(key, __u32);
	__type(value, struct rtsup_stack_budget);
} stack_budget SEC(".maps");

struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, RTSUP_STK_NR);
	__type(key, __u32);
	__type(value, __u64);
} stack_counters SEC(".maps");

/* A rule's unwinder for a thread (stackcfg.h); written by userspace only. */
struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);	/* --max-threads */
	__type(key, __u32);
	__type(value, struct rtsup_stack_cfg);
} stack_cfg SEC(".maps");

/* auto's verdict per process, tgid -> FP or DWARF (stackcfg.h); userspace's. */
struct {
	__uint(type, BPF_MAP_TYPE_HASH);
	__uint(max_entries, 1024);
	__type(key, __u32);
	__type(value, __u32);
} stack_auto SEC(".maps");

/* zero_mem - clear n bytes of a map value by copying the zero template */
static __always_inline void zero_mem(void *p, __u32 n)
{
	__u32 zero = 0;
	void *tmpl = bpf_map_lookup_elem(&zero_thread, &zero);

	if (tmpl && n <= sizeof(struct rtsup_thread))
		bpf_probe_read_kernel(p, n, tmpl);
}

/* CPUs whose steal counter's address is kept (cpu_steal); others read none */
#define STEAL_CPUS	1024

/* each CPU's steal counter's address, found at its first read; 0 = not yet */
__u64 steal_at[STEAL_CPUS];

/*
 * cpu_steal - this CPU's steal counter (KVM's steal_time.steal: what the
 * host ran instead of this vCPU, ns), for targets only (cause.h,
 * why_steal_in). It lies at cfg_steal_off (loader.c) from this CPU's run
 * queue, found once through the current task and checked against the CPU;
 * then one read. 0 where the kernel has none, or the run queue is not this
 * CPU's.
 */
static __always_inline __u64 cpu_steal(__u32 cpu)
{
	struct task_struct *task;
	__u64 steal = 0, at;
	struct rq *rq;

	if (!cfg_steal_off || cpu >= STEAL_CPUS)
		return 0;
	at = steal_at[cpu];
	if (!at) {
		task = (struct task_struct *)bpf_get_current_task();
		rq = BPF_CORE_READ(task, se.cfs_rq, rq);
		if (!rq || BPF_CORE_READ(rq, cpu) != (int)cpu)
			return 0;
		at = (__u64)rq + cfg_steal_off;
		steal_at[cpu] = at;
	}
	bpf_probe_read_kernel(&steal, sizeof(steal), (void *)at);
	return steal;
}

/* maybe_target - may this thread be in "threads"? No: return at once */
static __always_inline int maybe_target(__u32 tid)
{
	return tid_bit(tidmask, tid);
}

/* maybe_wake_read - may this target's wakeup be read? No: no lookup for it */
static __always_inline int maybe_wake_read(__u32 tid)
{
	return tid_bit(wakemask, tid);
}

/* note_wake - after an event: the wakemask bit follows cycle_wakeup_read() */
static __always_inline void note_wake(const struct rtsup_thread *t)
{
	wake_bit_sync(wakemask, t->tid, !t->exited && cycle_wakeup_read(t));
}

/*
 * moved_send - name the entry t of tid at slot in the ring "moved" for
 * read seq (threadread.h): once a read a thread, so out of line, not in
 * every hook
 */
static __noinline int moved_send(struct rtsup_thread *t, __u32 tid, __u32 slot, __u32 seq)
{
	struct rtsup_moved_rec r = { .tid = tid, .slot = slot };

	if (!t)
		return 0;
	if (bpf_ringbuf_output(&moved, &r, sizeof(r), BPF_RB_NO_WAKEUP))
		threads_moved_lost = 1;
	else
		t->moved_seq = seq;
	return 0;
}

/*
 * thread_entry - tid's entry, for a hook that may write it: its generation
 * moves (threadread.h). The only lookup of the thread map but thread_exists
 * and thread_add_entry.
 */
static __always_inline struct rtsup_thread *thread_entry(__u32 tid)
{
	__u32 *at = bpf_map_lookup_elem(&threads, &tid);
	__u32 seq = threads_moved_seq, slot;
	struct rtsup_thread *t;

	if (!at)
		return NULL;
	slot = *at;
	t = bpf_map_lookup_elem(&thread_mem, &slot);
	if (!t)
		return NULL;
	thread_touch(t);
	if (thread_moved_due(t->moved_seq, seq))
		moved_send(t, tid, slot, seq);
	return t;
}

/* thread_exists - tid has an entry; read only: its generation stays */
static __always_inline bool thread_exists(__u32 tid)
{
	return bpf_map_lookup_elem(&threads, &tid) != NULL;
}

/*
 * thread_add_entry - an entry for tid, a free slot of thread_mem set to
 * tmpl before the thread map names it (a hook that finds it finds it
 * whole): 0, -EEXIST when tid has one, -E2BIG when no slot is free (the
 * map is full), or the thread map's error (-EBUSY on PREEMPT_RT: add_thread)
 */
static __always_inline long thread_add_entry(__u32 tid, struct rtsup_thread *tmpl)
{
	__u32 slot;
	long err;

	if (thread_exists(tid))
		return -EEXIST;
	if (bpf_map_pop_elem(&thread_free, &slot))
		return -E2BIG;
	err = bpf_map_update_elem(&thread_mem, &slot, tmpl, BPF_ANY);
	if (!err)
		err = bpf_map_update_elem(&threads, &tid, &slot, BPF_NOEXIST);
	/* back where it was taken: the queue has room for every slot */
	if (err)
		bpf_map_push_elem(&thread_free, &slot, 0);
	return err;
}

/* lookup_thread - the thread's entry, NULL for every thread that is no target */
static __always_inline struct rtsup_thread *lookup_thread(__u32 tid)
{
	return maybe_target(tid) ? thread_entry(tid) : NULL;
}

/* count - bump one of our own counters */
static __always_inline void count(__u32 which)
{
	__u64 *c = bpf_map_lookup_elem(&counters, &which);

	if (c)
		(*c)++;
}

/* thread_cfg_of - a rule's settings for the thread; no lookup while no rule has any */
static __always_inline struct rtsup_thread_cfg *thread_cfg_of(__u32 tid)
{
	return thread_cfg_used ? bpf_map_lookup_elem(&thread_cfg, &tid) : NULL;
}

/* cfg - the state machine's settings for this event and thread */
static __always_inline struct cycle_cfg cfg(const struct rtsup_thread_cfg *tc)
{
	struct cycle_cfg c = {
		.ewma_w = tc && tc->ewma_w ? tc->ewma_w : cfg_ewma_w,
		.epoch = epoch,
		.period = tc && tc->period ? tc->period : cfg_period,
		.warmup = tc && tc->warmup ? tc->warmup : cfg_warmup,
	};
	return c;
}

/* in_list - is nr one of the first n entries of a short list? */
static __always_inline int in_list(const __u16 *list, __u32 n, __u32 max, __u32 nr)
{
	__u32 i;

	for (i = 0; i < max && i < n; i++)
		if (list[i] == nr)
			return 1;
	return 0;
}

/*
 * rb_wakeup - wake the loop for a record only when the buffer is a quarter
 * full; otherwise it reads the records at its next poll, 100 ms at most
 * away (COLLECTOR_POLL_MAX_MS). Woken for each, a storm of 10 000 threads
 * a second cost the loop ~14 000 wakeups a second and half its CPU, and
 * each wakeup was paid on the CPU of the thread that had the event.
 */
static __always_inline __u64 rb_wakeup(void *rb)
{
	__u64 quarter = bpf_ringbuf_query(rb, BPF_RB_RING_SIZE) / 4;

	if (bpf_ringbuf_query(rb, BPF_RB_AVAIL_DATA) >= quarter)
		return BPF_RB_FORCE_WAKEUP;
	return BPF_RB_NO_WAKEUP;
}

/*
 * ev_wakeup - an event's wakeup: a new process's now when stacks are on
 * (the unwinder reads its mappings while the process is there), the
 * others as rb_wakeup says
 */
static __always_inline __u64 ev_wakeup(__u32 type)
{
	if (type == RTSUP_EV_NEW && cfg_stack_any)
		return BPF_RB_FORCE_WAKEUP;
	return rb_wakeup(&events);
}

/* record_cycle - one finished cycle for --record; a full buffer is counted */
static __always_inline void record_cycle(struct rtsup_thread *t, const struct rtsup_cycle *c)
{
	struct rtsup_cycle_rec *r;

	if (!cfg_record)
		return;
	r = bpf_ringbuf_reserve(&cycles, sizeof(*r), 0);
	if (!r) {
		count(RTSUP_C_CYC_DROPS);
		return;
	}
	r->tid = t->tid;
	r->tgid = t->tgid;
	r->resets = t->resets;
	r->pad = 0;
	r->c = *c;
	bpf_ringbuf_submit(r, rb_wakeup(&cycles));
}

/* event_new - a rare event reserved and filled but for its cause; NULL when full */
static __always_inline struct rtsup_event *event_new(__u32 type, struct rtsup_thread *t,
						     __u64 now, __u64 arg, __u64 arg2)
{
	struct rtsup_event *e = bpf_ringbuf_reserve(&events, sizeof(*e), 0);

	if (!e) {
		count(RTSUP_C_RB_DROPS);
		return NULL;
	}
	e->ts = now;
	e->type = type;
	e->tid = t->tid;
	e->tgid = t->tgid;
	e->cpu = bpf_get_smp_processor_id();
	e->arg = arg;
	e->arg2 = arg2;
	__builtin_memcpy(e->comm, t->comm, sizeof(e->comm));
	return e;
}

/* emit - send one rare event; a full ring buffer is counted, not hidden */
static __always_inline void emit(__u32 type, struct rtsup_thread *t, __u64 now,
				 __u64 arg, __u64 arg2)
{
	struct rtsup_event *e = event_new(type, t, now, arg, arg2);

	if (!e)
		return;
	__builtin_memset(&e->cause, 0, sizeof(e->cause));
	bpf_ringbuf_submit(e, ev_wakeup(type));
}

/* count_stk - bump one of the stack records' counters */
static __always_inline void count_stk(__u32 which)
{
	__u64 *c = bpf_map_lookup_elem(&stack_counters, &which);

	if (c)
		(*c)++;
}

/* stack_budget_take - may the thread send one more stack this interval? */
static __always_inline int stack_budget_take(__u32 tid)
{
	struct rtsup_stack_budget *b = bpf_map_lookup_elem(&stack_budget, &tid), nb;

	if (!b) {
		nb.epoch = epoch;
		nb.n = 1;
		bpf_map_update_elem(&stack_budget, &tid, &nb, BPF_ANY);
		return 1;
	}
	if (b->epoch != epoch) {
		b->epoch = epoch;
		b->n = 0;
	}
	if (b->n >= cfg_stack_budget)
		return 0;
	b->n++;
	return 1;
}

/*
 * copy_regs - the user registers in DWARF numbering (libdwfl's order):
 * x86_64 rax rdx rcx rbx rsi rdi rbp rsp r8-r15 rip; arm64 x0-x30 sp pc
 */
static __always_inline __u64 copy_regs(__u64 *out, struct pt_regs *kregs)
{
#if defined(__TARGET_ARCH_x86)
	struct pt_regs r;

	if (bpf_probe_read_kernel(&r, sizeof(r), kregs))
		return 0;
	out[0] = r.ax; out[1] = r.dx; out[2] = r.cx; out[3] = r.bx;
	out[4] = r.si; out[5] = r.di; out[6] = r.bp; out[7] = r.sp;
	out[8] = r.r8; out[9] = r.r9; out[10] = r.r10; out[11] = r.r11;
	out[12] = r.r12; out[13] = r.r13; out[14] = r.r14; out[15] = r.r15;
	out[16] = r.ip;
	return r.sp;
#elif defined(__TARGET_ARCH_arm64)
	/* straight into the record: arm64's pt_regs would not fit the BPF stack */
	if (bpf_probe_read_kernel(out, 31 * sizeof(__u64), &kregs->regs[0]) ||
	    bpf_probe_read_kernel(&out[31], sizeof(__u64), &kregs->sp) ||
	    bpf_probe_read_kernel(&out[32], sizeof(__u64), &kregs->pc))
		return 0;
	return out[31];
#else
	return 0;
#endif
}

/*
 * dump_stack - the top of the user stack from sp: the whole size, or half
 * of it, and so on, where the stack's end is nearer (a main thread)
 */
static __always_inline __u32 dump_stack(void *dst, __u64 sp, __u32 size)
{
	/* 64 bits: a 32-bit value's zero-extension would lose the bound checked below */
	__u64 len = stack_dump_size(size, cfg_stack_size_max);
	__u32 i;

	for (i = 0; i < 5; i++, len >>= 1) {
		/* the bound again, on the register passed: the verifier's proof of the room */
		barrier_var(len);
		if (len && len <= cfg_stack_size_max && !bpf_probe_read_user(dst, len, (void *)sp))
			return len;
	}
	return 0;
}

/*
 * stack_choice - the thread's unwinder and size (stackcfg.h): its rule's,
 * else --stacks; auto by its process's verdict
 */
static __always_inline struct rtsup_stack_cfg stack_choice(const struct rtsup_thread *t)
{
	struct rtsup_stack_cfg c = stack_rule(cfg_stacks, cfg_stack_size, cfg_stack_rules ?
					      bpf_map_lookup_elem(&stack_cfg, &t->tid) : NULL);

	if (c.kind == RTSUP_STACKS_AUTO)
		c.kind = stack_auto_kind(bpf_map_lookup_elem(&stack_auto, &t->tgid));
	return c;
}

/* stack_rec_head - a stack record's header; the task is the current one */
static __always_inline void stack_rec_head(struct rtsup_stack_rec *r, const struct rtsup_thread *t,
					   struct task_struct *task, __u64 now, __u32 reason,
					   __u32 nr, __u32 kind)
{
	r->ts = now;
	r->tid = t->tid;
	r->tgid = t->tgid;
	r->reason = reason;
	r->nr = nr;
	r->kind = kind;
	r->nips = 0;
	r->dump_len = 0;
	r->sp = 0;
	r->exec_id = BPF_CORE_READ(task, self_exec_id);
}

/*
 * capture_dwarf, capture_fp - one record of each kind, each with its own
 * reservation (its size must be a constant: every DWARF record has the
 * largest room), so that the verifier sees the room where it is used
 */
static __always_inline void capture_dwarf(const struct rtsup_thread *t, __u64 now, __u32 reason,
					  __u32 nr, __u32 size)
{
	struct task_struct *task = bpf_get_current_task_btf();
	struct rtsup_stack_rec *r;

	r = bpf_ringbuf_reserve(&stacks, sizeof(*r) + cfg_stack_size_max, 0);
	if (!r) {
		count_stk(RTSUP_STK_LOST);
		return;
	}
	stack_rec_head(r, t, task, now, reason, nr, RTSUP_STACKS_DWARF);
	r->sp = copy_regs(r->regs, (struct pt_regs *)bpf_task_pt_regs(task));
	if (r->sp)
		r->dump_len = dump_stack(r + 1, r->sp, size);
	if (!r->dump_len)
		count_stk(RTSUP_STK_NO_STACK);
	bpf_ringbuf_submit(r, 0);
}

static __always_inline void capture_fp(const struct rtsup_thread *t, __u64 now, __u32 reason,
				       __u32 nr)
{
	struct task_struct *task = bpf_get_current_task_btf();
	struct rtsup_stack_rec *r;
	long n;

	r = bpf_ringbuf_reserve(&stacks, sizeof(*r), 0);
	if (!r) {
		count_stk(RTSUP_STK_LOST);
		return;
	}
	stack_rec_head(r, t, task, now, reason, nr, RTSUP_STACKS_FP);
	n = bpf_get_task_stack(task, r->ips, sizeof(r->ips), BPF_F_USER_STACK);
	r->nips = n > 0 ? n / sizeof(__u64) : 0;
	if (!r->nips)
		count_stk(RTSUP_STK_NO_STACK);
	bpf_ringbuf_submit(r, 0);
}

/*
 * capture_stack - the current target's user stack at an RT-unsafe event.
 * Only here, never on a clean cycle's path; beyond the thread's budget in
 * the interval or with a full ring buffer, counted instead.
 */
static __always_inline void capture_stack(struct rtsup_thread *t, __u64 now, __u32 reason,
					  __u32 nr)
{
	struct rtsup_stack_cfg sc;

	if (!cfg_stack_any)
		return;
	sc = stack_choice(t);
	if (sc.kind != RTSUP_STACKS_FP && sc.kind != RTSUP_STACKS_DWARF)
		return;
	if (!stack_budget_take(t->tid)) {
		count_stk(RTSUP_STK_OVER_BUDGET);
		return;
	}
	if (sc.kind == RTSUP_STACKS_DWARF)
		capture_dwarf(t, now, reason, nr, sc.size);
	else
		capture_fp(t, now, reason, nr);
}

/* emit_miss - a deadline miss with its cause (why_delim) */
static __always_inline void emit_miss(struct rtsup_thread *t, __u64 now, __u64 lateness,
				      __u64 exec)
{
	struct rtsup_event *e = event_new(RTSUP_EV_MISS, t, now, lateness, exec);

	if (!e)
		return;
	__builtin_memcpy(&e->cause, &t->why.out, sizeof(e->cause));
	bpf_ringbuf_submit(e, ev_wakeup(RTSUP_EV_MISS));
}

/* who_fill - name a task in a cause; the idle task is tid 0 and no more */
static __always_inline void who_fill(struct rtsup_who *w, struct task_struct *p, const int btf)
{
	w->tid = TREAD(btf, p, pid);
	if (!w->tid) {
		/* a clean release on an idle CPU: no name to read */
		why_who_clear(w);
		return;
	}
	w->tgid = TREAD(btf, p, tgid);
	w->policy = TREAD(btf, p, policy);
	w->prio = why_rt(w->policy) ? (__s32)TREAD(btf, p, rt_priority) :
				      (__s32)TREAD(btf, p, static_prio) - 120;
	bpf_probe_read_kernel(w->comm, sizeof(w->comm), &p->comm);
}

/* why_slot_of - the WHY_WAITERS wait slots of a CPU, NULL past the array */
static __always_inline struct why_slot *why_slot_of(__u32 cpu)
{
	if (cpu >= WHY_CPUS)
		return NULL;
	/* the mask bounds the index for the verifier, whatever clang kept */
	barrier_var(cpu);
	return why_cpu[cpu & (WHY_CPUS - 1)];
}

/*
 * why_settle - the thread runs after a wait on this CPU: fold the wait into
 * its cycle (cause.h). At each of its events, as settle() for the switch-in.
 */
static __always_inline void why_settle(struct rtsup_thread *t)
{
	__u32 i, cpu = bpf_get_smp_processor_id();
	struct why_slot *s = why_slot_of(cpu);

	if (!s)
		return;
	for (i = 0; i < WHY_WAITERS; i++) {
		if (s[i].tid != t->tid || !(s[i].state & WHY_RAN))
			continue;
		why_take(&t->why, &t->cs, &s[i], cpu);
		s[i].tid = 0;
	}
}

/* why_wakeup - a target is woken: it waits for its CPU from now (cause.h) */
static __always_inline void why_wakeup(struct task_struct *p, __u32 tid, __u64 now,
				       const int btf)
{
	struct why_slot *s = why_slot_of(TREAD(btf, p, thread_info.cpu));
	int i;

	if (!s)
		return;
	i = why_pick(s, tid, now);
	if (i < 0 || i >= WHY_WAITERS) {
		count(RTSUP_C_WHY_BUSY);
		return;
	}
	s += i;
	why_arm(s, tid, WHY_WOKEN, now);
	s->policy = TREAD(btf, p, policy);
	s->prio = why_rt(s->policy) ? (__s32)TREAD(btf, p, rt_priority) : 0;
	who_fill(&s->waker, CURRENT(btf), btf);
}

/*
 * why_switch - a switch on a CPU where a target waits: prev held the CPU
 * since the last switch (cause.h). Only while a target waits here.
 */
static __always_inline void why_switch(struct why_slot *s, struct task_struct *prev,
				       __u32 prev_tid, __u32 next_tid, const int btf)
{
	__u64 now = bpf_ktime_get_ns();

	if (why_stale(s, now)) {
		s->tid = 0;
		return;
	}
	if (why_switch_holder(s, prev_tid, next_tid, now))
		who_fill(&s->top, prev, btf);
}

/* comm_match - is this name one of the --comm targets? */
static __always_inline int comm_match(const char *comm)
{
	__u32 i, j;

	for (i = 0; i < RTSUP_MAX_COMMS && i < cfg_ncomm; i++) {
		for (j = 0; j < RTSUP_COMM_LEN; j++) {
			if (comm[j] != cfg_comms[i][j])
				break;
			if (!comm[j])
				return 1;
		}
		if (j == RTSUP_COMM_LEN)
			return 1;
	}
	return 0;
}

/* add_thread - start tracking a task; NULL when the map is full */
static __always_inline struct rtsup_thread *add_thread(struct task_struct *task,
							__u64 now)
{
	__u32 tid = BPF_CORE_READ(task, pid), zero = 0, tgid;
	struct rtsup_thread *tmpl, *t;
	long err;

	tmpl = bpf_map_lookup_elem(&zero_thread, &zero);
	if (!tmpl)
		return NULL;
	tid_mark_new(tidmask, wakemask, tid);
	err = thread_add_entry(tid, tmpl);
	/*
	 * The entry may be there whatever the error: -EEXIST, or -EBUSY on
	 * PREEMPT_RT, where a program preempted inside an update of this map
	 * holds its bucket lock slot on this CPU. Untracked only without one.
	 */
	t = thread_entry(tid);
	if (!t) {
		/* a thread, once: --rt at switch-ins tries again at every one */
		tgid = BPF_CORE_READ(task, tgid);
		if (!bpf_map_update_elem(&untracked, &tid, &tgid, BPF_NOEXIST))
			count(RTSUP_C_MAP_FULL);
		return NULL;
	}
	if (err) {
		/*
		 * Every caller has a live task: an entry of a thread that exited
		 * (not reaped yet) belongs to a new thread that reuses the tid,
		 * one that left RT (rtfollow.h) is followed again. It starts as
		 * new, with its own first_seen (userspace's check).
		 */
		if (!rt_entry_stale(t))
			return t;
		zero_mem(t, sizeof(*t));
	}
	cycle_thread_init(t, tid, BPF_CORE_READ(task, tgid), now);
	bpf_probe_read_kernel_str(t->comm, sizeof(t->comm), &task->comm);
	count(RTSUP_C_NEW);
	emit(RTSUP_EV_NEW, t, now, 0, 0);
	return t;
}

/* count_sys - add to a thread's count of one unsafe syscall */
static __always_inline void count_sys(struct rtsup_thread *t, __u32 nr, __u64 n)
{
	struct rtsup_sys_key k = { .tid = t->tid, .nr = nr, .mode = cycle_sys_mode(&t->cs) };
	__u64 *cnt = bpf_map_lookup_elem(&unsafe_sys, &k);

	if (cnt)
		__sync_fetch_and_add(cnt, n);
	else if (bpf_map_update_elem(&unsafe_sys, &k, &n, BPF_NOEXIST))
		count(RTSUP_C_SYS_FULL);
	/* after the write: a walk that saw the new value sees the count */
	__sync_fetch_and_add(&unsafe_sys_gen, 1);
}

/* flush_sys - the finished cycle's unsafe syscalls, by number */
static __always_inline void flush_sys(struct rtsup_thread *t)
{
	__u32 i;

	for (i = 0; i < RTSUP_PEND_SYS; i++) {
		if (t->cs.pend_cnt[i])
			count_sys(t, t->cs.pend_nr[i], t->cs.pend_cnt[i]);
		t->cs.pend_cnt[i] = 0;
	}
}

/* emit_cycle - what follows a finished cycle: counts, record, rare events */
static __always_inline void emit_cycle(__u32 ev, struct rtsup_thread *t, __u64 now,
				       const struct rtsup_cycle *c, __u64 lateness)
{
	flush_sys(t);
	record_cycle(t, c);
	if (ev & CYC_EV_MISS)
		emit_miss(t, now, lateness, c->exec);
	if (!(ev & CYC_EV_FAULTS))
		return;
	if (c->minflt)
		emit(RTSUP_EV_UNSAFE, t, now, RTSUP_U_MINFLT, c->minflt);
	if (c->majflt)
		emit(RTSUP_EV_UNSAFE, t, now, RTSUP_U_MAJFLT, c->majflt);
}

/* fd_is_file_or_tty - does fd of the current task name a file or a tty? */
static __always_inline int fd_is_file_or_tty(struct task_struct *task, __u64 fd)
{
	struct fdtable *fdt = BPF_CORE_READ(task, files, fdt);
	struct file **fds, *f = NULL;
	__u32 mode, major;

	if (!fdt || fd >= BPF_CORE_READ(fdt, max_fds))
		return 0;
	fds = BPF_CORE_READ(fdt, fd);
	if (bpf_probe_read_kernel(&f, sizeof(f), &fds[fd]) || !f)
		return 0;
	mode = BPF_CORE_READ(f, f_inode, i_mode);
	if ((mode & S_IFMT) == S_IFREG)
		return 1;
	if ((mode & S_IFMT) != S_IFCHR)
		return 0;
	/* ttys, the console and pseudo-terminals (devices.txt) */
	major = BPF_CORE_READ(f, f_inode, i_rdev) >> 20;
	return major == 4 || major == 5 || (major >= 136 && major <= 143);
}

/* clock_off_of - offset to CLOCK_MONOTONIC of a clock id (userspace writes them) */
static __always_inline __s64 clock_off_of(__u64 clk)
{
	return clock_off[clk & 15];
}

/*
 * sleep_release - requested release of a sleep syscall, 0 if unknown; an
 * absolute one's clock and the offset it was converted with go to t's
 * cycle state (cycle_sleep_clock), here: kept out of on_sys_enter's
 * locals, which the verifier would carry through every path after
 */
static __always_inline __u64 sleep_release(struct rtsup_thread *t, __u64 a1, __u64 a2,
					   __u64 a3, __u32 cls, __u64 now, int *absolute)
{
	struct __kernel_timespec ts;
	void *req;
	__u64 clk = 0, flags = 0, ns;
	__s64 off;

	cycle_sleep_clock(&t->cs, 0, 0, 0);
	if (cls & RTSUP_SC_ABSSLEEP) {
		clk = a1;
		flags = a2;
		req = (void *)a3;
	} else if (cls & RTSUP_SC_RELSLEEP) {
		req = (void *)a1;
	} else {
		return 0;
	}
	if (bpf_probe_read_user(&ts, sizeof(ts), req))
		return 0;
	ns = ts.tv_sec * 1000000000ULL + ts.tv_nsec;
	if (!(flags & TIMER_ABSTIME))
		return now + ns;
	*absolute = 1;
	off = clock_off_of(clk);
	cycle_sleep_clock(&t->cs, 1, clk & 15, off);
	return ns - off;
}

/*
 * wait_key - what a keyed delimiter waits on: its first argument (fd,
 * futex word, pollfd array) with the syscall, and a futex's operation.
 */
static __always_inline __u64 wait_key(struct pt_regs *regs, __u32 nr, __u32 cls,
				      const int btf)
{
	__u64 key = SYSARG(btf, regs, 1) ^ ((__u64)nr << 48);

	if (cls & RTSUP_SC_OPKEY)
		key ^= (SYSARG(btf, regs, 2) & 0x7f) << 56;
	return key | 1ULL << 63;	/* never 0, fd 0 included */
}

/*
 * held_for - is the record holding tid's switch-in? What it holds is the
 * switch-in of the thread that came on this CPU last, until that thread's
 * next event here settles it: at a sched_switch, its tid is 0 or prev's.
 * Only a sched_switch that went unseen (docs/design.md) leaves another's:
 * the next hold replaces it, or that thread's next event here applies it.
 */
static __always_inline int held_for(const struct cycle_switch_rec *r, __u32 tid)
{
	return r && r->tid == tid;
}

/* held_switch_in - this CPU's held switch-in record */
static __always_inline struct cycle_switch_rec *held_switch_in(void)
{
	__u32 zero = 0;

	return bpf_map_lookup_elem(&switch_rec, &zero);
}

/* settle - apply a switch-in held on this CPU for the thread, first thing */
static __always_inline void settle(struct rtsup_thread *t, struct cycle_switch_rec *r)
{
	/* cycle_settle leaves the record's time and CPU as they were */
	if (r && r->tid == t->tid) {
		why_steal_in(&t->why, r->cpu, r->steal);
		if (cycle_settle(t, r) & CYC_EV_MIGRATE)
			emit(RTSUP_EV_UNSAFE, t, r->now, RTSUP_U_MIGRATE,
			     why_migrated(&t->why, r->cpu));
	}
	why_settle(t);
}

/*
 * on_cpu - the current thread is in a syscall of its own on this CPU, its
 * held switch-in settled: a move no switch-in showed (cycle_on_cpu). Before
 * running(): a move while off CPU is not its next activation's.
 */
static __always_inline void on_cpu(struct rtsup_thread *t, __u64 now)
{
	__u32 cpu = bpf_get_smp_processor_id();

	if (cycle_on_cpu(t, cpu) & CYC_EV_MIGRATE)
		emit(RTSUP_EV_UNSAFE, t, now, RTSUP_U_MIGRATE, why_migrated(&t->why, cpu));
}

/* running - the current thread is in a syscall of its own: it has a CPU */
static __always_inline void running(struct rtsup_thread *t, __u64 now, const int btf)
{
	struct task_struct *task;

	/* rare: an activation whose switch-in no hook saw (cycle.h) */
	if (!cycle_switch_in_unseen(t))
		return;
	task = CURRENT(btf);
	cycle_running(t, now, TREAD(btf, task, min_flt), TREAD(btf, task, maj_flt));
}

/*
 * compat_syscall - is the syscall being entered a 32-bit one (ia32 on
 * x86_64, arm32 on arm64)? Its numbers are another table's: classified with
 * ours, clock_nanosleep would be readlinkat. Such syscalls are counted, not
 * classified (docs/cycle-model.md).
 */
static __always_inline int compat_syscall(struct task_struct *task, const int btf)
{
#if defined(__TARGET_ARCH_x86)
	return (TREAD(btf, task, thread_info.status) & 0x0002) != 0;	/* TS_COMPAT */
#elif defined(__TARGET_ARCH_arm64)
	return (TREAD(btf, task, thread_info.flags) & (1UL << 22)) != 0;	/* TIF_32BIT */
#else
	return 0;
#endif
}

/* the inputs of delim_cycle, one object: a global function takes five arguments */
struct delim_in {
	struct cycle_cfg cf;
	__u64 now, expected, minflt, majflt;
	__u64 absolute;
	__u64 late;	/* the entry of a sleep taken late (cycle_late_entry): its own time */
};

/*
 * The cycle a delimiter closed, per CPU, from delim_cycle to its caller: a
 * map value, whose contents the verifier never assumes (a stack object
 * written by a global function may keep what it held before the call, in
 * the verifier's view). Only the sys_enter programs use it. On
 * raw_syscalls the kernel never runs one twice at once on a CPU; the
 * per-syscall bodies run preemptible, from many stubs, so a target
 * preempted between delim_cycle and its reads here by another target that
 * enters a delimiter on another syscall, on this CPU, would read that one's
 * cycle. Not seen, not mended (docs/design.md, "Runs the kernel skips").
 */
struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, struct rtsup_cycle);
} delim_out SEC(".maps");

/*
 * delim_cycle - the cycle state machine at a delimiter (cycle.h). A global
 * function, which the verifier checks once on its own: inlined, each of
 * its paths went on through why_delim and emit_cycle (437 815
 * instructions verified, 0.5 s at every start on a PC, 5 s in an emulated
 * guest; docs/performance.md, "Start-up").
 */
__noinline int delim_cycle(struct rtsup_thread *t, const struct delim_in *in,
			   struct rtsup_cycle *c)
{
	__u32 ev;

	if (!t || !in || !c)
		return 0;
	/* cycle_late_entry, its close the one copy of cycle_delim_enter */
	if (in->late)
		cycle_late_swap(&t->cs);
	ev = cycle_delim_enter(t, &in->cf, in->now, in->expected, in->absolute,
			       in->minflt, in->majflt, c);
	if (in->late)
		cycle_late_restore(&t->cs);
	return ev;
}

/*
 * delim_of - is syscall nr (class cls, args in regs) the thread's delimiter?
 * Then *expected and *absolute are its requested release (sleep_release).
 */
static __always_inline int delim_of(struct rtsup_thread *t, const struct rtsup_thread_cfg *tc,
				    struct pt_regs *regs, __u32 nr, __u32 cls, __u64 now,
				    __u64 *expected, int *absolute, const int btf)
{
	int delim;

	if (tc && tc->ndelims)
		delim = in_list(tc->delims, tc->ndelims, RTSUP_CFG_DELIMS, nr);
	else
		delim = cls & RTSUP_SC_DELIM;
	if (delim) {
		/* the kernel's restart (below) keeps the interrupted sleep's clock */
		*expected = sleep_release(t, SYSARG(btf, regs, 1), SYSARG(btf, regs, 2),
					  SYSARG(btf, regs, 3), cls, now, absolute);
		/* a relative sleep inside an absolute loop is no boundary */
		if (cycle_rel_sleep_in_loop(t, cls, *absolute))
			delim = 0;
		else if (cls & RTSUP_SC_KEYED)
			delim = cycle_delim_key(&t->cs, wait_key(regs, nr, cls, btf));
		else
			t->cs.cand_key = 0;
	} else if ((cls & RTSUP_SC_RESTART) && (t->cs.flags & RTSUP_CS_INTR)) {
		/* the kernel resumes the interrupted sleep with its own arguments */
		delim = 1;
		*absolute = t->cs.abs_expected != 0;
		*expected = *absolute ? t->cs.abs_expected : t->cs.expected;
	}
	return delim;
}

/* on_sys_enter - cycle delimiter or a syscall inside a cycle */
static __always_inline int on_sys_enter(struct pt_regs *regs, long id, const int btf)
{
	__u32 tid = (__u32)bpf_get_current_pid_tgid();
	struct rtsup_thread *t = lookup_thread(tid);
	struct rtsup_thread_cfg *tc;
	struct task_struct *task;
	__u32 nr, *cls, ev;
	__u64 now, expected = 0;
	int unsafe, absolute = 0, delim;

	if (!t || t->exited)
		return 0;
	settle(t, held_switch_in());
	now = bpf_ktime_get_ns();
	on_cpu(t, now);
	running(t, now, btf);
	if (id < 0 || id >= RTSUP_MAX_SYSCALLS)
		return 0;
	nr = id;
	cls = bpf_map_lookup_elem(&sysclass, &nr);
	if (!cls)
		return 0;
	task = CURRENT(btf);
	if (compat_syscall(task, btf)) {
		t->compat_sys++;
		return 0;
	}
	/* a syscall of a thread still in its delimiter: that one returned unseen */
	if (cfg_sys_per && cycle_exit_missed(t, TREAD(btf, task, min_flt),
					     TREAD(btf, task, maj_flt)))
		count(RTSUP_C_DELIM_UNSEEN);
	tc = thread_cfg_of(tid);
	delim = delim_of(t, tc, regs, nr, *cls, now, &expected, &absolute, btf);
	/* what a sleep whose entry goes unseen is told by (cycle_entry_skipped) */
	if (cfg_sys_per)
		cycle_sys_seen(&t->cs, nr, delim);
	if (delim) {
		struct delim_in in = {
			.cf = cfg(tc), .now = now, .expected = expected, .absolute = absolute,
			.minflt = TREAD(btf, task, min_flt), .majflt = TREAD(btf, task, maj_flt),
		};
		__u32 zero = 0, cpu = bpf_get_smp_processor_id();
		__u64 steal = cpu_steal(cpu);
		struct rtsup_cycle *c = bpf_map_lookup_elem(&delim_out, &zero);

		if (!c)
			return 0;	/* an array's one entry: never */
		ev = delim_cycle(t, &in, c);
		/* what was stolen up to here is the closing cycle's; the next starts now */
		why_steal_out(&t->why, cpu, steal);
		why_delim(&t->why, ev, ev & CYC_EV_CLOSED ? c->cpu : 0,
			  ev & CYC_EV_CLOSED ? c->nominal : 0, now, expected);
		why_steal_in(&t->why, cpu, steal);
		note_wake(t);
		if (ev & CYC_EV_CLOSED)
			emit_cycle(ev, t, now, c, now - expected);
		return 0;
	}
	unsafe = *cls & RTSUP_SC_UNSAFE;
	if (tc && unsafe && in_list(tc->allow, tc->nallow, RTSUP_CFG_SYSCALLS, nr))
		unsafe = 0;
	else if (tc && !unsafe && in_list(tc->forbid, tc->nforbid, RTSUP_CFG_SYSCALLS, nr))
		unsafe = 1;
	if (unsafe && (*cls & RTSUP_SC_FDCHECK))
		unsafe = fd_is_file_or_tty(task, SYSARG(btf, regs, 1));
	/* what a block inside the cycle waits in (cause.h), where block_syscall cannot say */
	if (!cfg_block_sys)
		why_syscall(&t->why, nr,
			    *cls & RTSUP_SC_OPKEY ? (SYSARG(btf, regs, 2) & 0x7f) + 1 : 0);
	ev = cycle_syscall(t, unsafe);
	if (ev & CYC_EV_UNSAFE) {
		/* by number at the cycle's end, like the other counts */
		if (cycle_pend_sys(&t->cs, nr))
			count_sys(t, nr, 1);
		capture_stack(t, now, RTSUP_U_SYSCALL, nr);
		/* a signal handler's, unless the thread does not resume its wait */
		if (!(t->cs.flags & RTSUP_CS_INTR))
			emit(RTSUP_EV_UNSAFE, t, now, RTSUP_U_SYSCALL, nr);
	}
	return 0;
}

/* late_close's input: the returning syscall's number and first arguments */
struct late_in {
	__u64 a1, a2, a3;
	__u32 nr, pad;
};

/*
 * late_close - per-syscall hooks: the delimiter whose entry went unseen
 * returns; its sleep was taken for the entry (cycle_entry_skipped), whose
 * cycle closes now at that sleep's time, with the requested release read
 * from the arguments it still has. A relative sleep inside an absolute
 * loop is no boundary: it slept inside the cycle, a block counted now (a
 * keyed delimiter's key is not looked at). A global function, verified
 * once on its own: inlined in the exit body, 6.1's verifier walked its
 * paths through the rest of the body, 6 450 more instructions, over the
 * bound of the whole set (test_per_syscall_hooks_count_exactly...).
 */
__noinline int late_close(struct rtsup_thread *t, const struct late_in *li)
{
	__u32 nr, *cls, zero = 0, ev;
	struct rtsup_cycle *c;
	__u64 expected, at;
	int absolute = 0;

	if (!t || !li)
		return 0;
	nr = li->nr;
	at = t->cs.late_ts;
	cls = bpf_map_lookup_elem(&sysclass, &nr);
	c = bpf_map_lookup_elem(&delim_out, &zero);
	if (!cls || !c)
		return 0;	/* it stays unclosed: cycle_delim_exit drops it */
	expected = sleep_release(t, li->a1, li->a2, li->a3, *cls, at, &absolute);
	if (cycle_rel_sleep_in_loop(t, *cls, absolute)) {
		cycle_late_block(t);
		emit(RTSUP_EV_UNSAFE, t, at, RTSUP_U_BLOCK, t->cs.delim_sys);
		return 0;
	}
	struct delim_in in = { .cf = cfg(thread_cfg_of(t->tid)), .now = at,
			       .expected = expected, .absolute = absolute, .late = 1,
			       .minflt = t->cs.late_minflt, .majflt = t->cs.late_majflt };

	ev = delim_cycle(t, &in, c);
	count(RTSUP_C_DELIM_UNSEEN);
	if (!(ev & CYC_EV_CLOSED))
		return 0;
	/* emit_cycle but a miss's event: a delimiter that slept was not late */
	flush_sys(t);
	record_cycle(t, c);
	if (c->minflt)
		emit(RTSUP_EV_UNSAFE, t, at, RTSUP_U_MINFLT, c->minflt);
	if (c->majflt)
		emit(RTSUP_EV_UNSAFE, t, at, RTSUP_U_MAJFLT, c->majflt);
	return 0;
}

/*
 * on_sys_exit - the delimiter returns: a new cycle is released. 'late':
 * the per-syscall exit body, which closes a cycle whose delimiter entry
 * went unseen (late_close); regs are the syscall's there.
 */
static __always_inline int on_sys_exit(struct pt_regs *regs, long ret, const int btf,
				       const int late)
{
	__u32 tid = (__u32)bpf_get_current_pid_tgid();
	struct rtsup_thread *t = lookup_thread(tid);
	struct task_struct *task;
	int intr;

	if (!t)
		return 0;
	/* the exit is the first event of a thread switched in unseen */
	if (cycle_switch_in_unseen(t)) {
		__u64 now = bpf_ktime_get_ns();

		settle(t, held_switch_in());
		on_cpu(t, now);
		running(t, now, btf);
	}
	if (late)
		t->cs.cur_sys = 0;
	if (!t->cs.in_delim)
		return 0;
	settle(t, held_switch_in());
	/* moved while it slept: no cycle's move, but its CPU from here on */
	on_cpu(t, 0);
	if (late && (t->cs.flags & RTSUP_CS_ENTRY_LATE)) {
		struct late_in li = { .nr = SYSCALL_NR(regs), .a1 = SYSARG(btf, regs, 1),
				      .a2 = SYSARG(btf, regs, 2), .a3 = SYSARG(btf, regs, 3) };

		late_close(t, &li);
	}
	if (!t->cs.in_delim)
		return 0;	/* no boundary after all */
	task = CURRENT(btf);
	/* a step of the sleep's clock (date -s, NTP) moved its release */
	if (t->cs.clk)
		cycle_clock_at_exit(&t->cs, clock_off_of(t->cs.clk - 1));
	/* a delimiter that slept was released at its switch-in (no clock), unless woken before its release */
	intr = cycle_ret_interrupted(ret);
	cycle_delim_exit(t, cycle_delim_exit_timed(t, intr) ? bpf_ktime_get_ns() : 0, intr,
			 TREAD(btf, task, min_flt), TREAD(btf, task, maj_flt));
	note_wake(t);
	return 0;
}

/*
 * settle_prev - prev leaves the CPU: a switch-in held for it is applied now,
 * or dropped with it. Returns prev's entry (NULL: no target) and, in *r,
 * this CPU's record once looked up.
 */
static __always_inline struct rtsup_thread *settle_prev(__u32 prev_tid,
							struct cycle_switch_rec **r)
{
	struct rtsup_thread *pt;

	if (!maybe_target(prev_tid))
		return NULL;
	pt = thread_entry(prev_tid);
	*r = held_switch_in();
	if (held_for(*r, prev_tid)) {
		if (pt)
			settle(pt, *r);
		(*r)->tid = 0;
	}
	return pt;
}

/*
 * lookup_or_hold - next's entry when its switch-in needs one; NULL with
 * *hold set when the switch-in is held instead (its wakemask bit is clear:
 * rtsup.h), NULL alone when next is no target
 */
static __always_inline struct rtsup_thread *lookup_or_hold(__u32 next_tid, int *hold)
{
	if (!maybe_target(next_tid))
		return NULL;
	if (maybe_wake_read(next_tid))
		return thread_entry(next_tid);
	*hold = 1;
	return NULL;
}

/* rt_add - --rt: an RT thread becomes a target; RTSUP_RT_ONLY when it is nothing else */
static __always_inline struct rtsup_thread *rt_add(struct task_struct *task)
{
	__u64 now = bpf_ktime_get_ns();
	struct rtsup_thread *t = add_thread(task, now);

	/* added now, not a target already (-p, --comm, --cgroup) */
	if (t && t->first_seen == now)
		t->rt = RTSUP_RT_ONLY;
	return t;
}

/*
 * rt_at_switch - --rt without the policy hook (cfg_rt_at_switch): the
 * policy read at a switch-in stands in for it (rtfollow.h). A SCHED_FIFO,
 * RR or DEADLINE thread is added; a target that --rt alone followed and
 * that left RT is let go, as on_setsched does, at its next switch-in.
 * nt: next's entry or NULL; returns the entry to go on with.
 */
static __always_inline struct rtsup_thread *rt_at_switch(struct task_struct *next,
							 struct rtsup_thread *nt, const int btf)
{
	__u32 tgid;

	switch (rt_on_switch_in(TREAD(btf, next, policy), TREAD(btf, next, flags), nt)) {
	case RT_ADOPT:
		/*
		 * nt is NULL or left RT (rtfollow.h): one let go for leaving RT
		 * starts anew, as on_setsched's does
		 */
		return rt_add(next);
	case RT_LET_GO:
		tgid = TREAD(btf, next, tgid);
		rt_mark_left(nt, !!bpf_map_lookup_elem(&tgids, &tgid));
		return nt;
	default:
		return nt;
	}
}

/*
 * switch_has_work - anything to do: a target leaves (pt) or comes in (nt,
 * or held). Past it, pt != NULL whenever !nt && !hold.
 */
static __always_inline int switch_has_work(const struct rtsup_thread *pt,
					   const struct rtsup_thread *nt, int hold)
{
	return pt || nt || hold;
}

/*
 * switch_timed - does this switch read the clock? Every switch-in does
 * (looked up or held); a switch-out only on a path of cycle_switch_out
 * that uses the time, so a thread going to sleep in its delimiter alone
 * reads none. out is prev's path, decided once for both.
 */
static __always_inline int switch_timed(const struct rtsup_thread *nt, int hold,
					enum cycle_out_path out)
{
	return nt || hold || CYC_PATH_TIMED(CYC_OUT_TIMED, out);
}

/* the inputs of switch_out_cycle, one object, as delim_in */
struct switch_out_in {
	struct cycle_cfg cf;
	__u64 now, minflt, majflt;
	__u32 path, voluntary;
};

/* The cycle a switch-out closed, per CPU: as delim_out, for sched_switch only. */
struct {
	__uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
	__uint(max_entries, 1);
	__type(key, __u32);
	__type(value, struct rtsup_cycle);
} switch_out SEC(".maps");

/*
 * switch_out_cycle - the cycle state machine as a target leaves the CPU
 * (cycle.h); global for the reason delim_cycle is (96 666 instructions
 * verified in sched_switch inlined, 24 349 now)
 */
__noinline int switch_out_cycle(struct rtsup_thread *t, const struct switch_out_in *in,
				struct rtsup_cycle *c)
{
	if (!t || !in || !c)
		return 0;
	return cycle_switch_out_on(t, &in->cf, in->path, in->now, in->voluntary, in->minflt,
				   in->majflt, c);
}

/* switch_out_run - switch_out_cycle with this CPU's record for the cycle it may close (*c) */
static __always_inline __u32 switch_out_run(struct rtsup_thread *t,
					    const struct switch_out_in *in,
					    struct rtsup_cycle **c)
{
	__u32 zero = 0;

	*c = bpf_map_lookup_elem(&switch_out, &zero);
	return *c ? switch_out_cycle(t, in, *c) : 0;	/* an array's one entry: never NULL */
}

/*
 * block_syscall - the syscall a block waits in, read from the thread's
 * saved registers as it leaves the CPU (prev is still current at
 * sched_switch): per-syscall hooks see no unhooked syscall begin, and
 * sys_enter's last one may have returned. Outside a syscall (a page
 * fault) it is none; a kernel thread has none, and a 32-bit syscall is
 * left unnamed, as sys_enter leaves it.
 */
static __always_inline void block_syscall(struct rtsup_why *w)
{
	struct task_struct *task = bpf_get_current_task_btf();
	struct pt_regs *regs;
	__u32 nr, *cls;
	long id;

	w->sys_nr = 0;
	w->sys_op = 0;
	/* a 32-bit syscall's number is another table's (compat_syscall) */
	if ((task->flags & PF_KTHREAD) || compat_syscall(task, 1))
		return;
	regs = (struct pt_regs *)bpf_task_pt_regs(task);
	id = SYSCALL_NR(regs);
	if (id < 0 || id >= RTSUP_MAX_SYSCALLS)
		return;
	nr = id;
	cls = bpf_map_lookup_elem(&sysclass, &nr);
	why_syscall(w, nr, cls && (*cls & RTSUP_SC_OPKEY) ?
			   (PT_REGS_PARM2_CORE_SYSCALL(regs) & 0x7f) + 1 : 0);
}

/* the inputs of switch_out_state and switch_out_events: prev as on_switch read it */
struct switch_out_side_in {
	__u64 now, minflt, majflt;
	__u32 prev_tid, path, voluntary, state;
	__u32 cpu, pad;		/* this CPU, as on_switch read it */
	__s32 policy, prio;	/* read when preempted (not voluntary) only */
};

/*
 * switch_out_state, switch_out_events - what a target's switch-out does
 * past the reads of prev: its cycle's state (switch_out_cycle), then its
 * wait for this CPU and its events. Global: each verified once, not once
 * for each state of the switch's other side (6.1's verifier walked this
 * code inlined some 9000 times: 101 390 instructions for sched_switch).
 * Two, not one: 6.1 allows 512 bytes of stack for the deepest chain of
 * calls, each frame rounded up to 32, and switch_out_cycle's is three deep.
 */
__noinline int switch_out_state(struct rtsup_thread *pt, const struct switch_out_side_in *in)
{
	struct rtsup_cycle *c;
	__u32 path;

	if (!pt || !in)
		return 0;
	path = in->path;
	if (cfg_block_sys && why_is_block(&pt->cs, in->now, in->voluntary)) {
		block_syscall(&pt->why);
		/* per-syscall hooks: a sleep in the delimiter whose entry went unseen */
		if (cfg_sys_per && cycle_entry_skipped(pt, pt->why.sys_nr, in->now, in->minflt,
						       in->majflt)) {
			path = CYC_OUT_DELIM_SLEEP;
			/* the cycle ends here, as why_delim would end it (no miss: it sleeps) */
			why_reset(&pt->why.cur);
			pt->why.out_ts = 0;
		}
	}
	struct switch_out_in so = {
		.cf = cfg(pt->cs.mode == RTSUP_MODE_DELIM ? NULL : thread_cfg_of(in->prev_tid)),
		.now = in->now, .path = path, .voluntary = in->voluntary,
		.minflt = in->minflt, .majflt = in->majflt,
	};

	why_switch_out(&pt->why, &pt->cs, in->now, in->voluntary, in->state);
	/* a switch-out that reads no clock (asleep in its delimiter) counts no CPU time */
	if (in->now)
		why_steal_out(&pt->why, in->cpu, cpu_steal(in->cpu));
	else
		pt->why.steal_cpu = 0;
	return switch_out_run(pt, &so, &c);
}

__noinline int switch_out_events(struct rtsup_thread *pt, const struct switch_out_side_in *in,
				 __u32 ev)
{
	struct why_slot *ws;
	struct rtsup_cycle *c;
	__u32 zero = 0;

	if (!pt || !in)
		return 0;
	/* preempted while released: it waits for this CPU (cause.h) */
	ws = why_slot_of(in->cpu);
	if (!in->voluntary && in->now && ws) {
		int i = why_pick(ws, in->prev_tid, in->now);

		if (i >= 0 && i < WHY_WAITERS) {
			why_arm(&ws[i], in->prev_tid, WHY_PREEMPTED, in->now);
			ws[i].policy = in->policy;
			ws[i].prio = in->prio;
		} else
			count(RTSUP_C_WHY_BUSY);
	}
	if (ev & CYC_EV_BLOCK) {
		/* arg2: the syscall it waits in + 1, 0 none or unknown */
		emit(RTSUP_EV_UNSAFE, pt, in->now, RTSUP_U_BLOCK,
		     cfg_block_sys ? pt->why.sys_nr : 0);
		/* prev is the current task: where it blocked */
		capture_stack(pt, in->now, RTSUP_U_BLOCK, 0);
	}
	if (!(ev & CYC_EV_CLOSED))
		return 0;
	/* the cycle switch_out_state closed: this CPU's record of it */
	c = bpf_map_lookup_elem(&switch_out, &zero);
	if (c)
		emit_cycle(ev, pt, in->now, c, 0);
	return 0;
}

/* on_switch - one thread leaves the CPU, another gets it */
static __always_inline int on_switch(bool preempt, struct task_struct *prev,
				     struct task_struct *next, const int btf)
{
	__u32 prev_tid = TREAD(btf, prev, pid), next_tid = TREAD(btf, next, pid);
	struct rtsup_thread *pt, *nt;
	struct cycle_switch_rec *r = NULL;
	enum cycle_out_path out = CYC_OUT_IDLE;
	int voluntary, hold = 0;
	__u32 ev, state = 0, cpu = bpf_get_smp_processor_id();
	struct why_slot *ws = why_slot_of(cpu);
	__u64 now;

	/* a target waits for this CPU: prev held it (two loads when none does) */
	if (ws && ws[0].tid && !(ws[0].state & WHY_RAN))
		why_switch(&ws[0], prev, prev_tid, next_tid, btf);
	if (ws && ws[1].tid && !(ws[1].state & WHY_RAN))
		why_switch(&ws[1], prev, prev_tid, next_tid, btf);
	if (!maybe_target(prev_tid) && !maybe_target(next_tid) && !cfg_rt_at_switch)
		return 0;
	/* one side is usually no target (idle, a kworker): no lookup for it */
	pt = settle_prev(prev_tid, &r);
	/* a wait that ended in a switch-in no event followed */
	if (pt)
		why_settle(pt);
	nt = lookup_or_hold(next_tid, &hold);
	if (!hold && cfg_rt_at_switch && next_tid)
		nt = rt_at_switch(next, nt, btf);
	/* keeps clang from OR-ing the two pointers, which the verifier refuses */
	barrier_var(nt);
	if (!switch_has_work(pt, nt, hold))
		return 0;
	if (pt && !preempt)
		state = btf ? get_task_state_btf(prev) : get_task_state(prev);
	voluntary = cycle_switch_voluntary(state);
	if (pt)
		out = cycle_switch_out_path(&pt->cs, voluntary);
	now = switch_timed(nt, hold, out) ? bpf_ktime_get_ns() : 0;
	if (hold) {
		if (!r)
			r = held_switch_in();
		if (r) {
			cycle_switch_in_later(r, next_tid, now, cpu,
					      TREAD(btf, next, min_flt), TREAD(btf, next, maj_flt));
			r->steal = cpu_steal(cpu);
		}
	}
	if (pt) {
		struct switch_out_side_in in = {
			.now = now, .prev_tid = prev_tid, .path = out, .voluntary = voluntary,
			.state = state, .cpu = cpu,
			.minflt = TREAD(btf, prev, min_flt), .majflt = TREAD(btf, prev, maj_flt),
		};

		__u32 policy = TREAD(btf, prev, policy), rt_prio = TREAD(btf, prev, rt_priority);

		thread_sched_seen(pt, policy, rt_prio, TREAD(btf, prev, nr_cpus_allowed));
		if (!voluntary) {
			in.policy = policy;
			in.prio = why_rt(in.policy) ? (__s32)rt_prio : 0;
		}
		ev = switch_out_state(pt, &in);
		switch_out_events(pt, &in, ev);
	}
	if (nt) {
		ev = cycle_switch_in(nt, now, cpu, TREAD(btf, next, min_flt),
				     TREAD(btf, next, maj_flt));
		if (ev & CYC_EV_MIGRATE)
			emit(RTSUP_EV_UNSAFE, nt, now, RTSUP_U_MIGRATE, why_migrated(&nt->why, cpu));
		why_steal_in(&nt->why, cpu, cpu_steal(cpu));
		why_settle(nt);
	}
	return 0;
}

/*
 * on_cgroup_attach - a task (or a process) moved to another cgroup: rare,
 * and once per process whatever its threads, so any move makes the
 * collector's next read whole, with every entry's task (threadread.h)
 */
static __always_inline int on_cgroup_attach(void)
{
	threads_attrs_moved = 1;
	return 0;
}

/* on_wakeup - remember when a target became runnable */
static __always_inline int on_wakeup(struct task_struct *p, const int btf)
{
	__u32 tid = TREAD(btf, p, pid);
	struct rtsup_thread *t;
	__u64 now;

	/* no target: one load */
	if (!maybe_target(tid))
		return 0;
	now = bpf_ktime_get_ns();
	why_wakeup(p, tid, now, btf);
	/* a target whose wakeup time nobody reads: no lookup */
	if (!maybe_wake_read(tid))
		return 0;
	t = thread_entry(tid);
	if (t && cycle_wakeup_read(t))
		cycle_wakeup(t, now);
	return 0;
}

#define TASK_WAKING	0x0200

/*
 * cpu_allowed - is 'cpu' in the task's affinity mask? Only the mask's word
 * of 'cpu' is read (a mask may be as short as the machine's CPUs); an
 * unreadable one says yes (no affinity change claimed).
 */
static __always_inline int cpu_allowed(struct task_struct *p, __u32 cpu)
{
	__u64 mask = 0, w = 0;

	/* the mask's address as a number: a word of it at any CPU's offset */
	if (bpf_probe_read_kernel(&mask, sizeof(mask), &p->cpus_ptr) || !mask ||
	    bpf_probe_read_kernel(&w, sizeof(w), (const void *)(mask + cpu / 64 * 8)))
		return 1;
	return (w >> (cpu % 64)) & 1;
}

/*
 * on_migrate - a task moves to CPU 'to': for a target, from where and why
 * (why_migrate), and a wait for the old CPU goes on at the new one
 * (why_move). No target: one load.
 */
static __always_inline int on_migrate(struct task_struct *p, int to, const int btf)
{
	__u32 tid = TREAD(btf, p, pid), from;
	struct why_slot *s, *d;
	struct rtsup_thread *t;

	if (!maybe_target(tid))
		return 0;
	t = thread_entry(tid);
	if (!t)
		return 0;
	from = TREAD(btf, p, thread_info.cpu);
	why_migrate(&t->why, from, to,
		    ((btf ? get_task_state_btf(p) : get_task_state(p)) & TASK_WAKING) != 0,
		    cpu_allowed(p, from));
	s = why_slot_of(from);
	d = why_slot_of(to);
	if (s && d && from != (__u32)to && why_move(s, d, tid, bpf_ktime_get_ns()) < 0)
		count(RTSUP_C_WHY_BUSY);
	return 0;
}

/* on_fork - threads of a target process, tasks of the target cgroup */
static __always_inline int on_fork(struct task_struct *parent, struct task_struct *child)
{
	__u32 tgid = BPF_CORE_READ(child, tgid), ptgid = BPF_CORE_READ(parent, tgid), one = 1;

	/* -- CMD: what the command forks is part of it */
	if (cfg_follow && tgid != ptgid && bpf_map_lookup_elem(&tgids, &ptgid))
		bpf_map_update_elem(&tgids, &tgid, &one, BPF_ANY);
	if (bpf_map_lookup_elem(&tgids, &tgid) ||
	    (cfg_cgroup && bpf_current_task_under_cgroup(&cgroup, 0) == 1))
		add_thread(child, bpf_ktime_get_ns());
	/* --rt: the child of an RT thread is RT too, unless SCHED_RESET_ON_FORK */
	else if (cfg_rt && rt_policy(BPF_CORE_READ(child, policy)))
		rt_add(child);
	return 0;
}

/*
 * on_setsched - --rt: a thread's policy changed (rtfollow.h). Once per
 * change, instead of a policy read at every switch-in: an RT thread is
 * adopted, one that --rt alone followed and that left RT is marked for
 * userspace to let go. A target's entry counts the change, as its next
 * switch-out would (thread_sched_seen), for a parked one too.
 */
static __always_inline int on_setsched(struct task_struct *p)
{
	__u32 tid = p->pid, tgid = p->tgid;
	struct rtsup_thread *t = maybe_target(tid) ? thread_entry(tid) : NULL;

	if (t)
		t->setsched++;
	switch (rt_on_policy(p->policy, t)) {
	case RT_ADOPT:
		rt_add(p);
		break;
	case RT_LET_GO:
		rt_mark_left(t, !!bpf_map_lookup_elem(&tgids, &tgid));
		break;
	default:
		break;
	}
	return 0;
}

/*
 * exec_reset - a target thread runs a new program: the cycle that was
 * running is not the new program's, and its start-up is no loop. Its cycle
 * state and statistics start again, as for a new thread (resets tells
 * userspace), its tid and first_seen stay.
 */
static __always_inline void exec_reset(struct rtsup_thread *t)
{
	settle(t, held_switch_in());
	zero_mem(&t->cs, sizeof(t->cs));
	t->cs.last_cpu = -1;
	t->last_cycle = 0;
	cycle_reset_stats(t);
	note_wake(t);
}

/* stack_exec_mark - --stacks: the process's mappings are another program's now */
static __always_inline void stack_exec_mark(struct rtsup_thread *t, struct task_struct *p)
{
	struct rtsup_stack_rec *r;

	if (!cfg_stack_any)
		return;
	r = bpf_ringbuf_reserve(&stacks, sizeof(*r), 0);
	if (!r) {
		count_stk(RTSUP_STK_LOST);
		return;
	}
	__builtin_memset(r, 0, sizeof(*r));
	r->tid = t->tid;
	r->tgid = t->tgid;
	r->reason = RTSUP_STACK_EXEC;
	r->exec_id = BPF_CORE_READ(p, self_exec_id);
	bpf_ringbuf_submit(r, 0);
}

/*
 * on_exec - a target's cycles start again; a process that now carries a
 * --comm name becomes a target
 */
static __always_inline int on_exec(struct task_struct *p)
{
	__u32 tid = BPF_CORE_READ(p, pid), tgid, one = 1;
	struct rtsup_thread *t = maybe_target(tid) ? thread_entry(tid) : NULL;
	char comm[RTSUP_COMM_LEN];

	/*
	 * A thread other than the leader that execs takes the leader's tid
	 * (de_thread): the leader's entry, exited, is this thread's now
	 */
	if (t && t->exited)
		add_thread(p, bpf_ktime_get_ns());
	else if (t)
		exec_reset(t);
	if (t)
		stack_exec_mark(t, p);
	if (!cfg_ncomm)
		return 0;
	bpf_probe_read_kernel_str(comm, sizeof(comm), &p->comm);
	if (!comm_match(comm))
		return 0;
	tgid = BPF_CORE_READ(p, tgid);
	bpf_map_update_elem(&tgids, &tgid, &one, BPF_ANY);
	add_thread(p, bpf_ktime_get_ns());
	return 0;
}

/*
 * on_rename - a thread named like a --comm target; keep names current. A
 * leader so named makes its process a target, as the start-up scan takes
 * a process by its leader's name: the threads it creates are followed.
 */
static __always_inline int on_rename(struct task_struct *task, const char *newcomm)
{
	__u32 tid = BPF_CORE_READ(task, pid), tgid, one = 1;
	struct rtsup_thread *t = thread_entry(tid);
	char comm[RTSUP_COMM_LEN];

	if (!t && !cfg_ncomm)
		return 0;
	bpf_probe_read_kernel_str(comm, sizeof(comm), newcomm);
	if (cfg_ncomm && comm_match(comm)) {
		tgid = BPF_CORE_READ(task, tgid);
		if (tgid == tid)
			bpf_map_update_elem(&tgids, &tgid, &one, BPF_ANY);
	}
	if (!t && comm_match(comm))
		t = add_thread(task, bpf_ktime_get_ns());
	if (t)
		__builtin_memcpy(t->comm, comm, sizeof(comm));
	return 0;
}

/* on_exit - a target thread ends: report it, stop its cycle */
static __always_inline int on_exit(struct task_struct *task)
{
	__u32 tid = BPF_CORE_READ(task, pid);
	struct rtsup_thread *t = thread_entry(tid);
	__u64 now;

	if (!t)
		return 0;
	settle(t, held_switch_in());	/* it exits on its CPU */
	now = bpf_ktime_get_ns();
	cycle_exit(t, now, BPF_CORE_READ(task, min_flt), BPF_CORE_READ(task, maj_flt));
	note_wake(t);
	t->exit_code = BPF_CORE_READ(task, exit_code);
	/* the whole process ends, not this thread alone (checks.c: a clean end) */
	t->exit_group = !!(BPF_CORE_READ(task, signal, flags) & SIGNAL_GROUP_EXIT);
	emit(RTSUP_EV_EXIT, t, now, t->exit_mid_cycle, t->exit_code);
	return 0;
}

/*
 * on_fault - --stacks: a target's user page fault inside a cycle, where it
 * happened. Attached only with --stacks: every user fault on the machine
 * costs the tidmask load.
 */
static __always_inline int on_fault(void)
{
	__u32 tid = (__u32)bpf_get_current_pid_tgid();
	struct rtsup_thread *t = lookup_thread(tid);

	if (!t || t->exited)
		return 0;
	settle(t, held_switch_in());
	/* inside a cycle, as cycle_syscall counts a syscall */
	if (t->cs.start && !t->cs.in_delim)
		capture_stack(t, bpf_ktime_get_ns(), RTSUP_STACK_FAULT, 0);
	return 0;
}

/* on_signal - a signal is delivered to the current thread */
static __always_inline int on_signal(int sig)
{
	__u32 tid = (__u32)bpf_get_current_pid_tgid();
	struct rtsup_thread *t = thread_entry(tid);

	if (!t)
		return 0;
	t->signals++;
	t->last_signal = sig;
	emit(RTSUP_EV_SIGNAL, t, bpf_ktime_get_ns(), sig, 0);
	return 0;
}

#define PACKET_LOOPBACK	5

/* lookup_or_add - a map entry, created from a zero value on first use */
static __always_inline void *lookup_or_add(void *map, const void *key, const void *zero)
{
	void *v = bpf_map_lookup_elem(map, key);

	if (v || !zero)
		return v;
	bpf_map_update_elem(map, key, zero, BPF_NOEXIST);
	return bpf_map_lookup_elem(map, key);
}

/* can_if_get - the counters of an interface, created on first use */
static __always_inline struct rtsup_can_if *can_if_get(const struct rtsup_can_key *k)
{
	struct rtsup_can_ifkey ik = { .netns = k->netns, .ifindex = k->ifindex };
	struct rtsup_can_if zif = {};

	if (k->netns == cfg_netns && k->ifindex < RTSUP_CAN_IF_SLOTS)
		return &can_if_slot[k->ifindex];
	return lookup_or_add(&can_ifs, &ik, &zif);
}

/*
 * can_if_key - the ifindex a frame of this interface is counted under: its
 * own, or with --can IFACE the one the named interface had at start; 0 for
 * an interface that is not watched
 */
static __always_inline __u32 can_if_key(__u32 netns, __u32 ifindex)
{
	__u32 i;

	if (!cfg_can_nif)
		return ifindex;
	for (i = 0; i < RTSUP_CAN_WATCH && i < cfg_can_nif; i++)
		if (can_watch[i].ifindex == ifindex && can_watch[i].netns == netns)
			return can_watch[i].key;
	return 0;
}

/* can_key_of - the interface part of a CAN skb's key; 0 when not watched */
static __always_inline int can_key_of(const struct sk_buff *skb, struct rtsup_can_key *k,
				      const int btf)
{
	__u32 ifindex;

	if (btf) {
		ifindex = skb->dev->ifindex;
		k->netns = skb->dev->nd_net.net->ns.inum;
	} else {
		ifindex = BPF_CORE_READ(skb, dev, ifindex);
		k->netns = BPF_CORE_READ(skb, dev, nd_net.net, ns.inum);
	}
	k->ifindex = can_if_key(k->netns, ifindex);
	return k->ifindex != 0;
}

/* can_skb_proto - the frame kind of a CAN skb; -1 for anything else (one compare) */
static __always_inline int can_skb_proto(const struct sk_buff *skb, const int btf)
{
	__u16 proto = bpf_ntohs(TREAD(btf, skb, protocol));

	if ((__u16)(proto - RTSUP_ETH_P_CAN) > RTSUP_ETH_P_CANXL - RTSUP_ETH_P_CAN)
		return -1;
	return proto - RTSUP_ETH_P_CAN;
}

/* can_frame_read - identifier, length and first bytes of a CAN skb; 0 when read */
static __always_inline int can_frame_read(const struct sk_buff *skb, __u32 kind,
					  struct rtsup_can_frame *f, __u32 *len, const int btf)
{
	unsigned char *data = TREAD(btf, skb, data);
	struct rtsup_canxl_head xl;

	if (kind == RTSUP_CAN_XL) {
		if (bpf_probe_read_kernel(&xl, sizeof(xl), data))
			return -1;
		__builtin_memset(f, 0, sizeof(*f));
		f->can_id = xl.prio & RTSUP_CAN_SFF_MASK;
		*len = xl.len;
		bpf_probe_read_kernel(f->data, sizeof(f->data), data + sizeof(xl));
		return 0;
	}
	if (bpf_probe_read_kernel(f, sizeof(*f), data))
		return -1;
	*len = f->len;
	return 0;
}

/* can_sdo_response - CANopen: time from a node's SDO request to its response */
static __always_inline void can_sdo_response(struct rtsup_can_id *v,
					     const struct rtsup_can_key *k, __u32 id, __u64 now)
{
	struct rtsup_can_key rk = { .ifindex = k->ifindex, .netns = k->netns,
				    .can_id = id + 0x80 };
	struct rtsup_can_id *req;
	__u32 d;

	for (d = 0; d < RTSUP_CAN_DIRS; d++) {
		rk.dir = d;
		req = bpf_map_lookup_elem(&can_ids, &rk);
		if (can_sdo_match(v, req, now))
			return;
	}
}


/* on_softirq - a softirq starts (in) or ends on this CPU, in the current task */
static __always_inline int on_softirq(int in)
{
	__u32 zero = 0, *t = bpf_map_lookup_elem(&softirq_task, &zero);

	if (t)
		*t = in ? (__u32)bpf_get_current_pid_tgid() : 0;
	return 0;
}

/* in_kernel_work - a softirq or a kernel thread: not the current task's own work */
static __always_inline int in_kernel_work(const int btf)
{
	__u32 zero = 0, *t = bpf_map_lookup_elem(&softirq_task, &zero);
	struct task_struct *task = CURRENT(btf);

	if (TREAD(btf, task, flags) & PF_KTHREAD)
		return 1;
	/* the task too: on PREEMPT_RT another may preempt a softirq's task */
	return t && *t && *t == (__u32)bpf_get_current_pid_tgid();
}

/* can_charge - the thread a sent frame is charged to, and where in its cycle */
static __always_inline void can_charge(struct rtsup_can_id *v, __u64 now, const int btf)
{
	struct rtsup_thread *t;
	__u32 tid;

	/* a BCM or ISO-TP timer, can-gw: the kernel's send, whoever was current */
	if (in_kernel_work(btf)) {
		v->tx_tid = 0;
		CAN_ADD(&v->tx_kernel, 1);
		return;
	}
	tid = (__u32)bpf_get_current_pid_tgid();
	v->tx_tid = tid;
	t = lookup_thread(tid);
	if (t && t->cs.start && !t->cs.in_delim && now >= t->cs.start) {
		CAN_ADD(&v->tx_in_cycle, 1);
		CAN_ADD(&v->tx_offset_sum, now - t->cs.start);
		if (now - t->cs.start > v->tx_offset_max)
			v->tx_offset_max = now - t->cs.start;
	}
}

/* can_account - one frame of a watched interface, sent or received */
static __always_inline int can_account(const struct rtsup_can_key *k, struct rtsup_can_if *ifs,
				       const struct rtsup_can_frame *f, __u32 len, __u32 kind,
				       const int btf)
{
	struct rtsup_can_key key = *k;
	struct rtsup_can_id *v;
	__u32 zero = 0, id;
	__u64 now;

	now = bpf_ktime_get_ns();
	can_if_account(ifs, now, key.dir, f->can_id, len, kind, f->data);
	if (f->can_id & RTSUP_CAN_ERR_FLAG)
		return 0;
	id = can_key_id(f->can_id);
	key.can_id = id;
	v = bpf_map_lookup_elem(&can_ids, &key);
	if (!v)	/* a new identifier: the zero template only now */
		v = lookup_or_add(&can_ids, &key, bpf_map_lookup_elem(&zero_can, &zero));
	if (!v) {
		count(RTSUP_C_CAN_FULL);
		return 0;
	}
	if (cfg_canopen && can_is_sdo_response(id))
		can_sdo_response(v, &key, id, now);
	can_id_account(v, now, f->can_id, len, f->data, cfg_ewma_w, epoch);
	if (key.dir == RTSUP_CAN_TX)
		can_charge(v, now, btf);
	return 0;
}

/* on_can_rx - one SocketCAN frame arriving */
static __always_inline int on_can_rx(const struct sk_buff *skb, const int btf)
{
	struct rtsup_can_key key = { .dir = RTSUP_CAN_RX };
	int kind = can_skb_proto(skb, btf);
	struct rtsup_can_frame f;
	struct rtsup_can_if *ifs;
	__u32 len;

	if (kind < 0 || !can_key_of(skb, &key, btf))
		return 0;
	ifs = can_if_get(&key);
	if (!ifs)
		return 0;
	/*
	 * af_can (can_send) and echo-capable drivers (can_put_echo_skb) loop our
	 * own sends back as rx, PACKET_BROADCAST like a frame from the bus, but
	 * still owned by the sending socket: a frame from the bus has no skb->sk.
	 * Tested before the frame is read: an echo costs no more than this.
	 */
	if (TREAD(btf, skb, sk) ||
	    (btf ? BPF_CORE_READ_BITFIELD(skb, pkt_type) :
		   BPF_CORE_READ_BITFIELD_PROBED(skb, pkt_type)) == PACKET_LOOPBACK) {
		__sync_fetch_and_add(&ifs->loopback, 1);
		return 0;
	}
	if (can_frame_read(skb, kind, &f, &len, btf))
		return 0;
	return can_account(&key, ifs, &f, len, kind, btf);
}

/*
 * on_can_offer - a SocketCAN frame offered to its driver: stashed on this
 * CPU until the driver answers (on_can_sent), since a busy driver is
 * offered the same frame again. Both run with bottom halves off on this
 * CPU, which on PREEMPT_RT too admits one such section per CPU at a time:
 * no other offer comes in between.
 */
static __always_inline int on_can_offer(const struct sk_buff *skb, const int btf)
{
	struct rtsup_can_key key = { .dir = RTSUP_CAN_TX };
	int kind = can_skb_proto(skb, btf);
	struct rtsup_can_tx *s;
	__u32 zero = 0;

	if (kind < 0 || !can_key_of(skb, &key, btf))
		return 0;
	s = bpf_map_lookup_elem(&can_tx_stash, &zero);
	if (!s)
		return 0;
	s->skb = 0;
	if (can_frame_read(skb, kind, &s->f, &s->len, btf))
		return 0;
	s->key = key;
	s->kind = kind;
	s->skb = (__u64)skb;
	return 0;
}

#define ARPHRD_CAN	280

/* on_can_sent - the driver's answer: the stashed frame counts if it took it */
static __always_inline int on_can_sent(const struct sk_buff *skb, int rc,
				       const struct net_device *dev, const int btf)
{
	struct rtsup_can_if *ifs;
	struct rtsup_can_tx *s;
	__u32 zero = 0;

	/* anything but CAN costs this one compare; the skb may be freed by now */
	if (TREAD(btf, dev, type) != ARPHRD_CAN)
		return 0;
	s = bpf_map_lookup_elem(&can_tx_stash, &zero);
	if (!s || !can_tx_taken(s, (__u64)skb, rc))
		return 0;
	ifs = can_if_get(&s->key);
	if (!ifs)
		return 0;
	return can_account(&s->key, ifs, &s->f, s->len, s->kind, btf);
}

/*
 * on_task_iter - the task iterator's visit of one task: a target's policy,
 * RT priority, allowed CPUs and cgroup, for the collector's sample
 * (taskattrs.h). A mask wider than ours keeps its first 1024 CPUs; a
 * narrower one says how many words it filled.
 */
static __always_inline int on_task_iter(struct seq_file *seq, struct task_struct *task)
{
	struct rtsup_task_attrs a = {};
	__u32 tid = task->pid;

	if (!maybe_target(tid) || !thread_exists(tid) || task_attrs_fill(task, &a))
		return 0;
	bpf_seq_write(seq, &a, sizeof(a));
	return 0;
}

/*
 * The two program sets. RTSUP_EMPTY builds the same hooks with empty bodies:
 * the floor that the benchmark compares against.
 */
#ifdef RTSUP_EMPTY
#define BODY(x) 0
#else
#define BODY(x) x
#endif

#define RTSUP_PROGS(kind, sfx, btf)						\
SEC(kind "/sys_enter")								\
int BPF_PROG(sys_enter_##sfx, struct pt_regs *regs, long id)			\
{ return BODY(on_sys_enter(regs, id, btf)); }					\
SEC(kind "/sys_exit")								\
int BPF_PROG(sys_exit_##sfx, struct pt_regs *regs, long ret)			\
{ return BODY(on_sys_exit(regs, ret, btf, 0)); }					\
SEC(kind "/sched_switch")							\
int BPF_PROG(sched_switch_##sfx, bool preempt, struct task_struct *prev,	\
	     struct task_struct *next)						\
{ return BODY(on_switch(preempt, prev, next, btf)); }				\
SEC(kind "/sched_wakeup")							\
int BPF_PROG(sched_wakeup_##sfx, struct task_struct *p)				\
{ return BODY(on_wakeup(p, btf)); }						\
SEC(kind "/sched_migrate_task")							\
int BPF_PROG(sched_migrate_task_##sfx, struct task_struct *p, int dest_cpu)	\
{ return BODY(on_migrate(p, dest_cpu, btf)); }					\
SEC(kind "/sched_process_fork")							\
int BPF_PROG(sched_process_fork_##sfx, struct task_struct *parent,		\
	     struct task_struct *child)						\
{ return BODY(on_fork(parent, child)); }					\
SEC(kind "/sched_process_exec")							\
int BPF_PROG(sched_process_exec_##sfx, struct task_struct *p)			\
{ return BODY(on_exec(p)); }							\
SEC(kind "/task_rename")							\
int BPF_PROG(task_rename_##sfx, struct task_struct *task, const char *comm)	\
{ return BODY(on_rename(task, comm)); }						\
SEC(kind "/sched_process_exit")							\
int BPF_PROG(sched_process_exit_##sfx, struct task_struct *task)		\
{ return BODY(on_exit(task)); }							\
SEC(kind "/signal_deliver")							\
int BPF_PROG(signal_deliver_##sfx, int sig)					\
{ return BODY(on_signal(sig)); }							\
SEC(kind "/cgroup_attach_task")							\
int BPF_PROG(cgroup_attach_task_##sfx, struct cgroup *dst, const char *path,	\
	     struct task_struct *task, bool threadgroup)				\
{ return BODY(on_cgroup_attach()); }

#define RTSUP_CAN_PROGS(kind, sfx, btf)						\
SEC(kind "/net_dev_start_xmit")							\
int BPF_PROG(can_xmit_##sfx, const struct sk_buff *skb)				\
{ return BODY(on_can_offer(skb, btf)); }					\
SEC(kind "/net_dev_xmit")							\
int BPF_PROG(can_xmitted_##sfx, const struct sk_buff *skb, int rc,		\
	     const struct net_device *dev)					\
{ return BODY(on_can_sent(skb, rc, dev, btf)); }				\
SEC(kind "/netif_receive_skb")							\
int BPF_PROG(can_recv_##sfx, const struct sk_buff *skb)				\
{ return BODY(on_can_rx(skb, btf)); }						\
SEC(kind "/softirq_entry")							\
int BPF_PROG(can_softirq_in_##sfx, unsigned int vec)				\
{ return BODY(on_softirq(1)); }							\
SEC(kind "/softirq_exit")							\
int BPF_PROG(can_softirq_out_##sfx, unsigned int vec)				\
{ return BODY(on_softirq(0)); }

/* x86 only: the loader keeps them off elsewhere, and without --stacks */
#define RTSUP_FAULT_PROGS(kind, sfx)						\
SEC(kind "/page_fault_user")							\
int BPF_PROG(page_fault_user_##sfx, unsigned long address, struct pt_regs *regs,	\
	     unsigned long error_code)						\
{ return BODY(on_fault()); }

/*
 * --rt's policy hook (rtfollow.h): every policy change goes through
 * __sched_setscheduler. The loader keeps it only where the kernel's BTF
 * has the function; elsewhere cfg_rt_at_switch looks at every switch-in.
 */
SEC("fexit/__sched_setscheduler")
int BPF_PROG(rt_setsched, struct task_struct *p, const struct sched_attr *attr, bool user,
	     bool pi, int ret)
{ return BODY(on_setsched(p)); }

/*
 * --syscall-hooks per-syscall: a stub on each hooked syscall's function
 * (the loader names it, __x64_sys_NAME) lets every thread that is no target
 * go after one bit test, and hands a target to the full program by a tail
 * call: the whole of sys_enter/sys_exit, on the same regs, verified once.
 */
static __always_inline int sys_stub(void *ctx, void *body)
{
	if (maybe_target((__u32)bpf_get_current_pid_tgid()))
		bpf_tail_call(ctx, body, 0);
	return 0;
}

#define SYS_BODIES(g, late)							\
SEC("fentry")									\
int BPF_PROG(sys_in_prog##g, struct pt_regs *regs)				\
{ return BODY(on_sys_enter(regs, SYSCALL_NR(regs), 1)); }			\
SEC("fexit")									\
int BPF_PROG(sys_out_prog##g, struct pt_regs *regs, long ret)			\
{ return BODY(on_sys_exit(regs, ret, 1, late)); }
SYS_BODIES(, 1)
/*
 * syscalls without arguments (restart_syscall, sched_yield...): no late
 * entry, whose release is read from the arguments; a delimiter among them
 * whose entry went unseen loses that cycle at its return (cycle_delim_exit)
 */
SYS_BODIES(_z, 0)

#define SYS_IN(n, g)								\
SEC("fentry")									\
int sys_in##g##_##n(unsigned long long *ctx) { return BODY(sys_stub(ctx, &sys_in_body##g)); }
#define SYS_OUT(n, g)								\
SEC("fexit")									\
int sys_out##g##_##n(unsigned long long *ctx) { return BODY(sys_stub(ctx, &sys_out_body##g)); }
#define SYS_ROW(S, d, g) S(d##0, g) S(d##1, g) S(d##2, g) S(d##3, g) S(d##4, g)	\
			 S(d##5, g) S(d##6, g) S(d##7, g) S(d##8, g) S(d##9, g)

/* RTSUP_SYS_IN_SLOTS and RTSUP_SYS_OUT_SLOTS of them, and the _z ones (rtsup.h) */
SYS_ROW(SYS_IN, 0, ) SYS_ROW(SYS_IN, 1, ) SYS_ROW(SYS_IN, 2, ) SYS_ROW(SYS_IN, 3, )
SYS_ROW(SYS_IN, 4, ) SYS_ROW(SYS_IN, 5, ) SYS_ROW(SYS_IN, 6, ) SYS_ROW(SYS_IN, 7, )
SYS_ROW(SYS_OUT, 0, ) SYS_ROW(SYS_OUT, 1, ) SYS_ROW(SYS_OUT, 2, )
SYS_ROW(SYS_IN, 0, _z) SYS_ROW(SYS_IN, 1, _z)
SYS_OUT(00, _z) SYS_OUT(01, _z) SYS_OUT(02, _z) SYS_OUT(03, _z)

/* the collector's one read of the targets' attributes a sample (taskattrs.h) */
SEC("iter/task")
int attrs_task(struct bpf_iter__task *ctx)
{
	struct task_struct *task = ctx->task;

	return task ? BODY(on_task_iter(ctx->meta->seq, task)) : 0;
}

/* the collector's read of the thread map a sample, changed entries whole */
SEC("iter/bpf_map_elem")
int threads_read(struct bpf_iter__bpf_map_elem *ctx)
{
	__u32 *tid = ctx->key, *at = ctx->value, slot;
	struct rtsup_thread *t;

	if (!tid || !at)
		return 0;
	slot = *at;
	t = bpf_map_lookup_elem(&thread_mem, &slot);
	return t ? BODY(thread_rec_write(ctx->meta->seq, *tid, slot, t, THREAD_TASK_UNREAD,
					 NULL, false)) : 0;
}

RTSUP_PROGS("tp_btf", btf, 1)
RTSUP_PROGS("raw_tp", raw, 0)
RTSUP_FAULT_PROGS("tp_btf", btf)
RTSUP_FAULT_PROGS("raw_tp", raw)
RTSUP_CAN_PROGS("tp_btf", btf, 1)
RTSUP_CAN_PROGS("raw_tp", raw, 0)

char LICENSE[] SEC("license") = "Dual BSD/GPL";
