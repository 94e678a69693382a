// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * config.c - the configuration's model: the built-in defaults, the rules
 * (match: by process, thread, cgroup) and actions of the file, and which
 * rule a thread gets (config_match).
 *
 * libyaml builds the document tree; yamlwalk.c walks it. Every key a
 * rule or the defaults may give is described once, in the field tables
 * below (the can: section's in canconfig.c): the same tables parse, merge
 * and print (print.c), so the printed form reads back to the same
 * configuration.
 */
#include <fnmatch.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include "config/fields.h"
#include "model/syscalls.h"

/* no more than a thread's settings in the kernel hold (struct rtsup_thread_cfg) */
#define MAX_DELIMS	RTSUP_CFG_DELIMS
#define MAX_LIST	RTSUP_CFG_SYSCALLS
#define CGROUP_FS	"/sys/fs/cgroup"

_Static_assert(MAX_DELIMS <= CONFIG_MAX_SYSCALLS && MAX_LIST <= CONFIG_MAX_SYSCALLS,
	       "struct rule holds the lists");

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
const struct field rule_f[] = {
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
	{ .key = "stacks", .type = F_STACKS, .off = R(stacks), .flag = RF_STACKS },
	{ .key = "stack_size", .type = F_STACKSIZE, .off = R(stack_size), .flag = RF_STACK_SIZE },
	{ .key = "thresholds", .type = F_GROUP, .sub = thresholds_f },
	{},
};

/* An entry of actions: (struct action); exactly one of run, signal, fifo, unix. */
#define A(m)	offsetof(struct action, m)
#define UNIX_PATH_LEN	108	/* sizeof(sockaddr_un.sun_path) */

const struct field action_f[] = {
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
const struct action_kind_key action_kinds[] = {
	{ AF_RUN, ACTION_RUN },
	{ AF_SIGNAL, ACTION_SIGNAL },
	{ AF_FIFO, ACTION_FIFO },
	{ AF_UNIX, ACTION_UNIX },
};
const size_t naction_kinds = sizeof(action_kinds) / sizeof(action_kinds[0]);

/* the keys of a rule that parse_rule handles itself */
static const char *const rule_own[] = { "name", "match", NULL };

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
	if (cfg_want(p, map, YAML_MAPPING_NODE, "match"))
		return -1;
	for (i = 0; i < cfg_npairs(map); i++) {
		if (cfg_pair(p, map, i, &k, &v, in))
			return -1;
		if (!strcmp(cfg_text(k), "process")) {
			if (cfg_copy_str(p, v, "process", r->match_process, CONFIG_NAME_LEN))
				return -1;
		} else if (!strcmp(cfg_text(k), "thread")) {
			if (cfg_copy_str(p, v, "thread", r->match_thread, CONFIG_NAME_LEN))
				return -1;
		} else if (!strcmp(cfg_text(k), "cgroup")) {
			if (cfg_copy_str(p, v, "cgroup", r->match_cgroup, CONFIG_PATH_LEN))
				return -1;
			if (r->match_cgroup[0] != '/')
				return cfg_fail(p, v, "cgroup '%s' is not a path (want e.g. "
					    "/robot.slice)", r->match_cgroup);
			/* threads carry the path inside the hierarchy, not the mount */
			if (cgroup_below(r->match_cgroup, CGROUP_FS))
				return cfg_fail(p, v, "cgroup '%s' is a file system path (want the "
					    "path below %s, e.g. /robot.slice)", r->match_cgroup,
					    CGROUP_FS);
			/* a trailing slash would break the prefix test */
			n = strlen(r->match_cgroup);
			while (n > 1 && r->match_cgroup[n - 1] == '/')
				r->match_cgroup[--n] = '\0';
		} else {
			return cfg_fail(p, k, "unknown key '%s' %s", cfg_text(k), in);
		}
	}
	return 0;
}

/* list_node - the value of the last allow/forbid list a map gives, or the map */
static yaml_node_t *list_node(struct parse *p, yaml_node_t *map)
{
	yaml_node_t *at = map;
	int i;

	for (i = 0; i < cfg_npairs(map); i++) {
		yaml_node_pair_t *pp = &map->data.mapping.pairs.start[i];
		yaml_node_t *k = cfg_node(p, pp->key);

		if (!strcmp(cfg_text(k), "allow_syscalls") || !strcmp(cfg_text(k), "forbid_syscalls"))
			at = cfg_node(p, pp->value);
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
				return cfg_fail(p, list_node(p, map), "syscall '%s' is in both "
					    "allow_syscalls and forbid_syscalls of %s",
					    r->allow[i], p->where);
	return 0;
}

/* parse_rule - one entry of rules:, starting as a copy of the defaults */
static int parse_rule(struct parse *p, yaml_node_t *map, struct config *c, int idx)
{
	struct rule *r = &c->rules[idx];
	yaml_node_t *name, *k, *v;
	char in[CONFIG_NAME_LEN + 20];
	int i;

	if (cfg_want(p, map, YAML_MAPPING_NODE, "a rule"))
		return -1;
	*r = c->defaults;
	r->set = 0;
	r->line = map->start_mark.line + 1;
	memset(r->name, 0, sizeof(r->name));
	name = cfg_find_key(p, map, "name");
	if (!name)
		return cfg_fail(p, map, "rule %d has no name", idx + 1);
	if (cfg_copy_str(p, name, "rule name", r->name, CONFIG_NAME_LEN))
		return -1;
	snprintf(p->where, sizeof(p->where), "rule '%s'", r->name);
	cfg_in_where(p, "", in, sizeof(in));
	for (i = 0; i < idx; i++)
		if (!strcmp(c->rules[i].name, r->name))
			return cfg_fail(p, name, "duplicate rule name '%s' (first at line %d)",
				    r->name, c->rules[i].line);
	for (i = 0; i < cfg_npairs(map); i++) {
		if (cfg_pair(p, map, i, &k, &v, in))
			return -1;
		if (!strcmp(cfg_text(k), "match") && parse_match(p, v, r))
			return -1;
	}
	if (cfg_parse_group(p, rule_f, map, r, &r->set, "", NULL, rule_own))
		return -1;
	return conflicts(p, map, r);
}

/* parse_rules - the list under rules: */
static int parse_rules(struct parse *p, yaml_node_t *seq, struct config *c)
{
	int n, i;

	n = cfg_list_items(p, seq, "rules");
	if (n <= 0)
		return n;
	c->rules = calloc(n, sizeof(*c->rules));
	if (!c->rules)
		return cfg_fail(p, seq, "out of memory");
	for (i = 0; i < n; i++) {
		c->nrules = i + 1;
		if (parse_rule(p, cfg_node(p, seq->data.sequence.items.start[i]), c, i))
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
	if (cfg_parse_group(p, rule_f, map, &c->defaults, &c->defaults.set, "", NULL, NULL))
		return -1;
	return conflicts(p, map, &c->defaults);
}

/* parse_action - one entry of actions: */
static int parse_action(struct parse *p, yaml_node_t *map, struct action *a, int idx)
{
	__u32 set = 0, kinds = 0;
	size_t i;

	memset(a, 0, sizeof(*a));
	a->line = map->start_mark.line + 1;
	snprintf(p->where, sizeof(p->where), "action %d", idx + 1);
	if (cfg_parse_group(p, action_f, map, a, &set, "", "key", NULL))
		return -1;
	if (!(set & AF_LEVEL))
		return cfg_fail(p, map, "action %d has no level", idx + 1);
	for (i = 0; i < naction_kinds; i++) {
		if (set & action_kinds[i].flag) {
			a->kind = action_kinds[i].kind;
			kinds++;
		}
	}
	if (kinds != 1)
		return cfg_fail(p, map, "action %d: give one of run, signal, fifo or unix", idx + 1);
	if ((set & AF_PID) && a->kind != ACTION_SIGNAL)
		return cfg_fail(p, map, "action %d: pid goes with signal only", idx + 1);
	if ((set & AF_PID) && (!a->pid || a->pid > INT_MAX))
		return cfg_fail(p, map, "action %d: bad pid %llu (want a process id)", idx + 1,
			    (unsigned long long)a->pid);
	return 0;
}

/* parse_actions - the list under actions: */
static int parse_actions(struct parse *p, yaml_node_t *seq, struct config *c)
{
	int n, i;

	n = cfg_list_items(p, seq, "actions");
	if (n <= 0)
		return n;
	if (n > ACTION_MAX)
		return cfg_fail(p, seq, "%d actions (at most %d)", n, ACTION_MAX);
	c->actions = calloc(ACTION_MAX, sizeof(*c->actions));
	if (!c->actions)
		return cfg_fail(p, seq, "out of memory");
	for (i = 0; i < n; i++) {
		yaml_node_t *map = cfg_node(p, seq->data.sequence.items.start[i]);

		c->nactions = i + 1;
		if (cfg_want(p, map, YAML_MAPPING_NODE, "an action"))
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

	if (cfg_is_null(top))
		return 0;
	if (top->type != YAML_MAPPING_NODE)
		return cfg_fail(p, top, "the file must be a map, not %s", cfg_kind(top));
	for (i = 0; i < cfg_npairs(top); i++) {
		if (cfg_pair(p, top, i, &k, &v, "at top level"))
			return -1;
		if (!strcmp(cfg_text(k), "rules"))
			rules = v;
		else if (!strcmp(cfg_text(k), "defaults")) {
			if (parse_defaults(p, v, c))
				return -1;
		} else if (!strcmp(cfg_text(k), "can")) {
			if (cfg_parse_can(p, v, c))
				return -1;
		} else if (!strcmp(cfg_text(k), "actions")) {
			if (parse_actions(p, v, c))
				return -1;
		} else if (!strcmp(cfg_text(k), "ros2_diagnostics")) {
			const char *b;

			if (cfg_scalar(p, v, "ros2_diagnostics", &b))
				return -1;
			if (cfg_parse_bool(b, &c->ros2_diagnostics))
				return cfg_fail(p, v, "bad boolean '%s' (want true or false)", b);
		} else {
			return cfg_fail(p, k, "unknown key '%s' at top level (want defaults, "
				    "rules, can, actions or ros2_diagnostics)", cfg_text(k));
		}
	}
	/* rules copy the defaults, so they come after them whatever the order */
	return rules ? parse_rules(p, rules, c) : 0;
}

/* stack_dwarf - may this setting capture DWARF records? (auto: until a verdict, and after) */
static bool stack_dwarf(__u32 kind)
{
	return kind == RTSUP_STACKS_DWARF || kind == RTSUP_STACKS_AUTO;
}

void config_stack_plan(const struct config *c, struct stack_plan *p)
{
	int i;

	memset(p, 0, sizeof(*p));
	p->kind = c->defaults.stacks;
	p->size = c->defaults.stack_size;
	for (i = -1; i < c->nrules; i++) {
		const struct rule *r = i < 0 ? &c->defaults : &c->rules[i];

		if (r->stacks != RTSUP_STACKS_OFF)
			p->any = true;
		if (r->stacks == RTSUP_STACKS_AUTO)
			p->autos = true;
		if (stack_dwarf(r->stacks)) {
			p->dwarf = true;
			if (r->stack_size > p->size_max)
				p->size_max = r->stack_size;
		}
		if (r->stacks != p->kind || (stack_dwarf(r->stacks) && r->stack_size != p->size))
			p->rules = true;
	}
}

/* add_names - the numbers of names (checked at load) not yet in v, up to SYS_RULE_NAMES */
static void add_names(__u16 *v, int *n, const char (*names)[32], int count)
{
	int i, j, nr;

	for (i = 0; i < count && *n < SYS_RULE_NAMES; i++) {
		nr = syscall_nr(names[i]);
		for (j = 0; j < *n && v[j] != nr; j++)
			;
		if (nr >= 0 && j == *n)
			v[(*n)++] = nr;
	}
}

void config_sys_names(const struct config *c, struct sys_rule_names *n)
{
	int i;

	memset(n, 0, sizeof(*n));
	for (i = -1; i < c->nrules; i++) {
		const struct rule *r = i < 0 ? &c->defaults : &c->rules[i];

		add_names(n->delims, &n->ndelims, r->delims, r->ndelims);
		add_names(n->forbid, &n->nforbid, r->forbid, r->nforbid);
	}
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
	d->stacks = RTSUP_STACKS_OFF;
	d->stack_size = 8192;
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
	int ret;

	if (cfg_load_doc(path, &doc, err, errlen))
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
