/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * candump.h - read can-utils candump log files (`candump -l`, `candump -L`):
 *   (1436509052.249713) vcan0 123#1122334455667788
 * one frame per line, for `rtsup-trace can-replay`.
 */
#ifndef RTSUP_CANDUMP_H
#define RTSUP_CANDUMP_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>

struct candump_frame {
	__u64 ts_ns;		/* the log's timestamp, in ns */
	char iface[16];
	__u32 can_id;		/* with RTSUP_CAN_EFF/RTR/ERR flags as in struct can_frame */
	__u32 len;		/* payload length (RTR: the requested length) */
	__u32 kind;		/* enum rtsup_can_kind: CC, FD or XL */
	__u8 fd_flags;		/* CAN FD flags nibble */
	__u8 data[64];
	int dir;		/* RTSUP_CAN_RX, RTSUP_CAN_TX, or -1 when the log does not say */
};

/*
 * candump_parse - parse one line; 1 = a frame, 0 = a line to skip (blank,
 * comment), -1 = malformed, with what is wrong in err (no file or line: the
 * caller prefixes "FILE:LINE: ").
 */
int candump_parse(const char *line, struct candump_frame *f, char *err, size_t errlen);

#endif
