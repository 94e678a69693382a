// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* status.c - levels and messages of a component */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "judge/status.h"

void status_reset(struct status *s)
{
	s->level = LEVEL_OK;
	s->nmsg = 0;
	s->dropped = 0;
	s->check = NULL;
}

void status_copy(struct status *dst, const struct status *src)
{
	dst->level = src->level;
	dst->nmsg = src->nmsg;
	dst->dropped = src->dropped;
	dst->check = src->check;
	memcpy(dst->msg, src->msg, (size_t)src->nmsg * sizeof(src->msg[0]));
	memcpy(dst->fact, src->fact, (size_t)src->nmsg * sizeof(src->fact[0]));
}

void status_check(struct status *s, const char *check)
{
	s->check = check;
}

void status_count(struct status *s, const char *key, __u64 val)
{
	struct status_fact *f;

	/* a message dropped for room takes its numbers with it */
	if (!s->nmsg || s->dropped)
		return;
	f = &s->fact[s->nmsg - 1];
	if (f->ncounts < STATUS_MAX_COUNTS)
		f->counts[f->ncounts++] = (struct status_count){ key, val };
}

void status_add(struct status *s, enum level l, const char *fmt, ...)
{
	va_list ap;

	if (l > s->level)
		s->level = l;
	if (s->nmsg == STATUS_MAX_MSGS) {
		s->dropped++;
		return;
	}
	s->fact[s->nmsg] = (struct status_fact){ .check = s->check ? s->check : "other",
						 .level = l };
	va_start(ap, fmt);
	vsnprintf(s->msg[s->nmsg++], STATUS_MSG_LEN, fmt, ap);
	va_end(ap);
}

void status_join(const struct status *s, char *buf, size_t len)
{
	size_t off = 0;
	int i;

	buf[0] = '\0';
	for (i = 0; i < s->nmsg && off < len; i++)
		off += snprintf(buf + off, len - off, "%s%s", i ? "; " : "", s->msg[i]);
	if (s->dropped && off < len)
		snprintf(buf + off, len - off, "; %d more", s->dropped);
}

bool status_same(const struct status *a, const struct status *b)
{
	int i;

	if (a->level != b->level || a->nmsg != b->nmsg || a->dropped != b->dropped)
		return false;
	for (i = 0; i < a->nmsg; i++)
		if (strcmp(a->msg[i], b->msg[i]))
			return false;
	return true;
}

/* same_but_numbers - equal texts once every run of digits and dots is one mark */
static bool same_but_numbers(const char *a, const char *b)
{
	for (;;) {
		bool na = (*a >= '0' && *a <= '9'), nb = (*b >= '0' && *b <= '9');

		if (na != nb)
			return false;
		if (na) {
			while ((*a >= '0' && *a <= '9') || *a == '.')
				a++;
			while ((*b >= '0' && *b <= '9') || *b == '.')
				b++;
			continue;
		}
		if (*a != *b)
			return false;
		if (!*a)
			return true;
		a++;
		b++;
	}
}

bool status_same_kind(const struct status *a, const struct status *b)
{
	int i;

	if (a->level != b->level || a->nmsg != b->nmsg)
		return false;
	for (i = 0; i < a->nmsg; i++)
		if (!same_but_numbers(a->msg[i], b->msg[i]))
			return false;
	return true;
}

const char *level_name(enum level l)
{
	switch (l) {
	case LEVEL_OK: return "OK";
	case LEVEL_STALE: return "STALE";
	case LEVEL_WARN: return "WARN";
	case LEVEL_ERROR: return "ERROR";
	}
	return "?";
}

bool level_fails(enum level l, enum level min)
{
	return l >= LEVEL_WARN && l >= min;
}
