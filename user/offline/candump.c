// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * candump.c - one line of a can-utils candump log (`candump -l`, `candump -L`,
 * also with -x), in the format of can-utils' lib.c (sprint_canframe,
 * parse_canframe):
 *
 *   (1436509052.249713) can0 123#1122334455667788
 *   (1436509052.251001)   can0 12345678#DEADBE T
 *
 * "(SECONDS.FRACTION) IFACE FRAME [R|T]". candump pads the interface names
 * to the longest seen so far, so fields are separated by one or more blanks;
 * -x adds the direction, R (received) or T (sent by this host). FRAME is
 *
 *   123#11223344           classical CAN, 3 hex digits: 11-bit identifier
 *   12345678#11.22         8 hex digits: 29-bit identifier; '.' between bytes
 *   20000004#0010...       8 digits with CAN_ERR_FLAG (0x20000000): error frame
 *   123#R  123#R5          remote request, with the requested length
 *   123#1122334455667788_9 8 bytes and the raw DLC 9..F (CAN_CTRLMODE_CC_LEN8_DLC)
 *   123##511223344         CAN FD: flags nibble, then 0..64 bytes
 *   00123#80:00:11223344#AABB   CAN XL: VCID and priority (2 + 3 digits),
 *                          flags:SDT:AF, then 1..2048 bytes
 *
 * The raw DLC, and the VCID, flags, SDT and AF of CAN XL have no place in
 * struct candump_frame: they are checked and dropped. Of a CAN XL payload
 * the first 64 bytes are kept, len is the whole length.
 *
 * Only the bytes before the terminating NUL are read; no floating point.
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "offline/candump.h"
#include "can.h"

#define NS_PER_S	1000000000ULL
#define U64_MAX		(~0ULL)
#define CAN_MAX_DLEN	8
#define CANFD_MAX_DLEN	64
#define CANXL_MAX_DLEN	2048
#define IFACE_LEN	sizeof(((struct candump_frame *)0)->iface)
#define DATA_LEN	sizeof(((struct candump_frame *)0)->data)

/* one line's text and where the parse is */
struct line {
	const char *s;
	size_t n;	/* strlen(s) */
	size_t i;
	char *err;
	size_t errlen;
};

static int __attribute__((format(printf, 2, 3))) bad(struct line *l, const char *fmt, ...)
{
	va_list ap;

	if (l->err && l->errlen) {
		va_start(ap, fmt);
		vsnprintf(l->err, l->errlen, fmt, ap);
		va_end(ap);
	}
	return -1;
}

/* is_space - a field separator, or the line's end (\n, \r\n) */
static int is_space(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

static int hexval(char c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	if (c >= 'a' && c <= 'f')
		return c - 'a' + 10;
	if (c >= 'A' && c <= 'F')
		return c - 'A' + 10;
	return -1;
}

/* show - text for a message: at most 24 characters, unprintables as \xNN */
static const char *show(char *buf, size_t len, const char *s, size_t n)
{
	size_t o = 0, i;

	buf[0] = '\0';
	for (i = 0; i < n && o + 8 < len; i++) {
		unsigned char c = s[i];

		if (i == 24) {
			o += snprintf(buf + o, len - o, "...");
			break;
		}
		if (c < 0x20 || c >= 0x7f || c == '\'' || c == '\\')
			o += snprintf(buf + o, len - o, "\\x%02x", c);
		else
			buf[o++] = c, buf[o] = '\0';
	}
	return buf;
}

static void skip_spaces(struct line *l)
{
	while (l->i < l->n && is_space(l->s[l->i]))
		l->i++;
}

/* token - the length of the field at l->i (up to a blank or the end) */
static size_t token(const struct line *l)
{
	size_t j = l->i;

	while (j < l->n && !is_space(l->s[j]))
		j++;
	return j - l->i;
}

/* parse_timestamp - "(SECONDS.FRACTION)": 1 to 9 fraction digits, to ns */
static int parse_timestamp(struct line *l, __u64 *ns)
{
	const char *s = l->s;
	__u64 sec = 0, frac = 0;
	size_t i = l->i + 1, d;

	/* the caller saw the '(' */
	for (d = 0; i < l->n && s[i] >= '0' && s[i] <= '9'; i++, d++) {
		if (sec > (U64_MAX - 9) / 10)
			return bad(l, "timestamp out of range");
		sec = sec * 10 + (s[i] - '0');
	}
	if (!d || i >= l->n || s[i] != '.')
		return bad(l, "bad timestamp");
	for (i++, d = 0; i < l->n && s[i] >= '0' && s[i] <= '9'; i++, d++) {
		if (d == 9)
			return bad(l, "bad timestamp");
		frac = frac * 10 + (s[i] - '0');
	}
	if (!d || i >= l->n || s[i] != ')')
		return bad(l, "bad timestamp");
	for (; d < 9; d++)
		frac *= 10;
	if (sec > (U64_MAX - frac) / NS_PER_S)
		return bad(l, "timestamp out of range");
	*ns = sec * NS_PER_S + frac;
	l->i = i + 1;
	if (l->i < l->n && !is_space(s[l->i]))
		return bad(l, "bad timestamp");
	return 0;
}

/* parse_hex - n hex digits at s into v; -1 if one is not a hex digit */
static int parse_hex(const char *s, size_t n, __u32 *v)
{
	size_t i;

	*v = 0;
	for (i = 0; i < n; i++) {
		int d = hexval(s[i]);

		if (d < 0)
			return -1;
		*v = *v << 4 | d;
	}
	return 0;
}

/*
 * parse_data - hex byte pairs of s[0..n), a '.' allowed before each pair,
 * at most max bytes; stops at '_' when stop_raw (the raw DLC of classical
 * CAN). Returns the characters used, or -1.
 */
static long parse_data(struct line *l, const char *s, size_t n, size_t max, bool stop_raw,
		       struct candump_frame *f)
{
	char b[40];
	size_t i = 0;

	f->len = 0;
	while (i < n) {
		int hi, lo;

		if (s[i] == '_' && stop_raw)
			break;
		if (s[i] == '.') {
			if (i + 1 == n || s[i + 1] == '.' || (s[i + 1] == '_' && stop_raw))
				return bad(l, "misplaced '.' in data");
			i++;
			continue;
		}
		hi = hexval(s[i]);
		if (hi < 0)
			return bad(l, "bad data digit '%s'", show(b, sizeof(b), s + i, 1));
		if (i + 1 == n || s[i + 1] == '.' || (s[i + 1] == '_' && stop_raw))
			return bad(l, "odd number of data digits");
		lo = hexval(s[i + 1]);
		if (lo < 0)
			return bad(l, "bad data digit '%s'", show(b, sizeof(b), s + i + 1, 1));
		if (f->len == max)
			return bad(l, "data longer than %zu bytes", max);
		if (f->len < DATA_LEN)
			f->data[f->len] = hi << 4 | lo;
		f->len++;
		i += 2;
	}
	return (long)i;
}

/* parse_raw_dlc - "_9".."_F" after 8 bytes of classical CAN (s at the '_') */
static int parse_raw_dlc(struct line *l, const char *s, size_t n, __u32 len)
{
	char b[40];
	int d = n == 2 ? hexval(s[1]) : -1;

	if (len != CAN_MAX_DLEN || d < 9)
		return bad(l, "bad raw DLC '%s' (want _9.._F after 8 data bytes)",
			   show(b, sizeof(b), s, n));
	return 0;
}

static bool fd_len_ok(__u32 len)
{
	return len <= 8 || len == 12 || len == 16 || len == 20 || len == 24 || len == 32 ||
	       len == 48 || len == 64;
}

/* parse_xl - "VVPPP#FF:SS:AAAAAAAA#DATA" (s at the identifier) */
static int parse_xl(struct line *l, const char *s, size_t n, struct candump_frame *f)
{
	char b[40];
	__u32 prio, v;
	long used;

	parse_hex(s + 2, 3, &prio);	/* the caller checked the digits */
	if (prio > RTSUP_CAN_SFF_MASK)
		return bad(l, "CAN XL priority '%s' out of range (want 000..7FF)",
			   show(b, sizeof(b), s + 2, 3));
	/* 6 = "VVPPP#", 15 = "FF:SS:AAAAAAAA#" */
	if (n < 6 + 15 || s[8] != ':' || s[11] != ':' || s[20] != '#' ||
	    parse_hex(s + 6, 2, &v) || parse_hex(s + 9, 2, &v) || parse_hex(s + 12, 8, &v))
		return bad(l, "bad CAN XL header '%s' (want FLAGS:SDT:AF#, e.g. 80:00:00000000#)",
			   show(b, sizeof(b), s + 6, n - 6 < 15 ? n - 6 : 15));
	used = parse_data(l, s + 21, n - 21, CANXL_MAX_DLEN, false, f);
	if (used < 0)
		return -1;
	if (!f->len)
		return bad(l, "bad CAN XL length 0");
	f->can_id = prio;
	f->kind = RTSUP_CAN_XL;
	return 0;
}

/* parse_frame - FRAME, n characters at s */
static int parse_frame(struct line *l, const char *s, size_t n, struct candump_frame *f)
{
	const char *hash = memchr(s, '#', n), *d;
	size_t idlen, dn;
	char b[40];
	__u32 id;
	long used;

	if (!hash)
		return bad(l, "bad frame '%s' (no '#')", show(b, sizeof(b), s, n));
	idlen = hash - s;
	if ((idlen != 3 && idlen != 5 && idlen != 8) || parse_hex(s, idlen, &id))
		return bad(l, "bad identifier '%s'", show(b, sizeof(b), s, idlen));
	if (idlen == 5)
		return parse_xl(l, s, n, f);
	if (idlen == 3) {
		if (id > RTSUP_CAN_SFF_MASK)
			return bad(l, "identifier '%s' out of range (11-bit: 000..7FF)",
				   show(b, sizeof(b), s, idlen));
	} else if (id & RTSUP_CAN_ERR_FLAG) {
		/* lib.c writes an error frame's id with CAN_ERR_FLAG, no EFF flag */
		if (id > (RTSUP_CAN_ERR_FLAG | RTSUP_CAN_EFF_MASK))
			return bad(l, "identifier '%s' out of range (29-bit: 00000000..1FFFFFFF)",
				   show(b, sizeof(b), s, idlen));
	} else {
		if (id > RTSUP_CAN_EFF_MASK)
			return bad(l, "identifier '%s' out of range (29-bit: 00000000..1FFFFFFF)",
				   show(b, sizeof(b), s, idlen));
		id |= RTSUP_CAN_EFF_FLAG;
	}
	f->can_id = id;
	f->kind = RTSUP_CAN_CC;
	d = hash + 1;
	dn = n - idlen - 1;

	/* remote request: R, R0..R8, R8_9..R8_F */
	if (dn && (d[0] == 'R' || d[0] == 'r')) {
		if (id & RTSUP_CAN_ERR_FLAG)
			return bad(l, "error frame with RTR");
		f->can_id |= RTSUP_CAN_RTR_FLAG;
		if (dn == 1)
			return 0;
		if (d[1] < '0' || d[1] > '8')
			return bad(l, "bad RTR length '%s' (want R, or R0..R8)",
				   show(b, sizeof(b), d, dn));
		f->len = d[1] - '0';
		if (dn == 2)
			return 0;
		if (d[2] != '_')
			return bad(l, "bad RTR length '%s' (want R, or R0..R8)",
				   show(b, sizeof(b), d, dn));
		return parse_raw_dlc(l, d + 2, dn - 2, f->len);
	}

	/* CAN FD: ##, the flags nibble, data */
	if (dn && d[0] == '#') {
		if (id & RTSUP_CAN_ERR_FLAG)
			return bad(l, "error frame as CAN FD");
		if (dn == 1)
			return bad(l, "missing CAN FD flags after '##'");
		if (hexval(d[1]) < 0)
			return bad(l, "bad CAN FD flags '%s'", show(b, sizeof(b), d + 1, 1));
		f->fd_flags = hexval(d[1]);
		f->kind = RTSUP_CAN_FD;
		if (parse_data(l, d + 2, dn - 2, CANFD_MAX_DLEN, false, f) < 0)
			return -1;
		if (!fd_len_ok(f->len))
			return bad(l, "bad CAN FD length %u", f->len);
		return 0;
	}

	/* classical CAN (and error frames): 0..8 bytes, then maybe the raw DLC */
	used = parse_data(l, d, dn, CAN_MAX_DLEN, true, f);
	if (used < 0)
		return -1;
	if ((size_t)used < dn)
		return parse_raw_dlc(l, d + used, dn - used, f->len);
	return 0;
}

int candump_parse(const char *line, struct candump_frame *f, char *err, size_t errlen)
{
	struct line l = { .s = line, .n = strlen(line), .err = err, .errlen = errlen };
	char b[40];
	size_t n;

	if (err && errlen)
		err[0] = '\0';
	memset(f, 0, sizeof(*f));
	f->dir = -1;
	skip_spaces(&l);
	if (l.i == l.n || line[l.i] == '#')
		return 0;		/* blank, or a comment */
	/* candump -d writes the drops of its socket between the frames */
	if (!strncmp(line + l.i, "DROPCOUNT:", 10))
		return 0;
	if (line[l.i] != '(')
		return bad(&l, "no timestamp (want '(SECONDS.MICROS) IFACE FRAME', "
			   "as candump -l writes)");
	if (parse_timestamp(&l, &f->ts_ns))
		return -1;

	skip_spaces(&l);
	n = token(&l);
	if (!n)
		return bad(&l, "no interface");
	if (n >= IFACE_LEN)
		return bad(&l, "interface name '%s' too long (at most %zu characters)",
			   show(b, sizeof(b), line + l.i, n), IFACE_LEN - 1);
	memcpy(f->iface, line + l.i, n);
	f->iface[n] = '\0';
	l.i += n;

	skip_spaces(&l);
	n = token(&l);
	if (!n)
		return bad(&l, "no frame");
	if (parse_frame(&l, line + l.i, n, f))
		return -1;
	l.i += n;

	/* candump -x: R received, T sent by this host */
	skip_spaces(&l);
	n = token(&l);
	if (n) {
		if (n != 1 || (line[l.i] != 'R' && line[l.i] != 'T'))
			return bad(&l, "bad direction '%s' (want R or T)",
				   show(b, sizeof(b), line + l.i, n));
		f->dir = line[l.i] == 'R' ? RTSUP_CAN_RX : RTSUP_CAN_TX;
		l.i += n;
		skip_spaces(&l);
		n = token(&l);
		if (n)
			return bad(&l, "unexpected '%s' after the direction",
				   show(b, sizeof(b), line + l.i, n));
	}
	return 1;
}
