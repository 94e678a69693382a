/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * collector.h - kernel maps -> model: once per interval it flips the epoch,
 * reads every thread entry and the unsafe syscall counts, frees the entries
 * of dead threads, and gathers the ring buffer's rare events.
 */
#ifndef RTSUP_COLLECTOR_H
#define RTSUP_COLLECTOR_H

#include <stdbool.h>
#include "collect/clockoff.h"
#include "collect/iterread.h"
#include "collect/movedset.h"
#include "collect/procfile.h"
#include "collect/taskattrs.h"
#include "collect/threadmem.h"
#include "model/causes.h"
#include "model/eventlog.h"
#include "model/model.h"
#include "model/stackagg.h"
#include "options.h"

struct rtsup_bpf;
struct rtsup_tasks_bpf;
struct ring_buffer;
struct unwinder;
struct stack_maps;

/* Clocks whose absolute sleeps the kernel side converts to CLOCK_MONOTONIC (update_clocks). */
#define COLLECTOR_CLOCKS 5
/* Thread map entries per read at first: 64 entries of ~5 KiB. */
#define COLLECTOR_BATCH 64
/* A poll consumes events for its wait or this long, whichever is longer (poll_over). */
#define COLLECTOR_POLL_MIN_MS 10
/*
 * The loop polls at least this often while events come: the kernel wakes
 * it only for a quarter-full ring buffer (rb_wakeup), so no event waits
 * longer. Once a poll found none, at least this often (a wakeup costs the
 * loop more than its read of a parked thread: collector_poll_ms).
 */
#define COLLECTOR_POLL_MAX_MS 100
#define COLLECTOR_POLL_QUIET_MS 1000

/* process names remembered within one sample: a slot per tgid modulo this */
#define COLLECTOR_PNAMES 64

struct collector {
	struct rtsup_bpf *skel;
	/* the thread map's iterator that reads the tasks too (6.2+), NULL: skel's own */
	struct rtsup_tasks_bpf *tasks;
	const struct options *o;
	/* what the syscalls are seen by: "per-syscall" or "raw_syscalls"; NULL in a replay */
	const char *sys_hooks;
	/* where the targets' attributes come from (json.md, supervisor.task_attrs); NULL in a replay */
	const char *task_attrs;
	struct model model;
	struct ring_buffer *rb;
	__u32 bank;			/* interval bank of the last sample */
	__u64 counters[RTSUP_C_NR];	/* the kernel side's own counters */
	__u64 untracked_scan;		/* of them, found by the start-up scan (userspace) */
	struct eventlog events;		/* the interval's rare events (eventlog.h) */
	__u64 events_total;		/* every rare event of the run */
	/* deadline misses by cause (causes.h): the interval's and the run's */
	struct causes causes_win, causes_life;
	__u64 poll_until;		/* the running poll stops consuming here (ns) */
	__u64 polled;			/* records consumed, to read the clock once in 64 */
	__s64 real_off;			/* CLOCK_REALTIME - CLOCK_MONOTONIC, ns */
	struct clock_offset clock_held[COLLECTOR_CLOCKS]; /* what the kernel side converts with */
	/*
	 * real_off when the last step was told: a sample between the step and
	 * its clockwatch wakeup has already written the new offset to real_off
	 */
	__s64 real_off_said;
	/* live only (rb): a wall clock step updates the offsets at once (clockwatch.h) */
	int clock_fd;			/* -1: not watched, offsets each interval only */
	int epfd;			/* the ring buffer's epoll fd and clock_fd */
	bool poll_quiet;		/* the last poll found no event */
	__u64 clock_steps;		/* wall clock steps seen */
	__u64 start_ns;			/* monotonic start */
	__u64 end_ns;			/* when the last sample ended its interval */
	__u32 map_entries;		/* entries of the thread map at the last sample */
	/* the thread map is read COLLECTOR_BATCH tids and slots per syscall */
	__u32 *batch_keys;
	__u32 *batch_slots;
	struct rtsup_moved_rec *batch_at;	/* ... both, as read_ahead reads them */
	__u32 batch_cap;
	struct threadmem mem;		/* the entries, copied in place (threadmem.h) */
	__u32 unsafe_sys_seen;		/* unsafe_sys_gen at the last walk of unsafe_sys */
	bool unsafe_sys_pending;	/* ... which found a thread the model did not hold */
	struct rtsup_thread *entry;	/* the copy of one, taken */
	bool no_batch;			/* the kernel has no batch operations */
	/* or, where the kernel has its iterator, the entries that changed (threadread.h) */
	struct iter_buf threads_out;
	__u32 map_copied;		/* entries copied out whole at the last sample */
	__u32 map_short;		/* ... short: the buckets that moved (threadmem.h) */
	__u32 map_short_refused;	/* short copies the model could not take: copied whole */
	__u32 map_moved;		/* entries whose bytes changed since an earlier copy */
	__u32 map_visited;		/* entries the last sample's read looked at */
	bool map_whole;			/* ... all of them: it walked the map (threadread.h) */
	bool map_batch;			/* ... in batches of entries, not through the iterator */
	__u32 map_tasks;		/* tasks whose attributes the iterator read with it */
	/* the entries the hooks named since the last read (threadread.h) */
	struct movedset moved;
	/* --stacks: the stack records, their own ring so events keep their order */
	struct ring_buffer *stack_rb;
	struct unwinder *unwinder;
	struct stackagg stacks;		/* where in the code, per thread, reason, stack */
	/* sinks that want every cycle and event as it comes (--record, --perfetto) */
	void (*on_cycle)(void *ctx, const struct rtsup_cycle_rec *r);
	void (*on_rare)(void *ctx, const struct rtsup_event *e);
	/* --stacks: each stack record, symbolized (reason and nr as in stackagg) */
	void (*on_stack)(void *ctx, const struct rtsup_stack_rec *r,
			 const struct stack_frame *f, int n, const struct stack_maps *m);
	void *sink_ctx;
	/* the targets' attributes at the last walk of the task iterator (taskattrs.h) */
	struct task_attrs attrs;
	bool attrs_walked;		/* ... which was this sample's (thread_walk_tasks) */
	__u32 attrs_asked;		/* threads whose attributes this sample asked one by one */
	__u32 attrs_asked_last;		/* ... and the sample before */
	/* process names read in this sample, by tgid (refresh_identity) */
	__u64 sample_seq;
	struct collector_pname {
		__u32 tgid;
		__u64 seq;
		char comm[RTSUP_COMM_LEN];
		struct procfile file;	/* its main thread's comm, kept open */
	} pnames[COLLECTOR_PNAMES];
};

/* lost_records - what the ring buffers dropped so far: rare events and cycle records */
static inline __u64 lost_records(const __u64 *counters)
{
	return counters[RTSUP_C_RB_DROPS] + counters[RTSUP_C_CYC_DROPS];
}

/* collector_init - ring buffer, initial scan of the targets */
int collector_init(struct collector *c, struct rtsup_bpf *skel, const struct options *o);
/* collector_scan - add the threads of these targets found now (e.g. a restarted unit) */
int collector_scan(struct collector *c, const struct targets *t);
/* collector_poll - wait up to ms for rare events, consume for at most that (or 10 ms) */
int collector_poll(struct collector *c, int ms);
/*
 * collector_poll_ms - how long the loop's next poll may wait of the ms to
 * its next deadline: COLLECTOR_POLL_MAX_MS while events come, stacks are
 * unwound (the process's maps must still be there) or 'busy' (a child or
 * an action the loop reaps), else COLLECTOR_POLL_QUIET_MS
 */
int collector_poll_ms(const struct collector *c, int ms, bool busy);
/* collector_sample - end an interval at end_ns: refresh the model from the maps */
int collector_sample(struct collector *c);
/* collector_reap - after the sinks ran: free what dead threads left */
void collector_reap(struct collector *c);
struct supervisor;
/* collector_apply_rules - per-thread settings of the matching rules, to the kernel */
void collector_apply_rules(struct collector *c, const struct supervisor *s);
/* collector_take_event - one rare event for the interval's list */
void collector_take_event(struct collector *c, const struct rtsup_event *e);
/* collector_clear_events - forget the events of the interval */
void collector_clear_events(struct collector *c);
void collector_free(struct collector *c);
/* mono_now - CLOCK_MONOTONIC in ns, the clock of the BPF timestamps */
__u64 mono_now(void);

#endif
