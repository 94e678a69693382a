// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* output_stacks.c - where in the code: stacks of RT-unsafe events, table and JSON */
#include <string.h>
#include "config/stackopt.h"
#include "model/syscalls.h"
#include "sinks/output_stacks.h"

/* reason_name - JSON name of a stack's reason: an unsafe reason, or a page fault */
static const char *reason_name(__u32 reason)
{
	return reason == RTSUP_STACK_FAULT ? "page_fault" : unsafe_reason_name(reason);
}

void stack_what(const struct stack_entry *e, char *buf, size_t len)
{
	const char *sys = e->reason == RTSUP_U_SYSCALL ? syscall_name(e->nr) : NULL;

	if (e->reason == RTSUP_U_SYSCALL)
		snprintf(buf, len, "%s", sys ? sys : "syscall ?");
	else if (e->reason == RTSUP_STACK_FAULT)
		snprintf(buf, len, "page fault");
	else
		snprintf(buf, len, "%s", reason_name(e->reason));
}

/* comm_of - the thread's name from the model, "?" if it is not there */
static const char *comm_of(const struct model *m, __u32 tid)
{
	int i;

	for (i = 0; m && i < m->n; i++)
		if (m->t[i]->tid == tid)
			return m->t[i]->comm;
	return "?";
}

/* lost_line - records the kernel or we could not keep, never silent */
static void lost_line(FILE *out, const struct stackagg *a)
{
	if (a->kernel[RTSUP_STK_LOST] || a->kernel[RTSUP_STK_OVER_BUDGET] ||
	    a->kernel[RTSUP_STK_NO_STACK] || a->not_kept)
		fprintf(out, "  stacks not captured: %llu lost (ring buffer full), %llu over the "
			"per-thread budget, %llu unreadable, %llu not kept\n",
			(unsigned long long)a->kernel[RTSUP_STK_LOST],
			(unsigned long long)a->kernel[RTSUP_STK_OVER_BUDGET],
			(unsigned long long)a->kernel[RTSUP_STK_NO_STACK],
			(unsigned long long)a->not_kept);
}

void stacks_table(FILE *out, const struct stackagg *a, const struct model *m, bool window)
{
	char what[64], frame[512], line[2048];
	int i, j;

	if (!window)
		fprintf(out, "where in the code: %d distinct stacks from %llu records\n", a->n,
			(unsigned long long)a->records);
	for (i = 0; i < a->n; i++) {
		const struct stack_entry *e = &a->e[i];
		__u64 n = window ? stack_entry_interval(e) : e->total;

		if (!n)
			continue;
		stack_what(e, what, sizeof(what));
		if (window) {
			stack_format(e->frames, e->nframes, " <- ", line, sizeof(line));
			fprintf(out, "  %7u %-15.15s %s %llux, from %s\n", e->tid,
				comm_of(m, e->tid), what, (unsigned long long)n, line);
			continue;
		}
		fprintf(out, "  %u %s: %s %llux\n", e->tid, comm_of(m, e->tid), what,
			(unsigned long long)n);
		for (j = 0; j < e->nframes; j++) {
			frame_format(&e->frames[j], frame, sizeof(frame));
			fprintf(out, "      %s%s\n", j ? "<- " : "", frame);
		}
		if (!e->nframes)
			fprintf(out, "      [no user stack]\n");
	}
	lost_line(out, a);
}

/* frame_json - one frame: what is known of it, nothing made up */
static json_t *frame_json(const struct stack_frame *f)
{
	json_t *o = json_object();

	json_object_set_new(o, "pc", json_integer(f->pc));
	if (f->func[0])
		json_object_set_new(o, "function", json_string(f->func));
	if (f->line) {
		json_object_set_new(o, "file", json_string(f->file));
		json_object_set_new(o, "line", json_integer(f->line));
	}
	if (f->module[0]) {
		json_object_set_new(o, "module", json_string(f->module));
		json_object_set_new(o, "offset", json_integer(f->offset));
	}
	if (f->build_id[0])
		json_object_set_new(o, "build_id", json_string(f->build_id));
	if (f->flags & FRAME_REPLACED)
		json_object_set_new(o, "replaced_on_disk", json_true());
	if (f->flags & FRAME_DELETED)
		json_object_set_new(o, "deleted", json_true());
	return o;
}

/* kinds_json - the unwinders that took a stack: ["fp"], ["dwarf"] or both (auto, rules) */
static json_t *kinds_json(__u32 kinds)
{
	json_t *arr = json_array();
	__u32 k;

	for (k = RTSUP_STACKS_FP; k <= RTSUP_STACKS_DWARF; k++)
		if (kinds & (1u << k))
			json_array_append_new(arr, json_string(stacks_name(k)));
	return arr;
}

json_t *stacks_json(const struct stackagg *a, __u32 tid, bool window)
{
	json_t *arr = json_array(), *frames, *o;
	int i, j;

	for (i = 0; i < a->n; i++) {
		const struct stack_entry *e = &a->e[i];
		__u64 n = window ? stack_entry_interval(e) : e->total;

		if (e->tid != tid || !n)
			continue;
		frames = json_array();
		for (j = 0; j < e->nframes; j++)
			json_array_append_new(frames, frame_json(&e->frames[j]));
		o = json_pack("{s:s,s:I,s:I,s:o}", "reason", reason_name(e->reason),
			      "count", (json_int_t)n, "total", (json_int_t)e->total,
			      "frames", frames);
		if (e->reason == RTSUP_U_SYSCALL)
			json_object_set_new(o, "syscall", syscall_name(e->nr) ?
					    json_string(syscall_name(e->nr)) : json_integer(e->nr));
		if (e->kinds)
			json_object_set_new(o, "unwinders", kinds_json(e->kinds));
		json_array_append_new(arr, o);
	}
	return arr;
}

json_t *stacks_health_json(const struct stackagg *a)
{
	return json_pack("{s:I,s:i,s:I,s:I,s:I,s:I}", "records", (json_int_t)a->records,
			 "distinct", a->n,
			 "lost", (json_int_t)a->kernel[RTSUP_STK_LOST],
			 "over_budget", (json_int_t)a->kernel[RTSUP_STK_OVER_BUDGET],
			 "unreadable", (json_int_t)a->kernel[RTSUP_STK_NO_STACK],
			 "not_kept", (json_int_t)a->not_kept);
}
