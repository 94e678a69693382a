/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * textbuf.h - a growing text buffer, and the numbers the hand-written
 * outputs put in it without printf (prom.c's exposition, jsonw.c's thread
 * objects). 'oom' once an allocation failed: the text is then cut.
 */
#ifndef RTSUP_TEXTBUF_H
#define RTSUP_TEXTBUF_H

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

struct textbuf {
	char *p;
	size_t len;
	size_t cap;
	bool oom;
};

/* textbuf_grow - textbuf_room when the buffer must grow */
bool textbuf_grow(struct textbuf *b, size_t n);

/*
 * textbuf_room - room for n more bytes and a terminating NUL; false when
 * out of memory. Inline, as textbuf_put: JSON puts its text a few bytes at
 * a time (a call each was a tenth of -j's thread objects).
 */
static inline bool textbuf_room(struct textbuf *b, size_t n)
{
	return (!b->oom && b->len + n + 1 <= b->cap) || textbuf_grow(b, n);
}

/* textbuf_put - n bytes of raw text */
static inline void textbuf_put(struct textbuf *b, const char *s, size_t n)
{
	if (!textbuf_room(b, n))
		return;
	memcpy(b->p + b->len, s, n);
	b->len += n;
}
/* textbuf_u64 - v in decimal */
void textbuf_u64(struct textbuf *b, unsigned long long v);
/*
 * textbuf_fraction - ".ddd": fp as ndig (<= 20) decimal digits, its trailing
 * zeros cut but one when keep_one; nothing at all when fp is 0 and !keep_one
 */
void textbuf_fraction(struct textbuf *b, unsigned long long fp, int ndig, bool keep_one);
void textbuf_free(struct textbuf *b);

#endif
