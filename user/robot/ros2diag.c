// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* ros2diag.c - the verdicts as ROS 2 /diagnostics, through Cyclone DDS */
#include <dlfcn.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <dds/dds.h>
#include "robot/ros2diag.h"

/*
 * Debian's libddsc, opened only for --ros2-diagnostics: a robot that does
 * not publish does not map a DDS stack and its threads. Its ABI is the one
 * of the headers this was built with (cyclonedds-dev), hence the soname.
 */
#define DDSC_SONAME "libddsc.so.0debian"

static struct {
	void *h;
	__typeof__(dds_create_participant) *create_participant;
	__typeof__(dds_create_topic) *create_topic;
	__typeof__(dds_create_writer) *create_writer;
	__typeof__(dds_create_qos) *create_qos;
	__typeof__(dds_delete_qos) *delete_qos;
	__typeof__(dds_qset_reliability) *qset_reliability;
	__typeof__(dds_qset_durability) *qset_durability;
	__typeof__(dds_qset_history) *qset_history;
	__typeof__(dds_write) *write;
	__typeof__(dds_wait_for_acks) *wait_for_acks;
	__typeof__(dds_delete) *delete;
	__typeof__(dds_strretcode) *strretcode;
} dds;

/* ddsc_load - the library and its functions; one line on stderr, -1 */
static int ddsc_load(void)
{
	const struct {
		const char *name;
		void **slot;
	} fn[] = {
		{ "dds_create_participant", (void **)&dds.create_participant },
		{ "dds_create_topic", (void **)&dds.create_topic },
		{ "dds_create_writer", (void **)&dds.create_writer },
		{ "dds_create_qos", (void **)&dds.create_qos },
		{ "dds_delete_qos", (void **)&dds.delete_qos },
		{ "dds_qset_reliability", (void **)&dds.qset_reliability },
		{ "dds_qset_durability", (void **)&dds.qset_durability },
		{ "dds_qset_history", (void **)&dds.qset_history },
		{ "dds_write", (void **)&dds.write },
		{ "dds_wait_for_acks", (void **)&dds.wait_for_acks },
		{ "dds_delete", (void **)&dds.delete },
		{ "dds_strretcode", (void **)&dds.strretcode },
	};
	size_t i;
	void *h;

	if (dds.h)
		return 0;
	h = dlopen(DDSC_SONAME, RTLD_NOW | RTLD_LOCAL);
	if (!h) {
		fprintf(stderr, "rtsup-trace: --ros2-diagnostics needs %s (Debian: apt install "
			"libddsc0debian): %s\n", DDSC_SONAME, dlerror());
		return -1;
	}
	for (i = 0; i < sizeof(fn) / sizeof(fn[0]); i++) {
		*fn[i].slot = dlsym(h, fn[i].name);
		if (!*fn[i].slot) {
			fprintf(stderr, "rtsup-trace: --ros2-diagnostics: %s lacks %s\n",
				DDSC_SONAME, fn[i].name);
			dlclose(h);
			return -1;
		}
	}
	dds.h = h;
	return 0;
}

int ros2diag_domain(const char *env, uint32_t *domain)
{
	unsigned long v;
	char *end;

	*domain = 0;
	if (!env || !*env)
		return 0;
	errno = 0;
	v = strtoul(env, &end, 10);
	if (errno || *end || env[0] < '0' || env[0] > '9' || v > ROS2DIAG_MAX_DOMAIN)
		return -1;
	*domain = v;
	return 0;
}

/* ROS's DiagnosticStatus bytes, by our level (the enum's order is not ROS's). */
static const uint8_t ros_level[] = {
	[LEVEL_OK] = 0,
	[LEVEL_WARN] = 1,
	[LEVEL_ERROR] = 2,
	[LEVEL_STALE] = 3,
};

uint8_t ros2diag_level(enum level l)
{
	return (unsigned int)l < sizeof(ros_level) ? ros_level[l] : 2;
}

/*
 * The same threads as the Prometheus series and the systemd STATUS line:
 * alive ones, and dead judged ones (RT or named by a rule, now STALE) until
 * a restarted instance replaces them.
 */
bool ros2diag_listed(const struct thread_model *tm)
{
	return tm->alive || (!tm->replaced && (tm->was_rt || tm->rule >= 0));
}

/* What one message owns while it is filled: the statuses and their values. */
#define DIAG_MAX_VALUES	(16 + RTSUP_U_NR)

struct fill {
	ros2diag_msg *msg;
	uint32_t cap;
	const char *host;
	bool oom;
};

/* xstrdup - a copy; NULL when out of memory, and the message is not sent */
static char *xstrdup(struct fill *f, const char *s)
{
	char *p = strdup(s);

	if (!p) {
		f->oom = true;
		return NULL;
	}
	return p;
}

/* add_status - a new DiagnosticStatus named rtsup/<host>/<what>, NULL when full */
static diagnostic_msgs_msg_dds__DiagnosticStatus_ *add_status(struct fill *f, const char *what,
							       const struct status *st)
{
	dds_sequence_diagnostic_msgs_msg_dds__DiagnosticStatus_ *seq = &f->msg->status;
	diagnostic_msgs_msg_dds__DiagnosticStatus_ *d;
	char name[256], text[STATUS_MAX_MSGS * (STATUS_MSG_LEN + 2) + 16];

	if (seq->_length == f->cap) {
		uint32_t cap = f->cap ? 2 * f->cap : 16;
		void *p = realloc(seq->_buffer, cap * sizeof(*seq->_buffer));

		if (!p) {
			f->oom = true;
			return NULL;
		}
		seq->_buffer = p;
		f->cap = cap;
		seq->_maximum = cap;
	}
	d = &seq->_buffer[seq->_length++];
	memset(d, 0, sizeof(*d));
	snprintf(name, sizeof(name), "rtsup/%s/%s", f->host, what);
	status_join(st, text, sizeof(text));
	d->level = ros2diag_level(st->level);
	d->name = xstrdup(f, name);
	d->message = xstrdup(f, text[0] ? text : level_name(st->level));
	d->hardware_id = xstrdup(f, f->host);
	d->values._buffer = calloc(DIAG_MAX_VALUES, sizeof(*d->values._buffer));
	if (!d->values._buffer)
		f->oom = true;
	d->values._maximum = d->values._buffer ? DIAG_MAX_VALUES : 0;
	d->values._release = true;
	return d;
}

/* kv - one KeyValue of a status */
static void kv(struct fill *f, diagnostic_msgs_msg_dds__DiagnosticStatus_ *d, const char *key,
	       const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void kv(struct fill *f, diagnostic_msgs_msg_dds__DiagnosticStatus_ *d, const char *key,
	       const char *fmt, ...)
{
	diagnostic_msgs_msg_dds__KeyValue_ *v;
	char val[128];
	va_list ap;

	if (!d || d->values._length == d->values._maximum)
		return;
	va_start(ap, fmt);
	vsnprintf(val, sizeof(val), fmt, ap);
	va_end(ap);
	v = &d->values._buffer[d->values._length++];
	v->key = xstrdup(f, key);
	v->value = xstrdup(f, val);
}

/* kv_us - a metric of the last interval in microseconds, "-" without samples */
static void kv_us(struct fill *f, diagnostic_msgs_msg_dds__DiagnosticStatus_ *d,
		  const char *key, const struct metric_view *m, bool p99)
{
	if (!m->count)
		kv(f, d, key, "-");
	else
		kv(f, d, key, "%.1f", (p99 ? (double)m->p99 : m->mean) / 1e3);
}

/* safe_part - a name as one level of the status name: no '/' (the aggregator splits there) */
static void safe_part(char *dst, size_t len, const char *src)
{
	size_t i;

	if (dst != src)
		snprintf(dst, len, "%s", src);
	for (i = 0; dst[i]; i++)
		if (dst[i] == '/')
			dst[i] = '_';
}

/* fill_thread - a thread: its verdict and key numbers (interval and lifetime) */
static void fill_thread(struct fill *f, const struct thread_model *tm)
{
	diagnostic_msgs_msg_dds__DiagnosticStatus_ *d;
	char comm[RTSUP_COMM_LEN], what[64];
	int k;

	safe_part(comm, sizeof(comm), tm->comm);
	snprintf(what, sizeof(what), "%s[%u]", comm, tm->tid);
	d = add_status(f, what, &tm->st);
	kv(f, d, "process", "%s", tm->pcomm[0] ? tm->pcomm : tm->comm);
	kv(f, d, "pid", "%u", tm->tgid);
	kv(f, d, "tid", "%u", tm->tid);
	kv(f, d, "policy", "%s", policy_name(tm->policy));
	kv(f, d, "priority", "%d", tm->prio);
	kv(f, d, "cycles", "%llu", (unsigned long long)tm->win.cycles);
	kv_us(f, d, "period_mean_us", &tm->win.m[RTSUP_M_PERIOD], false);
	kv_us(f, d, "exec_p99_us", &tm->win.m[RTSUP_M_EXEC], true);
	kv_us(f, d, "latency_p99_us", &tm->win.m[RTSUP_M_LATENCY], true);
	kv(f, d, "misses_total", "%llu", (unsigned long long)tm->life.misses);
	kv(f, d, "overruns_total", "%llu", (unsigned long long)tm->life.overruns);
	kv(f, d, "unsafe_total", "%llu", (unsigned long long)tm->life.unsafe_total);
	for (k = 0; k < RTSUP_U_NR; k++) {
		char key[48];

		if (!tm->life.unsafe[k])
			continue;
		snprintf(key, sizeof(key), "unsafe_%s", unsafe_reason_name(k));
		kv(f, d, key, "%llu", (unsigned long long)tm->life.unsafe[k]);
	}
	kv(f, d, "worst_level", "%s", level_name(tm->worst));
}

/* Controller states as can_iface_ctrl gives them. */
static const char *const ctrl_name[] = {
	[CAN_CTRL_OK] = "error-active",
	[CAN_CTRL_PASSIVE_RX] = "error-passive-rx",
	[CAN_CTRL_PASSIVE_TX] = "error-passive-tx",
	[CAN_CTRL_BUSOFF] = "bus-off",
	[CAN_CTRL_DOWN] = "down",
};

/* fill_can - interfaces, named nodes, groups, CANopen nodes, and unnamed ids not OK */
static void fill_can(struct fill *f, const struct can_model *cm, const struct config *cfg)
{
	diagnostic_msgs_msg_dds__DiagnosticStatus_ *d;
	char what[128], part[96];
	int i;

	for (i = 0; i < cm->nifs; i++) {
		const struct can_iface *ifc = &cm->ifs[i];
		enum can_ctrl c = can_iface_ctrl(ifc);

		safe_part(part, sizeof(part), ifc->name);
		snprintf(what, sizeof(what), "can/%s", part);
		d = add_status(f, what, &ifc->st);
		if (ifc->load >= 0)
			kv(f, d, "bus_load_pct", "%.1f", ifc->load * 100);
		else
			kv(f, d, "bus_load_pct", "-");
		kv(f, d, "controller", "%s",
		   (unsigned int)c < sizeof(ctrl_name) / sizeof(ctrl_name[0]) ? ctrl_name[c] : "?");
		kv(f, d, "frames_rx", "%llu", (unsigned long long)ifc->cur.frames[RTSUP_CAN_RX]);
		kv(f, d, "frames_tx", "%llu", (unsigned long long)ifc->cur.frames[RTSUP_CAN_TX]);
		kv(f, d, "error_frames", "%llu", (unsigned long long)ifc->cur.err_frames);
		kv(f, d, "worst_level", "%s", level_name(ifc->worst));
	}
	for (i = 0; i < cm->nnodes && i < cfg->can.nnodes; i++) {
		const struct can_node_view *n = &cm->nodes[i];

		safe_part(part, sizeof(part), cfg->can.nodes[i].name);
		snprintf(what, sizeof(what), "can/node/%s", part);
		d = add_status(f, what, &n->st);
		kv(f, d, "state", "%s", n->last ? level_name(n->st.level) : "never seen");
		kv(f, d, "frames", "%llu", (unsigned long long)n->frames);
		kv(f, d, "frames_interval", "%llu", (unsigned long long)n->frames_win);
		if (n->period)
			kv(f, d, "period_us", "%.1f", n->period / 1e3);
		kv_us(f, d, "gap_p99_us", &n->gap, true);
		kv(f, d, "worst_level", "%s", level_name(n->worst));
	}
	for (i = 0; i < cm->ngroups; i++) {
		safe_part(part, sizeof(part), cm->groups[i].name);
		snprintf(what, sizeof(what), "can/group/%s", part);
		d = add_status(f, what, &cm->groups[i].st);
		kv(f, d, "worst_level", "%s", level_name(cm->groups[i].worst));
	}
	for (i = 0; i < cm->nifs * CANOPEN_NODES; i++) {
		const struct canopen_node *co = &cm->co[i / CANOPEN_NODES][i % CANOPEN_NODES];

		if (!co->seen)
			continue;
		safe_part(part, sizeof(part), cm->ifs[i / CANOPEN_NODES].name);
		snprintf(what, sizeof(what), "canopen/%s/%d", part, i % CANOPEN_NODES);
		d = add_status(f, what, &co->st);
		kv(f, d, "state", "%s", co->heartbeat_last ? can_nmt_name(co->nmt_state) : "unknown");
		kv(f, d, "emcy_frames", "%llu", (unsigned long long)co->emcy_frames);
		if (co->emcy_frames)
			kv(f, d, "emcy_code", "0x%04x", co->emcy_code);
		kv(f, d, "worst_level", "%s", level_name(co->worst));
	}
	/* an identifier no node names: only while it is not OK (a bus has thousands) */
	for (i = 0; i < cm->n; i++) {
		const struct can_entry *e = &cm->e[i];
		char comp[96];

		if (e->node >= 0 || e->st.level == LEVEL_OK)
			continue;
		can_component(cm, e, comp, sizeof(comp));
		safe_part(part, sizeof(part), comp);
		snprintf(what, sizeof(what), "can/id/%s", part);
		d = add_status(f, what, &e->st);
		kv(f, d, "frames", "%llu", (unsigned long long)e->cur.frames);
	}
}

int ros2diag_fill(ros2diag_msg *msg, const struct model *m, const struct supervisor *s,
		  const char *host, uint64_t now)
{
	struct fill f = { .msg = msg, .host = host };
	diagnostic_msgs_msg_dds__DiagnosticStatus_ *d;
	__s64 real = (__s64)now + s->real_off;
	int i, n = 0;

	memset(msg, 0, sizeof(*msg));
	msg->header.stamp.sec = (int32_t)(real / 1000000000);
	msg->header.stamp.nanosec = (uint32_t)(real % 1000000000);
	msg->header.frame_id = xstrdup(&f, "");
	msg->status._release = true;
	for (i = 0; i < m->n; i++)
		n += ros2diag_listed(m->t[i]);
	d = add_status(&f, "rtsup-trace", &s->self);
	kv(&f, d, "threads", "%d", n);
	if (s->overhead_pct >= 0)
		kv(&f, d, "bpf_overhead_pct", "%.3f", s->overhead_pct);
	kv(&f, d, "worst_level", "%s", level_name(s->self_worst));
	for (i = 0; i < m->n; i++)
		if (ros2diag_listed(m->t[i]))
			fill_thread(&f, m->t[i]);
	if (s->can)
		fill_can(&f, s->can, &s->cfg);
	return f.oom ? -1 : 0;
}

void ros2diag_msg_free(ros2diag_msg *msg)
{
	uint32_t i, k;

	for (i = 0; i < msg->status._length; i++) {
		diagnostic_msgs_msg_dds__DiagnosticStatus_ *d = &msg->status._buffer[i];

		free(d->name);
		free(d->message);
		free(d->hardware_id);
		for (k = 0; k < d->values._length; k++) {
			free(d->values._buffer[k].key);
			free(d->values._buffer[k].value);
		}
		free(d->values._buffer);
	}
	free(msg->status._buffer);
	free(msg->header.frame_id);
	memset(msg, 0, sizeof(*msg));
}

int ros2diag_open(struct ros2diag *d)
{
	dds_entity_t topic;
	dds_qos_t *qos;
	const char *env = getenv("ROS_DOMAIN_ID");

	memset(d, 0, sizeof(*d));
	if (ros2diag_domain(env, &d->domain)) {
		fprintf(stderr, "rtsup-trace: ROS_DOMAIN_ID '%s': want a domain id from 0 to %d\n",
			env, ROS2DIAG_MAX_DOMAIN);
		return -1;
	}
	if (gethostname(d->host, sizeof(d->host) - 1))
		snprintf(d->host, sizeof(d->host), "localhost");
	safe_part(d->host, sizeof(d->host), d->host);
	if (ddsc_load())
		return -1;
	d->participant = dds.create_participant(d->domain, NULL, NULL);
	if (d->participant < 0) {
		fprintf(stderr, "rtsup-trace: --ros2-diagnostics: no DDS participant in domain %u: "
			"%s (see CYCLONEDDS_URI)\n", d->domain, dds.strretcode(d->participant));
		return -1;
	}
	topic = dds.create_topic(d->participant, &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
				 ROS2DIAG_TOPIC, NULL, NULL);
	/* ROS 2's default QoS: reliable, volatile, keep last 10 */
	qos = dds.create_qos();
	dds.qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
	dds.qset_durability(qos, DDS_DURABILITY_VOLATILE);
	dds.qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
	d->writer = topic < 0 ? topic : dds.create_writer(d->participant, topic, qos, NULL);
	dds.delete_qos(qos);
	if (d->writer < 0) {
		fprintf(stderr, "rtsup-trace: --ros2-diagnostics: no writer for %s: %s\n",
			ROS2DIAG_TOPIC, dds.strretcode(d->writer));
		dds.delete(d->participant);
		return -1;
	}
	d->on = true;
	fprintf(stderr, "rtsup-trace: publishing ROS 2 /diagnostics (DDS domain %u)\n",
		d->domain);
	return 0;
}

void ros2diag_publish(struct ros2diag *d, const struct model *m, const struct supervisor *s,
		      uint64_t now)
{
	ros2diag_msg msg;
	dds_return_t rc;

	if (!d->on)
		return;
	if (ros2diag_fill(&msg, m, s, d->host, now)) {
		ros2diag_msg_free(&msg);
		rc = DDS_RETCODE_OUT_OF_RESOURCES;
	} else {
		rc = dds.write(d->writer, &msg);
		ros2diag_msg_free(&msg);
	}
	/* a failing write is said once, and once when it works again; the run goes on */
	if (rc < 0 && !d->failing)
		fprintf(stderr, "rtsup-trace: --ros2-diagnostics: cannot publish: %s (retrying "
			"every interval)\n", dds.strretcode(rc));
	else if (rc >= 0 && d->failing)
		fprintf(stderr, "rtsup-trace: --ros2-diagnostics: publishing again\n");
	d->failing = rc < 0;
	d->published += rc >= 0;
}

void ros2diag_close(struct ros2diag *d)
{
	if (!d->on)
		return;
	/* what was written reaches the subscribers before the participant goes */
	dds.wait_for_acks(d->writer, DDS_MSECS(200));
	dds.delete(d->participant);
	d->on = false;
}
