// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * fpcheck.c - --stacks auto: frame pointers kept or omitted, read from a
 * module's call frame information with libdw (no parser of our own)
 */
#include <stdlib.h>
#include <string.h>
#include <gelf.h>
#include <elfutils/libdw.h>
#include <dwarf.h>
#include "collect/fpcheck.h"
#include "rtsup.h"

#define FP_SAMPLES	256	/* addresses looked at per module */

/* the frame pointer in DWARF numbering: the CFA is defined through it */
#if defined(__x86_64__)
#define FP_REG	6	/* rbp */
#elif defined(__aarch64__)
#define FP_REG	29	/* x29 */
#else
#define FP_REG	-1
#endif

enum fp_verdict fp_verdict_of(unsigned int n, unsigned int fp)
{
	if (n < FP_MIN_SAMPLES)
		return FP_UNKNOWN;
	/* without: a few functions with alloca or realigned stacks; with: nearly all */
	return fp * 2 >= n ? FP_KEPT : FP_OMITTED;
}

__u32 fp_process_kind(const enum fp_verdict *v, int n)
{
	int i, kept = 0;

	for (i = 0; i < n; i++) {
		if (v[i] == FP_OMITTED)
			return RTSUP_STACKS_DWARF;
		kept += v[i] == FP_KEPT;
	}
	return kept ? RTSUP_STACKS_FP : RTSUP_STACKS_DWARF;
}

/* code_section - an executable section of code proper (not PLT stubs, init, fini) */
static int code_section(Elf *elf, size_t shstrndx, Elf_Scn *scn, GElf_Shdr *sh)
{
	const char *name;

	if (!gelf_getshdr(scn, sh) || sh->sh_type != SHT_PROGBITS ||
	    !(sh->sh_flags & SHF_EXECINSTR) || !sh->sh_size)
		return 0;
	name = elf_strptr(elf, shstrndx, sh->sh_name);
	return name && strncmp(name, ".plt", 4) && strcmp(name, ".init") && strcmp(name, ".fini");
}

/* cfa_through_fp - is the CFA at addr defined through the frame pointer? -1: no CFI */
static int cfa_through_fp(Dwarf_CFI *cfi, Dwarf_Addr addr)
{
	Dwarf_Frame *fr = NULL;
	Dwarf_Op *ops;
	size_t nops;
	int r = -1;

	if (dwarf_cfi_addrframe(cfi, addr, &fr))
		return -1;
	/* a register plus an offset is DW_OP_bregx (libdw), or DW_OP_bregN in an expression */
	if (!dwarf_frame_cfa(fr, &ops, &nops) && nops)
		r = ops[0].atom == DW_OP_bregx ? ops[0].number == FP_REG :
		    ops[0].atom == DW_OP_breg0 + FP_REG;
	free(fr);
	return r;
}

enum fp_verdict fp_elf_check(Elf *elf)
{
	Dwarf_CFI *cfi;
	Elf_Scn *scn = NULL;
	GElf_Shdr sh;
	size_t shstrndx;
	__u64 total = 0, at, step;
	unsigned int n = 0, fp = 0, k;
	int r;

	if (FP_REG < 0 || !elf || elf_getshdrstrndx(elf, &shstrndx))
		return FP_UNKNOWN;
	while ((scn = elf_nextscn(elf, scn)))
		if (code_section(elf, shstrndx, scn, &sh))
			total += sh.sh_size;
	cfi = total ? dwarf_getcfi_elf(elf) : NULL;
	if (!cfi)
		return FP_UNKNOWN;
	/* evenly spaced over all the code, each in the middle of its slice */
	step = total / FP_SAMPLES ? total / FP_SAMPLES : 1;
	for (k = 0, at = step / 2; k < FP_SAMPLES && at < total; k++, at += step) {
		__u64 off = at;

		for (scn = NULL; (scn = elf_nextscn(elf, scn));) {
			if (!code_section(elf, shstrndx, scn, &sh))
				continue;
			if (off < sh.sh_size)
				break;
			off -= sh.sh_size;
		}
		if (!scn)
			break;
		r = cfa_through_fp(cfi, sh.sh_addr + off);
		if (r < 0)
			continue;
		n++;
		fp += r;
	}
	dwarf_cfi_end(cfi);
	return fp_verdict_of(n, fp);
}
