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

/* Key of the map "can_ids": one (interface, identifier, direction). */
struct rtsup_can_key {
	__u32 ifindex;
	__u32 can_id;	/* identifier with the EFF flag, without RTR/ERR */
	__u32 dir;	/* enum rtsup_can_dir */
};

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
	__u32 tx_tid;		/* thread that sent the last frame (tx) */
	__u32 tx_in_cycle;	/* frames sent by a target thread inside a cycle */
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
	v->frames++;
	v->last = now;
	if (can_id & RTSUP_CAN_RTR_FLAG) {
		/* a remote request carries no data: keep the last payload */
		v->rtr++;
		return;
	}
	v->bytes += len;
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
		f->err_frames++;
		f->last_err = now;
		f->err_id = can_id & RTSUP_CAN_EFF_MASK;
		for (i = 0; i < RTSUP_CAN_ERR_CLASSES; i++)
			if (can_id & (1U << i))
				f->err_class[i]++;
		for (i = 0; i < 8; i++)
			f->err_data[i] = i < len ? data[i] : 0;
		return;
	}
	f->frames[dir]++;
	if (!(can_id & RTSUP_CAN_RTR_FLAG))
		f->bytes[dir] += len;
	f->bits[dir] += can_frame_bits(can_id, len, kind);
	if (can_id & RTSUP_CAN_RTR_FLAG)
		f->rtr++;
	if (kind == RTSUP_CAN_FD)
		f->fd++;
	else if (kind == RTSUP_CAN_XL)
		f->xl++;
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
