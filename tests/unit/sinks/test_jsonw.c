// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_jsonw.c - JSON written straight (user/sinks/jsonw.c) is what jansson
 * writes for the same values: strings escaped alike, invalid UTF-8 as
 * U+FFFD (jsonstr.c), integers, nesting; the reals read back as the value
 * (a mean to 0.001, a fixed-point value exactly)
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "sinks/jsonstr.h"
#include "sinks/jsonw.h"

static struct jw w;

/* text - what w holds, as a C string (static) */
static const char *text(void)
{
	static char buf[4096];

	assert_false(w.t.oom);
	assert_true(w.t.len < sizeof(buf));
	memcpy(buf, w.t.p, w.t.len);
	buf[w.t.len] = '\0';
	return buf;
}

/* dumped - jansson's text of v (freed) */
static const char *dumped(json_t *v)
{
	static char buf[4096];
	size_t n;

	assert_non_null(v);
	n = json_dumpb(v, buf, sizeof(buf) - 1, JSON_COMPACT | JSON_ENCODE_ANY);
	assert_true(n < sizeof(buf));
	buf[n] = '\0';
	json_decref(v);
	return buf;
}

/* every byte that needs an escape, UTF-8 of 2, 3 and 4 bytes, and bytes that are not */
static void test_jsonw_strings_as_jansson(void **state)
{
	static const char *const s[] = {
		"", "ctl-0", "a\"b\\c/d", "\b\f\n\r\t\x01\x1f\x7f", "caf\xc3\xa9 \xe2\x82\xac "
		"\xf0\x9f\x98\x80", "bad \xff end", "cut \xe2\x82", "\xc0\xaf overlong",
		"\xed\xa0\x80 surrogate", "\xf4\x90\x80\x80 past U+10FFFF",
	};
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(s) / sizeof(s[0]); i++) {
		jw_reset(&w);
		jw_str(&w, NULL, s[i], 64);
		assert_string_equal(text(), dumped(json_str(s[i], 64)));
	}
	/* at most max bytes, as json_str */
	jw_reset(&w);
	jw_str(&w, NULL, "0123456789", 4);
	assert_string_equal(text(), "\"0123\"");
}

static void test_jsonw_integers_and_nesting(void **state)
{
	json_t *o, *a;

	(void)state;
	jw_reset(&w);
	jw_obj(&w, NULL);
	jw_int(&w, "min", LLONG_MIN);
	jw_int(&w, "max", LLONG_MAX);
	jw_int(&w, "zero", 0);
	jw_int(&w, "neg", -42);
	jw_bool(&w, "t", true);
	jw_bool(&w, "f", false);
	jw_null(&w, "n");
	jw_arr(&w, "empty");
	jw_end_arr(&w);
	jw_arr(&w, "list");
	jw_obj(&w, NULL);
	jw_end_obj(&w);
	jw_int(&w, NULL, 7);
	jw_obj(&w, NULL);
	jw_str(&w, "k", "v", 8);
	jw_end_obj(&w);
	jw_end_arr(&w);
	jw_json(&w, "tree", json_pack("{s:[i,i],s:s}", "a", 1, 2, "b", "x"));
	jw_json(&w, "none", NULL);
	jw_end_obj(&w);

	a = json_pack("[{},i,{s:s}]", 7, "k", "v");
	o = json_pack("{s:I,s:I,s:i,s:i,s:b,s:b,s:n,s:[],s:o,s:{s:[i,i],s:s},s:n}",
		      "min", (json_int_t)LLONG_MIN, "max", (json_int_t)LLONG_MAX, "zero", 0,
		      "neg", -42, "t", 1, "f", 0, "n", "empty", "list", a, "tree", "a", 1, 2,
		      "b", "x", "none");
	assert_string_equal(text(), dumped(o));
}

/* read - the one number in w's text */
static double read_back(void)
{
	json_error_t e;
	json_t *v = json_loads(text(), JSON_DECODE_ANY, &e);
	double d;

	assert_non_null(v);
	assert_true(json_is_real(v));	/* a real, never read as an integer */
	d = json_real_value(v);
	json_decref(v);
	return d;
}

/* a mean: to 0.001, short when it is short, jansson's "x.0" for a whole number */
static void test_jsonw_ns_reads_back(void **state)
{
	static const double v[] = { 0, 47741.5, 100006292.9, 100003613.63157895, 0.0004,
				    0.0006, 123456789.9995, 8.9e12, 5e13, 1e300 };
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(v) / sizeof(v[0]); i++) {
		jw_reset(&w);
		jw_ns(&w, NULL, v[i]);
		/* past 9e12 ns (2.5 hours) every digit, as jansson */
		assert_true(fabs(read_back() - v[i]) <= (v[i] < 9e12 ? 0.0005 : 0));
	}
	jw_reset(&w);
	jw_ns(&w, NULL, 47741.5);
	assert_string_equal(text(), "47741.5");
	jw_reset(&w);
	jw_ns(&w, NULL, 50000);
	assert_string_equal(text(), "50000.0");
	jw_reset(&w);
	jw_ns(&w, NULL, 100003613.63157895);
	assert_string_equal(text(), "100003613.632");
	jw_reset(&w);
	jw_ns(&w, NULL, -2.5);
	assert_string_equal(text(), "-2.5");
	jw_reset(&w);
	jw_ns(&w, NULL, NAN);
	assert_string_equal(text(), "null");
}

/* the kernel's EWMA (8 fraction bits): every digit of v / 256 */
static void test_jsonw_fixed_exact(void **state)
{
	static const long long v[] = { 0, 1, 255, 256, 256 * 5 + 1, -5, 48812 * 256 + 113,
				       (1LL << 52) + 3 };
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(v) / sizeof(v[0]); i++) {
		jw_reset(&w);
		jw_fixed(&w, NULL, v[i], 8);
		assert_true(read_back() == (double)v[i] / 256);
	}
	jw_reset(&w);
	jw_fixed(&w, NULL, 256 * 5 + 1, 8);
	assert_string_equal(text(), "5.00390625");
	jw_reset(&w);
	jw_fixed(&w, NULL, -5, 8);
	assert_string_equal(text(), "-0.01953125");
	jw_reset(&w);
	jw_fixed(&w, NULL, 256 * 7, 8);
	assert_string_equal(text(), "7.0");
}

/* integers of every length, and at each power of ten and one below, as printf writes them */
static void test_jsonw_integers_every_length(void **state)
{
	unsigned long long p = 1;
	char want[32];
	int k, d;

	(void)state;
	for (k = 0; k <= 19; k++, p *= 10) {
		for (d = -1; d <= 1; d++) {
			long long v = (long long)(p + (unsigned long long)d);

			jw_reset(&w);
			jw_int(&w, NULL, v);
			snprintf(want, sizeof(want), "%lld", v);
			assert_string_equal(text(), want);
			jw_reset(&w);
			jw_int(&w, NULL, -v);
			snprintf(want, sizeof(want), "%lld", -v);
			assert_string_equal(text(), want);
		}
	}
}

/* a value bigger than the first buffer grows it; the buffer is kept across resets */
static void test_jsonw_grows(void **state)
{
	int i;

	(void)state;
	jw_reset(&w);
	jw_arr(&w, NULL);
	for (i = 0; i < 2000; i++)
		jw_int(&w, NULL, i);
	jw_end_arr(&w);
	assert_false(w.t.oom);
	assert_true(w.t.len > 4096);
	assert_memory_equal(w.t.p, "[0,1,2,", 7);
	assert_memory_equal(w.t.p + w.t.len - 6, ",1999]", 6);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_jsonw_strings_as_jansson),
		cmocka_unit_test(test_jsonw_integers_and_nesting),
		cmocka_unit_test(test_jsonw_ns_reads_back),
		cmocka_unit_test(test_jsonw_fixed_exact),
		cmocka_unit_test(test_jsonw_integers_every_length),
		cmocka_unit_test(test_jsonw_grows),
	};
	int r = cmocka_run_group_tests_name("jsonw", tests, NULL, NULL);

	jw_free(&w);
	return r;
}
