/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * cancollect.h - kernel CAN maps -> CAN model, once per interval; the
 * interfaces' names and bitrates from netlink (libnl).
 */
#ifndef RTSUP_CANCOLLECT_H
#define RTSUP_CANCOLLECT_H

#include "model/canmodel.h"
#include "options.h"

struct rtsup_bpf;

/* can_resolve - --can names to interface indexes; one-line error, -1 */
int can_resolve(struct options *o);
/* can_collect - read the CAN maps into the model */
void can_collect(struct can_model *m, struct rtsup_bpf *skel, const struct options *o,
		 const struct config *cfg);
/* can_bitrate - the bitrate netlink reports for a CAN interface, 0 if none */
__u64 can_bitrate(__u32 ifindex);

#endif
