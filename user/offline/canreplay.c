// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * canreplay.c - account every frame of a candump log like the kernel does,
 * judge the buses at each interval of log time, report like a live run.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include "can.h"
#include "offline/candump.h"
#include "offline/canreplay.h"
#include "collect/collector.h"
#include "sinks/output.h"
#include "sinks/progress.h"

struct can_replay {
	struct collector c;	/* what the outputs read: no threads here */
	struct can_model m;
	struct supervisor *s;
	const struct options *o;
	__u32 epoch;
	__u64 start, last, next, step;
	__u64 now;		/* log time of the last frame */
	__u64 shift;		/* clock steps taken out of the log's time so far */
	__u64 last_jump;	/* the clock step frame() just took out, for its note */
	struct progress pg;	/* on stderr, cleared before each report */
};

/*
 * A jump forward by more than this many intervals with no frame is a clock
 * step (a robot that boots in 1970 until NTP sets the clock), not silence:
 * one silent interval per second of it would never end.
 */
#define CAN_REPLAY_MAX_SILENT 1000

/* clock_step - the log time ts jumps this far past the next boundary, 0 if not a step */
static __u64 clock_step(const struct can_replay *r, __u64 ts)
{
	return ts > r->next && (ts - r->next) / r->step > CAN_REPLAY_MAX_SILENT ?
	       ts - r->now : 0;
}

/* iface_index - interfaces are numbered in order of appearance */
static __u32 iface_index(struct can_replay *r, const char *name)
{
	struct can_iface *f;
	int i;

	for (i = 0; i < r->m.nifs; i++)
		if (!strcmp(r->m.ifs[i].name, name))
			return r->m.ifs[i].ifindex;
	f = can_iface_get(&r->m, 0, r->m.nifs + 1, true);
	if (!f)
		return 0;
	/* a log's name longer than an interface name can be is cut to fit */
	snprintf(f->name, sizeof(f->name), "%.*s", (int)sizeof(f->name) - 1, name);
	f->bitrate = r->o->can_bitrate ? r->o->can_bitrate : r->s->cfg.can.bitrate;
	return f->ifindex;
}

/* interval - an interval of log time ended at 'at': judge and report it */
static void interval(struct can_replay *r, __u64 at, bool end)
{
	struct self_in self = { .overhead_pct = -1, .th = &r->s->cfg.defaults.th,
				.loop = SELF_SPAN_UNKNOWN, .loop_run = SELF_SPAN_UNKNOWN };
	double len = (at - r->last) / 1e9;

	r->m.bank = RTSUP_BANK(r->epoch);
	r->epoch++;
	r->c.bank = r->m.bank;
	supervise_interval(r->s, &r->c.model, r->c.bank, &self, at);
	supervise_can(r->s, at, len);
	progress_end(&r->pg);
	output_interval(&r->c, r->s, (at - r->start) / 1e9, len);
	if (end) {
		output_summary(&r->c, r->s, (at - r->start) / 1e9);
		return;
	}
	can_model_next(&r->m);
	r->last = at;
}

/*
 * frame - one logged frame, accounted as the kernel accounts it: 0, or -1
 * when the time goes backwards, or 1 for a clock step (r->last_jump; call
 * again for the same frame on the new time)
 */
static int frame(struct can_replay *r, const struct candump_frame *in)
{
	struct rtsup_can_key key = { .dir = in->dir == RTSUP_CAN_TX ? RTSUP_CAN_TX : RTSUP_CAN_RX };
	__u32 ewma_w = (__u32)(r->s->cfg.defaults.ewma_weight * RTSUP_EWMA_ONE + 0.5);
	struct candump_frame shifted = *in;
	const struct candump_frame *f = &shifted;
	struct can_iface *ifs;
	struct can_entry *e;
	__u64 jump;

	shifted.ts_ns -= r->shift;
	if (!r->start) {
		r->start = r->last = f->ts_ns;
		r->next = f->ts_ns + r->step;
		r->m.start_ns = f->ts_ns;
	}
	if (f->ts_ns < r->now)
		return -1;	/* time goes backwards: not one log */
	jump = r->start ? clock_step(r, f->ts_ns) : 0;
	if (jump) {
		/* the log goes on as if the clock had not stepped; said once per step */
		r->shift += jump;
		r->last_jump = jump;
		return 1;
	}
	/* every interval boundary the log passed, even silent ones */
	while (f->ts_ns >= r->next) {
		interval(r, r->next, false);
		r->next += r->step;
	}
	r->now = f->ts_ns;
	key.ifindex = iface_index(r, f->iface);
	ifs = can_iface_get(&r->m, 0, key.ifindex, false);
	if (!ifs)
		return 0;
	can_if_account(&ifs->cur, f->ts_ns, key.dir, f->can_id, f->len, f->kind, f->data);
	if (f->can_id & RTSUP_CAN_ERR_FLAG)
		return 0;
	key.can_id = can_key_id(f->can_id);
	e = can_entry_get(&r->m, &key, true);
	if (!e)
		return 0;
	if (r->s->cfg.can.canopen && can_is_sdo_response(key.can_id)) {
		struct rtsup_can_key rk = { .ifindex = key.ifindex, .can_id = key.can_id + 0x80 };
		struct can_entry *req;

		for (rk.dir = 0; rk.dir < RTSUP_CAN_DIRS; rk.dir++) {
			req = can_entry_get(&r->m, &rk, false);
			if (req && can_sdo_match(&e->cur, &req->cur, f->ts_ns))
				break;
		}
		e = can_entry_get(&r->m, &key, false);	/* no insert happened */
	}
	can_id_account(&e->cur, f->ts_ns, f->can_id, f->len, f->data, ewma_w, r->epoch);
	return 0;
}

int can_replay_run(const struct options *o, struct supervisor *s)
{
	struct can_replay r;
	struct candump_frame f;
	char line[1024], err[256];
	size_t lineno = 0;
	struct stat st;
	FILE *in;
	int ret = 1, n;
	bool parsed;

	memset(&r, 0, sizeof(r));
	r.s = s;
	r.o = o;
	r.c.o = o;
	r.step = (__u64)(o->interval * 1e9);
	s->can = &r.m;
	in = fopen(o->can_replay_path, "re");
	if (!in) {
		snprintf(err, sizeof(err), "%s: %s", o->can_replay_path, strerror(errno));
		output_error(o, err);
		goto out;
	}
	progress_start(&r.pg, stderr,
		       !fstat(fileno(in), &st) && S_ISREG(st.st_mode) ? (__u64)st.st_size : 0,
		       !o->quiet && isatty(STDERR_FILENO));
	while (fgets(line, sizeof(line), in)) {
		lineno++;
		if (progress_due(&r.pg))
			progress_draw(&r.pg, (__u64)ftell(in));
		if (!strchr(line, '\n') && !feof(in)) {
			progress_end(&r.pg);
			snprintf(err, sizeof(err), "%s:%zu: line too long", o->can_replay_path, lineno);
			output_error(o, err);
			goto out;
		}
		n = candump_parse(line, &f, err, sizeof(err));
		if (n == 0)
			continue;
		parsed = n > 0;
		if (parsed && (n = frame(&r, &f)) == 1) {
			/* a clock step: a note, and the frame is taken on the new time */
			progress_end(&r.pg);
			fprintf(stderr, "rtsup-trace: %s:%zu: the log's time jumps forward by %.0f s "
				"(a clock step?): replay goes on as if it had not\n",
				o->can_replay_path, lineno, r.last_jump / 1e9);
			n = frame(&r, &f);
		}
		if (n < 0) {
			char msg[512];

			progress_end(&r.pg);
			snprintf(msg, sizeof(msg), "%s:%zu: %s", o->can_replay_path, lineno,
				 parsed ? "timestamp goes backwards" : err);
			output_error(o, msg);
			goto out;
		}
	}
	progress_end(&r.pg);
	if (ferror(in)) {
		snprintf(err, sizeof(err), "%s: read error", o->can_replay_path);
		output_error(o, err);
		goto out;
	}
	if (!r.start) {
		snprintf(err, sizeof(err), "%s: no CAN frames in it", o->can_replay_path);
		output_error(o, err);
		goto out;
	}
	/* the log's last frame ends the last, partial interval */
	interval(&r, r.now, true);
	ret = 0;
	if (o->check && level_fails(supervise_worst(s, &r.c.model), o->fail_on))
		ret = 2;
out:
	progress_end(&r.pg);
	if (in)
		fclose(in);
	can_model_free(&r.m);
	collector_free(&r.c);
	s->can = NULL;
	return ret;
}
