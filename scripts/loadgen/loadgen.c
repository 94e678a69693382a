/*
 * rtsup-loadgen - synthetic periodic real-time load with fault injection.
 *
 * Each thread runs a cyclictest-style loop: exactly one clock_nanosleep()
 * per cycle followed by busy work, with no other syscalls unless a fault
 * is injected.  Every injection is counted here so that the JSON summary
 * is the exact truth the tracer's numbers are compared against.
 */
#include <argp.h>
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <limits.h>
#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#define PROG		"rtsup-loadgen"
#define MAX_THREADS	1024
#define MAX_PERIOD_US	10000000L
#define MAX_CYCLES	1000000000L
#define MAX_CPUS	CPU_SETSIZE
#define STACK_TOUCH	(64 * 1024)
#define WRITE_LEN	64

enum kind { K_OVERRUN, K_MMAP, K_WRITE, K_OPENAT, K_PAGEFAULT, K_BLOCK,
	    K_STALL, K_EXIT, NR_KINDS };

static const char *const kind_names[NR_KINDS] = {
	"overrun", "mmap", "write", "openat", "pagefault", "block", "stall",
	"exit",
};

enum sc { SC_MMAP, SC_MUNMAP, SC_WRITE, SC_OPENAT, SC_CLOSE, SC_FUTEX, NR_SC };

static const char *const sc_names[NR_SC] = {
	"mmap", "munmap", "write", "openat", "close", "futex",
};

struct fault {
	int kind;
	long arg;		/* us (overrun, block), pages, ms (stall); 0 = none */
	long at;		/* cycle for KIND@CYCLE, -1 for KIND/EVERY */
	long every;		/* for KIND/EVERY, 0 for KIND@CYCLE */
	int thread;		/* -1 = every thread */
	const char *spec;	/* for error messages */
};

struct inj {
	long cycle;
	int kind;
	long arg;
};

/*
 * --cycle-log: one cycle's clock reads, to set beside a tracer's recorded
 * cycles when a count differs (tests print them on a failure).
 */
struct cycle_rec {
	int64_t release;	/* the requested release (absolute sleeps) */
	int64_t before;		/* read before the sleep: the tracer's end of the last cycle is after */
	int64_t start;		/* read after the return: the tracer's start is before */
	int64_t end;		/* read after the work: the span we judge an overrun by */
	long invol, vol;	/* involuntary and voluntary switches at start (--audit) */
	int64_t rd_before, rd_start;	/* run_delay() after the last work, at start (--audit) */
};

/* Per RT thread state; aligned so counters of different threads never share a line. */
struct worker {
	int index;
	int cpu;			/* -1 = not pinned */
	pthread_t pt;
	pid_t tid;
	char comm[16];
	int policy, prio;
	long cycles, misses, overruns, overruns_seen, page_faults, stalls;
	/* blocks: futex waits that slept, what a tracer can see; blocks_injected: asked for */
	long blocks, blocks_injected;
	/* --audit: cycles a tracer may judge otherwise (race_audit()), sleeps */
	long misses_near, overruns_near, vol_switches;
	/*
	 * The longest a tracer can have seen since the start of this thread's
	 * last finished cycle: a cycle's start lies between its clock read
	 * before the sleep and the one after, so at any instant it is less
	 * than from the read before a cycle's sleep to the start of the cycle
	 * after next (or to the thread's end). Not kept past --hold's park.
	 */
	int64_t max_start_span;
	long sc[NR_SC];
	bool exited;
	long exit_cycle;
	struct inj *log;
	long nlog, maxlog;
	struct cycle_rec *clog;		/* --cycle-log: one per cycle, NULL without */
	int sched_fd;			/* --audit: its /proc schedstat, -1 without */
	char *pf_next;			/* next never-touched page of our slice */
	long pf_pages;
	/* block protocol with the helper (futex words) */
	int lock;			/* 0 free, 1 held, 2 held + waiter */
	int held, req, done;
	int64_t deadline;		/* request time + US */
	int hstate;			/* helper private: enum hstate */
	/* stall hog: trigger = ms to spin, -1 = quit */
	bool has_hog;
	pthread_t hog;
	pid_t hog_tid;
	int hog_trigger;
} __attribute__((aligned(64)));

static struct config {
	long threads, period_us, work_us, prio, cycles, start_delay_ms;
	bool relative;
	bool hold;
	bool audit;
	const char *wait_file;
	const char *summary;
	const char *cycle_log;
	const char *name;
	int cpus[MAX_CPUS];
	int ncpus;
	struct fault *faults;
	int nfaults;
} cfg = {
	.threads = 2, .period_us = 1000, .work_us = 100, .prio = 80,
	.cycles = 1000, .name = "lg",
};

static struct worker *workers;
static int tmp_fd = -1;
static char *pf_region;
static size_t page_size;
static int helper_seq;			/* futex word: bumped on each request */
static int helper_stop;
static pid_t helper_tid = -1;
static pthread_barrier_t aux_barrier;
static const char write_buf[WRITE_LEN] = "rtsup-loadgen write fault\n";

/* die - print one line "rtsup-loadgen: what: why" and exit 1 */
static void __attribute__((noreturn, format(printf, 2, 3)))
die(const char *what, const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, PROG ": %s: ", what);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	exit(1);
}

/* now_ns - CLOCK_MONOTONIC in ns (vDSO, no syscall) */
static inline int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* ns_to_ts - convert ns to a timespec */
static inline struct timespec ns_to_ts(int64_t ns)
{
	struct timespec ts = { ns / 1000000000LL, ns % 1000000000LL };

	return ts;
}

/* sleep_us - relative sleep, used only outside RT cycles */
static void sleep_us(long us)
{
	struct timespec ts = ns_to_ts((int64_t)us * 1000);

	while (clock_nanosleep(CLOCK_MONOTONIC, 0, &ts, &ts) == EINTR)
		;
}

/* futex - raw futex(2) on a private word */
static long futex(int *uaddr, int op, int val, const struct timespec *ts)
{
	return syscall(SYS_futex, uaddr, op, val, ts, NULL,
		       FUTEX_BITSET_MATCH_ANY);
}

/* parse_long - strict base-10 parse of @s into [min, max] or die */
static long parse_long(const char *what, const char *s, long min, long max)
{
	char *end;
	long v;

	errno = 0;
	v = strtol(s, &end, 10);
	if (errno || end == s || *end)
		die(what, "'%s' is not a valid integer", s);
	if (v < min || v > max)
		die(what, "'%s' must be in %ld..%ld", s, min, max);
	return v;
}

/* parse_cpus - parse a comma list of CPUs we are allowed to run on */
static void parse_cpus(const char *arg)
{
	char *s = strdup(arg), *rest = s, *tok;
	cpu_set_t allowed;
	long cpu;

	if (!s)
		die("--cpus", "out of memory");
	if (sched_getaffinity(0, sizeof(allowed), &allowed))
		die("sched_getaffinity", "%s", strerror(errno));
	cfg.ncpus = 0;
	/* strsep, not strtok: "0,,1" is an error, not "0,1" */
	while ((tok = strsep(&rest, ","))) {
		cpu = parse_long("--cpus", tok, 0, MAX_CPUS - 1);
		if (!CPU_ISSET(cpu, &allowed))
			die("--cpus", "CPU %ld is not in the allowed CPU set", cpu);
		if (cfg.ncpus == MAX_CPUS)
			die("--cpus", "too many CPUs");
		cfg.cpus[cfg.ncpus++] = cpu;
	}
	free(s);
}

/* parse_fault - parse KIND[:ARG]{@CYCLE|/EVERY}[,thread=I]; ranges needing
 * other options are checked later in check_faults() */
static void parse_fault(const char *arg)
{
	char what[256], *s = strdup(arg), *comma, *sep, *colon;
	struct fault *f;
	int k;

	if (!s)
		die("--fault", "out of memory");
	snprintf(what, sizeof(what), "--fault '%s'", arg);
	f = realloc(cfg.faults, (cfg.nfaults + 1) * sizeof(*f));
	if (!f)
		die(what, "out of memory");
	cfg.faults = f;
	f = &cfg.faults[cfg.nfaults++];
	memset(f, 0, sizeof(*f));
	f->spec = arg;
	f->thread = -1;
	f->at = -1;

	comma = strchr(s, ',');
	if (comma) {
		*comma++ = '\0';
		if (strncmp(comma, "thread=", 7))
			die(what, "expected ',thread=I' after the cycle");
		f->thread = parse_long(what, comma + 7, 0, MAX_THREADS - 1);
	}
	sep = strpbrk(s, "@/");
	if (!sep)
		die(what, "expected KIND[:ARG]@CYCLE or KIND[:ARG]/EVERY");
	if (*sep == '@')
		f->at = parse_long(what, sep + 1, 0, MAX_CYCLES - 1);
	else
		f->every = parse_long(what, sep + 1, 1, MAX_CYCLES);
	*sep = '\0';
	colon = strchr(s, ':');
	if (colon)
		*colon++ = '\0';
	for (k = 0; k < NR_KINDS; k++)
		if (!strcmp(s, kind_names[k]))
			break;
	if (k == NR_KINDS)
		die(what, "unknown kind '%s' (overrun, mmap, write, openat, "
		    "pagefault, block, stall, exit)", s);
	f->kind = k;
	switch (k) {
	case K_OVERRUN:		/* default 1.5 x period, set in check_faults() */
		f->arg = colon ? parse_long(what, colon, 1, 60000000L) : 0;
		break;
	case K_PAGEFAULT:
		f->arg = colon ? parse_long(what, colon, 1, 1000000L) : 1;
		break;
	case K_BLOCK:
		f->arg = colon ? parse_long(what, colon, 1, MAX_PERIOD_US) : 200;
		break;
	case K_STALL:
		f->arg = colon ? parse_long(what, colon, 1, 10000L) : 5;
		break;
	default:
		if (colon)
			die(what, "kind '%s' takes no argument", s);
	}
	free(s);
}

/* check_faults - cross-option checks once every option is known */
static void check_faults(void)
{
	char what[256];
	int i;

	for (i = 0; i < cfg.nfaults; i++) {
		struct fault *f = &cfg.faults[i];

		snprintf(what, sizeof(what), "--fault '%s'", f->spec);
		if (f->thread >= cfg.threads)
			die(what, "thread %d does not exist (-n %ld)",
			    f->thread, cfg.threads);
		if (f->kind == K_OVERRUN && !f->arg)
			f->arg = (cfg.period_us * 3 + 1) / 2;
		if (f->kind == K_OVERRUN && f->arg <= cfg.period_us)
			die(what, "overrun of %ld us must be > period (%ld us)",
			    f->arg, cfg.period_us);
		if (f->kind == K_STALL && (!cfg.ncpus || cfg.prio < 1))
			die(what, "stall needs pinned threads (-C) and prio >= 1");
	}
}

enum { OPT_RELATIVE = 0x100, OPT_NAME, OPT_START_DELAY, OPT_HOLD, OPT_WAIT_FILE, OPT_AUDIT,
       OPT_CYCLE_LOG };

const char *argp_program_version = PROG " 0.1";
static const char doc[] =
"Synthetic periodic real-time load with fault injection.\n"
"\n"
"USAGE: rtsup-loadgen [-n N] [-P US] [-w US] [-r PRIO] [-C LIST] [-c N]\n"
"                     [-f SPEC]... [-s FILE] [--relative] [--name PREFIX]\n"
"                     [--start-delay MS]\n"
"\n"
"Fault SPEC: KIND[:ARG]@CYCLE[,thread=I] injects once at 0-based CYCLE;\n"
"KIND[:ARG]/EVERY[,thread=I] injects at cycles EVERY-1, 2*EVERY-1, ...\n"
"Kinds: overrun[:US] (default 1.5 x period, must be > period), mmap, write,\n"
"openat, pagefault[:PAGES] (default 1), block[:US] (default 200),\n"
"stall[:MS] (default 5, needs -C and prio >= 1), exit.\n"
"\n"
"EXAMPLES:\n"
"    rtsup-loadgen -n 2 -c 3000 -s -        # clean load, summary on stdout\n"
"    rtsup-loadgen -r 0 -c 500              # unprivileged, SCHED_OTHER\n"
"    rtsup-loadgen -C 0,1 -f overrun@100 -f mmap/500,thread=1 \\\n"
"        -f pagefault:3@50 -f block@70 -f stall:5@300,thread=0 -s out.json\n"
"    rtsup-loadgen --relative --start-delay 2000 -f exit@10,thread=0\n";

static const struct argp_option opts[] = {
	{ "threads", 'n', "N", 0, "Number of periodic threads (default 2)", 0 },
	{ "period", 'P', "US", 0, "Period in microseconds (default 1000)", 0 },
	{ "work", 'w', "US", 0, "Busy work per cycle in us, < period (default 100)", 0 },
	{ "prio", 'r', "N", 0, "SCHED_FIFO priority 1..98, 0 = SCHED_OTHER (default 80)", 0 },
	{ "cpus", 'C', "LIST", 0, "Comma list of CPUs; thread i runs on LIST[i % len]", 0 },
	{ "cycles", 'c', "N", 0, "Cycles per thread (default 1000)", 0 },
	{ "fault", 'f', "SPEC", 0, "Inject a fault (repeatable)", 0 },
	{ "summary", 's', "FILE", 0, "Write the JSON summary to FILE ('-' = stdout)", 0 },
	{ "relative", OPT_RELATIVE, NULL, 0, "Sleep with relative clock_nanosleep", 0 },
	{ "name", OPT_NAME, "PREFIX", 0, "Thread name prefix (default \"lg\")", 0 },
	{ "audit", OPT_AUDIT, NULL, 0, "Count the cycles whose miss or overrun a tracer "
	  "may judge otherwise (two getrusage calls per cycle)", 0 },
	{ "cycle-log", OPT_CYCLE_LOG, "FILE", 0, "Write every cycle's clock reads to FILE "
	  "(text, one line a cycle, with the summary)", 0 },
	{ "start-delay", OPT_START_DELAY, "MS", 0, "Sleep MS before starting threads", 0 },
	{ "wait-file", OPT_WAIT_FILE, "PATH", 0, "Start the threads once PATH exists "
	  "(a tracer creates it when attached; at most 5 minutes)", 0 },
	{ "hold", OPT_HOLD, NULL, 0, "After the last cycle, park the threads in one more "
	  "clock_nanosleep, write the summary and wait for SIGTERM/SIGINT", 0 },
	{ NULL, 'h', NULL, OPTION_HIDDEN, "Show the full help", 0 },
	{},
};

/* parse_arg - argp callback */
static error_t parse_arg(int key, char *arg, struct argp_state *state)
{
	switch (key) {
	case 'n':
		cfg.threads = parse_long("--threads", arg, 1, MAX_THREADS);
		break;
	case 'P':
		cfg.period_us = parse_long("--period", arg, 1, MAX_PERIOD_US);
		break;
	case 'w':
		cfg.work_us = parse_long("--work", arg, 0, MAX_PERIOD_US);
		break;
	case 'r':
		cfg.prio = parse_long("--prio", arg, 0, 98);
		break;
	case 'C':
		parse_cpus(arg);
		break;
	case 'c':
		cfg.cycles = parse_long("--cycles", arg, 1, MAX_CYCLES);
		break;
	case 'f':
		parse_fault(arg);
		break;
	case 's':
		cfg.summary = arg;
		break;
	case OPT_RELATIVE:
		cfg.relative = true;
		break;
	case OPT_AUDIT:
		cfg.audit = true;
		break;
	case OPT_CYCLE_LOG:
		cfg.cycle_log = arg;
		break;
	case OPT_HOLD:
		cfg.hold = true;
		break;
	case OPT_WAIT_FILE:
		cfg.wait_file = arg;
		break;
	case OPT_NAME:
		if (!*arg || strlen(arg) > 15)
			die("--name", "prefix must be 1..15 characters");
		cfg.name = arg;
		break;
	case OPT_START_DELAY:
		cfg.start_delay_ms = parse_long("--start-delay", arg, 0, 3600000L);
		break;
	case 'h':
		argp_state_help(state, stderr, ARGP_HELP_STD_HELP);
		break;
	case ARGP_KEY_ARG:
		die(arg, "unexpected argument");
	case ARGP_KEY_END:
		if (cfg.work_us >= cfg.period_us)
			die("--work", "%ld us must be < period (%ld us)",
			    cfg.work_us, cfg.period_us);
		check_faults();
		break;
	default:
		return ARGP_ERR_UNKNOWN;
	}
	return 0;
}

/* applies - does fault @f target worker @w */
static inline bool applies(const struct fault *f, const struct worker *w)
{
	return f->thread < 0 || f->thread == w->index;
}

/* fires - does fault @f fire at cycle @c */
static inline bool fires(const struct fault *f, long c)
{
	return f->every ? c % f->every == f->every - 1 : c == f->at;
}

/* nr_fires - how many times @f fires in a full run */
static long nr_fires(const struct fault *f)
{
	if (f->every)
		return cfg.cycles / f->every;
	return f->at < cfg.cycles;
}

/* inject_block - block once on our lock word held by the helper */
static void inject_block(struct worker *w, long us)
{
	/* the helper takes the lock ahead of time; normally no spin at all */
	while (!__atomic_load_n(&w->held, __ATOMIC_ACQUIRE))
		;
	w->deadline = now_ns() + us * 1000;
	__atomic_store_n(&w->req, 1, __ATOMIC_RELEASE);
	__atomic_fetch_add(&helper_seq, 1, __ATOMIC_RELEASE);
	futex(&helper_seq, FUTEX_WAKE_PRIVATE, 1, NULL);
	w->sc[SC_FUTEX]++;
	/* glibc-style lock, open coded so that every futex call is counted */
	if (!__atomic_compare_exchange_n(&w->lock, &(int){ 0 }, 1, false,
					 __ATOMIC_ACQUIRE, __ATOMIC_RELAXED)) {
		while (__atomic_exchange_n(&w->lock, 2, __ATOMIC_ACQUIRE)) {
			/*
			 * a wait slept unless the word changed first (EAGAIN): late by
			 * the block's length (a preemption, an emulated CPU's stall),
			 * the helper had let go and there is no block to see
			 */
			if (!futex(&w->lock, FUTEX_WAIT_PRIVATE, 2, NULL) || errno == EINTR)
				w->blocks++;
			w->sc[SC_FUTEX]++;
		}
	}
	/* the helper never sleeps on the lock word: release without a wake */
	__atomic_store_n(&w->lock, 0, __ATOMIC_RELEASE);
	__atomic_store_n(&w->done, 1, __ATOMIC_RELEASE);
	w->blocks_injected++;
}

/* inject_one - inject fault @f; returns the work length for this cycle */
static int64_t inject_one(struct worker *w, const struct fault *f, long c,
			  int64_t work, bool *quit)
{
	void *p;
	int fd;
	long i;

	switch (f->kind) {
	case K_OVERRUN:
		w->overruns++;
		if ((int64_t)f->arg * 1000 > work)
			work = (int64_t)f->arg * 1000;
		break;
	case K_MMAP:
		p = mmap(NULL, page_size, PROT_READ | PROT_WRITE,
			 MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
		w->sc[SC_MMAP]++;
		if (p != MAP_FAILED) {
			munmap(p, page_size);
			w->sc[SC_MUNMAP]++;
		}
		break;
	case K_WRITE:
		/* the syscall was issued whatever it returns */
		(void)!write(tmp_fd, write_buf, WRITE_LEN);
		w->sc[SC_WRITE]++;
		break;
	case K_OPENAT:
		fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
		w->sc[SC_OPENAT]++;
		if (fd >= 0) {
			close(fd);
			w->sc[SC_CLOSE]++;
		}
		break;
	case K_PAGEFAULT:
		/* write, not read: a read would map the zero page first */
		for (i = 0; i < f->arg; i++) {
			*(volatile char *)w->pf_next = 1;
			w->pf_next += page_size;
			w->page_faults++;
		}
		break;
	case K_BLOCK:
		inject_block(w, f->arg);
		break;
	case K_STALL:
		/* our hog has prio + 1 on our CPU: it preempts us right here */
		__atomic_store_n(&w->hog_trigger, (int)f->arg, __ATOMIC_RELEASE);
		futex(&w->hog_trigger, FUTEX_WAKE_PRIVATE, 1, NULL);
		w->sc[SC_FUTEX]++;
		w->stalls++;
		break;
	case K_EXIT:
		*quit = true;
		break;
	}
	if (w->nlog < w->maxlog)
		w->log[w->nlog++] = (struct inj){ c, f->kind, f->arg };
	return work;
}

/* inject - inject this cycle's faults, stalls first; returns work length */
static int64_t inject(struct worker *w, long c, bool *quit)
{
	int64_t work = cfg.work_us * 1000;
	int pass, i;

	/* a stall is triggered at the very start of the work */
	for (pass = 0; pass < 2; pass++) {
		for (i = 0; i < cfg.nfaults; i++) {
			const struct fault *f = &cfg.faults[i];

			if ((f->kind == K_STALL) != (pass == 0) ||
			    !applies(f, w) || !fires(f, c))
				continue;
			work = inject_one(w, f, c, work, quit);
		}
	}
	return work;
}

/* touch_stack - prefault 64 KiB of stack so no cycle faults on it */
static void __attribute__((noinline)) touch_stack(void)
{
	volatile char buf[STACK_TOUCH];
	size_t i;

	for (i = 0; i < sizeof(buf); i += 1024)
		buf[i] = 0;
}

static int workers_done;	/* threads past their last cycle */

/*
 * --audit: the race between our clock reads and a tracer's syscall hooks.
 * The tracer judges a miss at the delimiter's entry (is the release past?)
 * and an overrun from the switch-in that released the cycle to the next
 * entry; we read the clock just before and just after those points. Only
 * the syscall path lies between (a few us), unless the thread is preempted
 * there. A cycle is "near" when the tracer may judge it otherwise than we
 * did: it is within RACE_NS of the limit, or the thread was preempted in
 * an edge window (involuntary switches read with getrusage around it).
 */
#define RACE_NS 50000	/* syscall entry or exit path plus an interrupt, with margin */

/* rusage_switches - this thread's context switches so far */
static void rusage_switches(long *vol, long *invol)
{
	struct rusage ru;

	getrusage(RUSAGE_THREAD, &ru);
	*vol = ru.ru_nvcsw;
	*invol = ru.ru_nivcsw;
}

/*
 * run_delay - the time this thread has waited on a run queue so far
 * (its schedstat's second field, CONFIG_SCHED_INFO), -1 when unknown. A
 * sleep that ended waited there from its wakeup to its switch-in.
 */
static int64_t run_delay(int fd)
{
	char buf[96];
	long long run, wait;
	ssize_t n;

	if (fd < 0 || (n = pread(fd, buf, sizeof(buf) - 1, 0)) <= 0)
		return -1;
	buf[n] = 0;
	return sscanf(buf, "%lld %lld", &run, &wait) == 2 ? wait : -1;
}

/*
 * One cycle's overrun verdict, settled once its end edge is known. The
 * tracer's cycle starts at the switch-in that released it: after the
 * release and after our read before the sleep, and later still by the
 * time it then waited on a run queue. What runs between that switch-in
 * and our start read (the wake path, an interrupt, a hypervisor's steal:
 * 1 ms and more, a few times in 2000 cycles under the noise injector) is
 * in its cycle and not in our span: 'start_lo' is the earliest it can be.
 */
struct pending_overrun {
	bool valid, seen, near;		/* near: preempted at its start */
	int64_t start_lo;		/* the earliest the tracer's start can be */
};

/*
 * audit_overrun - count a finished cycle a tracer may call an overrun when
 * we did not: preempted at an edge, or its longest span a tracer can see,
 * from start_lo to our read before the next sleep ('end_read', that
 * sleep's entry follows within RACE_NS), is over the period.
 */
static void audit_overrun(struct worker *w, const struct pending_overrun *p, bool end_edge,
			  int64_t end_read, int64_t period)
{
	if (p->valid && !p->seen &&
	    (p->near || end_edge || end_read + RACE_NS - p->start_lo > period))
		w->overruns_near++;
}

/*
 * cycle_start_lo - the earliest a tracer's start of a cycle can be: its
 * switch-in, after our read before the sleep ('before'); after the release
 * too, if it slept (a sleep that found its release past returns at once),
 * by the time it 'waited' on a run queue since. Never after our 'start'.
 */
static int64_t cycle_start_lo(int64_t release, int64_t before, int64_t start, int64_t waited)
{
	int64_t lo = release + waited > before ? release + waited : before;

	return lo < start ? lo : start;
}

/* worker_main - one periodic RT thread, cyclictest style */
static void *worker_main(void *arg)
{
	struct worker *w = arg;
	int64_t period = cfg.period_us * 1000, next, now, start, work, span;
	int64_t pre1 = 0, pre2 = 0;	/* the clock before the sleep, one and two cycles ago */
	int64_t rd_start = -1, rd_end = -1;	/* run_delay() at start, after the work */
	int64_t waited = 0;	/* on a run queue between the two: before the switch-in */
	long vol0 = 0, vol = 0, inv = 0, inv_end = 0;
	struct pending_overrun prev = { 0 };
	bool late, edge = false;
	struct sched_param sp;
	struct timespec ts;
	bool quit = false;
	char name[32];
	sigset_t all;
	long c;

	/* process signals go to the main thread, never into a cycle */
	sigfillset(&all);
	pthread_sigmask(SIG_BLOCK, &all, NULL);
	snprintf(name, sizeof(name), "%s-%d", cfg.name, w->index);
	prctl(PR_SET_NAME, name);
	prctl(PR_GET_NAME, w->comm);
	/* SCHED_OTHER runs would otherwise wake up to 50 us late */
	prctl(PR_SET_TIMERSLACK, 1UL);
	w->tid = gettid();
	pthread_getschedparam(pthread_self(), &w->policy, &sp);
	w->prio = sp.sched_priority;
	touch_stack();
	now_ns();	/* warm the vDSO */

	if (cfg.audit) {
		/* closed by main: a close here would be in the last cycle */
		w->sched_fd = open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC);
		rusage_switches(&vol0, &inv_end);
		rd_end = run_delay(w->sched_fd);
	}
	next = now_ns() + period;
	for (c = 0; c < cfg.cycles; c++) {
		now = now_ns();
		late = next <= now;
		if (late)
			w->misses++;
		/* exactly one clock_nanosleep per cycle, even when late */
		if (cfg.relative) {
			ts = ns_to_ts(next > now ? next - now : 0);
			clock_nanosleep(CLOCK_MONOTONIC, 0, &ts, NULL);
		} else {
			ts = ns_to_ts(next);
			clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
		}
		/*
		 * The start read comes first: a preemption after it is inside
		 * our span, one before it is in the switch count read next (read
		 * first, a preemption between the two reads would be in the
		 * tracer's cycle only, and in neither count).
		 */
		start = now_ns();
		if (c >= 2 && start - pre2 > w->max_start_span)
			w->max_start_span = start - pre2;
		pre2 = pre1;
		pre1 = now;
		if (cfg.audit) {
			/* preempted between the last end read and this cycle's start? */
			rusage_switches(&vol, &inv);
			rd_start = run_delay(w->sched_fd);
			waited = rd_start >= 0 && rd_end >= 0 ? rd_start - rd_end : 0;
			edge = inv > inv_end;
			if (!late && !cfg.relative && (next - now < RACE_NS || edge))
				w->misses_near++;
			audit_overrun(w, &prev, edge, now, period);
		}
		if (w->clog)
			w->clog[c] = (struct cycle_rec){ .release = next, .before = now,
				.start = start, .invol = inv, .vol = vol,
				.rd_before = rd_end, .rd_start = rd_start };
		work = w->maxlog ? inject(w, c, &quit) : cfg.work_us * 1000;
		while (now_ns() - start < work)
			;
		if (cfg.audit) {
			rusage_switches(&vol, &inv_end);
			rd_end = run_delay(w->sched_fd);
		}
		/* what a tracer sees: the work took longer than a period (stalls too) */
		span = now_ns() - start;
		if (w->clog)
			w->clog[c].end = start + span;
		if (span > period)
			w->overruns_seen++;
		prev = (struct pending_overrun){ .valid = true, .seen = span > period,
			.near = edge, .start_lo = cycle_start_lo(next, now, start, waited) };
		w->cycles++;
		if (quit) {
			w->exited = true;
			w->exit_cycle = c;
			break;
		}
		next += period;	/* never skip missed periods */
	}
	if (cfg.audit) {
		/* the last cycle's end edge is the next delimiter, never observed */
		audit_overrun(w, &prev, true, 0, period);
		rusage_switches(&vol, &inv);
		w->vol_switches = vol - vol0;
	}
	/* the last cycle never finishes: its predecessor's start is the last, until we end */
	now = now_ns();
	if (w->clog)	/* the park's sleep ends the last cycle */
		w->clog[w->cycles].before = now;
	if (w->cycles >= 2 && !cfg.hold && now - pre2 > w->max_start_span)
		w->max_start_span = now - pre2;
	__atomic_fetch_add(&workers_done, 1, __ATOMIC_RELEASE);
	/*
	 * --hold: one more delimiter call closes the last cycle, so a tracer
	 * sees whole cycles only; the process ends while the thread sleeps.
	 */
	while (cfg.hold && !quit) {
		ts = ns_to_ts(now_ns() + 3600 * 1000000000LL);
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
	}
	return NULL;
}

enum hstate { H_HELD, H_PENDING, H_RELEASED };

/* helper_step - advance @w's lock; returns when the helper must look again */
static int64_t helper_step(struct worker *w, int64_t now)
{
	int exp = 0;

	switch (w->hstate) {
	case H_HELD:
		if (!__atomic_exchange_n(&w->req, 0, __ATOMIC_ACQUIRE))
			return INT64_MAX;
		w->hstate = H_PENDING;
		/* fall through */
	case H_PENDING:
		if (now < w->deadline)
			return w->deadline;
		__atomic_store_n(&w->held, 0, __ATOMIC_RELEASE);
		if (__atomic_exchange_n(&w->lock, 0, __ATOMIC_RELEASE) == 2)
			futex(&w->lock, FUTEX_WAKE_PRIVATE, 1, NULL);
		w->hstate = H_RELEASED;
		/* fall through */
	case H_RELEASED:
		/* poll: a wake from the RT thread would cost it a syscall */
		if (!__atomic_load_n(&w->done, __ATOMIC_ACQUIRE) ||
		    !__atomic_compare_exchange_n(&w->lock, &exp, 1, false,
				__ATOMIC_ACQUIRE, __ATOMIC_RELAXED))
			return now + 20000;
		__atomic_store_n(&w->done, 0, __ATOMIC_RELAXED);
		__atomic_store_n(&w->held, 1, __ATOMIC_RELEASE);
		w->hstate = H_HELD;
	}
	return INT64_MAX;
}

/* helper_main - SCHED_OTHER thread holding the lock of every RT thread and
 * releasing each one US after its request, concurrently */
static void *helper_main(void *arg)
{
	int64_t now, next, t;
	struct timespec ts;
	char name[32];
	int i, seq;

	(void)arg;
	snprintf(name, sizeof(name), "%s-helper", cfg.name);
	prctl(PR_SET_NAME, name);
	prctl(PR_SET_TIMERSLACK, 1UL);
	helper_tid = gettid();
	/* hold every lock ahead of time: RT threads never wait for us to run */
	for (i = 0; i < cfg.threads; i++) {
		workers[i].lock = 1;
		__atomic_store_n(&workers[i].held, 1, __ATOMIC_RELEASE);
	}
	pthread_barrier_wait(&aux_barrier);
	while (!__atomic_load_n(&helper_stop, __ATOMIC_ACQUIRE)) {
		seq = __atomic_load_n(&helper_seq, __ATOMIC_ACQUIRE);
		now = now_ns();
		next = INT64_MAX;
		for (i = 0; i < cfg.threads; i++) {
			t = helper_step(&workers[i], now);
			next = t < next ? t : next;
		}
		/* absolute CLOCK_MONOTONIC timeout; a new request wakes us */
		ts = ns_to_ts(next);
		futex(&helper_seq, FUTEX_WAIT_BITSET_PRIVATE, seq,
		      next == INT64_MAX ? NULL : &ts);
	}
	return NULL;
}

/* hog_main - starve our victim: spin MS ms at prio + 1 on its CPU */
static void *hog_main(void *arg)
{
	struct worker *w = arg;
	char name[32];
	int64_t end;
	int ms;

	snprintf(name, sizeof(name), "%s-hog-%d", cfg.name, w->index);
	prctl(PR_SET_NAME, name);
	w->hog_tid = gettid();
	pthread_barrier_wait(&aux_barrier);
	for (;;) {
		ms = __atomic_exchange_n(&w->hog_trigger, 0, __ATOMIC_ACQUIRE);
		if (ms < 0)
			break;
		if (!ms) {
			futex(&w->hog_trigger, FUTEX_WAIT_PRIVATE, 0, NULL);
			continue;
		}
		end = now_ns() + ms * 1000000LL;
		while (now_ns() < end)
			;
	}
	return NULL;
}

/* start_thread - create a thread with explicit policy, prio and CPU */
static void start_thread(pthread_t *pt, void *(*fn)(void *), void *arg,
			 int prio, int cpu)
{
	struct sched_param sp = { .sched_priority = prio };
	pthread_attr_t attr;
	cpu_set_t set;
	int err;

	pthread_attr_init(&attr);
	pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
	pthread_attr_setschedpolicy(&attr, prio ? SCHED_FIFO : SCHED_OTHER);
	pthread_attr_setschedparam(&attr, &sp);
	if (cpu >= 0) {
		CPU_ZERO(&set);
		CPU_SET(cpu, &set);
		pthread_attr_setaffinity_np(&attr, sizeof(set), &set);
	}
	err = pthread_create(pt, &attr, fn, arg);
	if (err)
		die("pthread_create", "%s%s", strerror(err), err == EPERM ?
		    " (SCHED_FIFO needs privilege, try -r 0)" : "");
	pthread_attr_destroy(&attr);
}

#define MAX_INJ		(1L << 24)
#define MAX_PF_PAGES	(1L << 24)

/* plan - size and prefault per-thread logs from the fault plan */
static long plan(void)
{
	long pages = 0, n;
	int i, j;

	workers = aligned_alloc(64, cfg.threads * sizeof(*workers));
	if (!workers)
		die("workers", "out of memory");
	memset(workers, 0, cfg.threads * sizeof(*workers));
	for (i = 0; i < cfg.threads; i++) {
		struct worker *w = &workers[i];

		w->index = i;
		w->cpu = cfg.ncpus ? cfg.cpus[i % cfg.ncpus] : -1;
		w->exit_cycle = -1;
		w->hog_tid = -1;
		w->sched_fd = -1;
		/* one more for the read before the park's sleep */
		if (cfg.cycle_log && !(w->clog = calloc(cfg.cycles + 1, sizeof(*w->clog))))
			die("--cycle-log", "out of memory for %ld cycles", cfg.cycles);
		for (j = 0; j < cfg.nfaults; j++) {
			const struct fault *f = &cfg.faults[j];

			if (!applies(f, w))
				continue;
			n = nr_fires(f);
			w->maxlog += n;
			if (f->kind == K_PAGEFAULT)
				w->pf_pages += n * f->arg;
			if (f->kind == K_STALL && n)
				w->has_hog = true;
			if (w->maxlog > MAX_INJ || w->pf_pages > MAX_PF_PAGES)
				die("--fault", "plan too large for thread %d "
				    "(max %ld injections, %ld pages)", i,
				    MAX_INJ, MAX_PF_PAGES);
		}
		pages += w->pf_pages;
		if (pages > MAX_PF_PAGES)
			die("--fault", "page-fault plan needs over %ld pages",
			    MAX_PF_PAGES);
		if (!w->maxlog)
			continue;
		w->log = malloc(w->maxlog * sizeof(*w->log));
		if (!w->log)
			die("--fault", "out of memory");
		/* touch it now so logging never faults inside a cycle */
		memset(w->log, 0, w->maxlog * sizeof(*w->log));
	}
	return pages;
}

/* open_tmp - regular file for write faults, opened outside any cycle */
static void open_tmp(void)
{
	const char *dir = getenv("TMPDIR");
	char path[PATH_MAX];

	if (!dir || !*dir)
		dir = "/tmp";
	tmp_fd = open(dir, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
	if (tmp_fd >= 0)
		return;
	snprintf(path, sizeof(path), "%s/rtsup-loadgen.XXXXXX", dir);
	tmp_fd = mkstemp(path);
	if (tmp_fd < 0)
		die(path, "cannot create temporary file: %s", strerror(errno));
	unlink(path);
}

/* nop_thread - thread that ends at once, see warm_up() */
static void *nop_thread(void *arg)
{
	return arg;
}

/* warm_up - run each injection path once so its first use in a cycle
 * neither resolves a PLT slot nor faults in library text */
static void warm_up(void)
{
	struct timespec ts = { 0, 0 };
	int fd, word = 0;
	pthread_t pt;
	void *p;

	/* also map the thread exit path, which an 'exit' fault runs */
	if (!pthread_create(&pt, NULL, nop_thread, NULL))
		pthread_join(pt, NULL);

	p = mmap(NULL, page_size, PROT_READ | PROT_WRITE,
		 MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
	if (p != MAP_FAILED)
		munmap(p, page_size);
	fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
	if (fd >= 0)
		close(fd);
	if (tmp_fd >= 0 && write(tmp_fd, write_buf, WRITE_LEN) < 0)
		die("write", "temporary file: %s", strerror(errno));
	futex(&word, FUTEX_WAKE_PRIVATE, 1, NULL);
	/* first write to this .bss page must not happen inside a cycle */
	__atomic_store_n(&helper_seq, 0, __ATOMIC_RELAXED);
	clock_nanosleep(CLOCK_MONOTONIC, 0, &ts, NULL);
	now_ns();
}

/* map_pf_region - never-touched, unlocked, small-page region for page faults */
static void map_pf_region(long pages)
{
	char *p;
	int i;

	if (!pages)
		return;
	pf_region = mmap(NULL, pages * page_size, PROT_READ | PROT_WRITE,
			 MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
	if (pf_region == MAP_FAILED)
		die("mmap", "page-fault region: %s", strerror(errno));
	/*
	 * one touched page must be exactly one fault: no THP, no mTHP. EINVAL:
	 * a kernel without THP (Debian's arm64 PREEMPT_RT), where it is so anyway
	 */
	if (madvise(pf_region, pages * page_size, MADV_NOHUGEPAGE) && errno != EINVAL)
		die("madvise", "MADV_NOHUGEPAGE: %s", strerror(errno));
	for (p = pf_region, i = 0; i < cfg.threads; i++) {
		workers[i].pf_next = p;
		p += workers[i].pf_pages * page_size;
	}
}

/* policy_name - name of a scheduling policy */
static const char *policy_name(int policy)
{
	switch (policy) {
	case SCHED_FIFO:
		return "SCHED_FIFO";
	case SCHED_RR:
		return "SCHED_RR";
	case SCHED_OTHER:
		return "SCHED_OTHER";
	}
	return "unknown";
}

/* thread_json - summary object of one worker */
static json_t *thread_json(const struct worker *w)
{
	json_t *sc = json_object(), *faults = json_array(), *o;
	long i;

	for (i = 0; i < NR_SC; i++)
		if (w->sc[i])
			json_object_set_new(sc, sc_names[i], json_integer(w->sc[i]));
	for (i = 0; i < w->nlog; i++)
		json_array_append_new(faults, json_pack("{s:I, s:s, s:I}",
			"cycle", (json_int_t)w->log[i].cycle,
			"kind", kind_names[w->log[i].kind],
			"arg", (json_int_t)w->log[i].arg));
	o = json_pack("{s:i, s:i, s:s, s:s, s:i, s:i, s:I, s:I, s:I, s:o,"
		      " s:I, s:I, s:I, s:I, s:I, s:b, s:I, s:o, s:i}",
		      "index", w->index, "tid", (int)w->tid, "comm", w->comm,
		      "policy", policy_name(w->policy), "prio", w->prio,
		      "cpu", w->cpu, "cycles", (json_int_t)w->cycles,
		      "deadline_misses", (json_int_t)w->misses,
		      "overruns", (json_int_t)w->overruns, "syscalls", sc,
		      "overruns_seen", (json_int_t)w->overruns_seen,
		      "page_faults", (json_int_t)w->page_faults,
		      "blocks", (json_int_t)w->blocks,
		      "blocks_injected", (json_int_t)w->blocks_injected,
		      "stalls", (json_int_t)w->stalls, "exited", (int)w->exited,
		      "exit_cycle", (json_int_t)w->exit_cycle, "faults", faults,
		      "hog_tid", (int)w->hog_tid);
	if (!o)
		die("json", "cannot build the summary");
	if (cfg.audit)
		json_object_update_new(o, json_pack("{s:I, s:I, s:I}",
			"deadline_misses_near", (json_int_t)w->misses_near,
			"overruns_near", (json_int_t)w->overruns_near,
			"voluntary_switches", (json_int_t)w->vol_switches));
	json_object_set_new(o, "max_start_span_ns", json_integer((json_int_t)w->max_start_span));
	return o;
}

/* write_summary - dump the JSON summary to @out */
static void write_summary(FILE *out, bool locked)
{
	json_t *threads = json_array(), *root;
	int i;

	for (i = 0; i < cfg.threads; i++)
		json_array_append_new(threads, thread_json(&workers[i]));
	root = json_pack("{s:i, s:I, s:I, s:b, s:i, s:I, s:b, s:i, s:o}",
			 "pid", (int)getpid(),
			 "period_ns", (json_int_t)cfg.period_us * 1000,
			 "work_ns", (json_int_t)cfg.work_us * 1000,
			 "relative", (int)cfg.relative, "prio", (int)cfg.prio,
			 "cycles_requested", (json_int_t)cfg.cycles,
			 "mlocked", (int)locked, "helper_tid", (int)helper_tid,
			 "threads", threads);
	if (!root)
		die("json", "cannot build the summary");
	if (json_dumpf(root, out, JSON_INDENT(2)) || fputc('\n', out) == EOF ||
	    (out == stdout ? fflush(out) : fclose(out)))
		die("--summary", "%s: cannot write: %s", cfg.summary,
		    strerror(errno));
	json_decref(root);
}

/* write_cycle_log - every thread's cycles, one line each (--cycle-log) */
static void write_cycle_log(FILE *f)
{
	int i;
	long c;

	fprintf(f, "# tid cycle release before start end invol vol rd_before rd_start\n");
	for (i = 0; i < cfg.threads; i++) {
		const struct worker *w = &workers[i];

		for (c = 0; c < w->cycles; c++) {
			const struct cycle_rec *r = &w->clog[c];

			fprintf(f, "%d %ld %lld %lld %lld %lld %ld %ld %lld %lld\n", (int)w->tid,
				c, (long long)r->release, (long long)r->before,
				(long long)r->start, (long long)r->end, r->invol, r->vol,
				(long long)r->rd_before, (long long)r->rd_start);
		}
		/* the read before the sleep that ended the last cycle (0: none) */
		fprintf(f, "%d %ld 0 %lld 0 0 0 0 0 0\n", (int)w->tid, c,
			(long long)w->clog[c].before);
	}
	if (fclose(f))
		die("--cycle-log", "%s: cannot write: %s", cfg.cycle_log, strerror(errno));
}

/* main - parse, prepare memory, run the threads, report */
int main(int argc, char **argv)
{
	static const struct argp argp = {
		.options = opts, .parser = parse_arg, .doc = doc,
	};
	bool need_tmp = false, need_helper = false, locked;
	pthread_t helper;
	FILE *out = NULL, *clog_out = NULL;
	int i, naux = 0;
	long pages;

	argp_err_exit_status = 1;
	if (argp_parse(&argp, argc, argv, 0, NULL, NULL))
		return 1;
	page_size = sysconf(_SC_PAGESIZE);
	/* open the summary now: a bad path fails before the run, not after */
	if (cfg.summary) {
		out = strcmp(cfg.summary, "-") ? fopen(cfg.summary, "w") : stdout;
		if (!out)
			die("--summary", "%s: %s", cfg.summary, strerror(errno));
	}
	if (cfg.cycle_log && !(clog_out = fopen(cfg.cycle_log, "w")))
		die("--cycle-log", "%s: %s", cfg.cycle_log, strerror(errno));
	for (i = 0; i < cfg.nfaults; i++) {
		need_tmp |= cfg.faults[i].kind == K_WRITE;
		need_helper |= cfg.faults[i].kind == K_BLOCK;
	}
	pages = plan();
	if (need_tmp)
		open_tmp();
	warm_up();
	/* lock what exists now; the page-fault region is mapped after it */
	locked = !mlockall(MCL_CURRENT);
	if (!locked)
		fprintf(stderr, PROG ": warning: mlockall: %s, continuing\n",
			strerror(errno));
	map_pf_region(pages);
	if (cfg.start_delay_ms)
		sleep_us(cfg.start_delay_ms * 1000);
	/* a slow attach (an emulated guest verifies programs for seconds) */
	for (i = 0; cfg.wait_file && access(cfg.wait_file, F_OK) && i < 30000; i++)
		sleep_us(10000);
	if (cfg.wait_file && access(cfg.wait_file, F_OK))
		die("--wait-file", "%s did not appear in 5 minutes", cfg.wait_file);

	for (i = 0; i < cfg.threads; i++)
		naux += workers[i].has_hog;
	naux += need_helper;
	if (naux) {
		pthread_barrier_init(&aux_barrier, NULL, naux + 1);
		if (need_helper)
			start_thread(&helper, helper_main, NULL, 0, -1);
		for (i = 0; i < cfg.threads; i++)
			if (workers[i].has_hog)
				start_thread(&workers[i].hog, hog_main, &workers[i],
					     cfg.prio + 1, workers[i].cpu);
		/* helper holds its locks and hogs sleep before any cycle */
		pthread_barrier_wait(&aux_barrier);
	}
	for (i = 0; i < cfg.threads; i++)
		start_thread(&workers[i].pt, worker_main, &workers[i], cfg.prio,
			     workers[i].cpu);
	if (cfg.hold) {
		/* parked threads never return: wait until all are past their cycles */
		while (__atomic_load_n(&workers_done, __ATOMIC_ACQUIRE) < cfg.threads)
			sleep_us(10000);
		for (i = 0; i < cfg.threads; i++)
			if (workers[i].exited)
				pthread_join(workers[i].pt, NULL);
	} else {
		for (i = 0; i < cfg.threads; i++)
			pthread_join(workers[i].pt, NULL);
	}

	if (need_helper) {
		__atomic_store_n(&helper_stop, 1, __ATOMIC_RELEASE);
		__atomic_fetch_add(&helper_seq, 1, __ATOMIC_RELEASE);
		futex(&helper_seq, FUTEX_WAKE_PRIVATE, 1, NULL);
		pthread_join(helper, NULL);
	}
	for (i = 0; i < cfg.threads; i++) {
		if (!workers[i].has_hog)
			continue;
		__atomic_store_n(&workers[i].hog_trigger, -1, __ATOMIC_RELEASE);
		futex(&workers[i].hog_trigger, FUTEX_WAKE_PRIVATE, 1, NULL);
		pthread_join(workers[i].hog, NULL);
	}
	for (i = 0; i < cfg.threads; i++)
		if (workers[i].sched_fd >= 0)
			close(workers[i].sched_fd);
	/* before the summary: whoever waits for the summary finds the log whole */
	if (clog_out)
		write_cycle_log(clog_out);
	if (out)
		write_summary(out, locked);
	if (cfg.hold) {
		sigset_t set;
		int sig;

		sigemptyset(&set);
		sigaddset(&set, SIGTERM);
		sigaddset(&set, SIGINT);
		sigprocmask(SIG_BLOCK, &set, NULL);
		sigwait(&set, &sig);
	}
	return 0;
}
