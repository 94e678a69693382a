/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* jsonstr.h - a JSON string of any bytes: invalid UTF-8 as U+FFFD */
#ifndef RTSUP_JSONSTR_H
#define RTSUP_JSONSTR_H

#include <stddef.h>
#include <jansson.h>

/* json_utf8_seq - length of the valid UTF-8 sequence at s (n bytes left), 0 if invalid */
size_t json_utf8_seq(const unsigned char *s, size_t n);
/* json_str - a JSON string of s (at most max bytes), invalid UTF-8 as U+FFFD */
json_t *json_str(const char *s, size_t max);

#endif
