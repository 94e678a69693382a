// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * values.c - one key's value, by the type its field table gives: durations,
 * ratios, counts, booleans, policies, priorities, syscall lists, CAN ids,
 * interface names, levels, signals. Every refusal says what was wanted.
 */
#include <errno.h>
#include <math.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "config/fields.h"
#include "config/stackopt.h"
#include "can.h"
#include "model/syscalls.h"

#ifndef SCHED_DEADLINE
#define SCHED_DEADLINE 6
#endif

#define MAX_DURATION_NS	(1e18)		/* about 31 years: no overflow in __u64 */

static const struct {
	const char *name;
	int policy;
} policies[] = {
	{ "SCHED_OTHER", SCHED_OTHER },
	{ "SCHED_FIFO", SCHED_FIFO },
	{ "SCHED_RR", SCHED_RR },
	{ "SCHED_BATCH", SCHED_BATCH },
	{ "SCHED_IDLE", SCHED_IDLE },
	{ "SCHED_DEADLINE", SCHED_DEADLINE },
};

#define NPOLICIES (int)(sizeof(policies) / sizeof(policies[0]))

/* numeric - strtod over a plain decimal number only (no hex, inf, nan) */
static int numeric(const char *s, double *v, char **end)
{
	size_t n = strspn(s, "0123456789.eE+-");

	if (!n || (*s != '.' && *s != '+' && (*s < '0' || *s > '9')))
		return -1;
	errno = 0;
	*v = strtod(s, end);
	if (errno || *end == s || (size_t)(*end - s) > n || !isfinite(*v))
		return -1;
	return 0;
}

/* parse_duration_ns - "1ms", "100us", "5s", "5m", "1h", "500ns" or "0" */
static int parse_duration_ns(const char *s, __u64 *ns)
{
	static const struct {
		const char *unit;
		double mult;
	} units[] = {
		{ "ns", 1 }, { "us", 1e3 }, { "ms", 1e6 },
		{ "s", 1e9 }, { "m", 60e9 }, { "h", 3600e9 },
	};
	char *end;
	double v;
	size_t i;

	if (numeric(s, &v, &end) || v < 0)
		return -1;
	/* a bare number is ambiguous (s? ns?); only 0 needs no unit */
	if (!*end && v == 0) {
		*ns = 0;
		return 0;
	}
	for (i = 0; i < sizeof(units) / sizeof(units[0]); i++) {
		if (strcmp(end, units[i].unit))
			continue;
		if (v * units[i].mult > MAX_DURATION_NS)
			return -1;
		*ns = (__u64)llround(v * units[i].mult);
		return 0;
	}
	return -1;
}

/*
 * parse_ratio - "80%" or a plain ratio 0.8, as a ratio or as a percentage;
 * only one operation on the number, so printing it back is exact
 */
static int parse_ratio(const char *s, bool want_pct, double *r)
{
	bool pct;
	char *end;
	double v;

	if (numeric(s, &v, &end))
		return -1;
	pct = !strcmp(end, "%");
	if (!pct && *end)
		return -1;
	if (pct != want_pct)
		v = pct ? v / 100 : v * 100;
	*r = v;
	return 0;
}

/* parse_count - a whole number >= 0 */
static int parse_count(const char *s, __u64 *v)
{
	size_t n = strspn(s, "0123456789");

	if (!n || s[n])
		return -1;
	errno = 0;
	*v = strtoull(s, NULL, 10);
	return errno ? -1 : 0;
}

/* cfg_parse_bool - the YAML 1.1 spellings of true and false */
int cfg_parse_bool(const char *s, bool *b)
{
	static const char *const yes[] = { "true", "yes", "on" };
	static const char *const no[] = { "false", "no", "off" };
	size_t i;

	for (i = 0; i < 3; i++) {
		if (!strcasecmp(s, yes[i]) || !strcasecmp(s, no[i])) {
			*b = !strcasecmp(s, yes[i]);
			return 0;
		}
	}
	return -1;
}

/* parse_policy - SCHED_FIFO or FIFO (any case), or any */
static int parse_policy(const char *s, int *policy)
{
	int i;

	if (!strcasecmp(s, "any")) {
		*policy = -1;
		return 0;
	}
	for (i = 0; i < NPOLICIES; i++) {
		if (!strcasecmp(s, policies[i].name) || !strcasecmp(s, policies[i].name + 6)) {
			*policy = policies[i].policy;
			return 0;
		}
	}
	return -1;
}

/* parse_syslist - a list of syscall names known on this architecture */
static int parse_syslist(struct parse *p, const struct field *f, yaml_node_t *v,
			 void *obj)
{
	char (*names)[SYSNAME_LEN] = (void *)((char *)obj + f->off);
	int *count = (int *)((char *)obj + f->off2);
	yaml_node_item_t *it;
	int n = 0;

	if (cfg_want(p, v, YAML_SEQUENCE_NODE, f->key))
		return -1;
	if (v->type == YAML_SEQUENCE_NODE) {
		for (it = v->data.sequence.items.start; it < v->data.sequence.items.top; it++) {
			yaml_node_t *e = cfg_node(p, *it);
			const char *s;

			if (cfg_scalar(p, e, "a syscall name", &s))
				return -1;
			if (n == (int)f->max)
				return cfg_fail(p, e, "too many syscalls in %s (at most %d)", f->key,
					    (int)f->max);
			if (strlen(s) >= SYSNAME_LEN || syscall_nr(s) < 0)
				return cfg_fail(p, e, "unknown syscall '%s' in %s", s, f->key);
			snprintf(names[n++], SYSNAME_LEN, "%s", s);
		}
	}
	/* the cycle needs an end; the command line refuses an empty list too */
	if (!n && f->flag == RF_DELIMS)
		return cfg_fail(p, v, "%s must not be empty", f->key);
	*count = n;
	return 0;
}

/* parse_number - a double field: F_NUMBER, F_RATIO, F_PERCENT, F_EWMA */
static int parse_number(struct parse *p, const struct field *f, yaml_node_t *v,
			const char *name, double *d)
{
	const char *s = cfg_text(v);
	char *end;
	double x;

	switch (f->type) {
	case F_NUMBER:
		if (numeric(s, &x, &end) || *end || x < 0)
			return cfg_fail(p, v, "bad number '%s' (want a number >= 0)", s);
		break;
	case F_EWMA:
		if (numeric(s, &x, &end) || *end)
			return cfg_fail(p, v, "bad number '%s' (want 0 < w <= 1)", s);
		if (x <= 0 || x > 1)
			return cfg_fail(p, v, "%s '%s' out of range (want 0 < w <= 1)", name, s);
		break;
	default:	/* F_RATIO, F_PERCENT: .max in the stored unit */
		if (parse_ratio(s, f->type == F_PERCENT, &x))
			return cfg_fail(p, v, "bad percentage '%s' (want e.g. 80%% or 0.8)", s);
		if (x < 0 || x > f->max)
			return cfg_fail(p, v, "%s '%s' out of range (want 0..%g%%)", name, s,
				    f->type == F_RATIO ? f->max * 100 : f->max);
		break;
	}
	*d = x;
	return 0;
}

/* parse_prio - an RT priority 1..99, or any (-1) */
static int parse_prio(struct parse *p, yaml_node_t *v, int *prio)
{
	const char *s = cfg_text(v);
	__u64 u;

	if (!strcasecmp(s, "any")) {
		*prio = -1;
		return 0;
	}
	if (parse_count(s, &u))
		return cfg_fail(p, v, "bad priority '%s' (want 1..99 or any)", s);
	if (u < 1 || u > 99)
		return cfg_fail(p, v, "priority '%s' out of range (want 1..99 or any)", s);
	*prio = (int)u;
	return 0;
}

/*
 * parse_id_num - one CAN identifier of an id: key, "0x181" or "385";
 * 0 ok, -1 not a number, -2 above 0x1FFFFFFF. Eight hex digits, as
 * candump writes 29-bit ids, make a 29-bit id even when it is small.
 */
static int parse_id_num(const char *s, size_t n, __u32 *id, bool *eff)
{
	bool hex = n > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
	size_t i = hex ? 2 : 0, digits = n - i;
	__u64 v = 0;

	if (!digits)
		return -1;
	for (; i < n; i++) {
		int d;

		if (s[i] >= '0' && s[i] <= '9')
			d = s[i] - '0';
		else if (hex && s[i] >= 'a' && s[i] <= 'f')
			d = s[i] - 'a' + 10;
		else if (hex && s[i] >= 'A' && s[i] <= 'F')
			d = s[i] - 'A' + 10;
		else
			return -1;
		/* keep scanning the digits, but stop growing once out of range */
		if (v <= RTSUP_CAN_EFF_MASK)
			v = v * (hex ? 16 : 10) + d;
	}
	if (v > RTSUP_CAN_EFF_MASK)
		return -2;
	*id = (__u32)v;
	*eff = v > RTSUP_CAN_SFF_MASK || (hex && digits == 8);
	return 0;
}

/* parse_canid - id: a CAN identifier or an inclusive range "lo-hi" */
static int parse_canid(struct parse *p, yaml_node_t *v, __u32 *lo, __u32 *hi)
{
	const char *s = cfg_text(v), *dash = strchr(s, '-');
	size_t n1 = dash ? (size_t)(dash - s) : strlen(s);
	bool e1, e2;
	__u32 a, b;
	int r1, r2;

	r1 = parse_id_num(s, n1, &a, &e1);
	r2 = dash ? parse_id_num(dash + 1, strlen(dash + 1), &b, &e2) : r1;
	if (r1 == -1 || r2 == -1)
		return cfg_fail(p, v, "bad id '%s' (want e.g. 0x181, or a range 0x180-0x1ff)", s);
	if (r1 || r2)
		return cfg_fail(p, v, "id '%s' out of range (want 0..0x1FFFFFFF)", s);
	if (!dash) {
		b = a;
		e2 = e1;
	}
	if (e1 != e2)
		return cfg_fail(p, v, "id range '%s' mixes 11-bit and 29-bit ids", s);
	if (a > b)
		return cfg_fail(p, v, "id range '%s' is reversed (want low-high)", s);
	*lo = a | (e1 ? RTSUP_CAN_EFF_FLAG : 0);
	*hi = b | (e1 ? RTSUP_CAN_EFF_FLAG : 0);
	return 0;
}

/* parse_iface - a network interface name as the kernel allows it, or any */
static int parse_iface(struct parse *p, const struct field *f, yaml_node_t *v, char *dst)
{
	const char *s = cfg_text(v);

	if (!strcmp(s, "any")) {
		dst[0] = '\0';
		return 0;
	}
	if (cfg_copy_str(p, v, f->key, dst, (size_t)f->max))
		return -1;
	if (!strcmp(s, ".") || !strcmp(s, "..") || strpbrk(s, "/: \t\n\r\v\f"))
		return cfg_fail(p, v, "bad interface name '%s'", s);
	return 0;
}

/* cfg_parse_field - one key's value into the rule, can config or node */
int cfg_parse_field(struct parse *p, const struct field *f, yaml_node_t *v,
		       void *obj, __u32 *set, const char *path)
{
	void *dst = (char *)obj + f->off;
	const char *s;
	char name[64];
	__u64 u;

	/* the dotted name, e.g. thresholds.latency.max_error, for messages */
	snprintf(name, sizeof(name), "%s%s%s", path, *path ? "." : "", f->key);
	if (f->type == F_GROUP)
		return cfg_parse_group(p, f->sub, v, dst, set, name, f->what, NULL);
	if (f->type == F_SYSLIST)
		return parse_syslist(p, f, v, obj);
	if (cfg_scalar(p, v, name, &s))
		return -1;
	switch (f->type) {
	case F_DURATION:
	case F_SECONDS:
		if (parse_duration_ns(s, &u))
			return cfg_fail(p, v, "bad duration '%s' (want e.g. 1ms)", s);
		if (f->type == F_DURATION)
			*(__u64 *)dst = u;
		else
			*(double *)dst = (double)u / NS_PER_S;
		return 0;
	case F_COUNT:
		if (parse_count(s, dst))
			return cfg_fail(p, v, "bad count '%s' (want a whole number >= 0)", s);
		return 0;
	case F_BOOL:
		if (cfg_parse_bool(s, dst))
			return cfg_fail(p, v, "bad boolean '%s' (want true or false)", s);
		return 0;
	case F_STAT:
		if (strcmp(s, "p99") && strcmp(s, "ewma"))
			return cfg_fail(p, v, "unknown stat '%s' (want p99 or ewma)", s);
		*(enum exec_stat *)dst = strcmp(s, "p99") ? EXEC_STAT_EWMA : EXEC_STAT_P99;
		return 0;
	case F_POLICY:
		if (parse_policy(s, dst))
			return cfg_fail(p, v, "unknown policy '%s' (want SCHED_FIFO, SCHED_RR, "
				    "SCHED_DEADLINE, SCHED_OTHER, SCHED_BATCH, SCHED_IDLE "
				    "or any)", s);
		return 0;
	case F_PRIO:
		return parse_prio(p, v, dst);
	case F_STR:
		return cfg_copy_str(p, v, f->key, dst, (size_t)f->max);
	case F_IFACE:
		return parse_iface(p, f, v, dst);
	case F_CANID:
		return parse_canid(p, v, dst, (__u32 *)((char *)obj + f->off2));
	case F_CANDIR:
		if (!strcasecmp(s, "rx"))
			*(int *)dst = RTSUP_CAN_RX;
		else if (!strcasecmp(s, "tx"))
			*(int *)dst = RTSUP_CAN_TX;
		else if (!strcasecmp(s, "any"))
			*(int *)dst = CAN_DIR_ANY;
		else
			return cfg_fail(p, v, "unknown direction '%s' (want rx, tx or any)", s);
		return 0;
	case F_LEVEL:
		if (level_parse(s) < 0)
			return cfg_fail(p, v, "unknown level '%s' (want OK, WARN, ERROR or STALE)", s);
		*(enum level *)dst = level_parse(s);
		return 0;
	case F_WHEN:
		if (strcmp(s, "enter") && strcmp(s, "leave"))
			return cfg_fail(p, v, "unknown when '%s' (want enter or leave)", s);
		*(bool *)dst = !strcmp(s, "leave");
		return 0;
	case F_SIGNAL:
		if (signal_parse(s) < 0)
			return cfg_fail(p, v, "unknown signal '%s' (want e.g. USR1, TERM or 10)", s);
		*(int *)dst = signal_parse(s);
		return 0;
	case F_STACKS:
		if (stacks_parse(s, dst))
			return cfg_fail(p, v, "unknown stacks '%s' (want off, fp, dwarf or auto)", s);
		return 0;
	case F_STACKSIZE:
		if (stack_size_parse(s, dst))
			return cfg_fail(p, v, "bad stack_size '%s' (want bytes, a multiple of 8 "
				    "from 512 to 64K, e.g. 8K)", s);
		return 0;
	default:
		return parse_number(p, f, v, name, dst);
	}
}

/* sched_policy_name - SCHED_* name of a policy, "any" for -1 */
const char *sched_policy_name(int policy)
{
	int i;

	for (i = 0; i < NPOLICIES; i++)
		if (policies[i].policy == policy)
			return policies[i].name;
	return "any";
}
