// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * loader.c - the canonical libbpf lifecycle: check, open, set rodata,
 * load, attach. Everything that can fail for a user's reason fails here
 * with one line that says what to do.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <sys/syscall.h>
#include <linux/capability.h>
#include <bpf/bpf.h>
#include <bpf/btf.h>
#include <bpf/libbpf.h>
#include "collect/loader.h"
#include "collect/threadmem.h"
#include "rtsup.h"
#include "can.h"	/* the skeleton's .bss holds can_if_slot */
#include "rtfollow.h"
#include "threadread.h"
#include "rtsup.skel.h"
#include "rtsup_empty.skel.h"
#include "rtsup_tasks.skel.h"

#ifndef CAP_PERFMON
#define CAP_PERFMON 38
#endif
#ifndef CAP_BPF
#define CAP_BPF 39
#endif

/* has_cap - is a capability in our effective set? */
static bool has_cap(const struct __user_cap_data_struct d[2], int cap)
{
	return d[cap / 32].effective & (1U << (cap % 32));
}

/* check_privileges - root, or CAP_BPF with CAP_PERFMON, or CAP_SYS_ADMIN */
static int check_privileges(void)
{
	struct __user_cap_header_struct h = { _LINUX_CAPABILITY_VERSION_3, 0 };
	struct __user_cap_data_struct d[2] = {};

	if (syscall(SYS_capget, &h, d))
		return geteuid() == 0 ? 0 : -1;
	if (has_cap(d, CAP_SYS_ADMIN) || (has_cap(d, CAP_BPF) && has_cap(d, CAP_PERFMON)))
		return 0;
	fprintf(stderr, "rtsup-trace: not allowed to load BPF programs: "
			"run as root or grant CAP_BPF and CAP_PERFMON\n");
	return -1;
}

/*
 * The kernel's BTF answers the questions below. Parsing it is 5 ms here and
 * 70-150 ms in an emulated guest, so a start parses it once for all of
 * them (libbpf parses it once more to load) and frees it before the load.
 */

/* has_type - does the kernel's BTF (NULL: none) have 'name' of this kind? */
static bool has_type(const struct btf *kbtf, const char *name, __u32 kind)
{
	return kbtf && btf__find_by_name_kind(kbtf, name, kind) > 0;
}

/* probe_tp_btf - can this kernel attach tp_btf to our tracepoints? */
static bool probe_tp_btf(const struct btf *kbtf)
{
	/* the typedef exists only where tp_btf (BPF_PROG_TYPE_TRACING) does */
	return has_type(kbtf, "btf_trace_sched_switch", BTF_KIND_TYPEDEF);
}

/* has_tracepoint - does this kernel have the tracepoint (its BTF typedef)? */
static bool has_tracepoint(const struct btf *kbtf, const char *name)
{
	char tn[96];

	snprintf(tn, sizeof(tn), "btf_trace_%s", name);
	return has_type(kbtf, tn, BTF_KIND_TYPEDEF);
}

/* has_function - does this kernel's BTF have the function (fexit can attach)? */
static bool has_function(const struct btf *kbtf, const char *name)
{
	return has_type(kbtf, name, BTF_KIND_FUNC);
}

/* percpu_var_off - a per-CPU variable's offset in the per-CPU area (BTF), -1: none */
static long long percpu_var_off(const struct btf *kbtf, const char *name)
{
	int i, id = kbtf ? btf__find_by_name_kind(kbtf, ".data..percpu", BTF_KIND_DATASEC) : -1;
	const struct btf_var_secinfo *v;
	const struct btf_type *t;

	if (id <= 0)
		return -1;
	t = btf__type_by_id(kbtf, id);
	v = btf_var_secinfos(t);
	for (i = 0; i < btf_vlen(t); i++, v++)
		if (!strcmp(btf__name_by_offset(kbtf, btf__type_by_id(kbtf, v->type)->name_off),
			    name))
			return v->offset;
	return -1;
}

/* stolen_since_boot - the machine's steal time so far (/proc/stat), 0 when none or unread */
static unsigned long long stolen_since_boot(void)
{
	unsigned long long v[8] = { 0 };
	FILE *f = fopen("/proc/stat", "r");
	int n = 0;

	if (f) {
		n = fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2],
			   &v[3], &v[4], &v[5], &v[6], &v[7]);
		fclose(f);
	}
	return n == 8 ? v[7] : 0;
}

/*
 * steal_offset - where KVM's per-CPU steal time is from a CPU's run queue:
 * both are per-CPU variables, a fixed distance apart in every CPU's copy.
 * BPF reaches the run queue through the current task and cannot name
 * steal_time itself (a static: not in kallsyms without KALLSYMS_ALL).
 * 0 where the kernel has no steal_time (not x86, not a KVM guest kernel).
 * The caller asks only where something was ever stolen (stolen_since_boot):
 * elsewhere (bare metal, a host that gives no steal time) its reads, two a
 * cycle, would cost every target for nothing.
 */
static long long steal_offset(const struct btf *kbtf)
{
	long long rq = percpu_var_off(kbtf, "runqueues"), st = percpu_var_off(kbtf, "steal_time");

	return rq >= 0 && st >= 0 && st != rq ? st - rq : 0;
}

/* is_sys_prog - a per-syscall program: a stub or a body (sys_in_*, sys_out_*) */
static bool is_sys_prog(const char *name)
{
	return !strncmp(name, "sys_in_", 7) || !strncmp(name, "sys_out_", 8);
}

/*
 * select_programs - keep one of the two program sets; CAN only with --can,
 * the user page fault hook only with --stacks, --rt's policy hook (rt_*)
 * only when rt_hook, the task iterator only when attrs_iter, the thread map's
 * iterator only when threads_iter; neither iterator when map_attrs (the one
 * in rtsup_tasks.bpf.c reads the thread map and the tasks: tasks_start)
 */
static void select_programs(struct bpf_object *obj, bool btf, bool can, bool faults,
			    bool rt_hook, bool attrs_iter, bool threads_iter, bool map_attrs,
			    bool sys_per)
{
	struct bpf_program *p;

	bpf_object__for_each_program(p, obj) {
		const char *sec = bpf_program__section_name(p), *name = bpf_program__name(p);
		bool is_btf = !strncmp(sec, "tp_btf/", 7);
		bool is_can = !strncmp(name, "can_", 4);
		bool is_fault = !strncmp(name, "page_fault_", 11);
		bool is_raw_sys = !strncmp(name, "sys_enter_", 10) || !strncmp(name, "sys_exit_", 9);

		/* the per-syscall stubs and bodies: set_sys_hooks */
		if (is_sys_prog(name))
			bpf_program__set_autoload(p, sys_per);
		else if (is_raw_sys && sys_per)
			bpf_program__set_autoload(p, false);
		else if (!strncmp(name, "rt_", 3))
			bpf_program__set_autoload(p, rt_hook);
		else if (!strcmp(sec, "iter/task"))
			bpf_program__set_autoload(p, attrs_iter && !map_attrs);
		else if (!strcmp(sec, "iter/bpf_map_elem"))
			bpf_program__set_autoload(p, threads_iter && !map_attrs);
		else
			bpf_program__set_autoload(p, is_btf == btf && (can || !is_can) &&
						  (faults || !is_fault));
	}
}

/* the syscall class table, from data in syscalls.c: built before the load, written after */
static __u32 sys_table[RTSUP_MAX_SYSCALLS];

/* build_sysclass - the class table for the options; -1 with one line printed */
static int build_sysclass(const struct options *o)
{
	char err[128];

	if (sysclass_build(sys_table, RTSUP_MAX_SYSCALLS, o->delims, o->ndelims, err,
			   sizeof(err))) {
		fprintf(stderr, "rtsup-trace: --cycle-syscall: %s\n", err);
		return -1;
	}
	return 0;
}

/* fill_sysclass - write the class table into the kernel's map */
static int fill_sysclass(struct rtsup_bpf *s)
{
	const __u32 *table = sys_table;
	int fd = bpf_map__fd(s->maps.sysclass);
	__u32 i;

	for (i = 0; i < RTSUP_MAX_SYSCALLS; i++)
		if (table[i] && bpf_map_update_elem(fd, &i, &table[i], BPF_ANY))
			return -errno;
	return 0;
}

/* the kernel's function behind syscall NAME: what the stubs attach to */
#if defined(__x86_64__)
#define SYS_FN_PREFIX "__x64_sys_"
#elif defined(__aarch64__)
#define SYS_FN_PREFIX "__arm64_sys_"
#else
#define SYS_FN_PREFIX ""	/* no per-syscall hooks: plan_sys_hooks finds none */
#endif

/* sys_fn - the function of syscall nr into buf, "" when unknown */
static const char *sys_fn(int nr, char *buf, size_t len)
{
	const char *name = syscall_name(nr);

	if (*SYS_FN_PREFIX && name)
		snprintf(buf, len, SYS_FN_PREFIX "%s", name);
	else
		*buf = 0;
	return buf;
}

/* the stubs of each prototype group (rtsup.bpf.c, SYS_ROW), per direction: entry, exit */
static const struct sys_group {
	const char *stub_fmt[2], *body[2], *body_map[2];
	int slots[2];
	const char *what;
} sys_groups[2] = {
	{ { "sys_in_%d%d", "sys_out_%d%d" }, { "sys_in_prog", "sys_out_prog" },
	  { "sys_in_body", "sys_out_body" }, { RTSUP_SYS_IN_SLOTS, RTSUP_SYS_OUT_SLOTS },
	  "with arguments" },
	{ { "sys_in_z_%d%d", "sys_out_z_%d%d" }, { "sys_in_prog_z", "sys_out_prog_z" },
	  { "sys_in_body_z", "sys_out_body_z" },
	  { RTSUP_SYS_IN_SLOTS_Z, RTSUP_SYS_OUT_SLOTS_Z }, "without arguments" },
};

/* hookset_dir - a hookset's syscalls of one direction (0 entry, 1 exit) and their count */
static __u16 *hookset_dir(struct sys_hookset *h, int out, int **n)
{
	*n = out ? &h->nout : &h->nin;
	return out ? h->out : h->in;
}

/* fn_proto - the BTF prototype of the function behind syscall nr, 0 when none */
static __u32 fn_proto(const struct btf *kbtf, int nr)
{
	char fn[96];
	int id;

	if (!*sys_fn(nr, fn, sizeof(fn)))
		return 0;
	id = btf__find_by_name_kind(kbtf, fn, BTF_KIND_FUNC);
	return id > 0 ? btf__type_by_id(kbtf, id)->type : 0;
}

/*
 * split_by_proto - the hooked syscalls by their function's prototype: the
 * one of read's function (arguments, group 0), and one other (none, group
 * 1); a syscall the kernel has no function for, or of a third prototype, is
 * not hooked (dropped from h). False when a group has more than its stubs.
 */
static bool split_by_proto(const struct btf *kbtf, struct sys_hookset *h,
			   struct sys_hookset g[2], char *err, size_t errlen)
{
	__u32 proto[2] = { fn_proto(kbtf, syscall_nr("read")), 0 };
	int i, k, dir, *n, *gn, kept;
	__u16 *v, *gv;

	memset(g, 0, 2 * sizeof(*g));
	for (dir = 0; dir < 2; dir++) {
		v = hookset_dir(h, dir, &n);
		for (i = 0, kept = 0; i < *n; i++) {
			__u32 p = fn_proto(kbtf, v[i]);

			if (!p)
				continue;
			if (p != proto[0] && !proto[1])
				proto[1] = p;
			if (p == proto[0])
				k = 0;
			else if (p == proto[1])
				k = 1;
			else
				continue;
			gv = hookset_dir(&g[k], dir, &gn);
			if (*gn == sys_groups[k].slots[dir]) {
				snprintf(err, errlen, "more syscalls %s than their %d stubs",
					 sys_groups[k].what, sys_groups[k].slots[dir]);
				return false;
			}
			gv[(*gn)++] = v[i];
			v[kept++] = v[i];
		}
		*n = kept;
	}
	return proto[0] != 0;
}

/*
 * plan_sys_hooks - the syscalls the stubs go on (syshooks.h), by prototype;
 * false when they do not fit, with one line printed when per-syscall was
 * asked for
 */
static bool plan_sys_hooks(struct loader *l, const struct options *o, const struct btf *kbtf)
{
	struct sys_hookset *h = &l->hooks;
	char err[128] = "no syscall function in the kernel's BTF";

	if (syshooks_plan(h, sys_table, RTSUP_MAX_SYSCALLS, &o->sys_rules, err, sizeof(err)) ||
	    !split_by_proto(kbtf, h, l->by_proto, err, sizeof(err))) {
		if (o->sys_hooks == SYS_HOOKS_PER)
			fprintf(stderr, "rtsup-trace: --syscall-hooks per-syscall: %s\n", err);
		return false;
	}
	return true;
}

/* set_slots - the stubs named fmt: the first n on v's functions, the rest not loaded */
static void set_slots(struct bpf_object *obj, const char *fmt, int slots, const __u16 *v, int n)
{
	struct bpf_program *p;
	char name[32], fn[96];
	int i;

	for (i = 0; i < slots; i++) {
		snprintf(name, sizeof(name), fmt, i / 10, i % 10);
		p = bpf_object__find_program_by_name(obj, name);
		if (!p)
			continue;
		if (i < n)
			bpf_program__set_attach_target(p, 0, sys_fn(v[i], fn, sizeof(fn)));
		else
			bpf_program__set_autoload(p, false);
	}
}

/* set_body - a body for the stubs of its group: loaded on their first function, never attached */
static void set_body(struct bpf_object *obj, const char *name, const __u16 *v, int n, bool load)
{
	struct bpf_program *p = bpf_object__find_program_by_name(obj, name);
	char fn[96];

	if (!p)
		return;
	bpf_program__set_autoattach(p, false);
	if (n && load)
		bpf_program__set_attach_target(p, 0, sys_fn(v[0], fn, sizeof(fn)));
	else
		bpf_program__set_autoload(p, false);
}

/*
 * set_sys_hooks - each stub its syscall's function, the rest not loaded;
 * the bodies too, unless 'bodies' is false (the floor's stubs are empty)
 */
static void set_sys_hooks(struct bpf_object *obj, const struct sys_hookset g[2], bool bodies)
{
	int k, dir;

	for (k = 0; k < 2; k++)
		for (dir = 0; dir < 2; dir++) {
			const __u16 *v = dir ? g[k].out : g[k].in;
			int n = dir ? g[k].nout : g[k].nin;

			set_slots(obj, sys_groups[k].stub_fmt[dir], sys_groups[k].slots[dir], v, n);
			set_body(obj, sys_groups[k].body[dir], v, n, bodies);
		}
}

/* link_body - a body into its group's tail-call array, when it was loaded */
static int link_body(struct bpf_object *obj, const char *prog, const char *map)
{
	struct bpf_program *p = bpf_object__find_program_by_name(obj, prog);
	struct bpf_map *m = bpf_object__find_map_by_name(obj, map);
	__u32 zero = 0;
	int fd = p ? bpf_program__fd(p) : -1;

	if (fd < 0)
		return 0;
	return m && !bpf_map_update_elem(bpf_map__fd(m), &zero, &fd, BPF_ANY) ? 0 : -1;
}

/* link_sys_bodies - the stubs' tail-call targets, once loaded */
static int link_sys_bodies(struct rtsup_bpf *s)
{
	int k, dir;

	for (k = 0; k < 2; k++)
		for (dir = 0; dir < 2; dir++)
			if (link_body(s->obj, sys_groups[k].body[dir], sys_groups[k].body_map[dir])) {
				fprintf(stderr, "rtsup-trace: per-syscall hooks: cannot link "
					"their programs: %s\n", strerror(errno));
				return -1;
			}
	return 0;
}

/*
 * floor_start - --floor (the benchmark's floor): the same program set with
 * empty bodies (RTSUP_EMPTY) instead of ours; our maps stay for the collector
 */
static int floor_start(struct loader *l, const struct options *o)
{
	struct rtsup_empty_bpf *e = rtsup_empty_bpf__open();
	struct bpf_map *m;
	int err;

	if (!e)
		return -errno;
	l->floor = e;
	select_programs(e->obj, l->tp_btf, o->can, l->fault_stacks, l->rt_hook, false, false,
			false, l->sys_per);
	/* empty stubs on the same syscalls; no body to call */
	set_sys_hooks(e->obj, l->by_proto, false);
	bpf_program__set_autoattach(e->progs.rt_setsched, false);
	/* its maps are never used: keep them small */
	bpf_object__for_each_map(m, e->obj)
		if (bpf_map__type(m) != BPF_MAP_TYPE_RINGBUF)
			bpf_map__set_max_entries(m, 1);
	err = rtsup_empty_bpf__load(e) ?: rtsup_empty_bpf__attach(e);
	/* an empty body where fexit attaches, none where it cannot */
	if (!err && l->rt_hook)
		e->links.rt_setsched = bpf_program__attach(e->progs.rt_setsched);
	return err;
}

/*
 * The kernel's BTF may have __sched_setscheduler where fexit cannot attach
 * to it (Debian's arm64 6.1: ENOTSUPP at attach), or the kernel may refuse
 * to load an fexit program at all (a security module that forbids kernel
 * function tracing: EPERM at load): then everything is loaded again
 * without the policy hook, which --rt replaces by its per-switch read.
 */
static bool rt_hook_failed;
/* the same for the per-syscall hooks: raw_syscalls instead (--syscall-hooks auto) */
static bool sys_per_failed;
/* the same for the task iterator (an old kernel): the collector asks per thread */
static bool attrs_iter_failed;
/* the same for the thread map's iterator: the collector reads every entry */
static bool threads_iter_failed;
/* the same for its reading of the tasks (a kfunc): the task iterator does */
static bool map_attrs_failed;

/*
 * fallback_of - the optional piece to go without when loading (or, with
 * !at_load, the floor's start) failed, in the order they are given up;
 * NULL: none is left and the error is final. Each flag is set once, so a
 * start is tried at most four times.
 */
static bool *fallback_of(const struct loader *l, const struct options *o, bool at_load)
{
	if (l->sys_per && o->sys_hooks == SYS_HOOKS_AUTO)
		return &sys_per_failed;		/* raw_syscalls, as before */
	if (at_load && l->sys_per)
		return NULL;	/* forced per-syscall hooks refused: that is the error */
	if (l->rt_hook)
		return &rt_hook_failed;		/* the per-switch read */
	if (at_load && l->map_attrs)
		return &map_attrs_failed;	/* the task iterator reads them */
	if (at_load && l->threads_iter)
		return &threads_iter_failed;	/* batch reads of every entry */
	if (at_load && l->attrs_iter)
		return &attrs_iter_failed;	/* the collector asks per thread */
	return NULL;
}

/* attach_threads_iter - the thread map's iterator, on that map */
static bool attach_threads_iter(struct rtsup_bpf *s)
{
	DECLARE_LIBBPF_OPTS(bpf_iter_attach_opts, opts);
	union bpf_iter_link_info linfo = {};

	linfo.map.map_fd = bpf_map__fd(s->maps.threads);
	opts.link_info = &linfo;
	opts.link_info_len = sizeof(linfo);
	s->links.threads_read = bpf_program__attach_iter(s->progs.threads_read, &opts);
	return s->links.threads_read != NULL;
}

/*
 * tasks_start - the thread map's iterator that reads the tasks too, its own
 * object (rtsup_tasks.bpf.c), on our thread map; false when the kernel
 * refused it
 */
static bool tasks_start(struct loader *l)
{
	DECLARE_LIBBPF_OPTS(bpf_iter_attach_opts, opts);
	union bpf_iter_link_info linfo = {};
	struct rtsup_tasks_bpf *t = rtsup_tasks_bpf__open();

	l->tasks = t;
	if (!t)
		return false;
	/* the entries are ours: the same map, not a copy of its definition */
	if (bpf_map__reuse_fd(t->maps.thread_mem, bpf_map__fd(l->skel->maps.thread_mem)) ||
	    rtsup_tasks_bpf__load(t))
		return false;
	linfo.map.map_fd = bpf_map__fd(l->skel->maps.threads);
	opts.link_info = &linfo;
	opts.link_info_len = sizeof(linfo);
	t->links.threads_read_attrs = bpf_program__attach_iter(t->progs.threads_read_attrs, &opts);
	return t->links.threads_read_attrs != NULL;
}

/* start_again_without - stop, give up the piece the kernel refused, start again */
static int start_again_without(struct loader *l, const struct options *o, bool *piece)
{
	loader_stop(l);
	*piece = true;
	return loader_start(l, o);
}

/* has_task_pt_regs - bpf_task_pt_regs (5.15)? Probed once: a start may retry */
static bool has_task_pt_regs(void)
{
	static int probed = -1;

	if (probed < 0)
		probed = libbpf_probe_bpf_helper(BPF_PROG_TYPE_RAW_TRACEPOINT,
						 BPF_FUNC_task_pt_regs, NULL) == 1;
	return probed;
}

/* prog_info - a program's info from the kernel: 0, 1 when it is not loaded, -1 unreadable */
static int prog_info(const struct bpf_program *p, struct bpf_prog_info *info)
{
	__u32 len = sizeof(*info);
	int fd = bpf_program__fd(p);

	if (fd < 0)
		return 1;
	memset(info, 0, sizeof(*info));
	return bpf_obj_get_info_by_fd(fd, info, &len) ? -1 : 0;
}

/* is_sys_stub - a per-syscall stub (sys_in_NN, sys_out_z_NN...), not a body (_prog) */
static bool is_sys_stub(const char *name)
{
	return is_sys_prog(name) && !strstr(name, "_prog");
}

/*
 * print_verified - -v: how many instructions the verifier walked per program
 * (the kernel's verified_insns, 5.16 and later). That walk is most of a
 * start's time: 1 us per instruction on a PC, 10 on an emulated guest.
 */
static void print_verified(const struct bpf_object *obj)
{
	struct bpf_prog_info info;
	struct bpf_program *p;
	char line[2048];
	size_t n = 0;
	__u64 total = 0;

	__u64 stubs = 0;
	int nstubs = 0;

	bpf_object__for_each_program(p, obj) {
		if (prog_info(p, &info) || !info.verified_insns)
			continue;
		total += info.verified_insns;
		if (is_sys_stub(bpf_program__name(p))) {	/* fifty alike: one sum */
			stubs += info.verified_insns;
			nstubs++;
			continue;
		}
		if (n < sizeof(line))
			n += snprintf(line + n, sizeof(line) - n, "%s%s %u", n ? ", " : "",
				      bpf_program__name(p), info.verified_insns);
	}
	if (nstubs && n < sizeof(line))
		snprintf(line + n, sizeof(line) - n, ", sys_stubs*%d %llu", nstubs,
			 (unsigned long long)stubs);
	if (total)
		fprintf(stderr, "rtsup-trace: verified %llu instructions: %s\n",
			(unsigned long long)total, line);
}

int loader_start(struct loader *l, const struct options *o)
{
	struct rtsup_bpf *s;
	struct bpf_program *p;
	struct btf *kbtf;
	bool stolen, task_kfunc, *drop;
	int err, i;

	memset(l, 0, sizeof(*l));
	l->cgroup_fd = -1;
	l->stats_fd = -1;
	if (check_privileges())
		return -1;
	if (access("/sys/kernel/btf/vmlinux", R_OK)) {
		fprintf(stderr, "rtsup-trace: this kernel has no BTF (/sys/kernel/btf/vmlinux): "
				"it needs CONFIG_DEBUG_INFO_BTF=y\n");
		return -1;
	}
	s = rtsup_bpf__open();
	if (!s) {
		fprintf(stderr, "rtsup-trace: cannot open the BPF object: %s\n", strerror(errno));
		return -1;
	}
	l->skel = s;
	stolen = stolen_since_boot() != 0;
	/* the kernel's BTF only for what reads it: tp_btf, --stacks, the steal */
	kbtf = !o->raw_tp || o->stack_any || stolen ? btf__load_vmlinux_btf() : NULL;
	l->tp_btf = !o->raw_tp && probe_tp_btf(kbtf);
	/* where in the code of page faults: x86's exceptions:page_fault_user */
	l->fault_stacks = o->stack_any && has_tracepoint(kbtf, "page_fault_user");
	if (o->stack_any && !l->fault_stacks)
		fprintf(stderr, "rtsup-trace: --stacks: no page_fault_user tracepoint on this "
				"kernel: page faults are counted without their stacks\n");
	/* --rt: policy changes found where they happen, not at every switch */
	l->rt_hook = o->targets.rt && l->tp_btf && !rt_hook_failed &&
		     has_function(kbtf, RTSUP_RT_HOOK_FN);
	s->rodata->cfg_steal_off = stolen ? steal_offset(kbtf) : 0;
	if (build_sysclass(o)) {
		btf__free(kbtf);
		goto fail;
	}
	/* per-syscall hooks: fentry on the syscalls' functions, so tp_btf's kernels only */
	l->sys_per = o->sys_hooks != SYS_HOOKS_RAW && l->tp_btf && !sys_per_failed &&
		     plan_sys_hooks(l, o, kbtf);
	task_kfunc = has_function(kbtf, "bpf_task_from_pid");
	btf__free(kbtf);
	if (o->sys_hooks == SYS_HOOKS_PER && !l->sys_per) {
		fprintf(stderr, "rtsup-trace: --syscall-hooks per-syscall: %s\n",
			o->raw_tp ? "they are BTF programs: not with --raw-tp" :
			!l->tp_btf ? "this kernel has no tp_btf (BTF tracing programs)" :
			sys_per_failed ? "the kernel refused them (-v says why)" :
			"no syscall function found in the kernel's BTF");
		goto fail;
	}
	s->rodata->cfg_sys_per = l->sys_per;
	/* a block's syscall read where it blocks, where the helper is (5.15) */
	s->rodata->cfg_block_sys = has_task_pt_regs();
	/* the targets' attributes in one read a sample, where tracing programs load */
	l->attrs_iter = l->tp_btf && !attrs_iter_failed && !o->floor;
	l->threads_iter = !threads_iter_failed && !o->floor;
	/* ... and with it, where its kfunc is (6.2+), the attributes too */
	l->map_attrs = l->attrs_iter && l->threads_iter && !map_attrs_failed && task_kfunc;
	select_programs(s->obj, l->tp_btf, o->can, l->fault_stacks, l->rt_hook, l->attrs_iter,
			l->threads_iter, l->map_attrs, l->sys_per);
	if (l->sys_per)
		set_sys_hooks(s->obj, l->by_proto, true);
	/* attached on their own below, to know that they failed */
	bpf_program__set_autoattach(s->progs.rt_setsched, false);
	bpf_program__set_autoattach(s->progs.attrs_task, false);
	bpf_program__set_autoattach(s->progs.threads_read, false);
	if (o->floor)	/* none of ours: floor_start attaches the empty ones */
		bpf_object__for_each_program(p, s->obj)
			bpf_program__set_autoload(p, false);
	s->rodata->cfg_ewma_w = o->ewma_w;
	s->rodata->cfg_period = o->period_ns;
	s->rodata->cfg_warmup = o->warmup_ns;
	s->rodata->cfg_rt = o->targets.rt;
	s->rodata->cfg_rt_at_switch = o->targets.rt && !l->rt_hook;
	s->rodata->cfg_cgroup = o->targets.cgroup != NULL || o->unit;
	s->rodata->cfg_ncomm = o->targets.ncomms;
	s->rodata->cfg_record = o->record_path || o->perfetto_path;
	s->rodata->cfg_follow = o->cmd != NULL;
	s->rodata->cfg_can_nif = o->ncan;
	s->rodata->cfg_netns = o->can_netns;
	for (i = 0; i < o->ncan; i++)
		s->bss->can_watch[i] = (struct rtsup_can_watch){ .netns = o->can_netns,
			.ifindex = o->can_ifindex[i], .key = o->can_ifindex[i] };
	s->rodata->cfg_canopen = o->canopen;
	bpf_map__set_max_entries(s->maps.can_ids, o->can_max_ids);
	for (i = 0; i < o->targets.ncomms; i++)
		memcpy((char *)s->rodata->cfg_comms[i], o->targets.comms[i], RTSUP_COMM_LEN);
	bpf_map__set_max_entries(s->maps.threads, o->max_threads);
	bpf_map__set_max_entries(s->maps.thread_mem, o->max_threads);
	bpf_map__set_max_entries(s->maps.thread_free, o->max_threads);
	bpf_map__set_max_entries(s->maps.unsafe_sys, o->max_threads * 4);
	bpf_map__set_max_entries(s->maps.thread_cfg, o->max_threads);
	bpf_map__set_max_entries(s->maps.moved,
				 thread_moved_ring_bytes(o->max_threads, (__u32)getpagesize()));
	s->rodata->cfg_stacks = o->stacks;
	s->rodata->cfg_stack_size = o->stack_size;
	s->rodata->cfg_stack_any = o->stack_any;
	s->rodata->cfg_stack_rules = o->stack_rules;
	s->rodata->cfg_stack_size_max = o->stack_size_max;
	bpf_map__set_max_entries(s->maps.stack_cfg, o->max_threads);
	s->rodata->cfg_stack_budget = o->stack_budget;
	bpf_map__set_max_entries(s->maps.stack_budget, o->max_threads);
	/* room for a budget's worth of DWARF records of a few threads */
	if (o->stack_any)
		bpf_map__set_max_entries(s->maps.stacks, o->stack_dwarf ?
					 16 << 20 : 1 << 20);
	if (o->event_buffer)
		bpf_map__set_max_entries(s->maps.events, o->event_buffer);
	/* a cycle record per cycle: 4 MiB hold seconds of a busy machine */
	if (s->rodata->cfg_record)
		bpf_map__set_max_entries(s->maps.cycles, 4 << 20);

	err = rtsup_bpf__load(s);
	/* fentry refused (a security module: EPERM), or the hook's fault or
	 * not: the next try without it says which */
	drop = err ? fallback_of(l, o, true) : NULL;
	if (drop)
		return start_again_without(l, o, drop);
	if (err && l->sys_per) {
		fprintf(stderr, "rtsup-trace: --syscall-hooks per-syscall: the kernel refuses "
				"fentry programs on syscalls: %s (-v says why; auto falls back "
				"to raw_syscalls)\n", strerror(-err));
		goto fail;
	}
	if (err == -EPERM) {
		/* we hold the capabilities (checked above), yet the kernel says no:
		 * the verifier's log would not help */
		fprintf(stderr, "rtsup-trace: the kernel refuses BPF: %s (a user namespace, "
				"kernel lockdown, seccomp or a security module forbids it; run "
				"as root on the host)\n", strerror(-err));
		goto fail;
	}
	if (err) {
		fprintf(stderr, "rtsup-trace: loading the BPF programs failed: %s "
				"(run with -v for the verifier's log)\n", strerror(-err));
		goto fail;
	}
	if (fill_sysclass(s) || (l->sys_per && !o->floor && link_sys_bodies(s)))
		goto fail;
	/* before any hook runs: every slot is free */
	err = threadmem_fill(bpf_map__fd(s->maps.thread_free), o->max_threads);
	if (err) {
		fprintf(stderr, "rtsup-trace: filling the thread map's free slots failed: %s\n",
			strerror(-err));
		goto fail;
	}
	if (o->targets.cgroup) {
		__u32 zero = 0;

		l->cgroup_fd = open(o->targets.cgroup, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
		if (l->cgroup_fd < 0 ||
		    bpf_map_update_elem(bpf_map__fd(s->maps.cgroup), &zero, &l->cgroup_fd, BPF_ANY)) {
			fprintf(stderr, "rtsup-trace: --cgroup '%s': %s (want a cgroup v2 directory)\n",
				o->targets.cgroup, strerror(errno));
			goto fail;
		}
	}
	err = rtsup_bpf__attach(s);
	if (err && l->sys_per && o->sys_hooks == SYS_HOOKS_AUTO)
		return start_again_without(l, o, &sys_per_failed);
	if (!err && l->rt_hook && !o->floor) {
		s->links.rt_setsched = bpf_program__attach(s->progs.rt_setsched);
		if (!s->links.rt_setsched)
			return start_again_without(l, o, &rt_hook_failed);
	}
	/* without it the collector asks the kernel thread by thread */
	if (!err && l->attrs_iter && !l->map_attrs) {
		s->links.attrs_task = bpf_program__attach_iter(s->progs.attrs_task, NULL);
		l->attrs_iter = s->links.attrs_task != NULL;
	}
	/* without it the collector reads every entry (batch reads) */
	if (!err && l->threads_iter && !l->map_attrs)
		l->threads_iter = attach_threads_iter(s);
	if (!err && l->map_attrs && !tasks_start(l))
		return start_again_without(l, o, &map_attrs_failed);
	if (!err && o->floor) {
		err = floor_start(l, o);
		/* the floor falls back as ours does: its set is the one we would run */
		drop = err ? fallback_of(l, o, false) : NULL;
		if (drop)
			return start_again_without(l, o, drop);
	}
	if (err) {
		fprintf(stderr, "rtsup-trace: attaching the BPF programs failed: %s\n",
			strerror(-err));
		goto fail;
	}
	/* the start that stands: one a refused piece made us give up is not it */
	if (o->verbose)
		print_verified(s->obj);
	/* BPF statistics cost two clock reads per program run machine-wide:
	 * the main loop switches them on only for its sampling windows */
	return 0;
fail:
	loader_stop(l);
	return -1;
}

/*
 * prog_info_sums - run time and skipped runs summed over the programs that
 * run (with --floor, the empty ones); -1 when one program's info could not
 * be read (its numbers are left out)
 */
static int prog_info_sums(const struct loader *l, __u64 *run_time, __u64 *runs, __u64 *missed)
{
	struct bpf_prog_info info;
	struct bpf_program *p;
	int err = 0, r;

	const struct bpf_object *objs[2] = { l->floor ? l->floor->obj : l->skel->obj,
					     l->tasks ? l->tasks->obj : NULL };
	int i;

	*run_time = *runs = *missed = 0;
	for (i = 0; i < 2 && objs[i]; i++) {
		bpf_object__for_each_program(p, objs[i]) {
			r = prog_info(p, &info);
			if (r < 0)
				err = -1;
			if (r)
				continue;	/* unreadable, or the program set we did not load */
			*run_time += info.run_time_ns;
			*runs += info.run_cnt;
			*missed += info.recursion_misses;
		}
	}
	return err;
}

int loader_run_sums(const struct loader *l, __u64 *run_ns, __u64 *runs)
{
	__u64 missed;

	return prog_info_sums(l, run_ns, runs, &missed);
}

__u64 loader_runs_missed(const struct loader *l)
{
	__u64 run_time, runs, missed;

	prog_info_sums(l, &run_time, &runs, &missed);
	return missed;
}

int loader_stats(struct loader *l, bool on)
{
	if (on && l->stats_fd < 0)
		l->stats_fd = bpf_enable_stats(BPF_STATS_RUN_TIME);
	else if (!on && l->stats_fd >= 0) {
		close(l->stats_fd);
		l->stats_fd = -1;
	}
	return on && l->stats_fd < 0 ? -1 : 0;
}

void loader_stop(struct loader *l)
{
	if (l->stats_fd >= 0)
		close(l->stats_fd);
	l->stats_fd = -1;
	rtsup_empty_bpf__destroy(l->floor);
	l->floor = NULL;
	rtsup_tasks_bpf__destroy(l->tasks);
	l->tasks = NULL;
	rtsup_bpf__destroy(l->skel);
	l->skel = NULL;
	if (l->cgroup_fd >= 0)
		close(l->cgroup_fd);
	l->cgroup_fd = -1;
}
