// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* robot.c - systemd, journal, Prometheus, /diagnostics and --unit around the live loop */
#include <stdio.h>
#include <string.h>
#include "robot/robot.h"
#include "collect/since.h"

int robot_prepare(struct robot *r, const struct options *o, struct supervisor *s)
{
	memset(r, 0, sizeof(*r));
	r->o = o;
	r->unit.fd = -1;
	service_init(&r->sv);
	if (r->sv.journal)
		s->log = service_journal_log;
	if (o->unit)
		unit_init(&r->unit, o->unit);
	/* a taken port fails here, before any BPF is loaded */
	return promexp_open(&r->pe, o->prom_textfile, o->listen);
}

/* render - the exposition of now, to the exporters */
static void render(struct robot *r, struct collector *c, const struct supervisor *s,
		   __u64 now)
{
	struct prom_in in = {
		.m = &c->model,
		.s = s,
		.counters = c->counters,
		.bank = c->bank,
		.map_entries = c->map_entries,
		.map_capacity = r->o->max_threads,
		.forgotten = c->model.forgotten,
		.elapsed = ns_since(now, c->start_ns) / 1e9,
	};

	if (!r->o->prom_textfile && !r->o->listen)
		return;
	if (!prom_render(&in, &r->buf))
		promexp_update(&r->pe, r->buf.p, r->buf.len);
}

int robot_start(struct robot *r, struct collector *c, const struct supervisor *s)
{
	char line[256];

	if (r->o->unit) {
		unit_check(&r->unit, c);
		if (!r->unit.path[0])
			fprintf(stderr, "rtsup-trace: --unit %s: not running; waiting for it\n",
				r->unit.name);
	}
	/* read at the start only: a SIGHUP reload does not switch it */
	if ((r->o->ros2_diag || s->cfg.ros2_diagnostics) && ros2diag_open(&r->diag))
		return -1;	/* robot_stop closes the exporters */
	r->started = true;
	render(r, c, s, mono_now());
	service_status_line(&c->model, s, line, sizeof(line));
	service_ready(&r->sv, line);
	return 0;
}

void robot_tick(struct robot *r)
{
	if (r->started && !r->stopped)
		service_tick(&r->sv, mono_now());
}

__u64 robot_tick_ms(const struct robot *r)
{
	return r->started && !r->stopped ? service_tick_ms(&r->sv) : 0;
}

void robot_interval(struct robot *r, struct collector *c, const struct supervisor *s,
		    __u64 now)
{
	char line[256];

	if (!r->started || r->stopped)
		return;
	render(r, c, s, now);
	ros2diag_publish(&r->diag, &c->model, s, now);
	service_status_line(&c->model, s, line, sizeof(line));
	service_status(&r->sv, line);
	if (r->o->unit)
		unit_check(&r->unit, c);
}

void robot_reload(struct robot *r, bool done)
{
	if (r->started && !r->stopped)
		service_reloading(&r->sv, done);
}

void robot_stop(struct robot *r)
{
	if (r->stopped)
		return;
	r->stopped = true;
	if (r->started)
		service_stopping(&r->sv);
	promexp_close(&r->pe);
	ros2diag_close(&r->diag);
	unit_free(&r->unit);
	textbuf_free(&r->buf);
}
