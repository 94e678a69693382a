// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * rtsup-cansim - simulated CAN nodes on a SocketCAN interface, with fault
 * injection.
 *
 * Each node is one periodic thread (clock_nanosleep TIMER_ABSTIME) that
 * writes frames on its own raw socket; with --canopen the nodes also send
 * boot-up, heartbeats and TPDOs, and a receive thread answers their SDO
 * requests.  Every frame is counted once its write() succeeded, so the JSON
 * summary is the exact truth the tracer's CAN numbers are compared against.
 */
#include <argp.h>
#include <errno.h>
#include <jansson.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define PROG		"rtsup-cansim"
#define MAX_NODES	127
#define MAX_PERIOD_MS	60000L
#define MAX_DURATION_MS	(24 * 3600 * 1000L)
#define MAX_AT		1000000000L
#define MAX_BURST	100000L
#define STACK_SIZE	(256 * 1024)
#define STACK_TOUCH	(64 * 1024)
#define SDO_POLL_MS	100
#define SDO_ABORT_CMD	0x05040001u	/* CiA 301: command specifier not valid */

/* CANopen function codes (CiA 301 predefined connection set) */
#define CO_EMCY		0x080
#define CO_TPDO1	0x180
#define CO_SDO_TX	0x580
#define CO_SDO_RX	0x600
#define CO_HEARTBEAT	0x700
#define NMT_BOOTUP	0x00
#define NMT_OPERATIONAL	0x05

struct at_arg {
	long at;		/* after the node's AT-th cycle */
	long arg;		/* burst: extra frames; emcy: error code */
};

struct node {
	/* configuration */
	char name[16];
	canid_t id;		/* plain: CAN id with CAN_EFF_FLAG; CANopen: 0x180 + n */
	int co_id;		/* CANopen node id 1..127, 0 in plain mode */
	long period_ms;
	int len;
	bool never;
	long stop_at;		/* cycles; -1 = never stops */
	long hbstop_at;		/* heartbeats; -1 = never stops */
	struct at_arg *bursts, *emcys;
	int nbursts, nemcys;
	/* run time, written by the node's thread */
	int sock;
	pthread_t pt;
	bool started;
	pid_t tid;
	char comm[16];
	int policy, prio;
	long cycles;		/* atomic: the SDO thread reads it */
	uint64_t seq;		/* next sequence number of the main id */
	long hb_tries;		/* heartbeats attempted, for hbstop@N */
	int stopped;		/* atomic: the SDO thread reads it */
	long stopped_after;
	uint64_t sent_main, sent_bootup, sent_hb, sent_emcy, sent_burst;
	uint64_t bytes, send_errors;
	int last_errno;
	int64_t first_ns, last_ns;
	struct at_arg *emcy_log;	/* sent EMCYs (cycle, code), sized by the plan */
	int nemcy_log;
	/* run time, written by the SDO thread */
	uint64_t sent_sdo, sdo_bytes, sdo_received, sdo_answered, sdo_aborts;
	uint64_t sdo_ignored, sdo_send_errors;
} __attribute__((aligned(64)));

struct errframe {
	long at_ms;
	canid_t class;
	int data1;
	const char *spec;
	/* what happened */
	bool sent;
	int err;
	int64_t sent_ns;
};

static struct config {
	const char *ifname;
	long duration_ms;	/* 0 = until SIGINT/SIGTERM */
	long prio;
	bool canopen;
	const char *summary;
	struct node nodes[MAX_NODES];
	int nnodes;
	char **faults;		/* per-node fault specs, resolved at the end */
	int nfaults;
	struct errframe *errs;
	int nerrs;
} cfg;

static int ifindex;
static int stop_all;			/* atomic: end of the run */
static pthread_barrier_t start_barrier;
static int64_t t0_ns, end_ns;
static struct timespec t0_wall, end_wall;
static pthread_t sdo_pt;
static pid_t sdo_tid = -1;
static int sdo_sock = -1, err_sock = -1;
static uint64_t sdo_drops, sdo_unknown;
static bool locked;

/* die - print one line "rtsup-cansim: what: why" and exit 1 */
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

/* now_ns - CLOCK_MONOTONIC in ns, the clock of the tracer's timestamps */
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

/* parse_num - strict "0x" hex or decimal parse of @s into [min, max] or die;
 * @hex8 (may be NULL) tells whether it was written with exactly 8 hex digits */
static long parse_num(const char *what, const char *s, long min, long max, bool *hex8)
{
	bool hex = (s[0] == '0' && (s[1] == 'x' || s[1] == 'X'));
	const char *p = hex ? s + 2 : s;
	size_t digits = strspn(p, hex ? "0123456789abcdefABCDEF" : "0123456789");
	char *end;
	long v;

	/* strtol alone would take "-5", " 5", "+5" and "0x" */
	if (!digits || p[digits])
		die(what, "'%s' is not a valid %snumber", s, hex ? "hex " : "");
	errno = 0;
	v = strtol(p, &end, hex ? 16 : 10);
	if ((errno || v < min || v > max) && hex)
		die(what, "'%s' must be in 0x%lx..0x%lx", s, min, max);
	if (errno || v < min || v > max)
		die(what, "'%s' must be in %ld..%ld", s, min, max);
	if (hex8)
		*hex8 = hex && strlen(p) == 8;
	return v;
}

/* id_text - the tracer's spelling of an identifier: "0x181", "0x18fef100x" */
static void id_text(canid_t id, char *buf, size_t len)
{
	snprintf(buf, len, "0x%x%s", id & (id & CAN_EFF_FLAG ? CAN_EFF_MASK : CAN_SFF_MASK),
		 id & CAN_EFF_FLAG ? "x" : "");
}

/* find_node - the node called @name, or NULL */
static struct node *find_node(const char *name)
{
	int i;

	for (i = 0; i < cfg.nnodes; i++)
		if (!strcmp(cfg.nodes[i].name, name))
			return &cfg.nodes[i];
	return NULL;
}

/* parse_node - NAME:ID:PERIOD_MS[:LEN]; the ID's meaning depends on
 * --canopen, which may come later: checked in check_nodes() */
static void parse_node(const char *arg)
{
	char what[256], *s = strdup(arg), *f[5], *rest;
	struct node *n;
	bool hex8;
	long id;
	int nf = 0;

	if (!s)
		die("--node", "out of memory");
	snprintf(what, sizeof(what), "--node '%s'", arg);
	rest = s;
	/* strsep, not strtok: "a::10" is an error, not "a:10" */
	while (nf < 5 && (f[nf] = strsep(&rest, ":")))
		nf++;
	if (nf < 3 || nf > 4)
		die(what, "expected NAME:ID:PERIOD_MS[:LEN]");
	if (cfg.nnodes == MAX_NODES)
		die(what, "too many nodes (at most %d)", MAX_NODES);
	if (!*f[0] || strlen(f[0]) > 15 ||
	    f[0][strspn(f[0], "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
			"0123456789_.-")])
		die(what, "name must be 1..15 characters of A-Z a-z 0-9 _ . -");
	if (find_node(f[0]))
		die(what, "duplicate node name '%s'", f[0]);
	n = &cfg.nodes[cfg.nnodes++];
	memset(n, 0, sizeof(*n));
	snprintf(n->name, sizeof(n->name), "%s", f[0]);
	id = parse_num(what, f[1], 0, CAN_EFF_MASK, &hex8);
	/* like candump and the config file: 8 hex digits are a 29-bit id */
	n->id = (canid_t)id | (id > CAN_SFF_MASK || hex8 ? CAN_EFF_FLAG : 0);
	n->period_ms = parse_num(what, f[2], 1, MAX_PERIOD_MS, NULL);
	n->len = nf == 4 ? (int)parse_num(what, f[3], 0, CAN_MAX_DLEN, NULL) : CAN_MAX_DLEN;
	n->stop_at = n->hbstop_at = n->stopped_after = -1;
	n->sock = -1;
	n->tid = -1;
	free(s);
}

/* parse_errframe - errframe@MS[:CLASS[:DATA1]] */
static void parse_errframe(const char *arg)
{
	char what[256], *s = strdup(arg), *p, *cls, *d1;
	struct errframe *e;

	if (!s)
		die("--fault", "out of memory");
	snprintf(what, sizeof(what), "--fault '%s'", arg);
	e = realloc(cfg.errs, (cfg.nerrs + 1) * sizeof(*e));
	if (!e)
		die(what, "out of memory");
	cfg.errs = e;
	e = &cfg.errs[cfg.nerrs++];
	memset(e, 0, sizeof(*e));
	e->spec = arg;
	p = s + strlen("errframe@");
	cls = strchr(p, ':');
	if (cls)
		*cls++ = '\0';
	d1 = cls ? strchr(cls, ':') : NULL;
	if (d1)
		*d1++ = '\0';
	e->at_ms = parse_num(what, p, 0, MAX_DURATION_MS, NULL);
	e->class = cls ? (canid_t)parse_num(what, cls, 1, CAN_ERR_MASK, NULL) : CAN_ERR_CRTL;
	/* data[1] is the controller's state: only meaningful with CAN_ERR_CRTL */
	e->data1 = d1 ? (int)parse_num(what, d1, 0, 0xff, NULL) :
		   (e->class & CAN_ERR_CRTL ? CAN_ERR_CRTL_RX_PASSIVE : 0);
	free(s);
}

/* add_at - append an @N[:ARG] fault to a node's list */
static void add_at(struct at_arg **list, int *n, long at, long arg, const char *what)
{
	struct at_arg *l = realloc(*list, (*n + 1) * sizeof(**list));

	if (!l)
		die(what, "out of memory");
	l[*n] = (struct at_arg){ at, arg };
	*list = l;
	(*n)++;
}

/* apply_fault - NAME:KIND[@N[:ARG]], once every node is known */
static void apply_fault(const char *arg)
{
	char what[256], *s = strdup(arg), *kind, *at, *extra;
	struct node *n;
	long a;

	if (!s)
		die("--fault", "out of memory");
	snprintf(what, sizeof(what), "--fault '%s'", arg);
	kind = strchr(s, ':');
	if (!kind)
		die(what, "expected NAME:KIND[@N[:ARG]] or errframe@MS[:CLASS[:DATA1]]");
	*kind++ = '\0';
	n = find_node(s);
	if (!n)
		die(what, "no node named '%s' (-n)", s);
	at = strchr(kind, '@');
	if (at)
		*at++ = '\0';
	extra = at ? strchr(at, ':') : NULL;
	if (extra)
		*extra++ = '\0';
	if (!strcmp(kind, "never")) {
		if (at)
			die(what, "'never' takes no @N");
		n->never = true;
	} else if (!at) {
		die(what, "'%s' needs @N (never, stop@N, burst@N:COUNT, emcy@N:CODE, "
		    "hbstop@N)", kind);
	} else if (!strcmp(kind, "stop") || !strcmp(kind, "hbstop")) {
		bool hb = kind[0] == 'h';

		if (extra)
			die(what, "'%s' takes no argument after @N", kind);
		if (hb && !cfg.canopen)
			die(what, "hbstop needs --canopen");
		if ((hb ? n->hbstop_at : n->stop_at) >= 0)
			die(what, "node '%s' already has a %s fault", n->name, kind);
		/* stop@0 would be 'never' with a thread: say never */
		a = parse_num(what, at, hb ? 0 : 1, MAX_AT, NULL);
		*(hb ? &n->hbstop_at : &n->stop_at) = a;
	} else if (!strcmp(kind, "burst")) {
		if (!extra)
			die(what, "burst needs @N:COUNT");
		a = parse_num(what, at, 1, MAX_AT, NULL);
		add_at(&n->bursts, &n->nbursts, a, parse_num(what, extra, 1, MAX_BURST, NULL),
		       what);
	} else if (!strcmp(kind, "emcy")) {
		if (!cfg.canopen)
			die(what, "emcy needs --canopen");
		if (!extra)
			die(what, "emcy needs @N:CODE");
		a = parse_num(what, at, 1, MAX_AT, NULL);
		add_at(&n->emcys, &n->nemcys, a, parse_num(what, extra, 0, 0xffff, NULL), what);
	} else {
		die(what, "unknown fault '%s' (never, stop@N, burst@N:COUNT, emcy@N:CODE, "
		    "hbstop@N, errframe@MS)", kind);
	}
	free(s);
}

/* check_nodes - cross-option checks once every option is known */
static void check_nodes(void)
{
	char what[256];
	int i, j;

	if (!cfg.ifname)
		die("-i", "which CAN interface? (e.g. -i vcan0)");
	if (!cfg.nnodes && !cfg.nerrs)
		die("-n", "no node and no error frame: nothing to simulate");
	for (i = 0; i < cfg.nnodes; i++) {
		struct node *n = &cfg.nodes[i];

		snprintf(what, sizeof(what), "node '%s'", n->name);
		if (cfg.canopen) {
			if ((n->id & CAN_EFF_FLAG) || n->id < 1 || n->id > 127)
				die(what, "--canopen: ID is a node id and must be in 1..127");
			n->co_id = n->id;
			n->id = CO_TPDO1 + n->co_id;
		}
		for (j = 0; j < i; j++)
			if (cfg.nodes[j].id == n->id)
				die(what, "same %s as node '%s'", cfg.canopen ? "node id" :
				    "CAN id", cfg.nodes[j].name);
	}
	for (i = 0; i < cfg.nfaults; i++)
		apply_fault(cfg.faults[i]);
	for (i = 0; i < cfg.nnodes; i++) {
		struct node *n = &cfg.nodes[i];

		if (n->never && (n->stop_at >= 0 || n->hbstop_at >= 0 || n->nbursts || n->nemcys))
			die(n->name, "a 'never' node can have no other fault");
	}
	for (i = 0; i < cfg.nerrs; i++) {
		if (!cfg.duration_ms || cfg.errs[i].at_ms < cfg.duration_ms)
			continue;
		snprintf(what, sizeof(what), "--fault '%s'", cfg.errs[i].spec);
		die(what, "%ld ms is not before the end (-d %ld)", cfg.errs[i].at_ms,
		    cfg.duration_ms);
	}
}

enum { OPT_CANOPEN = 0x100, OPT_FAULT };

const char *argp_program_version = PROG " 0.1";
static const char doc[] =
"Simulated CAN nodes on a SocketCAN interface, with fault injection.\n"
"\n"
"USAGE: rtsup-cansim -i IFACE [-d MS] [--canopen] [-r PRIO] [-s FILE]\n"
"                    -n NAME:ID:PERIOD_MS[:LEN]... [--fault SPEC]...\n"
"\n"
"A node sends a frame with CAN id ID (0x hex or decimal; above 0x7FF, or\n"
"8 hex digits, a 29-bit id) every PERIOD_MS, LEN (default 8) bytes holding\n"
"the frame's sequence number, little endian.  With --canopen ID is a node\n"
"id n (1..127): boot-up 0x700+n once, then every PERIOD_MS a TPDO 0x180+n\n"
"and a heartbeat 0x700+n (operational), and SDO requests 0x600+n are\n"
"answered on 0x580+n.\n"
"\n"
"Fault SPEC (N counts the node's cycles, i.e. its periodic frames):\n"
"  NAME:never            the node never starts\n"
"  NAME:stop@N           silent after N cycles (no frame, no SDO answer)\n"
"  NAME:burst@N:COUNT    COUNT extra frames back to back after cycle N\n"
"  NAME:emcy@N:CODE      CANopen: EMCY 0x080+n with CODE after cycle N\n"
"  NAME:hbstop@N         CANopen: no heartbeat after N heartbeats\n"
"  errframe@MS[:CLASS[:DATA1]]  an error frame MS ms after the start\n"
"                        (default CLASS 0x4 controller, DATA1 0x10 rx-passive)\n"
"\n"
"EXAMPLES:\n"
"    rtsup-cansim -i vcan0 -d 2000 -n arm:0x181:10 -n imu:0x18fef100:20:3 -s -\n"
"    rtsup-cansim -i vcan0 -d 3000 --canopen -n drive:5:50 -n gripper:6:50 \\\n"
"        --fault drive:emcy@10:0x8130 --fault gripper:stop@20 \\\n"
"        --fault errframe@1000 -s sim.json\n";

static const struct argp_option opts[] = {
	{ "interface", 'i', "IFACE", 0, "SocketCAN interface (required)", 0 },
	{ "duration", 'd', "MS", 0, "Run MS milliseconds (default: until SIGINT/SIGTERM)", 0 },
	{ "node", 'n', "NAME:ID:PERIOD_MS[:LEN]", 0, "A simulated node (repeatable)", 0 },
	{ "canopen", OPT_CANOPEN, NULL, 0, "CANopen nodes: ID is the node id", 0 },
	{ "fault", OPT_FAULT, "SPEC", 0, "Inject a fault (repeatable)", 0 },
	{ "prio", 'r', "N", 0, "SCHED_FIFO priority 1..98 of the threads, 0 = SCHED_OTHER "
	  "(default 0)", 0 },
	{ "summary", 's', "FILE", 0, "Write the JSON summary to FILE ('-' = stdout)", 0 },
	{ NULL, 'h', NULL, OPTION_HIDDEN, "Show the full help", 0 },
	{},
};

/* parse_arg - argp callback */
static error_t parse_arg(int key, char *arg, struct argp_state *state)
{
	char **f;

	switch (key) {
	case 'i':
		if (!*arg || strlen(arg) >= IF_NAMESIZE || strchr(arg, '/'))
			die("-i", "'%s' is not an interface name", arg);
		cfg.ifname = arg;
		break;
	case 'd':
		cfg.duration_ms = parse_num("-d", arg, 1, MAX_DURATION_MS, NULL);
		break;
	case 'n':
		parse_node(arg);
		break;
	case OPT_CANOPEN:
		cfg.canopen = true;
		break;
	case OPT_FAULT:
		if (!strncmp(arg, "errframe@", 9)) {
			parse_errframe(arg);
			break;
		}
		f = realloc(cfg.faults, (cfg.nfaults + 1) * sizeof(*f));
		if (!f)
			die("--fault", "out of memory");
		cfg.faults = f;
		cfg.faults[cfg.nfaults++] = arg;
		break;
	case 'r':
		cfg.prio = parse_num("--prio", arg, 0, 98, NULL);
		break;
	case 's':
		cfg.summary = arg;
		break;
	case 'h':
		argp_state_help(state, stderr, ARGP_HELP_STD_HELP);
		break;
	case ARGP_KEY_ARG:
		die(arg, "unexpected argument");
	case ARGP_KEY_END:
		check_nodes();
		break;
	default:
		return ARGP_ERR_UNKNOWN;
	}
	return 0;
}

/* can_socket - a raw socket bound to the interface, receiving @nf filters
 * (0: nothing, so a send-only socket never queues the bus's traffic) */
static int can_socket(const char *what, const struct can_filter *f, int nf)
{
	struct sockaddr_can addr = { .can_family = AF_CAN, .can_ifindex = ifindex };
	int s = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);

	if (s < 0)
		die(what, "socket(PF_CAN, SOCK_RAW, CAN_RAW): %s%s", strerror(errno),
		    errno == EAFNOSUPPORT || errno == EPROTONOSUPPORT ?
		    " (no CAN in this kernel? modprobe can-raw)" : "");
	if (setsockopt(s, SOL_CAN_RAW, CAN_RAW_FILTER, f, nf * sizeof(*f)))
		die(what, "CAN_RAW_FILTER: %s", strerror(errno));
	if (bind(s, (struct sockaddr *)&addr, sizeof(addr)))
		die(what, "bind to %s: %s", cfg.ifname, strerror(errno));
	return s;
}

/* open_sockets - every socket before any thread: a failure is one line,
 * not a half-started simulation */
static void open_sockets(void)
{
	struct can_filter f[MAX_NODES];
	struct timeval tv = { 0, SDO_POLL_MS * 1000 };
	struct ifreq ifr;
	int i, nf = 0, one = 1, s;

	ifindex = if_nametoindex(cfg.ifname);
	if (!ifindex)
		die(cfg.ifname, "no such network interface");
	/* a down interface fails every write: say so now, once */
	s = can_socket(cfg.ifname, NULL, 0);
	snprintf(ifr.ifr_name, sizeof(ifr.ifr_name), "%s", cfg.ifname);
	if (ioctl(s, SIOCGIFFLAGS, &ifr))
		die(cfg.ifname, "SIOCGIFFLAGS: %s", strerror(errno));
	if (!(ifr.ifr_flags & IFF_UP))
		die(cfg.ifname, "interface is down (ip link set up %s)", cfg.ifname);
	close(s);
	for (i = 0; i < cfg.nnodes; i++) {
		struct node *n = &cfg.nodes[i];

		if (!n->never)
			n->sock = can_socket(n->name, NULL, 0);
		if (n->co_id)
			f[nf++] = (struct can_filter){ CO_SDO_RX + n->co_id,
						       CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG };
	}
	if (nf) {
		sdo_sock = can_socket("SDO socket", f, nf);
		if (setsockopt(sdo_sock, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv)) ||
		    setsockopt(sdo_sock, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof(one)))
			die("SDO socket", "setsockopt: %s", strerror(errno));
	}
	if (cfg.nerrs)
		err_sock = can_socket("error frame socket", NULL, 0);
}

/* send_frame - one write; counts the frame in @counter and @bytes only when
 * the kernel took it, so the summary never claims a frame it did not send */
static bool send_frame(int sock, canid_t id, const uint8_t *data, int len,
		       uint64_t *counter, uint64_t *bytes, uint64_t *errors, int *err)
{
	struct can_frame fr = { .can_id = id, .len = len };

	if (len)
		memcpy(fr.data, data, len);
	if (write(sock, &fr, sizeof(fr)) != sizeof(fr)) {
		(*errors)++;
		if (err)
			*err = errno;
		return false;
	}
	(*counter)++;
	*bytes += len;
	return true;
}

/* node_send - a node thread's frame, with the node's bookkeeping */
static void node_send(struct node *n, canid_t id, const uint8_t *data, int len,
		      uint64_t *counter)
{
	if (!send_frame(n->sock, id, data, len, counter, &n->bytes, &n->send_errors,
			&n->last_errno))
		return;
	n->last_ns = now_ns();
	if (!n->first_ns)
		n->first_ns = n->last_ns;
}

/* send_counter - a frame of the node's main id carrying its sequence
 * number; bursts continue the same sequence, so candump shows no gap */
static void send_counter(struct node *n, uint64_t *counter)
{
	uint8_t d[CAN_MAX_DLEN];
	uint64_t seq = n->seq++;
	int i;

	for (i = 0; i < n->len; i++)
		d[i] = (uint8_t)(seq >> (8 * i));
	node_send(n, n->id, d, n->len, counter);
}

/* send_nmt - boot-up or heartbeat: one byte, the NMT state */
static void send_nmt(struct node *n, uint8_t state)
{
	node_send(n, CO_HEARTBEAT + n->co_id, &state, 1,
		  state == NMT_BOOTUP ? &n->sent_bootup : &n->sent_hb);
}

/* send_emcy - error code (little endian), error register, 5 bytes of zeros */
static void send_emcy(struct node *n, long code)
{
	uint8_t d[8] = { code & 0xff, code >> 8, code ? 0x01 : 0x00 };
	uint64_t before = n->sent_emcy;

	node_send(n, CO_EMCY + n->co_id, d, 8, &n->sent_emcy);
	/* no malloc in a cycle: the log was sized by the plan */
	if (n->sent_emcy != before && n->nemcy_log < n->nemcys)
		n->emcy_log[n->nemcy_log++] = (struct at_arg){ n->cycles, code };
}

/* cycle - one period of a node: its periodic frames, then the faults due */
static void cycle(struct node *n)
{
	long c;
	int i, k;

	send_counter(n, &n->sent_main);
	/* attempts, not successes: hbstop@N is a plan, a failed write is counted apart */
	if (n->co_id && (n->hbstop_at < 0 || n->hb_tries < n->hbstop_at)) {
		n->hb_tries++;
		send_nmt(n, NMT_OPERATIONAL);
	}
	c = n->cycles + 1;
	__atomic_store_n(&n->cycles, c, __ATOMIC_RELEASE);
	for (i = 0; i < n->nbursts; i++)
		if (n->bursts[i].at == c)
			for (k = 0; k < n->bursts[i].arg; k++)
				send_counter(n, &n->sent_burst);
	for (i = 0; i < n->nemcys; i++)
		if (n->emcys[i].at == c)
			send_emcy(n, n->emcys[i].arg);
	if (n->stop_at == c) {
		n->stopped_after = c;
		__atomic_store_n(&n->stopped, 1, __ATOMIC_RELEASE);
	}
}

/* touch_stack - prefault 64 KiB of stack so no cycle faults on it */
static void __attribute__((noinline)) touch_stack(void)
{
	volatile char buf[STACK_TOUCH];
	size_t i;

	for (i = 0; i < sizeof(buf); i += 1024)
		buf[i] = 0;
}

/* thread_init - name, tid, scheduling and signals of a simulator thread;
 * @sock is written once with a bad size (EINVAL, nothing sent) so that the
 * first frame of a cycle neither binds the write() PLT slot nor faults */
static void thread_init(const char *name, int sock, pid_t *tid, char *comm, int *policy,
			int *prio)
{
	struct can_frame fr = { 0 };
	struct sched_param sp;
	sigset_t set;

	/* SIGINT/SIGTERM go to the main thread; SIGUSR1 ends our sleep */
	sigemptyset(&set);
	sigaddset(&set, SIGUSR1);
	pthread_sigmask(SIG_UNBLOCK, &set, NULL);
	prctl(PR_SET_NAME, name);
	if (comm)
		prctl(PR_GET_NAME, comm);
	/* SCHED_OTHER runs would otherwise wake up to 50 us late */
	prctl(PR_SET_TIMERSLACK, 1UL);
	*tid = gettid();
	if (policy) {
		pthread_getschedparam(pthread_self(), policy, &sp);
		*prio = sp.sched_priority;
	}
	touch_stack();
	now_ns();	/* warm the vDSO */
	/* 1 byte: a write of 0 bytes ends in the socket layer, before raw_sendmsg */
	if (write(sock, &fr, 1) >= 0)
		die(name, "a 1-byte write was taken as a frame");
}

/* node_main - one node: a periodic thread, one clock_nanosleep per cycle */
static void *node_main(void *arg)
{
	struct node *n = arg;
	int64_t period = n->period_ms * 1000000LL, next;
	struct timespec ts;

	thread_init(n->name, n->sock, &n->tid, n->comm, &n->policy, &n->prio);
	/* twice: every thread is ready, then the main thread has set t0 */
	pthread_barrier_wait(&start_barrier);
	pthread_barrier_wait(&start_barrier);
	next = t0_ns;
	/* a real node announces itself before its first heartbeat */
	if (n->co_id)
		send_nmt(n, NMT_BOOTUP);
	while (!__atomic_load_n(&stop_all, __ATOMIC_ACQUIRE)) {
		next += period;	/* never skip missed periods: every cycle sends */
		ts = ns_to_ts(next);
		if (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR ||
		    __atomic_load_n(&stop_all, __ATOMIC_ACQUIRE))
			break;
		/* a stopped node's thread keeps its cycle: the CAN node is what failed */
		if (!n->stopped)
			cycle(n);
	}
	return NULL;
}

/* sdo_answer - the response to one SDO request, CiA 301 expedited transfers:
 * upload -> 0x43 with a 4-byte value, download -> 0x60, anything else -> abort */
static void sdo_answer(struct node *n, const struct can_frame *req)
{
	uint8_t d[8] = { 0 }, ccs = req->len ? req->data[0] >> 5 : 0xff;
	uint32_t v;
	uint16_t index = req->len >= 3 ? req->data[1] | req->data[2] << 8 : 0;
	uint8_t sub = req->len >= 4 ? req->data[3] : 0;

	d[1] = index & 0xff;
	d[2] = index >> 8;
	d[3] = sub;
	if (ccs == 2) {		/* initiate upload */
		d[0] = 0x43;
		/* 0x1017:00 is the producer heartbeat time; anything else: the cycles */
		v = index == 0x1017 && !sub ? (uint32_t)n->period_ms :
		    (uint32_t)__atomic_load_n(&n->cycles, __ATOMIC_ACQUIRE);
	} else if (ccs == 1) {	/* initiate download, accepted and forgotten */
		d[0] = 0x60;
		v = 0;
	} else {
		d[0] = 0x80;
		v = SDO_ABORT_CMD;
	}
	d[4] = v;
	d[5] = v >> 8;
	d[6] = v >> 16;
	d[7] = v >> 24;
	if (send_frame(sdo_sock, CO_SDO_TX + n->co_id, d, 8, &n->sent_sdo, &n->sdo_bytes,
		       &n->sdo_send_errors, NULL)) {
		n->sdo_answered++;
		n->sdo_aborts += d[0] == 0x80;
	}
}

/* sdo_main - receive SDO requests for every CANopen node and answer them */
static void *sdo_main(void *arg)
{
	char cbuf[CMSG_SPACE(sizeof(uint32_t))];
	struct can_frame fr;
	struct iovec iov = { &fr, sizeof(fr) };
	struct msghdr mh = { .msg_iov = &iov, .msg_iovlen = 1 };
	struct cmsghdr *cm;
	struct node *n;
	ssize_t r;
	int i;

	(void)arg;
	thread_init("cansim-sdo", sdo_sock, &sdo_tid, NULL, NULL, NULL);
	pthread_barrier_wait(&start_barrier);
	pthread_barrier_wait(&start_barrier);
	while (!__atomic_load_n(&stop_all, __ATOMIC_ACQUIRE)) {
		mh.msg_control = cbuf;
		mh.msg_controllen = sizeof(cbuf);
		/* SO_RCVTIMEO bounds the wait; SIGUSR1 cuts it short at the end */
		r = recvmsg(sdo_sock, &mh, 0);
		if (r < 0)
			continue;
		for (cm = CMSG_FIRSTHDR(&mh); cm; cm = CMSG_NXTHDR(&mh, cm))
			if (cm->cmsg_level == SOL_SOCKET && cm->cmsg_type == SO_RXQ_OVFL)
				memcpy(&sdo_drops, CMSG_DATA(cm), sizeof(uint32_t));
		if (r != sizeof(fr))
			continue;
		for (i = 0, n = NULL; i < cfg.nnodes && !n; i++)
			if (cfg.nodes[i].co_id && fr.can_id == CO_SDO_RX + (canid_t)cfg.nodes[i].co_id)
				n = &cfg.nodes[i];
		if (!n) {
			sdo_unknown++;	/* the filter makes this impossible; count, don't guess */
			continue;
		}
		n->sdo_received++;
		/* a node that never started or stopped does not answer */
		if (!n->started || __atomic_load_n(&n->stopped, __ATOMIC_ACQUIRE))
			n->sdo_ignored++;
		else
			sdo_answer(n, &fr);
	}
	return NULL;
}

/* start_thread - create a thread with explicit policy and priority */
static void start_thread(pthread_t *pt, void *(*fn)(void *), void *arg)
{
	struct sched_param sp = { .sched_priority = (int)cfg.prio };
	pthread_attr_t attr;
	int err;

	pthread_attr_init(&attr);
	pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
	pthread_attr_setschedpolicy(&attr, cfg.prio ? SCHED_FIFO : SCHED_OTHER);
	pthread_attr_setschedparam(&attr, &sp);
	/* small stacks: many nodes stay cheap to lock with -r */
	pthread_attr_setstacksize(&attr, STACK_SIZE);
	err = pthread_create(pt, &attr, fn, arg);
	if (err)
		die("pthread_create", "%s%s", strerror(err), err == EPERM ?
		    " (SCHED_FIFO needs privilege, try -r 0)" : "");
	pthread_attr_destroy(&attr);
}

/* wait_until - sleep until monotonic @t (INT64_MAX: forever) unless SIGINT
 * or SIGTERM comes first; returns the signal or 0 */
static int wait_until(int64_t t, const sigset_t *set)
{
	struct timespec ts;
	int64_t now;
	int sig;

	for (;;) {
		now = now_ns();
		if (t != INT64_MAX && now >= t)
			return 0;
		ts = ns_to_ts(t - now);
		sig = sigtimedwait(set, NULL, t == INT64_MAX ? NULL : &ts);
		if (sig > 0)
			return sig;
	}
}

/* send_errframe - an error frame like a controller reports it */
static void send_errframe(struct errframe *e)
{
	uint8_t d[CAN_ERR_DLC] = { 0, (uint8_t)e->data1 };
	uint64_t sent = 0, bytes = 0, errors = 0;

	e->sent = send_frame(err_sock, CAN_ERR_FLAG | e->class, d, CAN_ERR_DLC, &sent,
			     &bytes, &errors, &e->err);
	e->sent_ns = now_ns();
}

/* errframe_cmp - error frames in time order */
static int errframe_cmp(const void *a, const void *b)
{
	const struct errframe *x = a, *y = b;

	return (x->at_ms > y->at_ms) - (x->at_ms < y->at_ms);
}

/* stop_thread - end a thread sleeping in clock_nanosleep or recvmsg; the
 * signal is repeated in case it came just before the thread went to sleep */
static void stop_thread(pthread_t pt)
{
	struct timespec ts;

	for (;;) {
		pthread_kill(pt, SIGUSR1);
		clock_gettime(CLOCK_REALTIME, &ts);
		ts.tv_nsec += 50 * 1000000L;
		if (ts.tv_nsec >= 1000000000L) {
			ts.tv_sec++;
			ts.tv_nsec -= 1000000000L;
		}
		if (!pthread_timedjoin_np(pt, NULL, &ts))
			return;
	}
}

/* iso_time - wall-clock time as ISO 8601 UTC with milliseconds */
static json_t *iso_time(const struct timespec *ts)
{
	char buf[64];
	struct tm tm;

	gmtime_r(&ts->tv_sec, &tm);
	strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%S", &tm);
	snprintf(buf + strlen(buf), sizeof(buf) - strlen(buf), ".%03ldZ", ts->tv_nsec / 1000000);
	return json_string(buf);
}

/* add_id - count @frames of @id into a frames-by-id object */
static void add_id(json_t *o, canid_t id, uint64_t frames, bool keep_zero)
{
	char key[24];
	json_t *v;

	if (!frames && !keep_zero)
		return;
	id_text(id, key, sizeof(key));
	v = json_object_get(o, key);
	json_object_set_new(o, key, json_integer((v ? json_integer_value(v) : 0) +
						 (json_int_t)frames));
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

/* opt_int - an integer, or null for "does not apply" (-1) */
static json_t *opt_int(long v)
{
	return v < 0 ? json_null() : json_integer(v);
}

/* node_json - summary object of one node; @all collects frames by id */
static json_t *node_json(const struct node *n, json_t *all)
{
	json_t *ids = json_object(), *o, *faults = json_object(), *bursts = json_array();
	char idt[24];
	uint64_t frames;
	int i, pass;

	/* per node every id it owns, zeros too; @all only what was on the bus */
	for (pass = 0; pass < 2; pass++) {
		json_t *t = pass ? all : ids;

		add_id(t, n->id, n->sent_main + n->sent_burst, !pass);
		if (!n->co_id)
			continue;
		add_id(t, CO_HEARTBEAT + n->co_id, n->sent_bootup + n->sent_hb, !pass);
		add_id(t, CO_EMCY + n->co_id, n->sent_emcy, !pass);
		add_id(t, CO_SDO_TX + n->co_id, n->sent_sdo, !pass);
	}
	frames = n->sent_main + n->sent_burst + n->sent_bootup + n->sent_hb + n->sent_emcy +
		 n->sent_sdo;
	for (i = 0; i < n->nbursts; i++)
		json_array_append_new(bursts, json_pack("{s:I, s:I}", "after_cycle",
			(json_int_t)n->bursts[i].at, "count", (json_int_t)n->bursts[i].arg));
	json_object_set_new(faults, "never", json_boolean(n->never));
	json_object_set_new(faults, "stop_at", opt_int(n->stop_at));
	json_object_set_new(faults, "hbstop_at", opt_int(n->hbstop_at));
	json_object_set_new(faults, "bursts", bursts);
	id_text(n->id, idt, sizeof(idt));
	o = json_pack("{s:s, s:s, s:I, s:b, s:I, s:i, s:b, s:o, s:s, s:s, s:i}",
		      "name", n->name, "id", idt, "can_id",
		      (json_int_t)(n->id & CAN_EFF_MASK), "extended", !!(n->id & CAN_EFF_FLAG),
		      "period_ms", (json_int_t)n->period_ms, "len", n->len,
		      "started", n->started, "tid", opt_int(n->tid),
		      "comm", n->started ? n->comm : "",
		      "policy", n->started ? policy_name(n->policy) : "-", "prio", n->prio);
	if (!o)
		die("json", "cannot build the summary");
	json_object_set_new(o, "node_id", n->co_id ? json_integer(n->co_id) : json_null());
	json_object_set_new(o, "cycles", json_integer(n->cycles));
	json_object_set_new(o, "frames_sent", ids);
	json_object_set_new(o, "frames_total", json_integer(frames));
	json_object_set_new(o, "bytes_sent", json_integer(n->bytes + n->sdo_bytes));
	json_object_set_new(o, "burst_frames", json_integer(n->sent_burst));
	json_object_set_new(o, "send_errors", json_integer(n->send_errors + n->sdo_send_errors));
	json_object_set_new(o, "last_error", n->send_errors || n->sdo_send_errors ?
			    json_string(strerror(n->last_errno)) : json_null());
	json_object_set_new(o, "stopped_after", opt_int(n->stopped_after));
	json_object_set_new(o, "first_frame_ns", n->first_ns ? json_integer(n->first_ns) :
			    json_null());
	json_object_set_new(o, "last_frame_ns", n->last_ns ? json_integer(n->last_ns) :
			    json_null());
	json_object_set_new(o, "faults", faults);
	if (n->co_id) {
		json_t *emcy = json_array();

		json_object_set_new(o, "bootup_sent", json_integer(n->sent_bootup));
		json_object_set_new(o, "heartbeats_sent", json_integer(n->sent_hb));
		json_object_set_new(o, "pdos_sent", json_integer(n->sent_main + n->sent_burst));
		json_object_set_new(o, "emcy_sent", json_integer(n->sent_emcy));
		for (i = 0; i < n->nemcy_log; i++)
			json_array_append_new(emcy, json_pack("{s:I, s:i, s:i}", "after_cycle",
				(json_int_t)n->emcy_log[i].at, "code", (int)n->emcy_log[i].arg,
				"register", n->emcy_log[i].arg ? 1 : 0));
		json_object_set_new(o, "emcy", emcy);
		json_object_set_new(o, "sdo_requests_received", json_integer(n->sdo_received));
		json_object_set_new(o, "sdo_requests_answered", json_integer(n->sdo_answered));
		json_object_set_new(o, "sdo_requests_ignored", json_integer(n->sdo_ignored));
		json_object_set_new(o, "sdo_aborts", json_integer(n->sdo_aborts));
	}
	return o;
}

/* write_summary - dump the JSON summary to @out */
static void write_summary(FILE *out, const char *ended_by)
{
	json_t *nodes = json_array(), *errs = json_array(), *all = json_object(), *root;
	uint64_t frames = 0, bytes = 0, nerr = 0;
	int i;

	for (i = 0; i < cfg.nnodes; i++) {
		const struct node *n = &cfg.nodes[i];
		json_t *o = node_json(n, all);

		frames += json_integer_value(json_object_get(o, "frames_total"));
		bytes += json_integer_value(json_object_get(o, "bytes_sent"));
		json_array_append_new(nodes, o);
	}
	for (i = 0; i < cfg.nerrs; i++) {
		const struct errframe *e = &cfg.errs[i];
		json_t *o = json_pack("{s:I, s:I, s:i, s:b}", "at_ms", (json_int_t)e->at_ms,
				      "class", (json_int_t)e->class, "data1", e->data1,
				      "sent", e->sent);

		json_object_set_new(o, "sent_ns", e->sent ? json_integer(e->sent_ns) :
				    json_null());
		json_object_set_new(o, "sent_after_ms", e->sent ?
				    json_real((e->sent_ns - t0_ns) / 1e6) : json_null());
		json_object_set_new(o, "error", e->err ? json_string(strerror(e->err)) :
				    json_null());
		nerr += e->sent;
		json_array_append_new(errs, o);
	}
	root = json_pack("{s:i, s:s, s:i, s:b, s:I, s:i, s:b, s:s}",
			 "pid", (int)getpid(), "interface", cfg.ifname, "ifindex", ifindex,
			 "canopen", cfg.canopen, "duration_ms", (json_int_t)cfg.duration_ms,
			 "prio", (int)cfg.prio, "mlocked", locked, "ended_by", ended_by);
	if (!root)
		die("json", "cannot build the summary");
	json_object_set_new(root, "start", iso_time(&t0_wall));
	json_object_set_new(root, "end", iso_time(&end_wall));
	json_object_set_new(root, "start_ns", json_integer(t0_ns));
	json_object_set_new(root, "end_ns", json_integer(end_ns));
	json_object_set_new(root, "elapsed_ms", json_real((end_ns - t0_ns) / 1e6));
	json_object_set_new(root, "nodes", nodes);
	json_object_set_new(root, "frames_sent", all);
	json_object_set_new(root, "frames_total", json_integer(frames));
	json_object_set_new(root, "bytes_total", json_integer(bytes));
	json_object_set_new(root, "error_frames", errs);
	json_object_set_new(root, "error_frames_sent", json_integer(nerr));
	json_object_set_new(root, "sdo_thread", sdo_sock < 0 ? json_null() :
			    json_pack("{s:i, s:s, s:I, s:I}", "tid", (int)sdo_tid,
				      "comm", "cansim-sdo", "socket_drops", (json_int_t)sdo_drops,
				      "unknown_requests", (json_int_t)sdo_unknown));
	if (json_dumpf(root, out, JSON_INDENT(2)) || fputc('\n', out) == EOF ||
	    (out == stdout ? fflush(out) : fclose(out)))
		die("--summary", "%s: cannot write: %s", cfg.summary, strerror(errno));
	json_decref(root);
}

/* noop - SIGUSR1 handler: its only job is to interrupt a sleep */
static void noop(int sig)
{
	(void)sig;
}

/* main - parse, open the sockets, run the nodes, report */
int main(int argc, char **argv)
{
	static const struct argp argp = {
		.options = opts, .parser = parse_arg, .doc = doc,
	};
	struct sigaction sa = { .sa_handler = noop };	/* no SA_RESTART */
	const char *ended_by = "duration";
	sigset_t set, waitset;
	FILE *out = NULL;
	int i, nthreads = 0, sig = 0;

	/*
	 * Block SIGINT/SIGTERM first: a background job of a script has them
	 * ignored, and one sent during the start-up (mlockall is slow) would be
	 * lost; blocked, it waits for sigtimedwait().  Threads inherit the mask.
	 */
	sigemptyset(&set);
	sigaddset(&set, SIGINT);
	sigaddset(&set, SIGTERM);
	waitset = set;
	sigaddset(&set, SIGUSR1);
	pthread_sigmask(SIG_BLOCK, &set, NULL);
	sigaction(SIGUSR1, &sa, NULL);

	argp_err_exit_status = 1;
	if (argp_parse(&argp, argc, argv, 0, NULL, NULL))
		return 1;
	/* open the summary now: a bad path fails before the run, not after */
	if (cfg.summary) {
		out = strcmp(cfg.summary, "-") ? fopen(cfg.summary, "w") : stdout;
		if (!out)
			die("--summary", "%s: %s", cfg.summary, strerror(errno));
	}
	open_sockets();
	qsort(cfg.errs, cfg.nerrs, sizeof(*cfg.errs), errframe_cmp);
	if (cfg.prio) {
		/* with -r the threads are real-time: none of them may fault */
		locked = !mlockall(MCL_CURRENT | MCL_FUTURE);
		if (!locked)
			fprintf(stderr, PROG ": warning: mlockall: %s, continuing\n",
				strerror(errno));
	}

	for (i = 0; i < cfg.nnodes; i++)
		nthreads += !cfg.nodes[i].never;
	pthread_barrier_init(&start_barrier, NULL, nthreads + (sdo_sock >= 0) + 1);
	for (i = 0; i < cfg.nnodes; i++) {
		struct node *n = &cfg.nodes[i];

		n->emcy_log = calloc(n->nemcys ? n->nemcys : 1, sizeof(*n->emcy_log));
		if (!n->emcy_log)
			die(n->name, "out of memory");
		if (n->never)
			continue;
		start_thread(&n->pt, node_main, n);
		n->started = true;
	}
	if (sdo_sock >= 0)
		start_thread(&sdo_pt, sdo_main, NULL);
	/* every thread is named and ready: one common start for all nodes */
	pthread_barrier_wait(&start_barrier);
	t0_ns = now_ns();
	clock_gettime(CLOCK_REALTIME, &t0_wall);
	end_ns = cfg.duration_ms ? t0_ns + cfg.duration_ms * 1000000LL : INT64_MAX;
	pthread_barrier_wait(&start_barrier);

	for (i = 0; i < cfg.nerrs && !sig; i++) {
		sig = wait_until(t0_ns + cfg.errs[i].at_ms * 1000000LL, &waitset);
		if (!sig)
			send_errframe(&cfg.errs[i]);
	}
	if (!sig)
		sig = wait_until(end_ns, &waitset);
	if (sig)
		ended_by = sig == SIGINT ? "SIGINT" : "SIGTERM";

	__atomic_store_n(&stop_all, 1, __ATOMIC_RELEASE);
	for (i = 0; i < cfg.nnodes; i++)
		if (cfg.nodes[i].started)
			stop_thread(cfg.nodes[i].pt);
	if (sdo_sock >= 0)
		stop_thread(sdo_pt);
	end_ns = now_ns();
	clock_gettime(CLOCK_REALTIME, &end_wall);
	if (out)
		write_summary(out, ended_by);
	return 0;
}
