// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* cli.c - the rtsup-trace command line (argp) */
#include <argp.h>
#include <errno.h>
#include <math.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "config/actionspec.h"
#include "config/stackopt.h"
#include "options.h"
#include "config/strict.h"
#include "rtsup.h"
#include "judge/status.h"
#include "sinks/rowcut.h"

const char *argp_program_version = "rtsup-trace 0.1";
const char *argp_program_bug_address = "the rtsup issue tracker";

static const char doc[] =
"rtsup-trace: supervise the real-time cycles of unmodified threads with eBPF.\n"
"\n"
"USAGE: rtsup-trace [-p PID] [-t TID] [-c COMM] [--rt] [--cgroup PATH]\n"
"                   [-i INTERVAL] [-d DURATION] [-j] [-v] [--config FILE]\n"
"                   [--check [--fail-on warn|error]] [--record FILE] [--perfetto FILE]\n"
"                   [--hist[=METRIC,...] [--hist-interval]] [--stacks fp|dwarf|auto|off]\n"
"                   [--top N | --all] [--json-threads all|active] [-- CMD [ARGS...]]\n"
"       rtsup-trace replay FILE [--config FILE] [-j] [--check] [--perfetto FILE]\n"
"                   [--hist[=METRIC,...]] [-q]\n"
"       rtsup-trace --check-config FILE\n"
"\n"
"EXAMPLES:\n"
"    rtsup-trace --pid $(pidof my_controller)   # table every second\n"
"    rtsup-trace --comm ros2_control_node -d 30s -j  # JSON lines for 30 s\n"
"    rtsup-trace --rt                          # every SCHED_FIFO/RR/DEADLINE thread\n"
"    rtsup-trace -p 1234 --cycle-syscall epoll_wait  # cycles end in epoll_wait\n"
"    rtsup-trace --check --config rt.yaml -- ./my_control_test  # CI\n"
"    rtsup-trace -p 1234 -d 30s --hist=latency,exec  # histograms at the end\n"
"    rtsup-trace -p 1234 --stacks dwarf          # where each RT-unsafe event came from\n"
"    rtsup-trace -p 1234 -d 1m --record run.rtsup; rtsup-trace replay run.rtsup --check\n"
"\n"
"Exit status: 0 on success (with --check: every component stayed OK), 1 on an\n"
"error of the tool itself, 2 with --check when a component reached WARN or\n"
"ERROR (see --fail-on). With -- CMD and no violation: the command's status.";

enum {
	OPT_RT = 1000,
	OPT_CGROUP,
	OPT_CYCLE_SYSCALL,
	OPT_EWMA,
	OPT_PERIOD,
	OPT_MAX_THREADS,
	OPT_RAW_TP,
	OPT_COLOR,
	OPT_CONFIG,
	OPT_CHECK_CONFIG,
	OPT_CHECK,
	OPT_FAIL_ON,
	OPT_RECORD,
	OPT_PERFETTO,
	OPT_NO_OVERHEAD,
	OPT_PROM_TEXTFILE,
	OPT_LISTEN,
	OPT_UNIT,
	OPT_CAN,
	OPT_BITRATE,
	OPT_CAN_MAX_IDS,
	OPT_FLOOR,
	OPT_HIST,
	OPT_HIST_INTERVAL,
	OPT_ON_LEVEL,
	OPT_ROS2_DIAG,
	OPT_STACKS,
	OPT_STACK_SIZE,
	OPT_STACK_BUDGET,
	OPT_EVENT_BUFFER,
	OPT_ALL,
	OPT_TOP,
	OPT_JSON_THREADS,
	OPT_SYSCALL_HOOKS,
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
	{ "json-threads", OPT_JSON_THREADS, "WHICH", 0,
	  "Threads in each JSON interval: all (default) or active (ran, switched or changed level)", 0 },
	{ "top", OPT_TOP, "N", 0,
	  "The table shows every thread not OK and the worst N others (default 10)", 0 },
	{ "all", OPT_ALL, NULL, 0, "The table shows every thread", 0 },
	{ "verbose", 'v', NULL, 0, "Show libbpf's own messages", 0 },
	{ "cycle-syscall", OPT_CYCLE_SYSCALL, "NAME[,NAME]", 0,
	  "Syscalls that end a cycle (default clock_nanosleep,nanosleep)", 0 },
	{ "ewma-weight", OPT_EWMA, "W", 0, "Weight of a new value in the weighted mean, 0 < W <= 1 (default 0.1)", 0 },
	{ "period", OPT_PERIOD, "TIME", 0, "Nominal period for overruns when the sleep does not tell it (e.g. 1ms)", 0 },
	{ "max-threads", OPT_MAX_THREADS, "N", 0, "Capacity of the thread map (default 4096)", 0 },
	{ "raw-tp", OPT_RAW_TP, NULL, 0, "Use raw tracepoints even where tp_btf works", 0 },
	{ "syscall-hooks", OPT_SYSCALL_HOOKS, "HOW", 0,
	  "raw (default: raw_syscalls, every syscall of every thread), per-syscall (only "
	  "the syscalls rtsup classifies; fentry) or auto (per-syscall where it loads)", 0 },
	{ "color", OPT_COLOR, "WHEN", 0, "auto (default), always or never", 0 },
	{ "config", OPT_CONFIG, "FILE", 0, "YAML rules and thresholds (SIGHUP reloads it)", 0 },
	{ "check-config", OPT_CHECK_CONFIG, "FILE", 0, "Validate FILE, print the effective rules, exit", 0 },
	{ "check", OPT_CHECK, NULL, 0, "Exit 2 if a component reached WARN or ERROR", 0 },
	{ "fail-on", OPT_FAIL_ON, "LEVEL", 0, "With --check: warn (default) or error", 0 },
	{ "record", OPT_RECORD, "FILE", 0, "Record every cycle and rare event to FILE", 0 },
	{ "perfetto", OPT_PERFETTO, "FILE", 0, "Write a Perfetto (Chrome JSON) trace to FILE", 0 },
	{ "no-overhead", OPT_NO_OVERHEAD, NULL, 0, "Do not switch on BPF run-time statistics (no overhead check)", 0 },
	{ "unit", OPT_UNIT, "NAME", 0, "Every thread of a systemd unit's cgroup, followed across restarts", 0 },
	{ "prom-textfile", OPT_PROM_TEXTFILE, "PATH", 0, "Write Prometheus metrics to PATH every interval (node_exporter textfile)", 0 },
	{ "listen", OPT_LISTEN, "ADDR:PORT", 0, "Serve Prometheus metrics at http://ADDR:PORT/metrics (default address 127.0.0.1)", 0 },
	{ "can", OPT_CAN, "IFACE", OPTION_ARG_OPTIONAL,
	  "Supervise a CAN interface (repeatable); without IFACE every CAN interface", 0 },
	{ "bitrate", OPT_BITRATE, "BPS", 0, "CAN bitrate for the bus load when the interface does not tell (vcan)", 0 },
	{ "can-max-ids", OPT_CAN_MAX_IDS, "N", 0, "Capacity of the CAN identifier map (default 4096)", 0 },
	{ "hist", OPT_HIST, "METRIC", OPTION_ARG_OPTIONAL,
	  "Histograms at the end: latency (default), exec, period, cpu; comma separated", 0 },
	{ "hist-interval", OPT_HIST_INTERVAL, NULL, 0, "With --hist: every interval's histograms too", 0 },
	{ "quiet", 'q', NULL, 0, "No progress bar (replay)", 0 },
	{ "on-level", OPT_ON_LEVEL, "SPEC", 0,
	  "On a level change run a command, send a signal or write a JSON line "
	  "(repeatable): [!]LEVEL:CMD, LEVEL:signal=SIG[@PID], LEVEL:fifo=PATH, "
	  "LEVEL:unix=PATH; ! = on leaving LEVEL", 0 },
	{ "ros2-diagnostics", OPT_ROS2_DIAG, NULL, 0,
	  "Publish the verdicts on ROS 2 /diagnostics (Cyclone DDS, ROS_DOMAIN_ID)", 0 },
	/* make bench: the same hooks with empty programs, the floor of any BPF tracer */
	{ "stacks", OPT_STACKS, "HOW", 0,
	  "User stack at each RT-unsafe event: off (default), fp (frame pointers), dwarf, or "
	  "auto (fp for a process whose every module keeps frame pointers, dwarf otherwise)", 0 },
	{ "stack-size", OPT_STACK_SIZE, "BYTES", 0, "With DWARF stacks: user stack copied per event (default 8K)", 0 },
	{ "stack-budget", OPT_STACK_BUDGET, "N", 0, "Stacks captured per thread per interval, the rest counted (default 256)", 0 },
	{ "event-buffer", OPT_EVENT_BUFFER, "BYTES", 0,
	  "Ring buffer of rare events, a power of two from 64K to 256M (default 2M); "
	  "what does not fit is counted as lost", 0 },
	{ "floor", OPT_FLOOR, NULL, OPTION_HIDDEN, "Attach empty programs instead (benchmark)", 0 },
	{},
};

/* the configuration's bound (about 31 years): a time in ns still fits a __u64 */
#define MAX_DURATION_S	1e9

/* duration_s - the number v with its suffix, in seconds; -1 for an unknown suffix */
static double duration_s(double v, const char *end)
{
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

double parse_duration(const char *s)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (errno || end == s || v < 0)
		return -1;
	v = duration_s(v, end);
	/* nan and inf parse as numbers; a huge --period overflowed its ns (fuzz_options) */
	if (!isfinite(v) || v > MAX_DURATION_S)
		return -1;
	return v;
}

/* hist_metric - RTSUP_M_* of a --hist name, -1 if none */
static int hist_metric(const char *name)
{
	static const char *const names[RTSUP_M_NR] = {
		[RTSUP_M_PERIOD] = "period", [RTSUP_M_EXEC] = "exec",
		[RTSUP_M_CPU] = "cpu", [RTSUP_M_LATENCY] = "latency",
	};
	int i;

	for (i = 0; i < RTSUP_M_NR; i++)
		if (!strcmp(name, names[i]))
			return i;
	return -1;
}

/* ring_size_parse - "64K", "2M", "4194304": a power of two from 64 KiB to 256 MiB */
static int ring_size_parse(const char *s, __u32 *out)
{
	long v;

	if (strict_size(s, 1L << 16, 1L << 28, &v) || (v & (v - 1)))
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

/* the words an option takes, and the value each gives */
struct choice {
	const char *word;
	int value;
};

static const struct choice json_threads_words[] = { { "all", 0 }, { "active", 1 }, { 0 } };
static const struct choice syscall_hooks_words[] = {
	{ "auto", SYS_HOOKS_AUTO }, { "per-syscall", SYS_HOOKS_PER }, { "raw", SYS_HOOKS_RAW }, { 0 }
};
static const struct choice color_words[] = { { "auto", -1 }, { "always", 1 }, { "never", 0 },
					     { 0 } };
static const struct choice fail_on_words[] = { { "warn", LEVEL_WARN }, { "error", LEVEL_ERROR },
					       { 0 } };

/* choose - *out from arg's word in c; else EINVAL with "want a, b or c" printed */
static int choose(struct argp_state *st, const char *opt, const char *arg,
		  const struct choice *c, int *out)
{
	char want[128] = "want ";
	size_t n = strlen(want);
	int i;

	for (i = 0; c[i].word; i++)
		if (!strcmp(arg, c[i].word)) {
			*out = c[i].value;
			return 0;
		}
	for (i = 0; c[i].word && n < sizeof(want); i++) {
		const char *sep = !i ? "" : c[i + 1].word ? ", " : " or ";

		n += snprintf(want + n, sizeof(want) - n, "%s%s", sep, c[i].word);
	}
	return bad(st, opt, arg, want);
}

static error_t parse_opt(int key, char *arg, struct argp_state *st)
{
	struct options *o = st->input;
	struct targets *t = &o->targets;
	char *tok, *save;
	double d;
	long v;
	int word;

	switch (key) {
	case 'p':
		if (strict_long(arg, 1, INT_MAX, &v))
			return bad(st, "--pid", arg, "not a process id");
		if (t->npids == TARGETS_MAX)
			return bad(st, "--pid", arg, "too many");
		t->pids[t->npids++] = v;
		break;
	case 't':
		if (strict_long(arg, 1, INT_MAX, &v))
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
		o->delims_given = true;
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
		o->ewma_given = true;
		o->ewma_w = (__u32)(d * RTSUP_EWMA_ONE + 0.5);
		if (!o->ewma_w)
			o->ewma_w = 1;
		break;
	case OPT_PERIOD:
		d = parse_duration(arg);
		if (d <= 0)
			return bad(st, "--period", arg, "want a time such as 1ms");
		o->period_given = true;
		o->period_ns = (__u64)(d * 1e9 + 0.5);
		break;
	case OPT_MAX_THREADS:
		if (strict_long(arg, 1, 1 << 20, &v))
			return bad(st, "--max-threads", arg, "want a number from 1 to 1048576");
		o->max_threads = v;
		break;
	case OPT_RAW_TP:
		o->raw_tp = true;
		break;
	case OPT_ALL:
		o->all = true;
		break;
	case OPT_TOP:
		if (strict_long(arg, 0, 1 << 20, &v))
			return bad(st, "--top", arg, "want a number from 0 to 1048576");
		o->top = v;
		break;
	case OPT_JSON_THREADS:
		if (choose(st, "--json-threads", arg, json_threads_words, &word))
			return EINVAL;
		o->json_active = word;
		break;
	case OPT_SYSCALL_HOOKS:
		return choose(st, "--syscall-hooks", arg, syscall_hooks_words, &o->sys_hooks);
	case OPT_COLOR:
		return choose(st, "--color", arg, color_words, &o->color);
	case OPT_CONFIG:
		o->config_path = arg;
		break;
	case OPT_CHECK_CONFIG:
		o->check_config = arg;
		break;
	case OPT_CHECK:
		o->check = true;
		break;
	case OPT_FAIL_ON:
		return choose(st, "--fail-on", arg, fail_on_words, &o->fail_on);
	case OPT_RECORD:
		o->record_path = arg;
		break;
	case OPT_PERFETTO:
		o->perfetto_path = arg;
		break;
	case OPT_NO_OVERHEAD:
		o->no_overhead = true;
		break;
	case OPT_UNIT:
		if (!*arg || strchr(arg, '/') || strlen(arg) > 200)
			return bad(st, "--unit", arg, "want a unit name such as ctrl.service");
		o->unit = arg;
		break;
	case OPT_PROM_TEXTFILE:
		o->prom_textfile = arg;
		break;
	case OPT_ROS2_DIAG:
		o->ros2_diag = true;
		break;
	case OPT_LISTEN:
		o->listen = arg;
		break;
	case OPT_CAN:
		o->can = true;
		if (!arg)
			break;
		if (o->ncan == 8)
			return bad(st, "--can", arg, "at most 8 interfaces");
		if (!*arg || strlen(arg) >= 16)
			return bad(st, "--can", arg, "not an interface name");
		o->can_ifs[o->ncan++] = arg;
		break;
	case OPT_BITRATE:
		if (strict_long(arg, 1000, 20000000, &v))
			return bad(st, "--bitrate", arg, "want bits per second, 1000 to 20000000");
		o->can_bitrate = v;
		break;
	case OPT_CAN_MAX_IDS:
		if (strict_long(arg, 16, 1 << 20, &v))
			return bad(st, "--can-max-ids", arg, "want a number from 16 to 1048576");
		o->can_max_ids = v;
		break;
	case OPT_FLOOR:
		o->floor = true;
		break;
	case OPT_STACKS:
		if (stacks_parse(arg, &o->stacks))
			return bad(st, "--stacks", arg, "want fp, dwarf, auto or off");
		o->stacks_given = true;
		break;
	case OPT_STACK_SIZE:
		if (stack_size_parse(arg, &o->stack_size))
			return bad(st, "--stack-size", arg,
				   "want bytes, a multiple of 8 from 512 to 64K (e.g. 8K)");
		o->stack_size_given = true;
		break;
	case OPT_EVENT_BUFFER:
		if (ring_size_parse(arg, &o->event_buffer))
			return bad(st, "--event-buffer", arg,
				   "want a power of two from 64K to 256M (e.g. 4M)");
		break;
	case OPT_STACK_BUDGET:
		if (strict_long(arg, 1, 1 << 20, &v))
			return bad(st, "--stack-budget", arg, "want a number from 1 to 1048576");
		o->stack_budget = v;
		break;
	case OPT_HIST:
		if (!arg) {
			o->hist = 1u << RTSUP_M_LATENCY;
			break;
		}
		o->hist = 0;
		for (tok = strtok_r(arg, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
			int m = hist_metric(tok);

			if (m < 0)
				return bad(st, "--hist", tok, "want latency, exec, period or cpu");
			o->hist |= 1u << m;
		}
		if (!o->hist)
			return bad(st, "--hist", arg, "empty list");
		break;
	case OPT_HIST_INTERVAL:
		o->hist_interval = true;
		break;
	case 'q':
		o->quiet = true;
		break;
	case OPT_ON_LEVEL: {
		struct action a;
		char why[160];

		if (o->non_level == ACTION_MAX)
			return bad(st, "--on-level", arg, "at most 16 actions");
		if (action_parse(arg, &a, why, sizeof(why)))
			return bad(st, "--on-level", arg, why);
		o->on_level[o->non_level++] = arg;
		break;
	}
	case ARGP_KEY_ARG:
		if (o->replay_path && !*o->replay_path) {
			o->replay_path = arg;	/* replay FILE */
			break;
		}
		if (o->can_replay_path && !*o->can_replay_path) {
			o->can_replay_path = arg;	/* can-replay FILE */
			break;
		}
		return ARGP_ERR_UNKNOWN;	/* the command: ARGP_KEY_ARGS */
	case ARGP_KEY_ARGS:
		if (o->replay_path || o->can_replay_path) {
			fprintf(stderr, "rtsup-trace: replay: unexpected argument '%s'\n",
				st->argv[st->next]);
			return EINVAL;
		}
		o->cmd = st->argv + st->next;
		break;
	case ARGP_KEY_END:
		if (o->replay_path && !*o->replay_path) {
			fprintf(stderr, "rtsup-trace: replay: which file? (rtsup-trace replay FILE)\n");
			return EINVAL;
		}
		if (o->can_replay_path && !*o->can_replay_path) {
			fprintf(stderr, "rtsup-trace: can-replay: which file? "
				"(rtsup-trace can-replay FILE)\n");
			return EINVAL;
		}
		if (!targets_any(t) && !o->cmd && !o->check_config && !o->replay_path &&
		    !o->can_replay_path && !o->can && !o->unit) {
			fprintf(stderr, "rtsup-trace: no target: give --pid, --tid, --comm, --rt, --cgroup or --unit\n");
			return EINVAL;
		}
		if (o->hist_interval && !o->hist) {
			fprintf(stderr, "rtsup-trace: --hist-interval: give --hist too\n");
			return EINVAL;
		}
		if (o->unit && t->cgroup) {
			fprintf(stderr, "rtsup-trace: --unit and --cgroup: give one of them\n");
			return EINVAL;
		}
		break;
	default:
		return ARGP_ERR_UNKNOWN;
	}
	return 0;
}

/* metric_list - "exec,latency": every name a --hist metric */
static bool metric_list(const char *s)
{
	char buf[64], *tok, *save;

	if (!*s || strlen(s) >= sizeof(buf))
		return false;
	strcpy(buf, s);
	for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save))
		if (hist_metric(tok) < 0)
			return false;
	return true;
}

/*
 * join_opt_args - "--can can0" means "--can=can0", "--hist exec" means
 * "--hist=exec": argp's optional arguments only come attached; a bare --can
 * means every interface, a bare --hist the latency
 */
static int join_opt_args(int argc, char **argv)
{
	static char buf[16][80];
	int i, n = 0;

	for (i = 1; i < argc - 1 && n < 16; i++) {
		bool can = !strcmp(argv[i], "--can"), hist = !strcmp(argv[i], "--hist");

		if (!strcmp(argv[i], "--"))
			break;
		if (!can && !hist)
			continue;
		if (can && (argv[i + 1][0] == '-' || !argv[i + 1][0]))
			continue;
		if (hist && !metric_list(argv[i + 1]))
			continue;
		snprintf(buf[n], sizeof(buf[n]), "%s=%s", argv[i], argv[i + 1]);
		argv[i] = buf[n++];
		/* the value is now part of the option: drop its own slot */
		memmove(&argv[i + 1], &argv[i + 2], (argc - i - 2) * sizeof(*argv));
		argv[--argc] = NULL;
	}
	return argc;
}

int options_parse(int argc, char **argv, struct options *o)
{
	return options_parse_flags(argc, argv, o, 0);
}

int options_parse_flags(int argc, char **argv, struct options *o, unsigned int flags)
{
	static const struct argp argp = { opts, parse_opt, NULL, doc, NULL, NULL, NULL };

	memset(o, 0, sizeof(*o));
	o->interval = 1;
	o->ewma_w = 102;
	o->max_threads = RTSUP_DEFAULT_THREADS;
	o->top = ROWCUT_TOP_DEFAULT;
	o->sys_hooks = SYS_HOOKS_DEFAULT;
	o->color = -1;
	o->delims[0] = "clock_nanosleep";
	o->delims[1] = "nanosleep";
	o->ndelims = 2;
	o->fail_on = LEVEL_WARN;
	o->can_max_ids = 4096;
	o->stack_size = 8192;
	o->stack_budget = RTSUP_STACK_BUDGET;
	/* argp's own usage errors exit with our "tool error" status */
	argp_err_exit_status = 1;
	if (argc > 1 && (!strcmp(argv[1], "replay") || !strcmp(argv[1], "can-replay"))) {
		/* "replay FILE [options]": argp sees FILE as the first argument */
		if (!strcmp(argv[1], "replay"))
			o->replay_path = "";
		else
			o->can_replay_path = "";
		argv[1] = argv[0];
		argc = join_opt_args(argc - 1, argv + 1) + 1;
		return argp_parse(&argp, argc - 1, argv + 1, flags, NULL, o) ? -1 : 0;
	}
	argc = join_opt_args(argc, argv);
	return argp_parse(&argp, argc, argv, flags, NULL, o) ? -1 : 0;
}
