// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* errline.c - one-line error messages for the file writers and readers */
#include <stdarg.h>
#include <stdio.h>
#include "sinks/errline.h"

/*
 * seterr - format one line into err: every control character becomes a
 * space. A damaged file's bytes quoted in a parser's message (jansson's
 * "near '...'") may hold a form feed or a vertical tab, which readers take
 * for a line break too (CI 104: the message's last line was "' (position 178)").
 */
void seterr(char *err, size_t errlen, const char *fmt, ...)
{
	va_list ap;
	char *p;

	if (!err || !errlen)
		return;
	va_start(ap, fmt);
	vsnprintf(err, errlen, fmt, ap);
	va_end(ap);
	for (p = err; *p; p++)
		if ((unsigned char)*p < 0x20 || *p == 0x7f)
			*p = ' ';
}
