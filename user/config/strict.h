/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* strict.h - whole numbers from option and configuration text, nothing else accepted */
#ifndef RTSUP_STRICT_H
#define RTSUP_STRICT_H

#include <errno.h>
#include <stdlib.h>

/* strict_long - a whole number in [min, max] with no trailing text: 0, or -1 */
static inline int strict_long(const char *s, long min, long max, long *out)
{
	char *end;
	long v;

	errno = 0;
	v = strtol(s, &end, 10);
	if (errno || end == s || *end || v < min || v > max)
		return -1;
	*out = v;
	return 0;
}

#endif
