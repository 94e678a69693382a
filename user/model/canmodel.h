/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * canmodel.h - what userspace knows about the CAN buses: per (interface,
 * identifier, direction) and per interface, the last two snapshots of the
 * kernel's counters; the components judged from them (interfaces, named
 * nodes and their groups, identifiers no node names, CANopen nodes) and
 * their checks. Plain C: the live collector and the candump replay fill it,
 * the unit tests drive it.
 */
#ifndef RTSUP_CANMODEL_H
#define RTSUP_CANMODEL_H

#include <stdbool.h>
#include "can.h"
#include "config/config.h"
#include "model/model.h"
#include "judge/status.h"

#define CANMODEL_MAX_IFS	16
#define CANOPEN_NODES		128

/* Learning an identifier's period: the gaps of a run of intervals (canmodel.c learn). */
struct can_learn {
	__u64 since;			/* start of this learning run, 0 = not started */
	__u64 count;			/* gaps seen in the run */
	double sum;			/* their sum, ns */
	__u64 min, max;			/* the smallest and largest */
	__u32 irregular;		/* learned: intervals in a row whose gaps were not steady */
};

struct can_entry {
	struct rtsup_can_key key;
	struct can_learn learning;
	struct rtsup_can_id cur;
	struct rtsup_can_id prev;	/* one interval ago */
	bool have_prev;
	__u64 *gap_life;		/* gap bucket counts up to prev, summed: no wrap */
	int node;			/* configured node, -1 = none */
	__u64 learned;			/* learned period, ns (0 = not yet) */
	struct status st;		/* verdict when no node names it */
	enum level worst;
};

struct can_iface {
	__u32 netns;			/* network namespace inode (0: a replay) */
	__u32 ifindex;			/* as the kernel counts it (can.h rtsup_can_watch) */
	char name[40];			/* "vcan0", "vcan0@ns" in another namespace */
	__u32 dev_ifindex;		/* its ifindex now; 0: removed (--can IFACE follows it) */
	__u64 bitrate;			/* bit/s, 0 = unknown */
	struct rtsup_can_if cur;
	struct rtsup_can_if prev;
	bool have_prev;
	double load;			/* bus load of the last interval, ratio; <0 unknown */
	/* the link as netlink says (can_iface_link); unknown in a replay */
	bool link_known, link_up;
	int ctrl_state;			/* CAN_STATE_* of a real controller, -1 none (vcan) */
	__u64 err_mark;			/* error frames before the link last came up */
	struct status st;
	enum level worst;
};

/* A configured node: its identifiers' numbers together. */
struct can_node_view {
	__u64 frames;			/* in total */
	__u64 frames_win;		/* in the last interval */
	__u64 last;			/* last frame of any of its identifiers, 0 = never */
	__u64 period;			/* configured, or learned */
	struct metric_view gap;		/* of the last interval, over its identifiers */
	struct metric_view gap_life;	/* since it was first seen */
	struct status st;
	enum level worst;
};

/* A CANopen node (1..127) of one bus, from the COB-IDs of its frames. */
struct canopen_node {
	bool seen;
	__u64 heartbeat_last;		/* 0x700+n */
	__u8 nmt_state;
	__u64 emcy_frames;		/* 0x080+n, in total */
	__u64 emcy_prev;		/* at the end of the previous interval */
	__u16 emcy_code;		/* error code of the last EMCY */
	__u8 emcy_reg;			/* error register */
	__u64 sdo_count;		/* SDO responses matched to requests */
	__u64 sdo_sum;
	__u64 sdo_max;
	struct status st;
	enum level worst;
};

#define CANMODEL_MAX_GROUPS	32

/* A group of configured nodes (e.g. left_arm): the worst of its nodes. */
struct can_group_view {
	char name[CONFIG_NAME_LEN];
	struct status st;
	enum level worst;
};

struct can_model {
	struct can_entry *e;		/* sorted by key */
	int n;
	int cap;
	struct can_iface ifs[CANMODEL_MAX_IFS];
	int nifs;
	struct can_node_view *nodes;	/* one per configured node */
	int nnodes;
	struct canopen_node co[CANMODEL_MAX_IFS][CANOPEN_NODES];	/* by interface slot */
	struct can_group_view groups[CANMODEL_MAX_GROUPS];
	int ngroups;
	__u64 start_ns;			/* when supervision started */
	__u32 bank;			/* interval bank of the last sample */
	__u64 full;			/* frames whose identifier did not fit the map */
};

/* can_entry_get - the entry of a key, created when 'create' */
struct can_entry *can_entry_get(struct can_model *m, const struct rtsup_can_key *k,
				bool create);
/*
 * can_iface_link - what netlink says of the interface now: up or down, and
 * the controller's CAN_STATE_* (-1: none, a vcan). A link that comes up
 * again (ip link down/up, a restart, a re-plugged adapter) forgets what
 * earlier error frames said of the controller.
 */
void can_iface_link(struct can_iface *f, bool up, int ctrl_state);

/* Controller states rtsup judges, worst last. */
enum can_ctrl {
	CAN_CTRL_OK,
	CAN_CTRL_PASSIVE_RX,
	CAN_CTRL_PASSIVE_TX,
	CAN_CTRL_BUSOFF,
	CAN_CTRL_DOWN,
};

/*
 * can_iface_ctrl - the controller's state: netlink's where the controller
 * reports one, else what the last error frame since the link came up said
 */
enum can_ctrl can_iface_ctrl(const struct can_iface *f);

/* can_iface_get - the interface (netns, ifindex), created when 'create' */
struct can_iface *can_iface_get(struct can_model *m, __u32 netns, __u32 ifindex, bool create);
/* can_model_next - end of an interval: current snapshots become previous */
void can_model_next(struct can_model *m);
void can_model_free(struct can_model *m);

/*
 * can_model_judge - match identifiers to nodes, learn periods, run the CAN
 * checks at 'now' for the interval of length 'interval_s'; level changes and
 * violations go through 'judge' with the component's name.
 */
typedef void (*can_judge_fn)(void *ctx, const char *component, const struct status *old,
			     const struct status *st, enum level *worst);
void can_model_judge(struct can_model *m, const struct config *cfg, __u64 now,
		     double interval_s, can_judge_fn judge, void *ctx);

/* can_iface_name - name of an interface of the model, "?" if unknown */
const char *can_iface_name(const struct can_model *m, __u32 netns, __u32 ifindex);
/* can_component - a display name: "can0 0x123 rx", or a node's name */
void can_component(const struct can_model *m, const struct can_entry *e, char *buf,
		   size_t len);
/* can_worst - the worst level any CAN component reached */
enum level can_worst(const struct can_model *m);
/* can_nmt_name - "operational", "pre-operational", ... */
const char *can_nmt_name(__u8 state);

/*
 * can_gap_life - an identifier's lifetime gap bucket counts (HIST_BUCKETS):
 * the kernel's __u32 buckets wrap, so can_model_next sums each interval's
 * difference into 64-bit counts, and this adds the current interval's
 */
void can_gap_life(const struct can_entry *e, __u64 *h);
/* can_gap_view_life - an identifier's lifetime gap view, from those counts */
void can_gap_view_life(const struct can_entry *e, struct metric_view *v);

#endif
