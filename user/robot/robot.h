/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * robot.h - what a long-running rtsup-trace on a robot adds to the live
 * loop: systemd readiness, status and watchdog, the journal, the
 * Prometheus exporters, ROS 2 /diagnostics and --unit. main.c calls these at fixed points; each
 * is a no-op when its option is not given.
 */
#ifndef RTSUP_ROBOT_H
#define RTSUP_ROBOT_H

#include <stdbool.h>
#include "collect/collector.h"
#include "options.h"
#include "sinks/prom.h"
#include "sinks/promexp.h"
#include "robot/ros2diag.h"
#include "robot/service.h"
#include "judge/supervise.h"
#include "robot/unit.h"

struct robot {
	const struct options *o;
	struct service sv;
	struct promexp pe;
	struct unit_follow unit;
	struct ros2diag diag;
	struct textbuf buf;
	bool started;
	bool stopped;
};

/*
 * robot_prepare - before loading: systemd's settings, --unit, the exporters
 * (an empty /metrics until robot_start); the supervisor's log hook
 */
int robot_prepare(struct robot *r, const struct options *o, struct supervisor *s);
/* robot_start - after attach: --unit's cgroup, first metrics, /diagnostics, READY=1 */
int robot_start(struct robot *r, struct collector *c, const struct supervisor *s);
/* robot_tick - every pass of the main loop: watchdog */
void robot_tick(struct robot *r);
/* robot_tick_ms - the longest the loop may go without robot_tick, 0 = no limit */
__u64 robot_tick_ms(const struct robot *r);
/* robot_interval - after the verdicts of an interval: metrics, /diagnostics, STATUS=, --unit */
void robot_interval(struct robot *r, struct collector *c, const struct supervisor *s,
		    __u64 now);
/* robot_reload - around a SIGHUP reload */
void robot_reload(struct robot *r, bool done);
/* robot_stop - STOPPING=1, exporters down; safe to call more than once */
void robot_stop(struct robot *r);

#endif
