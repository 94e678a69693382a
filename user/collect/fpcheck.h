/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * fpcheck.h - --stacks auto: does a process's code keep frame pointers?
 *
 * A module keeps them when its call frame information (.eh_frame, which
 * strip leaves) defines the frame's address through the frame pointer in
 * the body of most of its code: sampled at evenly spaced addresses of its
 * executable sections. A frame-pointer walk is only as good as its weakest
 * frame, and RT-unsafe calls are made inside the C library: a process is
 * "fp" only when every module it maps keeps them (Debian's glibc does not,
 * so there auto is DWARF; a distribution built with frame pointers, or a
 * program without the C library, gets fp).
 */
#ifndef RTSUP_FPCHECK_H
#define RTSUP_FPCHECK_H

#include <linux/types.h>

enum fp_verdict {
	FP_UNKNOWN,	/* too little call frame information to tell */
	FP_KEPT,	/* built with frame pointers */
	FP_OMITTED,	/* built without them */
};

#define FP_MIN_SAMPLES	8	/* fewer samples with CFI: unknown */

/* fp_verdict_of - a module's verdict from its samples: n with CFI, fp of them through it */
enum fp_verdict fp_verdict_of(unsigned int n, unsigned int fp);
/*
 * fp_process_kind - a process's unwinder from its modules' verdicts:
 * RTSUP_STACKS_FP when one keeps frame pointers and none omits them,
 * else RTSUP_STACKS_DWARF
 */
__u32 fp_process_kind(const enum fp_verdict *v, int n);

struct Elf;
/* fp_elf_check - sample the CFI of an ELF file's code (libdw) */
enum fp_verdict fp_elf_check(struct Elf *elf);

#endif
