/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* strict.h - whole numbers and sizes from option and configuration text, nothing else accepted */
#ifndef RTSUP_STRICT_H
#define RTSUP_STRICT_H

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* strict_long - a whole number in [min, max] with no trailing text: 0, or -1 */
static inline int strict_long(const char *s, long min, long max, long *out)
{
	char *end;
	long v;

	/* strtol would take leading blanks and a '+' */
	if (!((*s >= '0' && *s <= '9') || *s == '-'))
		return -1;
	errno = 0;
	v = strtol(s, &end, 10);
	if (errno || end == s || *end || v < min || v > max)
		return -1;
	*out = v;
	return 0;
}

/*
 * strict_size - bytes as a whole number with an optional binary suffix, K
 * or M ("64K", "2M", "4194304"), the whole in [min, max]: 0, or -1
 */
static inline int strict_size(const char *s, long min, long max, long *out)
{
	static const struct { char c; long mul; } suffix[] = {
		{ 'k', 1L << 10 }, { 'K', 1L << 10 }, { 'm', 1L << 20 }, { 'M', 1L << 20 },
	};
	char buf[16];
	size_t n = strlen(s), i;
	long v, mul = 1;

	if (!n || n >= sizeof(buf))
		return -1;
	memcpy(buf, s, n + 1);
	for (i = 0; i < sizeof(suffix) / sizeof(suffix[0]); i++)
		if (buf[n - 1] == suffix[i].c) {
			mul = suffix[i].mul;
			buf[n - 1] = '\0';
		}
	if (strict_long(buf, 1, max, &v) || v > max / mul || v * mul < min)
		return -1;
	*out = v * mul;
	return 0;
}

#endif
