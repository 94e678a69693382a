/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * prom.h - the Prometheus text exposition (format 0.0.4) of the model and
 * the verdicts: rendered into a buffer once per interval, then served over
 * HTTP (--listen) or written to a node_exporter textfile (--prom-textfile).
 * Plain C, no kernel, so the unit tests drive it. Metric list: docs/robot.md.
 */
#ifndef RTSUP_PROM_H
#define RTSUP_PROM_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>
#include "model/model.h"
#include "judge/supervise.h"
#include "sinks/textbuf.h"


struct prom_in {
	const struct model *m;
	const struct supervisor *s;
	const __u64 *counters;	/* the kernel side's counters, RTSUP_C_NR of them */
	__u32 bank;		/* interval bank of the last sample (interval maxima) */
	__u32 map_entries;	/* entries in the kernel's thread map */
	__u32 map_capacity;	/* --max-threads */
	__u64 forgotten;	/* dead threads dropped from the model (bounded memory) */
	double elapsed;		/* seconds since attach */
	/*
	 * More metric families after ours, e.g. the CAN supervision's per-node
	 * families (docs/robot.md lists the planned names): a module adds its
	 * own with prom_family() and prom_sample() here, prom.c stays as it is.
	 */
	void (*extra)(struct textbuf *b, void *ctx);
	void *extra_ctx;
};

/* Status gauge values: 0 OK, 1 WARN, 2 ERROR, 3 STALE (not the enum's order). */
int prom_level_value(enum level l);

/* prom_render - the whole exposition into b (cleared first); -1 when out of memory */
int prom_render(const struct prom_in *in, struct textbuf *b);

/* prom_family - "# HELP" and "# TYPE" of one metric family */
void prom_family(struct textbuf *b, const char *name, const char *type, const char *help);
/*
 * prom_sample - one sample; labels is NULL or "k1", "v1", "k2", "v2", ...,
 * NULL-terminated; values are escaped here
 */
void prom_sample(struct textbuf *b, const char *name, double value, const char *const *labels);
/* prom_printf - append raw text */
void prom_printf(struct textbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
