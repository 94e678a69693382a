// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * unwind.c - user stacks to frames with libdwfl (elfutils), the way perf's
 * util/unwind-libdw.c does: the modules of a process are reported from its
 * mappings, the copied registers and stack stand in for the live thread
 * (Dwfl_Thread_Callbacks), and dwfl_getthread_frames unwinds from
 * .eh_frame/.debug_frame. No unwinder or DWARF parser of our own.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <elfutils/libdwfl.h>
#include <elfutils/libdwelf.h>
#include "collect/fpcheck.h"
#include "collect/procmaps.h"
#include "collect/unwind.h"

/*
 * Symbolized frames by pc, direct-mapped: a control loop's unsafe events
 * come from a few call sites again and again, and libdwfl's lookups of
 * symbol and line cost tens of microseconds per frame.
 */
#define SYMCACHE_SIZE 512

struct symcache {
	__u64 pc;		/* 0: empty */
	bool act;
	struct stack_frame f;
};

/* One target process: its mappings and a libdwfl session over them. */
struct uproc {
	__u32 tgid;
	struct procmap *maps;
	__u32 *flags;		/* FRAME_* per mapping */
	int nmaps;
	Dwfl *dwfl;
	bool attached;		/* dwfl_attach_state done */
	bool exec_known;	/* exec_id is the one the mappings were read in */
	bool fresh_exec;	/* read at an exec mark: ld.so may still be mapping */
	__u32 exec_id;
	/* the record being unwound, for the thread callbacks */
	const struct rtsup_stack_rec *cur;
	__u64 pcs[STACK_MAX_FRAMES];
	bool act[STACK_MAX_FRAMES];	/* the exact pc, not a return address */
	int npcs;
	char (*bids)[48];	/* build-id per mapping, hex */
	__u32 gen;		/* the set of mappings: bumped at each new one */
	bool offline;		/* replay: mappings from the recording, files checked */
	bool dirty;		/* offline: mappings added since libdwfl was told */
	struct symcache *cache;	/* SYMCACHE_SIZE, emptied when the mappings change */
	bool want_verdict;	/* --stacks auto: judge its modules' frame pointers */
	__u32 verdict;		/* RTSUP_STACKS_FP or _DWARF, 0 before the first */
	bool verdict_new;	/* not taken yet (unwind_take_verdicts) */
};

struct unwinder {
	struct uproc *p;
	int n, cap;
	bool auto_fp;		/* --stacks auto somewhere: processes get a verdict */
};

/*
 * The modules' frame pointer verdicts by build-id: the C library's is
 * taken once for every process that maps it.
 */
#define FPCACHE_SIZE	64

static struct {
	char bid[48];
	enum fp_verdict v;
} fpcache[FPCACHE_SIZE];
static int fpcache_n;
static bool verdicts_pending;	/* some process has a verdict not taken yet */

static char *debuginfo_path;	/* NULL: libdwfl's default, .debug and /usr/lib/debug */

static const Dwfl_Callbacks dwfl_cbs = {
	.find_elf = dwfl_linux_proc_find_elf,
	.find_debuginfo = dwfl_standard_find_debuginfo,
	.debuginfo_path = &debuginfo_path,
};

struct unwinder *unwinder_new(void)
{
	elf_version(EV_CURRENT);
	return calloc(1, sizeof(struct unwinder));
}

/* build_id_of - the GNU build-id of an ELF file, hex; "" if none */
static void build_id_of(int fd, char *hex, size_t len)
{
	Elf *elf = fd >= 0 ? elf_begin(fd, ELF_C_READ_MMAP, NULL) : NULL;
	const unsigned char *id;
	ssize_t n, i;

	hex[0] = '\0';
	if (!elf)
		return;
	n = dwelf_elf_gnu_build_id(elf, (const void **)&id);
	for (i = 0; i < n && (size_t)(i * 2 + 2) < len; i++)
		snprintf(hex + i * 2, 3, "%02x", id[i]);
	elf_end(elf);
}

/*
 * vdso_fd - the vDSO image of a process ("self" for ours), from its memory,
 * as a file libdwfl can read (a memfd); -1 if it cannot be read
 */
static int vdso_fd(const char *pid, __u64 start, __u64 end)
{
	char path[64], *buf;
	size_t len = end - start;
	int mem, fd = -1;

	if (!len || len > (1 << 20))
		return -1;
	snprintf(path, sizeof(path), "/proc/%s/mem", pid);
	mem = open(path, O_RDONLY | O_CLOEXEC);
	buf = malloc(len);
	if (mem >= 0 && buf && pread(mem, buf, len, start) == (ssize_t)len) {
		fd = memfd_create("vdso", MFD_CLOEXEC);
		if (fd >= 0 && (write(fd, buf, len) != (ssize_t)len || lseek(fd, 0, SEEK_SET))) {
			close(fd);
			fd = -1;
		}
	}
	free(buf);
	if (mem >= 0)
		close(mem);
	return fd;
}

/*
 * own_vdso_fd - replay: our own vDSO, the recorded one when its build-id
 * says so (the same kernel build)
 */
static int own_vdso_fd(void)
{
	struct procmap *maps;
	FILE *f = fopen("/proc/self/maps", "re");
	int i, n, fd = -1;

	if (!f)
		return -1;
	n = procmaps_read(f, &maps);
	fclose(f);
	for (i = 0; i < n; i++)
		if (fd < 0 && procmap_is_vdso(&maps[i]))
			fd = vdso_fd("self", maps[i].start, maps[i].end);
	if (n >= 0)
		free(maps);
	return fd;
}

/*
 * replaced - is the file at the mapping's path another build than the one
 * mapped (map_fd, the mapped inode)? Then names from the path would be
 * wrong: libdwfl reads the mapped one, and the frame says so.
 */
static bool replaced(int map_fd, const char *path)
{
	char a[41], b[41];
	int fd = open(path, O_RDONLY | O_CLOEXEC);

	build_id_of(map_fd, a, sizeof(a));
	build_id_of(fd, b, sizeof(b));
	if (fd >= 0)
		close(fd);
	return a[0] && strcmp(a, b);
}

/* uproc_set_maps - a new set of mappings; what libdwfl knew goes with the old */
static int uproc_set_maps(struct uproc *p, struct procmap *maps, int n)
{
	if (p->dwfl)
		dwfl_end(p->dwfl);
	p->dwfl = NULL;
	free(p->maps);
	free(p->flags);
	free(p->bids);
	p->maps = maps;
	p->nmaps = n;
	p->flags = calloc(n ? n : 1, sizeof(*p->flags));
	p->bids = calloc(n ? n : 1, sizeof(*p->bids));
	p->attached = false;
	p->gen++;
	if (p->cache)
		memset(p->cache, 0, SYMCACHE_SIZE * sizeof(*p->cache));
	return p->flags && p->bids ? 0 : -ENOMEM;
}

/* module_bid - a libdwfl module's build-id, hex; "" if none */
static void module_bid(Dwfl_Module *m, char *hex, size_t len)
{
	const unsigned char *id;
	GElf_Addr vaddr;
	int i, n = dwfl_module_build_id(m, &id, &vaddr);

	hex[0] = '\0';
	for (i = 0; i < n && (size_t)(i * 2 + 2) < len; i++)
		snprintf(hex + i * 2, 3, "%02x", id[i]);
}

/* module_fp - fp_elf_check of one module, once per build-id */
static enum fp_verdict module_fp(Dwfl_Module *m)
{
	Dwarf_Addr bias;
	char bid[48];
	enum fp_verdict v;
	int i;

	module_bid(m, bid, sizeof(bid));
	for (i = 0; bid[0] && i < fpcache_n; i++)
		if (!strcmp(fpcache[i].bid, bid))
			return fpcache[i].v;
	v = fp_elf_check(dwfl_module_getelf(m, &bias));
	if (bid[0] && fpcache_n < FPCACHE_SIZE) {
		snprintf(fpcache[fpcache_n].bid, sizeof(fpcache[0].bid), "%s", bid);
		fpcache[fpcache_n++].v = v;
	}
	return v;
}

struct fp_walk {
	enum fp_verdict v[64];
	int n;
};

/* one_module_fp - dwfl_getmodules callback: each module's verdict */
static int one_module_fp(Dwfl_Module *m, void **ud, const char *name, Dwarf_Addr start,
			 void *arg)
{
	struct fp_walk *w = arg;

	if (w->n < 64)
		w->v[w->n++] = module_fp(m);
	return DWARF_CB_OK;
}

/*
 * uproc_judge_fp - --stacks auto: fp when every module the process maps
 * keeps frame pointers (fpcheck.h); a new verdict waits to be taken
 */
static void uproc_judge_fp(struct uproc *p)
{
	struct fp_walk w = { .n = 0 };
	__u32 kind;

	dwfl_getmodules(p->dwfl, one_module_fp, &w, 0);
	kind = fp_process_kind(w.v, w.n);
	if (kind != p->verdict) {
		p->verdict = kind;
		p->verdict_new = true;
		verdicts_pending = true;
	}
}

/*
 * uproc_report - the mappings as libdwfl modules. Live: each read through
 * /proc/PID/map_files/, the mapped inode whatever is at its path now.
 * Offline (replay): the file at the path, only if its build-id is the
 * recorded one; otherwise the frames stay module+offset.
 */
static int uproc_report(struct uproc *p)
{
	char path[64], bid[48];
	Dwfl_Module *mod;
	struct stat st;
	int i, j, fd;

	p->dwfl = dwfl_begin(&dwfl_cbs);
	if (!p->dwfl)
		return -ENOMEM;
	dwfl_report_begin(p->dwfl);
	for (i = 0; i < p->nmaps; i++) {
		struct procmap *m = &p->maps[i];

		/* a file mapped twice executable is one module */
		for (j = 0; j < i; j++)
			if (!strcmp(p->maps[j].path, m->path))
				break;
		if (j < i) {
			if (!p->offline) {
				p->flags[i] = p->flags[j];
				memcpy(p->bids[i], p->bids[j], sizeof(p->bids[i]));
			}
			continue;
		}
		if (p->offline) {
			/* a recorded path is outside input: a regular file, never a FIFO's wait */
			fd = procmap_is_vdso(m) ? own_vdso_fd() :
			     open(m->path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
			if (fd >= 0 && (fstat(fd, &st) || !S_ISREG(st.st_mode))) {
				close(fd);
				fd = -1;
			}
			build_id_of(fd, bid, sizeof(bid));
			/*
			 * another build here, or none recorded to check it by (the
			 * live side could not read the mapped file): no names from it
			 */
			if (fd >= 0 && strcmp(bid, p->bids[i])) {
				close(fd);
				continue;
			}
		} else if (procmap_is_vdso(m)) {
			snprintf(path, sizeof(path), "%u", p->tgid);
			fd = vdso_fd(path, m->start, m->end);
			build_id_of(fd, p->bids[i], sizeof(p->bids[i]));
		} else {
			snprintf(path, sizeof(path), "/proc/%u/map_files/%llx-%llx", p->tgid,
				 (unsigned long long)m->start, (unsigned long long)m->end);
			fd = open(path, O_RDONLY | O_CLOEXEC);
			build_id_of(fd, p->bids[i], sizeof(p->bids[i]));
			if (m->deleted)
				p->flags[i] |= FRAME_DELETED;
			else if (fd >= 0 && replaced(fd, m->path))
				p->flags[i] |= FRAME_REPLACED;
		}
		if (fd < 0 && (m->deleted || p->offline))
			continue;	/* nothing to read it from: module+offset */
		/* libdwfl owns fd on success */
		mod = dwfl_report_elf(p->dwfl, m->path, m->path, fd, m->start - m->pgoff, false);
		if (!mod && fd >= 0)
			close(fd);
		/* the mapped file unreadable, libdwfl read the path: record that one's build-id */
		if (mod && !p->offline && !p->bids[i][0])
			module_bid(mod, p->bids[i], sizeof(p->bids[i]));
	}
	dwfl_report_end(p->dwfl, NULL, NULL);
	if (p->want_verdict && !p->offline)
		uproc_judge_fp(p);
	return 0;
}

/* uproc_load - (re)read the mappings and report them as libdwfl modules */
static int uproc_load(struct uproc *p)
{
	char path[64];
	FILE *f;
	int n;
	struct procmap *maps;

	snprintf(path, sizeof(path), "/proc/%u/maps", p->tgid);
	f = fopen(path, "re");
	if (!f)
		return -errno;
	n = procmaps_read(f, &maps);
	fclose(f);
	if (n < 0)
		return -ENOMEM;
	/* a zombie has no mappings: what was read before is all there is */
	if (!n) {
		free(maps);
		return -ESRCH;
	}
	return uproc_set_maps(p, maps, n) ?: uproc_report(p);
}

/* uproc_find_or_add - the process's entry; *added when it is a new, zeroed one */
static struct uproc *uproc_find_or_add(struct unwinder *u, __u32 tgid, bool *added)
{
	struct uproc *p;
	int i;

	*added = false;
	for (i = 0; i < u->n; i++)
		if (u->p[i].tgid == tgid)
			return &u->p[i];
	if (u->n == u->cap) {
		int cap = u->cap ? u->cap * 2 : 8;
		struct uproc *np = realloc(u->p, cap * sizeof(*np));

		if (!np)
			return NULL;
		u->p = np;
		u->cap = cap;
	}
	p = &u->p[u->n++];
	memset(p, 0, sizeof(*p));
	p->tgid = tgid;
	p->want_verdict = u->auto_fp;
	p->cache = calloc(SYMCACHE_SIZE, sizeof(*p->cache));
	*added = true;
	return p;
}

/* uproc_get - the process's entry; its mappings are read at first sight */
static struct uproc *uproc_get(struct unwinder *u, __u32 tgid)
{
	bool added;
	struct uproc *p = uproc_find_or_add(u, tgid, &added);

	if (p && added)
		uproc_load(p);
	return p;
}

void unwind_note_process(struct unwinder *u, __u32 tgid)
{
	uproc_get(u, tgid);
}

void unwinder_set_auto(struct unwinder *u, bool on)
{
	u->auto_fp = on;
}

void unwind_take_verdicts(struct unwinder *u, void (*fn)(void *ctx, __u32 tgid, __u32 kind),
			  void *ctx)
{
	int i;

	/* called at every stack record: nothing to look at, most of the time */
	if (!verdicts_pending)
		return;
	verdicts_pending = false;
	for (i = 0; i < u->n; i++)
		if (u->p[i].verdict_new) {
			u->p[i].verdict_new = false;
			fn(ctx, u->p[i].tgid, u->p[i].verdict);
		}
}

/* ---- DWARF: the copied registers and stack as the thread's state ---- */

static pid_t next_thread(Dwfl *dwfl, void *arg, void **thread_argp)
{
	struct uproc *p = arg;

	if (*thread_argp)
		return 0;
	*thread_argp = p;
	return p->cur->tid;
}

/* memory_read - only the copied stack: what is outside is not known */
static bool memory_read(Dwfl *dwfl, Dwarf_Addr addr, Dwarf_Word *result, void *arg)
{
	struct uproc *p = arg;
	const struct rtsup_stack_rec *r = p->cur;

	if (addr < r->sp || addr + sizeof(*result) > r->sp + r->dump_len)
		return false;
	memcpy(result, (const char *)(r + 1) + (addr - r->sp), sizeof(*result));
	return true;
}

static bool set_initial_registers(Dwfl_Thread *thread, void *arg)
{
	struct uproc *p = arg;
	Dwarf_Word regs[RTSUP_STACK_REGS];
	int i;

	for (i = 0; i < RTSUP_STACK_REGS; i++)
		regs[i] = p->cur->regs[i];
#if defined(__x86_64__)
	return dwfl_thread_state_registers(thread, 0, 17, regs);
#elif defined(__aarch64__)
	if (!dwfl_thread_state_registers(thread, 0, 32, regs))
		return false;
	dwfl_thread_state_register_pc(thread, regs[32]);
	return true;
#else
	return false;
#endif
}

static const Dwfl_Thread_Callbacks thread_cbs = {
	.next_thread = next_thread,
	.memory_read = memory_read,
	.set_initial_registers = set_initial_registers,
};

/* one_frame - dwfl_getthread_frames callback: keep each frame's pc */
static int one_frame(Dwfl_Frame *state, void *arg)
{
	struct uproc *p = arg;
	Dwarf_Addr pc;
	bool act;

	if (!dwfl_frame_pc(state, &pc, &act) || !pc)
		return DWARF_CB_ABORT;
	p->pcs[p->npcs] = pc;
	p->act[p->npcs] = act;
	return ++p->npcs < STACK_MAX_FRAMES ? DWARF_CB_OK : DWARF_CB_ABORT;
}

/*
 * unwind_dwarf - the frames of a DWARF record, as far as the copy reaches;
 * -1 when libdwfl failed before the outermost frame
 */
static int unwind_dwarf(struct uproc *p, const struct rtsup_stack_rec *r)
{
	int err;

	if (!p->attached)
		p->attached = dwfl_attach_state(p->dwfl, NULL, p->tgid, &thread_cbs, p);
	if (!p->attached) {
		return -1;
	}
	p->cur = r;
	/* an unwind that stops early keeps the frames it found */
	err = dwfl_getthread_frames(p->dwfl, r->tid, one_frame, p);
	p->cur = NULL;
	return err < 0 ? -1 : 0;
}

/* ---- symbols ---- */

/* map_flags - FRAME_* of the mapping that holds pc */
static __u32 map_flags(const struct uproc *p, __u64 pc)
{
	int i;

	for (i = 0; i < p->nmaps; i++)
		if (pc >= p->maps[i].start && pc < p->maps[i].end)
			return p->flags[i];
	return 0;
}

/*
 * map_only - a pc in a mapping libdwfl has no module for (the file gone, or
 * another build at replay): its path, offset and build-id; else [unknown]
 * (anonymous code, JIT, the vDSO)
 */
static void map_only(const struct uproc *p, __u64 look, struct stack_frame *f)
{
	int i;

	for (i = 0; i < p->nmaps; i++) {
		const struct procmap *m = &p->maps[i];

		if (look < m->start || look >= m->end)
			continue;
		snprintf(f->module, sizeof(f->module), "%s", m->path);
		f->offset = f->pc - (m->start - m->pgoff);
		snprintf(f->build_id, sizeof(f->build_id), "%s", p->bids[i]);
		f->flags = p->flags[i];
		return;
	}
}

/* C++'s demangler, in libstdc++ (the Itanium ABI's, C linkage) */
extern char *__cxa_demangle(const char *mangled, char *buf, size_t *len, int *status);

/* demangle - "_ZN4ctrl4Loop6updateEl" as "ctrl::Loop::update(long)"; C names as they are */
static void demangle(const char *name, char *out, size_t len)
{
	char *d = NULL;
	int status = -1;

	if (name[0] == '_' && name[1] == 'Z')
		d = __cxa_demangle(name, NULL, NULL, &status);
	snprintf(out, len, "%s", d && !status ? d : name);
	free(d);
}

/* symbolize - what is known of one pc; 'act': the exact pc, else a return address */
static void symbolize(struct uproc *p, __u64 pc, bool act, struct stack_frame *f)
{
	Dwarf_Addr look = act ? pc : pc - 1, bias = 0, lineaddr;
	Dwfl_Module *m = p->dwfl ? dwfl_addrmodule(p->dwfl, look) : NULL;
	const unsigned char *id;
	const char *name, *src;
	GElf_Off off;
	GElf_Sym sym;
	Dwfl_Line *l;
	GElf_Addr vaddr;
	int n, i;

	memset(f, 0, sizeof(*f));
	f->pc = pc;
	if (!m) {
		map_only(p, look, f);	/* what the mapping says, or [unknown] */
		return;
	}
	f->flags = map_flags(p, look);
	name = dwfl_module_info(m, NULL, NULL, NULL, NULL, NULL, NULL, NULL);
	snprintf(f->module, sizeof(f->module), "%s", name ? name : "?");
	if (!dwfl_module_getelf(m, &bias))
		bias = 0;
	f->offset = pc - bias;
	n = dwfl_module_build_id(m, &id, &vaddr);
	for (i = 0; i < n && i < 20; i++)
		snprintf(f->build_id + i * 2, 3, "%02x", id[i]);
	name = dwfl_module_addrinfo(m, look, &off, &sym, NULL, NULL, NULL);
	if (name)
		demangle(name, f->func, sizeof(f->func));
	l = dwfl_module_getsrc(m, look);
	src = l ? dwfl_lineinfo(l, &lineaddr, &f->line, NULL, NULL, NULL) : NULL;
	if (src)
		snprintf(f->file, sizeof(f->file), "%s", src);
	else
		f->line = 0;
}

/* record_pc - the pc at the event: the first frame of either kind */
static __u64 record_pc(const struct rtsup_stack_rec *r)
{
	if (r->kind != RTSUP_STACKS_DWARF)
		return r->ips[0];
#if defined(__x86_64__)
	return r->regs[16];
#elif defined(__aarch64__)
	return r->regs[32];
#else
	return 0;
#endif
}

/* symbolize_cached - symbolize, once per pc while the mappings hold */
static void symbolize_cached(struct uproc *p, __u64 pc, bool act, struct stack_frame *f)
{
	struct symcache *c = p->cache ? &p->cache[(pc * 0x9e3779b97f4a7c15ULL) >> 55] : NULL;

	if (c && c->pc == pc && c->act == act) {
		*f = c->f;
		return;
	}
	symbolize(p, pc, act, f);
	if (c) {
		c->pc = pc;
		c->act = act;
		c->f = *f;
	}
}

/* alive - is the process still there to read its mappings? */
static bool alive(__u32 tgid)
{
	char path[32];

	snprintf(path, sizeof(path), "/proc/%u", tgid);
	return !access(path, F_OK);
}

/* in_module - is pc inside a module reported for the process? */
static bool in_module(const struct uproc *p, __u64 pc)
{
	return p->dwfl && dwfl_addrmodule(p->dwfl, pc);
}

int unwind_record(struct unwinder *u, const struct rtsup_stack_rec *r, size_t len,
		  struct stack_frame *out, int max)
{
	struct uproc *p = uproc_get(u, r->tgid);
	__u64 first;
	int i;

	if (!p)
		return 0;
	if (r->reason == RTSUP_STACK_EXEC) {
		/* a new program: its mappings from now on, as far as ld.so got */
		if (!p->exec_known || p->exec_id != r->exec_id)
			uproc_load(p);
		p->fresh_exec = true;
		p->exec_known = true;
		p->exec_id = r->exec_id;
		return -1;
	}
	if (r->kind == RTSUP_STACKS_DWARF &&
	    (len < sizeof(*r) + r->dump_len || !r->dump_len))
		return 0;
	first = record_pc(r);
	/*
	 * The mappings read at first sight hold until an exec mark says
	 * otherwise. One missed (its mark lost), or a module mapped since
	 * (dlopen): read them again while the process is there. Gone, the
	 * ones read before are all there is.
	 */
	if (!p->exec_known) {
		p->exec_known = true;
		p->exec_id = r->exec_id;
	}
	if (p->exec_id != r->exec_id || !in_module(p, first) || p->fresh_exec) {
		if (alive(r->tgid))
			uproc_load(p);
		p->exec_id = r->exec_id;
		p->fresh_exec = false;
	}
	p->npcs = 0;
	if (r->kind == RTSUP_STACKS_DWARF) {
		/*
		 * libdwfl found no CFI for the first pcs: mappings read while
		 * ld.so was still at work, say. Read them again, once, while it
		 * is there. (A stack that ends early keeps what it found.)
		 */
		if (unwind_dwarf(p, r) && p->npcs < 2 && alive(r->tgid) && !uproc_load(p)) {
			p->npcs = 0;
			unwind_dwarf(p, r);
		}
	} else {
		/* the walk ends at a zero frame pointer's return address */
		for (i = 0; i < (int)r->nips && i < RTSUP_STACK_DEPTH && i < STACK_MAX_FRAMES &&
			    r->ips[i]; i++) {
			p->pcs[i] = r->ips[i];
			p->act[i] = i == 0;	/* the others are return addresses */
		}
		p->npcs = i;
	}
	for (i = 0; i < p->npcs && i < max; i++) {
		/*
		 * A frame-pointer walk through code built without them reads
		 * garbage: a return address outside every module ends the
		 * stack as one "[unknown]" (pc 0), so such stacks still add up
		 */
		if (r->kind == RTSUP_STACKS_FP && i && !in_module(p, p->pcs[i] - 1)) {
			memset(&out[i], 0, sizeof(out[i]));
			return i + 1;
		}
		symbolize_cached(p, p->pcs[i], p->act[i], &out[i]);
	}
	return i;
}

int unwind_maps(struct unwinder *u, __u32 tgid, struct stack_maps *m)
{
	int i;

	memset(m, 0, sizeof(*m));
	for (i = 0; i < u->n; i++) {
		if (u->p[i].tgid != tgid)
			continue;
		m->maps = u->p[i].maps;
		m->flags = u->p[i].flags;
		m->bids = (const char (*)[48])u->p[i].bids;
		m->gen = u->p[i].gen;
		m->n = u->p[i].nmaps;
		return m->n;
	}
	return 0;
}

/* uproc_offline - a process of the recording, created empty */
static struct uproc *uproc_offline(struct unwinder *u, __u32 tgid)
{
	bool added;
	struct uproc *p = uproc_find_or_add(u, tgid, &added);

	if (p && added) {
		p->offline = true;
		p->gen = ~0U;
	}
	return p;
}

void unwind_offline_map(struct unwinder *u, __u32 tgid, __u32 gen, const struct procmap *m,
			__u32 flags, const char *build_id)
{
	struct uproc *p = uproc_offline(u, tgid);
	struct procmap *nm;
	char (*nb)[48];
	__u32 *nf;

	if (!p)
		return;
	if (p->gen != gen) {	/* a new set: the old one goes */
		uproc_set_maps(p, NULL, 0);
		p->gen = gen;
	}
	nm = realloc(p->maps, (p->nmaps + 1) * sizeof(*nm));
	if (nm)
		p->maps = nm;
	nf = realloc(p->flags, (p->nmaps + 1) * sizeof(*nf));
	if (nf)
		p->flags = nf;
	nb = realloc(p->bids, (p->nmaps + 1) * sizeof(*nb));
	if (nb)
		p->bids = nb;
	if (!nm || !nf || !nb)
		return;
	p->maps[p->nmaps] = *m;
	p->flags[p->nmaps] = flags;
	snprintf(p->bids[p->nmaps], sizeof(p->bids[0]), "%s", build_id);
	p->nmaps++;
	p->dirty = true;
}

int unwind_offline_pcs(struct unwinder *u, __u32 tgid, const __u64 *pcs, int n,
		       struct stack_frame *out, int max)
{
	struct uproc *p = uproc_offline(u, tgid);
	int i;

	if (!p)
		return 0;
	if (p->dirty || !p->dwfl) {
		if (p->dwfl)
			dwfl_end(p->dwfl);
		p->dwfl = NULL;
		if (p->cache)
			memset(p->cache, 0, SYMCACHE_SIZE * sizeof(*p->cache));
		uproc_report(p);
		p->dirty = false;
	}
	for (i = 0; i < n && i < max; i++)
		symbolize_cached(p, pcs[i], i == 0, &out[i]);
	return i;
}

void unwinder_free(struct unwinder *u)
{
	int i;

	if (!u)
		return;
	for (i = 0; i < u->n; i++) {
		if (u->p[i].dwfl)
			dwfl_end(u->p[i].dwfl);
		free(u->p[i].maps);
		free(u->p[i].flags);
		free(u->p[i].bids);
		free(u->p[i].cache);
	}
	free(u->p);
	free(u);
}
