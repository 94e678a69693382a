/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * can.h - CAN frame accounting, shared by the BPF programs, the live
 * collector and the candump log replay: one function per frame, so the
 * kernel and `rtsup-trace can-replay` compute the same numbers.
 *
 * The uapi layout of CAN frames is declared here: a kernel built without
 * CAN has none of it in its BTF.
 */
#ifndef RTSUP_CAN_H
#define RTSUP_CAN_H

#include "rtsup.h"
#include "stats.h"

#define RTSUP_CAN_EFF_FLAG	0x80000000U	/* 29-bit identifier */
#define RTSUP_CAN_RTR_FLAG	0x40000000U	/* remote transmission request */
#define RTSUP_CAN_ERR_FLAG	0x20000000U	/* error frame */
#define RTSUP_CAN_SFF_MASK	0x000007FFU
#define RTSUP_CAN_EFF_MASK	0x1FFFFFFFU

#define RTSUP_ETH_P_CAN		0x000C
#define RTSUP_ETH_P_CANFD	0x000D
#define RTSUP_ETH_P_CANXL	0x000E

#define RTSUP_CAN_ERR_CLASSES	10	/* CAN_ERR_TX_TIMEOUT .. CAN_ERR_CNT */
#define RTSUP_CAN_ERR_CRTL	0x00000004U	/* controller problems, data[1] */
#define RTSUP_CAN_ERR_BUSOFF	0x00000040U
#define RTSUP_CAN_ERR_CRTL_RX_PASSIVE	0x10
#define RTSUP_CAN_ERR_CRTL_TX_PASSIVE	0x20
#define RTSUP_CAN_ERR_CRTL_RX_WARNING	0x04
#define RTSUP_CAN_ERR_CRTL_TX_WARNING	0x08

/* The frame layouts of include/uapi/linux/can.h. */
struct rtsup_can_frame {
	__u32 can_id;
	__u8 len;
	__u8 flags;	/* CAN FD flags; len8_dlc padding for classic CAN */
	__u8 res0;
	__u8 res1;
	__u8 data[8];	/* the first 8 bytes of a CAN FD payload too */
};

struct rtsup_canxl_head {
	__u32 prio;	/* 11-bit priority: the arbitration identifier */
	__u8 flags;
	__u8 sdt;
	__u16 len;
	__u32 af;
};

enum rtsup_can_dir {
	RTSUP_CAN_RX,
	RTSUP_CAN_TX,
	RTSUP_CAN_DIRS,
};

/* Frame kinds, from the skb protocol. */
enum rtsup_can_kind {
	RTSUP_CAN_CC,	/* classical CAN */
	RTSUP_CAN_FD,
	RTSUP_CAN_XL,
};

/*
 * Key of the map "can_ids": one (interface, identifier, direction). An
 * interface is (network namespace, ifindex): every namespace numbers its
 * own from 1, so a container's vcan0 may have the host's vcan0's ifindex.
 */
struct rtsup_can_key {
	__u32 ifindex;
	__u32 can_id;	/* identifier with the EFF flag, without RTR/ERR */
	__u32 dir;	/* enum rtsup_can_dir */
	__u32 netns;	/* inode of the interface's network namespace, 0 in a replay */
};

/* Key of the map "can_ifs": an interface of any namespace. */
struct rtsup_can_ifkey {
	__u32 netns;
	__u32 ifindex;
};

/*
 * A --can interface: the kernel counts its frames under 'key', the ifindex
 * it had when rtsup-trace started, so that an interface removed and added
 * again (a USB adapter re-plugged: a new ifindex) keeps its counters.
 * Userspace rewrites 'ifindex' when the name comes back.
 */
struct rtsup_can_watch {
	__u32 netns;
	__u32 ifindex;	/* now; 0 while the interface is gone */
	__u32 key;	/* the ifindex its frames are counted under */
};
#define RTSUP_CAN_WATCH	8

#define RTSUP_NETDEV_TX_OK	0x00

/*
 * A frame offered to a driver: net_dev_start_xmit stashes it on its CPU,
 * net_dev_xmit counts it once the driver took it (NETDEV_TX_OK). A driver
 * that answers NETDEV_TX_BUSY is offered the frame again later: counted
 * once. The skb may be freed by net_dev_xmit: only its address is compared.
 */
struct rtsup_can_tx {
	__u64 skb;		/* the offered skb, 0: none */
	struct rtsup_can_key key;
	struct rtsup_can_frame f;
	__u32 len;
	__u32 kind;		/* enum rtsup_can_kind */
};

/* can_tx_taken - net_dev_xmit of 'skb' returned 'rc': is the stashed frame sent? */
RTSUP_INLINE int can_tx_taken(struct rtsup_can_tx *s, __u64 skb, int rc)
{
	if (!s->skb || s->skb != skb)
		return 0;
	s->skb = 0;	/* taken or not, this offer is over; a retry stashes again */
	return rc == RTSUP_NETDEV_TX_OK;
}

/* Per (interface, identifier, direction): counts and inter-frame gaps. */
struct rtsup_can_id {
	__u64 frames;
	__u64 bytes;
	__u64 rtr;
	__u64 first;		/* first seen, CLOCK_MONOTONIC ns */
	__u64 last;		/* last seen */
	__u32 epoch;		/* interval whose bank the gap stats write to */
	__u32 len;		/* payload length of the last frame */
	__u8 data[8];		/* first bytes of the last payload (CANopen state, EMCY code) */
	__u32 tx_tid;		/* thread that sent the last frame (tx), 0: the kernel */
	__u32 tx_in_cycle;	/* frames sent by a target thread inside a cycle */
	__u64 tx_kernel;	/* frames the kernel sent on its own (timer, softirq, kthread) */
	__u64 tx_offset_sum;	/* time from its cycle's start to the send, summed */
	__u64 tx_offset_max;
	__u64 resp_count;	/* CANopen SDO: responses matched to a request */
	__u64 resp_sum;		/* request -> response time, summed */
	__u64 resp_max;
	struct rtsup_metric_stats gap;	/* time since the previous frame of this key */
};

/* Per interface: array can_if_slot by ifindex, map "can_ifs" above that. */
#define RTSUP_CAN_IF_SLOTS	256

struct rtsup_can_if {
	__u64 frames[RTSUP_CAN_DIRS];
	__u64 bytes[RTSUP_CAN_DIRS];
	__u64 bits[RTSUP_CAN_DIRS];	/* on the wire, worst-case bit stuffing */
	__u64 loopback;			/* local echoes of our own sends, not counted as rx */
	__u64 rtr;
	__u64 fd;
	__u64 xl;
	__u64 err_frames;
	__u64 err_class[RTSUP_CAN_ERR_CLASSES];	/* by CAN_ERR_* bit of the id */
	__u64 last_err;			/* time of the last error frame */
	__u32 err_id;			/* the last error frame's class bits */
	__u8 err_data[8];		/* and its data: controller state in data[1] */
	__u32 pad;
};

/*
 * can_frame_bits - bits a frame takes on the wire, with worst-case bit
 * stuffing as can-utils' canbusload estimates it (CFL_WORSTCASE): the
 * 34 (SFF) or 54 (EFF) bits before the data plus the data can need one
 * stuff bit every 4. CAN FD and XL are counted at the nominal bitrate,
 * which overestimates their data phase.
 */
RTSUP_INLINE __u32 can_frame_bits(__u32 can_id, __u32 len, __u32 kind)
{
	__u32 eff = can_id & RTSUP_CAN_EFF_FLAG;
	__u32 bits;

	if (kind == RTSUP_CAN_CC) {
		if (can_id & RTSUP_CAN_RTR_FLAG)
			len = 0;
		if (len > 8)
			len = 8;
		bits = (eff ? 67 : 47) + 8 * len;
		return bits + ((eff ? 54 : 34) + 8 * len - 1) / 4;
	}
	/* FD: 17- or 21-bit CRC and the stuff count, same worst-case rule */
	bits = (eff ? 80 : 61) + 8 * len + (len > 16 ? 4 : 0);
	return bits + ((eff ? 54 : 34) + 8 * len - 1) / 4;
}

/* can_key_id - the identifier a frame is counted under */
RTSUP_INLINE __u32 can_key_id(__u32 can_id)
{
	if (can_id & RTSUP_CAN_EFF_FLAG)
		return can_id & (RTSUP_CAN_EFF_MASK | RTSUP_CAN_EFF_FLAG);
	return can_id & RTSUP_CAN_SFF_MASK;
}

/*
 * CAN_ADD - a counter that frames on other CPUs bump at the same time (rx
 * on every CPU that a sender ran on, tx and rx of one interface): one
 * atomic add, no lost increment. The gap statistics and the last payload
 * of an identifier are plain stores: two frames of one identifier, in one
 * direction, accounted in the same ~100 ns on two CPUs may lose one gap.
 */
#define CAN_ADD(p, n) __sync_fetch_and_add(p, n)

/* can_id_account - one frame of a key at time 'now' */
RTSUP_INLINE void can_id_account(struct rtsup_can_id *v, __u64 now, __u32 can_id,
				 __u32 len, const __u8 *data, __u32 ewma_w, __u32 epoch)
{
	__u32 i;

	if (v->epoch != epoch) {
		v->epoch = epoch;
		minmax_reset(&v->gap.win[RTSUP_BANK(epoch)]);
	}
	if (v->frames && now >= v->last)
		metric_add(&v->gap, now - v->last, ewma_w, epoch);
	if (!v->frames)
		v->first = now;
	CAN_ADD(&v->frames, 1);
	v->last = now;
	if (can_id & RTSUP_CAN_RTR_FLAG) {
		/* a remote request carries no data: keep the last payload */
		CAN_ADD(&v->rtr, 1);
		return;
	}
	CAN_ADD(&v->bytes, len);
	v->len = len;
	for (i = 0; i < 8; i++)
		v->data[i] = i < len ? data[i] : 0;
}

/* can_if_account - one frame of an interface (not a loopback echo) */
RTSUP_INLINE void can_if_account(struct rtsup_can_if *f, __u64 now, __u32 dir, __u32 can_id,
				 __u32 len, __u32 kind, const __u8 *data)
{
	__u32 i;

	if (dir >= RTSUP_CAN_DIRS)
		return;
	if (can_id & RTSUP_CAN_ERR_FLAG) {
		/* a report of the controller, not a frame on the bus */
		CAN_ADD(&f->err_frames, 1);
		f->last_err = now;
		f->err_id = can_id & RTSUP_CAN_EFF_MASK;
		for (i = 0; i < RTSUP_CAN_ERR_CLASSES; i++)
			if (can_id & (1U << i))
				CAN_ADD(&f->err_class[i], 1);
		for (i = 0; i < 8; i++)
			f->err_data[i] = i < len ? data[i] : 0;
		return;
	}
	CAN_ADD(&f->frames[dir], 1);
	if (!(can_id & RTSUP_CAN_RTR_FLAG))
		CAN_ADD(&f->bytes[dir], len);
	CAN_ADD(&f->bits[dir], can_frame_bits(can_id, len, kind));
	if (can_id & RTSUP_CAN_RTR_FLAG)
		CAN_ADD(&f->rtr, 1);
	if (kind == RTSUP_CAN_FD)
		CAN_ADD(&f->fd, 1);
	else if (kind == RTSUP_CAN_XL)
		CAN_ADD(&f->xl, 1);
}

/* can_is_sdo_response - CANopen: 0x581..0x5FF, an SDO server's answer */
RTSUP_INLINE int can_is_sdo_response(__u32 id)
{
	return !(id & RTSUP_CAN_EFF_FLAG) && (id & 0x780) == 0x580 && (id & 0x7f);
}

/*
 * can_sdo_match - CANopen: a response answers the request (0x600+n, the id
 * plus 0x80) sent after the previous response; call before accounting the
 * response. Returns 1 when matched.
 */
RTSUP_INLINE int can_sdo_match(struct rtsup_can_id *resp, const struct rtsup_can_id *req,
			       __u64 now)
{
	__u64 t;

	if (!req || !req->last || req->last > now || req->last <= resp->last)
		return 0;
	t = now - req->last;
	resp->resp_count++;
	resp->resp_sum += t;
	if (t > resp->resp_max)
		resp->resp_max = t;
	return 1;
}

#endif /* RTSUP_CAN_H */
