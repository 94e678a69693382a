// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* collector.c - read the kernel's maps into the model, once per interval */
#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/syscall.h>
#include <bpf/bpf.h>
#include <bpf/libbpf.h>
#include <sys/epoll.h>
#include "collect/collector.h"
#include "collect/clockoff.h"
#include "collect/clockwatch.h"
#include "collect/liveness.h"
#include "collect/mapprune.h"
#include "cycle.h"
#include "rtfollow.h"
#include "threadread.h"
#include "collect/targets.h"
#include "collect/unwind.h"
#include "model/syscalls.h"
#include "judge/supervise.h"
#include "can.h"	/* the skeleton's .bss holds can_if_slot */
#include "rtsup.skel.h"
#include "rtsup_tasks.skel.h"

__u64 mono_now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000000000ULL + ts.tv_nsec;
}

/* a clock the kernel side converts and the one it reads (the alarm clocks sleep on their base) */
static const clockid_t converted_clocks[COLLECTOR_CLOCKS][2] = {
	{ CLOCK_REALTIME, CLOCK_REALTIME }, { CLOCK_REALTIME_ALARM, CLOCK_REALTIME },
	{ CLOCK_BOOTTIME, CLOCK_BOOTTIME }, { CLOCK_BOOTTIME_ALARM, CLOCK_BOOTTIME },
	{ CLOCK_TAI, CLOCK_TAI },
};

/*
 * update_clocks - let the kernel side convert absolute sleeps to its clock:
 * a reading replaces the held offset when the clock moved by more than the
 * two readings' errors, or when it is known 'stepped' or read first
 * (clockoff_keep)
 */
static void update_clocks(struct collector *c, bool stepped)
{
	struct clock_offset now;
	size_t i;

	for (i = 0; i < COLLECTOR_CLOCKS; i++) {
		now = clockoff_read(converted_clocks[i][1]);
		c->clock_held[i] = clockoff_keep(c->clock_held[i], now, stepped);
		c->skel->bss->clock_off[converted_clocks[i][0]] = c->clock_held[i].off;
	}
	c->real_off = c->skel->bss->clock_off[CLOCK_REALTIME];
}

/*
 * watch_clock - the ring buffer's epoll fd and a clockwatch timer in one
 * epoll set, so a step of the wall clock wakes the poll. Without it (no
 * timerfd cancel: kernels before 3.0) the offsets follow each interval.
 */
static void watch_clock(struct collector *c)
{
	struct epoll_event ev = { .events = EPOLLIN };

	c->clock_fd = clockwatch_open();
	c->epfd = c->clock_fd < 0 ? -1 : epoll_create1(EPOLL_CLOEXEC);
	if (c->epfd >= 0 && !epoll_ctl(c->epfd, EPOLL_CTL_ADD, c->clock_fd, &ev) &&
	    !epoll_ctl(c->epfd, EPOLL_CTL_ADD, ring_buffer__epoll_fd(c->rb), &ev))
		return;
	if (c->epfd >= 0)
		close(c->epfd);
	if (c->clock_fd >= 0)
		close(c->clock_fd);
	c->epfd = c->clock_fd = -1;
}

/* clock_stepped - the wall clock was stepped: new offsets to the kernel side now */
static void clock_stepped(struct collector *c)
{
	update_clocks(c, true);
	c->clock_steps++;
	fprintf(stderr, "rtsup-trace: the wall clock was stepped by %+.6f s; "
		"absolute sleeps on it are judged with its new time\n",
		(c->real_off - c->real_off_said) / 1e9);
	c->real_off_said = c->real_off;
}

/*
 * poll_over - a flood of events (a thread in an mmap loop) would keep
 * ring_buffer__poll consuming for as long as it lasts, and the interval
 * late: past the poll's time, a negative return stops it after this
 * record. What is left waits for the next poll; what the kernel cannot
 * write meanwhile is counted as lost. The clock is read once in 64 records.
 */
static int poll_over(struct collector *c)
{
	if (++c->polled % 64 || mono_now() < c->poll_until)
		return 0;
	return -EAGAIN;
}

/* put_verdict - --stacks auto: a process's unwinder, for the kernel side (stackcfg.h) */
static void put_verdict(void *ctx, __u32 tgid, __u32 kind)
{
	struct collector *c = ctx;

	bpf_map_update_elem(bpf_map__fd(c->skel->maps.stack_auto), &tgid, &kind, BPF_ANY);
}

/* on_event - ring buffer callback: keep the event for the sinks */
static int on_event(void *ctx, void *data, size_t len)
{
	struct collector *c = ctx;

	if (len < sizeof(struct rtsup_event))
		return 0;
	if (c->on_rare)
		c->on_rare(c->sink_ctx, data);
	/* a new target process: its mappings now, while it is there */
	if (c->unwinder && ((struct rtsup_event *)data)->type == RTSUP_EV_NEW) {
		unwind_note_process(c->unwinder, ((struct rtsup_event *)data)->tgid);
		unwind_take_verdicts(c->unwinder, put_verdict, c);
	}
	collector_take_event(c, data);
	return poll_over(c);
}

/* on_stack_rec - stack ring buffer callback: unwind, symbolize, count */
static int on_stack_rec(void *ctx, void *data, size_t len)
{
	static struct stack_frame frames[STACK_MAX_FRAMES];
	struct collector *c = ctx;
	const struct rtsup_stack_rec *r = data;
	int n;

	if (len < sizeof(*r))
		return 0;
	n = unwind_record(c->unwinder, r, len, frames, STACK_MAX_FRAMES);
	/* its mappings were read again (an exec, a dlopen): auto may say otherwise */
	unwind_take_verdicts(c->unwinder, put_verdict, c);
	if (n < 0)
		return 0;	/* an exec mark: no event */
	c->stacks.records++;
	stackagg_add_kind(&c->stacks, r->tid, r->tgid, NULL, r->reason, r->nr, r->kind, frames,
			  n);
	if (c->on_stack) {
		struct stack_maps m;

		unwind_maps(c->unwinder, r->tgid, &m);
		c->on_stack(c->sink_ctx, r, frames, n, &m);
	}
	return 0;
}

/* open_stacks - --stacks: the unwinder and the stack ring buffer */
static int open_stacks(struct collector *c)
{
	if (!c->skel->rodata->cfg_stack_any)
		return 0;
	c->unwinder = unwinder_new();
	if (c->unwinder)
		unwinder_set_auto(c->unwinder, c->o->stack_auto);
	c->stack_rb = ring_buffer__new(bpf_map__fd(c->skel->maps.stacks), on_stack_rec, c, NULL);
	if (!c->unwinder || !c->stack_rb) {
		fprintf(stderr, "rtsup-trace: --stacks: cannot create the stack ring buffer: %s\n",
			strerror(errno));
		return -1;
	}
	return 0;
}

/* read_stack_counters - the stack records the kernel side could not send */
static void read_stack_counters(struct collector *c)
{
	int ncpu = libbpf_num_possible_cpus(), fd = bpf_map__fd(c->skel->maps.stack_counters);
	__u64 vals[ncpu > 0 ? ncpu : 1], sum;
	__u32 k;
	int i;

	if (!c->stack_rb)
		return;
	/* what the kernel has sent so far counts in this interval */
	ring_buffer__consume(c->stack_rb);
	for (k = 0; k < RTSUP_STK_NR; k++) {
		if (ncpu <= 0 || bpf_map_lookup_elem(fd, &k, vals))
			continue;
		for (sum = 0, i = 0; i < ncpu; i++)
			sum += vals[i];
		c->stacks.kernel[k] = sum;
	}
}

void collector_take_event(struct collector *c, const struct rtsup_event *e)
{
	struct rtsup_event ev = *e;

	ev.comm[RTSUP_COMM_LEN - 1] = '\0';
	comm_sanitize(ev.comm, RTSUP_COMM_LEN);
	c->events_total++;
	if (ev.type == RTSUP_EV_MISS) {
		ev.cause.who.comm[RTSUP_COMM_LEN - 1] = '\0';
		comm_sanitize(ev.cause.who.comm, RTSUP_COMM_LEN);
		ev.cause.waker.comm[RTSUP_COMM_LEN - 1] = '\0';
		comm_sanitize(ev.cause.waker.comm, RTSUP_COMM_LEN);
		for (int i = 0; i < RTSUP_CAUSE_TOP; i++) {
			ev.cause.top[i].who.comm[RTSUP_COMM_LEN - 1] = '\0';
			comm_sanitize(ev.cause.top[i].who.comm, RTSUP_COMM_LEN);
		}
		causes_add(&c->causes_win, ev.tid, &ev.cause);
		causes_add(&c->causes_life, ev.tid, &ev.cause);
	}
	eventlog_add(&c->events, &ev);
}

/* on_cycle_rec - recording ring buffer callback: hand the cycle to the sinks */
static int on_cycle_rec(void *ctx, void *data, size_t len)
{
	struct collector *c = ctx;

	if (len >= sizeof(struct rtsup_cycle_rec) && c->on_cycle)
		c->on_cycle(c->sink_ctx, data);
	return poll_over(c);
}

/* add_initial - a thread found by the start-up scan goes into the maps */
static int add_initial(void *ctx, pid_t tgid, pid_t tid, const char *comm, unsigned int how)
{
	bool process = how & TARGET_PROCESS;
	struct collector *c = ctx;
	struct rtsup_thread *t = calloc(1, sizeof(*t));
	__u32 key = tid, one = 1, k = tgid;
	int err = 0;

	if (!t)
		return -ENOMEM;
	cycle_thread_init(t, tid, tgid, mono_now());
	strncpy(t->comm, comm, RTSUP_COMM_LEN - 1);
	/* --rt alone: let go when it leaves RT (rtfollow.h) */
	if (how & TARGET_RT)
		t->rt = RTSUP_RT_ONLY;
	if (process)
		bpf_map_update_elem(bpf_map__fd(c->skel->maps.tgids), &k, &one, BPF_ANY);
	/* the hooks look a thread up only when its bits are set (rtsup.h) */
	tid_mark_new(c->skel->bss->tidmask, c->skel->bss->wakemask, key);
	if (c->unwinder && process) {
		unwind_note_process(c->unwinder, tgid);
		unwind_take_verdicts(c->unwinder, put_verdict, c);
	}
	/* written here, not by a hook: named for the next read */
	movedset_note(&c->moved, key, THREAD_NO_SLOT);
	err = threadmem_add(&c->mem, key, t);
	if (err == -EEXIST)
		err = 0;	/* a hook added it since attach: its entry stays */
	if (err == -E2BIG) {
		err = 0;
		/* counted once, by whichever side notes it first (rtsup.bpf.c) */
		if (!bpf_map_update_elem(bpf_map__fd(c->skel->maps.untracked), &key, &k,
					 BPF_NOEXIST))
			c->untracked_scan++;
	}
	free(t);
	return err;
}

int collector_init(struct collector *c, struct rtsup_bpf *skel, const struct options *o)
{
	int err;

	memset(c, 0, sizeof(*c));
	c->skel = skel;
	c->o = o;
	c->start_ns = mono_now();
	c->clock_fd = c->epfd = -1;
	c->batch_cap = COLLECTOR_BATCH;
	c->batch_keys = calloc(c->batch_cap, sizeof(*c->batch_keys));
	c->batch_slots = calloc(c->batch_cap, sizeof(*c->batch_slots));
	c->batch_at = calloc(c->batch_cap, sizeof(*c->batch_at));
	c->entry = calloc(1, sizeof(*c->entry));
	if (!c->batch_keys || !c->batch_slots || !c->batch_at || !c->entry) {
		fprintf(stderr, "rtsup-trace: out of memory\n");
		return -1;
	}
	err = threadmem_open(&c->mem, bpf_map__fd(skel->maps.thread_mem),
			     bpf_map__fd(skel->maps.threads), bpf_map__fd(skel->maps.thread_free),
			     bpf_map__max_entries(skel->maps.thread_mem));
	if (err) {
		fprintf(stderr, "rtsup-trace: mapping the thread map's entries: %s\n",
			strerror(-err));
		return -1;
	}
	update_clocks(c, true);	/* the first readings, whole */
	c->real_off_said = c->real_off;
	c->rb = ring_buffer__new(bpf_map__fd(skel->maps.events), on_event, c, NULL);
	if (!c->rb || (skel->rodata->cfg_record &&
		       ring_buffer__add(c->rb, bpf_map__fd(skel->maps.cycles), on_cycle_rec, c))) {
		fprintf(stderr, "rtsup-trace: cannot create the ring buffer: %s\n", strerror(errno));
		return -1;
	}
	watch_clock(c);
	/* without it every read walks the whole map */
	if (movedset_open(&c->moved, bpf_map__fd(skel->maps.moved)))
		fprintf(stderr, "rtsup-trace: the ring of moved threads: %s (every read is whole)\n",
			strerror(errno));
	if (open_stacks(c))
		return -1;
	err = targets_scan(&o->targets, add_initial, c);
	if (err) {
		fprintf(stderr, "rtsup-trace: adding targets: %s\n", strerror(-err));
		return -1;
	}
	return 0;
}

int collector_scan(struct collector *c, const struct targets *t)
{
	return targets_scan(t, add_initial, c);
}

int collector_poll(struct collector *c, int ms)
{
	int err, budget = ms > COLLECTOR_POLL_MIN_MS ? ms : COLLECTOR_POLL_MIN_MS;

	c->poll_until = mono_now() + (__u64)budget * 1000000;
	if (c->epfd >= 0) {
		struct epoll_event ev[2];

		if (epoll_wait(c->epfd, ev, 2, ms) < 0 && errno != EINTR)
			return -errno;
		if (clockwatch_stepped(c->clock_fd) > 0)
			clock_stepped(c);
		err = ring_buffer__consume(c->rb);
	} else {
		err = ring_buffer__poll(c->rb, ms);
	}
	c->poll_quiet = err == 0;
	if (c->stack_rb && ring_buffer__consume(c->stack_rb) != 0)
		c->poll_quiet = false;
	return err == -EINTR || err == -EAGAIN ? 0 : err;
}

int collector_poll_ms(const struct collector *c, int ms, bool busy)
{
	int cap = c->poll_quiet && !c->stack_rb && !busy ? COLLECTOR_POLL_QUIET_MS
							 : COLLECTOR_POLL_MAX_MS;

	return ms > cap ? cap : ms;
}

/*
 * counter_base - what userspace adds to a kernel counter: the threads the
 * start-up scan could not add are untracked too, never counted by the kernel
 */
static __u64 counter_base(const struct collector *c, __u32 k)
{
	return k == RTSUP_C_MAP_FULL ? c->untracked_scan : 0;
}

/* read_counters - sum the per-CPU counters of the kernel side */
static void read_counters(struct collector *c)
{
	int ncpu = libbpf_num_possible_cpus(), fd = bpf_map__fd(c->skel->maps.counters);
	__u64 vals[ncpu > 0 ? ncpu : 1];
	__u32 k;
	int i;

	for (k = 0; k < RTSUP_C_NR; k++) {
		__u64 sum = counter_base(c, k);

		if (ncpu <= 0 || bpf_map_lookup_elem(fd, &k, vals))
			continue;	/* keep the last sum: counters never go back */
		for (i = 0; i < ncpu; i++)
			sum += vals[i];
		c->counters[k] = sum;
	}
}

/*
 * unsafe_sys_due - must this sample walk unsafe_sys? A walk of the hash
 * map reads all its buckets however few entries it holds (16384 by
 * default, a fortieth of the loop's CPU with 900 parked threads): only
 * when a hook wrote it since the last walk (unsafe_sys_gen), when the last
 * walk found an entry of a thread the model did not hold yet or a thread's
 * mode moved since (take: its keys of the new mode count, not the old),
 * and every THREAD_TASK_EVERY-th sample as a net.
 */
static bool unsafe_sys_due(struct collector *c)
{
	__u32 gen = __atomic_load_n(&c->skel->bss->unsafe_sys_gen, __ATOMIC_ACQUIRE);
	bool due = gen != c->unsafe_sys_seen || c->unsafe_sys_pending ||
		   c->sample_seq % THREAD_TASK_EVERY == 0;

	/* before the walk: a write during it makes the next sample walk again */
	c->unsafe_sys_seen = gen;
	return due;
}

/* read_unsafe_sys - per-syscall unsafe counts into the model */
static void read_unsafe_sys(struct collector *c)
{
	int fd = bpf_map__fd(c->skel->maps.unsafe_sys);
	struct rtsup_sys_key key, next, *prev = NULL;
	struct thread_model *tm;
	__u64 n;

	if (!unsafe_sys_due(c))
		return;
	c->unsafe_sys_pending = false;
	while (!bpf_map_get_next_key(fd, prev, &next)) {
		key = next;
		prev = &key;
		if (bpf_map_lookup_elem(fd, &key, &n))
			continue;
		tm = model_get(&c->model, key.tid, false);
		if (!tm)
			c->unsafe_sys_pending = true;	/* its model may come at the next read */
		/* counts of the start-up phase stay out of a delimiter thread */
		else if (key.mode == cycle_sys_mode(&tm->cur.cs))
			model_sys_set(tm, key.nr, n);
	}
}

/* read_cgroup - a thread's cgroup v2 path from /proc/<tid>/cgroup, "" if unknown */
static void read_cgroup(__u32 tgid, __u32 tid, char *buf, size_t len)
{
	char path[64], line[512];
	FILE *f;

	buf[0] = '\0';
	snprintf(path, sizeof(path), "/proc/%u/task/%u/cgroup", tgid, tid);
	f = fopen(path, "re");
	if (!f)
		return;
	while (fgets(line, sizeof(line), f)) {
		if (!strncmp(line, "0::", 3)) {
			line[strcspn(line, "\n")] = '\0';
			snprintf(buf, len, "%.255s", line + 3);
			break;
		}
	}
	fclose(f);
}

/*
 * rematch - the rules match on the thread's name, its process's name and
 * its cgroup: when one changes (PR_SET_NAME, exec, a move to another
 * cgroup) the rules are matched again and the kernel gets the new settings
 */
static void rematch(struct thread_model *tm)
{
	tm->rule_gen = 0;
	tm->cfg_gen = 0;
}

/*
 * process_name - the process's name, read once per sample for all its
 * threads (a thousand threads of one process read it a thousand times)
 */
static void process_name(struct collector *c, const struct thread_model *tm, char *pcomm)
{
	struct collector_pname *p = &c->pnames[tm->tgid % COLLECTOR_PNAMES];
	char path[64], text[RTSUP_COMM_LEN + 1];

	if (p->tgid == tm->tgid && p->seq == c->sample_seq) {
		memcpy(pcomm, p->comm, RTSUP_COMM_LEN);
		return;
	}
	if (p->tgid != tm->tgid)
		procfile_close(&p->file);	/* another process's */
	snprintf(path, sizeof(path), "/proc/%u/task/%u/comm", tm->tgid, tm->tgid);
	if (procfile_read(&p->file, path, text, sizeof(text)) > 0) {
		text[strcspn(text, "\n")] = '\0';
		snprintf(pcomm, RTSUP_COMM_LEN, "%.*s", RTSUP_COMM_LEN - 1, text);
	} else {
		snprintf(pcomm, RTSUP_COMM_LEN, "%s", tm->comm);
	}
	comm_sanitize(pcomm, RTSUP_COMM_LEN);
	p->tgid = tm->tgid;
	p->seq = c->sample_seq;
	memcpy(p->comm, pcomm, RTSUP_COMM_LEN);
}

/*
 * sample_attrs - tm's attributes as last read, by the thread map's iterator
 * (threads_read_attrs) or the task iterator's walk, at this sample or at
 * one before and not moved since (thread_task_due, thread_walk_tasks);
 * NULL if none holds
 */
static const struct rtsup_task_attrs *sample_attrs(const struct collector *c,
						   const struct thread_model *tm)
{
	(void)c;
	return tm->attrs_seq && !tm->task_gone && !tm->attrs_stale ? &tm->attrs : NULL;
}

/* attrs_hold - a, just read of tm's task, is what tm holds: applied again if it moved */
static void attrs_hold(const struct collector *c, struct thread_model *tm,
		       const struct rtsup_task_attrs *a)
{
	tm->attrs_stale = false;
	if (memcmp(&tm->attrs, a, sizeof(*a))) {
		tm->attrs = *a;
		tm->attrs_applied = false;
	}
	tm->attrs_seq = c->sample_seq;
}

/*
 * note_task - what the thread map's iterator read of tm's task (record r,
 * attributes a), if it read it: attributes that moved are applied again
 */
static void note_task(const struct collector *c, struct thread_model *tm,
		      const struct rtsup_thread_rec *r, const struct rtsup_task_attrs *a)
{
	if (!r || r->task == THREAD_TASK_UNREAD)
		return;
	tm->task_gone = r->task == THREAD_TASK_GONE;
	if (a)
		attrs_hold(c, tm, a);
}

/*
 * note_walk - what this sample's walk of the task iterator found of tm's
 * task: its attributes, held until the next walk unless they move; none
 * (gone, or unreadable), and the kernel is asked for them
 */
static void note_walk(const struct collector *c, struct thread_model *tm)
{
	const struct rtsup_task_attrs *a = task_attrs_of(&c->attrs, tm->tid);

	if (a)
		attrs_hold(c, tm, a);
	else
		tm->attrs_seq = 0;
}

/*
 * attrs_kept - tm's policy, CPUs and cgroup are those of its attributes as
 * last read, which did not move since (nor did the CPUs online)
 */
static bool attrs_kept(const struct collector *c, const struct thread_model *tm)
{
	return tm->attrs_seq && tm->attrs_applied && !tm->task_gone && !tm->attrs_stale &&
	       !c->attrs.online_moved;
}

/*
 * attrs_from_iter - the sample's task iterator record of the thread: its
 * scheduling attributes, and its cgroup's path read again only when its
 * cgroup changed (a cgroup directory renamed in place keeps its id and its
 * old path here). False when there is none: the caller asks the kernel.
 */
static bool attrs_from_iter(struct collector *c, struct thread_model *tm, char *cg, size_t len)
{
	const struct rtsup_task_attrs *a = sample_attrs(c, tm);

	if (!a)
		return false;
	if (a->cgroup_id && a->cgroup_id == tm->cgroup_id)
		snprintf(cg, len, "%s", tm->cgroup);
	else
		read_cgroup(tm->tgid, tm->tid, cg, len);
	tm->cgroup_id = a->cgroup_id;
	tm->policy = a->policy;
	tm->prio = a->rt_priority;
	if (!task_attrs_cpus(&c->attrs, a, tm->cpus, sizeof(tm->cpus)))
		cpu_list(tm->tid, tm->cpus, sizeof(tm->cpus));
	tm->attrs_applied = a == &tm->attrs;
	return true;
}

/* identity_set - the process's name and the cgroup read: kept, the rules matched again */
static void identity_set(struct thread_model *tm, const char *pcomm, const char *cg)
{
	bool moved = false;

	if (strcmp(pcomm, tm->pcomm)) {
		snprintf(tm->pcomm, sizeof(tm->pcomm), "%s", pcomm);
		moved = true;
	}
	if (cg != tm->cgroup && strcmp(cg, tm->cgroup)) {
		snprintf(tm->cgroup, sizeof(tm->cgroup), "%s", cg);
		moved = true;
	}
	if (moved)
		rematch(tm);
}

/*
 * left_rt_after_sample - the policy hook let the thread go for leaving RT,
 * and the sample still says an RT policy: the task iterator read it before
 * the change, the thread map after (the rt-6.1 guest said "left RT (policy
 * SCHED_FIFO)" so once). Its attributes are asked of the kernel instead,
 * once: the entry is let go after it is reported.
 */
static bool left_rt_after_sample(const struct thread_model *tm)
{
	return (tm->cur.rt & RTSUP_RT_LEFT) && tm->policy >= 0 && rt_policy(tm->policy);
}

/* refresh_identity - names, cgroup and scheduling attributes of a live thread */
static void refresh_identity(struct collector *c, struct thread_model *tm)
{
	char pcomm[RTSUP_COMM_LEN], cg[sizeof(tm->cgroup)];
	struct sched_param sp;
	bool iter;

	if (!tm->pcomm[0])
		tm->kthread = thread_is_kernel(tm->tgid, tm->tid);
	process_name(c, tm, pcomm);
	/*
	 * Read at every sample, not copied by the hooks: a thread that changes
	 * its own policy while it runs would keep a stale copy for a while,
	 * and the policy check would raise an ERROR that is not true.
	 */
	if (attrs_kept(c, tm)) {
		identity_set(tm, pcomm, tm->cgroup);
		iter = true;
	} else {
		iter = attrs_from_iter(c, tm, cg, sizeof(cg));
		if (!iter)
			read_cgroup(tm->tgid, tm->tid, cg, sizeof(cg));
		identity_set(tm, pcomm, cg);
	}
	if (iter && !left_rt_after_sample(tm))
		return;
	c->attrs_asked++;	/* thread_walk_tasks: a storm of these takes a walk */
	tm->policy = sched_getscheduler(tm->tid);
	if (tm->policy < 0)
		return;
	tm->policy &= ~SCHED_RESET_ON_FORK;
	tm->prio = sched_getparam(tm->tid, &sp) ? 0 : sp.sched_priority;
	cpu_list(tm->tid, tm->cpus, sizeof(tm->cpus));
}

/* idle_in_window - not switched in or out in the interval just read */
static bool idle_in_window(const struct thread_model *tm)
{
	return model_win_empty(tm) || (!tm->win.vol_cs && !tm->win.invol_cs);
}

/*
 * thread_gone - the thread does not exist any more. The start-up scan can
 * find a thread already past its exit tracepoint: no exit event will mark
 * its entry, so an idle entry is checked against the kernel (see listed).
 */
static bool thread_gone(__u32 tgid, __u32 tid)
{
	return syscall(SYS_tgkill, tgid, tid, 0) < 0 && errno == ESRCH;
}

/*
 * rt_left_by_read - --rt without the policy hook (the loader fell back to
 * the per-switch read: cfg_rt_at_switch): the interval's policy read stands
 * in for the hook's let-go (rtfollow.h). A thread --rt alone follows whose
 * policy is no longer RT is marked as on_setsched marks it; a thread whose
 * process is a target is kept. collector_reap lets it go.
 */
static void rt_left_by_read(struct collector *c, struct thread_model *tm)
{
	__u32 tgid = tm->tgid, one;

	if (!c->skel->rodata->cfg_rt_at_switch || !tm->alive || tm->policy < 0 ||
	    rt_on_policy(tm->policy, &tm->cur) != RT_LET_GO)
		return;
	rt_mark_left(&tm->cur, !bpf_map_lookup_elem(bpf_map__fd(c->skel->maps.tgids), &tgid, &one));
}

/*
 * listed - the sample's task iterator found the thread: it was there after
 * the hooks were attached, so an exit since is marked by the exit hook,
 * and an idle thread needs no thread_gone syscall (900 parked threads made
 * 900 tgkill calls a second)
 */
static bool listed(const struct collector *c, const struct thread_model *tm)
{
	return sample_attrs(c, tm) != NULL;
}

/* seen_now - this sample's read of the thread map found tm's entry */
static bool seen_now(const struct collector *c, const struct thread_model *tm)
{
	return tm->seen_seq == c->sample_seq;
}

/* take_rest - after the model took t, the rest of the thread: names, life, attributes */
static void take_rest(struct collector *c, struct thread_model *tm, __u32 tid,
		      const struct rtsup_thread *t, const struct rtsup_thread_rec *r,
		      const struct rtsup_task_attrs *a)
{
	char comm[RTSUP_COMM_LEN];

	note_task(c, tm, r, a);
	if (c->attrs_walked)
		note_walk(c, tm);
	/* the snapshot the model holds (take_unchanged): its names were taken from it */
	if (t != &tm->cur) {
		tm->tgid = t->tgid;
		memcpy(comm, t->comm, RTSUP_COMM_LEN);
		comm[RTSUP_COMM_LEN - 1] = '\0';
		comm_sanitize(comm, RTSUP_COMM_LEN);
		if (strcmp(comm, tm->comm)) {
			memcpy(tm->comm, comm, RTSUP_COMM_LEN);
			rematch(tm);
		}
	}
	tm->seen_seq = c->sample_seq;
	tm->alive = !thread_dead(false, true, t->exited) &&
		    !(idle_in_window(tm) && !listed(c, tm) && thread_gone(t->tgid, tid));
	if (tm->alive)
		refresh_identity(c, tm);
	else
		tm->policy = -1;
	rt_left_by_read(c, tm);
}

/*
 * take - one thread's new kernel snapshot, a copy of its entry (short when
 * sent: threadmem_copy_short), into its model tm (NULL: none yet, made
 * here); the copy's reader fields zeroed first (thread_rec_normalize).
 * 1: a short copy the model cannot take (model_set_sent), nothing taken.
 */
static int take(struct collector *c, struct thread_model *tm, __u32 tid, struct rtsup_thread *t,
		bool sent, const struct rtsup_thread_rec *r, const struct rtsup_task_attrs *a)
{
	bool fresh;
	int moved;

	if (!tm)
		tm = model_get(&c->model, tid, true);
	thread_rec_normalize(t);
	if (!tm)
		return -ENOMEM;
	if (!tm->cur.first_seen)
		tm->rule = -1;
	/* a tid reused by a new thread starts a new model */
	if (tm->cur.first_seen && tm->cur.first_seen != t->first_seen) {
		model_remove(&c->model, tid);
		tm = model_get(&c->model, tid, true);
		if (!tm)
			return -ENOMEM;
	}
	fresh = !tm->cur.first_seen;
	/*
	 * its policy changed (thread_sched_seen): the attributes last read are
	 * not the task's, unless they are what its switch-out saw
	 */
	if (!fresh && t->setsched != tm->cur.setsched &&
	    !(tm->attrs_seq && thread_attrs_as_seen(t->sched_seen, &tm->attrs)))
		tm->attrs_stale = true;
	/* its unsafe_sys keys of another mode count now (read_unsafe_sys) */
	if (!fresh && cycle_sys_mode(&t->cs) != cycle_sys_mode(&tm->cur.cs))
		c->unsafe_sys_pending = true;
	moved = model_set_sent(tm, t, c->bank, sent);
	if (moved < 0) {
		c->map_short_refused++;
		return 1;
	}
	thread_copied(t->gen, &tm->read_seen, &tm->read_again);
	if (sent)
		c->map_short++;
	else
		c->map_copied++;
	if (moved && !fresh)
		c->map_moved++;	/* a first copy says nothing of the next (batch_read_cheaper) */
	take_rest(c, tm, tid, t, r, a);
	return 0;
}

/*
 * entry_kept - a read the thread map's iterator has no say in (a batch
 * read, a read of the named): is tid's entry at slot the one the model
 * holds? The iterator's rule (thread_copy_due), applied by userspace to
 * the model's own reader fields: its generation, read in place, did not
 * move since it was copied twice at it (threadread.h). Without the
 * iterator (kernels that refuse it), the whole read of every 8th sample
 * copied 900 parked threads' 6 KiB each. A tid taken again by a new
 * thread has another first_seen.
 */
static bool entry_kept(struct collector *c, struct thread_model *tm, __u32 tid, __u32 slot)
{
	__u32 gen, seen, again;
	__u64 first_seen;

	if (!tm || !tm->cur.first_seen || slot == THREAD_NO_SLOT ||
	    threadmem_gen(&c->mem, tid, slot, &gen, &first_seen) ||
	    first_seen != tm->cur.first_seen)
		return false;
	seen = tm->read_seen;
	again = tm->read_again;
	return !thread_copy_due(gen, &seen, &again);
}

/* take_unchanged is take_entry's too */
static int take_unchanged(struct collector *c, struct thread_model *tm, __u32 tid,
			  const struct rtsup_thread_rec *r, const struct rtsup_task_attrs *a);

/*
 * take_entry - take tid's entry at slot (THREAD_NO_SLOT: where the thread
 * map says) into its model tm (model_get's, NULL: none), a short copy when
 * the model can take one, else whole: 0, 1 when it has none (reaped since
 * it was named), or -errno. The caller looked tm up: a search less per
 * entry, three to four before.
 */
static int take_entry(struct collector *c, struct thread_model *tm, __u32 tid, __u32 slot,
		      const struct rtsup_thread_rec *r, const struct rtsup_task_attrs *a)
{
	int err;

	if (!r && entry_kept(c, tm, tid, slot))
		return take_unchanged(c, tm, tid, NULL, NULL);
	if (tm && model_takes_short(tm)) {
		if (threadmem_copy_short(&c->mem, tid, slot, c->entry))
			return 1;
		err = take(c, tm, tid, c->entry, true, r, a);
		if (err != 1)
			return err;
	}
	if (threadmem_copy(&c->mem, tid, slot, c->entry))
		return 1;
	return take(c, tm, tid, c->entry, false, r, a);
}

/*
 * take_unchanged - tid's entry did not change since it was last copied
 * (tm: its model, NULL if none): what take makes of the same bytes, without
 * them. An entry the model does not hold (it cannot be, but the kernel
 * decides) is read.
 */
static int take_unchanged(struct collector *c, struct thread_model *tm, __u32 tid,
			  const struct rtsup_thread_rec *r, const struct rtsup_task_attrs *a)
{
	if (!tm || !tm->cur.first_seen) {
		int err = take_entry(c, tm, tid, THREAD_NO_SLOT, r, a);

		return err > 0 ? 0 : err;	/* gone since: as if never read */
	}
	model_idle(tm);
	take_rest(c, tm, tid, &tm->cur, r, a);
	return 0;
}

/* rec_whole - the record at p + off, in *r, is whole within len (with its followers) */
static bool rec_whole(const char *p, size_t off, size_t len, struct rtsup_thread_rec *r)
{
	if (off + sizeof(*r) > len)
		return false;
	memcpy(r, p + off, sizeof(*r));
	return off + thread_rec_len(r) <= len;
}

/* rec_attrs - the attributes that follow record r at p, NULL if none */
static const struct rtsup_task_attrs *rec_attrs(const struct rtsup_thread_rec *r,
						const char *p)
{
	return r->task == THREAD_TASK_ATTRS ? (const void *)(p + sizeof(*r)) : NULL;
}

/*
 * take_recs - the whole records at the front of one read of the thread
 * map's iterator; returns the bytes they fill. A record seen twice in one
 * read (an entry added to the hash bucket being read moves the others by
 * one) is taken once.
 */
static long take_recs(void *ctx, char *p, size_t len)
{
	struct collector *c = ctx;
	const struct rtsup_task_attrs *a;
	struct rtsup_thread_rec r;
	struct thread_model *tm;
	size_t off = 0;
	int err;

	for (; rec_whole(p, off, len, &r); off += thread_rec_len(&r)) {
		tm = model_get(&c->model, r.tid, false);
		if (tm && seen_now(c, tm))
			continue;
		c->map_entries++;
		/* records of 8-byte multiples from the buffer's front: aligned */
		a = rec_attrs(&r, p + off);
		c->map_tasks += a != NULL;
		/* take_entry's 1: reaped since, as if never read */
		err = r.full ? take_entry(c, tm, r.tid, r.slot, &r, a)
			     : take_unchanged(c, tm, r.tid, &r, a);
		if (err < 0)
			return err;
	}
	return (long)off;
}

/*
 * take_tasks - the records of the pass that only reads the tasks, before a
 * batch read of the entries: their attributes kept for take_rest. A thread
 * the model does not hold yet is asked of the kernel as before.
 */
static long take_tasks(void *ctx, char *p, size_t len)
{
	struct collector *c = ctx;
	const struct rtsup_task_attrs *a;
	struct rtsup_thread_rec r;
	struct thread_model *tm;
	size_t off = 0;

	for (; rec_whole(p, off, len, &r); off += thread_rec_len(&r)) {
		tm = model_get(&c->model, r.tid, false);
		a = rec_attrs(&r, p + off);
		c->map_tasks += a != NULL;
		if (tm)
			note_task(c, tm, &r, a);
	}
	return (long)off;
}

/* threads_link - the thread map's iterator attached, NULL if none */
static struct bpf_link *threads_link(const struct collector *c)
{
	return c->tasks ? c->tasks->links.threads_read_attrs : c->skel->links.threads_read;
}

/*
 * read_tasks - the thread map's iterator copies no entry, only reads their
 * tasks (a batch read copies the entries next)
 */
static int read_tasks(struct collector *c)
{
	int err;

	c->tasks->bss->threads_read_tasks_only = 1;
	err = iter_read_each(&c->threads_out, bpf_link__fd(threads_link(c)), take_tasks, c);
	c->tasks->bss->threads_read_tasks_only = 0;
	return err;
}

/*
 * read_changed - the thread map through its iterator (threadread.h): a
 * record per entry that changed (the entry itself after it) or whose task
 * it read, taken read by read (the buffer holds a read, not all 7 MiB of
 * 1000 changed entries); the others are kept as they were (take_kept)
 */
static int read_changed(struct collector *c)
{
	return iter_read_each(&c->threads_out, bpf_link__fd(threads_link(c)), take_recs, c);
}

/*
 * take_kept - the threads the thread map's iterator sent nothing for
 * (thread_rec_skipped): their entries did not change, their tasks were not
 * read. Entries leave the map only by collector_reap, which marks their
 * threads reported_exit first: any other thread the model holds is in the
 * map still, as it was.
 */
static int take_kept(struct collector *c)
{
	struct thread_model *tm;
	int i, err;

	for (i = 0; i < c->model.n; i++) {
		tm = c->model.t[i];
		if (i + 1 < c->model.n)
			model_prefetch_kept(c->model.t[i + 1]);
		if (seen_now(c, tm) || tm->reported_exit)
			continue;
		c->map_entries++;
		err = take_unchanged(c, tm, tm->tid, NULL, NULL);
		if (err)
			return err;
	}
	return 0;
}

/* read_one_by_one - the thread map without batch operations (kernels < 5.6) */
static int read_one_by_one(struct collector *c, int fd)
{
	__u32 key, next, *prev = NULL;

	while (!bpf_map_get_next_key(fd, prev, &next)) {
		key = next;
		prev = &key;
		c->map_entries++;
		/* take_entry's 1: deleted since its key was read, like a key never read */
		if (take_entry(c, model_get(&c->model, key, false), key, THREAD_NO_SLOT,
			       NULL, NULL) < 0)
			return -ENOMEM;
	}
	/* ENOENT: past the last key; anything else: the read stopped half-way */
	return errno == ENOENT ? 0 : -errno;
}

/* grow_batch - twice the entries per read */
static int grow_batch(struct collector *c)
{
	__u32 cap = c->batch_cap * 2;
	__u32 *k = realloc(c->batch_keys, cap * sizeof(*k)), *v;
	struct rtsup_moved_rec *at;

	if (!k)
		return -1;
	c->batch_keys = k;
	v = realloc(c->batch_slots, cap * sizeof(*v));
	if (!v)
		return -1;
	c->batch_slots = v;
	at = realloc(c->batch_at, cap * sizeof(*at));
	if (!at)
		return -1;
	c->batch_at = at;
	c->batch_cap = cap;
	return 0;
}

/*
 * batch_read_cheaper - most entries moved at the last sample: their copies
 * through the iterator's 32 KiB reads cost more syscalls than batches of
 * 64 (1000 threads all at 10 Hz: +8 % of the loop's CPU), and the batches
 * copy the few that did not move too. The iterator's own fields stay
 * right across batch reads: it skips only an entry whose generation did
 * not move since its own last copy, older than the batch's. Moved means
 * since an earlier copy: at start-up every entry is new, and a batch read
 * at the second sample left the iterator's second copies to the third
 * (900 parked threads: three full reads instead of two, 2.4 ms a second
 * for two seconds).
 */
static bool batch_read_cheaper(const struct collector *c)
{
	return c->map_entries >= 256 && c->map_moved * 4 >= c->map_entries * 3;
}

/*
 * The entries a read takes, asked of the memory ahead (read_ahead): 1000
 * running threads' models and entries are out of the cache by the next
 * interval, and a take waited for each of its misses in turn. Two steps:
 * the first lines of the thread after next (its model's, its entry's:
 * where its buckets moved is in them), then the buckets of the next.
 */
struct ahead {
	struct thread_model *tm;
	const struct rtsup_thread *t;	/* its entry in place, NULL: none */
};

/* ahead_first - the first step for tid's entry at slot */
static struct ahead ahead_first(struct collector *c, __u32 tid, __u32 slot)
{
	struct ahead a = { model_get(&c->model, tid, false), threadmem_at(&c->mem, slot) };

	model_prefetch(a.tm);
	threadmem_prefetch(&c->mem, slot);
	return a;
}

/* ahead_next - the second step: its buckets (model_prefetch_spans) */
static void ahead_next(const struct ahead *a)
{
	if (a->t)
		model_prefetch_spans(a->tm, a->t);
}

/*
 * read_ahead - before taking entry i of n, the steps for i + 1 and i + 2
 * (at[k]: entry k's tid and slot); next holds i + 1's first step, and
 * i + 2's after
 */
static void read_ahead(struct collector *c, const struct rtsup_moved_rec *at, __u32 i, __u32 n,
		       struct ahead *next)
{
	struct ahead after = { NULL, NULL };

	if (i == 0 && n > 1)
		*next = ahead_first(c, at[1].tid, at[1].slot);
	if (i + 2 < n)
		after = ahead_first(c, at[i + 2].tid, at[i + 2].slot);
	if (i + 1 < n)
		ahead_next(next);
	*next = after;
}

/*
 * read_whole - the whole thread map, through its iterator or batch_cap
 * entries per syscall (batch: batch_read_cheaper, asked before the read's
 * counts were reset)
 */
static int read_whole(struct collector *c, bool batch)
{
	int fd = bpf_map__fd(c->skel->maps.threads), err;
	struct ahead next = { NULL, NULL };
	__u64 in = 0, out = 0;
	__u32 n, i, tid;
	bool first = true;

	c->map_batch = batch || !threads_link(c);
	if (!c->map_batch) {
		err = read_changed(c);
		return err ?: take_kept(c);
	}
	/*
	 * the tasks' attributes first: no task iterator runs (a failure: asked
	 * per thread), unless this read reads none (thread_read_tasks)
	 */
	if (c->tasks && c->tasks->bss->threads_read_tasks != THREAD_TASKS_NONE)
		read_tasks(c);
	if (c->no_batch)
		return read_one_by_one(c, fd);
	do {
		n = c->batch_cap;
		err = bpf_map_lookup_batch(fd, first ? NULL : &in, &out, c->batch_keys,
					   c->batch_slots, &n, NULL);
		if (err && errno == ENOSPC && !n) {
			/* one hash bucket holds more than the buffer: grow it, retry */
			if (grow_batch(c))
				return -ENOMEM;
			continue;
		}
		if (err && errno != ENOENT) {
			if (first && map_batch_unsupported(errno)) {
				c->no_batch = true;
				return read_one_by_one(c, fd);
			}
			return -errno;
		}
		for (i = 0; i < n; i++) {
			c->batch_at[i].tid = c->batch_keys[i];
			c->batch_at[i].slot = c->batch_slots[i];
		}
		for (i = 0; i < n; i++) {
			c->map_entries++;
			read_ahead(c, c->batch_at, i, n, &next);
			tid = c->batch_keys[i];
			if (take_entry(c, model_get(&c->model, tid, false), tid,
				       c->batch_slots[i], NULL, NULL) < 0)
				return -ENOMEM;
		}
		in = out;
		first = false;
	} while (!err);
	return 0;
}

/*
 * read_named - only the entries the ring named (movedset.h), a lookup
 * each; the others did not change and are kept (take_kept). A tid named
 * twice is taken once; one with no entry was reaped after it was named.
 */
static int read_named(struct collector *c)
{
	const struct tid_list *l[] = { &c->moved.now, &c->moved.again };
	struct thread_model *tm;
	__u32 i, k, tid;
	int err;

	for (k = 0; k < 2; k++) {
		const struct rtsup_moved_rec *at = l[k]->at;
		struct ahead next = { NULL, NULL };

		for (i = 0; i < l[k]->n; i++) {
			tid = at[i].tid;
			read_ahead(c, at, i, l[k]->n, &next);
			tm = model_get(&c->model, tid, false);
			if (tm && seen_now(c, tm))
				continue;
			c->map_visited++;
			err = take_entry(c, tm, tid, l[k]->at[i].slot, NULL, NULL);
			if (err < 0)
				return err;
			c->map_entries += !err;	/* 1: reaped since it was named */
		}
	}
	return take_kept(c);
}

/*
 * read_threads - the entries the ring named, or the whole thread map
 * (thread_read_whole): through its iterator, or batch_cap entries per syscall
 */
static int read_threads(struct collector *c, bool forced)
{
	bool named = c->moved.rb != NULL;
	/* the last read's counts decide, before they are reset */
	bool batch = batch_read_cheaper(c);
	int err;

	c->map_entries = c->map_copied = c->map_moved = c->map_visited = c->map_tasks = 0;
	c->map_short = c->map_short_refused = 0;
	c->map_batch = false;
	c->map_whole = thread_read_whole(named, c->sample_seq, forced,
					 movedset_due(&c->moved), (__u32)c->model.n);
	if (c->tasks)
		c->tasks->bss->threads_read_tasks = thread_read_tasks(named, c->sample_seq, forced);
	err = c->map_whole ? read_whole(c, batch) : read_named(c);
	if (c->map_whole)
		c->map_visited = c->map_entries;
	if (named)
		movedset_end(&c->moved);
	return err;
}

/*
 * An interval, as collector_sample reads it: epoch_flip ends it in the
 * kernel (rtsup.h, "Interval windows"); the thread map read marks those
 * it finds with the sample (seen_seq; take: the snapshot difference, and
 * alive from the entry), and those it did not
 * find get an empty interval and are dead only after a complete read
 * (mark_absent).
 */

/*
 * epoch_flip - the interval ends, at one instant: the clock read and its
 * min/max bank no longer written. Every "how long ago" of the checks is
 * taken from end_ns, read before the maps: a reader held up while or after
 * it reads them (an emulated guest, a busy CPU) cannot make a thread look
 * starved; a stamp newer than end_ns is 0 ns old (since.h).
 */
static void epoch_flip(struct collector *c)
{
	c->end_ns = mono_now();
	c->bank = RTSUP_BANK(c->skel->bss->epoch);
	c->skel->bss->epoch++;
}

/*
 * mark_absent - after the read: a thread not in the map any more had an
 * empty interval (one read sets the interval of each it found), and is
 * dead only if the whole map was read
 */
static void mark_absent(struct collector *c, bool read_complete)
{
	struct model *m = &c->model;
	int i;

	for (i = 0; i < m->n; i++) {
		if (seen_now(c, m->t[i]))
			continue;
		model_idle(m->t[i]);
		if (thread_dead(read_complete, false, false))
			m->t[i]->alive = false;
	}
}

/*
 * read_begin - the sample's read begins (movedset_begin: threads_moved_seq
 * moves, the ring is drained); must it see every entry and task? A tid the
 * ring named that could not be kept (out of memory), then the hooks' flags,
 * taken after the begin so that a send the ring refused before it makes
 * this read whole: a send refused (the ring full), a task that changed
 * cgroups
 */
static bool read_begin(struct collector *c)
{
	bool named = c->moved.rb != NULL;
	bool lost = named && movedset_begin(&c->moved, &c->skel->bss->threads_moved_seq);

	return lost |
	       (__atomic_exchange_n(&c->skel->bss->threads_moved_lost, 0, __ATOMIC_RELAXED) |
		__atomic_exchange_n(&c->skel->bss->threads_attrs_moved, 0, __ATOMIC_RELAXED));
}

/*
 * walk_tasks - the task iterator's walk of every task, when this sample
 * takes it (thread_walk_tasks): the attributes of the targets it finds
 * are held until the next (note_walk)
 */
static void walk_tasks(struct collector *c, bool forced)
{
	c->attrs_walked = false;
	c->attrs_asked_last = c->attrs_asked;
	c->attrs_asked = 0;
	if (!c->skel->links.attrs_task ||
	    !thread_walk_tasks(c->moved.rb != NULL, c->sample_seq, forced, c->attrs_asked_last))
		return;
	/* a failed walk: none found, every thread asked of the kernel */
	if (task_attrs_read(&c->attrs, bpf_link__fd(c->skel->links.attrs_task)))
		c->attrs.n = 0;
	c->attrs_walked = true;
}

int collector_sample(struct collector *c)
{
	bool forced;
	int err;

	epoch_flip(c);
	update_clocks(c, false);
	c->sample_seq++;	/* process names are read again */
	if (c->tasks)
		c->tasks->bss->threads_read_seq = (__u32)c->sample_seq;
	collector_poll(c, 0);
	/* what came in the interval (the poll above was its last), in time order */
	eventlog_finish(&c->events);
	causes_sort(&c->causes_win);
	causes_sort(&c->causes_life);
	forced = read_begin(c);
	/* every target's attributes in one walk; without it, asked thread by thread */
	walk_tasks(c, forced);
	/* or the thread map's iterator reads them (take_rest); the CPUs online still */
	if (c->tasks || (c->skel->links.attrs_task && !c->attrs_walked))
		task_attrs_online(&c->attrs);
	err = read_threads(c, forced);
	if (err)
		fprintf(stderr, "rtsup-trace: reading the thread map: %s\n", strerror(-err));
	model_sort(&c->model);	/* the reports list threads by tid */
	mark_absent(c, !err);
	read_unsafe_sys(c);
	read_counters(c);
	read_stack_counters(c);
	/* the checks name each thread's top cause: every thread is in the model now */
	causes_to_model(&c->causes_win, &c->causes_life, &c->model);
	return err;
}

static int cmp_tid(const void *a, const void *b)
{
	__u32 x = *(const __u32 *)a, y = *(const __u32 *)b;

	return x < y ? -1 : x > y;
}

/* the dead threads' tids, sorted, for the prunes of collector_reap */
struct tid_set {
	const __u32 *tids;
	int n;
};

static bool sys_of_dead(const void *key, const void *value, void *ctx)
{
	const struct rtsup_sys_key *k = key;
	const struct tid_set *d = ctx;

	(void)value;
	return bsearch(&k->tid, d->tids, d->n, sizeof(*d->tids), cmp_tid);
}

/*
 * forget_sys - drop the unsafe syscall entries of the dead threads tids[n]
 * (sorted) in one pass over the map: a pass per thread cost a storm of
 * 4096 dead threads 4096 walks of the whole map, seconds per interval
 */
static void forget_sys(struct collector *c, const __u32 *tids, int n)
{
	struct tid_set d = { tids, n };

	if (n)
		map_prune(bpf_map__fd(c->skel->maps.unsafe_sys), sizeof(struct rtsup_sys_key),
			  sizeof(__u64), sys_of_dead, &d);
}

/* same_thread - does the kernel entry of tm's tid still belong to tm's thread? */
static bool same_thread(struct collector *c, const struct thread_model *tm)
{
	if (threadmem_copy(&c->mem, tm->tid, THREAD_NO_SLOT, c->entry))
		return true;	/* gone already: deleting it again does no harm */
	return c->entry->first_seen == tm->cur.first_seen;
}

/* untracked_gone - an untracked thread (key: tid, value: tgid) that is gone */
static bool untracked_gone(const void *key, const void *value, void *ctx)
{
	(void)ctx;
	return thread_gone(*(const __u32 *)value, *(const __u32 *)key);
}

static bool process_gone(const void *key, const void *value, void *ctx)
{
	(void)value;
	(void)ctx;
	return !process_exists(*(const __u32 *)key);
}

/*
 * tid_release - a tid whose entry is gone: its wakemask bit is set (always
 * safe, rtsup.h), so its switch-ins are looked up, not held. A clear one
 * (a let-go thread in delimiter mode, an exited one) held every switch-in
 * of whoever has the tid for good, and --rt's per-switch policy read
 * (rt_at_switch) never saw a thread come back to RT, or a new thread with
 * the tid become RT. Costs one failed lookup per switch-in of that thread.
 */
static void tid_release(struct collector *c, __u32 tid)
{
	if (c->skel->rodata->cfg_rt_at_switch)
		tid_bit_set(c->skel->bss->wakemask, tid);
}

/*
 * untracked_ever - a thread was ever untracked (the map full): the count
 * moves with every entry written to 'untracked' (kernel and start-up scan),
 * so without one that map is empty and its walk is skipped (a batch read
 * walks all of its 16384 buckets: a tenth of a small run's loop)
 */
static bool untracked_ever(const struct collector *c)
{
	return c->counters[RTSUP_C_MAP_FULL] != 0;
}

/*
 * processes_due - are the target processes checked for being gone? When a
 * thread was let go this sample (a process ends with its threads, and each
 * tracked thread's end is reported), when a thread was untracked (its
 * end is not), and every THREAD_TASK_EVERY-th sample as a net: a pid is
 * reused after the kernel went through every other one.
 */
static bool processes_due(const struct collector *c, int nlet)
{
	return nlet || untracked_ever(c) || c->sample_seq % THREAD_TASK_EVERY == 0;
}

void collector_reap(struct collector *c)
{
	__u32 *dead = malloc((c->model.n ? c->model.n : 1) * sizeof(*dead));
	int i, j, ndead = 0, nlet = 0;

	for (i = 0; i < c->model.n; i++) {
		struct thread_model *tm = c->model.t[i];

		for (j = 0; j < tm->nsys; j++)
			tm->sys[j].prev = tm->sys[j].total;
		if ((tm->alive && !(tm->cur.rt & RTSUP_RT_LEFT)) || tm->reported_exit)
			continue;
		/*
		 * reported once: the kernel entry is freed, the model keeps the
		 * numbers; so is a thread that left RT under --rt (rtfollow.h)
		 */
		tm->reported_exit = true;
		nlet++;
		if (!same_thread(c, tm))
			continue;	/* a new thread has the tid already (add_thread) */
		threadmem_remove(&c->mem, tm->tid);
		tid_release(c, tm->tid);
		/* only if written: a storm's threads, dead before, cost no syscall */
		if (tm->cfg_in_kernel) {
			bpf_map_delete_elem(bpf_map__fd(c->skel->maps.thread_cfg), &tm->tid);
			bpf_map_delete_elem(bpf_map__fd(c->skel->maps.stack_cfg), &tm->tid);
		}
		if (dead)
			dead[ndead++] = tm->tid;
		else
			forget_sys(c, &tm->tid, 1);	/* no memory: one pass each */
	}
	if (dead)
		qsort(dead, ndead, sizeof(*dead), cmp_tid);
	forget_sys(c, dead, ndead);
	free(dead);
	model_prune_dead(&c->model, MODEL_KEEP_DEAD);
	/* threads not tracked that are gone: their tid may come back */
	if (untracked_ever(c))
		map_prune(bpf_map__fd(c->skel->maps.untracked), sizeof(__u32), sizeof(__u32),
			  untracked_gone, NULL);
	if (!processes_due(c, nlet))
		return;
	/* processes that are gone must not match a reused pid */
	map_prune(bpf_map__fd(c->skel->maps.tgids), sizeof(__u32), sizeof(__u32), process_gone,
		  NULL);
	/* and auto's verdicts with them (the unwinder keeps its own) */
	if (c->o->stack_auto)
		map_prune(bpf_map__fd(c->skel->maps.stack_auto), sizeof(__u32), sizeof(__u32),
			  process_gone, NULL);
}

/* syscall_list - names to numbers for the kernel; unknown names were rejected at load */
static __u32 syscall_list(__u16 *out, __u32 max, char names[][32], int n)
{
	__u32 k = 0;
	int i, nr;

	for (i = 0; i < n && k < max; i++)
		if ((nr = syscall_nr(names[i])) >= 0)
			out[k++] = nr;
	return k;
}

/*
 * stack_cfg_apply - a rule's stacks: for its thread, in map stack_cfg when
 * they are not what the kernel side was loaded with (stackcfg.h)
 */
static void stack_cfg_apply(struct collector *c, const struct thread_model *tm,
			    const struct rule *r)
{
	const struct options *o = c->o;
	struct rtsup_stack_cfg sc = { .kind = r->stacks, .size = r->stack_size };
	int fd = bpf_map__fd(c->skel->maps.stack_cfg);

	if (!o->stack_rules)
		return;
	if (sc.kind == o->stacks && sc.size == o->stack_size)
		bpf_map_delete_elem(fd, &tm->tid);
	else
		bpf_map_update_elem(fd, &tm->tid, &sc, BPF_ANY);
}

void collector_apply_rules(struct collector *c, const struct supervisor *s)
{
	int fd = bpf_map__fd(c->skel->maps.thread_cfg), i;

	for (i = 0; i < c->model.n; i++) {
		struct thread_model *tm = c->model.t[i];
		const struct rule *r;
		struct rtsup_thread_cfg tc = {};

		if (!tm->alive || tm->cfg_gen == s->gen || tm->rule_gen != s->gen)
			continue;
		r = supervise_rule(s, tm);
		tc.period = r->period_ns;
		tc.warmup = r->warmup_ns;
		tc.ewma_w = (__u32)(r->ewma_weight * RTSUP_EWMA_ONE + 0.5);
		tc.ndelims = syscall_list(tc.delims, RTSUP_CFG_DELIMS, (char (*)[32])r->delims,
					  r->ndelims);
		tc.nallow = syscall_list(tc.allow, RTSUP_CFG_SYSCALLS, (char (*)[32])r->allow,
					 r->nallow);
		tc.nforbid = syscall_list(tc.forbid, RTSUP_CFG_SYSCALLS, (char (*)[32])r->forbid,
					  r->nforbid);
		tm->cfg_in_kernel = true;
		stack_cfg_apply(c, tm, r);
		/* the hooks look thread_cfg up only from now on */
		c->skel->bss->thread_cfg_used = 1;
		if (!bpf_map_update_elem(fd, &tm->tid, &tc, BPF_ANY))
			tm->cfg_gen = s->gen;
	}
}

void collector_clear_events(struct collector *c)
{
	eventlog_clear(&c->events);
	stackagg_interval_end(&c->stacks);
	causes_clear(&c->causes_win);
}

void collector_free(struct collector *c)
{
	int i;

	for (i = 0; i < COLLECTOR_PNAMES; i++)
		procfile_close(&c->pnames[i].file);
	if (c->rb && c->epfd >= 0) {
		close(c->epfd);
		close(c->clock_fd);
	}
	ring_buffer__free(c->rb);
	ring_buffer__free(c->stack_rb);
	unwinder_free(c->unwinder);
	stackagg_free(&c->stacks);
	eventlog_free(&c->events);
	causes_free(&c->causes_win);
	causes_free(&c->causes_life);
	model_free(&c->model);
	free(c->batch_keys);
	free(c->batch_slots);
	free(c->batch_at);
	free(c->entry);
	threadmem_close(&c->mem);
	iter_buf_free(&c->threads_out);
	task_attrs_free(&c->attrs);
	movedset_free(&c->moved);
}
