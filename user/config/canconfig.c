// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * canconfig.c - the can: section: bus thresholds and named CAN nodes
 * (struct can_config, struct can_node), their field tables, and which
 * node names a counted identifier (config_can_node).
 */
#include <stdlib.h>
#include <string.h>
#include "config/fields.h"
#include "can.h"

/* The can: section. Offsets from struct can_config, can_thresholds, can_node. */
#define CC(m)	offsetof(struct can_config, m)
#define CT(m)	offsetof(struct can_thresholds, m)
#define N(m)	offsetof(struct can_node, m)
#define IFACE_LEN	sizeof(((struct can_node *)0)->iface)

static const struct field busload_f[] = {
	{ .key = "warn", .type = F_RATIO, .off = CC(busload_warn), .max = 1 },
	{ .key = "error", .type = F_RATIO, .off = CC(busload_error), .max = 1 },
	{},
};

static const struct field errframes_f[] = {
	{ .key = "warn", .type = F_COUNT, .off = CC(err_warn) },
	{ .key = "error", .type = F_COUNT, .off = CC(err_error) },
	{},
};

static const struct field responding_f[] = {
	{ .key = "warn_periods", .type = F_NUMBER, .off = CT(warn_periods) },
	{ .key = "error_periods", .type = F_NUMBER, .off = CT(error_periods) },
	{},
};

static const struct field can_jitter_f[] = {
	{ .key = "warn", .type = F_DURATION, .off = CT(jitter_warn_ns) },
	{ .key = "error", .type = F_DURATION, .off = CT(jitter_error_ns) },
	{},
};

/* the keys of can.defaults (from struct can_thresholds) */
static const struct field can_th_f[] = {
	{ .key = "not_responding", .type = F_GROUP, .sub = responding_f },
	{ .key = "jitter", .type = F_GROUP, .sub = can_jitter_f },
	{ .key = "learn", .type = F_SECONDS, .off = CT(learn_s) },
	{ .key = "init_timeout", .type = F_SECONDS, .off = CT(init_timeout_s) },
	{},
};

/* the keys of can: besides nodes */
const struct field can_f[] = {
	{ .key = "canopen", .type = F_BOOL, .off = CC(canopen) },
	{ .key = "bitrate", .type = F_COUNT, .off = CC(bitrate) },
	{ .key = "bus_load", .type = F_GROUP, .sub = busload_f },
	{ .key = "error_frames", .type = F_GROUP, .sub = errframes_f },
	{ .key = "heartbeat_timeout", .type = F_DURATION, .off = CC(heartbeat_timeout_ns) },
	{ .key = "defaults", .type = F_GROUP, .off = CC(defaults), .sub = can_th_f },
	{},
};

/* the keys of a node besides name: its own, then can.defaults' over its th */
const struct field node_f[] = {
	{ .key = "interface", .type = F_IFACE, .off = N(iface), .max = IFACE_LEN },
	{ .key = "id", .type = F_CANID, .off = N(id_lo), .off2 = N(id_hi), .flag = NF_ID },
	{ .key = "direction", .type = F_CANDIR, .off = N(dir) },
	{ .key = "period", .type = F_DURATION, .off = N(period_ns) },
	{ .key = "group", .type = F_STR, .off = N(group), .max = CONFIG_NAME_LEN },
	{ .key = "not_responding", .type = F_GROUP, .off = N(th), .sub = responding_f },
	{ .key = "jitter", .type = F_GROUP, .off = N(th), .sub = can_jitter_f },
	{ .key = "learn", .type = F_SECONDS, .off = N(th) + CT(learn_s) },
	{ .key = "init_timeout", .type = F_SECONDS, .off = N(th) + CT(init_timeout_s) },
	{},
};

static const char *const node_own[] = { "name", NULL };
static const char *const can_own[] = { "nodes", NULL };

/* parse_node - one entry of can.nodes, starting from can.defaults */
static int parse_node(struct parse *p, yaml_node_t *map, struct can_config *cc, int idx)
{
	struct can_node *n = &cc->nodes[idx];
	yaml_node_t *name;
	__u32 set = 0;
	int i;

	if (cfg_want(p, map, YAML_MAPPING_NODE, "a can node"))
		return -1;
	memset(n, 0, sizeof(*n));
	n->dir = CAN_DIR_ANY;
	n->th = cc->defaults;
	n->line = map->start_mark.line + 1;
	name = cfg_find_key(p, map, "name");
	if (!name)
		return cfg_fail(p, map, "can node %d has no name", idx + 1);
	if (cfg_copy_str(p, name, "node name", n->name, CONFIG_NAME_LEN))
		return -1;
	snprintf(p->where, sizeof(p->where), "can node '%s'", n->name);
	for (i = 0; i < idx; i++)
		if (!strcmp(cc->nodes[i].name, n->name))
			return cfg_fail(p, name, "duplicate node name '%s' (first at line %d)",
				    n->name, cc->nodes[i].line);
	if (cfg_parse_group(p, node_f, map, n, &set, "", NULL, node_own))
		return -1;
	if (!(set & NF_ID))
		return cfg_fail(p, map, "can node '%s' has no id", n->name);
	return 0;
}

/* parse_nodes - the list under can.nodes */
static int parse_nodes(struct parse *p, yaml_node_t *seq, struct can_config *cc)
{
	int n, i;

	n = cfg_list_items(p, seq, "can.nodes");
	if (n <= 0)
		return n;
	cc->nodes = calloc(n, sizeof(*cc->nodes));
	if (!cc->nodes)
		return cfg_fail(p, seq, "out of memory");
	for (i = 0; i < n; i++) {
		cc->nnodes = i + 1;
		if (parse_node(p, cfg_node(p, seq->data.sequence.items.start[i]), cc, i))
			return -1;
	}
	return 0;
}

/* cfg_parse_can - the can: map; nodes start from can.defaults, so they come last */
int cfg_parse_can(struct parse *p, yaml_node_t *map, struct config *c)
{
	yaml_node_t *nodes;

	p->where[0] = '\0';
	if (cfg_parse_group(p, can_f, map, &c->can, NULL, "can", NULL, can_own))
		return -1;
	nodes = map->type == YAML_MAPPING_NODE ? cfg_find_key(p, map, "nodes") : NULL;
	return nodes ? parse_nodes(p, nodes, &c->can) : 0;
}

int config_can_node(const struct config *c, const char *iface, __u32 id, int dir)
{
	__u32 eff = id & RTSUP_CAN_EFF_FLAG, key = id & RTSUP_CAN_EFF_MASK;
	int i;

	/* an error frame is a report of the controller, not an identifier */
	if (id & RTSUP_CAN_ERR_FLAG)
		return -1;
	for (i = 0; i < c->can.nnodes; i++) {
		const struct can_node *n = &c->can.nodes[i];

		if (n->iface[0] && (!iface || strcmp(n->iface, iface)))
			continue;
		/* a 29-bit node never names an 11-bit identifier, nor the reverse */
		if ((n->id_lo & RTSUP_CAN_EFF_FLAG) != eff)
			continue;
		if (key < (n->id_lo & RTSUP_CAN_EFF_MASK) || key > (n->id_hi & RTSUP_CAN_EFF_MASK))
			continue;
		if (n->dir != CAN_DIR_ANY && n->dir != dir)
			continue;
		return i;
	}
	return -1;
}
