/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * syshooks.h - which syscalls the per-syscall hooks attach to
 * (--syscall-hooks, docs/design.md "Syscall hooks"): every syscall the
 * class table names, and the ones the configuration's rules name. Fixed
 * when the programs are loaded.
 */
#ifndef RTSUP_SYSHOOKS_H
#define RTSUP_SYSHOOKS_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"

enum sys_hooks_mode {
	SYS_HOOKS_AUTO,		/* per-syscall where the kernel attaches them, else raw */
	SYS_HOOKS_PER,		/* per-syscall or fail */
	SYS_HOOKS_RAW,		/* raw_syscalls:sys_enter/sys_exit, every syscall */
};

/*
 * Not auto by default: a kernel releases a syscall's fentry hook with an
 * RCU-tasks grace period, one after the other, so a stop with some fifty
 * hooks took 20 s in a PREEMPT_RT guest (docs/performance.md, "Per-syscall
 * hooks").
 */
#define SYS_HOOKS_DEFAULT SYS_HOOKS_RAW

/* The syscalls per-syscall hooks need: entry stubs and exit stubs. */
struct sys_hookset {
	__u16 in[RTSUP_SYS_IN_SLOTS];	/* a stub on entry */
	int nin;
	__u16 out[RTSUP_SYS_OUT_SLOTS];	/* and on exit: syscalls that may end a cycle */
	int nout;
};

/* Syscalls the rules name by number (config_sys_names), for the plan. */
#define SYS_RULE_NAMES 64
struct sys_rule_names {
	__u16 delims[SYS_RULE_NAMES];	/* a rule's cycle: syscalls: entry and exit */
	int ndelims;
	__u16 forbid[SYS_RULE_NAMES];	/* a rule's forbid: entry */
	int nforbid;
};

/* syshooks_has - is nr hooked on entry (out false) or on exit (out true)? */
bool syshooks_has(const struct sys_hookset *h, int nr, bool out);
/*
 * syshooks_plan - the hooks for a class table (sysclass_build) and the
 * rules' names: every classified syscall on entry; the delimiters and
 * restart_syscall on exit too. -1 with the reason in err when they do
 * not fit the compiled-in stubs.
 */
int syshooks_plan(struct sys_hookset *h, const __u32 *table, size_t n,
		  const struct sys_rule_names *rules, char *err, size_t errlen);
/* syshooks_missing - the first name of rules that h does not hook (a reload's), -1: none */
int syshooks_missing(const struct sys_hookset *h, const struct sys_rule_names *rules);

#endif
