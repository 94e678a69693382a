// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* textbuf.c - a growing text buffer (textbuf.h) */
#include <stdlib.h>
#include <string.h>
#include "sinks/textbuf.h"

bool textbuf_grow(struct textbuf *b, size_t n)
{
	size_t cap;
	char *p;

	if (b->oom)
		return false;
	if (b->len + n + 1 <= b->cap)
		return true;
	cap = b->cap ? b->cap : 4096;
	while (cap < b->len + n + 1)
		cap *= 2;
	p = realloc(b->p, cap);
	if (!p) {
		b->oom = true;
		return false;
	}
	b->p = p;
	b->cap = cap;
	return true;
}

void textbuf_u64(struct textbuf *b, unsigned long long v)
{
	/* two digits a division: half the divisions of one at a time */
	static const char pairs[] = "00010203040506070809101112131415161718192021222324"
				    "25262728293031323334353637383940414243444546474849"
				    "50515253545556575859606162636465666768697071727374"
				    "75767778798081828384858687888990919293949596979899";
	char d[24];
	int i = sizeof(d);

	while (v >= 100) {
		unsigned r = (unsigned)(v % 100);

		v /= 100;
		d[--i] = pairs[2 * r + 1];
		d[--i] = pairs[2 * r];
	}
	if (v >= 10) {
		d[--i] = pairs[2 * v + 1];
		d[--i] = pairs[2 * v];
	} else {
		d[--i] = (char)('0' + v);
	}
	textbuf_put(b, d + i, sizeof(d) - i);
}

void textbuf_fraction(struct textbuf *b, unsigned long long fp, int ndig, bool keep_one)
{
	char f[20];
	int i, n = ndig;

	for (i = ndig - 1; i >= 0; i--, fp /= 10)
		f[i] = (char)('0' + fp % 10);
	while (n > (keep_one ? 1 : 0) && f[n - 1] == '0')
		n--;
	if (!n)
		return;
	textbuf_put(b, ".", 1);
	textbuf_put(b, f, (size_t)n);
}

void textbuf_free(struct textbuf *b)
{
	free(b->p);
	memset(b, 0, sizeof(*b));
}
