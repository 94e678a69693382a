/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * progress.h - a progress bar on stderr for long replays: only on a
 * terminal, not with -q, and only once a replay has taken a while.
 */
#ifndef RTSUP_PROGRESS_H
#define RTSUP_PROGRESS_H

#include <stdbool.h>
#include <stdio.h>
#include <linux/types.h>

struct progress {
	bool on;		/* drawing allowed (a terminal, no -q) */
	bool shown;		/* something is on the line: clear it at the end */
	__u64 total;		/* bytes */
	__u64 start_ns;
	__u64 next_ns;		/* next redraw */
	unsigned int calls;	/* progress_due calls: the clock is read every 256th */
	FILE *f;
};

/* a replay shorter than this shows no bar; redraws at most this often */
#define PROGRESS_DELAY_NS	500000000ULL
#define PROGRESS_EVERY_NS	100000000ULL

/* progress_start - a bar over 'total' bytes on f, drawn when 'on' */
void progress_start(struct progress *p, FILE *f, __u64 total, bool on);
/*
 * progress_due - time to redraw? Cheap: most calls only count. Only then
 * the caller finds out how far it is (an lseek) and calls progress_draw.
 */
bool progress_due(struct progress *p);
/* progress_draw - draw 'done' bytes of the total */
void progress_draw(struct progress *p, __u64 done);
/* progress_end - clear the bar's line */
void progress_end(struct progress *p);
/* progress_line - the bar's text for done of total in 'width' columns (pure) */
void progress_line(char *buf, size_t len, __u64 done, __u64 total, int width);

#endif
