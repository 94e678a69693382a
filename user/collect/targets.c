// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * targets.c - find the threads to supervise in /proc and in a cgroup.
 *
 * This is the start-up scan only: threads created later are added by the
 * kernel side (fork, exec, rename, switch-in of an RT thread).
 */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "collect/targets.h"

/* text of /proc or a cgroup that was read but did not parse (targets.h) */
static __u64 parse_errors;

__u64 targets_parse_errors(void)
{
	return parse_errors;
}

bool targets_any(const struct targets *t)
{
	return t->npids || t->ntids || t->ncomms || t->rt || t->cgroup;
}

bool process_exists(pid_t pid)
{
	char path[64];

	snprintf(path, sizeof(path), "/proc/%d", pid);
	return access(path, F_OK) == 0;
}

int comm_read(FILE *f, char *buf, size_t len)
{
	size_t n;

	if (!fgets(buf, len, f))
		return -EIO;
	n = strlen(buf);
	if (n && buf[n - 1] == '\n')
		buf[n - 1] = '\0';
	return 0;
}

int thread_comm(pid_t tgid, pid_t tid, char *buf, size_t len)
{
	char path[96];
	FILE *f;
	int err;

	snprintf(path, sizeof(path), "/proc/%d/task/%d/comm", tgid, tid);
	f = fopen(path, "re");
	if (!f)
		return -errno;
	err = comm_read(f, buf, len);
	fclose(f);
	return err;
}

unsigned long stat_flags(const char *line)
{
	/* the name may hold spaces and ')': the fields start after the last ')' */
	const char *p = strrchr(line, ')');
	unsigned long flags;

	/* state ppid pgrp session tty_nr tpgid flags */
	if (!p || sscanf(p + 1, " %*c %*d %*d %*d %*d %*d %lu", &flags) != 1) {
		parse_errors++;
		return 0;
	}
	return flags;
}

bool thread_is_kernel(pid_t tgid, pid_t tid)
{
	char path[96], line[512];
	FILE *f;
	bool k = false;

	snprintf(path, sizeof(path), "/proc/%d/task/%d/stat", tgid, tid);
	f = fopen(path, "re");
	if (!f)
		return false;
	if (fgets(line, sizeof(line), f))
		k = stat_flags(line) & TARGETS_PF_KTHREAD;
	fclose(f);
	return k;
}

void comm_sanitize(char *s, size_t len)
{
	size_t i;

	for (i = 0; i < len && s[i]; i++)
		if ((unsigned char)s[i] < 0x20 || (unsigned char)s[i] >= 0x7f)
			s[i] = '?';
}

bool comm_matches(const struct targets *t, const char *comm)
{
	int i;

	for (i = 0; i < t->ncomms; i++)
		if (!strncmp(t->comms[i], comm, RTSUP_COMM_LEN - 1))
			return true;
	return false;
}

pid_t status_tgid(FILE *f)
{
	char line[128];
	pid_t tgid = -1;
	bool read = false;

	while (fgets(line, sizeof(line), f)) {
		read = true;
		if (sscanf(line, "Tgid: %d", &tgid) == 1)
			return tgid;
	}
	/* nothing read: the thread went away meanwhile, not a parse error */
	if (read)
		parse_errors++;
	return -1;
}

/* tgid_of - the process a thread belongs to, from /proc/<tid>/status */
static pid_t tgid_of(pid_t tid)
{
	char path[64];
	pid_t tgid;
	FILE *f;

	snprintf(path, sizeof(path), "/proc/%d/status", tid);
	f = fopen(path, "re");
	if (!f)
		return -1;
	tgid = status_tgid(f);
	fclose(f);
	return tgid;
}

/* is_rt - does the thread run with an RT policy? */
static bool is_rt(pid_t tid)
{
	int p = sched_getscheduler(tid);

	return p == SCHED_FIFO || p == SCHED_RR || p == 6 /* SCHED_DEADLINE */;
}

/* for_each_thread - call fn for every thread of a process */
static int for_each_thread(pid_t tgid, int (*fn)(void *, pid_t, pid_t), void *arg)
{
	char path[64];
	struct dirent *de;
	DIR *d;
	int err = 0;

	snprintf(path, sizeof(path), "/proc/%d/task", tgid);
	d = opendir(path);
	if (!d)
		return 0;	/* gone meanwhile */
	while (!err && (de = readdir(d))) {
		if (!isdigit((unsigned char)de->d_name[0]))
			continue;
		err = fn(arg, tgid, atoi(de->d_name));
	}
	closedir(d);
	return err;
}

struct scan {
	const struct targets *t;
	target_cb cb;
	void *ctx;
};

/* scan_thread - decide for one thread of the system-wide walk */
static int scan_thread(void *arg, pid_t tgid, pid_t tid)
{
	struct scan *s = arg;
	char comm[RTSUP_COMM_LEN] = "", pcomm[RTSUP_COMM_LEN] = "";
	int i;

	if (thread_comm(tgid, tid, comm, sizeof(comm)))
		return 0;
	for (i = 0; i < s->t->npids; i++)
		if (s->t->pids[i] == tgid)
			return s->cb(s->ctx, tgid, tid, comm, TARGET_PROCESS);
	for (i = 0; i < s->t->ntids; i++)
		if (s->t->tids[i] == tid)
			return s->cb(s->ctx, tgid, tid, comm, false);
	if (s->t->ncomms) {
		/* a process by its name (all its threads), or a thread by its own */
		if (!thread_comm(tgid, tgid, pcomm, sizeof(pcomm)) &&
		    comm_matches(s->t, pcomm))
			return s->cb(s->ctx, tgid, tid, comm, TARGET_PROCESS);
		if (comm_matches(s->t, comm))
			return s->cb(s->ctx, tgid, tid, comm, false);
	}
	if (s->t->rt && is_rt(tid))
		return s->cb(s->ctx, tgid, tid, comm, TARGET_RT);
	return 0;
}

int cgroup_threads(FILE *f, int (*fn)(void *, pid_t), void *arg)
{
	int tid, n = 0, err = 0;

	while (!err && (n = fscanf(f, "%d", &tid)) == 1)
		err = fn(arg, tid);
	/* the rest of the file is skipped: counted, not silent */
	if (!err && n == 0)
		parse_errors++;
	return err;
}

/* cgroup_thread - one thread of the cgroup, if it still exists */
static int cgroup_thread(void *arg, pid_t tid)
{
	struct scan *s = arg;
	char comm[RTSUP_COMM_LEN];
	pid_t tgid = tgid_of(tid);

	if (tgid > 0 && !thread_comm(tgid, tid, comm, sizeof(comm)))
		return s->cb(s->ctx, tgid, tid, comm, false);
	return 0;
}

/* scan_cgroup - every thread listed in the cgroup's cgroup.threads */
static int scan_cgroup(struct scan *s)
{
	char path[4096];
	FILE *f;
	int err;

	snprintf(path, sizeof(path), "%s/cgroup.threads", s->t->cgroup);
	f = fopen(path, "re");
	if (!f)
		return -errno;
	err = cgroup_threads(f, cgroup_thread, s);
	fclose(f);
	return err;
}

int targets_scan(const struct targets *t, target_cb cb, void *ctx)
{
	struct scan s = { .t = t, .cb = cb, .ctx = ctx };
	struct dirent *de;
	DIR *d;
	int err = 0, i;

	if (t->cgroup && (err = scan_cgroup(&s)))
		return err;
	if (!t->ncomms && !t->rt) {
		/* only pids and tids: no need to walk the whole system */
		for (i = 0; !err && i < t->npids; i++)
			err = for_each_thread(t->pids[i], scan_thread, &s);
		for (i = 0; !err && i < t->ntids; i++) {
			pid_t tgid = tgid_of(t->tids[i]);

			if (tgid > 0)
				err = scan_thread(&s, tgid, t->tids[i]);
		}
		return err;
	}
	d = opendir("/proc");
	if (!d)
		return -errno;
	while (!err && (de = readdir(d))) {
		if (!isdigit((unsigned char)de->d_name[0]))
			continue;
		err = for_each_thread(atoi(de->d_name), scan_thread, &s);
	}
	closedir(d);
	return err;
}

int cpu_list_parse(const char *text, unsigned long *bits, int nbits)
{
	const int w = 8 * sizeof(*bits);
	const char *p = text;
	char *end;
	long a, b, c;

	memset(bits, 0, (nbits + w - 1) / w * sizeof(*bits));
	while (*p && *p != '\n') {
		a = strtol(p, &end, 10);
		if (end == p || a < 0)
			return -EINVAL;
		b = a;
		p = end;
		if (*p == '-') {
			b = strtol(++p, &end, 10);
			if (end == p || b < a)
				return -EINVAL;
			p = end;
		}
		for (c = a; c <= b && c < nbits; c++)
			bits[c / w] |= 1UL << (c % w);
		if (*p == ',')
			p++;
		else if (*p && *p != '\n')
			return -EINVAL;
	}
	return 0;
}

void cpu_list_mask(const unsigned long *bits, int nbits, char *buf, size_t len)
{
	const int w = 8 * sizeof(*bits);
	size_t off = 0;
	int c, start = -1;

	buf[0] = '\0';
	for (c = 0; c <= nbits; c++) {
		bool in = c < nbits && (bits[c / w] >> (c % w) & 1);

		/* a whole empty word at once: most of a 1024-bit set */
		if (!in && start < 0 && c % w == 0 && c < nbits && !bits[c / w]) {
			c += w - 1;
			continue;
		}
		if (in && start < 0)
			start = c;
		if (!in && start >= 0) {
			if (off < len)
				off += snprintf(buf + off, len - off, "%s%d", off ? "," : "",
						start);
			if (c - 1 > start && off < len)
				off += snprintf(buf + off, len - off, "-%d", c - 1);
			start = -1;
		}
	}
}

void cpu_list(pid_t tid, char *buf, size_t len)
{
	cpu_set_t set;

	if (sched_getaffinity(tid, sizeof(set), &set)) {
		snprintf(buf, len, "-");
		return;
	}
	cpu_list_mask(set.__bits, CPU_SETSIZE, buf, len);
}
