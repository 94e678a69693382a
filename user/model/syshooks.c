// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * syshooks.c - the syscalls the per-syscall hooks attach to. A syscall
 * that is not here is not seen at all with those hooks: its entry costs
 * no thread anything, and a target's counts leave it out.
 */
#include <stdio.h>
#include "model/syshooks.h"
#include "model/syscalls.h"

/* the classes that may end a cycle: their exit releases the next one */
#define SC_ENDS_CYCLE (RTSUP_SC_DELIM | RTSUP_SC_RESTART)

bool syshooks_has(const struct sys_hookset *h, int nr, bool out)
{
	const __u16 *v = out ? h->out : h->in;
	int i, n = out ? h->nout : h->nin;

	for (i = 0; i < n; i++)
		if (v[i] == nr)
			return true;
	return false;
}

/* add - hook nr on entry, and on exit when out; -1 when the stubs are all taken */
static int add(struct sys_hookset *h, int nr, bool out, char *err, size_t errlen)
{
	if (!syshooks_has(h, nr, false)) {
		if (h->nin == RTSUP_SYS_IN_SLOTS) {
			snprintf(err, errlen, "more than %d syscalls to hook on entry",
				 RTSUP_SYS_IN_SLOTS);
			return -1;
		}
		h->in[h->nin++] = nr;
	}
	if (out && !syshooks_has(h, nr, true)) {
		if (h->nout == RTSUP_SYS_OUT_SLOTS) {
			snprintf(err, errlen, "more than %d syscalls that end a cycle",
				 RTSUP_SYS_OUT_SLOTS);
			return -1;
		}
		h->out[h->nout++] = nr;
	}
	return 0;
}

int syshooks_plan(struct sys_hookset *h, const __u32 *table, size_t n,
		  const struct sys_rule_names *rules, char *err, size_t errlen)
{
	size_t nr;
	int i;

	h->nin = h->nout = 0;
	for (nr = 0; nr < n; nr++)
		if (table[nr] && add(h, nr, table[nr] & SC_ENDS_CYCLE, err, errlen))
			return -1;
	for (i = 0; rules && i < rules->ndelims; i++)
		if (add(h, rules->delims[i], true, err, errlen))
			return -1;
	for (i = 0; rules && i < rules->nforbid; i++)
		if (add(h, rules->forbid[i], false, err, errlen))
			return -1;
	return 0;
}

int syshooks_missing(const struct sys_hookset *h, const struct sys_rule_names *rules)
{
	int i;

	for (i = 0; i < rules->ndelims; i++)
		if (!syshooks_has(h, rules->delims[i], true))
			return rules->delims[i];
	for (i = 0; i < rules->nforbid; i++)
		if (!syshooks_has(h, rules->forbid[i], false))
			return rules->forbid[i];
	return -1;
}
