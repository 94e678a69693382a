// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_can.c - the CAN frame accounting of include/can.h, the code the BPF
 * programs and the candump replay share: frame bits on the wire, key ids,
 * per-identifier and per-interface counters, CANopen SDO matching.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include <pthread.h>

#include "can.h"

#define US	1000ULL
#define MS	1000000ULL
#define EWMA_W	102	/* 0.1 of RTSUP_EWMA_ONE */

/* sff_bits / eff_bits - the worst-case stuffing formula, written out again */
static __u32 sff_bits(__u32 n)
{
	return 47 + 8 * n + (34 + 8 * n - 1) / 4;
}

static __u32 eff_bits(__u32 n)
{
	return 67 + 8 * n + (54 + 8 * n - 1) / 4;
}

/* a zeroed entry with the statistics as metric_init leaves them */
static void id_init(struct rtsup_can_id *v)
{
	memset(v, 0, sizeof(*v));
	metric_init(&v->gap);
}

static void test_frame_bits_formula(void **state)
{
	__u32 n;

	for (n = 0; n <= 8; n++) {
		assert_int_equal(can_frame_bits(0x123, n, RTSUP_CAN_CC), sff_bits(n));
		assert_int_equal(can_frame_bits(0x7ff, n, RTSUP_CAN_CC), sff_bits(n));
		assert_int_equal(can_frame_bits(RTSUP_CAN_EFF_FLAG | 0x18fef100, n, RTSUP_CAN_CC),
				 eff_bits(n));
		/* canbusload's CFL_WORSTCASE closed form: 55 + 10n and 80 + 10n */
		assert_int_equal(sff_bits(n), 55 + 10 * n);
		assert_int_equal(eff_bits(n), 80 + 10 * n);
		/* a remote request carries no data, whatever its DLC */
		assert_int_equal(can_frame_bits(RTSUP_CAN_RTR_FLAG | 0x123, n, RTSUP_CAN_CC),
				 sff_bits(0));
		assert_int_equal(can_frame_bits(RTSUP_CAN_EFF_FLAG | RTSUP_CAN_RTR_FLAG | 0x1234,
						n, RTSUP_CAN_CC), eff_bits(0));
	}
}

static void test_frame_bits_values(void **state)
{
	/* by hand: 47 + 64 + 97/4 = 111 + 24 */
	assert_int_equal(can_frame_bits(0x181, 8, RTSUP_CAN_CC), 135);
	/* 67 + 24 + 77/4 = 91 + 19 */
	assert_int_equal(can_frame_bits(RTSUP_CAN_EFF_FLAG | 0x100, 3, RTSUP_CAN_CC), 110);
	/* 47 + 33/4 */
	assert_int_equal(can_frame_bits(RTSUP_CAN_RTR_FLAG | 0x181, 8, RTSUP_CAN_CC), 55);
	assert_int_equal(can_frame_bits(0x181, 0, RTSUP_CAN_CC), 55);
	assert_int_equal(can_frame_bits(RTSUP_CAN_EFF_FLAG, 0, RTSUP_CAN_CC), 80);
	assert_int_equal(can_frame_bits(RTSUP_CAN_EFF_FLAG | 0x1fffffff, 8, RTSUP_CAN_CC), 160);
	/* a classic frame never has more than 8 bytes on the wire */
	assert_int_equal(can_frame_bits(0x181, 15, RTSUP_CAN_CC), 135);
}

static void test_key_id(void **state)
{
	assert_int_equal(can_key_id(0x123), 0x123);
	assert_int_equal(can_key_id(RTSUP_CAN_RTR_FLAG | 0x123), 0x123);
	/* bits above the 11-bit mask of a standard frame are dropped */
	assert_int_equal(can_key_id(0x1fff), 0x7ff);
	assert_int_equal(can_key_id(RTSUP_CAN_EFF_FLAG | 0x18fef100),
			 RTSUP_CAN_EFF_FLAG | 0x18fef100);
	assert_int_equal(can_key_id(RTSUP_CAN_EFF_FLAG | RTSUP_CAN_RTR_FLAG | 0x1fffffff),
			 RTSUP_CAN_EFF_FLAG | 0x1fffffff);
	/* an 11-bit 0x123 and a 29-bit 0x123 are different keys */
	assert_int_not_equal(can_key_id(0x123), can_key_id(RTSUP_CAN_EFF_FLAG | 0x123));
	assert_int_equal(can_key_id(RTSUP_CAN_ERR_FLAG | 0x40), 0x40);
}

static void test_id_account_first_and_gaps(void **state)
{
	static const __u8 d[8] = { 1, 2, 3, 4, 5, 6, 7, 8 };
	struct rtsup_can_id v;

	id_init(&v);
	can_id_account(&v, 1000 * MS, 0x181, 8, d, EWMA_W, 1);
	assert_int_equal(v.frames, 1);
	assert_int_equal(v.bytes, 8);
	assert_int_equal(v.first, 1000 * MS);
	assert_int_equal(v.last, 1000 * MS);
	assert_int_equal(v.gap.count, 0);	/* no gap before the first frame */
	assert_int_equal(v.len, 8);
	assert_memory_equal(v.data, d, 8);

	can_id_account(&v, 1010 * MS, 0x181, 8, d, EWMA_W, 1);
	can_id_account(&v, 1022 * MS, 0x181, 4, d, EWMA_W, 1);
	can_id_account(&v, 1030 * MS + 5, 0x181, 2, d, EWMA_W, 1);
	assert_int_equal(v.frames, 4);
	assert_int_equal(v.bytes, 22);
	assert_int_equal(v.first, 1000 * MS);
	assert_int_equal(v.last, 1030 * MS + 5);
	assert_int_equal(v.gap.count, 3);
	assert_int_equal(v.gap.sum, 30 * MS + 5);
	assert_int_equal(v.gap.min, 8 * MS + 5);
	assert_int_equal(v.gap.max, 12 * MS);
	assert_int_equal(v.gap.win[1].min, 8 * MS + 5);
	assert_int_equal(v.gap.win[1].max, 12 * MS);
	assert_int_equal(v.rtr, 0);
}

static void test_id_account_zero_entry(void **state)
{
	static const __u8 d[2] = { 0xaa, 0xbb };
	struct rtsup_can_id v;

	/* as the kernel creates it: all zero, no metric_init */
	memset(&v, 0, sizeof(v));
	can_id_account(&v, 5 * MS, 0x200, 2, d, EWMA_W, 3);
	can_id_account(&v, 7 * MS, 0x200, 2, d, EWMA_W, 3);
	can_id_account(&v, 10 * MS, 0x200, 2, d, EWMA_W, 3);
	assert_int_equal(v.first, 5 * MS);
	assert_int_equal(v.gap.count, 2);
	assert_int_equal(v.gap.min, 2 * MS);
	assert_int_equal(v.gap.max, 3 * MS);
	/* epoch 3 differs from the zero entry's 0: bank 1 was reset first */
	assert_int_equal(v.epoch, 3);
	assert_int_equal(v.gap.win[1].min, 2 * MS);
	assert_int_equal(v.gap.win[1].max, 3 * MS);
}

static void test_id_account_epoch_bank(void **state)
{
	static const __u8 d[1] = { 0 };
	struct rtsup_can_id v;

	id_init(&v);
	can_id_account(&v, 0, 0x10, 1, d, EWMA_W, 1);
	can_id_account(&v, 5 * MS, 0x10, 1, d, EWMA_W, 1);	/* gap 5 in bank 1 */
	can_id_account(&v, 6 * MS, 0x10, 1, d, EWMA_W, 1);	/* gap 1 in bank 1 */
	assert_int_equal(v.gap.win[1].min, 1 * MS);
	assert_int_equal(v.gap.win[1].max, 5 * MS);

	/* epoch 2: bank 0 is reset once, then collects; bank 1 is kept */
	v.gap.win[0].min = 1;
	v.gap.win[0].max = 999 * MS;	/* stale values of two intervals ago */
	can_id_account(&v, 9 * MS, 0x10, 1, d, EWMA_W, 2);	/* gap 3 */
	assert_int_equal(v.epoch, 2);
	assert_int_equal(v.gap.win[0].min, 3 * MS);
	assert_int_equal(v.gap.win[0].max, 3 * MS);
	can_id_account(&v, 13 * MS, 0x10, 1, d, EWMA_W, 2);	/* gap 4: no second reset */
	assert_int_equal(v.gap.win[0].min, 3 * MS);
	assert_int_equal(v.gap.win[0].max, 4 * MS);
	assert_int_equal(v.gap.win[1].min, 1 * MS);
	assert_int_equal(v.gap.win[1].max, 5 * MS);

	/* epoch 3: bank 1 is reset, the lifetime statistics are not */
	can_id_account(&v, 15 * MS, 0x10, 1, d, EWMA_W, 3);	/* gap 2 */
	assert_int_equal(v.gap.win[1].min, 2 * MS);
	assert_int_equal(v.gap.win[1].max, 2 * MS);
	assert_int_equal(v.gap.count, 5);
	assert_int_equal(v.gap.min, 1 * MS);
	assert_int_equal(v.gap.max, 5 * MS);
	assert_int_equal(v.gap.sum, 15 * MS);
}

static void test_id_account_backwards_time(void **state)
{
	static const __u8 d[1] = { 0 };
	struct rtsup_can_id v;

	id_init(&v);
	can_id_account(&v, 10 * MS, 0x10, 1, d, EWMA_W, 1);
	/* a timestamp before the last one adds no (negative) gap */
	can_id_account(&v, 9 * MS, 0x10, 1, d, EWMA_W, 1);
	assert_int_equal(v.frames, 2);
	assert_int_equal(v.gap.count, 0);
	assert_int_equal(v.last, 9 * MS);
}

static void test_id_account_rtr_and_data(void **state)
{
	static const __u8 d[8] = { 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88 };
	static const __u8 want3[8] = { 0x11, 0x22, 0x33, 0, 0, 0, 0, 0 };
	static const __u8 zero[8] = { 0 };
	struct rtsup_can_id v;

	id_init(&v);
	can_id_account(&v, 1 * MS, 0x300, 8, d, EWMA_W, 1);
	assert_memory_equal(v.data, d, 8);
	/* a shorter payload pads the rest with zeroes, not the old bytes */
	can_id_account(&v, 2 * MS, 0x300, 3, d, EWMA_W, 1);
	assert_memory_equal(v.data, want3, 8);
	assert_int_equal(v.len, 3);
	/* a remote request is counted under its id; it carries no data, so the
	 * last payload stays (a guarding request must not read as a state) */
	can_id_account(&v, 3 * MS, RTSUP_CAN_RTR_FLAG | 0x300, 5, zero, EWMA_W, 1);
	assert_int_equal(v.rtr, 1);
	assert_int_equal(v.frames, 3);
	assert_int_equal(v.bytes, 11);
	assert_int_equal(v.len, 3);
	assert_memory_equal(v.data, want3, 8);
	/* a 64-byte CAN FD payload keeps its first 8 bytes */
	can_id_account(&v, 4 * MS, 0x300, 64, d, EWMA_W, 1);
	assert_memory_equal(v.data, d, 8);
	assert_int_equal(v.bytes, 75);
	assert_int_equal(v.len, 64);
}

static void test_if_account_frames(void **state)
{
	static const __u8 d[8] = { 0 };
	struct rtsup_can_if f;

	memset(&f, 0, sizeof(f));
	can_if_account(&f, 1 * MS, RTSUP_CAN_RX, 0x181, 8, RTSUP_CAN_CC, d);
	can_if_account(&f, 2 * MS, RTSUP_CAN_RX, RTSUP_CAN_EFF_FLAG | 0x100, 3, RTSUP_CAN_CC, d);
	can_if_account(&f, 3 * MS, RTSUP_CAN_TX, RTSUP_CAN_RTR_FLAG | 0x181, 8, RTSUP_CAN_CC, d);
	can_if_account(&f, 4 * MS, RTSUP_CAN_TX, 0x200, 2, RTSUP_CAN_CC, d);
	assert_int_equal(f.frames[RTSUP_CAN_RX], 2);
	assert_int_equal(f.frames[RTSUP_CAN_TX], 2);
	assert_int_equal(f.bytes[RTSUP_CAN_RX], 11);
	/* the RTR's wire bits have no data */
	assert_int_equal(f.bits[RTSUP_CAN_RX], 135 + 110);
	assert_int_equal(f.bits[RTSUP_CAN_TX], 55 + 75);
	assert_int_equal(f.rtr, 1);
	assert_int_equal(f.fd, 0);
	assert_int_equal(f.xl, 0);
	assert_int_equal(f.err_frames, 0);

	can_if_account(&f, 5 * MS, RTSUP_CAN_RX, 0x123, 64, RTSUP_CAN_FD, d);
	can_if_account(&f, 6 * MS, RTSUP_CAN_TX, 0x123, 12, RTSUP_CAN_FD, d);
	can_if_account(&f, 7 * MS, RTSUP_CAN_RX, 0x042, 100, RTSUP_CAN_XL, d);
	assert_int_equal(f.fd, 2);
	assert_int_equal(f.xl, 1);
	assert_int_equal(f.frames[RTSUP_CAN_RX], 4);
	assert_int_equal(f.frames[RTSUP_CAN_TX], 3);
	assert_int_equal(f.bytes[RTSUP_CAN_RX], 11 + 64 + 100);
	assert_int_equal(f.bits[RTSUP_CAN_RX], 135 + 110 + can_frame_bits(0x123, 64, RTSUP_CAN_FD) +
			 can_frame_bits(0x042, 100, RTSUP_CAN_XL));
	/* an FD frame takes more bits than a classic one of the same payload */
	assert_true(can_frame_bits(0x123, 8, RTSUP_CAN_FD) > can_frame_bits(0x123, 8, RTSUP_CAN_CC));

	/* a direction out of range is ignored */
	can_if_account(&f, 8 * MS, RTSUP_CAN_DIRS, 0x123, 8, RTSUP_CAN_CC, d);
	assert_int_equal(f.frames[RTSUP_CAN_RX] + f.frames[RTSUP_CAN_TX], 7);
}

/* Two CPUs receive frames of one interface and identifier at once (on the senders' CPUs). */
#define RACE_FRAMES	2000000

struct race {
	struct rtsup_can_if *f;
	struct rtsup_can_id *v;
	pthread_barrier_t *go;
};

static void *race_rx(void *arg)
{
	static const __u8 d[8] = { 0 };
	struct race *r = arg;
	__u32 i;

	pthread_barrier_wait(r->go);
	for (i = 0; i < RACE_FRAMES; i++) {
		/* every 4th an RTR: the rtr counters race too */
		__u32 id = (i & 3) ? 0x181 : RTSUP_CAN_RTR_FLAG | 0x181;

		can_if_account(r->f, i, RTSUP_CAN_RX, id, 2, RTSUP_CAN_CC, d);
		can_id_account(r->v, i, id, 2, d, EWMA_W, 0);
	}
	return NULL;
}

static void test_account_two_cpus_lose_nothing(void **state)
{
	static struct rtsup_can_if f;
	static struct rtsup_can_id v;
	pthread_barrier_t go;
	struct race r = { &f, &v, &go };
	pthread_t t[2];
	int i;

	memset(&f, 0, sizeof(f));
	id_init(&v);
	pthread_barrier_init(&go, NULL, 2);
	for (i = 0; i < 2; i++)
		assert_int_equal(pthread_create(&t[i], NULL, race_rx, &r), 0);
	for (i = 0; i < 2; i++)
		pthread_join(t[i], NULL);
	pthread_barrier_destroy(&go);
	assert_int_equal(f.frames[RTSUP_CAN_RX], 2 * RACE_FRAMES);
	assert_int_equal(f.rtr, 2 * RACE_FRAMES / 4);
	assert_int_equal(f.bytes[RTSUP_CAN_RX], 2 * 2 * RACE_FRAMES * 3 / 4);
	assert_int_equal(f.bits[RTSUP_CAN_RX], 2 * (RACE_FRAMES * 3 / 4 * (55 + 20) +
						    RACE_FRAMES / 4 * 55));
	assert_int_equal(v.frames, 2 * RACE_FRAMES);
	assert_int_equal(v.rtr, 2 * RACE_FRAMES / 4);
	assert_int_equal(v.bytes, 2 * 2 * RACE_FRAMES * 3 / 4);
}

/* net_dev_start_xmit stashes, net_dev_xmit counts what the driver took */
static void test_tx_taken_once_after_busy(void **state)
{
	struct rtsup_can_tx s;
	int sent = 0;

	memset(&s, 0, sizeof(s));
	/* nothing offered: a non-CAN or unwatched skb's answer */
	assert_false(can_tx_taken(&s, 0x1000, RTSUP_NETDEV_TX_OK));
	/* offered, NETDEV_TX_BUSY, requeued and offered again, taken */
	s.skb = 0x1000;
	sent += can_tx_taken(&s, 0x1000, 0x10);
	assert_int_equal(s.skb, 0);
	s.skb = 0x1000;
	sent += can_tx_taken(&s, 0x1000, 0x10);
	s.skb = 0x1000;
	sent += can_tx_taken(&s, 0x1000, RTSUP_NETDEV_TX_OK);
	assert_int_equal(sent, 1);
	/* an answer for another skb does not take the stashed one */
	s.skb = 0x2000;
	assert_false(can_tx_taken(&s, 0x3000, RTSUP_NETDEV_TX_OK));
	assert_int_equal(s.skb, 0x2000);
	assert_true(can_tx_taken(&s, 0x2000, RTSUP_NETDEV_TX_OK));
	/* a driver that drops it (NET_XMIT_DROP) did not send it */
	s.skb = 0x4000;
	assert_false(can_tx_taken(&s, 0x4000, 1));
	assert_false(can_tx_taken(&s, 0x4000, RTSUP_NETDEV_TX_OK));
}

static void test_if_account_error_frame(void **state)
{
	static const __u8 d[8] = { 0, RTSUP_CAN_ERR_CRTL_RX_PASSIVE, 0, 0, 0, 0, 0x80, 0x7f };
	static const __u8 want5[8] = { 0, RTSUP_CAN_ERR_CRTL_RX_PASSIVE, 0, 0, 0, 0, 0, 0 };
	struct rtsup_can_if f;
	__u32 id = RTSUP_CAN_ERR_FLAG | RTSUP_CAN_ERR_CRTL | 0x08 | RTSUP_CAN_ERR_BUSOFF;
	int i;

	memset(&f, 0, sizeof(f));
	can_if_account(&f, 3 * MS, RTSUP_CAN_RX, id, 8, RTSUP_CAN_CC, d);
	assert_int_equal(f.err_frames, 1);
	assert_int_equal(f.last_err, 3 * MS);
	assert_int_equal(f.err_id, RTSUP_CAN_ERR_CRTL | 0x08 | RTSUP_CAN_ERR_BUSOFF);
	assert_memory_equal(f.err_data, d, 8);
	for (i = 0; i < RTSUP_CAN_ERR_CLASSES; i++)
		assert_int_equal(f.err_class[i], i == 2 || i == 3 || i == 6 ? 1 : 0);
	/* a report of the controller: no frame, byte or bit on the bus */
	assert_int_equal(f.frames[RTSUP_CAN_RX], 0);
	assert_int_equal(f.frames[RTSUP_CAN_TX], 0);
	assert_int_equal(f.bytes[RTSUP_CAN_RX], 0);
	assert_int_equal(f.bits[RTSUP_CAN_RX], 0);
	assert_int_equal(f.bits[RTSUP_CAN_TX], 0);
	assert_int_equal(f.rtr, 0);

	/* the next one replaces the last error's id and data, classes add up */
	can_if_account(&f, 9 * MS, RTSUP_CAN_RX, RTSUP_CAN_ERR_FLAG | RTSUP_CAN_ERR_CRTL, 5,
		       RTSUP_CAN_CC, d);
	assert_int_equal(f.err_frames, 2);
	assert_int_equal(f.last_err, 9 * MS);
	assert_int_equal(f.err_id, RTSUP_CAN_ERR_CRTL);
	assert_memory_equal(f.err_data, want5, 8);
	assert_int_equal(f.err_class[2], 2);
	assert_int_equal(f.err_class[3], 1);
	assert_int_equal(f.err_class[6], 1);

	/* the highest class bit, CAN_ERR_CNT (0x200), is the last counter */
	can_if_account(&f, 10 * MS, RTSUP_CAN_RX, RTSUP_CAN_ERR_FLAG | 0x200, 8, RTSUP_CAN_CC, d);
	assert_int_equal(f.err_class[RTSUP_CAN_ERR_CLASSES - 1], 1);
	assert_int_equal(f.err_frames, 3);
}

static void test_sdo_is_response(void **state)
{
	assert_true(can_is_sdo_response(0x581));
	assert_true(can_is_sdo_response(0x5ff));
	assert_false(can_is_sdo_response(0x580));	/* node 0 does not exist */
	assert_false(can_is_sdo_response(0x601));
	assert_false(can_is_sdo_response(0x181));
	assert_false(can_is_sdo_response(RTSUP_CAN_EFF_FLAG | 0x581));
}

static void test_sdo_match(void **state)
{
	static const __u8 d[8] = { 0x40, 0x00, 0x10, 0, 0, 0, 0, 0 };
	struct rtsup_can_id req, resp;

	id_init(&req);
	id_init(&resp);
	/* no request yet */
	assert_int_equal(can_sdo_match(&resp, &req, 1 * MS), 0);
	assert_int_equal(can_sdo_match(&resp, NULL, 1 * MS), 0);

	/* request at 10 ms, response at 10.35 ms */
	can_id_account(&req, 10 * MS, 0x605, 8, d, EWMA_W, 1);
	assert_int_equal(can_sdo_match(&resp, &req, 10 * MS + 350 * US), 1);
	can_id_account(&resp, 10 * MS + 350 * US, 0x585, 8, d, EWMA_W, 1);
	assert_int_equal(resp.resp_count, 1);
	assert_int_equal(resp.resp_sum, 350 * US);
	assert_int_equal(resp.resp_max, 350 * US);

	/* a second response without a new request is not matched */
	assert_int_equal(can_sdo_match(&resp, &req, 11 * MS), 0);
	can_id_account(&resp, 11 * MS, 0x585, 8, d, EWMA_W, 1);
	assert_int_equal(resp.resp_count, 1);

	/* a new request: matched again, the max and the sum follow */
	can_id_account(&req, 20 * MS, 0x605, 8, d, EWMA_W, 1);
	assert_int_equal(can_sdo_match(&resp, &req, 21 * MS), 1);
	can_id_account(&resp, 21 * MS, 0x585, 8, d, EWMA_W, 1);
	assert_int_equal(resp.resp_count, 2);
	assert_int_equal(resp.resp_sum, 350 * US + 1 * MS);
	assert_int_equal(resp.resp_max, 1 * MS);

	/* a request stamped after the response's time answers nothing */
	can_id_account(&req, 31 * MS, 0x605, 8, d, EWMA_W, 1);
	assert_int_equal(can_sdo_match(&resp, &req, 30 * MS), 0);
	assert_int_equal(resp.resp_count, 2);
	assert_int_equal(resp.resp_sum, 350 * US + 1 * MS);

	/* a shorter answer keeps the max */
	assert_int_equal(can_sdo_match(&resp, &req, 31 * MS + 100 * US), 1);
	assert_int_equal(resp.resp_count, 3);
	assert_int_equal(resp.resp_max, 1 * MS);
	assert_int_equal(resp.resp_sum, 350 * US + 1 * MS + 100 * US);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_frame_bits_formula),
		cmocka_unit_test(test_frame_bits_values),
		cmocka_unit_test(test_key_id),
		cmocka_unit_test(test_id_account_first_and_gaps),
		cmocka_unit_test(test_id_account_zero_entry),
		cmocka_unit_test(test_id_account_epoch_bank),
		cmocka_unit_test(test_id_account_backwards_time),
		cmocka_unit_test(test_id_account_rtr_and_data),
		cmocka_unit_test(test_if_account_frames),
		cmocka_unit_test(test_if_account_error_frame),
		cmocka_unit_test(test_account_two_cpus_lose_nothing),
		cmocka_unit_test(test_tx_taken_once_after_busy),
		cmocka_unit_test(test_sdo_is_response),
		cmocka_unit_test(test_sdo_match),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
