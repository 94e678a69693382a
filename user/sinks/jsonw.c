// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* jsonw.c - JSON written straight into a buffer (jsonw.h) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sinks/jsonstr.h"
#include "sinks/jsonw.h"

static void put(struct jw *w, const char *s, size_t n)
{
	textbuf_put(&w->t, s, n);
}

static void putc1(struct jw *w, char c)
{
	textbuf_put(&w->t, &c, 1);
}

/* member - the comma before a value and its key (a constant name: no escapes) */
static void member(struct jw *w, const char *key)
{
	if (w->depth > JW_DEPTH) {	/* deeper than kept: a comma always (no writer does) */
		putc1(w, ',');
	} else if (w->depth > 0) {
		if (!w->first[w->depth - 1])
			putc1(w, ',');
		w->first[w->depth - 1] = false;
	}
	if (key) {
		putc1(w, '"');
		put(w, key, strlen(key));
		put(w, "\":", 2);
	}
}

void jw_reset(struct jw *w)
{
	w->t.len = 0;
	w->t.oom = false;
	w->depth = 0;
}

void jw_free(struct jw *w)
{
	textbuf_free(&w->t);
	w->depth = 0;
}

static void open_(struct jw *w, const char *key, char c)
{
	member(w, key);
	putc1(w, c);
	if (w->depth < JW_DEPTH)
		w->first[w->depth] = true;
	w->depth++;
}

void jw_obj(struct jw *w, const char *key)
{
	open_(w, key, '{');
}

void jw_arr(struct jw *w, const char *key)
{
	open_(w, key, '[');
}

void jw_end_obj(struct jw *w)
{
	w->depth--;
	putc1(w, '}');
}

void jw_end_arr(struct jw *w)
{
	w->depth--;
	putc1(w, ']');
}

void jw_int(struct jw *w, const char *key, long long v)
{
	member(w, key);
	if (v < 0)
		putc1(w, '-');
	textbuf_u64(&w->t, v < 0 ? 0ULL - (unsigned long long)v : (unsigned long long)v);
}

void jw_bool(struct jw *w, const char *key, bool v)
{
	member(w, key);
	if (v)
		put(w, "true", 4);
	else
		put(w, "false", 5);
}

void jw_null(struct jw *w, const char *key)
{
	member(w, key);
	put(w, "null", 4);
}

void jw_str(struct jw *w, const char *key, const char *s, size_t max)
{
	static const char hex[] = "0123456789ABCDEF";
	const unsigned char *p = (const unsigned char *)s;
	size_t n = strnlen(s, max), i, k;

	member(w, key);
	putc1(w, '"');
	for (i = 0; i < n; i += k) {
		unsigned char c = p[i];

		k = 1;
		if (c == '"' || c == '\\') {
			putc1(w, '\\');
			putc1(w, (char)c);
		} else if (c < 0x20) {
			/* jansson's escapes: the short ones, else \u00XX */
			const char *e = c == '\b' ? "\\b" : c == '\f' ? "\\f" : c == '\n' ? "\\n" :
					c == '\r' ? "\\r" : c == '\t' ? "\\t" : NULL;
			char u[6] = { '\\', 'u', '0', '0', hex[c >> 4], hex[c & 15] };

			if (e)
				put(w, e, 2);
			else
				put(w, u, sizeof(u));
		} else if (c < 0x80) {
			putc1(w, (char)c);
		} else {
			k = json_utf8_seq(p + i, n - i);
			if (k) {
				put(w, s + i, k);
			} else {
				put(w, "\xef\xbf\xbd", 3);	/* U+FFFD */
				k = 1;
			}
		}
	}
	putc1(w, '"');
}

/* real - "ip.fp", fp being ndig decimal digits, its trailing zeros cut but one */
static void real(struct jw *w, bool neg, unsigned long long ip, unsigned long long fp, int ndig)
{
	if (neg)
		putc1(w, '-');
	textbuf_u64(&w->t, ip);
	textbuf_fraction(&w->t, fp, ndig, true);
}

void jw_ns(struct jw *w, const char *key, double v)
{
	char b[32];
	int n;

	if (!isfinite(v)) {
		jw_null(w, key);
		return;
	}
	member(w, key);
	if (fabs(v) < 9e12) {	/* v * 1000 exact in a long long */
		long long q = llround(fabs(v) * 1000);

		real(w, v < 0 && q, (unsigned long long)q / 1000,
			    (unsigned long long)q % 1000, 3);
		return;
	}
	n = snprintf(b, sizeof(b), "%.17g", v);
	put(w, b, (size_t)n);
	if (!strpbrk(b, ".e"))
		put(w, ".0", 2);
}

void jw_fixed(struct jw *w, const char *key, long long v, int shift)
{
	unsigned long long u = v < 0 ? 0ULL - (unsigned long long)v : (unsigned long long)v;
	unsigned long long f = u & ((1ULL << shift) - 1), p5 = 1;
	int i;

	member(w, key);
	/* f / 2^shift = f * 5^shift / 10^shift: shift decimal digits, exactly */
	for (i = 0; i < shift; i++)
		p5 *= 5;
	real(w, v < 0, u >> shift, f * p5, shift ? shift : 1);
}

void jw_json(struct jw *w, const char *key, json_t *v)
{
	size_t n;

	member(w, key);
	if (!v) {
		put(w, "null", 4);
		return;
	}
	n = json_dumpb(v, NULL, 0, JSON_COMPACT | JSON_ENCODE_ANY);
	if (n && textbuf_room(&w->t, n))
		w->t.len += json_dumpb(v, w->t.p + w->t.len, n, JSON_COMPACT | JSON_ENCODE_ANY);
	json_decref(v);
}
