// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* errline.c - one-line error messages for the file writers and readers */
#include <stdarg.h>
#include <stdio.h>
#include "sinks/errline.h"

/* seterr - format one line into err (newlines become spaces) */
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
		if (*p == '\n' || *p == '\r')
			*p = ' ';
}
