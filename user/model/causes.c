// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* causes.c - deadline misses grouped by cause and culprit, and their text */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "model/causes.h"
#include "model/model.h"
#include "model/syscalls.h"

static const char *const kind_names[RTSUP_CAUSE_NR] = {
	[RTSUP_CAUSE_NONE] = "none",
	[RTSUP_CAUSE_TIMER] = "timer",
	[RTSUP_CAUSE_WAIT] = "wait",
	[RTSUP_CAUSE_PREEMPT] = "preemption",
	[RTSUP_CAUSE_BLOCK] = "block",
	[RTSUP_CAUSE_BACKLOG] = "backlog",
	[RTSUP_CAUSE_EXEC] = "exec",
	[RTSUP_CAUSE_STEAL] = "steal",
};

const char *cause_kind_name(__u32 kind)
{
	return kind < RTSUP_CAUSE_NR ? kind_names[kind] : "unknown";
}

static const char *const mig_names[RTSUP_MIG_NR] = {
	[RTSUP_MIG_UNKNOWN] = "unknown",
	[RTSUP_MIG_WAKEUP] = "wakeup",
	[RTSUP_MIG_AFFINITY] = "affinity",
	[RTSUP_MIG_BALANCE] = "balance",
};

const char *mig_why_name(__u32 why)
{
	return why < RTSUP_MIG_NR ? mig_names[why] : "unknown";
}

/* mig_text - "; migrated CPU 0 -> 1 (affinity change)", or "" */
static void mig_text(char *buf, size_t len, const struct rtsup_cause *d)
{
	static const char *const how[RTSUP_MIG_NR] = {
		[RTSUP_MIG_UNKNOWN] = "", [RTSUP_MIG_WAKEUP] = " (placed at its wakeup)",
		[RTSUP_MIG_AFFINITY] = " (affinity change)", [RTSUP_MIG_BALANCE] = " (load balance)",
	};
	char from[16] = "?";

	buf[0] = '\0';
	if (!d || !d->migrations)
		return;
	if (d->mig_from != RTSUP_MIG_NOCPU)
		snprintf(from, sizeof(from), "%u", d->mig_from);
	if (d->migrations > 1)
		snprintf(buf, len, "; migrated %u times, last CPU %s -> %u%s", d->migrations, from,
			 d->mig_to, how[d->mig_why < RTSUP_MIG_NR ? d->mig_why : 0]);
	else
		snprintf(buf, len, "; migrated CPU %s -> %u%s", from, d->mig_to,
			 how[d->mig_why < RTSUP_MIG_NR ? d->mig_why : 0]);
}

/* group_after - what a miss's group keeps of its 'after': a backlog's only */
static __u32 group_after(const struct rtsup_cause *c)
{
	return c->kind == RTSUP_CAUSE_BACKLOG ? c->after : 0;
}

/* same_group - one group per thread, kind and culprit (and a backlog's after) */
static int same_group(const struct cause_group *g, __u32 tid, const struct rtsup_cause *c)
{
	return g->tid == tid && g->kind == c->kind && g->who.tid == c->who.tid &&
	       !strncmp(g->who.comm, c->who.comm, RTSUP_COMM_LEN) && g->after == group_after(c);
}

/* group_hash - the slot a group of thread tid with cause kind, culprit and after starts at */
static size_t group_hash(__u32 tid, __u32 kind, __u32 who, __u32 after, size_t cap)
{
	__u64 h = ((__u64)tid * 0x9e3779b97f4a7c15ULL) ^ ((__u64)who * 0xc2b2ae3d27d4eb4fULL) ^
		  ((__u64)(kind << 8 | after) * 0x165667b19e3779f9ULL);

	return (size_t)(h ^ h >> 29) & (cap - 1);
}

/* index_due - the index must grow (or be made) to hold n groups: at most half full */
static int index_due(size_t index_cap, size_t n)
{
	return index_cap < 2 * n || index_cap < 16;
}

static size_t slot_of(const struct causes *cs, const struct cause_group *g)
{
	return group_hash(g->tid, g->kind, g->who.tid, g->after, cs->index_cap);
}

/* index_put - group i into the index (it has room: index_due) */
static void index_put(struct causes *cs, size_t i)
{
	size_t k = slot_of(cs, &cs->g[i]);

	while (cs->index[k])
		k = (k + 1) & (cs->index_cap - 1);
	cs->index[k] = (__u32)i + 1;
}

/*
 * index_rebuild - every group into an index of cap slots: it grew, or the
 * groups moved (causes_sort). -1 without memory: the index is dropped and
 * causes_add walks the groups, as it did before it had one.
 */
static int index_rebuild(struct causes *cs, size_t cap)
{
	size_t i;

	if (cap != cs->index_cap) {
		__u32 *x = realloc(cs->index, cap * sizeof(*x));

		if (!x) {
			free(cs->index);
			cs->index = NULL;
			cs->index_cap = 0;
			return -1;
		}
		cs->index = x;
		cs->index_cap = cap;
	}
	memset(cs->index, 0, cap * sizeof(*cs->index));
	for (i = 0; i < cs->n; i++)
		index_put(cs, i);
	return 0;
}

/* find_group - the group of thread tid that miss c belongs to, NULL if none yet */
static struct cause_group *find_group(const struct causes *cs, __u32 tid,
				      const struct rtsup_cause *c)
{
	size_t i, k;

	if (!cs->index) {
		for (i = 0; i < cs->n; i++)
			if (same_group(&cs->g[i], tid, c))
				return &cs->g[i];
		return NULL;
	}
	for (k = group_hash(tid, c->kind, c->who.tid, group_after(c), cs->index_cap); cs->index[k];
	     k = (k + 1) & (cs->index_cap - 1))
		if (same_group(&cs->g[cs->index[k] - 1], tid, c))
			return &cs->g[cs->index[k] - 1];
	return NULL;
}

void causes_add(struct causes *cs, __u32 tid, const struct rtsup_cause *c)
{
	struct cause_group *g = find_group(cs, tid, c);

	if (!g) {
		if (cs->n == cs->cap) {
			size_t cap = cs->cap ? cs->cap * 2 : 16;
			struct cause_group *ng = realloc(cs->g, cap * sizeof(*ng));

			if (!ng) {
				cs->dropped++;
				return;
			}
			cs->g = ng;
			cs->cap = cap;
		}
		g = &cs->g[cs->n++];
		memset(g, 0, sizeof(*g));
		g->tid = tid;
		g->kind = c->kind;
		g->after = group_after(c);
		g->who = c->who;
		g->who.comm[RTSUP_COMM_LEN - 1] = '\0';
		if (index_due(cs->index_cap, cs->n)) {
			size_t cap = cs->index_cap ? cs->index_cap : 16;

			while (index_due(cap, cs->n))
				cap *= 2;
			index_rebuild(cs, cap);
		} else if (cs->index) {
			index_put(cs, cs->n - 1);
		}
	}
	g->flags |= c->flags;
	g->count++;
	g->total_ns += c->ns;
	if (c->ns > g->max_ns)
		g->max_ns = c->ns;
}

static int cmp_group(const void *a, const void *b)
{
	const struct cause_group *x = a, *y = b;

	if (x->tid != y->tid)
		return x->tid < y->tid ? -1 : 1;
	if (x->total_ns != y->total_ns)
		return x->total_ns > y->total_ns ? -1 : 1;
	return x->count > y->count ? -1 : x->count < y->count;
}

void causes_sort(struct causes *cs)
{
	if (!cs->n)
		return;
	qsort(cs->g, cs->n, sizeof(*cs->g), cmp_group);
	if (cs->index)	/* the groups moved */
		index_rebuild(cs, cs->index_cap);
}

const struct cause_group *causes_of(const struct causes *cs, __u32 tid, size_t *n)
{
	size_t lo = 0, hi = cs->n, j;

	while (lo < hi) {	/* the first group of tid or after it */
		size_t mid = lo + (hi - lo) / 2;

		if (cs->g[mid].tid < tid)
			lo = mid + 1;
		else
			hi = mid;
	}
	for (j = lo; j < cs->n && cs->g[j].tid == tid; j++)
		;
	*n = j - lo;
	return *n ? &cs->g[lo] : NULL;
}

/* policy_short - a scheduling policy as in "FIFO/99" */
static const char *policy_short(__u32 policy)
{
	static const char *const names[] = { "OTHER", "FIFO", "RR", "BATCH", "ISO", "IDLE",
					     "DL" };

	return policy < sizeof(names) / sizeof(names[0]) ? names[policy] : "?";
}

void cause_who_text(char *buf, size_t len, const struct rtsup_who *w, __u32 self)
{
	if (!w->tid)
		snprintf(buf, len, "the idle task");
	else
		snprintf(buf, len, "%.15s[%u] %s/%d%s", w->comm, w->tid, policy_short(w->policy),
			 w->prio, self && w->tgid == self ? " (rtsup-trace itself)" : "");
}

/* futex_op_name - the futex command of a block (block_op - 1) */
static const char *futex_op_name(__u32 op)
{
	static const char *const names[] = {
		"FUTEX_WAIT", "FUTEX_WAKE", "FUTEX_FD", "FUTEX_REQUEUE", "FUTEX_CMP_REQUEUE",
		"FUTEX_WAKE_OP", "FUTEX_LOCK_PI", "FUTEX_UNLOCK_PI", "FUTEX_TRYLOCK_PI",
		"FUTEX_WAIT_BITSET", "FUTEX_WAKE_BITSET", "FUTEX_WAIT_REQUEUE_PI",
		"FUTEX_CMP_REQUEUE_PI", "FUTEX_LOCK_PI2",
	};

	return op < sizeof(names) / sizeof(names[0]) ? names[op] : "futex";
}

/* causes_block_in - where a block waited: "futex FUTEX_WAIT", "read", "" */
static void block_in(char *buf, size_t len, const struct rtsup_cause *d)
{
	const char *sys = d && d->block_nr ? syscall_name(d->block_nr - 1) : NULL;

	if (d && d->block_op)
		snprintf(buf, len, " in futex %s", futex_op_name(d->block_op - 1));
	else if (sys)
		snprintf(buf, len, " in %s", sys);
	else
		buf[0] = '\0';
}

/* a holder below the target's priority kept the CPU: the kernel could not preempt it */
#define BELOW	", below its priority: not preemptible (kernel section, softirq, IRQs off)"

/* after_text - what a backlog behind no task follows: " (machine / timer latency)" */
static const char *after_text(__u32 after)
{
	switch (after) {
	case RTSUP_CAUSE_TIMER:
		return " (machine / timer latency)";
	case RTSUP_CAUSE_WAIT:
		return " (machine latency: idle exit, interrupts or hypervisor)";
	case RTSUP_CAUSE_EXEC:
		return " (its own CPU time)";
	case RTSUP_CAUSE_STEAL:
		return " (hypervisor steal)";
	}
	return "";
}

/* causes_text_kind - causes_text without the migrations */
static void causes_text_kind(char *buf, size_t len, __u32 kind, __u32 flags, __u64 ns,
			     const struct rtsup_who *who, const struct rtsup_cause *detail,
			     __u32 self)
{
	char w[64], in[48];
	double ms = ns / 1e6;

	cause_who_text(w, sizeof(w), who, self);
	/*
	 * the idle task held the CPU: slow to leave its idle state, or held by
	 * interrupts or the hypervisor between the wakeup and the switch
	 */
	if (kind == RTSUP_CAUSE_WAIT && !who->tid) {
		snprintf(buf, len, "woken, then waited %.3f ms for its idle CPU: machine latency "
			 "(idle exit, interrupts or hypervisor)", ms);
		return;
	}
	switch (kind) {
	case RTSUP_CAUSE_TIMER:
		snprintf(buf, len, "woken %.3f ms after its release: machine / timer latency%s",
			 ms, flags & RTSUP_CAUSE_F_IDLE ? " (idle CPU: idle exit)" :
			 " (interrupts, hypervisor or hardware held the CPU)");
		break;
	case RTSUP_CAUSE_WAIT:
		snprintf(buf, len, "woken, then waited %.3f ms for the CPU behind %s%s", ms, w,
			 flags & RTSUP_CAUSE_F_BELOW ? BELOW : "");
		break;
	case RTSUP_CAUSE_PREEMPT:
		snprintf(buf, len, "preempted for %.3f ms by %s%s", ms, w,
			 flags & RTSUP_CAUSE_F_BELOW ? BELOW : "");
		break;
	case RTSUP_CAUSE_BLOCK:
		block_in(in, sizeof(in), detail);
		snprintf(buf, len, "blocked %.3f ms%s%s, woken by %s%s", ms, in,
			 flags & RTSUP_CAUSE_F_DSTATE ? " (uninterruptible)" : "", w,
			 flags & RTSUP_CAUSE_F_INVERSION ? ": priority inversion" : "");
		break;
	case RTSUP_CAUSE_BACKLOG:
		if (who->tid)
			snprintf(buf, len, "released %.3f ms late: the cycle before ended late "
				 "(behind %s)", ms, w);
		else
			snprintf(buf, len, "released %.3f ms late: the cycle before ended late%s",
				 ms, after_text(detail ? detail->after : RTSUP_CAUSE_NONE));
		break;
	case RTSUP_CAUSE_EXEC:
		snprintf(buf, len, "its own CPU time, %.3f ms", ms);
		break;
	case RTSUP_CAUSE_STEAL:
		snprintf(buf, len, "the hypervisor ran something else on its vCPU for %.3f ms "
			 "while it ran: machine latency (steal)", ms);
		break;
	default:
		snprintf(buf, len, "no cause measured");
	}
}

void causes_text(char *buf, size_t len, __u32 kind, __u32 flags, __u64 ns,
		 const struct rtsup_who *who, const struct rtsup_cause *detail, __u32 self)
{
	char mig[64];
	size_t n;

	causes_text_kind(buf, len, kind, flags, ns, who, detail, self);
	mig_text(mig, sizeof(mig), detail);
	n = strlen(buf);
	if (mig[0] && n + 1 < len)
		snprintf(buf + n, len - n, "%s", mig);
}

void causes_group_text(char *buf, size_t len, const struct cause_group *g, __u32 self)
{
	struct rtsup_cause d;

	memset(&d, 0, sizeof(d));
	d.after = g->after;
	causes_text(buf, len, g->kind, g->flags, g->max_ns, &g->who, &d, self);
}

/* machine - what a miss behind no task says it was, for a verdict */
static const char *machine(__u32 kind)
{
	switch (kind) {
	case RTSUP_CAUSE_TIMER:
		return "machine / timer latency";
	case RTSUP_CAUSE_WAIT:
		return "machine latency (idle CPU)";
	case RTSUP_CAUSE_EXEC:
		return "its own CPU time";
	case RTSUP_CAUSE_STEAL:
		return "machine / hypervisor steal";
	case RTSUP_CAUSE_BACKLOG:
		return "the late cycle before";
	}
	return "nothing measured";
}

/* causes_brief - one group in a few words, for a verdict message */
static void causes_brief(char *buf, size_t len, const struct cause_group *g)
{
	char w[64];

	if (g->who.tid) {
		cause_who_text(w, sizeof(w), &g->who, 0);
		snprintf(buf, len, "%llu caused by %s (%s, %.1f ms max)",
			 (unsigned long long)g->count, w, cause_kind_name(g->kind), g->max_ns / 1e6);
	} else {
		snprintf(buf, len, "%llu caused by %s (%.1f ms max)", (unsigned long long)g->count,
			 machine(g->kind), g->max_ns / 1e6);
	}
}

/*
 * top_culprit - a thread's leading cause: its longest group but a backlog
 * (the consequence of another), with the misses of every group of the same
 * culprit (a hog's waits and the backlogs after them) counted in; with no
 * task, the backlogs after the same kind (a hypervisor's late wakeups and
 * the releases they swallowed)
 */
static void top_culprit(char *buf, size_t len, const struct cause_group *g, size_t n)
{
	struct cause_group top;
	size_t i, lead = 0;

	for (i = 1; i < n; i++)
		if (g[lead].kind == RTSUP_CAUSE_BACKLOG && g[i].kind != RTSUP_CAUSE_BACKLOG)
			lead = i;
	top = g[lead];
	for (i = 0; i < n; i++)
		if (i != lead && ((g[i].who.tid && g[i].who.tid == top.who.tid) ||
				  (!g[i].who.tid && !top.who.tid && !top.who.comm[0] &&
				   top.kind != RTSUP_CAUSE_BACKLOG &&
				   g[i].kind == RTSUP_CAUSE_BACKLOG && g[i].after == top.kind)))
			top.count += g[i].count;
	causes_brief(buf, len, &top);
}

/* why_each - each thread's top group of cs into its interval's text, or its lifetime's */
static void why_each(const struct causes *cs, struct model *m, bool life)
{
	struct thread_model *tm;
	size_t i, j;

	for (i = 0; i < cs->n; i = j) {
		for (j = i; j < cs->n && cs->g[j].tid == cs->g[i].tid; j++)
			;
		tm = model_get(m, cs->g[i].tid, false);
		if (tm && life)
			top_culprit(tm->why_life, sizeof(tm->why_life), &cs->g[i], j - i);
		else if (tm)
			top_culprit(tm->why_win, sizeof(tm->why_win), &cs->g[i], j - i);
	}
}

void causes_to_model(const struct causes *win, const struct causes *life, struct model *m)
{
	int i;

	for (i = 0; i < m->n; i++)
		m->t[i]->why_win[0] = m->t[i]->why_life[0] = '\0';
	why_each(win, m, false);
	why_each(life, m, true);
}

void causes_clear(struct causes *cs)
{
	cs->n = 0;
	cs->dropped = 0;
	if (cs->index)
		memset(cs->index, 0, cs->index_cap * sizeof(*cs->index));
}

void causes_free(struct causes *cs)
{
	free(cs->g);
	free(cs->index);
	memset(cs, 0, sizeof(*cs));
}

const char *unsafe_event_syscall(const struct rtsup_event *e)
{
	if (e->type != RTSUP_EV_UNSAFE)
		return NULL;
	if (e->arg == RTSUP_U_SYSCALL)
		return syscall_name(e->arg2);
	if (e->arg == RTSUP_U_BLOCK && e->arg2)
		return syscall_name(e->arg2 - 1);
	return NULL;
}
