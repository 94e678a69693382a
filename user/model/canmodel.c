// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * canmodel.c - CAN snapshots, node aggregation and the CAN checks: never
 * seen, not responding, gap jitter, bus load, error frames, error-passive and
 * bus-off, and the CANopen profile (heartbeat, NMT state, EMCY, SDO).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "model/canmodel.h"
#include "hist.h"
#include "collect/since.h"

/* key_cmp - order of the entries */
static int key_cmp(const struct rtsup_can_key *a, const struct rtsup_can_key *b)
{
	if (a->netns != b->netns)
		return a->netns < b->netns ? -1 : 1;
	if (a->ifindex != b->ifindex)
		return a->ifindex < b->ifindex ? -1 : 1;
	if (a->can_id != b->can_id)
		return a->can_id < b->can_id ? -1 : 1;
	if (a->dir != b->dir)
		return a->dir < b->dir ? -1 : 1;
	return 0;
}

struct can_entry *can_entry_get(struct can_model *m, const struct rtsup_can_key *k,
				bool create)
{
	int lo = 0, hi = m->n, c;

	while (lo < hi) {
		int mid = (lo + hi) / 2;

		c = key_cmp(&m->e[mid].key, k);
		if (!c)
			return &m->e[mid];
		if (c < 0)
			lo = mid + 1;
		else
			hi = mid;
	}
	if (!create)
		return NULL;
	if (m->n == m->cap) {
		int cap = m->cap ? m->cap * 2 : 64;
		struct can_entry *e = realloc(m->e, cap * sizeof(*e));

		if (!e)
			return NULL;
		m->e = e;
		m->cap = cap;
	}
	memmove(&m->e[lo + 1], &m->e[lo], (m->n - lo) * sizeof(*m->e));
	m->n++;
	memset(&m->e[lo], 0, sizeof(m->e[lo]));
	m->e[lo].key = *k;
	m->e[lo].node = -1;
	return &m->e[lo];
}

struct can_iface *can_iface_get(struct can_model *m, __u32 netns, __u32 ifindex, bool create)
{
	int i;

	for (i = 0; i < m->nifs; i++)
		if (m->ifs[i].ifindex == ifindex && m->ifs[i].netns == netns)
			return &m->ifs[i];
	if (!create || m->nifs == CANMODEL_MAX_IFS)
		return NULL;
	memset(&m->ifs[m->nifs], 0, sizeof(m->ifs[0]));
	m->ifs[m->nifs].netns = netns;
	m->ifs[m->nifs].ifindex = ifindex;
	m->ifs[m->nifs].load = -1;
	m->ifs[m->nifs].ctrl_state = -1;
	snprintf(m->ifs[m->nifs].name, sizeof(m->ifs[0].name), "if%u", ifindex);
	return &m->ifs[m->nifs++];
}

void can_iface_link(struct can_iface *f, bool up, int ctrl_state)
{
	/* only a down we saw: error frames from before we first looked still count */
	if (up && f->link_known && !f->link_up)
		f->err_mark = f->cur.err_frames;
	f->link_known = true;
	f->link_up = up;
	f->ctrl_state = ctrl_state;
}

/* CAN_STATE_* of <linux/can/netlink.h> */
#define CAN_STATE_ERROR_PASSIVE_	2
#define CAN_STATE_BUS_OFF_		3
#define CAN_STATE_STOPPED_		4

enum can_ctrl can_iface_ctrl(const struct can_iface *f)
{
	__u8 crtl = f->cur.err_data[1];

	if (f->link_known && !f->link_up)
		return CAN_CTRL_DOWN;
	if (f->ctrl_state >= 0) {
		/* the controller's own word beats any old error frame */
		if (f->ctrl_state == CAN_STATE_BUS_OFF_)
			return CAN_CTRL_BUSOFF;
		if (f->ctrl_state == CAN_STATE_STOPPED_)
			return CAN_CTRL_DOWN;
		/* netlink does not say which side is passive: the last frame may */
		if (f->ctrl_state == CAN_STATE_ERROR_PASSIVE_)
			return crtl & RTSUP_CAN_ERR_CRTL_TX_PASSIVE ? CAN_CTRL_PASSIVE_TX :
								     CAN_CTRL_PASSIVE_RX;
		return CAN_CTRL_OK;
	}
	/* a vcan or a replay: the last error frame since the link came up */
	if (f->cur.err_frames <= f->err_mark)
		return CAN_CTRL_OK;
	if (f->cur.err_id & RTSUP_CAN_ERR_BUSOFF)
		return CAN_CTRL_BUSOFF;
	if ((f->cur.err_id & RTSUP_CAN_ERR_CRTL) &&
	    (crtl & (RTSUP_CAN_ERR_CRTL_RX_PASSIVE | RTSUP_CAN_ERR_CRTL_TX_PASSIVE)))
		return crtl & RTSUP_CAN_ERR_CRTL_TX_PASSIVE ? CAN_CTRL_PASSIVE_TX :
							     CAN_CTRL_PASSIVE_RX;
	return CAN_CTRL_OK;
}

const char *can_iface_name(const struct can_model *m, __u32 netns, __u32 ifindex)
{
	const struct can_iface *f = can_iface_get((struct can_model *)m, netns, ifindex, false);

	return f ? f->name : "?";
}

void can_component(const struct can_model *m, const struct can_entry *e, char *buf,
		   size_t len)
{
	snprintf(buf, len, "%s 0x%x %s", can_iface_name(m, e->key.netns, e->key.ifindex),
		 e->key.can_id & RTSUP_CAN_EFF_MASK, e->key.dir == RTSUP_CAN_TX ? "tx" : "rx");
}

void can_gap_life(const struct can_entry *e, __u64 *h)
{
	int b;

	if (!e->gap_life) {	/* none yet, or out of memory: the kernel's counts */
		hist_delta(e->cur.gap.hist, NULL, h);
		return;
	}
	hist_delta(e->cur.gap.hist, e->have_prev ? e->prev.gap.hist : NULL, h);
	for (b = 0; b < HIST_BUCKETS; b++)
		h[b] += e->gap_life[b];
}

void can_gap_view_life(const struct can_entry *e, struct metric_view *v)
{
	__u64 h[HIST_BUCKETS];

	can_gap_life(e, h);
	metric_view_counts(&e->cur.gap, h, v);
}

/* gap_life_add - fold the interval that ends into an entry's lifetime counts */
static void gap_life_add(struct can_entry *e)
{
	__u64 h[HIST_BUCKETS];

	if (!e->gap_life && !e->cur.gap.count)
		return;
	can_gap_life(e, h);	/* everything up to now */
	if (!e->gap_life)
		e->gap_life = malloc(HIST_BUCKETS * sizeof(*e->gap_life));
	if (e->gap_life)
		memcpy(e->gap_life, h, sizeof(h));
}

void can_model_next(struct can_model *m)
{
	int i;

	for (i = 0; i < m->n; i++) {
		gap_life_add(&m->e[i]);
		m->e[i].prev = m->e[i].cur;
		m->e[i].have_prev = true;
	}
	for (i = 0; i < m->nifs; i++) {
		m->ifs[i].prev = m->ifs[i].cur;
		m->ifs[i].have_prev = true;
	}
	for (i = 0; i < CANMODEL_MAX_IFS * CANOPEN_NODES; i++)
		m->co[i / CANOPEN_NODES][i % CANOPEN_NODES].emcy_prev =
			m->co[i / CANOPEN_NODES][i % CANOPEN_NODES].emcy_frames;
}

void can_model_free(struct can_model *m)
{
	int i;

	for (i = 0; i < m->n; i++)
		free(m->e[i].gap_life);
	free(m->e);
	free(m->nodes);
	memset(m, 0, sizeof(*m));
}

const char *can_nmt_name(__u8 state)
{
	switch (state) {
	case 0x00: return "boot-up";
	case 0x04: return "stopped";
	case 0x05: return "operational";
	case 0x7f: return "pre-operational";
	default: return "unknown";
	}
}

/* gap_window - the gap statistics of the last interval of one entry */
static void gap_window(const struct can_model *m, const struct can_entry *e,
		       struct metric_view *v)
{
	metric_view_window(&e->cur.gap, e->have_prev ? &e->prev.gap : NULL, m->bank, v);
}

/* merge_gap - fold one entry's gap view into a node's */
static void merge_gap(struct metric_view *into, const struct metric_view *v)
{
	if (!v->count)
		return;
	if (!into->count || v->min < into->min)
		into->min = v->min;
	if (v->max > into->max)
		into->max = v->max;
	into->mean = (into->mean * into->count + v->mean * v->count) / (into->count + v->count);
	if (v->p99 > into->p99)
		into->p99 = v->p99;	/* the worst identifier's */
	into->count += v->count;
}

/*
 * Learning a period. A period is learned from a steady run only: at least
 * CAN_LEARN_MIN_GAPS gaps over the learning time, each within a factor
 * CAN_STEADY of their mean, frames still coming at its end. A burst (an SDO
 * transfer, a request and its answers) is no run: it would teach a period
 * its silence then breaks forever. A learned period is dropped after
 * CAN_UNLEARN intervals in a row of unsteady gaps (traffic turned sporadic);
 * silence keeps it, since silence is what "not responding" is about.
 */
#define CAN_LEARN_MIN_GAPS	8
#define CAN_STEADY		3
#define CAN_UNLEARN		3

/* can_gaps_steady - are gaps of this min and max steady around 'mean'? */
static bool can_gaps_steady(__u64 min, __u64 max, double mean)
{
	return max <= CAN_STEADY * mean && min * CAN_STEADY >= mean;
}

/* can_sporadic_cobid - CANopen identifiers that are sporadic by nature */
static bool can_sporadic_cobid(__u32 id)
{
	if (id & RTSUP_CAN_EFF_FLAG)
		return false;
	return id == 0x000 ||				/* NMT */
	       (id >= 0x081 && id <= 0x0ff) ||		/* EMCY */
	       (id >= 0x581 && id <= 0x5ff) ||		/* SDO responses */
	       (id >= 0x601 && id <= 0x67f) ||		/* SDO requests */
	       id == 0x7e4 || id == 0x7e5;		/* LSS */
}

/* learn_restart - a new learning run from 'now' */
static void learn_restart(struct can_learn *l, __u64 now)
{
	memset(l, 0, sizeof(*l));
	l->since = now;
}

/* learn - one interval of an identifier's gaps: learn, keep or drop its period */
static void learn(struct can_entry *e, const struct can_thresholds *th, bool canopen,
		  const struct metric_view *gap, __u64 now)
{
	struct can_learn *l = &e->learning;
	double mean;

	if (canopen && can_sporadic_cobid(e->key.can_id))
		return;
	if (e->learned) {
		if (!gap->count)
			return;
		l->irregular = can_gaps_steady(gap->min, gap->max, e->learned) ? 0 :
			       l->irregular + 1;
		if (l->irregular >= CAN_UNLEARN) {
			e->learned = 0;
			learn_restart(l, now);
		}
		return;
	}
	if (!l->since) {
		if (!e->cur.frames)
			return;
		l->since = e->cur.first;
	}
	if (gap->count) {
		if (!l->count || gap->min < l->min)
			l->min = gap->min;
		if (gap->max > l->max)
			l->max = gap->max;
		l->count += gap->count;
		l->sum += gap->mean * gap->count;
	}
	if (ns_since(now, l->since) < th->learn_s * 1e9)
		return;
	mean = l->count ? l->sum / l->count : 0;
	if (l->count >= CAN_LEARN_MIN_GAPS && can_gaps_steady(l->min, l->max, mean) &&
	    ns_since(now, e->cur.last) <= CAN_STEADY * mean)
		e->learned = (__u64)(mean + 0.5);
	else
		learn_restart(l, now);	/* not a steady run: look again */
}

/* check_responding - not responding and gap jitter of one component */
static void check_responding(struct status *st, const struct can_thresholds *th,
			     __u64 last, __u64 period, const struct metric_view *gap, __u64 now)
{
	double k;
	__u64 j;

	status_check(st, "can_responding");
	if (period && last) {
		k = (double)ns_since(now, last) / period;
		if (th->error_periods && k >= th->error_periods)
			status_add(st, LEVEL_ERROR, "not responding: no frame for %.1f ms (%.0f periods)",
				   ns_since(now, last) / 1e6, k);
		else if (th->warn_periods && k >= th->warn_periods)
			status_add(st, LEVEL_WARN, "not responding: no frame for %.1f ms (%.0f periods)",
				   ns_since(now, last) / 1e6, k);
	}
	if (!period || !gap->count || (!th->jitter_warn_ns && !th->jitter_error_ns))
		return;
	j = gap->max > period ? gap->max - period : 0;
	if (gap->min < period && period - gap->min > j)
		j = period - gap->min;
	if (th->jitter_error_ns && j > th->jitter_error_ns)
		status_add(st, LEVEL_ERROR, "gap jitter %.1f us > %.1f us", j / 1e3,
			   th->jitter_error_ns / 1e3);
	else if (th->jitter_warn_ns && j > th->jitter_warn_ns)
		status_add(st, LEVEL_WARN, "gap jitter %.1f us > %.1f us", j / 1e3,
			   th->jitter_warn_ns / 1e3);
}

/* check_iface - bus load, error frames, error-passive and bus-off */
static void check_iface(struct can_iface *f, const struct can_config *cc, double interval_s)
{
	__u64 bits = f->cur.bits[0] + f->cur.bits[1], err = f->cur.err_frames;
	enum can_ctrl ctrl = can_iface_ctrl(f);

	if (f->have_prev) {
		bits -= f->prev.bits[0] + f->prev.bits[1];
		err -= f->prev.err_frames;
	}
	f->load = f->bitrate && interval_s > 0 ? bits / (interval_s * f->bitrate) : -1;
	status_reset(&f->st);
	status_check(&f->st, "can_bus");
	if (f->load >= 0 && cc->busload_error && f->load > cc->busload_error)
		status_add(&f->st, LEVEL_ERROR, "bus load %.1f %% > %.0f %%", f->load * 100,
			   cc->busload_error * 100);
	else if (f->load >= 0 && cc->busload_warn && f->load > cc->busload_warn)
		status_add(&f->st, LEVEL_WARN, "bus load %.1f %% > %.0f %%", f->load * 100,
			   cc->busload_warn * 100);
	if (cc->err_error && err >= cc->err_error)
		status_add(&f->st, LEVEL_ERROR, "%llu error frames in the last interval",
			   (unsigned long long)err);
	else if (cc->err_warn && err >= cc->err_warn)
		status_add(&f->st, LEVEL_WARN, "%llu error frames in the last interval",
			   (unsigned long long)err);
	if (ctrl == CAN_CTRL_DOWN)
		status_add(&f->st, LEVEL_ERROR, "interface down");
	else if (ctrl == CAN_CTRL_BUSOFF)
		status_add(&f->st, LEVEL_ERROR, "bus-off");
	else if (ctrl == CAN_CTRL_PASSIVE_RX || ctrl == CAN_CTRL_PASSIVE_TX)
		status_add(&f->st, LEVEL_WARN, "controller error-passive (%s)",
			   ctrl == CAN_CTRL_PASSIVE_TX ? "tx" : "rx");
}

/* canopen_update - the CANopen view of one entry (11-bit ids only) */
static void canopen_update(struct can_model *m, const struct can_entry *e)
{
	__u32 id = e->key.can_id, fn = id & 0x780, n = id & 0x7f;
	struct can_iface *f = can_iface_get(m, e->key.netns, e->key.ifindex, false);
	struct canopen_node *co;

	if ((id & RTSUP_CAN_EFF_FLAG) || !n || !f)
		return;
	/* node ids repeat on every bus (one bus per arm): per interface */
	co = &m->co[f - m->ifs][n];
	switch (fn) {
	case 0x700:	/* heartbeat, or boot-up */
		/* a master's node-guarding request (RTR) is not the node's heartbeat */
		if (e->cur.rtr == e->cur.frames)
			return;
		co->seen = true;
		co->heartbeat_last = e->cur.last;
		co->nmt_state = e->cur.data[0];
		break;
	case 0x080:	/* EMCY */
		co->seen = true;
		co->emcy_frames = e->cur.frames;
		co->emcy_code = e->cur.data[0] | e->cur.data[1] << 8;
		co->emcy_reg = e->cur.data[2];
		break;
	case 0x580:	/* SDO response, matched to its request in the kernel */
		co->seen = true;
		co->sdo_count += e->cur.resp_count;
		co->sdo_sum += e->cur.resp_sum;
		if (e->cur.resp_max > co->sdo_max)
			co->sdo_max = e->cur.resp_max;
		break;
	}
}

/* check_canopen - heartbeat timeout, NMT state, new emergencies */
static void check_canopen(struct canopen_node *co, const struct can_config *cc, __u64 now)
{
	status_reset(&co->st);
	status_check(&co->st, "canopen");
	if (co->heartbeat_last && cc->heartbeat_timeout_ns &&
	    ns_since(now, co->heartbeat_last) > cc->heartbeat_timeout_ns)
		status_add(&co->st, LEVEL_ERROR, "no heartbeat for %.0f ms",
			   ns_since(now, co->heartbeat_last) / 1e6);
	else if (co->heartbeat_last && co->nmt_state != 0x05)
		status_add(&co->st, LEVEL_WARN, "NMT state %s", can_nmt_name(co->nmt_state));
	if (co->emcy_frames > co->emcy_prev) {
		if (co->emcy_code)
			status_add(&co->st, LEVEL_ERROR, "EMCY error code 0x%04x, register 0x%02x",
				   co->emcy_code, co->emcy_reg);
		else
			status_add(&co->st, LEVEL_OK, "EMCY error reset");
	}
}

/* nodes_prepare - one view per configured node, kept across intervals */
static void nodes_prepare(struct can_model *m, const struct config *cfg)
{
	int i;

	if (m->nnodes != cfg->can.nnodes) {
		free(m->nodes);
		m->nodes = calloc(cfg->can.nnodes ? cfg->can.nnodes : 1, sizeof(*m->nodes));
		m->nnodes = m->nodes ? cfg->can.nnodes : 0;
	}
	for (i = 0; i < m->nnodes; i++) {
		struct can_node_view *v = &m->nodes[i];

		v->frames = v->frames_win = v->last = 0;
		v->period = cfg->can.nodes[i].period_ns;
		memset(&v->gap, 0, sizeof(v->gap));
		memset(&v->gap_life, 0, sizeof(v->gap_life));
	}
}

/* judge_groups - a group is as bad as its worst node */
static void judge_groups(struct can_model *m, const struct config *cfg, can_judge_fn judge,
			 void *ctx)
{
	char comp[96];
	int i, g;

	m->ngroups = 0;
	for (i = 0; i < m->nnodes; i++) {
		const char *name = cfg->can.nodes[i].group;

		if (!*name)
			continue;
		for (g = 0; g < m->ngroups && strcmp(m->groups[g].name, name); g++)
			;
		if (g == m->ngroups && g < CANMODEL_MAX_GROUPS) {
			/* the same slot keeps its last verdict while its name is the same */
			struct can_group_view *gv = &m->groups[m->ngroups++];

			if (strcmp(gv->name, name)) {
				memset(gv, 0, sizeof(*gv));
				snprintf(gv->name, sizeof(gv->name), "%s", name);
			}
		}
	}
	for (g = 0; g < m->ngroups; g++) {
		struct can_group_view *gv = &m->groups[g];
		struct status old, st;

		status_copy(&old, &gv->st);
		status_reset(&st);
		status_check(&st, "can_group");
		for (i = 0; i < m->nnodes; i++)
			if (!strcmp(cfg->can.nodes[i].group, gv->name) &&
			    m->nodes[i].st.level >= LEVEL_WARN)
				status_add(&st, m->nodes[i].st.level, "%s: %s",
					   cfg->can.nodes[i].name, level_name(m->nodes[i].st.level));
		status_copy(&gv->st, &st);
		snprintf(comp, sizeof(comp), "group:%s", gv->name);
		judge(ctx, comp, &old, &gv->st, &gv->worst);
	}
}

void can_model_judge(struct can_model *m, const struct config *cfg, __u64 now,
		     double interval_s, can_judge_fn judge, void *ctx)
{
	const struct can_config *cc = &cfg->can;
	struct metric_view gap;
	struct status old;
	char comp[96];
	int i;

	nodes_prepare(m, cfg);
	for (i = 0; i < CANMODEL_MAX_IFS * CANOPEN_NODES; i++) {
		struct canopen_node *co = &m->co[i / CANOPEN_NODES][i % CANOPEN_NODES];

		co->sdo_count = co->sdo_sum = co->sdo_max = 0;
	}
	for (i = 0; i < m->n; i++) {
		struct can_entry *e = &m->e[i];
		const struct can_thresholds *th;

		e->node = config_can_node(cfg, can_iface_name(m, e->key.netns, e->key.ifindex),
					  e->key.can_id, e->key.dir);
		th = e->node >= 0 ? &cc->nodes[e->node].th : &cc->defaults;
		gap_window(m, e, &gap);
		learn(e, th, cc->canopen, &gap, now);
		if (cc->canopen)
			canopen_update(m, e);
		if (e->node >= 0) {
			struct can_node_view *v = &m->nodes[e->node];

			v->frames += e->cur.frames;
			v->frames_win += e->cur.frames - (e->have_prev ? e->prev.frames : 0);
			if (e->cur.last > v->last)
				v->last = e->cur.last;
			if (!v->period)
				v->period = e->learned;
			merge_gap(&v->gap, &gap);
			can_gap_view_life(e, &gap);
			merge_gap(&v->gap_life, &gap);
			continue;
		}
		/* an identifier no node names: judged on its own learned period */
		status_copy(&old, &e->st);
		status_reset(&e->st);
		check_responding(&e->st, th, e->cur.last, e->learned, &gap, now);
		can_component(m, e, comp, sizeof(comp));
		judge(ctx, comp, &old, &e->st, &e->worst);
	}
	for (i = 0; i < m->nnodes; i++) {
		struct can_node_view *v = &m->nodes[i];
		const struct can_node *n = &cc->nodes[i];

		status_copy(&old, &v->st);
		status_reset(&v->st);
		status_check(&v->st, "initialization");
		if (!v->frames && n->th.init_timeout_s &&
		    ns_since(now, m->start_ns) >= n->th.init_timeout_s * 1e9)
			status_add(&v->st, LEVEL_WARN, "not initialized: never seen in %.1f s",
				   ns_since(now, m->start_ns) / 1e9);
		check_responding(&v->st, &n->th, v->last, v->period, &v->gap, now);
		snprintf(comp, sizeof(comp), "node:%s", n->name);
		judge(ctx, comp, &old, &v->st, &v->worst);
	}
	judge_groups(m, cfg, judge, ctx);
	for (i = 0; i < m->nifs; i++) {
		status_copy(&old, &m->ifs[i].st);
		check_iface(&m->ifs[i], cc, interval_s);
		judge(ctx, m->ifs[i].name, &old, &m->ifs[i].st, &m->ifs[i].worst);
	}
	for (i = 0; cc->canopen && i < m->nifs * CANOPEN_NODES; i++) {
		struct canopen_node *co = &m->co[i / CANOPEN_NODES][i % CANOPEN_NODES];

		if (!co->seen)
			continue;
		status_copy(&old, &co->st);
		check_canopen(co, cc, now);
		snprintf(comp, sizeof(comp), "canopen:%s:%d", m->ifs[i / CANOPEN_NODES].name,
			 i % CANOPEN_NODES);
		judge(ctx, comp, &old, &co->st, &co->worst);
	}
}

enum level can_worst(const struct can_model *m)
{
	enum level w = LEVEL_OK;
	int i;

	for (i = 0; i < m->n; i++)
		if (m->e[i].worst > w)
			w = m->e[i].worst;
	for (i = 0; i < m->nnodes; i++)
		if (m->nodes[i].worst > w)
			w = m->nodes[i].worst;
	for (i = 0; i < m->ngroups; i++)
		if (m->groups[i].worst > w)
			w = m->groups[i].worst;
	for (i = 0; i < m->nifs; i++)
		if (m->ifs[i].worst > w)
			w = m->ifs[i].worst;
	for (i = 0; i < CANMODEL_MAX_IFS * CANOPEN_NODES; i++)
		if (m->co[i / CANOPEN_NODES][i % CANOPEN_NODES].worst > w)
			w = m->co[i / CANOPEN_NODES][i % CANOPEN_NODES].worst;
	return w;
}
