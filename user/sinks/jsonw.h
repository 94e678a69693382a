/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * jsonw.h - JSON written straight into a buffer, value by value, for what
 * goes out for every thread every interval (output.c's thread objects).
 * Built as jansson trees, 1000 threads cost about 45 us each (the trees'
 * mallocs, and every real formatted until it reads back the same); written
 * here, a few. Strings are escaped as jansson escapes them, invalid UTF-8
 * becomes U+FFFD (jsonstr.h). Rarer parts (causes, stacks, histograms)
 * stay jansson values, written in place by jw_json.
 */
#ifndef RTSUP_JSONW_H
#define RTSUP_JSONW_H

#include <stdbool.h>
#include <stddef.h>
#include <jansson.h>
#include "sinks/textbuf.h"

#define JW_DEPTH 16

struct jw {
	struct textbuf t;		/* t.oom: a write failed for memory, the value is cut */
	int depth;
	bool first[JW_DEPTH];		/* no member yet at that depth */
};

/* jw_reset - an empty buffer for the next value (kept allocated) */
void jw_reset(struct jw *w);
void jw_free(struct jw *w);
/* key: the member's name inside an object, NULL inside an array or at the top */
void jw_obj(struct jw *w, const char *key);
void jw_arr(struct jw *w, const char *key);
void jw_end_obj(struct jw *w);
void jw_end_arr(struct jw *w);
void jw_int(struct jw *w, const char *key, long long v);
void jw_bool(struct jw *w, const char *key, bool v);
void jw_null(struct jw *w, const char *key);
/* jw_str - s, at most max bytes, escaped */
void jw_str(struct jw *w, const char *key, const char *s, size_t max);
/*
 * jw_ns - a real number of ns to 0.001 ns (a mean): integer arithmetic,
 * none of printf's exact binary-to-decimal work; always with a '.', as
 * jansson writes a real
 */
void jw_ns(struct jw *w, const char *key, double v);
/* jw_fixed - a fixed-point value (v / 2^shift, shift <= 16), exactly */
void jw_fixed(struct jw *w, const char *key, long long v, int shift);
/* jw_json - a jansson value, dumped in place and freed (NULL: null) */
void jw_json(struct jw *w, const char *key, json_t *v);

#endif
