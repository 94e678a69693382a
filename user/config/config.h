/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * config.h - the YAML configuration: defaults plus rules matched by process
 * name, thread name (glob) or cgroup, each giving the expected period, the
 * check thresholds, the EWMA weight, the cycle delimiter and syscalls to
 * allow or forbid. Parsed with libyaml; errors say file:line:column.
 */
#ifndef RTSUP_CONFIG_H
#define RTSUP_CONFIG_H

#include <stdbool.h>
#include <stdio.h>
#include <linux/types.h>
#include "config/actionspec.h"
#include "model/syshooks.h"
#include "rtsup.h"

#define CONFIG_MAX_SYSCALLS	16
#define CONFIG_NAME_LEN		64
#define CONFIG_PATH_LEN		256

/* Which statistic "execution time near the period" looks at. */
enum exec_stat {
	EXEC_STAT_P99,
	EXEC_STAT_EWMA,
};

/* Thresholds of the checks; 0 switches a threshold off unless noted. */
struct thresholds {
	double init_timeout_s;		/* seen but no cycle within N s -> WARN */
	__u64 miss_warn;		/* misses in the window >= this -> WARN */
	double miss_error_rate;		/* misses / cycles in the window > this -> ERROR (0..1) */
	double exec_warn_ratio;		/* exec stat > ratio * period -> WARN (0..1+) */
	enum exec_stat exec_stat;
	double starve_warn_periods;	/* no new cycle for k periods -> WARN */
	double starve_error_periods;	/* ... -> ERROR */
	__u64 unsafe_warn;		/* unsafe events in the window >= this -> WARN */
	__u64 unsafe_error[RTSUP_U_NR];	/* per reason: count >= this -> ERROR */
	__u64 latency_p99_warn_ns;
	__u64 latency_max_warn_ns;
	__u64 latency_max_error_ns;
	__u64 jitter_warn_ns;		/* max |period - nominal| in the window */
	__u64 jitter_error_ns;
	double overhead_warn_pct;	/* BPF run time, % of one CPU */
	double overhead_error_pct;
	bool lifetime;			/* also check lifetime totals, not only the window */
};

/* Bits of rule.set: which fields a rule gives (the rest comes from defaults). */
enum rule_field {
	RF_PERIOD = 1 << 0,
	RF_EWMA = 1 << 1,
	RF_DELIMS = 1 << 2,
	RF_POLICY = 1 << 3,
	RF_PRIO = 1 << 4,
	RF_ALLOW = 1 << 5,
	RF_FORBID = 1 << 6,
	RF_WARMUP = 1 << 7,
	RF_STACKS = 1 << 8,
	RF_STACK_SIZE = 1 << 9,
};

struct rule {
	char name[CONFIG_NAME_LEN];
	/* match: every given key must match; none given matches everything */
	char match_process[CONFIG_NAME_LEN];	/* glob on the process name */
	char match_thread[CONFIG_NAME_LEN];	/* glob on the thread name */
	char match_cgroup[CONFIG_PATH_LEN];	/* cgroup v2 path prefix, e.g. /robot.slice */
	__u32 set;				/* RF_* given by this rule */
	__u64 period_ns;			/* expected period, 0 = derive */
	__u64 warmup_ns;			/* start-up lasts at least this */
	double ewma_weight;			/* 0 < w <= 1 */
	char delims[CONFIG_MAX_SYSCALLS][32];	/* cycle delimiter syscalls */
	int ndelims;
	int policy;				/* expected SCHED_*, -1 = any */
	int prio;				/* expected RT priority, -1 = any */
	char allow[CONFIG_MAX_SYSCALLS][32];	/* syscalls that are not unsafe here */
	int nallow;
	char forbid[CONFIG_MAX_SYSCALLS][32];	/* extra syscalls that are unsafe here */
	int nforbid;
	__u32 stacks;				/* enum rtsup_stacks: over --stacks for its threads */
	__u32 stack_size;			/* DWARF: bytes of user stack per event */
	struct thresholds th;			/* merged over the defaults at load */
	int line;				/* where the rule starts in the file */
};

/* Thresholds of one CAN node (or of an identifier no node names). */
struct can_thresholds {
	double warn_periods;		/* not responding: no frame for k periods -> WARN */
	double error_periods;		/* ... -> ERROR */
	__u64 jitter_warn_ns;		/* largest |gap - period| in the window */
	__u64 jitter_error_ns;
	double learn_s;			/* no period given: learn it over the first N s */
	double init_timeout_s;		/* a named node never seen within N s -> WARN */
};

#define CAN_DIR_ANY	-1

/* A named node: an identifier (range) on an interface, in a direction. */
struct can_node {
	char name[CONFIG_NAME_LEN];
	char iface[16];			/* "" = any interface */
	__u32 id_lo;			/* inclusive range; RTSUP_CAN_EFF_FLAG set for 29-bit ids */
	__u32 id_hi;
	int dir;			/* CAN_DIR_ANY, RTSUP_CAN_RX or RTSUP_CAN_TX */
	__u64 period_ns;		/* expected period, 0 = learn it */
	char group[CONFIG_NAME_LEN];	/* "" = none; groups aggregate nodes */
	struct can_thresholds th;	/* merged over can.defaults at load */
	int line;
};

struct can_config {
	bool canopen;			/* CANopen profile: heartbeat, EMCY, SDO */
	__u64 bitrate;			/* when the interface does not tell (vcan), 0 = unknown */
	double busload_warn;		/* ratio of the bitrate, 0 = off */
	double busload_error;
	__u64 err_warn;			/* error frames in the window >= this -> WARN, 0 = off */
	__u64 err_error;
	__u64 heartbeat_timeout_ns;	/* CANopen: no heartbeat for this long -> ERROR */
	struct can_thresholds defaults;	/* for every identifier, and the base of each node */
	struct can_node *nodes;
	int nnodes;
};

struct config {
	char path[CONFIG_PATH_LEN];	/* "" when built in */
	struct rule defaults;
	struct rule *rules;
	int nrules;
	struct can_config can;
	struct action *actions;		/* actions: then --on-level, in that order */
	int nactions;
	bool ros2_diagnostics;		/* publish ROS 2 /diagnostics (robot/ros2diag.c) */
};

/* What the rules' stacks: ask of the kernel side, fixed when it is loaded. */
struct stack_plan {
	__u32 kind;		/* the defaults' (enum rtsup_stacks): threads no rule changes */
	__u32 size;
	bool any;		/* some thread may have stacks */
	bool rules;		/* a rule's stacks or size differ from the defaults' */
	bool dwarf;		/* some thread may have DWARF stacks (dwarf or auto) */
	bool autos;		/* some thread has auto: processes need a verdict */
	__u32 size_max;		/* the largest size of those */
};

/* config_defaults - the built-in configuration (no file) */
void config_defaults(struct config *c);
/*
 * config_load - parse a file; on error return -1 and write one line
 * "file:line:column: what is wrong" into err. *c is untouched on error.
 */
int config_load(const char *path, struct config *c, char *err, size_t errlen);
/*
 * config_match - the effective rule of a thread: the defaults with the
 * first matching rule applied over them; returns that rule's index or -1.
 */
int config_match(const struct config *c, const char *process, const char *thread,
		 const char *cgroup, struct rule *effective);
/*
 * config_can_node - the first node naming (interface, identifier, direction),
 * its index or -1; id is the counted identifier (EFF flag for 29-bit ids)
 */
int config_can_node(const struct config *c, const char *iface, __u32 id, int dir);
/* config_stack_plan - the stacks every rule may ask for (after the command line's) */
void config_stack_plan(const struct config *c, struct stack_plan *p);
/* config_sys_names - the syscalls the rules name (per-syscall hooks must cover them) */
void config_sys_names(const struct config *c, struct sys_rule_names *n);
/* config_add_action - append an action (--on-level); -1 when ACTION_MAX are there */
int config_add_action(struct config *c, const struct action *a);
/* config_print - the effective configuration, in the file's YAML form */
void config_print(const struct config *c, FILE *out);
void config_free(struct config *c);

#endif
