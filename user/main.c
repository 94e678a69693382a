// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * main.c - rtsup-trace: parse, load, attach, then once per interval
 * collect -> model -> output; SIGINT/SIGTERM end with a summary.
 */
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <bpf/libbpf.h>
#include "collector.h"
#include "loader.h"
#include "options.h"
#include "output.h"
#include "targets.h"
#include "rtsup.skel.h"

static volatile sig_atomic_t exiting;

static void on_signal(int sig)
{
	exiting = 1;
}

static bool verbose;

/* libbpf_print - libbpf's messages only with -v */
static int libbpf_print(enum libbpf_print_level level, const char *fmt, va_list args)
{
	if (!verbose)
		return 0;
	return vfprintf(stderr, fmt, args);
}

/* check_targets - named pids and tids must exist now */
static int check_targets(const struct options *o)
{
	char msg[64];
	int i;

	for (i = 0; i < o->targets.npids; i++) {
		if (!process_exists(o->targets.pids[i])) {
			snprintf(msg, sizeof(msg), "--pid %d: no such process", o->targets.pids[i]);
			output_error(o, msg);
			return -1;
		}
	}
	for (i = 0; i < o->targets.ntids; i++) {
		if (!process_exists(o->targets.tids[i])) {
			snprintf(msg, sizeof(msg), "--tid %d: no such thread", o->targets.tids[i]);
			output_error(o, msg);
			return -1;
		}
	}
	return 0;
}

int main(int argc, char **argv)
{
	struct options o;
	struct loader l;
	struct collector c;
	struct sigaction sa = { .sa_handler = on_signal };
	__u64 start, next, last, now, end = 0;
	int err = 1;

	if (options_parse(argc, argv, &o))
		return 1;
	verbose = o.verbose;
	libbpf_set_print(libbpf_print);
	if (check_targets(&o))
		return 1;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	if (loader_start(&l, &o))
		return 1;
	if (collector_init(&c, l.skel, &o))
		goto out;
	/* stderr, so stdout stays parsable; tests wait for this line */
	fprintf(stderr, "rtsup-trace: tracing with %s programs; Ctrl-C ends with a summary\n",
		l.tp_btf ? "tp_btf" : "raw tracepoint");
	start = last = mono_now();
	next = start + (__u64)(o.interval * 1e9);
	if (o.duration)
		end = start + (__u64)(o.duration * 1e9);
	while (!exiting) {
		now = mono_now();
		if (end && now >= end)
			break;
		if (now < next) {
			__u64 until = end && end < next ? end : next;
			int ms = (until - now) / 1000000 + 1;

			if (collector_poll(&c, ms > 100 ? 100 : ms) < 0)
				break;
			continue;
		}
		collector_sample(&c);
		output_interval(&c, (now - start) / 1e9, (now - last) / 1e9);
		collector_clear_events(&c);
		collector_reap(&c);
		last = now;
		next += (__u64)(o.interval * 1e9);
		if (next <= now)
			next = now + (__u64)(o.interval * 1e9);
	}
	/* the last partial interval still counts in the summary */
	collector_sample(&c);
	now = mono_now();
	output_summary(&c, (now - start) / 1e9);
	err = 0;
out:
	collector_free(&c);
	loader_stop(&l);
	return err;
}
