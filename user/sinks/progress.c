// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* progress.c - a progress bar on stderr for long replays */
#include <string.h>
#include <time.h>
#include "sinks/progress.h"

/* now_ns - CLOCK_MONOTONIC */
static __u64 now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (__u64)ts.tv_sec * 1000000000ULL + ts.tv_nsec;
}

void progress_line(char *buf, size_t len, __u64 done, __u64 total, int width)
{
	int bar = width - 28, fill, n;

	if (bar < 10)
		bar = 10;
	if (bar > 200)
		bar = 200;
	if (done > total)
		done = total;
	fill = total ? (int)(done * bar / total) : bar;
	n = snprintf(buf, len, "replay [");
	for (int i = 0; i < bar && (size_t)n + 1 < len; i++)
		buf[n++] = i < fill ? '#' : '.';
	snprintf(buf + n, len - n, "] %3d%% %6.1f MB", total ? (int)(done * 100 / total) : 100,
		 done / 1e6);
}

void progress_start(struct progress *p, FILE *f, __u64 total, bool on)
{
	memset(p, 0, sizeof(*p));
	p->on = on && total;
	p->total = total;
	p->f = f;
	p->start_ns = now_ns();
	p->next_ns = p->start_ns + PROGRESS_DELAY_NS;
}

bool progress_due(struct progress *p)
{
	__u64 t;

	/* a clock read every 256 records is plenty */
	if (!p->on || (++p->calls & 255))
		return false;
	t = now_ns();
	if (t < p->next_ns)
		return false;
	p->next_ns = t + PROGRESS_EVERY_NS;
	return true;
}

void progress_draw(struct progress *p, __u64 done)
{
	char line[256];

	progress_line(line, sizeof(line), done, p->total, 72);
	fprintf(p->f, "\r%s", line);
	fflush(p->f);
	p->shown = true;
}

void progress_end(struct progress *p)
{
	if (p->shown)
		fprintf(p->f, "\r\033[K");
	p->shown = false;
}
