/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* errline.h - one-line error messages */
#ifndef RTSUP_ERRLINE_H
#define RTSUP_ERRLINE_H

#include <stddef.h>

/* seterr - format one line into err (control characters become spaces) */
void seterr(char *err, size_t errlen, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

#endif
