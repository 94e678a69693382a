/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * config/fields.h - inside the configuration module (not for other stages):
 * the field tables that describe every key of the file once, and the walk
 * over libyaml's document that the parts share. The same tables parse
 * (yamlwalk.c, values.c), merge (config.c, canconfig.c) and print
 * (print.c), so the printed form reads back to the same configuration.
 */
#ifndef RTSUP_CONFIG_FIELDS_H
#define RTSUP_CONFIG_FIELDS_H

#include <stddef.h>
#include <stdio.h>
#include <yaml.h>
#include "config/config.h"

#define NS_PER_S	1000000000ULL
#define SYSNAME_LEN	32

/* the type of a key's value: how values.c reads it and print.c writes it */
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
	F_STACKS,	/* __u32 enum rtsup_stacks: off, fp, dwarf, auto */
	F_STACKSIZE,	/* __u32 bytes: "8K", 512 to 64K, 8-aligned */
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

/* Bits of a node's keys, to tell which were given (parse only). */
enum node_field {
	NF_ID = 1 << 0,
};

/* Bits of an action's keys (parse_action, print_actions). */
enum action_field {
	AF_LEVEL = 1 << 0,
	AF_RUN = 1 << 1,
	AF_SIGNAL = 1 << 2,
	AF_FIFO = 1 << 3,
	AF_UNIX = 1 << 4,
	AF_PID = 1 << 5,
};

/* State of one config_load. */
struct parse {
	const char *file;
	yaml_document_t *doc;
	char *err;
	size_t errlen;
	char where[CONFIG_NAME_LEN + 16];	/* "defaults", "rule 'x'", "can node 'x'" or "" */
};

/* the tables (config.c: a rule, an action; canconfig.c: the can: section) */
extern const struct field rule_f[];
extern const struct field action_f[];
extern const struct field can_f[];
extern const struct field node_f[];

/* which key of an action gives which kind of action (config.c) */
struct action_kind_key {
	__u32 flag;
	enum action_kind kind;
};
extern const struct action_kind_key action_kinds[];
extern const size_t naction_kinds;

/* yamlwalk.c: the document and its nodes */
int cfg_load_doc(const char *path, yaml_document_t *doc, char *err, size_t errlen);
int __attribute__((format(printf, 3, 4)))
cfg_fail(struct parse *p, const yaml_node_t *n, const char *fmt, ...);
const char *cfg_kind(const yaml_node_t *n);
const char *cfg_text(const yaml_node_t *n);
bool cfg_is_null(const yaml_node_t *n);
int cfg_want(struct parse *p, const yaml_node_t *n, yaml_node_type_t type, const char *key);
yaml_node_t *cfg_node(struct parse *p, int i);
int cfg_npairs(const yaml_node_t *n);
int cfg_pair(struct parse *p, yaml_node_t *map, int i, yaml_node_t **k, yaml_node_t **v,
	 const char *in);
int cfg_scalar(struct parse *p, const yaml_node_t *n, const char *key, const char **s);
int cfg_parse_bool(const char *s, bool *b);
void cfg_in_where(const struct parse *p, const char *path, char *in, size_t len);
int cfg_parse_group(struct parse *p, const struct field *fields, yaml_node_t *map,
		void *obj, __u32 *set, const char *path, const char *what,
		const char *const *own);
int cfg_copy_str(struct parse *p, yaml_node_t *v, const char *key, char *dst, size_t len);
yaml_node_t *cfg_find_key(struct parse *p, yaml_node_t *map, const char *key);
int cfg_list_items(struct parse *p, yaml_node_t *seq, const char *what);

/* values.c: one key's value, by its type */
int cfg_parse_field(struct parse *p, const struct field *f, yaml_node_t *v,
		void *obj, __u32 *set, const char *path);
const char *sched_policy_name(int policy);

/* canconfig.c: the can: map */
int cfg_parse_can(struct parse *p, yaml_node_t *map, struct config *c);

/* print.c: the can: section, for config_print */
void cfg_print_can(FILE *out, const struct can_config *cc);

#endif
