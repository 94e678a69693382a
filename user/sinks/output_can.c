// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * output_can.c - CAN statistics like the seed's GeneralPublisher: per
 * interface (bus load, errors), per identifier or named node (frames, rate,
 * gaps, last seen) and the CANopen nodes.
 */
#include <stdio.h>
#include <string.h>
#include "model/model.h"
#include "sinks/output_can.h"
#include "collect/since.h"

/* id_text - "0x123" or "0x12345678x" for 29-bit identifiers */
static void id_text(__u32 id, char *buf, size_t len)
{
	snprintf(buf, len, "0x%x%s", id & RTSUP_CAN_EFF_MASK,
		 id & RTSUP_CAN_EFF_FLAG ? "x" : "");
}

/* entry_gap - gap statistics of one identifier, window or lifetime */
static void entry_gap(const struct can_model *m, const struct can_entry *e, bool total,
		      struct metric_view *v)
{
	if (total || !e->have_prev)
		can_gap_view_life(e, v);
	else
		metric_view_window(&e->cur.gap, &e->prev.gap, m->bank, v);
}

/* entry_frames - frames of one identifier, window or lifetime */
static __u64 entry_frames(const struct can_entry *e, bool total)
{
	return e->cur.frames - (total || !e->have_prev ? 0 : e->prev.frames);
}

/* iface_delta - a counter of an interface, window or lifetime */
#define IFD(f, field, total) ((f)->cur.field - ((total) || !(f)->have_prev ? 0 : (f)->prev.field))

static const char *const err_names[RTSUP_CAN_ERR_CLASSES] = {
	"tx_timeout", "lost_arbitration", "controller", "protocol", "transceiver",
	"no_ack", "bus_off", "bus_error", "restarted", "counters",
};

void can_table(const struct can_model *m, const struct config *cfg, __u64 now,
	       double interval_s, bool total)
{
	char id[24], load[16], g[4][16], ago[16];
	struct metric_view v;
	double span = total ? ns_since(now, m->start_ns) / 1e9 : interval_s;
	int i;

	printf("%-10s %9s %9s %9s %9s %6s %9s %s\n", "CAN", "LOAD", "BITRATE", "RX/s", "TX/s",
	       "ERR", "LOOPBACK", "STATUS");
	for (i = 0; i < m->nifs; i++) {
		const struct can_iface *f = &m->ifs[i];

		if (f->load >= 0 && !total)
			snprintf(load, sizeof(load), "%.1f%%", f->load * 100);
		else
			snprintf(load, sizeof(load), "-");
		printf("%-10s %9s %9llu %9.1f %9.1f %6llu %9llu %s\n", f->name, load,
		       (unsigned long long)f->bitrate,
		       span > 0 ? IFD(f, frames[RTSUP_CAN_RX], total) / span : 0,
		       span > 0 ? IFD(f, frames[RTSUP_CAN_TX], total) / span : 0,
		       (unsigned long long)IFD(f, err_frames, total),
		       (unsigned long long)IFD(f, loopback, total),
		       level_name(total ? f->worst : f->st.level));
	}
	printf("  %-22s %3s %9s %9s %9s %9s %9s %9s %9s %s\n", "ID / NODE", "DIR", "FRAMES",
	       "RATE/s", "GAP avg", "min", "max", "p99 (us)", "LAST ms", "STATUS");
	for (i = 0; i < m->n; i++) {
		const struct can_entry *e = &m->e[i];
		char name[48];

		entry_gap(m, e, total, &v);
		id_text(e->key.can_id, id, sizeof(id));
		snprintf(name, sizeof(name), "%s %s%s%.20s",
			 can_iface_name(m, e->key.netns, e->key.ifindex), id,
			 e->node >= 0 ? " " : "",
			 e->node >= 0 ? cfg->can.nodes[e->node].name : "");
		snprintf(g[0], 16, v.count ? "%.1f" : "-", v.mean / 1e3);
		snprintf(g[1], 16, v.count ? "%.1f" : "-", v.min / 1e3);
		snprintf(g[2], 16, v.count ? "%.1f" : "-", v.max / 1e3);
		snprintf(g[3], 16, v.count ? "%.1f" : "-", v.p99 / 1e3);
		snprintf(ago, sizeof(ago), "%.0f", ns_since(now, e->cur.last) / 1e6);
		printf("  %-22.22s %3s %9llu %9.1f %9s %9s %9s %9s %9s %s\n", name,
		       e->key.dir == RTSUP_CAN_TX ? "tx" : "rx",
		       (unsigned long long)entry_frames(e, total),
		       span > 0 ? entry_frames(e, total) / span : 0, g[0], g[1], g[2], g[3], ago,
		       e->node >= 0 ? "(node)" :
		       level_name(total ? e->worst : e->st.level));
	}
	for (i = 0; i < m->nnodes; i++) {
		const struct can_node_view *n = &m->nodes[i];

		printf("  node:%-17.17s %3s %9llu %9.1f %9s %9s %9s %9s %9s %s\n",
		       cfg->can.nodes[i].name, "", (unsigned long long)(total ? n->frames :
									  n->frames_win),
		       span > 0 ? (total ? n->frames : n->frames_win) / span : 0, "", "", "", "",
		       n->last ? "" : "never", level_name(total ? n->worst : n->st.level));
		for (int j = 0; !total && j < n->st.nmsg; j++)
			printf("    %-5s node:%s: %s\n", level_name(n->st.level),
			       cfg->can.nodes[i].name, n->st.msg[j]);
	}
	for (i = 0; i < m->ngroups; i++)
		printf("  group:%-16.16s %s\n", m->groups[i].name,
		       level_name(total ? m->groups[i].worst : m->groups[i].st.level));
	for (i = 0; i < m->nifs * CANOPEN_NODES; i++) {
		const struct canopen_node *co = &m->co[i / CANOPEN_NODES][i % CANOPEN_NODES];

		if (!co->seen)
			continue;
		printf("  canopen:%s:%-3d NMT %-15s EMCY %llu (last 0x%04x) SDO %llu  %s\n",
		       m->ifs[i / CANOPEN_NODES].name, i % CANOPEN_NODES,
		       co->heartbeat_last ? can_nmt_name(co->nmt_state) : "-",
		       (unsigned long long)co->emcy_frames, co->emcy_code,
		       (unsigned long long)co->sdo_count,
		       level_name(total ? co->worst : co->st.level));
	}
	if (m->full)
		printf("  %llu frames not counted by identifier: the id map is full (--can-max-ids)\n",
		       (unsigned long long)m->full);
	/* the messages of every CAN component that is not OK */
	for (i = 0; !total && i < m->nifs; i++)
		for (int j = 0; j < m->ifs[i].st.nmsg; j++)
			printf("  %-5s %s: %s\n", level_name(m->ifs[i].st.level), m->ifs[i].name,
			       m->ifs[i].st.msg[j]);
	for (i = 0; !total && i < m->n; i++) {
		char comp[96];

		can_component(m, &m->e[i], comp, sizeof(comp));
		for (int j = 0; m->e[i].node < 0 && j < m->e[i].st.nmsg; j++)
			printf("  %-5s %s: %s\n", level_name(m->e[i].st.level), comp,
			       m->e[i].st.msg[j]);
	}
	for (i = 0; !total && i < m->nifs * CANOPEN_NODES; i++) {
		const struct canopen_node *co = &m->co[i / CANOPEN_NODES][i % CANOPEN_NODES];

		for (int j = 0; co->seen && j < co->st.nmsg; j++)
			printf("  %-5s canopen:%s:%d: %s\n", level_name(co->st.level),
			       m->ifs[i / CANOPEN_NODES].name, i % CANOPEN_NODES, co->st.msg[j]);
	}
}

/* json_metric_can - a gap metric */
static json_t *json_gap(const struct metric_view *v)
{
	if (!v->count)
		return json_pack("{s:I}", "count", (json_int_t)0);
	return json_pack("{s:I,s:I,s:I,s:f,s:f,s:I,s:I,s:I}", "count", (json_int_t)v->count,
			 "min", (json_int_t)v->min, "max", (json_int_t)v->max, "mean", v->mean,
			 "ewma", v->ewma, "p50", (json_int_t)v->p50, "p99", (json_int_t)v->p99,
			 "p999", (json_int_t)v->p999);
}

/* json_st - level and messages */
static json_t *json_st(const struct status *st, enum level worst)
{
	json_t *msgs = json_array();
	int i;

	for (i = 0; i < st->nmsg; i++)
		json_array_append_new(msgs, json_string(st->msg[i]));
	return json_pack("{s:s,s:o,s:s}", "level", level_name(st->level), "messages", msgs,
			 "worst_level", level_name(worst));
}

json_t *can_json(const struct can_model *m, const struct config *cfg, __u64 now,
		 double interval_s, bool total)
{
	json_t *o = json_object(), *ifs = json_array(), *ids = json_array(),
	       *nodes = json_array(), *groups = json_array(), *co = json_array();
	double span = total ? ns_since(now, m->start_ns) / 1e9 : interval_s;
	struct metric_view v;
	char id[24];
	int i, k;

	for (i = 0; i < m->nifs; i++) {
		const struct can_iface *f = &m->ifs[i];
		json_t *ec = json_object(), *x;

		for (k = 0; k < RTSUP_CAN_ERR_CLASSES; k++)
			json_object_set_new(ec, err_names[k], json_integer(IFD(f, err_class[k], total)));
		x = json_pack("{s:s,s:i,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:o,s:o}",
			      "interface", f->name, "ifindex", f->ifindex,
			      "bitrate", (json_int_t)f->bitrate,
			      "frames_rx", (json_int_t)IFD(f, frames[RTSUP_CAN_RX], total),
			      "frames_tx", (json_int_t)IFD(f, frames[RTSUP_CAN_TX], total),
			      "bytes", (json_int_t)(IFD(f, bytes[0], total) + IFD(f, bytes[1], total)),
			      "bits", (json_int_t)(IFD(f, bits[0], total) + IFD(f, bits[1], total)),
			      "loopback", (json_int_t)IFD(f, loopback, total),
			      "rtr", (json_int_t)IFD(f, rtr, total), "fd", (json_int_t)IFD(f, fd, total),
			      "error_frames", (json_int_t)IFD(f, err_frames, total),
			      "xl", (json_int_t)IFD(f, xl, total), "error_classes", ec,
			      "status", json_st(&f->st, f->worst));
		json_object_set_new(x, "bus_load", f->load >= 0 && !total ? json_real(f->load) :
				    json_null());
		json_object_set_new(x, "netns", json_integer(f->netns));
		json_array_append_new(ifs, x);
	}
	for (i = 0; i < m->n; i++) {
		const struct can_entry *e = &m->e[i];
		json_t *x;

		entry_gap(m, e, total, &v);
		id_text(e->key.can_id, id, sizeof(id));
		x = json_pack("{s:s,s:s,s:I,s:b,s:s,s:I,s:I,s:f,s:o,s:f,s:I}", "interface",
			      can_iface_name(m, e->key.netns, e->key.ifindex), "id", id,
			      "can_id", (json_int_t)(e->key.can_id & RTSUP_CAN_EFF_MASK),
			      "extended", !!(e->key.can_id & RTSUP_CAN_EFF_FLAG),
			      "dir", e->key.dir == RTSUP_CAN_TX ? "tx" : "rx",
			      "frames", (json_int_t)entry_frames(e, total),
			      "rtr", (json_int_t)e->cur.rtr,
			      "rate", span > 0 ? entry_frames(e, total) / span : 0.0,
			      "gap_ns", json_gap(&v),
			      "last_ago_ms", ns_since(now, e->cur.last) / 1e6,
			      "learned_period_ns", (json_int_t)e->learned);
		if (e->node >= 0)
			json_object_set_new(x, "node", json_string(cfg->can.nodes[e->node].name));
		else
			json_object_set_new(x, "status", json_st(&e->st, e->worst));
		if (e->key.dir == RTSUP_CAN_TX)
			json_object_set_new(x, "sender", json_pack(
				"{s:i,s:I,s:I,s:f,s:I}", "tid", e->cur.tx_tid,
				"kernel", (json_int_t)e->cur.tx_kernel,
				"in_cycle", (json_int_t)e->cur.tx_in_cycle,
				"cycle_offset_mean_ns", e->cur.tx_in_cycle ?
				(double)e->cur.tx_offset_sum / e->cur.tx_in_cycle : 0.0,
				"cycle_offset_max_ns", (json_int_t)e->cur.tx_offset_max));
		json_array_append_new(ids, x);
	}
	for (i = 0; i < m->nnodes; i++) {
		const struct can_node_view *n = &m->nodes[i];

		json_array_append_new(nodes, json_pack(
			"{s:s,s:s,s:I,s:I,s:o,s:o,s:o}", "name", cfg->can.nodes[i].name,
			"group", cfg->can.nodes[i].group, "frames",
			(json_int_t)(total ? n->frames : n->frames_win), "period_ns",
			(json_int_t)n->period, "gap_ns", json_gap(total ? &n->gap_life : &n->gap),
			"last_ago_ms",
			n->last ? json_real(ns_since(now, n->last) / 1e6) : json_null(),
			"status", json_st(&n->st, n->worst)));
	}
	for (i = 0; i < m->ngroups; i++)
		json_array_append_new(groups, json_pack("{s:s,s:o}", "name", m->groups[i].name,
							"status", json_st(&m->groups[i].st,
									  m->groups[i].worst)));
	for (i = 0; i < m->nifs * CANOPEN_NODES; i++) {
		const struct canopen_node *c = &m->co[i / CANOPEN_NODES][i % CANOPEN_NODES];

		if (!c->seen)
			continue;
		json_array_append_new(co, json_pack(
			"{s:s,s:i,s:s,s:o,s:I,s:i,s:i,s:I,s:f,s:I,s:o}",
			"interface", m->ifs[i / CANOPEN_NODES].name, "node", i % CANOPEN_NODES,
			"nmt_state",
			c->heartbeat_last ? can_nmt_name(c->nmt_state) : "unknown",
			"heartbeat_ago_ms", c->heartbeat_last ?
			json_real(ns_since(now, c->heartbeat_last) / 1e6) : json_null(),
			"emcy_frames", (json_int_t)c->emcy_frames, "emcy_code", c->emcy_code,
			"emcy_register", c->emcy_reg, "sdo_responses", (json_int_t)c->sdo_count,
			"sdo_mean_ns", c->sdo_count ? (double)c->sdo_sum / c->sdo_count : 0.0,
			"sdo_max_ns", (json_int_t)c->sdo_max, "status", json_st(&c->st, c->worst)));
	}
	json_object_set_new(o, "interfaces", ifs);
	json_object_set_new(o, "ids", ids);
	json_object_set_new(o, "nodes", nodes);
	json_object_set_new(o, "groups", groups);
	json_object_set_new(o, "canopen", co);
	json_object_set_new(o, "frames_not_counted_by_id", json_integer(m->full));
	return o;
}
