// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* statsfloor.c - an empty program's run time under the BPF statistics (statsfloor.h) */
#include <errno.h>
#include <string.h>
#include <unistd.h>
#include <bpf/bpf.h>
#include <linux/bpf.h>
#include "collect/statsfloor.h"

#define FLOOR_BATCHES	3
#define FLOOR_RUNS	200	/* a batch: about 10-20 us */

void stats_floor_init(struct stats_floor *f)
{
	*f = STATS_FLOOR_NONE;
}

/* floor_load - "return 0": a socket filter, the oldest type the kernel test-runs in a loop */
static int floor_load(struct stats_floor *f)
{
	const struct bpf_insn empty[] = {
		{ .code = BPF_ALU64 | BPF_MOV | BPF_K, .dst_reg = BPF_REG_0, .imm = 0 },
		{ .code = BPF_JMP | BPF_EXIT },
	};

	if (f->fd >= 0 || f->err)
		return f->fd;
	f->fd = bpf_prog_load(BPF_PROG_TYPE_SOCKET_FILTER, "rtsup_floor", "Dual BSD/GPL", empty,
			      sizeof(empty) / sizeof(empty[0]), NULL);
	if (f->fd < 0)
		f->err = -errno;
	return f->fd;
}

/* floor_counts - the program's runs and run time so far; -1 */
static int floor_counts(int fd, __u64 *runs, __u64 *ns)
{
	struct bpf_prog_info info;
	__u32 len = sizeof(info);

	memset(&info, 0, sizeof(info));
	if (bpf_obj_get_info_by_fd(fd, &info, &len))
		return -1;
	*runs = info.run_cnt;
	*ns = info.run_time_ns;
	return 0;
}

double stats_floor_measure(struct stats_floor *f)
{
	char pkt[64] = { 0 };	/* a frame the size of the smallest Ethernet one */
	LIBBPF_OPTS(bpf_test_run_opts, run, .data_in = pkt, .data_size_in = sizeof(pkt),
		    .repeat = FLOOR_RUNS);
	__u64 r0, t0, r1, t1;
	double best = -1, per;
	int i;

	if (floor_load(f) < 0)
		return -1;
	for (i = 0; i < FLOOR_BATCHES; i++) {
		if (floor_counts(f->fd, &r0, &t0) || bpf_prog_test_run_opts(f->fd, &run) ||
		    floor_counts(f->fd, &r1, &t1) || r1 <= r0)
			return -1;
		per = (double)(t1 - t0) / (double)(r1 - r0);
		if (best < 0 || per < best)
			best = per;
	}
	return best;
}

void stats_floor_close(struct stats_floor *f)
{
	if (f->fd >= 0)
		close(f->fd);
	stats_floor_init(f);
}
