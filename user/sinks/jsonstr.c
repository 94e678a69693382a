// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * jsonstr.c - JSON strings from bytes that may not be UTF-8 (thread names,
 * command lines, configuration files): jansson refuses those, so invalid
 * sequences become U+FFFD. Shared by the recorded trace and the Perfetto writer.
 */
#include <stdlib.h>
#include <string.h>
#include "sinks/jsonstr.h"

size_t json_utf8_seq(const unsigned char *s, size_t n)
{
	unsigned int c = s[0], cp;
	size_t len, i;

	if (c < 0x80)
		return 1;
	if (c >= 0xc2 && c <= 0xdf)
		len = 2, cp = c & 0x1f;
	else if (c >= 0xe0 && c <= 0xef)
		len = 3, cp = c & 0x0f;
	else if (c >= 0xf0 && c <= 0xf4)
		len = 4, cp = c & 0x07;
	else
		return 0;
	if (len > n)
		return 0;
	for (i = 1; i < len; i++) {
		if ((s[i] & 0xc0) != 0x80)
			return 0;
		cp = cp << 6 | (s[i] & 0x3f);
	}
	if ((len == 3 && cp < 0x800) || (len == 4 && (cp < 0x10000 || cp > 0x10ffff)) ||
	    (cp >= 0xd800 && cp <= 0xdfff))
		return 0;
	return len;
}

/* json_str - a JSON string of s (at most max bytes), invalid UTF-8 as U+FFFD */
json_t *json_str(const char *s, size_t max)
{
	size_t n = strnlen(s, max), i, o = 0, k;
	json_t *j = json_stringn(s, n);
	char *buf;

	if (j)
		return j;
	buf = malloc(n * 3 + 1);
	if (!buf)
		return NULL;
	for (i = 0; i < n; i += k) {
		k = json_utf8_seq((const unsigned char *)s + i, n - i);
		if (k) {
			memcpy(buf + o, s + i, k);
			o += k;
		} else {
			memcpy(buf + o, "\xef\xbf\xbd", 3);
			o += 3;
			k = 1;
		}
	}
	j = json_stringn(buf, o);
	free(buf);
	return j;
}
