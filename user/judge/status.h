/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * status.h - the verdict on one supervised component (a thread, a CAN node,
 * the supervisor itself): a level and every message that led to it. Each
 * check adds its messages on its own; the worst level wins.
 */
#ifndef RTSUP_STATUS_H
#define RTSUP_STATUS_H

#include <stdbool.h>
#include <linux/types.h>

enum level {
	LEVEL_OK,
	LEVEL_STALE,	/* no data any more (the thread is gone) */
	LEVEL_WARN,
	LEVEL_ERROR,
};

#define STATUS_MAX_MSGS	8
#define STATUS_MSG_LEN	160
#define STATUS_MAX_COUNTS 6

/* A number a message is about, for machines: "minor_fault" 2. */
struct status_count {
	const char *key;	/* static text */
	__u64 val;
};

/* What a machine reads of one message: which check, how bad, its numbers. */
struct status_fact {
	const char *check;	/* static text, e.g. "deadline_miss" (docs/json.md) */
	enum level level;
	int ncounts;
	struct status_count counts[STATUS_MAX_COUNTS];
};

struct status {
	enum level level;
	int nmsg;
	int dropped;	/* messages beyond STATUS_MAX_MSGS */
	const char *check;	/* the check adding messages now (status_check) */
	char msg[STATUS_MAX_MSGS][STATUS_MSG_LEN];
	struct status_fact fact[STATUS_MAX_MSGS];
};

/* status_reset - OK, no messages */
void status_reset(struct status *s);
/*
 * status_copy - *src into *dst, the messages it has only: a thread's status
 * is copied twice an interval, and most have none (the whole is 2 KiB)
 */
void status_copy(struct status *dst, const struct status *src);
/* status_check - the messages added from now on are this check's */
void status_check(struct status *s, const char *check);
/* status_count - a number of the last message, for machines (JSON "counts") */
void status_count(struct status *s, const char *key, __u64 val);
/* status_add - add one message at a level; the worst level wins */
void status_add(struct status *s, enum level l, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
/* status_join - all messages in one line, "; " separated */
void status_join(const struct status *s, char *buf, size_t len);
/* status_same - same level and same messages? */
bool status_same(const struct status *a, const struct status *b);
/*
 * status_same_kind - same level and the same messages but for their numbers:
 * "no frame for 30 ms" and "no frame for 40 ms" are one ongoing condition
 */
bool status_same_kind(const struct status *a, const struct status *b);
/* level_name - "OK", "WARN", "ERROR", "STALE" */
const char *level_name(enum level l);
/* level_fails - does this level fail a --check run at --fail-on 'min'? */
bool level_fails(enum level l, enum level min);

#endif
