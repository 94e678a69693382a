// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_canmodel.c - user/model/canmodel.c: the entries and interfaces of the CAN
 * model, node views, groups, the CANopen profile and every CAN check, driven
 * with frames accounted by include/can.h as the candump replay does and with
 * synthetic interface counters; a judge callback records each verdict.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "model/canmodel.h"
#include "hist.h"

#define US	1000ULL
#define MS	1000000ULL
#define SEC	1000000000ULL
#define EWMA_W	102
#define EFF	RTSUP_CAN_EFF_FLAG
#define RX	RTSUP_CAN_RX
#define TX	RTSUP_CAN_TX

/* One verdict given to the judge callback. */
struct rec {
	char comp[96];
	struct status old;
	struct status st;
};

#define MAX_REC 512

/* The model under test, its configuration and the verdicts of the last judge. */
struct fx {
	struct can_model m;
	struct config cfg;
	__u32 epoch;
	struct rec rec[MAX_REC];
	int nrec;
	int dropped;
};

static void rec_judge(void *ctx, const char *comp, const struct status *old,
		      const struct status *st, enum level *worst)
{
	struct fx *f = ctx;

	if (f->nrec == MAX_REC) {
		f->dropped++;
	} else {
		struct rec *r = &f->rec[f->nrec++];

		snprintf(r->comp, sizeof(r->comp), "%s", comp);
		r->old = *old;
		r->st = *st;
	}
	if (st->level > *worst)
		*worst = st->level;
}

static int setup(void **state)
{
	struct fx *f = calloc(1, sizeof(*f));

	if (!f)
		return -1;
	config_defaults(&f->cfg);
	f->m.start_ns = 1 * SEC;
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	struct fx *f = *state;

	can_model_free(&f->m);
	config_free(&f->cfg);
	free(f);
	return 0;
}

/* load_cfg - a YAML text through config_load, from a temporary file */
static void load_cfg(struct fx *f, const char *yaml)
{
	const char *tmp = getenv("TMPDIR");
	char path[256], err[512] = "";
	FILE *out;
	int fd, ret;

	snprintf(path, sizeof(path), "%s/test_canmodel.XXXXXX", tmp && *tmp ? tmp : "/tmp");
	fd = mkstemp(path);
	assert_true(fd >= 0);
	out = fdopen(fd, "w");
	assert_non_null(out);
	fputs(yaml, out);
	assert_int_equal(fclose(out), 0);
	config_free(&f->cfg);
	config_defaults(&f->cfg);
	ret = config_load(path, &f->cfg, err, sizeof(err));
	unlink(path);
	if (ret)
		print_error("%s\n", err);
	assert_int_equal(ret, 0);
}

/* iface - an interface of the model with its name and bitrate */
static struct can_iface *iface(struct fx *f, __u32 ifindex, const char *name, __u64 bitrate)
{
	struct can_iface *i = can_iface_get(&f->m, 0, ifindex, true);

	assert_non_null(i);
	snprintf(i->name, sizeof(i->name), "%s", name);
	i->bitrate = bitrate;
	return i;
}

/* frame - one frame accounted as the kernel and the candump replay do */
static void frame(struct fx *f, __u32 ifindex, __u32 dir, __u32 can_id, __u64 t,
		  const __u8 *data, __u32 len)
{
	static const __u8 zero[8];
	struct rtsup_can_key key = { .ifindex = ifindex, .dir = dir };
	struct can_iface *i = can_iface_get(&f->m, 0, ifindex, true);
	struct can_entry *e;

	if (!data)
		data = zero;
	assert_non_null(i);
	can_if_account(&i->cur, t, dir, can_id, len, RTSUP_CAN_CC, data);
	if (can_id & RTSUP_CAN_ERR_FLAG)
		return;
	key.can_id = can_key_id(can_id);
	e = can_entry_get(&f->m, &key, true);
	assert_non_null(e);
	if (f->cfg.can.canopen && can_is_sdo_response(key.can_id)) {
		struct rtsup_can_key rk = { .ifindex = ifindex, .can_id = key.can_id + 0x80 };
		struct can_entry *req;

		for (rk.dir = 0; rk.dir < RTSUP_CAN_DIRS; rk.dir++) {
			req = can_entry_get(&f->m, &rk, false);
			if (req && can_sdo_match(&e->cur, &req->cur, t))
				break;
		}
	}
	can_id_account(&e->cur, t, can_id, len, data, EWMA_W, f->epoch);
}

/* feed - n frames of one identifier, 'gap' apart, after *t; *t is the last */
static void feed(struct fx *f, __u32 ifindex, __u32 dir, __u32 can_id, __u64 *t, __u64 gap,
		 int n)
{
	int k;

	for (k = 0; k < n; k++) {
		*t += gap;
		frame(f, ifindex, dir, can_id, *t, NULL, 8);
	}
}

/* judge - end of an interval at 'now': judge it, then start the next */
static void judge(struct fx *f, __u64 now, double interval_s)
{
	f->nrec = 0;
	f->dropped = 0;
	f->m.bank = f->epoch & 1;
	f->epoch++;
	can_model_judge(&f->m, &f->cfg, now, interval_s, rec_judge, f);
	assert_int_equal(f->dropped, 0);
	can_model_next(&f->m);
}

/* rec_of - the verdict on a component in the last judge, NULL if none */
static const struct rec *rec_of(const struct fx *f, const char *comp)
{
	int i;

	for (i = 0; i < f->nrec; i++)
		if (!strcmp(f->rec[i].comp, comp))
			return &f->rec[i];
	return NULL;
}

/* verdict - the status a component got; it must have been judged */
static const struct status *verdict(const struct fx *f, const char *comp)
{
	const struct rec *r = rec_of(f, comp);

	if (!r)
		fail_msg("component '%s' was not judged", comp);
	return &r->st;
}

/* has_msg - index of the message containing 'sub', -1 if none */
static int has_msg(const struct status *s, const char *sub)
{
	int i;

	for (i = 0; i < s->nmsg; i++)
		if (strstr(s->msg[i], sub))
			return i;
	return -1;
}

/* expect - a component's level, and one message containing 'sub' if given */
static void expect(const struct fx *f, const char *comp, enum level l, const char *sub)
{
	const struct status *s = verdict(f, comp);

	if (s->level != l || (sub && has_msg(s, sub) < 0)) {
		char buf[1024];

		status_join(s, buf, sizeof(buf));
		fail_msg("%s: %s '%s', want %s with '%s'", comp, level_name(s->level), buf,
			 level_name(l), sub ? sub : "");
	}
}

/* --- entries and interfaces --- */

static int key_order(const struct rtsup_can_key *a, const struct rtsup_can_key *b)
{
	if (a->netns != b->netns)
		return a->netns < b->netns ? -1 : 1;
	if (a->ifindex != b->ifindex)
		return a->ifindex < b->ifindex ? -1 : 1;
	if (a->can_id != b->can_id)
		return a->can_id < b->can_id ? -1 : 1;
	if (a->dir != b->dir)
		return a->dir < b->dir ? -1 : 1;
	return 0;
}

static void test_entries_sorted(void **state)
{
	struct fx *f = *state;
	struct rtsup_can_key keys[300], k;
	unsigned int seed = 7;
	struct can_entry *e;
	int i, j, n = 0;

	for (i = 0; i < 300; i++) {
		seed = seed * 1103515245 + 12345;
		keys[i].ifindex = 1 + (seed >> 16) % 3;
		/* two namespaces number their interfaces alike: never one key */
		keys[i].netns = 4026531840U + (seed >> 24) % 2;
		keys[i].can_id = (seed >> 8) % 5 ? (seed >> 4) % 0x800 : EFF | (seed >> 3);
		keys[i].dir = (seed >> 20) & 1;
		for (j = 0; j < i && key_order(&keys[j], &keys[i]); j++)
			;
		if (j == i)
			n++;	/* a new key */
		e = can_entry_get(&f->m, &keys[i], true);
		assert_non_null(e);
		assert_int_equal(key_order(&e->key, &keys[i]), 0);
		if (j == i) {
			assert_int_equal(e->node, -1);
			assert_int_equal(e->cur.frames, 0);
			e->cur.frames = i + 1;	/* mark it: moves must keep it */
		}
	}
	assert_int_equal(f->m.n, n);
	assert_true(f->m.cap >= n);
	for (i = 1; i < f->m.n; i++)
		assert_true(key_order(&f->m.e[i - 1].key, &f->m.e[i].key) < 0);
	for (i = 0; i < 300; i++) {
		e = can_entry_get(&f->m, &keys[i], false);
		assert_non_null(e);
		assert_int_equal(key_order(&e->key, &keys[i]), 0);
		/* the mark of the key's first insert */
		for (j = 0; key_order(&keys[j], &keys[i]); j++)
			;
		assert_int_equal(e->cur.frames, j + 1);
	}
	/* an existing key is found, not added again */
	e = can_entry_get(&f->m, &keys[5], true);
	assert_int_equal(f->m.n, n);
	assert_int_equal(key_order(&e->key, &keys[5]), 0);
	/* a missing key is not created without 'create' */
	k = (struct rtsup_can_key){ .ifindex = 9, .can_id = 0x123, .dir = RX };
	assert_null(can_entry_get(&f->m, &k, false));
	assert_int_equal(f->m.n, n);
	/* the same id in the other direction, or 29-bit, is another key */
	k = (struct rtsup_can_key){ .ifindex = 9, .can_id = 0x7ff, .dir = RX };
	assert_non_null(can_entry_get(&f->m, &k, true));
	k.dir = TX;
	assert_null(can_entry_get(&f->m, &k, false));
	k = (struct rtsup_can_key){ .ifindex = 9, .can_id = EFF | 0x7ff, .dir = RX };
	assert_null(can_entry_get(&f->m, &k, false));
	assert_int_equal(f->m.n, n + 1);
}

static void test_entries_small(void **state)
{
	struct fx *f = *state;
	struct rtsup_can_key a = { 2, 0x100, RX, 0 }, b = { 1, EFF | 0x100, RX, 0 },
			     c = { 1, 0x100, TX, 0 },
			     d = { 1, 0x100, RX, 0 };

	can_entry_get(&f->m, &a, true);
	can_entry_get(&f->m, &b, true);
	can_entry_get(&f->m, &c, true);
	can_entry_get(&f->m, &d, true);
	assert_int_equal(f->m.n, 4);
	/* by interface, then identifier (11-bit before 29-bit), then direction */
	assert_int_equal(key_order(&f->m.e[0].key, &d), 0);
	assert_int_equal(key_order(&f->m.e[1].key, &c), 0);
	assert_int_equal(key_order(&f->m.e[2].key, &b), 0);
	assert_int_equal(key_order(&f->m.e[3].key, &a), 0);
}

static void test_iface_get(void **state)
{
	struct fx *f = *state;
	struct can_iface *i;
	__u32 n;

	assert_null(can_iface_get(&f->m, 0, 4, false));
	assert_string_equal(can_iface_name(&f->m, 0, 4), "?");
	i = can_iface_get(&f->m, 0, 4, true);
	assert_non_null(i);
	assert_int_equal(i->ifindex, 4);
	assert_string_equal(i->name, "if4");
	assert_true(i->load < 0);
	assert_int_equal(i->bitrate, 0);
	assert_ptr_equal(can_iface_get(&f->m, 0, 4, true), i);
	assert_int_equal(f->m.nifs, 1);
	snprintf(i->name, sizeof(i->name), "vcan0");
	assert_string_equal(can_iface_name(&f->m, 0, 4), "vcan0");
	/* at most CANMODEL_MAX_IFS interfaces */
	for (n = 100; f->m.nifs < CANMODEL_MAX_IFS; n++)
		assert_non_null(can_iface_get(&f->m, 0, n, true));
	assert_null(can_iface_get(&f->m, 0, 999, true));
	assert_int_equal(f->m.nifs, CANMODEL_MAX_IFS);
}

/* two network namespaces number their interfaces alike: vcan0 is ifindex 2 in each */
static void test_iface_same_ifindex_two_namespaces(void **state)
{
	struct rtsup_can_key ka = { 2, 0x123, TX, 4026531840U }, kb = { 2, 0x123, TX, 4026532300U };
	struct fx *f = *state;
	struct can_iface *a = can_iface_get(&f->m, 4026531840U, 2, true);
	struct can_iface *b = can_iface_get(&f->m, 4026532300U, 2, true);
	struct can_entry *ea, *eb;
	char buf[96];

	assert_non_null(a);
	assert_non_null(b);
	assert_ptr_not_equal(a, b);
	snprintf(a->name, sizeof(a->name), "vcan0");
	snprintf(b->name, sizeof(b->name), "vcan0@robot");
	assert_string_equal(can_iface_name(&f->m, 4026531840U, 2), "vcan0");
	assert_string_equal(can_iface_name(&f->m, 4026532300U, 2), "vcan0@robot");
	assert_string_equal(can_iface_name(&f->m, 0, 2), "?");
	ea = can_entry_get(&f->m, &ka, true);
	ea->cur.frames = 5;
	eb = can_entry_get(&f->m, &kb, true);
	assert_ptr_not_equal(can_entry_get(&f->m, &ka, false), eb);
	assert_int_equal(f->m.n, 2);
	assert_int_equal(can_entry_get(&f->m, &ka, false)->cur.frames, 5);
	assert_int_equal(can_entry_get(&f->m, &kb, false)->cur.frames, 0);
	can_component(&f->m, can_entry_get(&f->m, &kb, false), buf, sizeof(buf));
	assert_string_equal(buf, "vcan0@robot 0x123 tx");
}

/* an adapter unplugged (dev_ifindex 0): down; back, its old errors forgotten */
static void test_iface_replugged(void **state)
{
	struct fx *f = *state;
	struct can_iface *i = can_iface_get(&f->m, 0, 3, true);

	can_iface_link(i, true, -1);
	i->cur.err_frames = 1;
	i->cur.err_id = RTSUP_CAN_ERR_BUSOFF;
	assert_int_equal(can_iface_ctrl(i), CAN_CTRL_BUSOFF);
	can_iface_link(i, false, -1);	/* removed */
	assert_int_equal(can_iface_ctrl(i), CAN_CTRL_DOWN);
	can_iface_link(i, true, -1);	/* back, under the same counters */
	assert_int_equal(can_iface_ctrl(i), CAN_CTRL_OK);
}

/*
 * An identifier's gap bucket wraps between two intervals (0xFFFFFFF0 ->
 * 0x10): the lifetime counts grow by 0x20, and its lifetime p50 stays put.
 */
static void test_gap_life_wrap(void **state)
{
	struct fx *f = *state;
	struct rtsup_can_key k = { 3, 0x123, RX, 0 };
	struct can_entry *e = can_entry_get(&f->m, &k, true);
	__u32 b = hist_bucket(10000000);	/* 10 ms */
	__u64 h[HIST_BUCKETS];
	struct metric_view v;

	e->cur.gap.hist[b] = 0xFFFFFFF0;
	e->cur.gap.count = 0xFFFFFFF0;
	e->cur.gap.sum = 0xFFFFFFF0ULL * 10000000;
	e->cur.gap.min = e->cur.gap.max = 10000000;
	can_model_next(&f->m);
	e->cur.gap.hist[b] = 0x10;
	e->cur.gap.count += 0x20;
	e->cur.gap.sum += 0x20ULL * 10000000;
	can_gap_life(e, h);
	assert_int_equal(h[b], 0x100000010ULL);
	can_model_next(&f->m);	/* and once folded in */
	can_gap_life(e, h);
	assert_int_equal(h[b], 0x100000010ULL);
	can_gap_view_life(e, &v);
	assert_int_equal(v.p50, 10000000);
}

static void test_component_name(void **state)
{
	struct fx *f = *state;
	struct rtsup_can_key k1 = { 3, 0x123, RX, 0 }, k2 = { 3, EFF | 0x18fef100, TX, 0 },
			     k3 = { 7, 0x5, RX, 0 };
	char buf[96];

	iface(f, 3, "vcan0", 0);
	can_component(&f->m, can_entry_get(&f->m, &k1, true), buf, sizeof(buf));
	assert_string_equal(buf, "vcan0 0x123 rx");
	can_component(&f->m, can_entry_get(&f->m, &k2, true), buf, sizeof(buf));
	assert_string_equal(buf, "vcan0 0x18fef100 tx");
	can_component(&f->m, can_entry_get(&f->m, &k3, true), buf, sizeof(buf));
	assert_string_equal(buf, "? 0x5 rx");
}

static void test_model_next(void **state)
{
	struct fx *f = *state;
	struct can_iface *i = iface(f, 1, "can0", 500000);
	struct can_entry *e;
	__u64 t = 1 * SEC;

	feed(f, 1, RX, 0x181, &t, 10 * MS, 5);
	e = can_entry_get(&f->m, &(struct rtsup_can_key){ 1, 0x181, RX, 0 }, false);
	assert_non_null(e);
	assert_false(e->have_prev);
	assert_false(i->have_prev);
	assert_int_equal(e->prev.frames, 0);
	f->m.co[0][5].emcy_frames = 3;
	can_model_next(&f->m);
	assert_true(e->have_prev);
	assert_memory_equal(&e->prev, &e->cur, sizeof(e->cur));
	assert_true(i->have_prev);
	assert_memory_equal(&i->prev, &i->cur, sizeof(i->cur));
	assert_int_equal(i->prev.frames[RX], 5);
	assert_int_equal(f->m.co[0][5].emcy_prev, 3);
	/* new frames change cur only */
	feed(f, 1, RX, 0x181, &t, 10 * MS, 2);
	assert_int_equal(e->cur.frames, 7);
	assert_int_equal(e->prev.frames, 5);
	assert_int_equal(i->cur.frames[RX], 7);
	assert_int_equal(i->prev.frames[RX], 5);
}

/* --- identifiers no node names --- */

static void test_unnamed_learn_then_silent(void **state)
{
	struct fx *f = *state;
	struct can_entry *e;
	__u64 t = 1 * SEC - 10 * MS;

	iface(f, 3, "vcan0", 0);
	feed(f, 3, RX, 0x123, &t, 10 * MS, 100);	/* 1.00 .. 1.99 s */
	judge(f, 2 * SEC, 1.0);
	e = can_entry_get(&f->m, &(struct rtsup_can_key){ 3, 0x123, RX, 0 }, false);
	assert_non_null(e);
	/* 1 s of the 2 s learning time: nothing learned, nothing judged */
	assert_int_equal(e->learned, 0);
	assert_int_equal(e->node, -1);
	expect(f, "vcan0 0x123 rx", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "vcan0 0x123 rx")->nmsg, 0);

	feed(f, 3, RX, 0x123, &t, 10 * MS, 100);	/* .. 2.99 s */
	judge(f, 3 * SEC, 1.0);
	assert_int_equal(e->learned, 10 * MS);
	expect(f, "vcan0 0x123 rx", LEVEL_OK, NULL);

	/* silent: 2.9 periods OK, 3 WARN, 10 ERROR (the defaults) */
	judge(f, t + 29 * MS, 0.029);
	expect(f, "vcan0 0x123 rx", LEVEL_OK, NULL);
	judge(f, t + 30 * MS, 0.001);
	expect(f, "vcan0 0x123 rx", LEVEL_WARN,
	       "not responding: no frame for 30.0 ms (3 periods)");
	assert_int_equal(e->worst, LEVEL_WARN);
	judge(f, t + 99 * MS, 0.069);
	expect(f, "vcan0 0x123 rx", LEVEL_WARN, "not responding");
	judge(f, t + 100 * MS, 0.001);
	expect(f, "vcan0 0x123 rx", LEVEL_ERROR,
	       "not responding: no frame for 100.0 ms (10 periods)");
	assert_int_equal(verdict(f, "vcan0 0x123 rx")->nmsg, 1);
	assert_int_equal(verdict(f, "vcan0 0x123 rx")->level, LEVEL_ERROR);
	/* the callback is given the previous verdict */
	assert_int_equal(rec_of(f, "vcan0 0x123 rx")->old.level, LEVEL_WARN);
	assert_int_equal(e->worst, LEVEL_ERROR);
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);

	/* frames again: OK, the worst level stays */
	feed(f, 3, RX, 0x123, &t, 10 * MS, 3);
	judge(f, t + 1 * MS, 0.1);
	expect(f, "vcan0 0x123 rx", LEVEL_OK, NULL);
	assert_int_equal(e->worst, LEVEL_ERROR);
}

/* a burst is no period: it would make the silence after it "not responding" forever */
static void test_unnamed_burst_not_learned(void **state)
{
	struct fx *f = *state;
	struct can_entry *e;
	__u64 t = 1 * SEC;

	iface(f, 3, "vcan0", 0);
	/* an SDO-like exchange: 10 frames 1 ms apart, then nothing for 9 s */
	feed(f, 3, RX, 0x321, &t, 1 * MS, 10);
	judge(f, 2 * SEC, 1.0);
	judge(f, 10 * SEC, 8.0);
	e = can_entry_get(&f->m, &(struct rtsup_can_key){ 3, 0x321, RX, 0 }, false);
	assert_int_equal(e->learned, 0);
	expect(f, "vcan0 0x321 rx", LEVEL_OK, NULL);
	/* three gaps of 100 ms, 100 ms and 9.5 s: not steady, not learned */
	t = 10 * SEC;
	feed(f, 3, RX, 0x321, &t, 100 * MS, 2);
	frame(f, 3, RX, 0x321, 19 * SEC + 700 * MS, NULL, 1);
	judge(f, 19 * SEC + 701 * MS, 9.7);
	judge(f, 30 * SEC, 10.3);
	assert_int_equal(e->learned, 0);
	expect(f, "vcan0 0x321 rx", LEVEL_OK, NULL);
}

/* a learned period is dropped when the traffic turns sporadic, and learned again */
static void test_unnamed_unlearned_when_sporadic(void **state)
{
	struct fx *f = *state;
	struct can_entry *e;
	__u64 t = 1 * SEC - 10 * MS, now;
	int k;

	iface(f, 3, "vcan0", 0);
	feed(f, 3, RX, 0x124, &t, 10 * MS, 300);	/* 1.00 .. 3.99 s, steady */
	judge(f, 4 * SEC, 3.0);
	e = can_entry_get(&f->m, &(struct rtsup_can_key){ 3, 0x124, RX, 0 }, false);
	assert_int_equal(e->learned, 10 * MS);
	/* now bursts: 5 frames 1 ms apart every 400 ms, for three 1 s intervals */
	for (now = 5 * SEC, k = 0; k < 3; k++, now += SEC) {
		int b;

		for (b = 0; b < 2; b++) {
			t = now - SEC + b * 400 * MS + 100 * MS;
			feed(f, 3, RX, 0x124, &t, 1 * MS, 5);
		}
		judge(f, now, 1.0);
		/* two intervals of bursts: still the old period, "not responding" */
		if (k < 2)
			assert_int_equal(e->learned, 10 * MS);
	}
	/* the third: dropped, nothing judged any more */
	assert_int_equal(e->learned, 0);
	expect(f, "vcan0 0x124 rx", LEVEL_OK, NULL);
	/*
	 * steady again, 1 s intervals: the first interval holds the gap from
	 * the bursts, so that run fails; the next run of 2 s learns
	 */
	t = now - SEC;
	for (k = 0; k < 4; k++) {
		feed(f, 3, RX, 0x124, &t, 20 * MS, 50);
		judge(f, t + 1 * MS, 1.0);
		assert_int_equal(e->learned, k < 3 ? 0 : 20 * MS);
	}
}

/* CANopen: SDO, NMT, LSS and EMCY identifiers are sporadic, never learned */
static void test_canopen_sporadic_ids_never_learned(void **state)
{
	struct fx *f = *state;
	/* the last is a PDO: learned as any identifier */
	static const __u32 ids[] = { 0x000, 0x085, 0x585, 0x605, 0x7e4, 0x185 };
	__u64 t;
	size_t i, n = sizeof(ids) / sizeof(ids[0]);

	load_cfg(f, "can:\n  canopen: true\n");
	iface(f, 1, "can0", 0);
	for (i = 0; i < n; i++) {
		t = 1 * SEC;
		feed(f, 1, RX, ids[i], &t, 10 * MS, 300);	/* steady, even */
	}
	judge(f, t + 1 * MS, 3.0);
	for (i = 0; i < n; i++) {
		struct can_entry *e = can_entry_get(&f->m,
			&(struct rtsup_can_key){ 1, ids[i], RX, 0 }, false);

		assert_non_null(e);
		assert_int_equal(e->learned, i == n - 1 ? 10 * MS : 0);
	}
}

/* --- configured nodes and groups --- */

static const char NODES_YAML[] =
	"can:\n"
	"  nodes:\n"
	"    - name: shoulder\n"
	"      interface: vcan0\n"
	"      id: 0x181-0x182\n"
	"      direction: rx\n"
	"      period: 10ms\n"
	"      group: left_arm\n"
	"      init_timeout: 2s\n"
	"    - name: elbow\n"
	"      id: 0x190\n"
	"      period: 10ms\n"
	"      group: left_arm\n"
	"    - name: wrist\n"
	"      id: 0x1a0\n"
	"      period: 20ms\n"
	"      group: right_arm\n"
	"      init_timeout: 0\n";

static void test_node_never_seen(void **state)
{
	struct fx *f = *state;

	load_cfg(f, NODES_YAML);
	assert_int_equal(f->cfg.can.nnodes, 3);
	iface(f, 1, "vcan0", 0);
	judge(f, 2900 * MS, 1.9);
	expect(f, "node:shoulder", LEVEL_OK, NULL);
	expect(f, "node:elbow", LEVEL_OK, NULL);
	expect(f, "group:left_arm", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "group:left_arm")->nmsg, 0);

	/* 2 s after the start: the shoulder's init_timeout */
	judge(f, 3 * SEC, 0.1);
	expect(f, "node:shoulder", LEVEL_WARN, "not initialized: never seen in 2.0 s");
	expect(f, "node:elbow", LEVEL_OK, NULL);
	expect(f, "group:left_arm", LEVEL_WARN, "shoulder: WARN");
	assert_int_equal(verdict(f, "group:left_arm")->nmsg, 1);

	/* the elbow has the default 5 s; the wrist's 0 switches it off */
	judge(f, 6 * SEC, 3.0);
	expect(f, "node:shoulder", LEVEL_WARN, "not initialized");
	expect(f, "node:elbow", LEVEL_WARN, "not initialized: never seen in 5.0 s");
	expect(f, "node:wrist", LEVEL_OK, NULL);
	expect(f, "group:left_arm", LEVEL_WARN, "elbow: WARN");
	assert_int_equal(verdict(f, "group:left_arm")->nmsg, 2);
	expect(f, "group:right_arm", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "group:right_arm")->nmsg, 0);
	assert_int_equal(f->m.ngroups, 2);
	assert_int_equal(can_worst(&f->m), LEVEL_WARN);
}

static void test_node_range_aggregates(void **state)
{
	struct fx *f = *state;
	struct can_node_view *v;
	__u64 t1 = 1 * SEC - 10 * MS, t2 = 1 * SEC - 5 * MS, t3 = 1 * SEC, t4 = 1 * SEC;

	load_cfg(f, NODES_YAML);
	iface(f, 1, "vcan0", 0);
	iface(f, 2, "vcan1", 0);
	feed(f, 1, RX, 0x181, &t1, 10 * MS, 100);	/* 1.000 .. 1.990 */
	feed(f, 1, RX, 0x182, &t2, 10 * MS, 100);	/* 1.005 .. 1.995 */
	/* not the shoulder's: the other direction, the other interface */
	feed(f, 1, TX, 0x181, &t3, 10 * MS, 10);
	feed(f, 2, RX, 0x181, &t4, 10 * MS, 10);
	judge(f, 2 * SEC, 1.0);

	v = &f->m.nodes[0];
	assert_int_equal(f->m.nnodes, 3);
	assert_int_equal(v->frames, 200);
	assert_int_equal(v->frames_win, 200);
	assert_int_equal(v->last, 1995 * MS);
	assert_int_equal(v->period, 10 * MS);
	assert_int_equal(v->gap.count, 198);
	assert_int_equal(v->gap.min, 10 * MS);
	assert_int_equal(v->gap.max, 10 * MS);
	expect(f, "node:shoulder", LEVEL_OK, NULL);
	/* a node's identifiers are judged as the node, not alone */
	assert_null(rec_of(f, "vcan0 0x181 rx"));
	assert_null(rec_of(f, "vcan0 0x182 rx"));
	assert_non_null(rec_of(f, "vcan0 0x181 tx"));
	assert_non_null(rec_of(f, "vcan1 0x181 rx"));
	assert_int_equal(can_entry_get(&f->m, &(struct rtsup_can_key){ 1, 0x181, RX, 0 },
				       false)->node,
			 0);
	assert_int_equal(can_entry_get(&f->m, &(struct rtsup_can_key){ 1, 0x182, RX, 0 },
				       false)->node,
			 0);
	assert_int_equal(can_entry_get(&f->m, &(struct rtsup_can_key){ 1, 0x181, TX, 0 },
				       false)->node,
			 -1);
	assert_int_equal(can_entry_get(&f->m, &(struct rtsup_can_key){ 2, 0x181, RX, 0 },
				       false)->node,
			 -1);

	/* only 0x182 goes on: the node still answers */
	feed(f, 1, RX, 0x182, &t2, 10 * MS, 50);	/* .. 2.495 */
	judge(f, 2500 * MS, 0.5);
	assert_int_equal(v->frames, 250);
	assert_int_equal(v->frames_win, 50);
	assert_int_equal(v->last, 2495 * MS);
	expect(f, "node:shoulder", LEVEL_OK, NULL);

	/* then nothing: 3 periods WARN, 10 periods ERROR */
	judge(f, 2525 * MS, 0.025);
	expect(f, "node:shoulder", LEVEL_WARN, "not responding: no frame for 30.0 ms (3 periods)");
	assert_int_equal(v->frames_win, 0);
	judge(f, 2595 * MS, 0.07);
	expect(f, "node:shoulder", LEVEL_ERROR,
	       "not responding: no frame for 100.0 ms (10 periods)");
	assert_int_equal(verdict(f, "node:shoulder")->nmsg, 1);
	/* the group is as bad as its worst node and names it */
	expect(f, "group:left_arm", LEVEL_ERROR, "shoulder: ERROR");
	assert_int_equal(verdict(f, "group:left_arm")->nmsg, 1);
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);
}

static void test_group_worst_node(void **state)
{
	struct fx *f = *state;
	const struct status *g;
	__u64 t = 1 * SEC, tw = 1 * SEC;

	load_cfg(f, NODES_YAML);
	iface(f, 1, "vcan0", 0);
	/* the shoulder stops at 1.5 s; the elbow is never seen; the wrist is fine */
	feed(f, 1, RX, 0x181, &t, 10 * MS, 50);
	feed(f, 1, RX, 0x1a0, &tw, 20 * MS, 249);	/* .. 5.98 s */
	judge(f, 6 * SEC, 5.0);
	expect(f, "node:shoulder", LEVEL_ERROR, "not responding");
	expect(f, "node:elbow", LEVEL_WARN, "not initialized");
	expect(f, "node:wrist", LEVEL_OK, NULL);
	g = verdict(f, "group:left_arm");
	expect(f, "group:left_arm", LEVEL_ERROR, NULL);
	assert_int_equal(g->nmsg, 2);
	assert_string_equal(g->msg[0], "shoulder: ERROR");
	assert_string_equal(g->msg[1], "elbow: WARN");
	expect(f, "group:right_arm", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "group:right_arm")->nmsg, 0);
	assert_int_equal(f->m.groups[0].worst, LEVEL_ERROR);
	assert_string_equal(f->m.groups[0].name, "left_arm");
}

/*
 * The same verdict interval after interval: the callback's 'old' is the
 * previous verdict, messages included, so supervise.c's judge() counts one
 * violation, not one per interval. Nodes do that; groups must too.
 */
static void test_group_old_status_keeps_messages(void **state)
{
	struct fx *f = *state;
	const struct rec *r;

	load_cfg(f, NODES_YAML);
	iface(f, 1, "vcan0", 0);
	judge(f, 6 * SEC, 5.0);
	expect(f, "group:left_arm", LEVEL_WARN, "shoulder: WARN");
	judge(f, 7 * SEC, 1.0);
	r = rec_of(f, "node:shoulder");
	assert_non_null(r);
	assert_int_equal(r->old.level, LEVEL_WARN);
	assert_int_equal(r->old.nmsg, 1);
	assert_string_equal(r->old.msg[0], "not initialized: never seen in 5.0 s");
	r = rec_of(f, "group:left_arm");
	assert_non_null(r);
	assert_int_equal(r->st.level, LEVEL_WARN);
	assert_int_equal(r->old.level, LEVEL_WARN);
	/* canmodel.c judge_groups() resets the group's messages before judging */
	if (!status_same(&r->old, &r->st))
		fail_msg("group:left_arm: old verdict has %d messages, the same new one %d: "
			 "a new violation every interval", r->old.nmsg, r->st.nmsg);
}

static void test_node_learns_period(void **state)
{
	struct fx *f = *state;
	__u64 t = 1 * SEC - 20 * MS;

	load_cfg(f, "can:\n"
		    "  nodes:\n"
		    "    - name: imu\n"
		    "      id: 0x300\n"
		    "      learn: 1s\n");
	iface(f, 1, "can0", 0);
	feed(f, 1, RX, 0x300, &t, 20 * MS, 25);	/* 1.00 .. 1.48 */
	judge(f, 1490 * MS, 0.49);
	assert_int_equal(f->m.nodes[0].period, 0);
	expect(f, "node:imu", LEVEL_OK, NULL);
	feed(f, 1, RX, 0x300, &t, 20 * MS, 30);	/* .. 2.08 */
	judge(f, 2090 * MS, 0.6);
	assert_int_equal(f->m.nodes[0].period, 20 * MS);
	expect(f, "node:imu", LEVEL_OK, NULL);
	judge(f, t + 60 * MS, 0.05);
	expect(f, "node:imu", LEVEL_WARN, "not responding: no frame for 60.0 ms (3 periods)");
	judge(f, t + 200 * MS, 0.14);
	expect(f, "node:imu", LEVEL_ERROR, "(10 periods)");
}

static void test_node_gap_jitter(void **state)
{
	struct fx *f = *state;
	__u64 t = 1 * SEC - 10 * MS;

	load_cfg(f, "can:\n"
		    "  nodes:\n"
		    "    - name: drive\n"
		    "      id: 0x201\n"
		    "      period: 10ms\n"
		    "      jitter: {warn: 1ms, error: 3ms}\n");
	iface(f, 1, "can0", 0);
	/* exact gaps */
	feed(f, 1, RX, 0x201, &t, 10 * MS, 100);
	judge(f, t + 5 * MS, 1.0);
	expect(f, "node:drive", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "node:drive")->nmsg, 0);

	/* one gap of 12 ms: 2 ms from the period */
	feed(f, 1, RX, 0x201, &t, 10 * MS, 10);
	feed(f, 1, RX, 0x201, &t, 12 * MS, 1);
	feed(f, 1, RX, 0x201, &t, 10 * MS, 10);
	judge(f, t + 5 * MS, 0.2);
	expect(f, "node:drive", LEVEL_WARN, "gap jitter 2000.0 us > 1000.0 us");
	assert_int_equal(f->m.nodes[0].gap.max, 12 * MS);
	assert_int_equal(f->m.nodes[0].gap.min, 10 * MS);

	/* the next interval is clean again: the window forgot the 12 ms */
	feed(f, 1, RX, 0x201, &t, 10 * MS, 20);
	judge(f, t + 5 * MS, 0.2);
	expect(f, "node:drive", LEVEL_OK, NULL);
	assert_int_equal(f->m.nodes[0].gap.max, 10 * MS);

	/* a gap of 6 ms: 4 ms short, ERROR */
	feed(f, 1, RX, 0x201, &t, 10 * MS, 5);
	feed(f, 1, RX, 0x201, &t, 6 * MS, 1);
	feed(f, 1, RX, 0x201, &t, 10 * MS, 5);
	judge(f, t + 5 * MS, 0.2);
	expect(f, "node:drive", LEVEL_ERROR, "gap jitter 4000.0 us > 3000.0 us");

	/* exactly 3 ms off: not above the error limit, WARN */
	feed(f, 1, RX, 0x201, &t, 13 * MS, 1);
	feed(f, 1, RX, 0x201, &t, 10 * MS, 5);
	judge(f, t + 5 * MS, 0.2);
	expect(f, "node:drive", LEVEL_WARN, "gap jitter 3000.0 us > 1000.0 us");
	assert_int_equal(verdict(f, "node:drive")->nmsg, 1);
}

/* --- interfaces --- */

static void test_iface_bus_load(void **state)
{
	struct fx *f = *state;
	struct can_iface *i = iface(f, 1, "can0", 500000);
	struct can_iface *u = iface(f, 2, "vcan0", 0);

	/* 360000 of 500000 bits: 72 % */
	i->cur.bits[RX] = 300000;
	i->cur.bits[TX] = 60000;
	u->cur.bits[RX] = 10000000;
	judge(f, 2 * SEC, 1.0);
	assert_true(i->load > 0.7199 && i->load < 0.7201);
	expect(f, "can0", LEVEL_WARN, "bus load 72.0 % > 70 %");
	assert_int_equal(verdict(f, "can0")->nmsg, 1);
	/* no bitrate: no load, no check */
	assert_true(u->load < 0);
	expect(f, "vcan0", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "vcan0")->nmsg, 0);

	/* the interval's bits only: 460000 more, 92 % */
	i->cur.bits[RX] += 400000;
	i->cur.bits[TX] += 60000;
	judge(f, 3 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "bus load 92.0 % > 90 %");
	assert_int_equal(verdict(f, "can0")->nmsg, 1);

	/* exactly 70 % in half a second: not above */
	i->cur.bits[RX] += 175000;
	judge(f, 3500 * MS, 0.5);
	assert_true(i->load > 0.6999 && i->load < 0.7001);
	expect(f, "can0", LEVEL_OK, NULL);

	/* the load is per second of the interval: 17500 bits in 50 ms is 70 % */
	i->cur.bits[TX] += 17500;
	judge(f, 3550 * MS, 0.05);
	assert_true(i->load > 0.6999 && i->load < 0.7001);
	expect(f, "can0", LEVEL_OK, NULL);
	/* one bit more is above */
	i->cur.bits[TX] += 17501;
	judge(f, 3600 * MS, 0.05);
	expect(f, "can0", LEVEL_WARN, "bus load 70.0 % > 70 %");
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);
}

static void test_iface_bus_load_frames(void **state)
{
	struct fx *f = *state;
	struct can_iface *i = iface(f, 1, "can0", 125000);
	__u64 t = 1 * SEC;

	/* 100 frames of 8 bytes, 135 bits each, in 0.1 s at 125 kbit/s: 108 % */
	feed(f, 1, RX, 0x181, &t, 1 * MS, 100);
	judge(f, 1100 * MS, 0.1);
	assert_int_equal(i->cur.bits[RX], 13500);
	assert_true(i->load > 1.0799 && i->load < 1.0801);
	expect(f, "can0", LEVEL_ERROR, "bus load 108.0 % > 90 %");
	/* nothing in the next interval */
	judge(f, 1200 * MS, 0.1);
	assert_true(i->load == 0);
	expect(f, "can0", LEVEL_OK, NULL);
	/* busload limits of 0 switch the check off */
	f->cfg.can.busload_warn = 0;
	f->cfg.can.busload_error = 0;
	feed(f, 1, RX, 0x181, &t, 1 * MS, 100);
	judge(f, 1300 * MS, 0.1);
	expect(f, "can0", LEVEL_OK, NULL);
}

static void err_frames(struct fx *f, __u32 ifindex, __u32 id, __u8 crtl, int n, __u64 t)
{
	__u8 d[8] = { 0, crtl, 0, 0, 0, 0, 0, 0 };
	int k;

	for (k = 0; k < n; k++)
		frame(f, ifindex, RX, RTSUP_CAN_ERR_FLAG | id, t + k, d, 8);
}

static void test_iface_error_frames(void **state)
{
	struct fx *f = *state;
	struct can_iface *i = iface(f, 1, "can0", 0);

	err_frames(f, 1, 0x08, 0, 1, 1 * SEC);	/* CAN_ERR_PROT */
	judge(f, 2 * SEC, 1.0);
	expect(f, "can0", LEVEL_WARN, "1 error frames in the last interval");
	assert_int_equal(verdict(f, "can0")->nmsg, 1);
	/* an error frame is no identifier of the bus */
	assert_int_equal(f->m.n, 0);
	assert_int_equal(i->cur.frames[RX], 0);

	err_frames(f, 1, 0x08, 0, 99, 2 * SEC);
	judge(f, 3 * SEC, 1.0);
	expect(f, "can0", LEVEL_WARN, "99 error frames in the last interval");

	err_frames(f, 1, 0x08, 0, 100, 3 * SEC);
	judge(f, 4 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "100 error frames in the last interval");
	assert_int_equal(verdict(f, "can0")->nmsg, 1);

	judge(f, 5 * SEC, 1.0);
	expect(f, "can0", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "can0")->nmsg, 0);
	assert_int_equal(i->worst, LEVEL_ERROR);
}

static void test_iface_bus_off(void **state)
{
	struct fx *f = *state;

	iface(f, 1, "can0", 0);
	err_frames(f, 1, RTSUP_CAN_ERR_BUSOFF, 0, 1, 1 * SEC);
	judge(f, 2 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "bus-off");
	assert_true(has_msg(verdict(f, "can0"), "1 error frames") >= 0);
	/* the controller stays bus-off until an error frame says otherwise */
	judge(f, 3 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "bus-off");
	/* CAN_ERR_RESTARTED (0x100): back on the bus */
	err_frames(f, 1, 0x100, 0, 1, 3100 * MS);
	judge(f, 3200 * MS, 1.0);
	expect(f, "can0", LEVEL_WARN, "1 error frames");
	judge(f, 3300 * MS, 1.0);
	expect(f, "can0", LEVEL_OK, NULL);
	/* bus-off needs no error frame threshold */
	f->cfg.can.err_warn = 0;
	f->cfg.can.err_error = 0;
	err_frames(f, 1, RTSUP_CAN_ERR_BUSOFF | RTSUP_CAN_ERR_CRTL, RTSUP_CAN_ERR_CRTL_TX_PASSIVE,
		   1, 3500 * MS);
	judge(f, 4 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "bus-off");
	assert_int_equal(verdict(f, "can0")->nmsg, 1);
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);
}

/* a link that comes down and up again (a restart, a re-plug) is a new controller */
static void test_iface_bus_off_cleared_by_link_up(void **state)
{
	struct fx *f = *state;
	struct can_iface *i;

	iface(f, 1, "vcan0", 0);
	i = can_iface_get(&f->m, 0, 1, false);
	can_iface_link(i, true, -1);		/* a vcan: no controller state */
	err_frames(f, 1, RTSUP_CAN_ERR_BUSOFF, 0, 1, 1 * SEC);
	can_iface_link(i, true, -1);
	judge(f, 2 * SEC, 1.0);
	expect(f, "vcan0", LEVEL_ERROR, "bus-off");
	can_iface_link(i, false, -1);
	judge(f, 3 * SEC, 1.0);
	expect(f, "vcan0", LEVEL_ERROR, "interface down");
	assert_int_equal(verdict(f, "vcan0")->nmsg, 1);
	/* up again, no error frame since: what the old one said is gone */
	can_iface_link(i, true, -1);
	judge(f, 4 * SEC, 1.0);
	expect(f, "vcan0", LEVEL_OK, NULL);
	/* a new bus-off after that counts again */
	err_frames(f, 1, RTSUP_CAN_ERR_BUSOFF, 0, 1, 4100 * MS);
	can_iface_link(i, true, -1);
	judge(f, 5 * SEC, 1.0);
	expect(f, "vcan0", LEVEL_ERROR, "bus-off");
}

/* a real controller says its state: that beats the last error frame */
static void test_iface_controller_state_from_netlink(void **state)
{
	struct fx *f = *state;
	struct can_iface *i;

	iface(f, 1, "can0", 0);
	f->cfg.can.err_warn = 0;
	f->cfg.can.err_error = 0;
	i = can_iface_get(&f->m, 0, 1, false);
	err_frames(f, 1, RTSUP_CAN_ERR_BUSOFF, 0, 1, 1 * SEC);
	can_iface_link(i, true, 3);		/* CAN_STATE_BUS_OFF */
	judge(f, 2 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "bus-off");
	/* restarted by the driver (restart-ms) with no error frame: active again */
	can_iface_link(i, true, 0);		/* CAN_STATE_ERROR_ACTIVE */
	judge(f, 3 * SEC, 1.0);
	expect(f, "can0", LEVEL_OK, NULL);
	can_iface_link(i, true, 2);		/* CAN_STATE_ERROR_PASSIVE */
	judge(f, 4 * SEC, 1.0);
	expect(f, "can0", LEVEL_WARN, "controller error-passive");
	can_iface_link(i, true, 4);		/* CAN_STATE_STOPPED */
	judge(f, 5 * SEC, 1.0);
	expect(f, "can0", LEVEL_ERROR, "interface down");
}

static void test_iface_error_passive(void **state)
{
	struct fx *f = *state;

	iface(f, 1, "can0", 0);
	f->cfg.can.err_warn = 0;	/* the controller state alone */
	f->cfg.can.err_error = 0;
	judge(f, 1 * SEC, 1.0);
	expect(f, "can0", LEVEL_OK, NULL);

	err_frames(f, 1, RTSUP_CAN_ERR_CRTL, RTSUP_CAN_ERR_CRTL_RX_PASSIVE, 1, 1100 * MS);
	judge(f, 2 * SEC, 1.0);
	expect(f, "can0", LEVEL_WARN, "controller error-passive (rx)");
	/* the state holds until another error frame tells otherwise */
	judge(f, 3 * SEC, 1.0);
	expect(f, "can0", LEVEL_WARN, "controller error-passive (rx)");
	assert_int_equal(verdict(f, "can0")->nmsg, 1);

	err_frames(f, 1, RTSUP_CAN_ERR_CRTL,
		   RTSUP_CAN_ERR_CRTL_TX_PASSIVE | RTSUP_CAN_ERR_CRTL_RX_WARNING, 1, 3100 * MS);
	judge(f, 4 * SEC, 1.0);
	expect(f, "can0", LEVEL_WARN, "controller error-passive (tx)");

	/* back to warning level: no longer passive */
	err_frames(f, 1, RTSUP_CAN_ERR_CRTL, RTSUP_CAN_ERR_CRTL_TX_WARNING, 1, 4100 * MS);
	judge(f, 5 * SEC, 1.0);
	expect(f, "can0", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "can0")->nmsg, 0);

	/* passive bits without the CAN_ERR_CRTL class are not the controller's state */
	err_frames(f, 1, 0x08, RTSUP_CAN_ERR_CRTL_RX_PASSIVE, 1, 5100 * MS);
	judge(f, 6 * SEC, 1.0);
	expect(f, "can0", LEVEL_OK, NULL);
	assert_int_equal(can_worst(&f->m), LEVEL_WARN);
}

/* --- CANopen --- */

static const char CANOPEN_YAML[] =
	"can:\n"
	"  canopen: true\n"
	"  heartbeat_timeout: 500ms\n";

static void heartbeat(struct fx *f, __u32 ifindex, int node, __u8 state, __u64 t)
{
	__u8 d[1] = { state };

	frame(f, ifindex, RX, 0x700 + node, t, d, 1);
}

static void test_canopen_heartbeat(void **state)
{
	struct fx *f = *state;

	load_cfg(f, CANOPEN_YAML);
	assert_true(f->cfg.can.canopen);
	assert_int_equal(f->cfg.can.heartbeat_timeout_ns, 500 * MS);
	iface(f, 1, "can0", 0);

	heartbeat(f, 1, 5, 0x05, 1000 * MS);
	judge(f, 1100 * MS, 0.1);
	assert_true(f->m.co[0][5].seen);
	assert_int_equal(f->m.co[0][5].nmt_state, 0x05);
	assert_int_equal(f->m.co[0][5].heartbeat_last, 1000 * MS);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "canopen:can0:5")->nmsg, 0);
	/* only the nodes seen are judged */
	assert_null(rec_of(f, "canopen:can0:4"));
	assert_null(rec_of(f, "canopen:can0:0"));

	heartbeat(f, 1, 5, 0x7f, 1200 * MS);
	judge(f, 1300 * MS, 0.2);
	expect(f, "canopen:can0:5", LEVEL_WARN, "NMT state pre-operational");

	heartbeat(f, 1, 5, 0x04, 1400 * MS);
	judge(f, 1500 * MS, 0.2);
	expect(f, "canopen:can0:5", LEVEL_WARN, "NMT state stopped");

	heartbeat(f, 1, 5, 0x00, 1600 * MS);
	judge(f, 1700 * MS, 0.2);
	expect(f, "canopen:can0:5", LEVEL_WARN, "NMT state boot-up");

	heartbeat(f, 1, 5, 0x05, 1800 * MS);
	judge(f, 1900 * MS, 0.2);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);

	/* 500 ms without a heartbeat is still in time, 501 ms is not */
	judge(f, 2300 * MS, 0.4);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
	judge(f, 2301 * MS, 0.001);
	expect(f, "canopen:can0:5", LEVEL_ERROR, "no heartbeat for 501 ms");
	assert_int_equal(verdict(f, "canopen:can0:5")->nmsg, 1);
	assert_int_equal(f->m.co[0][5].worst, LEVEL_ERROR);
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);

	/* a timeout says so, not the NMT state of the last heartbeat */
	heartbeat(f, 1, 9, 0x7f, 2400 * MS);
	judge(f, 3 * SEC, 0.7);
	expect(f, "canopen:can0:9", LEVEL_ERROR, "no heartbeat for 600 ms");
	assert_int_equal(verdict(f, "canopen:can0:9")->nmsg, 1);
	assert_string_equal(can_nmt_name(0x42), "unknown");
}

/*
 * The live loop takes 'now' before it reads the maps: a heartbeat can be
 * stamped after 'now'. It is not older than the timeout.
 */
static void test_canopen_heartbeat_after_now(void **state)
{
	struct fx *f = *state;

	load_cfg(f, CANOPEN_YAML);
	iface(f, 1, "can0", 0);
	heartbeat(f, 1, 5, 0x05, 2000 * MS + 1);
	judge(f, 2000 * MS, 1.0);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
}

/*
 * CANopen node guarding: the master's remote request on 0x700+n (tx) asks
 * the node for its state; the node's answer (rx) is what tells the state.
 * The request is no heartbeat of the node.
 */
static void test_canopen_guarding_rtr_not_heartbeat(void **state)
{
	struct fx *f = *state;
	__u64 t;

	load_cfg(f, CANOPEN_YAML);
	iface(f, 1, "can0", 0);
	heartbeat(f, 1, 5, 0x05, 1000 * MS);
	frame(f, 1, TX, RTSUP_CAN_RTR_FLAG | 0x705, 1100 * MS, NULL, 1);
	judge(f, 1150 * MS, 0.15);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
	assert_int_equal(f->m.co[0][5].nmt_state, 0x05);
	/* the node stops answering; the master keeps asking */
	for (t = 1200 * MS; t <= 1600 * MS; t += 100 * MS)
		frame(f, 1, TX, RTSUP_CAN_RTR_FLAG | 0x705, t, NULL, 1);
	judge(f, 1650 * MS, 0.5);
	expect(f, "canopen:can0:5", LEVEL_ERROR, "no heartbeat for 650 ms");
}

/*
 * A robot often has one CANopen bus per arm, each with nodes 1..n. Node 1
 * of can0 dies while node 1 of can1 goes on: some component must say so.
 */
static void test_canopen_same_node_two_buses(void **state)
{
	struct fx *f = *state;
	bool error = false;
	__u64 t;
	int i;

	load_cfg(f, CANOPEN_YAML);
	iface(f, 1, "can0", 0);
	iface(f, 2, "can1", 0);
	heartbeat(f, 1, 1, 0x05, 1000 * MS);
	for (t = 1000 * MS; t <= 2000 * MS; t += 100 * MS)
		heartbeat(f, 2, 1, 0x05, t);
	judge(f, 2050 * MS, 1.05);
	for (i = 0; i < f->nrec; i++)
		if (strstr(f->rec[i].comp, "canopen") && f->rec[i].st.level == LEVEL_ERROR &&
		    has_msg(&f->rec[i].st, "no heartbeat") >= 0)
			error = true;
	if (!error)
		fail_msg("node 1 of can0 silent for 1050 ms, node 1 of can1 alive: no CANopen "
			 "component is ERROR (canopen:1 is %s)",
			 rec_of(f, "canopen:can0:1") ? level_name(rec_of(f, "canopen:can0:1")->st.level) : "-");
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);
}

static void test_canopen_emcy(void **state)
{
	struct fx *f = *state;
	static const __u8 emcy[8] = { 0x30, 0x81, 0x11, 0, 0, 0, 0, 0 };
	static const __u8 emcy2[8] = { 0x10, 0x23, 0x05, 0, 0, 0, 0, 0 };
	static const __u8 reset[8] = { 0 };

	load_cfg(f, CANOPEN_YAML);
	iface(f, 1, "can0", 0);
	frame(f, 1, RX, 0x085, 1000 * MS, emcy, 8);
	judge(f, 1100 * MS, 0.1);
	assert_int_equal(f->m.co[0][5].emcy_code, 0x8130);
	assert_int_equal(f->m.co[0][5].emcy_reg, 0x11);
	assert_int_equal(f->m.co[0][5].emcy_frames, 1);
	expect(f, "canopen:can0:5", LEVEL_ERROR, "EMCY error code 0x8130, register 0x11");
	assert_int_equal(verdict(f, "canopen:can0:5")->nmsg, 1);

	/* no new emergency: OK, though the last code is still 0x8130 */
	judge(f, 1200 * MS, 0.1);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "canopen:can0:5")->nmsg, 0);

	/* two in one interval: the last one's code */
	frame(f, 1, RX, 0x085, 1210 * MS, emcy, 8);
	frame(f, 1, RX, 0x085, 1220 * MS, emcy2, 8);
	judge(f, 1300 * MS, 0.1);
	expect(f, "canopen:can0:5", LEVEL_ERROR, "EMCY error code 0x2310, register 0x05");
	assert_int_equal(f->m.co[0][5].emcy_frames, 3);

	/* error reset: code 0 is OK, and says so */
	frame(f, 1, RX, 0x085, 1310 * MS, reset, 8);
	judge(f, 1400 * MS, 0.1);
	expect(f, "canopen:can0:5", LEVEL_OK, "EMCY error reset");
	assert_int_equal(verdict(f, "canopen:can0:5")->nmsg, 1);
	judge(f, 1500 * MS, 0.1);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
	assert_int_equal(verdict(f, "canopen:can0:5")->nmsg, 0);
	assert_int_equal(f->m.co[0][5].worst, LEVEL_ERROR);
	/* 0x080 itself is the SYNC, no node */
	frame(f, 1, RX, 0x080, 1510 * MS, emcy, 8);
	judge(f, 1600 * MS, 0.1);
	assert_false(f->m.co[0][0].seen);
	assert_null(rec_of(f, "canopen:can0:0"));
}

static void test_canopen_sdo(void **state)
{
	struct fx *f = *state;
	static const __u8 up[8] = { 0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0 };

	load_cfg(f, CANOPEN_YAML);
	iface(f, 1, "can0", 0);
	frame(f, 1, TX, 0x605, 1000 * MS, up, 8);
	frame(f, 1, RX, 0x585, 1000 * MS + 300 * US, up, 8);
	frame(f, 1, TX, 0x605, 1010 * MS, up, 8);
	frame(f, 1, RX, 0x585, 1011 * MS + 200 * US, up, 8);
	/* an answer without a request is not timed */
	frame(f, 1, RX, 0x585, 1020 * MS, up, 8);
	frame(f, 1, TX, 0x605, 1030 * MS, up, 8);
	frame(f, 1, RX, 0x585, 1032 * MS, up, 8);
	judge(f, 1100 * MS, 0.1);
	assert_true(f->m.co[0][5].seen);
	assert_int_equal(f->m.co[0][5].sdo_count, 3);
	assert_int_equal(f->m.co[0][5].sdo_sum, 300 * US + 1200 * US + 2 * MS);
	assert_int_equal(f->m.co[0][5].sdo_max, 2 * MS);
	expect(f, "canopen:can0:5", LEVEL_OK, NULL);
	/* the counts are totals: judging again does not add them twice */
	judge(f, 1200 * MS, 0.1);
	assert_int_equal(f->m.co[0][5].sdo_count, 3);
	assert_int_equal(f->m.co[0][5].sdo_sum, 3500 * US);
	/* a request: the node is not seen from it */
	assert_false(f->m.co[0][6].seen);
}

static void test_canopen_off(void **state)
{
	struct fx *f = *state;
	static const __u8 emcy[8] = { 0x30, 0x81, 0x11, 0, 0, 0, 0, 0 };
	int i;

	assert_false(f->cfg.can.canopen);
	iface(f, 1, "can0", 0);
	heartbeat(f, 1, 5, 0x7f, 1000 * MS);
	frame(f, 1, RX, 0x085, 1000 * MS, emcy, 8);
	judge(f, 3 * SEC, 2.0);
	assert_false(f->m.co[0][5].seen);
	for (i = 0; i < f->nrec; i++)
		assert_null(strstr(f->rec[i].comp, "canopen:"));
	/* judged as plain identifiers */
	assert_non_null(rec_of(f, "can0 0x705 rx"));
	assert_non_null(rec_of(f, "can0 0x85 rx"));
	assert_int_equal(can_worst(&f->m), LEVEL_OK);
}

static void test_canopen_29bit_ignored(void **state)
{
	struct fx *f = *state;
	__u8 d[1] = { 0x7f };

	load_cfg(f, CANOPEN_YAML);
	iface(f, 1, "can0", 0);
	frame(f, 1, RX, EFF | 0x705, 1000 * MS, d, 1);
	judge(f, 1100 * MS, 0.1);
	assert_false(f->m.co[0][5].seen);
	assert_null(rec_of(f, "canopen:can0:5"));
}

static void test_can_worst(void **state)
{
	struct fx *f = *state;

	assert_int_equal(can_worst(&f->m), LEVEL_OK);
	iface(f, 1, "can0", 0);
	iface(f, 2, "can1", 0);
	judge(f, 1 * SEC, 1.0);
	assert_int_equal(can_worst(&f->m), LEVEL_OK);
	err_frames(f, 2, 0x08, 0, 1, 1100 * MS);
	judge(f, 2 * SEC, 1.0);
	assert_int_equal(can_worst(&f->m), LEVEL_WARN);
	/* the worst level reached, not the current one */
	judge(f, 3 * SEC, 1.0);
	expect(f, "can1", LEVEL_OK, NULL);
	assert_int_equal(can_worst(&f->m), LEVEL_WARN);
	err_frames(f, 1, RTSUP_CAN_ERR_BUSOFF, 0, 1, 3100 * MS);
	judge(f, 4 * SEC, 1.0);
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);
	assert_int_equal(f->m.ifs[0].worst, LEVEL_ERROR);
	assert_int_equal(f->m.ifs[1].worst, LEVEL_WARN);
	/* a CANopen node's worst counts too */
	f->m.co[0][3].worst = LEVEL_STALE;
	assert_int_equal(can_worst(&f->m), LEVEL_ERROR);
}

#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(test_entries_sorted),
		T(test_entries_small),
		T(test_iface_get),
		T(test_iface_same_ifindex_two_namespaces),
		T(test_iface_replugged),
		T(test_component_name),
		T(test_gap_life_wrap),
		T(test_model_next),
		T(test_unnamed_learn_then_silent),
		T(test_unnamed_burst_not_learned),
		T(test_unnamed_unlearned_when_sporadic),
		T(test_canopen_sporadic_ids_never_learned),
		T(test_node_never_seen),
		T(test_node_range_aggregates),
		T(test_group_worst_node),
		T(test_group_old_status_keeps_messages),
		T(test_node_learns_period),
		T(test_node_gap_jitter),
		T(test_iface_bus_load),
		T(test_iface_bus_load_frames),
		T(test_iface_error_frames),
		T(test_iface_bus_off),
		T(test_iface_bus_off_cleared_by_link_up),
		T(test_iface_controller_state_from_netlink),
		T(test_iface_error_passive),
		T(test_canopen_heartbeat),
		T(test_canopen_heartbeat_after_now),
		T(test_canopen_guarding_rtr_not_heartbeat),
		T(test_canopen_same_node_two_buses),
		T(test_canopen_emcy),
		T(test_canopen_sdo),
		T(test_canopen_off),
		T(test_canopen_29bit_ignored),
		T(test_can_worst),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
