// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * print.c - the effective configuration, in the file's YAML form
 * (--check-config): every field through the same tables that parse
 * it, each value written so that reading it back gives the same value.
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include "config/fields.h"
#include "config/stackopt.h"
#include "can.h"

#define N(m)	offsetof(struct can_node, m)

/* fmt_shortest - the shortest %g of v * scale that reads back to v */
static bool fmt_shortest(char *buf, size_t len, double v, double scale)
{
	int prec;

	for (prec = 6; prec <= 17; prec++) {
		snprintf(buf, len, "%.*g", prec, v * scale);
		/* the parser divides by the same scale */
		if (strtod(buf, NULL) / scale == v)
			return true;
	}
	return false;
}

/*
 * fmt_num - a number, as a percentage when scale is 100, so that loading
 * the text gives v again; a ratio no percentage reads back to is written
 * as the plain ratio
 */
static void fmt_num(char *buf, size_t len, double v, double scale, const char *suffix)
{
	if (fmt_shortest(buf, len - strlen(suffix), v, scale)) {
		strcat(buf, suffix);
		return;
	}
	fmt_shortest(buf, len, v, 1);
}

/* fmt_duration - ns with the largest unit that divides it exactly */
static void fmt_duration(char *buf, size_t len, __u64 ns)
{
	static const struct {
		const char *unit;
		__u64 mult;
	} units[] = {
		{ "h", 3600 * NS_PER_S }, { "m", 60 * NS_PER_S }, { "s", NS_PER_S },
		{ "ms", 1000000 }, { "us", 1000 },
	};
	size_t i;

	if (!ns) {
		snprintf(buf, len, "0");
		return;
	}
	for (i = 0; i < sizeof(units) / sizeof(units[0]); i++) {
		if (ns % units[i].mult == 0) {
			snprintf(buf, len, "%llu%s", (unsigned long long)(ns / units[i].mult),
				 units[i].unit);
			return;
		}
	}
	snprintf(buf, len, "%lluns", (unsigned long long)ns);
}

/* fmt_syslist - [a, b] */
static void fmt_syslist(char *buf, size_t len, const char (*names)[SYSNAME_LEN], int n)
{
	size_t o;
	int i;

	o = snprintf(buf, len, "[");
	for (i = 0; i < n && o < len; i++)
		o += snprintf(buf + o, len - o, "%s%s", i ? ", " : "", names[i]);
	if (o < len)
		snprintf(buf + o, len - o, "]");
}

/* fmt_str - a double-quoted YAML string */
static void fmt_str(char *buf, size_t len, const char *s)
{
	size_t o = snprintf(buf, len, "\"");

	for (; *s && o < len; s++) {
		if (*s == '"' || *s == '\\')
			o += snprintf(buf + o, len - o, "\\%c", *s);
		else if ((unsigned char)*s < 0x20)
			o += snprintf(buf + o, len - o, "\\x%02x", (unsigned char)*s);
		else
			o += snprintf(buf + o, len - o, "%c", *s);
	}
	if (o < len)
		snprintf(buf + o, len - o, "\"");
}

/* fmt_canid - 0x181, 0x180-0x1FF; 29-bit ids with 8 digits, as candump does */
static void fmt_canid(char *buf, size_t len, __u32 lo, __u32 hi)
{
	bool eff = lo & RTSUP_CAN_EFF_FLAG;
	int w = eff ? 8 : 3;

	lo &= RTSUP_CAN_EFF_MASK;
	hi &= RTSUP_CAN_EFF_MASK;
	if (lo == hi)
		snprintf(buf, len, "0x%0*X", w, lo);
	else
		snprintf(buf, len, "0x%0*X-0x%0*X", w, lo, w, hi);
}

static void fmt_group(char *buf, size_t len, const struct field *fields,
		      const void *obj);

/* fmt_value - one field's value as YAML text */
static void fmt_value(char *buf, size_t len, const struct field *f, const void *obj)
{
	const void *src = (const char *)obj + f->off;
	int i;

	switch (f->type) {
	case F_DURATION:
		fmt_duration(buf, len, *(const __u64 *)src);
		break;
	case F_SECONDS:
		fmt_duration(buf, len, (__u64)llround(*(const double *)src * NS_PER_S));
		break;
	case F_COUNT:
		snprintf(buf, len, "%llu", *(const unsigned long long *)src);
		break;
	case F_NUMBER:
	case F_EWMA:
		fmt_num(buf, len, *(const double *)src, 1, "");
		break;
	case F_RATIO:
		fmt_num(buf, len, *(const double *)src, 100, "%");
		break;
	case F_PERCENT:
		fmt_num(buf, len, *(const double *)src, 1, "%");
		break;
	case F_BOOL:
		snprintf(buf, len, "%s", *(const bool *)src ? "true" : "false");
		break;
	case F_STAT:
		snprintf(buf, len, "%s",
			 *(const enum exec_stat *)src == EXEC_STAT_EWMA ? "ewma" : "p99");
		break;
	case F_POLICY:
		snprintf(buf, len, "%s", sched_policy_name(*(const int *)src));
		break;
	case F_PRIO:
		i = *(const int *)src;
		if (i < 0)
			snprintf(buf, len, "any");
		else
			snprintf(buf, len, "%d", i);
		break;
	case F_SYSLIST:
		fmt_syslist(buf, len, src, *(const int *)((const char *)obj + f->off2));
		break;
	case F_GROUP:
		fmt_group(buf, len, f->sub, src);
		break;
	case F_IFACE:
		if (!*(const char *)src) {
			snprintf(buf, len, "any");
			break;
		}
		/* fall through */
	case F_STR:
		fmt_str(buf, len, src);
		break;
	case F_CANID:
		fmt_canid(buf, len, *(const __u32 *)src,
			  *(const __u32 *)((const char *)obj + f->off2));
		break;
	case F_CANDIR:
		i = *(const int *)src;
		snprintf(buf, len, "%s", i == RTSUP_CAN_RX ? "rx" : i == RTSUP_CAN_TX ? "tx" : "any");
		break;
	case F_LEVEL:
		snprintf(buf, len, "%s", level_name(*(const enum level *)src));
		break;
	case F_WHEN:
		snprintf(buf, len, "%s", *(const bool *)src ? "leave" : "enter");
		break;
	case F_SIGNAL:
		snprintf(buf, len, "%s", signal_name(*(const int *)src));
		break;
	case F_STACKS:
		snprintf(buf, len, "%s", stacks_name(*(const __u32 *)src));
		break;
	case F_STACKSIZE:
		i = *(const __u32 *)src;
		snprintf(buf, len, i % 1024 ? "%d" : "%dK", i % 1024 ? i : i / 1024);
		break;
	default:
		buf[0] = '\0';
	}
}

/* fmt_group - a nested group as a flow map {k: v, ...} */
static void fmt_group(char *buf, size_t len, const struct field *fields,
		      const void *obj)
{
	char val[256];
	size_t o;

	o = snprintf(buf, len, "{");
	for (; fields->key && o < len; fields++) {
		fmt_value(val, sizeof(val), fields, obj);
		o += snprintf(buf + o, len - o, "%s%s: %s", o > 1 ? ", " : "", fields->key,
			      val);
	}
	if (o < len)
		snprintf(buf + o, len - o, "}");
}

/* print_str - a double-quoted YAML string */
static void print_str(FILE *out, const char *s)
{
	char buf[4 * CONFIG_PATH_LEN + 3];

	fmt_str(buf, sizeof(buf), s);
	fputs(buf, out);
}

/*
 * print_rule - the keys of a rule (or the defaults) at an indent. Keys the
 * rule takes from elsewhere are shown as comments, so that reading the text
 * back gives the same "set" bits and the rule keeps following the defaults.
 */
static void print_rule(FILE *out, const struct rule *r, const char *ind,
		       const char *inherited)
{
	const struct field *f, *t;
	char val[512];

	for (f = rule_f; f->key; f++) {
		if (f->type == F_GROUP) {
			fprintf(out, "%s%s:\n", ind, f->key);
			for (t = f->sub; t->key; t++) {
				fmt_value(val, sizeof(val), t, (const char *)r + f->off);
				fprintf(out, "%s  %s: %s\n", ind, t->key, val);
			}
			continue;
		}
		fmt_value(val, sizeof(val), f, r);
		if (r->set & f->flag)
			fprintf(out, "%s%s: %s\n", ind, f->key, val);
		else
			fprintf(out, "%s# %s: %s  (%s)\n", ind, f->key, val, inherited);
	}
}

/* print_match - a rule's match: as a flow map, or nothing */
static void print_match(FILE *out, const struct rule *r)
{
	const char *keys[] = { "process", "thread", "cgroup" };
	const char *vals[] = { r->match_process, r->match_thread, r->match_cgroup };
	int i, n = 0;

	for (i = 0; i < 3; i++) {
		if (!vals[i][0])
			continue;
		fprintf(out, "%s%s: ", n++ ? ", " : "    match: {", keys[i]);
		print_str(out, vals[i]);
	}
	fprintf(out, n ? "}\n" : "    # match: {}  (every thread)\n");
}

/*
 * print_fields - the keys of a table at an indent: groups of plain keys
 * as flow maps, a group holding groups (can.defaults) as a block
 */
static void print_fields(FILE *out, const struct field *fields, const void *obj,
			 const char *ind)
{
	const struct field *f, *t;
	char val[512], deeper[32];

	for (f = fields; f->key; f++) {
		for (t = f->type == F_GROUP ? f->sub : NULL; t && t->key; t++)
			if (t->type == F_GROUP)
				break;
		if (t && t->key) {
			fprintf(out, "%s%s:\n", ind, f->key);
			snprintf(deeper, sizeof(deeper), "%s  ", ind);
			print_fields(out, f->sub, (const char *)obj + f->off, deeper);
			continue;
		}
		fmt_value(val, sizeof(val), f, obj);
		fprintf(out, "%s%s: %s\n", ind, f->key, val);
	}
}

/*
 * print_node - one entry of can.nodes. Its thresholds are printed in full,
 * like a rule's: struct can_node keeps the merged values, not which keys
 * the file gave. A period or group it has not are shown as comments.
 */
static void print_node(FILE *out, const struct can_node *n)
{
	const char *ind = "      ";
	const struct field *f;
	char val[512];

	fprintf(out, "    - name: ");
	print_str(out, n->name);
	fputc('\n', out);
	for (f = node_f; f->key; f++) {
		if (f->off == N(period_ns) && !n->period_ns) {
			fprintf(out, "%s# period: 0  (learned)\n", ind);
		} else if (f->off == N(group) && !n->group[0]) {
			fprintf(out, "%s# group: \"\"  (none)\n", ind);
		} else {
			fmt_value(val, sizeof(val), f, n);
			fprintf(out, "%s%s: %s\n", ind, f->key, val);
		}
	}
}

/* cfg_print_can - the can: section */
void cfg_print_can(FILE *out, const struct can_config *cc)
{
	int i;

	fprintf(out, "can:\n");
	print_fields(out, can_f, cc, "  ");
	if (!cc->nnodes) {
		fprintf(out, "  nodes: []\n");
		return;
	}
	fprintf(out, "  nodes:\n");
	for (i = 0; i < cc->nnodes; i++)
		print_node(out, &cc->nodes[i]);
}

/* print_actions - the actions: section; of run, signal, fifo, unix only its own */
static void print_actions(FILE *out, const struct config *c)
{
	const struct field *f;
	char val[4 * ACTION_ARG_LEN + 3];
	size_t k;
	int i;

	if (!c->nactions) {
		fprintf(out, "actions: []\n");
		return;
	}
	fprintf(out, "actions:\n");
	for (i = 0; i < c->nactions; i++) {
		const struct action *a = &c->actions[i];
		bool first = true;

		for (f = action_f; f->key; f++) {
			bool skip = false;

			for (k = 0; k < naction_kinds; k++)
				if (f->flag == action_kinds[k].flag && a->kind != action_kinds[k].kind)
					skip = true;
			if (skip || (f->flag == AF_PID && a->kind != ACTION_SIGNAL))
				continue;
			fmt_value(val, sizeof(val), f, a);
			if (f->flag == AF_PID && !a->pid)
				fprintf(out, "    # pid: 0  (the component's process)\n");
			else
				fprintf(out, "%s%s: %s\n", first ? "  - " : "    ", f->key, val);
			first = false;
		}
	}
}

void config_print(const struct config *c, FILE *out)
{
	int i;

	fprintf(out, "# rtsup-trace effective configuration (%s)\n",
		c->path[0] ? c->path : "built in");
	fprintf(out, "defaults:\n");
	print_rule(out, &c->defaults, "  ", "built in");
	if (!c->nrules) {
		fprintf(out, "rules: []\n");
	} else {
		fprintf(out, "rules:\n");
		for (i = 0; i < c->nrules; i++) {
			fprintf(out, "  - name: ");
			print_str(out, c->rules[i].name);
			fputc('\n', out);
			print_match(out, &c->rules[i]);
			print_rule(out, &c->rules[i], "    ", "from defaults");
		}
	}
	cfg_print_can(out, &c->can);
	print_actions(out, c);
	fprintf(out, "ros2_diagnostics: %s\n", c->ros2_diagnostics ? "true" : "false");
}
