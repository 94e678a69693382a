// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * main.c - rtsup-trace: parse, load, attach, then once per interval
 * collect -> model -> checks -> sinks; SIGINT/SIGTERM end with a summary,
 * SIGHUP reloads the configuration.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <malloc.h>
#include <sys/wait.h>
#include <bpf/libbpf.h>
#include "robot/actions.h"
#include "collect/cancollect.h"
#include "offline/canreplay.h"
#include "collect/collector.h"
#include "config/config.h"
#include "collect/loader.h"
#include "options.h"
#include "sinks/output.h"
#include "collect/pidns.h"
#include "offline/replay.h"
#include "robot/robot.h"
#include "sinks/sinks.h"
#include "judge/supervise.h"
#include "collect/targets.h"
#include "collect/selfsched.h"
#include "collect/statsfloor.h"
#include "judge/overhead.h"
#include "can.h"	/* the skeleton's .bss holds can_if_slot */
#include "rtsup.skel.h"

static volatile sig_atomic_t exiting, reload;

static void on_signal(int sig)
{
	if (sig == SIGHUP)
		reload = 1;
	else
		exiting = sig;
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

/* load_config - the file (or the built-in defaults) with the command line over it */
static int load_config(const struct options *o, const char *path, struct config *cfg)
{
	char err[512];
	int i;

	if (!path) {
		config_defaults(cfg);
	} else if (config_load(path, cfg, err, sizeof(err))) {
		fprintf(stderr, "rtsup-trace: %s\n", err);
		return -1;
	}
	/* what the command line says wins over the file's defaults */
	for (i = -1; i < cfg->nrules; i++) {
		struct rule *r = i < 0 ? &cfg->defaults : &cfg->rules[i];
		int d;

		if (o->delims_given && (i < 0 || !(r->set & RF_DELIMS))) {
			for (d = 0; d < o->ndelims && d < CONFIG_MAX_SYSCALLS; d++)
				snprintf(r->delims[d], sizeof(r->delims[d]), "%s", o->delims[d]);
			r->ndelims = d;
		}
		if (o->ewma_given && (i < 0 || !(r->set & RF_EWMA)))
			r->ewma_weight = (double)o->ewma_w / RTSUP_EWMA_ONE;
		if (o->period_given && (i < 0 || !(r->set & RF_PERIOD)))
			r->period_ns = o->period_ns;
		/* a rule's stacks: win over --stacks for its threads (docs/config.md) */
		if (o->stacks_given && (i < 0 || !(r->set & RF_STACKS)))
			r->stacks = o->stacks;
		if (o->stack_size_given && (i < 0 || !(r->set & RF_STACK_SIZE)))
			r->stack_size = o->stack_size;
	}
	/* --on-level adds to the file's actions: (cli.c checked each) */
	for (i = 0; i < o->non_level; i++) {
		struct action a;
		char why[160] = "too many actions with the file's (at most 16)";

		if (action_parse(o->on_level[i], &a, why, sizeof(why)) ||
		    config_add_action(cfg, &a)) {
			fprintf(stderr, "rtsup-trace: --on-level '%s': %s\n", o->on_level[i], why);
			config_free(cfg);
			return -1;
		}
	}
	return 0;
}

/*
 * spawn_cmd - fork the command; it waits on a pipe until the programs are
 * attached, so its first instruction is already supervised.
 */
static pid_t spawn_cmd(char **cmd, int *go_fd)
{
	int p[2];
	pid_t pid;
	char c;

	if (pipe2(p, O_CLOEXEC))
		return -1;
	pid = fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		close(p[1]);
		if (read(p[0], &c, 1) != 1)
			_exit(127);	/* rtsup-trace failed: do not run unsupervised */
		execvp(cmd[0], cmd);
		fprintf(stderr, "rtsup-trace: cannot run '%s': %s\n", cmd[0], strerror(errno));
		_exit(127);
	}
	close(p[0]);
	*go_fd = p[1];
	return pid;
}

/*
 * The overhead check samples: BPF statistics are on for a short window
 * (OVERHEAD_WINDOW, at most an interval) at the start of one interval in
 * OVERHEAD_EVERY, the first one included, and the last measure holds in
 * between. Always on, they cost every BPF program on the machine two clock
 * reads per run (docs/performance.md): sampled, 100 ms in 30 s at the default
 * 1 s interval, a third of a percent of that.
 */
#define OVERHEAD_EVERY 30
#define OVERHEAD_WINDOW 100000000ULL	/* ns */

struct overhead {
	bool open;		/* a window is open */
	__u64 rt0, runs0;	/* our programs' run time and runs when it opened */
	__u64 t0, end;		/* when the window opened, when it closes */
	struct stats_window last;	/* the last window closed (overhead.h) */
	struct stats_floor floor;	/* its floor's empty program */
	unsigned int n;		/* intervals so far */
};

/* overhead_close - close the open window once it is due (or now, 'force') */
static void overhead_close(struct overhead *ov, struct loader *l, __u64 now, bool force)
{
	__u64 rt, runs;

	if (!ov->open || (!force && now < ov->end))
		return;
	if (!loader_run_sums(l, &rt, &runs) && now > ov->t0) {
		ov->last.wall_ns = now - ov->t0;
		ov->last.run_ns = rt - ov->rt0;
		ov->last.runs = runs - ov->runs0;
	}
	loader_stats(l, false);
	ov->open = false;
}

/*
 * overhead_interval - an interval begins: maybe open a window (its floor
 * measured first: the window times our programs only); the last window
 * closed (wall_ns 0: none yet, or --no-overhead)
 */
static const struct stats_window *overhead_interval(struct overhead *ov, struct loader *l,
						    const struct options *o, __u64 now, bool last)
{
	__u64 len = (__u64)(o->interval * 1e9);

	if (o->no_overhead)
		return &ov->last;
	overhead_close(ov, l, now, true);
	if (!last && ov->n++ % OVERHEAD_EVERY == 0 && !loader_stats(l, true)) {
		ov->last.floor_ns = stats_floor_measure(&ov->floor);
		now = mono_now();
		ov->open = !loader_run_sums(l, &ov->rt0, &ov->runs0);
		ov->t0 = now;
		ov->end = now + (len < OVERHEAD_WINDOW ? len : OVERHEAD_WINDOW);
	}
	return &ov->last;
}

/* The main loop's own schedstat at the start and at the last interval's end. */
struct loop_clock {
	struct self_sched start, last;
	bool ok;		/* the kernel keeps schedstat (CONFIG_SCHED_INFO) */
};

/* loop_clock_start - the run begins */
static void loop_clock_start(struct loop_clock *lc)
{
	lc->ok = !self_sched_read(&lc->start);
	lc->last = lc->start;
}

/* loop_clock_take - an interval ends: its span and the run's */
static void loop_clock_take(struct loop_clock *lc, struct self_in *in)
{
	struct self_sched now = lc->last;
	bool ok = lc->ok && !self_sched_read(&now);

	in->loop = self_span_since(&lc->last, &now, ok);
	in->loop_run = self_span_since(&lc->start, &now, ok);
	if (ok)
		lc->last = now;
}

/* self_in - what the supervisor knows about itself this interval */
static void self_in(struct self_in *in, const struct collector *c, const struct supervisor *s,
		    const struct stats_window *stats, __u64 *last_drops)
{
	in->th = &s->cfg.defaults.th;
	in->stats = *stats;
	in->overhead_pct = stats_overhead_pct(stats);
	/* the interval's: the counters never go back (read_counters) */
	in->lost_events = lost_records(c->counters) - *last_drops;
	*last_drops = lost_records(c->counters);
	in->untracked_threads = c->counters[RTSUP_C_MAP_FULL];
}

/* take_health - the tool's own health after an interval's verdicts (and actions) */
static void take_health(struct supervisor *s, const struct collector *c, const struct loader *l,
			const struct actions *a)
{
	struct health *h = &s->health;

	health_counters(h, c->counters);
	h->thread_map.entries = c->map_entries;
	h->thread_map_copied = c->map_copied;
	h->thread_map_short = c->map_short;
	h->thread_map_short_refused = c->map_short_refused;
	h->thread_map_visited = c->map_visited;
	h->thread_map_whole = c->map_whole;
	h->thread_map_batch = c->map_batch;
	h->thread_map_tasks = c->map_tasks;
	h->task_walk = c->attrs_walked;
	h->tasks_asked = c->attrs_asked;
	h->thread_map.capacity = c->o->max_threads;
	if (s->can) {
		h->can_id_map.entries = s->can->n;
		h->can_id_map.capacity = c->o->can_max_ids;
	}
	h->events_not_kept += c->events.dropped;
	h->parse_errors = targets_parse_errors();
	h->actions_dropped = a->skipped_rate + a->skipped_busy;
	h->hook_runs_missed = loader_runs_missed(l);
}

/* sample_can - the CAN maps into the CAN model, on the thread model's interval */
static void sample_can(const struct options *o, struct supervisor *s, const struct loader *l,
		       const struct collector *c)
{
	if (!s->can)
		return;
	can_collect(s->can, l->skel, o, &s->cfg);
	s->can->bank = c->bank;
	s->can->full = c->counters[RTSUP_C_CAN_FULL];
}

/*
 * sample - end an interval: the clock, then every map. 'now' is the
 * interval's end as the kernel's epoch flip marks it (collector.c,
 * epoch_flip), not the end of the read: read after, it counted the read's
 * own time (tens of ms in an emulated guest) as time a thread went
 * without a cycle, a false "starving".
 */
static __u64 sample(const struct options *o, struct supervisor *s, const struct loader *l,
		    struct collector *c)
{
	collector_sample(c);
	s->real_off = c->real_off;
	sample_can(o, s, l, c);
	return c->end_ns;
}

/* stacks_plan - what the kernel side is loaded with for --stacks and the rules' stacks: */
static void stacks_plan(struct options *o, const struct config *cfg)
{
	struct stack_plan p;

	config_stack_plan(cfg, &p);
	o->stacks = p.kind;
	o->stack_size = p.size;
	o->stack_any = p.any;
	o->stack_rules = p.rules;
	o->stack_dwarf = p.dwarf;
	o->stack_auto = p.autos;
	o->stack_size_max = p.size_max;
}

/* print_sys_hooks - -v: the syscalls the per-syscall hooks watch */
static void print_sys_hooks(const struct sys_hookset *h)
{
	int i;

	fprintf(stderr, "rtsup-trace: per-syscall hooks on %d syscalls:", h->nin);
	for (i = 0; i < h->nin; i++)
		fprintf(stderr, " %s", syscall_name(h->in[i]));
	fprintf(stderr, "; at their exit too:");
	for (i = 0; i < h->nout; i++)
		fprintf(stderr, " %s", syscall_name(h->out[i]));
	fputc('\n', stderr);
}

/* do_reload - SIGHUP: a good file replaces the rules, a bad one is refused */
static void do_reload(const struct options *o, struct supervisor *s, const struct loader *l)
{
	struct sys_rule_names names;
	struct stack_plan sp;
	struct config cfg;
	int nr;

	if (!o->config_path) {
		fprintf(stderr, "rtsup-trace: SIGHUP: no --config file to reload\n");
		return;
	}
	if (load_config(o, o->config_path, &cfg)) {
		fprintf(stderr, "rtsup-trace: SIGHUP: keeping the previous rules\n");
		return;
	}
	config_stack_plan(&cfg, &sp);
	/* the kernel side was sized and switched at load: more needs a restart */
	if ((sp.any && !o->stack_any) || (sp.rules && !o->stack_rules) ||
	    (sp.dwarf && sp.size_max > o->stack_size_max) || sp.kind != o->stacks ||
	    sp.size != o->stack_size)
		fprintf(stderr, "rtsup-trace: SIGHUP: %s: its stacks settings take effect at "
			"the next start\n", o->config_path);
	/* the per-syscall hooks were attached at load: a syscall they miss is not seen */
	config_sys_names(&cfg, &names);
	if (l->sys_per && (nr = syshooks_missing(&l->hooks, &names)) >= 0)
		fprintf(stderr, "rtsup-trace: SIGHUP: %s: syscall %s is not hooked (per-syscall "
			"hooks are fixed at start): it takes effect at the next start\n",
			o->config_path, syscall_name(nr));
	supervise_reload(s, &cfg);
	fprintf(stderr, "rtsup-trace: SIGHUP: reloaded %s\n", o->config_path);
}

/* run_live - supervise targets until the duration, a signal, or the command ends */
static int run_live(struct options *o, struct supervisor *s)
{
	struct loader l;
	struct collector c;
	struct sinks sk;
	struct robot rb;
	struct self_in self;
	struct loop_clock lc;
	struct can_model cm;
	struct actions act;
	__u64 start, next, last, now, end = 0, last_drops = 0;
	struct overhead ov = { .open = false, .floor = STATS_FLOOR_NONE };
	pid_t child = -1;
	int go_fd = -1, status = 0, err = 1;
	enum level worst = LEVEL_OK;
	bool child_done = false;

	if (!pidns_is_initial()) {
		output_error(o, "PID namespace: rtsup-trace runs inside a container's PID "
			     "namespace, where its tids are not the kernel's; run it on the host");
		return 1;
	}
	if (robot_prepare(&rb, o, s) || check_targets(o) || (o->can && can_resolve(o)))
		return 1;
	actions_open(&act, s);
	o->canopen = s->cfg.can.canopen;
	/* known from the start: a thread's period may settle before its rule is applied */
	o->warmup_ns = s->cfg.defaults.warmup_ns;
	stacks_plan(o, &s->cfg);
	config_sys_names(&s->cfg, &o->sys_rules);
	if (o->cmd) {
		child = spawn_cmd(o->cmd, &go_fd);
		if (child < 0) {
			fprintf(stderr, "rtsup-trace: cannot start '%s': %s\n", o->cmd[0],
				strerror(errno));
			return 1;
		}
		o->targets.pids[o->targets.npids++] = child;
		s->cmd_mode = true;
	}
	if (loader_start(&l, o))
		goto out_child;
	if (collector_init(&c, l.skel, o))
		goto out;
	c.tasks = l.tasks;
	c.sys_hooks = l.sys_per ? "per-syscall" : "raw_syscalls";
	c.task_attrs = l.tasks ? "thread_map" : l.skel->links.attrs_task ? "task_walk" : "asked";
	if (sinks_open(&sk, o, s, &c))
		goto out;
	if (o->can) {
		memset(&cm, 0, sizeof(cm));
		cm.start_ns = mono_now();
		s->can = &cm;
	}
	s->real_off = c.real_off;
	fprintf(stderr, "rtsup-trace: tracing with %s programs, syscalls %s; Ctrl-C ends with "
		"a summary\n", l.tp_btf ? "tp_btf" : "raw tracepoint",
		l.sys_per ? "by per-syscall hooks" : "on raw_syscalls");
	if (l.sys_per && o->verbose)
		print_sys_hooks(&l.hooks);
	if (go_fd >= 0) {
		if (write(go_fd, "g", 1) != 1)
			goto out;
		close(go_fd);
		go_fd = -1;
	}
	if (robot_start(&rb, &c, s))
		goto out;
	/*
	 * the start-up read the kernel's BTF whole seven times (libbpf, for each
	 * object it relocates; loader.c) and freed it; glibc keeps such pages
	 * (10 MiB of RssAnon on a 6.18 kernel): given back before the loop
	 */
	malloc_trim(0);
	start = last = mono_now();
	loop_clock_start(&lc);
	overhead_interval(&ov, &l, o, start, false);	/* the first window */
	next = start + (__u64)(o->interval * 1e9);
	if (o->duration)
		end = start + (__u64)(o->duration * 1e9);
	while (!exiting && !child_done) {
		robot_tick(&rb);
		now = mono_now();
		if (end && now >= end)
			break;
		if (reload) {
			reload = 0;
			robot_reload(&rb, false);
			do_reload(o, s, &l);
			robot_reload(&rb, true);
		}
		if (child > 0 && waitpid(child, &status, WNOHANG) == child)
			child_done = true;
		actions_poll(&act);
		overhead_close(&ov, &l, now, false);
		if (now < next && !child_done) {
			__u64 until = end && end < next ? end : next;
			int ms;

			if (ov.open && ov.end < until)
				until = ov.end;
			ms = (until - now) / 1000000 + 1;
			ms = collector_poll_ms(&c, ms, child > 0 || actions_running(&act));
			if (robot_tick_ms(&rb) && (__u64)ms > robot_tick_ms(&rb))
				ms = (int)robot_tick_ms(&rb);	/* the watchdog's ping */
			if (collector_poll(&c, ms) < 0)
				break;
			continue;
		}
		now = sample(o, s, &l, &c);
		self_in(&self, &c, s, overhead_interval(&ov, &l, o, now, false), &last_drops);
		loop_clock_take(&lc, &self);
		supervise_interval(s, &c.model, c.bank, &self, now);
		supervise_can(s, now, (now - last) / 1e9);
		take_health(s, &c, &l, &act);
		output_interval(&c, s, (now - start) / 1e9, (now - last) / 1e9);
		if (s->can)
			can_model_next(s->can);
		if (sinks_interval(&sk, &c, &self, now))
			goto out;
		robot_interval(&rb, &c, s, now);
		collector_apply_rules(&c, s);
		collector_clear_events(&c);
		collector_reap(&c);
		last = now;
		next += (__u64)(o->interval * 1e9);
		if (next <= now)
			next = now + (__u64)(o->interval * 1e9);
	}
	robot_stop(&rb);
	/* the last partial interval still counts in the summary */
	if (child > 0 && !child_done) {
		kill(child, exiting ? exiting : SIGTERM);
		waitpid(child, &status, 0);
		child_done = true;
	}
	now = sample(o, s, &l, &c);
	self_in(&self, &c, s, overhead_interval(&ov, &l, o, now, true), &last_drops);
	loop_clock_take(&lc, &self);
	supervise_interval(s, &c.model, c.bank, &self, now);
	supervise_can(s, now, (now - last) / 1e9);
	take_health(s, &c, &l, &act);
	/* the last, partial interval: the intervals add up to the summary */
	output_interval(&c, s, (now - start) / 1e9, (now - last) / 1e9);
	output_summary(&c, s, (now - start) / 1e9);
	if (sinks_close(&sk, &c, &self, now))
		goto out;
	err = 0;
	worst = supervise_worst(s, &c.model);
out:
	actions_close(&act);
	robot_stop(&rb);
	if (s->can) {
		can_model_free(s->can);
		s->can = NULL;
	}
	collector_free(&c);
	loader_stop(&l);
	stats_floor_close(&ov.floor);
out_child:
	robot_stop(&rb);	/* the exporters opened before loading */
	if (go_fd >= 0)
		close(go_fd);	/* the command sees EOF and does not run */
	if (child > 0 && !child_done)
		waitpid(child, &status, 0);
	if (err)
		return 1;
	if (o->check && level_fails(worst, o->fail_on))
		return 2;
	if (child > 0 && WIFEXITED(status) && WEXITSTATUS(status)) {
		fprintf(stderr, "rtsup-trace: %s exited with status %d\n", o->cmd[0],
			WEXITSTATUS(status));
		return WEXITSTATUS(status);
	}
	if (child > 0 && WIFSIGNALED(status)) {
		fprintf(stderr, "rtsup-trace: %s was killed by signal %d\n", o->cmd[0],
			WTERMSIG(status));
		return 128 + WTERMSIG(status);
	}
	return 0;
}

int main(int argc, char **argv)
{
	struct sigaction sa = { .sa_handler = on_signal };
	struct options o;
	struct supervisor s;
	struct config cfg;
	int ret;

	if (options_parse(argc, argv, &o))
		return 1;
	verbose = o.verbose;
	libbpf_set_print(libbpf_print);
	if (o.check_config) {
		if (load_config(&o, o.check_config, &cfg))
			return 1;
		config_print(&cfg, stdout);
		config_free(&cfg);
		return 0;
	}
	if (load_config(&o, o.config_path, &cfg))
		return 1;
	supervise_init(&s, &cfg);
	s.json = o.json;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	sigaction(SIGHUP, &sa, NULL);
	if (o.replay_path)
		ret = replay_run(&o, &s);
	else if (o.can_replay_path)
		ret = can_replay_run(&o, &s);
	else
		ret = run_live(&o, &s);
	supervise_free(&s);
	return ret;
}
