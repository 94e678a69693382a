// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * yamlwalk.c - the walk over libyaml's document tree: reading the file into
 * one document, typed access to its nodes, errors as "file:line:column:
 * what", and cfg_parse_group(), which applies a map to the field table that
 * describes it (each value through values.c).
 */
#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include "config/fields.h"

#define MAX_FILE_SIZE	(1 << 20)

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

/* cfg_fail - write "file:line:column: message" for a node, return -1 */
int cfg_fail(struct parse *p, const yaml_node_t *n, const char *fmt, ...)
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

/* cfg_kind - a node type in words, for type errors */
const char *cfg_kind(const yaml_node_t *n)
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

/* cfg_text - the value of a scalar node (NUL-terminated by libyaml) */
const char *cfg_text(const yaml_node_t *n)
{
	return (const char *)n->data.scalar.value;
}

/* cfg_is_null - an empty plain scalar or ~/null: an absent value */
bool cfg_is_null(const yaml_node_t *n)
{
	const char *s;

	if (n->type != YAML_SCALAR_NODE || n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
		return false;
	s = cfg_text(n);
	return !*s || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") ||
	       !strcmp(s, "NULL");
}

/* cfg_want - check a node's type; a null stands for an empty map or list */
int cfg_want(struct parse *p, const yaml_node_t *n, yaml_node_type_t type,
		const char *key)
{
	static const char *const names[] = {
		[YAML_SCALAR_NODE] = "a scalar",
		[YAML_SEQUENCE_NODE] = "a list",
		[YAML_MAPPING_NODE] = "a map",
	};

	if (n->type == type || (type != YAML_SCALAR_NODE && cfg_is_null(n)))
		return 0;
	return cfg_fail(p, n, "%s must be %s, not %s", key, names[type], cfg_kind(n));
}

/* cfg_node - a node of the document by index */
yaml_node_t *cfg_node(struct parse *p, int i)
{
	return yaml_document_get_node(p->doc, i);
}

/* cfg_npairs - number of pairs of a map node, 0 for a null */
int cfg_npairs(const yaml_node_t *n)
{
	if (n->type != YAML_MAPPING_NODE)
		return 0;
	return n->data.mapping.pairs.top - n->data.mapping.pairs.start;
}

/*
 * pair - key and value of the i-th pair of a map; keys must be scalars and
 * unique (libyaml does not check that, and a repeated key is a typo)
 */
int cfg_pair(struct parse *p, yaml_node_t *map, int i, yaml_node_t **k,
		yaml_node_t **v, const char *in)
{
	yaml_node_pair_t *pp = map->data.mapping.pairs.start;
	int j;

	*k = cfg_node(p, pp[i].key);
	*v = cfg_node(p, pp[i].value);
	if ((*k)->type != YAML_SCALAR_NODE)
		return cfg_fail(p, *k, "keys must be scalars, not %s", cfg_kind(*k));
	for (j = 0; j < i; j++) {
		yaml_node_t *o = cfg_node(p, pp[j].key);

		if (o->type == YAML_SCALAR_NODE && !strcmp(cfg_text(o), cfg_text(*k)))
			return cfg_fail(p, *k, "duplicate key '%s' %s", cfg_text(*k), in);
	}
	return 0;
}

/* cfg_scalar - the text of a node that must be a scalar */
int cfg_scalar(struct parse *p, const yaml_node_t *n, const char *key,
		  const char **s)
{
	if (cfg_want(p, n, YAML_SCALAR_NODE, key))
		return -1;
	*s = cfg_text(n);
	return 0;
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
void cfg_in_where(const struct parse *p, const char *path, char *in, size_t len)
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
int cfg_parse_group(struct parse *p, const struct field *fields, yaml_node_t *map,
		       void *obj, __u32 *set, const char *path, const char *what,
		       const char *const *own)
{
	const struct field *f;
	yaml_node_t *k, *v;
	char in[160], keys[160];
	int i;

	cfg_in_where(p, path, in, sizeof(in));
	if (cfg_want(p, map, YAML_MAPPING_NODE, *path ? path : p->where))
		return -1;
	for (i = 0; i < cfg_npairs(map); i++) {
		if (cfg_pair(p, map, i, &k, &v, in))
			return -1;
		/* e.g. name and match of a rule, handled by parse_rule */
		if (is_own(own, cfg_text(k)))
			continue;
		f = lookup(fields, cfg_text(k));
		if (!f && what) {
			key_list(fields, keys, sizeof(keys));
			return cfg_fail(p, k, "unknown %s '%s' %s (want %s)", what, cfg_text(k), in,
				    keys);
		}
		if (!f)
			return cfg_fail(p, k, "unknown key '%s' %s", cfg_text(k), in);
		if (cfg_parse_field(p, f, v, obj, set, path))
			return -1;
		if (set)
			*set |= f->flag;
	}
	return 0;
}

/* cfg_copy_str - a string field of limited length */
int cfg_copy_str(struct parse *p, yaml_node_t *v, const char *key, char *dst,
		    size_t len)
{
	const char *s;

	if (cfg_scalar(p, v, key, &s))
		return -1;
	if (!*s)
		return cfg_fail(p, v, "%s must not be empty", key);
	if (strlen(s) >= len)
		return cfg_fail(p, v, "%s too long (at most %zu characters)", key, len - 1);
	memcpy(dst, s, strlen(s) + 1);
	return 0;
}

/* cfg_find_key - the value of a key of a map (a rule's or node's name), or NULL */
yaml_node_t *cfg_find_key(struct parse *p, yaml_node_t *map, const char *key)
{
	yaml_node_pair_t *pp;

	if (map->type != YAML_MAPPING_NODE)
		return NULL;
	for (pp = map->data.mapping.pairs.start; pp < map->data.mapping.pairs.top; pp++) {
		yaml_node_t *k = cfg_node(p, pp->key);

		if (k->type == YAML_SCALAR_NODE && !strcmp(cfg_text(k), key))
			return cfg_node(p, pp->value);
	}
	return NULL;
}

/* cfg_list_items - items of the list under 'what': 0 when empty or null, -1 if no list */
int cfg_list_items(struct parse *p, yaml_node_t *seq, const char *what)
{
	if (cfg_want(p, seq, YAML_SEQUENCE_NODE, what))
		return -1;
	if (seq->type != YAML_SEQUENCE_NODE)
		return 0;
	return seq->data.sequence.items.top - seq->data.sequence.items.start;
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

/* cfg_load_doc - the file as one YAML document; -1 with err written */
int cfg_load_doc(const char *path, yaml_document_t *doc, char *err, size_t errlen)
{
	size_t len;
	char *buf;
	int ret;

	buf = read_file(path, &len, err, errlen);
	if (!buf)
		return -1;
	ret = load_doc(path, buf, len, doc, err, errlen);
	free(buf);
	return ret;
}
