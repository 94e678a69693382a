/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* options.h - rtsup-trace settings, filled from the command line */
#ifndef RTSUP_OPTIONS_H
#define RTSUP_OPTIONS_H

#include <stdbool.h>
#include <linux/types.h>
#include "collect/targets.h"
#include "model/syscalls.h"
#include "model/syshooks.h"

struct options {
	struct targets targets;
	double interval;	/* s */
	double duration;	/* s, 0 = until a signal */
	bool json;
	bool json_active;	/* --json-threads active: intervals list active threads only */
	bool all;		/* --all: the table shows every thread */
	int top;		/* --top: the worst N OK threads the table shows */
	bool verbose;
	bool raw_tp;		/* force the raw tracepoint programs */
	const char *delims[SYSCALLS_MAX_DELIMS];
	int ndelims;
	__u32 ewma_w;		/* per RTSUP_EWMA_ONE */
	__u64 period_ns;	/* nominal period when none is derived */
	__u64 warmup_ns;	/* config defaults' warmup: */
	__u32 max_threads;
	int color;		/* -1 auto, 0 never, 1 always */
	bool delims_given;	/* command-line settings win over the config's defaults */
	bool ewma_given;
	bool period_given;
	const char *config_path;	/* --config */
	const char *check_config;	/* --check-config: validate, print, exit */
	bool check;		/* --check: exit 2 on violations */
	int fail_on;		/* enum level: LEVEL_WARN (default) or LEVEL_ERROR */
	const char *record_path;	/* --record */
	const char *perfetto_path;	/* --perfetto */
	bool no_overhead;	/* --no-overhead: keep BPF statistics off */
	char **cmd;		/* -- CMD ARGS: run and supervise it */
	const char *replay_path;	/* rtsup-trace replay FILE */
	const char *prom_textfile;	/* --prom-textfile: node_exporter textfile */
	const char *listen;	/* --listen ADDR:PORT: HTTP /metrics */
	const char *unit;	/* --unit NAME: a systemd unit's cgroup */
	const char *can_replay_path;	/* rtsup-trace can-replay FILE */
	bool can;		/* --can: supervise CAN interfaces */
	int ncan;		/* --can IFACE given: how many; 0 = every CAN interface */
	const char *can_ifs[8];
	__u32 can_ifindex[8];	/* at start: the kernel counts them under these */
	__u32 can_netns;	/* inode of our network namespace */
	__u64 can_bitrate;	/* --bitrate: overrides what the interface says */
	__u32 can_max_ids;	/* --can-max-ids: capacity of the identifier map */
	bool canopen;		/* from the configuration: CANopen matching in the kernel */
	unsigned int hist;	/* --hist: bit (1 << RTSUP_M_*) per metric to draw */
	bool hist_interval;	/* --hist-interval: every interval's too */
	bool quiet;		/* -q: no progress bar */
	const char *on_level[16];	/* --on-level SPEC, checked by action_parse */
	int non_level;
	bool ros2_diag;		/* --ros2-diagnostics (or the config's ros2_diagnostics:) */
	__u32 stacks;		/* --stacks: enum rtsup_stacks; then the config's defaults */
	__u32 stack_size;	/* --stack-size: DWARF bytes of user stack per event */
	bool stacks_given;	/* --stacks was given: it wins over the file's defaults */
	bool stack_size_given;
	/* from the rules too (stacks_plan in main.c), for the loader */
	bool stack_any;		/* some thread may have stacks */
	bool stack_rules;	/* a rule's stacks differ from the default's */
	bool stack_dwarf;	/* some thread may have DWARF stacks (dwarf or auto) */
	bool stack_auto;	/* some thread has auto: processes get a verdict */
	__u32 stack_size_max;	/* the largest DWARF size */
	__u32 stack_budget;	/* --stack-budget: records per thread per interval */
	__u32 event_buffer;	/* --event-buffer: bytes of the rare events' ring; 0 = the BPF default */
	int sys_hooks;		/* --syscall-hooks: enum sys_hooks_mode */
	struct sys_rule_names sys_rules;	/* the rules' syscalls: hooked too (main.c) */
	bool floor;		/* --floor (hidden): empty programs on the same hooks, for make bench */
};

/* options_parse - parse argv; prints a one-line error and returns -1 on error */
int options_parse(int argc, char **argv, struct options *o);
/*
 * options_parse_flags - the same with argp flags: ARGP_NO_EXIT lets the fuzz
 * target (tests/fuzz) see argp's usage errors as a return, not an exit
 */
int options_parse_flags(int argc, char **argv, struct options *o, unsigned int flags);

/* parse_duration - "30s", "5m", "1h", "250ms" or plain seconds; -1 on error */
double parse_duration(const char *s);

#endif
