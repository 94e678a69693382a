// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_record.c - user/sinks/record.c: header and record round trips, and a
 * reader that ends every damaged, truncated or foreign file with one line
 * naming the file and the offset of the bad record, never with a crash.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <unistd.h>
#include <sys/stat.h>
#include <cmocka.h>
#include <zlib.h>

#include "sinks/record.h"
#include "sinks/errline.h"

#define ERRLEN	512
#define HDR_PRE	16	/* magic | version | header_len */

struct fx {
	char dir[256];
	char path[300];
	char path2[300];
};

/* xorshift64: deterministic pseudo-random bytes */
static __u64 rnd_state = 88172645463325252ULL;

static __u64 rnd(void)
{
	rnd_state ^= rnd_state << 13;
	rnd_state ^= rnd_state >> 7;
	rnd_state ^= rnd_state << 17;
	return rnd_state;
}

static int fx_setup(void **state)
{
	const char *tmp = getenv("TMPDIR");
	struct fx *f = calloc(1, sizeof(*f));

	if (!f)
		return -1;
	snprintf(f->dir, sizeof(f->dir), "%s/rtsup-rec-XXXXXX", tmp && *tmp ? tmp : "/tmp");
	if (!mkdtemp(f->dir)) {
		free(f);
		return -1;
	}
	snprintf(f->path, sizeof(f->path), "%s/trace.rec", f->dir);
	snprintf(f->path2, sizeof(f->path2), "%s/cut.rec", f->dir);
	*state = f;
	return 0;
}

static int fx_teardown(void **state)
{
	struct fx *f = *state;
	struct dirent *d;
	char p[600];
	DIR *dir;

	dir = opendir(f->dir);
	if (dir) {
		while ((d = readdir(dir)))
			if (strcmp(d->d_name, ".") && strcmp(d->d_name, "..")) {
				snprintf(p, sizeof(p), "%s/%s", f->dir, d->d_name);
				unlink(p);
			}
		closedir(dir);
	}
	rmdir(f->dir);
	free(f);
	return 0;
}

/* one_line - a non-empty error message without a newline */
static void assert_one_line(const char *err)
{
	assert_true(err[0] != '\0');
	assert_null(strchr(err, '\n'));
}

static void fill_header(struct rec_header *h, const char *text)
{
	memset(h, 0, sizeof(*h));
	snprintf(h->kernel, sizeof(h->kernel), "6.1.0-18-rt-amd64 #1 SMP PREEMPT_RT Debian");
	snprintf(h->host, sizeof(h->host), "rt-box");
	snprintf(h->args, sizeof(h->args), "rtsup-trace --comm \"ctl\\loop\" --record x");
	snprintf(h->config_path, sizeof(h->config_path), "/etc/rtsup/cfg.yaml");
	h->config_text = text ? strdup(text) : NULL;
	h->start_real_ns = 1712345678901234567ULL;
	h->start_mono_ns = 0xfedcba9876543210ULL;	/* above 2^63 */
	h->interval_s = 1.25;
	h->ewma_w = 4000000000U;
}

/* payload - deterministic bytes of a record type; returns its size */
static size_t payload(enum rec_type t, unsigned char *buf)
{
	size_t len = 0, i;

	switch (t) {
	case REC_THREAD:
		len = sizeof(struct rec_thread);
		break;
	case REC_CYCLE:
		len = sizeof(struct rec_cycle);
		break;
	case REC_EVENT:
		len = sizeof(struct rtsup_event);
		break;
	case REC_INTERVAL:
	case REC_END:
		len = sizeof(struct rec_interval);
		break;
	case REC_STACK:
		len = sizeof(struct rec_stack);
		break;
	case REC_MODULE:
		len = sizeof(struct rec_module);
		break;
	}
	for (i = 0; i < len; i++)
		buf[i] = rnd();
	return len;
}

struct layout {
	size_t header_end;	/* offset of the first record */
	size_t n;		/* records */
	size_t off[512];	/* offset of each record, off[n] = file size */
	enum rec_type type[512];
};

/* write_trace - header plus n records cycling through the types */
static void write_trace(const char *path, size_t n, bool end, struct layout *l)
{
	unsigned char buf[REC_MAX_PAYLOAD];
	struct rec_writer *w;
	struct rec_header h;
	char err[ERRLEN];
	size_t i, len;
	struct stat st;

	fill_header(&h, "a: 1\n");
	assert_int_equal(rec_create(&w, path, &h, err, sizeof(err)), 0);
	free(h.config_text);
	assert_int_equal(stat(path, &st), 0);
	l->n = 0;
	for (i = 0; i < n; i++) {
		enum rec_type t = end && i == n - 1 ? REC_END : (enum rec_type)(1 + i % 4);

		len = payload(t, buf);
		assert_int_equal(rec_write(w, t, buf, len, err, sizeof(err)), 0);
		l->type[l->n] = t;
		l->off[++l->n] = len + 8;	/* sizes now, offsets below */
	}
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);
	assert_int_equal(stat(path, &st), 0);
	l->header_end = st.st_size;
	for (i = 1; i <= l->n; i++)
		l->header_end -= l->off[i];
	l->off[0] = l->header_end;
	for (i = 1; i <= l->n; i++)
		l->off[i] += l->off[i - 1];
	assert_int_equal(l->off[l->n], (size_t)st.st_size);
}

static unsigned char *slurp(const char *path, size_t *size)
{
	unsigned char *b;
	struct stat st;
	FILE *f;

	assert_int_equal(stat(path, &st), 0);
	b = malloc(st.st_size + 1);
	assert_non_null(b);
	f = fopen(path, "rb");
	assert_non_null(f);
	assert_int_equal(fread(b, 1, st.st_size, f), (size_t)st.st_size);
	fclose(f);
	*size = st.st_size;
	return b;
}

static void spill(const char *path, const void *b, size_t size)
{
	FILE *f = fopen(path, "wb");

	assert_non_null(f);
	assert_int_equal(fwrite(b, 1, size, f), size);
	assert_int_equal(fclose(f), 0);
}

/*
 * read_all - open and read every record: 0 at a clean end, -1 on an error
 * (err set), -2 when rec_open failed; *n records read. Fails the test if
 * the reader does not end within one call per 8 bytes of file.
 */
static int read_all(const char *path, size_t size, size_t *n, char *err)
{
	unsigned char buf[REC_MAX_PAYLOAD];
	struct rec_reader *r;
	struct rec_header h;
	enum rec_type t;
	size_t len, guard = size / 8 + 2;
	int ret;

	*n = 0;
	err[0] = '\0';
	if (rec_open(&r, path, &h, err, ERRLEN)) {
		assert_null(r);
		assert_null(h.config_text);
		return -2;
	}
	while ((ret = rec_next(r, &t, buf, &len, err, ERRLEN)) == 1) {
		assert_true(len <= REC_MAX_PAYLOAD);
		assert_true(t >= REC_THREAD && t <= REC_END);
		(*n)++;
		assert_true(*n <= guard);
	}
	rec_free(r);
	free(h.config_text);
	return ret;
}

/* the header comes back field by field, config_text included */
static void test_record_header_roundtrip(void **state)
{
	const char *text = "# rules\nthreads:\n  - comm: \"ctl\\t\"\n    period: 1ms  # é ✓\n";
	unsigned char buf[REC_MAX_PAYLOAD];
	struct fx *f = *state;
	struct rec_header h, g;
	struct rec_writer *w;
	struct rec_reader *r;
	char err[ERRLEN];
	enum rec_type t;
	size_t len;

	fill_header(&h, text);
	assert_int_equal(rec_create(&w, f->path, &h, err, sizeof(err)), 0);
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);

	memset(&g, 0xaa, sizeof(g));
	assert_int_equal(rec_open(&r, f->path, &g, err, sizeof(err)), 0);
	assert_string_equal(g.kernel, h.kernel);
	assert_string_equal(g.host, h.host);
	assert_string_equal(g.args, h.args);
	assert_string_equal(g.config_path, h.config_path);
	assert_non_null(g.config_text);
	assert_string_equal(g.config_text, text);
	assert_true(g.start_real_ns == h.start_real_ns);
	assert_true(g.start_mono_ns == h.start_mono_ns);
	assert_true(g.interval_s == h.interval_s);
	assert_int_equal(g.ewma_w, h.ewma_w);
	/* no records: a clean end at once, and again */
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 0);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 0);
	rec_free(r);
	free(g.config_text);
	free(h.config_text);
}

/* without a configuration: config_text NULL, config_path "" */
static void test_record_header_no_config(void **state)
{
	struct fx *f = *state;
	struct rec_header h, g;
	struct rec_writer *w;
	struct rec_reader *r;
	char err[ERRLEN];

	fill_header(&h, NULL);
	h.config_path[0] = '\0';
	h.interval_s = 0.5;
	assert_int_equal(rec_create(&w, f->path, &h, err, sizeof(err)), 0);
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);
	assert_int_equal(rec_open(&r, f->path, &g, err, sizeof(err)), 0);
	assert_null(g.config_text);
	assert_string_equal(g.config_path, "");
	assert_string_equal(g.kernel, h.kernel);
	assert_true(g.interval_s == 0.5);
	rec_free(r);
}

/* strings that are not UTF-8 are stored (as U+FFFD), not lost */
static void test_record_header_invalid_utf8(void **state)
{
	struct fx *f = *state;
	struct rec_header h, g;
	struct rec_writer *w;
	struct rec_reader *r;
	char err[ERRLEN];

	fill_header(&h, "caf\xe9\n");
	snprintf(h.args, sizeof(h.args), "rtsup-trace --comm \xff\xfe");
	assert_int_equal(rec_create(&w, f->path, &h, err, sizeof(err)), 0);
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);
	assert_int_equal(rec_open(&r, f->path, &g, err, sizeof(err)), 0);
	assert_string_equal(g.config_text, "caf\xef\xbf\xbd\n");
	assert_string_equal(g.args, "rtsup-trace --comm \xef\xbf\xbd\xef\xbf\xbd");
	rec_free(r);
	free(g.config_text);
	free(h.config_text);
}

/* N records of every type come back in order, byte for byte */
static void test_record_roundtrip(void **state)
{
	enum { N = 300 };
	static unsigned char want[5 * N][REC_MAX_PAYLOAD];
	static size_t wlen[5 * N];
	static enum rec_type wtype[5 * N];
	unsigned char buf[REC_MAX_PAYLOAD];
	struct fx *f = *state;
	struct rec_header h, g;
	struct rec_writer *w;
	struct rec_reader *r;
	char err[ERRLEN];
	enum rec_type t;
	size_t i, len;

	fill_header(&h, "x");
	assert_int_equal(rec_create(&w, f->path, &h, err, sizeof(err)), 0);
	for (i = 0; i < 5 * N; i++) {
		wtype[i] = i == 5 * N - 1 ? REC_END : (enum rec_type)(1 + rnd() % 4);
		wlen[i] = payload(wtype[i], want[i]);
		assert_int_equal(rec_write(w, wtype[i], want[i], wlen[i], err, sizeof(err)), 0);
	}
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);

	assert_int_equal(rec_open(&r, f->path, &g, err, sizeof(err)), 0);
	for (i = 0; i < 5 * N; i++) {
		assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 1);
		assert_int_equal(t, wtype[i]);
		assert_int_equal(len, wlen[i]);
		assert_memory_equal(buf, want[i], len);
	}
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 0);
	rec_free(r);
	free(g.config_text);
	free(h.config_text);
}

/* typed records survive: a struct rec_cycle and a struct rtsup_event */
static void test_record_roundtrip_typed(void **state)
{
	unsigned char buf[REC_MAX_PAYLOAD];
	struct fx *f = *state;
	struct rec_header h, g;
	struct rec_writer *w;
	struct rec_reader *r;
	struct rec_cycle c = { 0 }, *cb = (void *)buf;
	struct rtsup_event e = { 0 }, *eb = (void *)buf;
	struct rec_thread th = { 0 }, *tb = (void *)buf;
	struct rec_interval iv = { 0 }, *ib = (void *)buf;
	char err[ERRLEN];
	enum rec_type t;
	size_t len;

	c.end = 123456789;
	c.r.tid = 42;
	c.r.tgid = 40;
	c.r.c.start = 123000000;
	c.r.c.exec = 456789;
	c.r.c.flags = RTSUP_CF_MISS | RTSUP_CF_HAS_PERIOD;
	e.ts = 99;
	e.type = RTSUP_EV_UNSAFE;
	e.arg = RTSUP_U_SYSCALL;
	e.arg2 = 9;
	strcpy(e.comm, "worker");
	th.tid = 42;
	strcpy(th.comm, "ctl");
	strcpy(th.pcomm, "app");
	th.exit_code = 3;
	iv.mono_ns = 5;
	iv.counters[RTSUP_C_CYC_DROPS] = 7;
	iv.overhead_pct = -1;

	fill_header(&h, NULL);
	assert_int_equal(rec_create(&w, f->path, &h, err, sizeof(err)), 0);
	assert_int_equal(rec_write(w, REC_THREAD, &th, sizeof(th), err, sizeof(err)), 0);
	assert_int_equal(rec_write(w, REC_CYCLE, &c, sizeof(c), err, sizeof(err)), 0);
	assert_int_equal(rec_write(w, REC_EVENT, &e, sizeof(e), err, sizeof(err)), 0);
	assert_int_equal(rec_write(w, REC_INTERVAL, &iv, sizeof(iv), err, sizeof(err)), 0);
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);

	/* a file without REC_END is readable to its end */
	assert_int_equal(rec_open(&r, f->path, &g, err, sizeof(err)), 0);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 1);
	assert_int_equal(t, REC_THREAD);
	assert_int_equal(tb->tid, 42);
	assert_string_equal(tb->pcomm, "app");
	assert_int_equal(tb->exit_code, 3);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 1);
	assert_int_equal(t, REC_CYCLE);
	assert_int_equal(cb->r.c.exec, 456789);
	assert_int_equal(cb->r.tgid, 40);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 1);
	assert_int_equal(t, REC_EVENT);
	assert_string_equal(eb->comm, "worker");
	assert_int_equal(eb->arg2, 9);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 1);
	assert_int_equal(t, REC_INTERVAL);
	assert_int_equal(ib->counters[RTSUP_C_CYC_DROPS], 7);
	assert_true(ib->overhead_pct == -1);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 0);
	rec_free(r);
}

/*
 * A file cut at every byte: inside the header rec_open fails; after it,
 * 0 only at record boundaries, else -1 naming the offset of the cut record,
 * and every record before the cut is read.
 */
static void test_record_truncated(void **state)
{
	struct fx *f = *state;
	struct layout l;
	unsigned char *b;
	char err[ERRLEN], want[64];
	size_t size, cut, n, k;
	int ret;

	write_trace(f->path, 15, true, &l);
	b = slurp(f->path, &size);
	for (cut = 0; cut <= size; cut++) {
		spill(f->path2, b, cut);
		ret = read_all(f->path2, cut, &n, err);
		if (cut < l.header_end) {
			assert_int_equal(ret, -2);
			assert_one_line(err);
			assert_non_null(strstr(err, f->path2));
			continue;
		}
		for (k = 0; k < l.n && l.off[k + 1] <= cut; k++)
			;
		/* k complete records before the cut */
		assert_int_equal(n, k);
		if (cut == l.off[k]) {
			assert_int_equal(ret, 0);
		} else {
			assert_int_equal(ret, -1);
			assert_one_line(err);
			snprintf(want, sizeof(want), ": offset %zu: ", l.off[k]);
			assert_non_null(strstr(err, want));
			assert_non_null(strstr(err, "truncated"));
		}
	}
	free(b);
}

/* a flipped payload byte: a CRC error at the offset of that record */
static void test_record_crc(void **state)
{
	struct fx *f = *state;
	struct layout l;
	unsigned char *b;
	char err[ERRLEN], want[400];
	size_t size, n, k;

	write_trace(f->path, 12, true, &l);
	b = slurp(f->path, &size);
	for (k = 0; k < l.n; k++) {
		size_t pos = l.off[k] + 8 + (l.off[k + 1] - l.off[k] - 8) / 2;

		b[pos] ^= 0x10;
		spill(f->path2, b, size);
		b[pos] ^= 0x10;
		assert_int_equal(read_all(f->path2, size, &n, err), -1);
		assert_int_equal(n, k);
		snprintf(want, sizeof(want), "%s: offset %zu: record damaged (crc)", f->path2,
			 l.off[k]);
		assert_string_equal(err, want);
	}
	/* the CRC itself damaged */
	b[l.off[3] + 5] ^= 1;
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -1);
	assert_int_equal(n, 3);
	assert_non_null(strstr(err, "record damaged (crc)"));
	free(b);
}

static void test_record_bad_magic(void **state)
{
	struct fx *f = *state;
	char err[ERRLEN], want[400];
	size_t n;

	spill(f->path2, "RTSUPREX\1\0\0\0\2\0\0\0{}", 18);
	assert_int_equal(read_all(f->path2, 18, &n, err), -2);
	snprintf(want, sizeof(want), "%s: not an rtsup trace (bad magic)", f->path2);
	assert_string_equal(err, want);

	spill(f->path2, "RTSUP", 5);
	assert_int_equal(read_all(f->path2, 5, &n, err), -2);
	assert_string_equal(err, want);

	spill(f->path2, "", 0);
	assert_int_equal(read_all(f->path2, 0, &n, err), -2);
	assert_non_null(strstr(err, "not an rtsup trace (empty file)"));
}

/* version 2, and a file from a host of the other byte order */
static void test_record_version(void **state)
{
	struct fx *f = *state;
	char err[ERRLEN], want[400];
	struct layout l;
	unsigned char *b;
	size_t size, n;
	__u32 v = 2;

	write_trace(f->path, 3, true, &l);
	b = slurp(f->path, &size);
	memcpy(b + 8, &v, 4);
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -2);
	snprintf(want, sizeof(want), "%s: version 2, this rtsup-trace reads 1", f->path2);
	assert_string_equal(err, want);

	v = 0x01000000;
	memcpy(b + 8, &v, 4);
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -2);
	assert_non_null(strstr(err, "other byte order"));
	free(b);
}

/* a length over REC_MAX_PAYLOAD, an unknown type, a wrong size */
static void test_record_bad_record_header(void **state)
{
	struct fx *f = *state;
	char err[ERRLEN], want[400];
	struct layout l;
	unsigned char *b;
	size_t size, n;
	__u16 v;

	write_trace(f->path, 8, true, &l);
	b = slurp(f->path, &size);

	v = 5000;	/* record 2: len too large */
	memcpy(b + l.off[2] + 2, &v, 2);
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -1);
	assert_int_equal(n, 2);
	snprintf(want, sizeof(want), "%s: offset %zu: record length 5000 over the maximum 4096",
		 f->path2, l.off[2]);
	assert_string_equal(err, want);
	v = l.off[3] - l.off[2] - 8;
	memcpy(b + l.off[2] + 2, &v, 2);

	v = 99;		/* record 4: unknown type */
	memcpy(b + l.off[4], &v, 2);
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -1);
	assert_int_equal(n, 4);
	snprintf(want, sizeof(want), "%s: offset %zu: unknown record type 99", f->path2,
		 l.off[4]);
	assert_string_equal(err, want);
	v = 0;
	memcpy(b + l.off[4], &v, 2);
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -1);
	assert_non_null(strstr(err, "unknown record type 0"));
	v = l.type[4];
	memcpy(b + l.off[4], &v, 2);

	v = l.off[6] - l.off[5] - 8 - 1;	/* record 5: one byte short */
	memcpy(b + l.off[5] + 2, &v, 2);
	spill(f->path2, b, size);
	assert_int_equal(read_all(f->path2, size, &n, err), -1);
	assert_int_equal(n, 5);
	snprintf(want, sizeof(want), "%s: offset %zu: ", f->path2, l.off[5]);
	assert_non_null(strstr(err, want));
	assert_non_null(strstr(err, "expected"));
	free(b);
}

/* a record of a fixed-size type with another size, its CRC right */
static void test_record_size_mismatch(void **state)
{
	static const struct { enum rec_type t; size_t len; const char *name; } cases[] = {
		{ REC_THREAD, sizeof(struct rec_thread) + 8, "thread" },
		{ REC_CYCLE, sizeof(struct rec_cycle) - 1, "cycle" },
		{ REC_EVENT, 0, "event" },
		{ REC_INTERVAL, sizeof(struct rec_interval) * 2, "interval" },
		{ REC_END, 4, "end" },
	};
	unsigned char payload_buf[REC_MAX_PAYLOAD] = { 1, 2, 3 }, *b;
	struct fx *f = *state;
	char err[ERRLEN], want[400];
	struct layout l;
	size_t size, n, i;

	write_trace(f->path, 0, false, &l);
	b = slurp(f->path, &size);
	for (i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		__u16 t = cases[i].t, len = cases[i].len;
		__u32 crc = crc32(0L, payload_buf, len);
		FILE *o;

		spill(f->path2, b, size);
		o = fopen(f->path2, "ab");
		assert_non_null(o);
		fwrite(&t, 2, 1, o);
		fwrite(&len, 2, 1, o);
		fwrite(&crc, 4, 1, o);
		fwrite(payload_buf, 1, len, o);
		fclose(o);
		assert_int_equal(read_all(f->path2, size + 8 + len, &n, err), -1);
		assert_int_equal(n, 0);
		snprintf(want, sizeof(want), "%s: offset %zu: %s record of %zu bytes, expected ",
			 f->path2, size, cases[i].name, cases[i].len);
		assert_memory_equal(err, want, strlen(want));
	}
	free(b);
}

/*
 * open_with_record - a fresh trace with one more record (type t, payload of
 * len bytes) appended, opened: its reader in *r, its header in *h
 */
static void open_with_record(struct fx *f, __u16 t, const void *payload, __u16 len,
			     struct rec_reader **r, struct rec_header *h)
{
	__u32 crc = crc32(0L, payload, len);
	char err[ERRLEN];
	struct layout l;
	unsigned char *b;
	size_t size;
	FILE *o;

	write_trace(f->path, 0, false, &l);
	b = slurp(f->path, &size);
	spill(f->path2, b, size);
	free(b);
	o = fopen(f->path2, "ab");
	assert_non_null(o);
	fwrite(&t, 2, 1, o);
	fwrite(&len, 2, 1, o);
	fwrite(&crc, 4, 1, o);
	fwrite(payload, 1, len, o);
	fclose(o);
	assert_int_equal(rec_open(r, f->path2, h, err, ERRLEN), 0);
}

/*
 * an event recorded before events carried a cause (len REC_EVENT_NO_CAUSE),
 * before a cause said when and where (REC_EVENT_CAUSE_1), or before it had
 * the hypervisor's steal (REC_EVENT_CAUSE_2): read, the rest zero
 */
static void old_event(void **state, __u16 len)
{
	unsigned char payload_buf[REC_MAX_PAYLOAD];
	struct rtsup_event e = { .ts = 5, .type = RTSUP_EV_MISS, .tid = 7, .arg = 42,
				 .cause = { .kind = RTSUP_CAUSE_TIMER, .held_to = 9,
					   .steal_ns = 11 } };
	struct rec_reader *r;
	struct rec_header h;
	enum rec_type type;
	char err[ERRLEN];
	size_t got, n = 0;

	open_with_record(*state, REC_EVENT, &e, len, &r, &h);
	memset(payload_buf, 0xff, sizeof(payload_buf));
	while (rec_next(r, &type, payload_buf, &got, err, ERRLEN) == 1)
		n++;
	/* the last record read is the old event, its cause zero */
	assert_int_equal(type, REC_EVENT);
	assert_int_equal(got, sizeof(struct rtsup_event));
	memcpy(&e, payload_buf, sizeof(e));
	assert_int_equal(e.tid, 7);
	assert_int_equal(e.arg, 42);
	assert_int_equal(e.cause.kind, len == REC_EVENT_NO_CAUSE ? RTSUP_CAUSE_NONE :
				       RTSUP_CAUSE_TIMER);
	assert_int_equal(e.cause.who.tid, 0);
	assert_int_equal(e.cause.held_to, len == REC_EVENT_CAUSE_2 ? 9 : 0);
	assert_int_equal(e.cause.steal_ns, 0);
	assert_int_equal(n, 1);
	rec_free(r);
	free(h.config_text);
}

static void test_record_event_without_cause(void **state)
{
	old_event(state, REC_EVENT_NO_CAUSE);
	old_event(state, REC_EVENT_CAUSE_1);
	old_event(state, REC_EVENT_CAUSE_2);
}

/*
 * an interval recorded with 7 counters (REC_INTERVAL_C7, before
 * RTSUP_C_DELIM_UNSEEN): its counters read, the new one zero, its overhead
 * where it was
 */
static void test_record_interval_of_7_counters(void **state)
{
	unsigned char payload_buf[REC_MAX_PAYLOAD], old[REC_INTERVAL_C7];
	double overhead = 0.25;
	struct rec_interval ri;
	struct rec_reader *r;
	struct rec_header h;
	enum rec_type type;
	char err[ERRLEN];
	size_t got;
	__u64 v;
	int k;

	for (k = 0; k < 8; k++) {	/* mono_ns, then counters 0..6: 100, 101... */
		v = 100 + k - 1;
		memcpy(old + k * 8, &v, 8);
	}
	memcpy(old + 64, &overhead, sizeof(overhead));
	open_with_record(*state, REC_INTERVAL, old, REC_INTERVAL_C7, &r, &h);
	while (rec_next(r, &type, payload_buf, &got, err, ERRLEN) == 1)
		;
	assert_int_equal(type, REC_INTERVAL);
	assert_int_equal(got, sizeof(ri));
	memcpy(&ri, payload_buf, sizeof(ri));
	assert_int_equal(ri.mono_ns, 99);
	for (k = 0; k < 7; k++)
		assert_int_equal(ri.counters[k], 100 + k);
	assert_int_equal(ri.counters[RTSUP_C_DELIM_UNSEEN], 0);
	assert_true(ri.overhead_pct == 0.25);
	rec_free(r);
	free(h.config_text);
}

/* headers that are cut, too long, not JSON, not an object, mistyped */
static void test_record_bad_header(void **state)
{
	static const char *const bad[] = {
		"{\"host\":", "[1,2]", "{\"host\":42}", "{\"interval_s\":\"1\"}",
		"{\"ewma_w\":-1}", "{\"config_text\":[]}", "{\"host\":\"a\",\"host\":\"b\"}",
	};
	unsigned char b[256];
	struct fx *f = *state;
	char err[ERRLEN];
	__u32 v[2] = { REC_VERSION, 0 };
	size_t n, i;

	for (i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		v[1] = strlen(bad[i]);
		memcpy(b, REC_MAGIC, 8);
		memcpy(b + 8, v, 8);
		memcpy(b + 16, bad[i], v[1]);
		spill(f->path2, b, 16 + v[1]);
		assert_int_equal(read_all(f->path2, 16 + v[1], &n, err), -2);
		assert_one_line(err);
		assert_non_null(strstr(err, "header"));
	}
	/* a header length far beyond the file */
	v[1] = 0xfffffff0;
	memcpy(b + 8, v, 8);
	spill(f->path2, b, 16);
	assert_int_equal(read_all(f->path2, 16, &n, err), -2);
	assert_non_null(strstr(err, "too large"));
	v[1] = 100;
	memcpy(b + 8, v, 8);
	memcpy(b + 16, "{}", 2);
	spill(f->path2, b, 18);
	assert_int_equal(read_all(f->path2, 18, &n, err), -2);
	assert_non_null(strstr(err, "header truncated (2 of 100 bytes)"));
	/* an empty object is a valid, if uninformative, header */
	v[1] = 2;
	memcpy(b + 8, v, 8);
	spill(f->path2, b, 18);
	assert_int_equal(read_all(f->path2, 18, &n, err), 0);
}

static void test_record_missing_file(void **state)
{
	struct fx *f = *state;
	struct rec_reader *r = (void *)1;
	struct rec_header h;
	char err[ERRLEN], path[400], want[500];

	snprintf(path, sizeof(path), "%s/none.rec", f->dir);
	snprintf(want, sizeof(want), "%s: No such file or directory", path);
	assert_int_equal(rec_open(&r, path, &h, err, sizeof(err)), -1);
	assert_null(r);
	assert_null(h.config_text);
	assert_string_equal(err, want);
}

static void test_record_create_fails(void **state)
{
	struct fx *f = *state;
	struct rec_writer *w = (void *)1;
	struct rec_header h;
	char err[ERRLEN], path[400];

	fill_header(&h, NULL);
	snprintf(path, sizeof(path), "%s/no/such/dir.rec", f->dir);
	assert_int_equal(rec_create(&w, path, &h, err, sizeof(err)), -1);
	assert_null(w);
	assert_one_line(err);
	assert_non_null(strstr(err, path));
}

/* the writer refuses what the reader would refuse */
static void test_record_write_rejects(void **state)
{
	unsigned char buf[REC_MAX_PAYLOAD] = { 0 };
	struct fx *f = *state;
	struct rec_writer *w;
	struct rec_header h;
	char err[ERRLEN];
	size_t n;

	fill_header(&h, NULL);
	assert_int_equal(rec_create(&w, f->path, &h, err, sizeof(err)), 0);
	assert_int_equal(rec_write(w, (enum rec_type)0, buf, 8, err, sizeof(err)), -1);
	assert_non_null(strstr(err, "unknown record type 0"));
	assert_int_equal(rec_write(w, (enum rec_type)6, buf, 8, err, sizeof(err)), -1);
	assert_int_equal(rec_write(w, REC_CYCLE, buf, sizeof(struct rec_cycle) + 1, err,
				   sizeof(err)), -1);
	assert_non_null(strstr(err, "expected"));
	assert_int_equal(rec_write(w, REC_CYCLE, buf, REC_MAX_PAYLOAD + 1, err, sizeof(err)),
			 -1);
	assert_int_equal(rec_write(w, REC_CYCLE, buf, sizeof(struct rec_cycle), err,
				   sizeof(err)), 0);
	assert_int_equal(rec_close(w, err, sizeof(err)), 0);
	/* the rejected records left no trace */
	assert_int_equal(read_all(f->path, 4096, &n, err), 0);
	assert_int_equal(n, 1);
}

/* a full device: an error from rec_write or rec_close, never a crash */
static void test_record_full_device(void **state)
{
	unsigned char buf[REC_MAX_PAYLOAD] = { 0 };
	struct rec_writer *w;
	struct rec_header h;
	char err[ERRLEN];
	int i, fails = 0;

	if (access("/dev/full", W_OK))
		skip();
	fill_header(&h, "x");
	/* a few records: the error shows at close */
	if (rec_create(&w, "/dev/full", &h, err, sizeof(err)) == 0) {
		for (i = 0; i < 10; i++)
			fails += rec_write(w, REC_CYCLE, buf, sizeof(struct rec_cycle), err,
					   sizeof(err)) != 0;
		assert_int_equal(fails, 0);
		assert_int_equal(rec_close(w, err, sizeof(err)), -1);
	}
	assert_one_line(err);
	assert_non_null(strstr(err, "/dev/full"));
	assert_non_null(strstr(err, "No space left on device"));

	/* many records: rec_write fails once the buffer is written, and stays failed */
	err[0] = '\0';
	if (rec_create(&w, "/dev/full", &h, err, sizeof(err)) == 0) {
		for (i = 0; i < 100000; i++)
			if (rec_write(w, REC_THREAD, buf, sizeof(struct rec_thread), err,
				      sizeof(err)))
				fails++;
			else
				assert_int_equal(fails, 0);
		assert_true(fails > 0);
		assert_non_null(strstr(err, "No space left on device"));
		assert_int_equal(rec_close(w, err, sizeof(err)), -1);
	}
	assert_one_line(err);
	free(h.config_text);
}

/* after an error rec_next keeps failing with the same line; tiny errlen */
static void test_record_error_sticks(void **state)
{
	unsigned char buf[REC_MAX_PAYLOAD], *b;
	struct fx *f = *state;
	struct rec_reader *r;
	struct rec_header h;
	char err[ERRLEN], err2[ERRLEN], tiny[6];
	struct layout l;
	enum rec_type t;
	size_t size, len;

	write_trace(f->path, 4, true, &l);
	b = slurp(f->path, &size);
	b[l.off[1] + 9] ^= 0xff;
	spill(f->path2, b, size);
	assert_int_equal(rec_open(&r, f->path2, &h, err, sizeof(err)), 0);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), 1);
	assert_int_equal(rec_next(r, &t, buf, &len, err, sizeof(err)), -1);
	assert_int_equal(rec_next(r, &t, buf, &len, err2, sizeof(err2)), -1);
	assert_string_equal(err, err2);
	assert_int_equal(rec_next(r, &t, buf, &len, tiny, sizeof(tiny)), -1);
	assert_int_equal(strlen(tiny), sizeof(tiny) - 1);
	rec_free(r);
	free(h.config_text);
	free(b);
}

/*
 * Fuzz-ish: every byte flipped three ways, random bytes overwritten and
 * the file cut at random points; the reader ends (-2, -1 or 0) within one
 * call per 8 bytes, errors are one line, and a flipped payload byte is
 * always caught by the CRC at its record's offset.
 */
static void test_record_fuzz(void **state)
{
	static const unsigned char masks[] = { 0x01, 0x80, 0xff };
	struct fx *f = *state;
	struct layout l;
	unsigned char *b, *m;
	char err[ERRLEN], want[64];
	size_t size, pos, i, n, k, cut;
	int ret, round;

	write_trace(f->path, 20, true, &l);
	b = slurp(f->path, &size);
	m = malloc(size);
	assert_non_null(m);
	for (pos = 0; pos < size; pos++) {
		for (i = 0; i < sizeof(masks); i++) {
			memcpy(m, b, size);
			m[pos] ^= masks[i];
			spill(f->path2, m, size);
			ret = read_all(f->path2, size, &n, err);
			assert_true(ret == -2 || ret == -1 || ret == 0);
			if (ret)
				assert_one_line(err);
			if (ret == -1)
				assert_non_null(strstr(err, "offset"));
			if (pos < l.header_end)
				continue;
			for (k = 0; l.off[k + 1] <= pos; k++)
				;
			/*
			 * Only the payload is under the CRC: a flipped type bit
			 * may turn an interval into an end record (same size).
			 */
			if (ret == 0 && pos == l.off[k] &&
			    (l.type[k] == REC_INTERVAL || l.type[k] == REC_END) &&
			    (m[pos] == REC_INTERVAL || m[pos] == REC_END))
				continue;
			assert_int_equal(ret, -1);	/* every other record byte matters */
			assert_int_equal(n, k);
			snprintf(want, sizeof(want), ": offset %zu: ", l.off[k]);
			assert_non_null(strstr(err, want));
			if (pos >= l.off[k] + 4)	/* crc or payload */
				assert_non_null(strstr(err, "record damaged (crc)"));
		}
	}
	for (round = 0; round < 3000; round++) {
		memcpy(m, b, size);
		for (i = 0; i < 1 + rnd() % 8; i++)
			m[rnd() % size] = rnd();
		cut = rnd() % 4 ? size : rnd() % (size + 1);
		spill(f->path2, m, cut);
		ret = read_all(f->path2, cut, &n, err);
		assert_true(ret == -2 || ret == -1 || ret == 0);
		if (ret)
			assert_one_line(err);
	}
	/* garbage after a valid header */
	for (round = 0; round < 500; round++) {
		size_t gsize = l.header_end + rnd() % 2000;

		memcpy(m, b, l.header_end);
		for (i = l.header_end; i < gsize && i < size; i++)
			m[i] = rnd() % 3 ? rnd() : rnd() % 6;
		if (gsize > size)
			gsize = size;
		spill(f->path2, m, gsize);
		ret = read_all(f->path2, gsize, &n, err);
		assert_true(ret == -1 || ret == 0);
	}
	free(m);
	free(b);
}

/* an error is one line: no byte a reader may split lines at */
static void test_seterr_one_line(void **state)
{
	char err[64];
	const char *p;

	(void)state;
	seterr(err, sizeof(err), "near '%s' (position %d)", "a\nb\rc\vd\fe\x1c" "f\x7f" "g", 178);
	assert_string_equal(err, "near 'a b c d e f g' (position 178)");
	for (p = err; *p; p++)
		assert_true((unsigned char)*p >= 0x20 && *p != 0x7f);
}

#define T(fn) cmocka_unit_test_setup_teardown(fn, fx_setup, fx_teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_seterr_one_line),
		T(test_record_header_roundtrip),
		T(test_record_header_no_config),
		T(test_record_header_invalid_utf8),
		T(test_record_roundtrip),
		T(test_record_roundtrip_typed),
		T(test_record_truncated),
		T(test_record_crc),
		T(test_record_bad_magic),
		T(test_record_version),
		T(test_record_bad_record_header),
		T(test_record_size_mismatch),
		T(test_record_event_without_cause),
		T(test_record_interval_of_7_counters),
		T(test_record_bad_header),
		T(test_record_missing_file),
		T(test_record_create_fails),
		T(test_record_write_rejects),
		T(test_record_full_device),
		T(test_record_error_sticks),
		T(test_record_fuzz),
	};

	return cmocka_run_group_tests_name("record", tests, NULL, NULL);
}
