// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_hist.c - log-linear histogram buckets (include/hist.h) */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "hist.h"

/* xorshift64: deterministic pseudo-random values */
static __u64 rnd_state = 0x9E3779B97F4A7C15ULL;

static __u64 rnd(void)
{
	rnd_state ^= rnd_state << 13;
	rnd_state ^= rnd_state >> 7;
	rnd_state ^= rnd_state << 17;
	return rnd_state;
}

/* check_value - v lies inside its bucket, and the bucket is in range */
static void check_value(__u64 v)
{
	__u32 b = hist_bucket(v);

	assert_in_range(b, 0, HIST_BUCKETS - 1);
	if (hist_bucket_low(b) > v || hist_bucket_high(b) < v)
		fail_msg("v=%llu bucket %u [%llu, %llu]", (unsigned long long)v, b,
			 (unsigned long long)hist_bucket_low(b),
			 (unsigned long long)hist_bucket_high(b));
}

/* hist_log2 is the index of the highest set bit, for every bit position */
static void test_hist_log2_powers(void **state)
{
	unsigned int i;

	for (i = 0; i < 64; i++) {
		__u64 p = 1ULL << i;

		assert_int_equal(hist_log2(p), i);
		assert_int_equal(hist_log2(p | (p - 1)), i);	/* all bits below */
		if (i > 1)
			assert_int_equal(hist_log2(p - 1), i - 1);
	}
	assert_int_equal(hist_log2(~0ULL), 63);
}

/* values below HIST_SUB get a bucket each, exact low and high */
static void test_hist_small_values_exact(void **state)
{
	__u32 v;

	for (v = 0; v < HIST_SUB; v++) {
		assert_int_equal(hist_bucket(v), v);
		assert_int_equal(hist_bucket_low(v), v);
		assert_int_equal(hist_bucket_high(v), v);
	}
	/* the linear range continues one-to-one up to 2 * HIST_SUB */
	for (v = HIST_SUB; v < 2 * HIST_SUB; v++)
		assert_int_equal(hist_bucket_low(hist_bucket(v)), v);
}

/* low(b) <= v <= high(b) for every v in 0..10^6 */
static void test_hist_bucket_contains_dense(void **state)
{
	__u64 v;

	for (v = 0; v <= 1000000; v++)
		check_value(v);
}

/* low(b) <= v <= high(b) for random values up to 2^40, and bit edges */
static void test_hist_bucket_contains_random(void **state)
{
	unsigned int i;

	for (i = 0; i < 200000; i++) {
		unsigned int bits = 1 + (unsigned int)(rnd() % 40);

		check_value(rnd() & ((1ULL << bits) - 1));
	}
	for (i = 1; i < 64; i++) {
		check_value(1ULL << i);
		check_value((1ULL << i) - 1);
		check_value((1ULL << i) + 1);
	}
	check_value(~0ULL);
}

/* bucket boundaries tile the value range: low(b+1) = high(b) + 1 */
static void test_hist_buckets_monotonic(void **state)
{
	__u32 b;

	assert_int_equal(hist_bucket_low(0), 0);
	for (b = 0; b + 1 < HIST_BUCKETS; b++) {
		assert_true(hist_bucket_low(b) <= hist_bucket_high(b));
		assert_true(hist_bucket_low(b + 1) > hist_bucket_low(b));
		assert_int_equal(hist_bucket_low(b + 1), hist_bucket_high(b) + 1);
		/* both edges of a bucket map back to it */
		assert_int_equal(hist_bucket(hist_bucket_low(b)), b);
		assert_int_equal(hist_bucket(hist_bucket_high(b)), b);
	}
}

/* hist_bucket never decreases as the value grows */
static void test_hist_bucket_nondecreasing(void **state)
{
	__u32 prev = 0, b;
	__u64 v;

	for (v = 0; v <= 1000000; v++) {
		b = hist_bucket(v);
		assert_true(b >= prev);
		assert_true(b - prev <= 1);
		prev = b;
	}
}

/* every bucket above 8 is at most 1/8 wide relative to its low edge */
static void test_hist_relative_width(void **state)
{
	__u32 b;

	for (b = HIST_SUB; b < HIST_BUCKETS - 1; b++) {
		__u64 low = hist_bucket_low(b);
		__u64 width = hist_bucket_high(b) - low + 1;

		if (width * 8 > low)
			fail_msg("bucket %u: width %llu low %llu", b,
				 (unsigned long long)width, (unsigned long long)low);
	}
}

/* huge values land in the last bucket, whose high edge is unbounded */
static void test_hist_last_bucket(void **state)
{
	const __u32 last = HIST_BUCKETS - 1;

	assert_int_equal(hist_bucket(1ULL << (HIST_MAX_EXP + 1)), last);
	assert_int_equal(hist_bucket((1ULL << (HIST_MAX_EXP + 1)) - 1), last);
	assert_int_equal(hist_bucket(1ULL << 40), last);
	assert_int_equal(hist_bucket(1ULL << 63), last);
	assert_int_equal(hist_bucket(~0ULL), last);
	assert_true(hist_bucket_high(last) == ~0ULL);
	/* 2^HIST_MAX_EXP still has its own linear buckets */
	assert_int_equal(hist_bucket(1ULL << HIST_MAX_EXP),
			 (HIST_MAX_EXP - HIST_SUB_BITS + 1) * HIST_SUB);
	assert_true(hist_bucket(1ULL << HIST_MAX_EXP) < last);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_hist_log2_powers),
		cmocka_unit_test(test_hist_small_values_exact),
		cmocka_unit_test(test_hist_bucket_contains_dense),
		cmocka_unit_test(test_hist_bucket_contains_random),
		cmocka_unit_test(test_hist_buckets_monotonic),
		cmocka_unit_test(test_hist_bucket_nondecreasing),
		cmocka_unit_test(test_hist_relative_width),
		cmocka_unit_test(test_hist_last_bucket),
	};

	return cmocka_run_group_tests_name("hist", tests, NULL, NULL);
}
