/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * record.h - the recorded trace (--record FILE): a compact, versioned binary
 * file of per-cycle records, rare events and per-interval thread state, with
 * a header saying where and when it was recorded. `rtsup-trace replay FILE`
 * reads it back into the same model, checks and outputs.
 *
 * Layout (little endian, the recording host's):
 *   "RTSUPREC" | u32 version | u32 header_len | header (JSON text)
 *   then records: u16 type | u16 len | u32 crc32(payload) | payload[len]
 */
#ifndef RTSUP_RECORD_H
#define RTSUP_RECORD_H

#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"

#define REC_MAGIC	"RTSUPREC"
#define REC_VERSION	1
#define REC_MAX_PAYLOAD	4096
/* an event of a recording made before events carried their cause (issue 14) */
#define REC_EVENT_NO_CAUSE	offsetof(struct rtsup_event, cause)
/* and before a cause said when and where (held_from on: Perfetto), and migrations */
#define REC_EVENT_CAUSE_1	(offsetof(struct rtsup_event, cause) + \
				 offsetof(struct rtsup_cause, held_from))
/* and before a cause had the hypervisor's steal */
#define REC_EVENT_CAUSE_2	(offsetof(struct rtsup_event, cause) + \
				 offsetof(struct rtsup_cause, steal_ns))

struct rec_header {
	char kernel[128];	/* uname -r -v */
	char host[64];
	char args[512];		/* the command line that recorded */
	char config_path[256];	/* "" when none */
	char *config_text;	/* the configuration file's text, malloc'd, may be NULL */
	__u64 start_real_ns;	/* CLOCK_REALTIME at start */
	__u64 start_mono_ns;	/* CLOCK_MONOTONIC at start: the clock of every timestamp */
	double interval_s;
	__u32 ewma_w;
};

enum rec_type {
	REC_THREAD = 1,		/* struct rec_thread: identity and non-cycle counters */
	REC_CYCLE,		/* struct rec_cycle: one finished cycle */
	REC_EVENT,		/* struct rtsup_event: one rare event */
	REC_INTERVAL,		/* struct rec_interval: an interval ended */
	REC_END,		/* struct rec_interval: the run ended */
	REC_STACK,		/* struct rec_stack: a user stack at an RT-unsafe event (--stacks) */
	REC_MODULE,		/* struct rec_module: a file mapped executable, for REC_STACK */
};

/* A thread's identity and its counters that are not per cycle. */
struct rec_thread {
	__u32 tid;
	__u32 tgid;
	char comm[RTSUP_COMM_LEN];
	char pcomm[RTSUP_COMM_LEN];	/* its process's name */
	__s32 policy;
	__s32 prio;
	__u64 first_seen;
	__u64 vol_cs;
	__u64 invol_cs;
	__u64 migrations;
	__u64 signals;
	__u64 exited;		/* exit time, 0 while alive */
	__s32 exit_code;
	__u32 exit_mid_cycle;
	__u32 mode;		/* enum rtsup_mode */
	__u32 resets;
	__u64 nominal;		/* nominal period the kernel derived */
	__u64 last_cycle;	/* start of the last finished cycle */
	/* lifetime counters as the kernel keeps them (not derived from cycles) */
	__u64 syscalls;
	__u64 minflt;
	__u64 majflt;
	__u64 unsafe[RTSUP_U_NR];
	__u32 nsys;		/* unsafe syscalls by number */
	__u32 exit_group;	/* its process ended with it (0 in recordings before it) */
	struct {
		__u32 nr;
		__u32 pad;
		__u64 total;
	} sys[16];
};

struct rec_cycle {
	__u64 end;		/* CLOCK_MONOTONIC ns when the cycle finished */
	struct rtsup_cycle_rec r;
};

/*
 * A user stack as unwound live: its pcs, symbolized at replay from the
 * REC_MODULEs of its process (the same binaries, found by path and checked
 * by build-id), on this machine or another.
 */
struct rec_stack {
	__u64 ts;
	__u32 tid;
	__u32 tgid;
	__u32 reason;		/* enum rtsup_unsafe, RTSUP_STACK_FAULT */
	__u32 nr;
	__u32 npcs;
	__u32 kind;		/* the unwinder, enum rtsup_stacks (0 in older recordings) */
	__u64 pcs[RTSUP_STACK_DEPTH];	/* the exact pc, then return addresses */
};

/* One executable file mapping of a process; a new gen starts its set again. */
struct rec_module {
	__u64 start, end, pgoff;
	__u32 tgid;
	__u32 gen;		/* the set of mappings it belongs to */
	__u32 flags;		/* FRAME_REPLACED, FRAME_DELETED */
	__u32 pad;
	char path[256];
	char build_id[48];	/* hex, "" unknown */
};

struct rec_interval {
	__u64 mono_ns;		/* when the interval ended */
	__u64 counters[RTSUP_C_NR];
	double overhead_pct;	/* BPF run time in the interval, % of a CPU; <0 unknown */
};
/* an interval of a recording made before RTSUP_C_DELIM_UNSEEN: 7 counters */
#define REC_INTERVAL_C7	(offsetof(struct rec_interval, counters) + 7 * sizeof(__u64) + \
			 sizeof(double))

struct rec_writer;
struct rec_reader;

/* rec_create - create FILE and write the header; -1 with one line in err */
int rec_create(struct rec_writer **w, const char *path, const struct rec_header *h,
	       char *err, size_t errlen);
/* rec_write - append one record; -1 with one line in err (disk full...) */
int rec_write(struct rec_writer *w, enum rec_type type, const void *payload, size_t len,
	      char *err, size_t errlen);
/* rec_close - flush and close; -1 with one line in err */
int rec_close(struct rec_writer *w, char *err, size_t errlen);

/*
 * rec_open - open FILE and read its header (h->config_text is malloc'd);
 * -1 with one line in err, e.g. "FILE: not an rtsup trace (bad magic)".
 */
int rec_open(struct rec_reader **r, const char *path, struct rec_header *h, char *err,
	     size_t errlen);
/*
 * rec_next - read the next record into buf (at least REC_MAX_PAYLOAD bytes):
 * 1 and *type, *len set; 0 at a clean end of file; -1 with one line in err
 * naming the byte offset, e.g. "FILE: offset 1234: record truncated".
 */
int rec_next(struct rec_reader *r, enum rec_type *type, void *buf, size_t *len,
	     char *err, size_t errlen);
void rec_free(struct rec_reader *r);
/* rec_tell - bytes read so far and the file's size (0 if unknown), for progress */
void rec_tell(const struct rec_reader *r, __u64 *done, __u64 *total);

#endif
