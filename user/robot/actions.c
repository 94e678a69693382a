// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * actions.c - the actions sink: a level change runs commands, sends signals
 * and writes JSON lines to FIFOs and Unix sockets, without ever waiting.
 *
 * A command is /bin/sh -c CMD, spawned with the change in its environment
 * (RTSUP_*) and as one JSON line on its stdin (written into the pipe before
 * the parent lets go of its read end, so it never blocks nor raises
 * SIGPIPE); its stdout goes to our stderr, so that -j output stays JSON.
 * It is reaped by actions_poll(), once per loop turn. Rate limit: one
 * action runs at most once a second per component (actionspec.h), and at
 * most ACTIONS_MAX_RUNNING commands run at once; what either skips is
 * counted, logged the first time and counted again at the end.
 */
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <jansson.h>
#include "robot/actions.h"

extern char **environ;

#define SPEC_LEN	(ACTION_ARG_LEN + 32)
#define NENV		7	/* the RTSUP_* variables */

/* fail - the one line of a failed action */
static void __attribute__((format(printf, 3, 4)))
fail(const struct action *act, const char *comp, const char *fmt, ...)
{
	char spec[SPEC_LEN], why[512];
	va_list ap;

	action_format(act, spec, sizeof(spec));
	va_start(ap, fmt);
	vsnprintf(why, sizeof(why), fmt, ap);
	va_end(ap);
	fprintf(stderr, "rtsup-trace: action '%s' for %s: %s\n", spec, comp, why);
}

char *actions_json(const struct level_change *c)
{
	json_t *o = json_object(), *msgs = json_array(), *checks = json_array();
	char *line;
	int i;

	for (i = 0; i < c->st->nmsg; i++) {
		json_array_append_new(msgs, json_string(c->st->msg[i]));
		if (c->st->fact[i].check)
			json_array_append_new(checks, json_string(c->st->fact[i].check));
	}
	json_object_set_new(o, "type", json_string("level_change"));
	json_object_set_new(o, "time", json_string(c->when));
	json_object_set_new(o, "component", json_string(c->component));
	json_object_set_new(o, "level", json_string(level_name(c->to)));
	json_object_set_new(o, "from", json_string(level_name(c->from)));
	if (c->tid) {
		json_object_set_new(o, "tid", json_integer(c->tid));
		json_object_set_new(o, "pid", json_integer(c->pid));
	}
	json_object_set_new(o, "messages", msgs);
	json_object_set_new(o, "checks", checks);
	line = json_dumps(o, JSON_COMPACT);
	json_decref(o);
	return line;
}

/*
 * not passed on: our own RTSUP_* from a parent, and systemd's notify and
 * watchdog settings, which are rtsup-trace's and not a command's
 */
static const char *const env_drop[] = {
	"RTSUP_", "NOTIFY_SOCKET=", "WATCHDOG_PID=", "WATCHDOG_USEC=",
};

/* env_dropped - a variable a command does not inherit */
static bool env_dropped(const char *var)
{
	size_t i;

	for (i = 0; i < sizeof(env_drop) / sizeof(env_drop[0]); i++)
		if (!strncmp(var, env_drop[i], strlen(env_drop[i])))
			return true;
	return false;
}

/* make_env - our environment with the RTSUP_* variables of this change first */
static char **make_env(const struct level_change *c, char vars[NENV][1200])
{
	char msgs[1024];
	char **env;
	size_t n = 0, i, k = 0;

	while (environ[n])
		n++;
	env = calloc(n + NENV + 1, sizeof(*env));
	if (!env)
		return NULL;
	status_join(c->st, msgs, sizeof(msgs));
	snprintf(vars[0], 1200, "RTSUP_COMPONENT=%s", c->component);
	snprintf(vars[1], 1200, "RTSUP_LEVEL=%s", level_name(c->to));
	snprintf(vars[2], 1200, "RTSUP_FROM=%s", level_name(c->from));
	snprintf(vars[3], 1200, "RTSUP_TIME=%s", c->when);
	snprintf(vars[4], 1200, "RTSUP_MESSAGES=%s", msgs);
	/* empty for a component that is not a thread (CAN, rtsup-trace) */
	if (c->tid) {
		snprintf(vars[5], 1200, "RTSUP_TID=%u", c->tid);
		snprintf(vars[6], 1200, "RTSUP_PID=%u", c->pid);
	} else {
		snprintf(vars[5], 1200, "RTSUP_TID=");
		snprintf(vars[6], 1200, "RTSUP_PID=");
	}
	for (i = 0; i < NENV; i++)
		env[k++] = vars[i];
	for (i = 0; i < n; i++)
		if (!env_dropped(environ[i]))
			env[k++] = environ[i];
	return env;
}

/* run_cmd - spawn /bin/sh -c CMD with the change on stdin; never waits */
static void run_cmd(struct actions *a, const struct action *act,
		    const struct level_change *c, const char *line)
{
	static char vars[NENV][1200];
	posix_spawn_file_actions_t fa;
	posix_spawnattr_t attr;
	sigset_t def, none;
	char *argv[] = { "sh", "-c", (char *)act->arg, NULL };
	char **env;
	int slot, p[2], err;
	pid_t pid;

	for (slot = 0; slot < ACTIONS_MAX_RUNNING; slot++)
		if (!a->child[slot].pid)
			break;
	if (slot == ACTIONS_MAX_RUNNING) {
		if (!a->skipped_busy++)
			fail(act, c->component, "skipped: %d commands still running (logged "
			     "once, counted at the end)", ACTIONS_MAX_RUNNING);
		return;
	}
	if (pipe2(p, O_CLOEXEC)) {
		fail(act, c->component, "pipe: %s", strerror(errno));
		return;
	}
	env = make_env(c, vars);
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_adddup2(&fa, p[0], 0);
	posix_spawn_file_actions_adddup2(&fa, 2, 1);	/* keep our stdout JSON */
	/* our own signal handlers and mask are not the command's */
	posix_spawnattr_init(&attr);
	sigemptyset(&none);
	sigemptyset(&def);
	sigaddset(&def, SIGPIPE);
	sigaddset(&def, SIGINT);
	sigaddset(&def, SIGTERM);
	sigaddset(&def, SIGHUP);
	posix_spawnattr_setsigmask(&attr, &none);
	posix_spawnattr_setsigdefault(&attr, &def);
	posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
	err = env ? posix_spawn(&pid, "/bin/sh", &fa, &attr, argv, env) : ENOMEM;
	posix_spawnattr_destroy(&attr);
	posix_spawn_file_actions_destroy(&fa);
	free(env);
	if (err) {
		fail(act, c->component, "cannot run /bin/sh: %s", strerror(err));
		close(p[0]);
		close(p[1]);
		return;
	}
	/* we still hold the read end: no SIGPIPE, and one line fits the pipe */
	if (fcntl(p[1], F_SETFL, O_NONBLOCK) || write(p[1], line, strlen(line)) < 0)
		fail(act, c->component, "stdin: %s", strerror(errno));
	close(p[1]);
	close(p[0]);
	a->child[slot].pid = pid;
	action_format(act, a->child[slot].spec, sizeof(a->child[slot].spec));
	snprintf(a->child[slot].component, sizeof(a->child[slot].component), "%s",
		 c->component);
	a->runs++;
}

/* send_signal - to the given pid, or to the thread's process */
static void send_signal(struct actions *a, const struct action *act,
			const struct level_change *c)
{
	pid_t pid = act->pid ? (pid_t)act->pid : (pid_t)c->pid;

	if (!pid) {
		fail(act, c->component, "no process to signal (not a thread; give "
		     "signal=SIG@PID)");
		return;
	}
	if (kill(pid, act->sig))
		fail(act, c->component, "kill %d: %s", pid, strerror(errno));
	else
		a->runs++;
}

/* write_quiet - write() that says EPIPE instead of raising SIGPIPE (a FIFO's reader left) */
static ssize_t write_quiet(int fd, const void *buf, size_t len)
{
	struct timespec zero = { 0 };
	sigset_t pipe, old;
	ssize_t n;
	int err;

	sigemptyset(&pipe);
	sigaddset(&pipe, SIGPIPE);
	pthread_sigmask(SIG_BLOCK, &pipe, &old);
	n = write(fd, buf, len);
	err = errno;
	if (n < 0 && err == EPIPE)
		sigtimedwait(&pipe, NULL, &zero);
	pthread_sigmask(SIG_SETMASK, &old, NULL);
	errno = err;
	return n;
}

/* unix_connect - a non-blocking connected socket, or -1 with errno */
static int unix_connect(const char *path, int type)
{
	struct sockaddr_un sa = { .sun_family = AF_UNIX };
	int fd, err;

	snprintf(sa.sun_path, sizeof(sa.sun_path), "%s", path);
	fd = socket(AF_UNIX, type | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
	if (fd < 0 || !connect(fd, (struct sockaddr *)&sa, sizeof(sa)))
		return fd;
	err = errno;
	close(fd);
	errno = err;
	return -1;
}

/* write_line - the JSON line to a FIFO (with a reader) or a Unix socket */
static void write_line(struct actions *a, const struct action *act,
		       const struct level_change *c, const char *line)
{
	size_t len = strlen(line);
	struct stat st;
	ssize_t n;
	int fd;

	if (act->kind == ACTION_FIFO) {
		fd = open(act->arg, O_WRONLY | O_NONBLOCK | O_CLOEXEC);
		if (fd < 0) {
			fail(act, c->component, "%s", errno == ENXIO ? "no reader on the FIFO" :
			     strerror(errno));
			return;
		}
		if (fstat(fd, &st) || !S_ISFIFO(st.st_mode)) {
			fail(act, c->component, "not a FIFO");
			close(fd);
			return;
		}
	} else {
		fd = unix_connect(act->arg, SOCK_STREAM);
		if (fd < 0 && errno == EPROTOTYPE)
			fd = unix_connect(act->arg, SOCK_DGRAM);	/* a datagram socket */
		if (fd < 0) {
			fail(act, c->component, "%s", strerror(errno));
			return;
		}
	}
	if (act->kind == ACTION_UNIX)
		n = send(fd, line, len, MSG_NOSIGNAL | MSG_DONTWAIT);
	else
		n = write_quiet(fd, line, len);
	if (n < 0)
		fail(act, c->component, "%s", errno == EAGAIN ? "full (the reader is slow), "
		     "line dropped" : strerror(errno));
	else if ((size_t)n < len)
		fail(act, c->component, "only %zd of %zu bytes written", n, len);
	else
		a->runs++;
	close(fd);
}

/* on_change - the supervisor's sink callback: every action this change fires */
static void on_change(void *ctx, const struct level_change *c)
{
	struct actions *a = ctx;
	const struct config *cfg = &a->s->cfg;
	char *json = NULL, *line;
	int i;

	if (a->gen != a->s->gen) {
		/* a reload may renumber the actions */
		rate_init(&a->rate);
		a->gen = a->s->gen;
	}
	for (i = 0; i < cfg->nactions; i++) {
		const struct action *act = &cfg->actions[i];

		if (!action_matches(act, c->from, c->to))
			continue;
		if (!rate_allow(&a->rate, i, c->component, c->mono_ns)) {
			if (!a->skipped_rate++)
				fail(act, c->component, "skipped: at most once a second per "
				     "component (logged once, counted at the end)");
			continue;
		}
		if (act->kind == ACTION_SIGNAL) {
			send_signal(a, act, c);
			continue;
		}
		if (!json) {
			json = actions_json(c);
			line = json ? malloc(strlen(json) + 2) : NULL;
			if (!line) {
				fail(act, c->component, "out of memory");
				break;
			}
			sprintf(line, "%s\n", json);
			free(json);
			json = line;
		}
		if (act->kind == ACTION_RUN)
			run_cmd(a, act, c, json);
		else
			write_line(a, act, c, json);
	}
	free(json);
}

void actions_open(struct actions *a, struct supervisor *s)
{
	memset(a, 0, sizeof(*a));
	a->s = s;
	a->gen = s->gen;
	rate_init(&a->rate);
	s->on_change = on_change;
	s->on_change_ctx = a;
}

void actions_poll(struct actions *a)
{
	int i, st;

	for (i = 0; i < ACTIONS_MAX_RUNNING; i++) {
		if (!a->child[i].pid || waitpid(a->child[i].pid, &st, WNOHANG) != a->child[i].pid)
			continue;
		a->child[i].pid = 0;
		if (WIFEXITED(st) && WEXITSTATUS(st))
			fprintf(stderr, "rtsup-trace: action '%s' for %s: exited with status %d%s\n",
				a->child[i].spec, a->child[i].component, WEXITSTATUS(st),
				WEXITSTATUS(st) == 127 ? " (command not found?)" : "");
		else if (WIFSIGNALED(st))
			fprintf(stderr, "rtsup-trace: action '%s' for %s: killed by signal %d\n",
				a->child[i].spec, a->child[i].component, WTERMSIG(st));
	}
}

int actions_running(const struct actions *a)
{
	int i, n = 0;

	for (i = 0; i < ACTIONS_MAX_RUNNING; i++)
		n += a->child[i].pid != 0;
	return n;
}

void actions_close(struct actions *a)
{
	int n;

	if (!a->s)
		return;
	actions_poll(a);
	n = actions_running(a);
	if (a->skipped_rate || a->skipped_busy || n)
		fprintf(stderr, "rtsup-trace: actions: %llu done, %llu skipped by the rate limit, "
			"%llu with %d commands running, %d still running\n",
			(unsigned long long)a->runs, (unsigned long long)a->skipped_rate,
			(unsigned long long)a->skipped_busy, ACTIONS_MAX_RUNNING, n);
	a->s->on_change = NULL;
	a->s = NULL;
}
