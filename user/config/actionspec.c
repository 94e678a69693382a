// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* actionspec.c - parse and print --on-level specs; the actions' rate limit */
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "config/actionspec.h"
#include "config/strict.h"

/* what a Unix socket's address holds (sizeof(sockaddr_un.sun_path)) */
#define UNIX_PATH_LEN	108

/* The keywords of WHAT; any other text is a shell command. */
static const struct {
	const char *prefix;
	enum action_kind kind;
} kinds[] = {
	{ "run=", ACTION_RUN },
	{ "signal=", ACTION_SIGNAL },
	{ "fifo=", ACTION_FIFO },
	{ "unix=", ACTION_UNIX },
};

#define NKINDS (int)(sizeof(kinds) / sizeof(kinds[0]))

int level_parse(const char *s)
{
	static const enum level levels[] = { LEVEL_OK, LEVEL_STALE, LEVEL_WARN, LEVEL_ERROR };
	size_t i;

	for (i = 0; i < sizeof(levels) / sizeof(levels[0]); i++)
		if (!strcasecmp(s, level_name(levels[i])))
			return levels[i];
	return -1;
}

/* parse_int - strict whole number in [min, max], -1 if not */
static long parse_int(const char *s, long min, long max)
{
	long v;

	return strict_long(s, min, max, &v) ? -1 : v;
}

int signal_parse(const char *s)
{
	const char *abbr;
	int sig;

	if (*s >= '0' && *s <= '9')
		return parse_int(s, 1, SIGRTMAX);
	if (!strncasecmp(s, "SIG", 3))
		s += 3;
	if (!strncasecmp(s, "RTMIN+", 6)) {
		sig = parse_int(s + 6, 0, SIGRTMAX - SIGRTMIN);
		return sig < 0 ? -1 : SIGRTMIN + sig;
	}
	for (sig = 1; sig < SIGRTMIN; sig++) {
		abbr = sigabbrev_np(sig);
		if (abbr && !strcasecmp(s, abbr))
			return sig;
	}
	return -1;
}

const char *signal_name(int sig)
{
	static char buf[16];
	const char *abbr = sig < SIGRTMIN ? sigabbrev_np(sig) : NULL;

	if (abbr)
		return abbr;
	if (sig >= SIGRTMIN && sig <= SIGRTMAX)
		snprintf(buf, sizeof(buf), "RTMIN+%d", sig - SIGRTMIN);
	else
		snprintf(buf, sizeof(buf), "%d", sig);
	return buf;
}

/* parse_signal - SIG[@PID] */
static int parse_signal(const char *s, struct action *a, char *err, size_t errlen)
{
	char name[32];
	const char *at = strchr(s, '@');
	size_t n = at ? (size_t)(at - s) : strlen(s);
	long pid = 0;

	if (n >= sizeof(name))
		n = sizeof(name) - 1;
	memcpy(name, s, n);
	name[n] = '\0';
	a->sig = signal_parse(name);
	if (a->sig < 0) {
		snprintf(err, errlen, "unknown signal '%s' (want e.g. USR1, TERM, RTMIN+1 or 10)",
			 name);
		return -1;
	}
	if (at) {
		pid = parse_int(at + 1, 1, INT_MAX);
		if (pid < 0) {
			snprintf(err, errlen, "bad pid '%s' after '@' (want a process id)",
				 at + 1);
			return -1;
		}
	}
	a->pid = pid;
	return 0;
}

int action_parse(const char *spec, struct action *a, char *err, size_t errlen)
{
	const char *colon, *what, *orig = spec;
	char lvl[16];
	size_t n;
	int i, l;

	memset(a, 0, sizeof(*a));
	if (*spec == '!') {
		a->leave = true;
		spec++;
	}
	colon = strchr(spec, ':');
	n = colon ? (size_t)(colon - spec) : 0;
	if (!colon || n >= sizeof(lvl)) {
		snprintf(err, errlen, "want [!]LEVEL:ACTION, e.g. ERROR:signal=USR1");
		return -1;
	}
	memcpy(lvl, spec, n);
	lvl[n] = '\0';
	l = level_parse(lvl);
	if (l < 0) {
		snprintf(err, errlen, "unknown level '%s' (want OK, WARN, ERROR or STALE)", lvl);
		return -1;
	}
	a->level = l;
	what = colon + 1;
	a->kind = ACTION_RUN;
	for (i = 0; i < NKINDS; i++) {
		if (!strncmp(what, kinds[i].prefix, strlen(kinds[i].prefix))) {
			a->kind = kinds[i].kind;
			what += strlen(kinds[i].prefix);
			break;
		}
	}
	if (a->kind == ACTION_SIGNAL)
		return parse_signal(what, a, err, errlen);
	if (!*what) {
		snprintf(err, errlen, "nothing to do after '%.*s' (want a command, signal=, "
			 "fifo= or unix=)", (int)(what - orig), orig);
		return -1;
	}
	n = a->kind == ACTION_UNIX ? UNIX_PATH_LEN : ACTION_ARG_LEN;
	if (strlen(what) >= n) {
		snprintf(err, errlen, "too long (at most %zu characters)", n - 1);
		return -1;
	}
	strcpy(a->arg, what);
	return 0;
}

void action_format(const struct action *a, char *buf, size_t len)
{
	const char *prefix = "";
	int i, o;

	o = snprintf(buf, len, "%s%s:", a->leave ? "!" : "", level_name(a->level));
	if (o < 0 || (size_t)o >= len)
		return;
	if (a->kind == ACTION_SIGNAL) {
		snprintf(buf + o, len - o, "signal=%s", signal_name(a->sig));
		if (a->pid)
			snprintf(buf + strlen(buf), len - strlen(buf), "@%llu",
				 (unsigned long long)a->pid);
		return;
	}
	for (i = 0; i < NKINDS; i++) {
		if (a->kind != ACTION_RUN && a->kind == kinds[i].kind)
			prefix = kinds[i].prefix;
		/* a command that starts like a keyword keeps its run= */
		if (a->kind == ACTION_RUN &&
		    !strncmp(a->arg, kinds[i].prefix, strlen(kinds[i].prefix)))
			prefix = "run=";
	}
	snprintf(buf + o, len - o, "%s%s", prefix, a->arg);
}

bool action_matches(const struct action *a, enum level from, enum level to)
{
	if (from == to)
		return false;
	return a->leave ? from == a->level : to == a->level;
}

void rate_init(struct rate_limit *r)
{
	int i;

	memset(r, 0, sizeof(*r));
	for (i = 0; i < RATE_SLOTS; i++)
		r->slot[i].action = -1;
}

bool rate_allow(struct rate_limit *r, int action, const char *component, __u64 now)
{
	struct rate_slot *s, *use = NULL;
	int i;

	for (i = 0; i < RATE_SLOTS; i++) {
		s = &r->slot[i];
		if (s->action == action && !strncmp(s->component, component,
						    sizeof(s->component) - 1)) {
			if (now - s->last_ns < RATE_GAP_NS && now >= s->last_ns)
				return false;
			s->last_ns = now;
			return true;
		}
		/* a free slot, else the one that ran longest ago */
		if (!use || (use->action >= 0 && (s->action < 0 || s->last_ns < use->last_ns)))
			use = s;
	}
	use->action = action;
	snprintf(use->component, sizeof(use->component), "%s", component);
	use->last_ns = now;
	return true;
}
