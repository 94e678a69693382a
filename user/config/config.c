// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * config.c - the YAML configuration file: defaults, rules, matching.
 *
 * libyaml builds the document tree; this file only walks it. Every key a
 * rule or the defaults may give is described once, in the field tables
 * below: the same tables parse, merge and print, so the printed form reads
 * back to the same configuration. The can: section (bus thresholds and
 * named CAN nodes) uses the same tables over struct can_config and
 * struct can_node.
 */
#include <errno.h>
#include <fnmatch.h>
#include <limits.h>
#include <math.h>
#include <sched.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <yaml.h>
#include "config/config.h"
#include "can.h"
#include "model/syscalls.h"

#ifndef SCHED_DEADLINE
#define SCHED_DEADLINE 6
#endif

#define NS_PER_S	1000000000ULL
#define MAX_DURATION_NS	(1e18)		/* about 31 years: no overflow in __u64 */
#define MAX_FILE_SIZE	(1 << 20)
#define SYSNAME_LEN	32
/* no more than a thread's settings in the kernel hold (struct rtsup_thread_cfg) */
#define MAX_DELIMS	RTSUP_CFG_DELIMS
#define MAX_LIST	RTSUP_CFG_SYSCALLS
#define CGROUP_FS	"/sys/fs/cgroup"

_Static_assert(MAX_DELIMS <= CONFIG_MAX_SYSCALLS && MAX_LIST <= CONFIG_MAX_SYSCALLS,
	       "struct rule holds the lists");

enum ftype {
	F_END,
	F_DURATION,	/* __u64 ns: "1ms", "250us", "0" */
	F_SECONDS,	/* double s, written as a duration */
	F_COUNT,	/* __u64 whole number */
	F_NUMBER,	/* double >= 0, e.g. periods */
	F_RATIO,	/* double ratio: "80%" or 0.8, up to .max */
	F_PERCENT,	/* double percent: "1%" or 0.01, up to .max percent */
	F_EWMA,		/* double 0 < w <= 1 */
	F_BOOL,
	F_STAT,		/* enum exec_stat */
	F_POLICY,	/* int SCHED_*, -1 any */
	F_PRIO,		/* int 1..99, -1 any */
	F_SYSLIST,	/* char [][32] at .off, int count at .off2 */
	F_GROUP,	/* nested map, keys in .sub, their offsets from here + .off */
	F_STR,		/* char [.max], not empty */
	F_IFACE,	/* char [16], a network interface name, "any" = "" */
	F_CANID,	/* __u32 id_lo at .off, id_hi at .off2: a CAN id or range */
	F_CANDIR,	/* int RTSUP_CAN_RX, RTSUP_CAN_TX or CAN_DIR_ANY */
	F_LEVEL,	/* enum level: OK, WARN, ERROR, STALE */
	F_WHEN,		/* bool: "enter" false, "leave" true */
	F_SIGNAL,	/* int signal number: USR1, SIGTERM, 10 */
};

struct field {
	const char *key;
	enum ftype type;
	size_t off;		/* from the start of the struct the table describes */
	size_t off2;
	double max;
	__u32 flag;		/* bit the key sets: RF_* of a rule, NF_* of a node */
	const struct field *sub;
	const char *what;	/* what an unknown key of a group is, "key" if NULL */
};

#define R(m)	offsetof(struct rule, m)
#define TH(m)	(offsetof(struct rule, th) + offsetof(struct thresholds, m))
#define UE(i)	TH(unsafe_error[i])

static const struct field miss_f[] = {
	{ .key = "warn", .type = F_COUNT, .off = TH(miss_warn) },
	{ .key = "error_rate", .type = F_RATIO, .off = TH(miss_error_rate), .max = 1 },
	{},
};

static const struct field exec_f[] = {
	{ .key = "warn", .type = F_RATIO, .off = TH(exec_warn_ratio), .max = 10 },
	{ .key = "stat", .type = F_STAT, .off = TH(exec_stat) },
	{},
};

static const struct field starve_f[] = {
	{ .key = "warn_periods", .type = F_NUMBER, .off = TH(starve_warn_periods) },
	{ .key = "error_periods", .type = F_NUMBER, .off = TH(starve_error_periods) },
	{},
};

/* the reason names of unsafe_reason_name() in model.c */
static const struct field unsafe_error_f[] = {
	{ .key = "syscall", .type = F_COUNT, .off = UE(RTSUP_U_SYSCALL) },
	{ .key = "minor_fault", .type = F_COUNT, .off = UE(RTSUP_U_MINFLT) },
	{ .key = "major_fault", .type = F_COUNT, .off = UE(RTSUP_U_MAJFLT) },
	{ .key = "block", .type = F_COUNT, .off = UE(RTSUP_U_BLOCK) },
	{ .key = "migration", .type = F_COUNT, .off = UE(RTSUP_U_MIGRATE) },
	{},
};

static const struct field unsafe_f[] = {
	{ .key = "warn", .type = F_COUNT, .off = TH(unsafe_warn) },
	{ .key = "error", .type = F_GROUP, .sub = unsafe_error_f, .what = "unsafe reason" },
	{},
};

static const struct field latency_f[] = {
	{ .key = "p99_warn", .type = F_DURATION, .off = TH(latency_p99_warn_ns) },
	{ .key = "max_warn", .type = F_DURATION, .off = TH(latency_max_warn_ns) },
	{ .key = "max_error", .type = F_DURATION, .off = TH(latency_max_error_ns) },
	{},
};

static const struct field jitter_f[] = {
	{ .key = "warn", .type = F_DURATION, .off = TH(jitter_warn_ns) },
	{ .key = "error", .type = F_DURATION, .off = TH(jitter_error_ns) },
	{},
};

static const struct field overhead_f[] = {
	{ .key = "warn", .type = F_PERCENT, .off = TH(overhead_warn_pct), .max = 100 },
	{ .key = "error", .type = F_PERCENT, .off = TH(overhead_error_pct), .max = 100 },
	{},
};

static const struct field thresholds_f[] = {
	{ .key = "init_timeout", .type = F_SECONDS, .off = TH(init_timeout_s) },
	{ .key = "deadline_miss", .type = F_GROUP, .sub = miss_f },
	{ .key = "exec_near_period", .type = F_GROUP, .sub = exec_f },
	{ .key = "starvation", .type = F_GROUP, .sub = starve_f },
	{ .key = "unsafe", .type = F_GROUP, .sub = unsafe_f },
	{ .key = "latency", .type = F_GROUP, .sub = latency_f },
	{ .key = "jitter", .type = F_GROUP, .sub = jitter_f },
	{ .key = "overhead", .type = F_GROUP, .sub = overhead_f },
	{ .key = "lifetime", .type = F_BOOL, .off = TH(lifetime) },
	{},
};

/* the keys of defaults:, and of a rule besides name and match */
static const struct field rule_f[] = {
	{ .key = "period", .type = F_DURATION, .off = R(period_ns), .flag = RF_PERIOD },
	{ .key = "ewma_weight", .type = F_EWMA, .off = R(ewma_weight), .flag = RF_EWMA },
	{ .key = "warmup", .type = F_DURATION, .off = R(warmup_ns), .flag = RF_WARMUP },
	{ .key = "cycle_syscalls", .type = F_SYSLIST, .off = R(delims), .off2 = R(ndelims),
	  .max = MAX_DELIMS, .flag = RF_DELIMS },
	{ .key = "policy", .type = F_POLICY, .off = R(policy), .flag = RF_POLICY },
	{ .key = "priority", .type = F_PRIO, .off = R(prio), .flag = RF_PRIO },
	{ .key = "allow_syscalls", .type = F_SYSLIST, .off = R(allow), .off2 = R(nallow),
	  .max = MAX_LIST, .flag = RF_ALLOW },
	{ .key = "forbid_syscalls", .type = F_SYSLIST, .off = R(forbid), .off2 = R(nforbid),
	  .max = MAX_LIST, .flag = RF_FORBID },
	{ .key = "thresholds", .type = F_GROUP, .sub = thresholds_f },
	{},
};

/* The can: section. Offsets from struct can_config, can_thresholds, can_node. */
#define CC(m)	offsetof(struct can_config, m)
#define CT(m)	offsetof(struct can_thresholds, m)
#define N(m)	offsetof(struct can_node, m)
#define IFACE_LEN	sizeof(((struct can_node *)0)->iface)

/* Bits of a node's keys, to tell which were given (parse only). */
enum node_field {
	NF_ID = 1 << 0,
};

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
static const struct field can_f[] = {
	{ .key = "canopen", .type = F_BOOL, .off = CC(canopen) },
	{ .key = "bitrate", .type = F_COUNT, .off = CC(bitrate) },
	{ .key = "bus_load", .type = F_GROUP, .sub = busload_f },
	{ .key = "error_frames", .type = F_GROUP, .sub = errframes_f },
	{ .key = "heartbeat_timeout", .type = F_DURATION, .off = CC(heartbeat_timeout_ns) },
	{ .key = "defaults", .type = F_GROUP, .off = CC(defaults), .sub = can_th_f },
	{},
};

/* the keys of a node besides name: its own, then can.defaults' over its th */
static const struct field node_f[] = {
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

/* An entry of actions: (struct action); exactly one of run, signal, fifo, unix. */
#define A(m)	offsetof(struct action, m)
#define UNIX_PATH_LEN	108	/* sizeof(sockaddr_un.sun_path) */

enum action_field {
	AF_LEVEL = 1 << 0,
	AF_RUN = 1 << 1,
	AF_SIGNAL = 1 << 2,
	AF_FIFO = 1 << 3,
	AF_UNIX = 1 << 4,
	AF_PID = 1 << 5,
};

static const struct field action_f[] = {
	{ .key = "level", .type = F_LEVEL, .off = A(level), .flag = AF_LEVEL },
	{ .key = "when", .type = F_WHEN, .off = A(leave) },
	{ .key = "run", .type = F_STR, .off = A(arg), .max = ACTION_ARG_LEN, .flag = AF_RUN },
	{ .key = "signal", .type = F_SIGNAL, .off = A(sig), .flag = AF_SIGNAL },
	{ .key = "pid", .type = F_COUNT, .off = A(pid), .flag = AF_PID },
	{ .key = "fifo", .type = F_STR, .off = A(arg), .max = ACTION_ARG_LEN, .flag = AF_FIFO },
	{ .key = "unix", .type = F_STR, .off = A(arg), .max = UNIX_PATH_LEN, .flag = AF_UNIX },
	{},
};

/* which key of an entry gives which kind of action */
static const struct {
	__u32 flag;
	enum action_kind kind;
} action_kinds[] = {
	{ AF_RUN, ACTION_RUN },
	{ AF_SIGNAL, ACTION_SIGNAL },
	{ AF_FIFO, ACTION_FIFO },
	{ AF_UNIX, ACTION_UNIX },
};

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

/* State of one config_load. */
struct parse {
	const char *file;
	yaml_document_t *doc;
	char *err;
	size_t errlen;
	char where[CONFIG_NAME_LEN + 16];	/* "defaults", "rule 'x'", "can node 'x'" or "" */
};

/* the keys a rule's and a node's callers handle themselves */
static const char *const rule_own[] = { "name", "match", NULL };
static const char *const node_own[] = { "name", NULL };
static const char *const can_own[] = { "nodes", NULL };

/*
 * one_line - a message quoting the file's text, with its control bytes
 * escaped: a YAML scalar may hold a newline (a blank line in a plain
 * scalar), and the error must stay one line
 */
static void one_line(char *dst, size_t len, const char *src)
{
	size_t o = 0;

	for (; *src && o + 5 < len; src++) {
		unsigned char ch = *src;

		if (ch == '\n')
			o += snprintf(dst + o, len - o, "\\n");
		else if (ch < 0x20 || ch == 0x7f)
			o += snprintf(dst + o, len - o, "\\x%02x", ch);
		else
			dst[o++] = ch;
	}
	dst[o] = '\0';
}

/* fail - write "file:line:column: message" for a node, return -1 */
static int __attribute__((format(printf, 3, 4)))
fail(struct parse *p, const yaml_node_t *n, const char *fmt, ...)
{
	char msg[256], line[256];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	one_line(line, sizeof(line), msg);
	snprintf(p->err, p->errlen, "%s:%zu:%zu: %s", p->file,
		 n->start_mark.line + 1, n->start_mark.column + 1, line);
	return -1;
}

/* kind - a node type in words, for type errors */
static const char *kind(const yaml_node_t *n)
{
	switch (n->type) {
	case YAML_MAPPING_NODE:
		return "a map";
	case YAML_SEQUENCE_NODE:
		return "a list";
	default:
		return "a scalar";
	}
}

/* text - the value of a scalar node (NUL-terminated by libyaml) */
static const char *text(const yaml_node_t *n)
{
	return (const char *)n->data.scalar.value;
}

/* is_null - an empty plain scalar or ~/null: an absent value */
static bool is_null(const yaml_node_t *n)
{
	const char *s;

	if (n->type != YAML_SCALAR_NODE || n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
		return false;
	s = text(n);
	return !*s || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") ||
	       !strcmp(s, "NULL");
}

/* want - check a node's type; a null stands for an empty map or list */
static int want(struct parse *p, const yaml_node_t *n, yaml_node_type_t type,
		const char *key)
{
	static const char *const names[] = {
		[YAML_SCALAR_NODE] = "a scalar",
		[YAML_SEQUENCE_NODE] = "a list",
		[YAML_MAPPING_NODE] = "a map",
	};

	if (n->type == type || (type != YAML_SCALAR_NODE && is_null(n)))
		return 0;
	return fail(p, n, "%s must be %s, not %s", key, names[type], kind(n));
}

/* node - a node of the document by index */
static yaml_node_t *node(struct parse *p, int i)
{
	return yaml_document_get_node(p->doc, i);
}

/* npairs - number of pairs of a map node, 0 for a null */
static int npairs(const yaml_node_t *n)
{
	if (n->type != YAML_MAPPING_NODE)
		return 0;
	return n->data.mapping.pairs.top - n->data.mapping.pairs.start;
}

/*
 * pair - key and value of the i-th pair of a map; keys must be scalars and
 * unique (libyaml does not check that, and a repeated key is a typo)
 */
static int pair(struct parse *p, yaml_node_t *map, int i, yaml_node_t **k,
		yaml_node_t **v, const char *in)
{
	yaml_node_pair_t *pp = map->data.mapping.pairs.start;
	int j;

	*k = node(p, pp[i].key);
	*v = node(p, pp[i].value);
	if ((*k)->type != YAML_SCALAR_NODE)
		return fail(p, *k, "keys must be scalars, not %s", kind(*k));
	for (j = 0; j < i; j++) {
		yaml_node_t *o = node(p, pp[j].key);

		if (o->type == YAML_SCALAR_NODE && !strcmp(text(o), text(*k)))
			return fail(p, *k, "duplicate key '%s' %s", text(*k), in);
	}
	return 0;
}

/* scalar - the text of a node that must be a scalar */
static int scalar(struct parse *p, const yaml_node_t *n, const char *key,
		  const char **s)
{
	if (want(p, n, YAML_SCALAR_NODE, key))
		return -1;
	*s = text(n);
	return 0;
}

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

/* parse_bool - the YAML 1.1 spellings of true and false */
static int parse_bool(const char *s, bool *b)
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

	if (want(p, v, YAML_SEQUENCE_NODE, f->key))
		return -1;
	if (v->type == YAML_SEQUENCE_NODE) {
		for (it = v->data.sequence.items.start; it < v->data.sequence.items.top; it++) {
			yaml_node_t *e = node(p, *it);
			const char *s;

			if (scalar(p, e, "a syscall name", &s))
				return -1;
			if (n == (int)f->max)
				return fail(p, e, "too many syscalls in %s (at most %d)", f->key,
					    (int)f->max);
			if (strlen(s) >= SYSNAME_LEN || syscall_nr(s) < 0)
				return fail(p, e, "unknown syscall '%s' in %s", s, f->key);
			snprintf(names[n++], SYSNAME_LEN, "%s", s);
		}
	}
	/* the cycle needs an end; the command line refuses an empty list too */
	if (!n && f->flag == RF_DELIMS)
		return fail(p, v, "%s must not be empty", f->key);
	*count = n;
	return 0;
}

static int parse_group(struct parse *p, const struct field *fields, yaml_node_t *map,
		       void *obj, __u32 *set, const char *path, const char *what,
		       const char *const *own);
static int copy_str(struct parse *p, yaml_node_t *v, const char *key, char *dst,
		    size_t len);

/* parse_number - a double field: F_NUMBER, F_RATIO, F_PERCENT, F_EWMA */
static int parse_number(struct parse *p, const struct field *f, yaml_node_t *v,
			const char *name, double *d)
{
	const char *s = text(v);
	char *end;
	double x;

	switch (f->type) {
	case F_NUMBER:
		if (numeric(s, &x, &end) || *end || x < 0)
			return fail(p, v, "bad number '%s' (want a number >= 0)", s);
		break;
	case F_EWMA:
		if (numeric(s, &x, &end) || *end)
			return fail(p, v, "bad number '%s' (want 0 < w <= 1)", s);
		if (x <= 0 || x > 1)
			return fail(p, v, "%s '%s' out of range (want 0 < w <= 1)", name, s);
		break;
	default:	/* F_RATIO, F_PERCENT: .max in the stored unit */
		if (parse_ratio(s, f->type == F_PERCENT, &x))
			return fail(p, v, "bad percentage '%s' (want e.g. 80%% or 0.8)", s);
		if (x < 0 || x > f->max)
			return fail(p, v, "%s '%s' out of range (want 0..%g%%)", name, s,
				    f->type == F_RATIO ? f->max * 100 : f->max);
		break;
	}
	*d = x;
	return 0;
}

/* parse_prio - an RT priority 1..99, or any (-1) */
static int parse_prio(struct parse *p, yaml_node_t *v, int *prio)
{
	const char *s = text(v);
	__u64 u;

	if (!strcasecmp(s, "any")) {
		*prio = -1;
		return 0;
	}
	if (parse_count(s, &u))
		return fail(p, v, "bad priority '%s' (want 1..99 or any)", s);
	if (u < 1 || u > 99)
		return fail(p, v, "priority '%s' out of range (want 1..99 or any)", s);
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
	const char *s = text(v), *dash = strchr(s, '-');
	size_t n1 = dash ? (size_t)(dash - s) : strlen(s);
	bool e1, e2;
	__u32 a, b;
	int r1, r2;

	r1 = parse_id_num(s, n1, &a, &e1);
	r2 = dash ? parse_id_num(dash + 1, strlen(dash + 1), &b, &e2) : r1;
	if (r1 == -1 || r2 == -1)
		return fail(p, v, "bad id '%s' (want e.g. 0x181, or a range 0x180-0x1ff)", s);
	if (r1 || r2)
		return fail(p, v, "id '%s' out of range (want 0..0x1FFFFFFF)", s);
	if (!dash) {
		b = a;
		e2 = e1;
	}
	if (e1 != e2)
		return fail(p, v, "id range '%s' mixes 11-bit and 29-bit ids", s);
	if (a > b)
		return fail(p, v, "id range '%s' is reversed (want low-high)", s);
	*lo = a | (e1 ? RTSUP_CAN_EFF_FLAG : 0);
	*hi = b | (e1 ? RTSUP_CAN_EFF_FLAG : 0);
	return 0;
}

/* parse_iface - a network interface name as the kernel allows it, or any */
static int parse_iface(struct parse *p, const struct field *f, yaml_node_t *v, char *dst)
{
	const char *s = text(v);

	if (!strcmp(s, "any")) {
		dst[0] = '\0';
		return 0;
	}
	if (copy_str(p, v, f->key, dst, (size_t)f->max))
		return -1;
	if (!strcmp(s, ".") || !strcmp(s, "..") || strpbrk(s, "/: \t\n\r\v\f"))
		return fail(p, v, "bad interface name '%s'", s);
	return 0;
}

/* parse_field - one key's value into the rule, can config or node */
static int parse_field(struct parse *p, const struct field *f, yaml_node_t *v,
		       void *obj, __u32 *set, const char *path)
{
	void *dst = (char *)obj + f->off;
	const char *s;
	char name[64];
	__u64 u;

	/* the dotted name, e.g. thresholds.latency.max_error, for messages */
	snprintf(name, sizeof(name), "%s%s%s", path, *path ? "." : "", f->key);
	if (f->type == F_GROUP)
		return parse_group(p, f->sub, v, dst, set, name, f->what, NULL);
	if (f->type == F_SYSLIST)
		return parse_syslist(p, f, v, obj);
	if (scalar(p, v, name, &s))
		return -1;
	switch (f->type) {
	case F_DURATION:
	case F_SECONDS:
		if (parse_duration_ns(s, &u))
			return fail(p, v, "bad duration '%s' (want e.g. 1ms)", s);
		if (f->type == F_DURATION)
			*(__u64 *)dst = u;
		else
			*(double *)dst = (double)u / NS_PER_S;
		return 0;
	case F_COUNT:
		if (parse_count(s, dst))
			return fail(p, v, "bad count '%s' (want a whole number >= 0)", s);
		return 0;
	case F_BOOL:
		if (parse_bool(s, dst))
			return fail(p, v, "bad boolean '%s' (want true or false)", s);
		return 0;
	case F_STAT:
		if (strcmp(s, "p99") && strcmp(s, "ewma"))
			return fail(p, v, "unknown stat '%s' (want p99 or ewma)", s);
		*(enum exec_stat *)dst = strcmp(s, "p99") ? EXEC_STAT_EWMA : EXEC_STAT_P99;
		return 0;
	case F_POLICY:
		if (parse_policy(s, dst))
			return fail(p, v, "unknown policy '%s' (want SCHED_FIFO, SCHED_RR, "
				    "SCHED_DEADLINE, SCHED_OTHER, SCHED_BATCH, SCHED_IDLE "
				    "or any)", s);
		return 0;
	case F_PRIO:
		return parse_prio(p, v, dst);
	case F_STR:
		return copy_str(p, v, f->key, dst, (size_t)f->max);
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
			return fail(p, v, "unknown direction '%s' (want rx, tx or any)", s);
		return 0;
	case F_LEVEL:
		if (level_parse(s) < 0)
			return fail(p, v, "unknown level '%s' (want OK, WARN, ERROR or STALE)", s);
		*(enum level *)dst = level_parse(s);
		return 0;
	case F_WHEN:
		if (strcmp(s, "enter") && strcmp(s, "leave"))
			return fail(p, v, "unknown when '%s' (want enter or leave)", s);
		*(bool *)dst = !strcmp(s, "leave");
		return 0;
	case F_SIGNAL:
		if (signal_parse(s) < 0)
			return fail(p, v, "unknown signal '%s' (want e.g. USR1, TERM or 10)", s);
		*(int *)dst = signal_parse(s);
		return 0;
	default:
		return parse_number(p, f, v, name, dst);
	}
}

/* key_list - "a, b or c": the keys of a table, to say what is allowed */
static void key_list(const struct field *f, char *buf, size_t len)
{
	size_t o = 0;

	buf[0] = '\0';
	for (; f->key && o < len; f++)
		o += snprintf(buf + o, len - o, "%s%s", o ? (f[1].key ? ", " : " or ") : "",
			      f->key);
}

/* lookup - the field of a key in a table, NULL if unknown */
static const struct field *lookup(const struct field *fields, const char *key)
{
	for (; fields->key; fields++)
		if (!strcmp(fields->key, key))
			return fields;
	return NULL;
}

/*
 * in_where - "in rule 'x'" or "in thresholds.latency of rule 'x'"; in the
 * can: map, where is "" and the path says it all: "in can.bus_load"
 */
static void in_where(const struct parse *p, const char *path, char *in, size_t len)
{
	if (!p->where[0])
		snprintf(in, len, "in %s", path);
	else if (*path)
		snprintf(in, len, "in %s of %s", path, p->where);
	else
		snprintf(in, len, "in %s", p->where);
}

/* is_own - a key the caller of parse_group handles itself */
static bool is_own(const char *const *own, const char *key)
{
	for (; own && *own; own++)
		if (!strcmp(*own, key))
			return true;
	return false;
}

/*
 * parse_group - a map of keys of one field table, over the values at obj;
 * path is where the map is ("" for the rule itself), what names its keys,
 * own the keys the caller handles; set collects the keys' flag bits
 */
static int parse_group(struct parse *p, const struct field *fields, yaml_node_t *map,
		       void *obj, __u32 *set, const char *path, const char *what,
		       const char *const *own)
{
	const struct field *f;
	yaml_node_t *k, *v;
	char in[160], keys[160];
	int i;

	in_where(p, path, in, sizeof(in));
	if (want(p, map, YAML_MAPPING_NODE, *path ? path : p->where))
		return -1;
	for (i = 0; i < npairs(map); i++) {
		if (pair(p, map, i, &k, &v, in))
			return -1;
		/* e.g. name and match of a rule, handled by parse_rule */
		if (is_own(own, text(k)))
			continue;
		f = lookup(fields, text(k));
		if (!f && what) {
			key_list(fields, keys, sizeof(keys));
			return fail(p, k, "unknown %s '%s' %s (want %s)", what, text(k), in,
				    keys);
		}
		if (!f)
			return fail(p, k, "unknown key '%s' %s", text(k), in);
		if (parse_field(p, f, v, obj, set, path))
			return -1;
		if (set)
			*set |= f->flag;
	}
	return 0;
}

/* copy_str - a string field of limited length */
static int copy_str(struct parse *p, yaml_node_t *v, const char *key, char *dst,
		    size_t len)
{
	const char *s;

	if (scalar(p, v, key, &s))
		return -1;
	if (!*s)
		return fail(p, v, "%s must not be empty", key);
	if (strlen(s) >= len)
		return fail(p, v, "%s too long (at most %zu characters)", key, len - 1);
	memcpy(dst, s, strlen(s) + 1);
	return 0;
}

/* cgroup_below - path equals prefix or is below it at a '/' boundary */
static bool cgroup_below(const char *path, const char *prefix)
{
	size_t n = strlen(prefix);

	if (!strcmp(prefix, "/"))
		return path[0] == '/';
	return !strncmp(path, prefix, n) && (path[n] == '\0' || path[n] == '/');
}

/* parse_match - process, thread and cgroup of a rule's match: */
static int parse_match(struct parse *p, yaml_node_t *map, struct rule *r)
{
	char in[160];
	yaml_node_t *k, *v;
	size_t n;
	int i;

	snprintf(in, sizeof(in), "in match of %s", p->where);
	if (want(p, map, YAML_MAPPING_NODE, "match"))
		return -1;
	for (i = 0; i < npairs(map); i++) {
		if (pair(p, map, i, &k, &v, in))
			return -1;
		if (!strcmp(text(k), "process")) {
			if (copy_str(p, v, "process", r->match_process, CONFIG_NAME_LEN))
				return -1;
		} else if (!strcmp(text(k), "thread")) {
			if (copy_str(p, v, "thread", r->match_thread, CONFIG_NAME_LEN))
				return -1;
		} else if (!strcmp(text(k), "cgroup")) {
			if (copy_str(p, v, "cgroup", r->match_cgroup, CONFIG_PATH_LEN))
				return -1;
			if (r->match_cgroup[0] != '/')
				return fail(p, v, "cgroup '%s' is not a path (want e.g. "
					    "/robot.slice)", r->match_cgroup);
			/* threads carry the path inside the hierarchy, not the mount */
			if (cgroup_below(r->match_cgroup, CGROUP_FS))
				return fail(p, v, "cgroup '%s' is a file system path (want the "
					    "path below %s, e.g. /robot.slice)", r->match_cgroup,
					    CGROUP_FS);
			/* a trailing slash would break the prefix test */
			n = strlen(r->match_cgroup);
			while (n > 1 && r->match_cgroup[n - 1] == '/')
				r->match_cgroup[--n] = '\0';
		} else {
			return fail(p, k, "unknown key '%s' %s", text(k), in);
		}
	}
	return 0;
}

/* list_node - the value of the last allow/forbid list a map gives, or the map */
static yaml_node_t *list_node(struct parse *p, yaml_node_t *map)
{
	yaml_node_t *at = map;
	int i;

	for (i = 0; i < npairs(map); i++) {
		yaml_node_pair_t *pp = &map->data.mapping.pairs.start[i];
		yaml_node_t *k = node(p, pp->key);

		if (!strcmp(text(k), "allow_syscalls") || !strcmp(text(k), "forbid_syscalls"))
			at = node(p, pp->value);
	}
	return at;
}

/*
 * conflicts - a syscall both allowed and forbidden is a contradiction, also
 * when one of the lists comes from the defaults (which one wins is unclear)
 */
static int conflicts(struct parse *p, yaml_node_t *map, const struct rule *r)
{
	int i, j;

	for (i = 0; i < r->nallow; i++)
		for (j = 0; j < r->nforbid; j++)
			if (!strcmp(r->allow[i], r->forbid[j]))
				return fail(p, list_node(p, map), "syscall '%s' is in both "
					    "allow_syscalls and forbid_syscalls of %s",
					    r->allow[i], p->where);
	return 0;
}

/* find_key - the value of a key of a map (a rule's or node's name), or NULL */
static yaml_node_t *find_key(struct parse *p, yaml_node_t *map, const char *key)
{
	yaml_node_pair_t *pp;

	if (map->type != YAML_MAPPING_NODE)
		return NULL;
	for (pp = map->data.mapping.pairs.start; pp < map->data.mapping.pairs.top; pp++) {
		yaml_node_t *k = node(p, pp->key);

		if (k->type == YAML_SCALAR_NODE && !strcmp(text(k), key))
			return node(p, pp->value);
	}
	return NULL;
}

/* parse_rule - one entry of rules:, starting as a copy of the defaults */
static int parse_rule(struct parse *p, yaml_node_t *map, struct config *c, int idx)
{
	struct rule *r = &c->rules[idx];
	yaml_node_t *name, *k, *v;
	char in[CONFIG_NAME_LEN + 20];
	int i;

	if (want(p, map, YAML_MAPPING_NODE, "a rule"))
		return -1;
	*r = c->defaults;
	r->set = 0;
	r->line = map->start_mark.line + 1;
	memset(r->name, 0, sizeof(r->name));
	name = find_key(p, map, "name");
	if (!name)
		return fail(p, map, "rule %d has no name", idx + 1);
	if (copy_str(p, name, "rule name", r->name, CONFIG_NAME_LEN))
		return -1;
	snprintf(p->where, sizeof(p->where), "rule '%s'", r->name);
	in_where(p, "", in, sizeof(in));
	for (i = 0; i < idx; i++)
		if (!strcmp(c->rules[i].name, r->name))
			return fail(p, name, "duplicate rule name '%s' (first at line %d)",
				    r->name, c->rules[i].line);
	for (i = 0; i < npairs(map); i++) {
		if (pair(p, map, i, &k, &v, in))
			return -1;
		if (!strcmp(text(k), "match") && parse_match(p, v, r))
			return -1;
	}
	if (parse_group(p, rule_f, map, r, &r->set, "", NULL, rule_own))
		return -1;
	return conflicts(p, map, r);
}

/* list_items - items of the list under 'what': 0 when empty or null, -1 if no list */
static int list_items(struct parse *p, yaml_node_t *seq, const char *what)
{
	if (want(p, seq, YAML_SEQUENCE_NODE, what))
		return -1;
	if (seq->type != YAML_SEQUENCE_NODE)
		return 0;
	return seq->data.sequence.items.top - seq->data.sequence.items.start;
}

/* parse_rules - the list under rules: */
static int parse_rules(struct parse *p, yaml_node_t *seq, struct config *c)
{
	int n, i;

	n = list_items(p, seq, "rules");
	if (n <= 0)
		return n;
	c->rules = calloc(n, sizeof(*c->rules));
	if (!c->rules)
		return fail(p, seq, "out of memory");
	for (i = 0; i < n; i++) {
		c->nrules = i + 1;
		if (parse_rule(p, node(p, seq->data.sequence.items.start[i]), c, i))
			return -1;
	}
	return 0;
}

/* parse_defaults - the defaults: map, over the built-in defaults */
static int parse_defaults(struct parse *p, yaml_node_t *map, struct config *c)
{
	snprintf(p->where, sizeof(p->where), "defaults");
	if (map->type == YAML_MAPPING_NODE)
		c->defaults.line = map->start_mark.line + 1;
	if (parse_group(p, rule_f, map, &c->defaults, &c->defaults.set, "", NULL, NULL))
		return -1;
	return conflicts(p, map, &c->defaults);
}

/* parse_node - one entry of can.nodes, starting from can.defaults */
static int parse_node(struct parse *p, yaml_node_t *map, struct can_config *cc, int idx)
{
	struct can_node *n = &cc->nodes[idx];
	yaml_node_t *name;
	__u32 set = 0;
	int i;

	if (want(p, map, YAML_MAPPING_NODE, "a can node"))
		return -1;
	memset(n, 0, sizeof(*n));
	n->dir = CAN_DIR_ANY;
	n->th = cc->defaults;
	n->line = map->start_mark.line + 1;
	name = find_key(p, map, "name");
	if (!name)
		return fail(p, map, "can node %d has no name", idx + 1);
	if (copy_str(p, name, "node name", n->name, CONFIG_NAME_LEN))
		return -1;
	snprintf(p->where, sizeof(p->where), "can node '%s'", n->name);
	for (i = 0; i < idx; i++)
		if (!strcmp(cc->nodes[i].name, n->name))
			return fail(p, name, "duplicate node name '%s' (first at line %d)",
				    n->name, cc->nodes[i].line);
	if (parse_group(p, node_f, map, n, &set, "", NULL, node_own))
		return -1;
	if (!(set & NF_ID))
		return fail(p, map, "can node '%s' has no id", n->name);
	return 0;
}

/* parse_nodes - the list under can.nodes */
static int parse_nodes(struct parse *p, yaml_node_t *seq, struct can_config *cc)
{
	int n, i;

	n = list_items(p, seq, "can.nodes");
	if (n <= 0)
		return n;
	cc->nodes = calloc(n, sizeof(*cc->nodes));
	if (!cc->nodes)
		return fail(p, seq, "out of memory");
	for (i = 0; i < n; i++) {
		cc->nnodes = i + 1;
		if (parse_node(p, node(p, seq->data.sequence.items.start[i]), cc, i))
			return -1;
	}
	return 0;
}

/* parse_can - the can: map; nodes start from can.defaults, so they come last */
static int parse_can(struct parse *p, yaml_node_t *map, struct config *c)
{
	yaml_node_t *nodes;

	p->where[0] = '\0';
	if (parse_group(p, can_f, map, &c->can, NULL, "can", NULL, can_own))
		return -1;
	nodes = map->type == YAML_MAPPING_NODE ? find_key(p, map, "nodes") : NULL;
	return nodes ? parse_nodes(p, nodes, &c->can) : 0;
}

/* parse_action - one entry of actions: */
static int parse_action(struct parse *p, yaml_node_t *map, struct action *a, int idx)
{
	__u32 set = 0, kinds = 0;
	size_t i;

	memset(a, 0, sizeof(*a));
	a->line = map->start_mark.line + 1;
	snprintf(p->where, sizeof(p->where), "action %d", idx + 1);
	if (parse_group(p, action_f, map, a, &set, "", "key", NULL))
		return -1;
	if (!(set & AF_LEVEL))
		return fail(p, map, "action %d has no level", idx + 1);
	for (i = 0; i < sizeof(action_kinds) / sizeof(action_kinds[0]); i++) {
		if (set & action_kinds[i].flag) {
			a->kind = action_kinds[i].kind;
			kinds++;
		}
	}
	if (kinds != 1)
		return fail(p, map, "action %d: give one of run, signal, fifo or unix", idx + 1);
	if ((set & AF_PID) && a->kind != ACTION_SIGNAL)
		return fail(p, map, "action %d: pid goes with signal only", idx + 1);
	if ((set & AF_PID) && (!a->pid || a->pid > INT_MAX))
		return fail(p, map, "action %d: bad pid %llu (want a process id)", idx + 1,
			    (unsigned long long)a->pid);
	return 0;
}

/* parse_actions - the list under actions: */
static int parse_actions(struct parse *p, yaml_node_t *seq, struct config *c)
{
	int n, i;

	n = list_items(p, seq, "actions");
	if (n <= 0)
		return n;
	if (n > ACTION_MAX)
		return fail(p, seq, "%d actions (at most %d)", n, ACTION_MAX);
	c->actions = calloc(ACTION_MAX, sizeof(*c->actions));
	if (!c->actions)
		return fail(p, seq, "out of memory");
	for (i = 0; i < n; i++) {
		yaml_node_t *map = node(p, seq->data.sequence.items.start[i]);

		c->nactions = i + 1;
		if (want(p, map, YAML_MAPPING_NODE, "an action"))
			return -1;
		if (parse_action(p, map, &c->actions[i], i))
			return -1;
	}
	return 0;
}

/* parse_top - the document: a map with defaults:, rules:, can:, actions: and ros2_diagnostics: */
static int parse_top(struct parse *p, yaml_node_t *top, struct config *c)
{
	yaml_node_t *k, *v, *rules = NULL;
	int i;

	if (is_null(top))
		return 0;
	if (top->type != YAML_MAPPING_NODE)
		return fail(p, top, "the file must be a map, not %s", kind(top));
	for (i = 0; i < npairs(top); i++) {
		if (pair(p, top, i, &k, &v, "at top level"))
			return -1;
		if (!strcmp(text(k), "rules"))
			rules = v;
		else if (!strcmp(text(k), "defaults")) {
			if (parse_defaults(p, v, c))
				return -1;
		} else if (!strcmp(text(k), "can")) {
			if (parse_can(p, v, c))
				return -1;
		} else if (!strcmp(text(k), "actions")) {
			if (parse_actions(p, v, c))
				return -1;
		} else if (!strcmp(text(k), "ros2_diagnostics")) {
			const char *b;

			if (scalar(p, v, "ros2_diagnostics", &b))
				return -1;
			if (parse_bool(b, &c->ros2_diagnostics))
				return fail(p, v, "bad boolean '%s' (want true or false)", b);
		} else {
			return fail(p, k, "unknown key '%s' at top level (want defaults, "
				    "rules, can, actions or ros2_diagnostics)", text(k));
		}
	}
	/* rules copy the defaults, so they come after them whatever the order */
	return rules ? parse_rules(p, rules, c) : 0;
}

/* read_file - the whole file into memory */
static char *read_file(const char *path, size_t *len, char *err, size_t errlen)
{
	char *buf = NULL;
	size_t n = 0, got;
	FILE *f;
	int e;

	f = fopen(path, "r");
	if (!f) {
		snprintf(err, errlen, "%s: cannot read: %s", path, strerror(errno));
		return NULL;
	}
	do {
		char *nb = realloc(buf, n + 4096 + 1);

		if (!nb || n > MAX_FILE_SIZE) {
			e = nb ? EFBIG : ENOMEM;
			free(nb ? nb : buf);
			fclose(f);
			snprintf(err, errlen, "%s: cannot read: %s", path, strerror(e));
			return NULL;
		}
		buf = nb;
		got = fread(buf + n, 1, 4096, f);
		n += got;
	} while (got == 4096);
	if (ferror(f)) {
		e = errno;
		free(buf);
		fclose(f);
		snprintf(err, errlen, "%s: cannot read: %s", path, strerror(e));
		return NULL;
	}
	fclose(f);
	buf[n] = '\0';
	*len = n;
	return buf;
}

/* offset_mark - line and column of a byte offset, for reader errors */
static yaml_mark_t offset_mark(const char *buf, size_t off)
{
	yaml_mark_t m = { 0 };
	size_t i;

	for (i = 0; i < off && buf[i]; i++) {
		if (buf[i] == '\n') {
			m.line++;
			m.column = 0;
		} else {
			m.column++;
		}
	}
	return m;
}

/* syntax_error - libyaml's own message, with where it happened */
static void syntax_error(const char *path, const char *buf, const yaml_parser_t *y,
			 char *err, size_t errlen)
{
	const char *what = y->problem ? y->problem : "syntax error";
	yaml_mark_t m = y->problem_mark;

	/* the reader (bad UTF-8...) gives a byte offset, not a mark */
	if (y->error == YAML_READER_ERROR)
		m = offset_mark(buf, y->problem_offset);
	if (y->context && y->context_mark.line != m.line)
		snprintf(err, errlen, "%s:%zu:%zu: %s (%s at line %zu)", path, m.line + 1,
			 m.column + 1, what, y->context, y->context_mark.line + 1);
	else
		snprintf(err, errlen, "%s:%zu:%zu: %s", path, m.line + 1, m.column + 1, what);
}

/* load_doc - parse the text; a second document in the file is an error */
static int load_doc(const char *path, const char *buf, size_t len, yaml_document_t *doc,
		    char *err, size_t errlen)
{
	yaml_document_t extra;
	yaml_parser_t y;
	int ret = -1;

	if (!yaml_parser_initialize(&y)) {
		snprintf(err, errlen, "%s: cannot read: %s", path, strerror(ENOMEM));
		return -1;
	}
	yaml_parser_set_input_string(&y, (const unsigned char *)buf, len);
	if (!yaml_parser_load(&y, doc)) {
		syntax_error(path, buf, &y, err, errlen);
		goto out;
	}
	if (!yaml_parser_load(&y, &extra)) {
		syntax_error(path, buf, &y, err, errlen);
		yaml_document_delete(doc);
		goto out;
	}
	if (yaml_document_get_root_node(&extra)) {
		snprintf(err, errlen, "%s:%zu:%zu: more than one YAML document", path,
			 extra.start_mark.line + 1, extra.start_mark.column + 1);
		yaml_document_delete(&extra);
		yaml_document_delete(doc);
		goto out;
	}
	yaml_document_delete(&extra);
	ret = 0;
out:
	yaml_parser_delete(&y);
	return ret;
}

void config_defaults(struct config *c)
{
	struct rule *d = &c->defaults;

	memset(c, 0, sizeof(*c));
	snprintf(d->name, sizeof(d->name), "defaults");
	d->ewma_weight = 0.1;
	snprintf(d->delims[0], SYSNAME_LEN, "clock_nanosleep");
	snprintf(d->delims[1], SYSNAME_LEN, "nanosleep");
	d->ndelims = 2;
	d->policy = -1;
	d->prio = -1;
	d->th.init_timeout_s = 5;
	d->th.miss_warn = 1;
	d->th.miss_error_rate = 0.01;
	d->th.exec_warn_ratio = 0.8;
	d->th.exec_stat = EXEC_STAT_P99;
	d->th.starve_warn_periods = 10;
	d->th.starve_error_periods = 100;
	d->th.unsafe_warn = 1;
	d->th.unsafe_error[RTSUP_U_MAJFLT] = 1;
	d->th.overhead_warn_pct = 1;
	d->th.overhead_error_pct = 5;
	c->can.busload_warn = 0.7;
	c->can.busload_error = 0.9;
	c->can.err_warn = 1;
	c->can.err_error = 100;
	c->can.heartbeat_timeout_ns = NS_PER_S;
	c->can.defaults.warn_periods = 3;
	c->can.defaults.error_periods = 10;
	c->can.defaults.learn_s = 2;
	c->can.defaults.init_timeout_s = 5;
}

int config_load(const char *path, struct config *c, char *err, size_t errlen)
{
	struct parse p = { .file = path, .err = err, .errlen = errlen };
	yaml_document_t doc;
	struct config tmp;
	yaml_node_t *top;
	size_t len;
	char *buf;
	int ret;

	buf = read_file(path, &len, err, errlen);
	if (!buf)
		return -1;
	ret = load_doc(path, buf, len, &doc, err, errlen);
	free(buf);
	if (ret)
		return -1;
	config_defaults(&tmp);
	snprintf(tmp.path, sizeof(tmp.path), "%s", path);
	p.doc = &doc;
	top = yaml_document_get_root_node(&doc);
	ret = top ? parse_top(&p, top, &tmp) : 0;
	yaml_document_delete(&doc);
	if (ret) {
		config_free(&tmp);
		return -1;
	}
	*c = tmp;
	return 0;
}

/* rule_matches - every match key the rule gives matches; unknown never does */
static bool rule_matches(const struct rule *r, const char *process, const char *thread,
			 const char *cgroup)
{
	if (r->match_process[0] && (!process || fnmatch(r->match_process, process, 0)))
		return false;
	if (r->match_thread[0] && (!thread || fnmatch(r->match_thread, thread, 0)))
		return false;
	if (r->match_cgroup[0] && (!cgroup || !cgroup_below(cgroup, r->match_cgroup)))
		return false;
	return true;
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

int config_match(const struct config *c, const char *process, const char *thread,
		 const char *cgroup, struct rule *effective)
{
	int i;

	for (i = 0; i < c->nrules; i++) {
		if (rule_matches(&c->rules[i], process, thread, cgroup)) {
			if (effective)
				*effective = c->rules[i];
			return i;
		}
	}
	if (effective)
		*effective = c->defaults;
	return -1;
}

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

/* policy_name - SCHED_* name of a policy, "any" for -1 */
static const char *policy_name(int policy)
{
	int i;

	for (i = 0; i < NPOLICIES; i++)
		if (policies[i].policy == policy)
			return policies[i].name;
	return "any";
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
		snprintf(buf, len, "%s", policy_name(*(const int *)src));
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

/* print_can - the can: section */
static void print_can(FILE *out, const struct can_config *cc)
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

			for (k = 0; k < sizeof(action_kinds) / sizeof(action_kinds[0]); k++)
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

int config_add_action(struct config *c, const struct action *a)
{
	if (c->nactions == ACTION_MAX)
		return -1;
	if (!c->actions) {
		c->actions = calloc(ACTION_MAX, sizeof(*c->actions));
		if (!c->actions)
			return -1;
	}
	c->actions[c->nactions++] = *a;
	return 0;
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
	print_can(out, &c->can);
	print_actions(out, c);
	fprintf(out, "ros2_diagnostics: %s\n", c->ros2_diagnostics ? "true" : "false");
}

void config_free(struct config *c)
{
	free(c->rules);
	c->rules = NULL;
	c->nrules = 0;
	free(c->can.nodes);
	c->can.nodes = NULL;
	c->can.nnodes = 0;
	free(c->actions);
	c->actions = NULL;
	c->nactions = 0;
}
