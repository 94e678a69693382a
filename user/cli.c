// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* cli.c - the rtsup-trace command line (argp) */
#include <argp.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "options.h"
#include "rtsup.h"

const char *argp_program_version = "rtsup-trace 0.1";
const char *argp_program_bug_address = "the rtsup issue tracker";

static const char doc[] =
"rtsup-trace: supervise the real-time cycles of unmodified threads with eBPF.\n"
"\n"
"USAGE: rtsup-trace [-p PID] [-t TID] [-c COMM] [--rt] [--cgroup PATH]\n"
"                   [-i INTERVAL] [-d DURATION] [-j] [-v]\n"
"\n"
"EXAMPLES:\n"
"    rtsup-trace --pid $(pidof my_controller)   # table every second\n"
"    rtsup-trace --comm ros2_control_node -d 30s -j  # JSON lines for 30 s\n"
"    rtsup-trace --rt                          # every SCHED_FIFO/RR/DEADLINE thread\n"
"    rtsup-trace -p 1234 --cycle-syscall epoll_wait  # cycles end in epoll_wait\n"
"\n"
"Exit status: 0 on success, 1 on an error of the tool itself.";

enum {
	OPT_RT = 1000,
	OPT_CGROUP,
	OPT_CYCLE_SYSCALL,
	OPT_EWMA,
	OPT_PERIOD,
	OPT_MAX_THREADS,
	OPT_RAW_TP,
	OPT_COLOR,
};

static const struct argp_option opts[] = {
	{ "pid", 'p', "PID", 0, "Process to supervise, with all its threads (repeatable)", 0 },
	{ "tid", 't', "TID", 0, "Single thread to supervise (repeatable)", 0 },
	{ "comm", 'c', "NAME", 0, "Processes and threads by name, also ones started later (repeatable)", 0 },
	{ "rt", OPT_RT, NULL, 0, "Every thread with an RT policy, system wide", 0 },
	{ "cgroup", OPT_CGROUP, "PATH", 0, "Every thread of a cgroup v2 directory", 0 },
	{ "interval", 'i', "TIME", 0, "Report interval (default 1s)", 0 },
	{ "duration", 'd', "TIME", 0, "Stop after TIME (s/m/h suffixes; default: until Ctrl-C)", 0 },
	{ "json", 'j', NULL, 0, "One JSON object per interval on stdout", 0 },
	{ "verbose", 'v', NULL, 0, "Show libbpf's own messages", 0 },
	{ "cycle-syscall", OPT_CYCLE_SYSCALL, "NAME[,NAME]", 0,
	  "Syscalls that end a cycle (default clock_nanosleep,nanosleep)", 0 },
	{ "ewma-weight", OPT_EWMA, "W", 0, "Weight of a new value in the weighted mean, 0 < W <= 1 (default 0.1)", 0 },
	{ "period", OPT_PERIOD, "TIME", 0, "Nominal period for overruns when the sleep does not tell it (e.g. 1ms)", 0 },
	{ "max-threads", OPT_MAX_THREADS, "N", 0, "Capacity of the thread map (default 4096)", 0 },
	{ "raw-tp", OPT_RAW_TP, NULL, 0, "Use raw tracepoints even where tp_btf works", 0 },
	{ "color", OPT_COLOR, "WHEN", 0, "auto (default), always or never", 0 },
	{},
};

double parse_duration(const char *s)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (errno || end == s || v < 0)
		return -1;
	if (!strcmp(end, "") || !strcmp(end, "s"))
		return v;
	if (!strcmp(end, "ms"))
		return v / 1000;
	if (!strcmp(end, "us"))
		return v / 1e6;
	if (!strcmp(end, "m"))
		return v * 60;
	if (!strcmp(end, "h"))
		return v * 3600;
	return -1;
}

/* parse_long - strict whole number in [min, max] */
static int parse_long(const char *s, long min, long max, long *out)
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

/* bad - one-line error about an option value */
static int bad(struct argp_state *st, const char *opt, const char *arg, const char *why)
{
	fprintf(stderr, "rtsup-trace: %s '%s': %s\n", opt, arg, why);
	(void)st;
	return EINVAL;
}

static error_t parse_opt(int key, char *arg, struct argp_state *st)
{
	struct options *o = st->input;
	struct targets *t = &o->targets;
	char *tok, *save;
	double d;
	long v;

	switch (key) {
	case 'p':
		if (parse_long(arg, 1, INT_MAX, &v))
			return bad(st, "--pid", arg, "not a process id");
		if (t->npids == TARGETS_MAX)
			return bad(st, "--pid", arg, "too many");
		t->pids[t->npids++] = v;
		break;
	case 't':
		if (parse_long(arg, 1, INT_MAX, &v))
			return bad(st, "--tid", arg, "not a thread id");
		if (t->ntids == TARGETS_MAX)
			return bad(st, "--tid", arg, "too many");
		t->tids[t->ntids++] = v;
		break;
	case 'c':
		if (!*arg || strlen(arg) >= RTSUP_COMM_LEN)
			return bad(st, "--comm", arg, "names are 1 to 15 characters (the kernel's comm)");
		if (t->ncomms == RTSUP_MAX_COMMS)
			return bad(st, "--comm", arg, "at most 8 names");
		strcpy(t->comms[t->ncomms++], arg);
		break;
	case OPT_RT:
		t->rt = true;
		break;
	case OPT_CGROUP:
		t->cgroup = arg;
		break;
	case 'i':
		d = parse_duration(arg);
		if (d < 0.01)
			return bad(st, "--interval", arg, "want a time of at least 10ms, e.g. 1s");
		o->interval = d;
		break;
	case 'd':
		d = parse_duration(arg);
		if (d <= 0)
			return bad(st, "--duration", arg, "want a time such as 30s, 5m or 1h");
		o->duration = d;
		break;
	case 'j':
		o->json = true;
		break;
	case 'v':
		o->verbose = true;
		break;
	case OPT_CYCLE_SYSCALL:
		o->ndelims = 0;
		for (tok = strtok_r(arg, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
			if (o->ndelims == SYSCALLS_MAX_DELIMS)
				return bad(st, "--cycle-syscall", tok, "at most 8 syscalls");
			if (syscall_nr(tok) < 0)
				return bad(st, "--cycle-syscall", tok, "no such syscall on this architecture");
			o->delims[o->ndelims++] = tok;
		}
		if (!o->ndelims)
			return bad(st, "--cycle-syscall", arg, "empty list");
		break;
	case OPT_EWMA:
		d = strtod(arg, &tok);
		if (*tok || d <= 0 || d > 1)
			return bad(st, "--ewma-weight", arg, "want a number in (0, 1]");
		o->ewma_w = (__u32)(d * RTSUP_EWMA_ONE + 0.5);
		if (!o->ewma_w)
			o->ewma_w = 1;
		break;
	case OPT_PERIOD:
		d = parse_duration(arg);
		if (d <= 0)
			return bad(st, "--period", arg, "want a time such as 1ms");
		o->period_ns = (__u64)(d * 1e9 + 0.5);
		break;
	case OPT_MAX_THREADS:
		if (parse_long(arg, 1, 1 << 20, &v))
			return bad(st, "--max-threads", arg, "want a number from 1 to 1048576");
		o->max_threads = v;
		break;
	case OPT_RAW_TP:
		o->raw_tp = true;
		break;
	case OPT_COLOR:
		if (!strcmp(arg, "auto"))
			o->color = -1;
		else if (!strcmp(arg, "always"))
			o->color = 1;
		else if (!strcmp(arg, "never"))
			o->color = 0;
		else
			return bad(st, "--color", arg, "want auto, always or never");
		break;
	case ARGP_KEY_ARG:
		fprintf(stderr, "rtsup-trace: unexpected argument '%s'\n", arg);
		return EINVAL;
	case ARGP_KEY_END:
		if (!targets_any(t)) {
			fprintf(stderr, "rtsup-trace: no target: give --pid, --tid, --comm, --rt or --cgroup\n");
			return EINVAL;
		}
		break;
	default:
		return ARGP_ERR_UNKNOWN;
	}
	return 0;
}

int options_parse(int argc, char **argv, struct options *o)
{
	static const struct argp argp = { opts, parse_opt, NULL, doc, NULL, NULL, NULL };

	memset(o, 0, sizeof(*o));
	o->interval = 1;
	o->ewma_w = 102;
	o->max_threads = RTSUP_DEFAULT_THREADS;
	o->color = -1;
	o->delims[0] = "clock_nanosleep";
	o->delims[1] = "nanosleep";
	o->ndelims = 2;
	/* argp's own usage errors exit with our "tool error" status */
	argp_err_exit_status = 1;
	return argp_parse(&argp, argc, argv, 0, NULL, o) ? -1 : 0;
}
