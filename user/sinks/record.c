// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * record.c - the recorded trace (see record.h): writer and reader.
 *
 * The writer goes through a large stdio buffer, so a record costs two
 * memcpy, not a syscall; the first write error sticks and every later call
 * reports it again. The reader trusts nothing: magic, version, header
 * length and JSON, then per record its type, length and CRC, so a damaged
 * or truncated file ends with one line naming the byte offset of the bad
 * record, and every successful record moves forward by at least 8 bytes.
 *
 * All integers are in the recording host's byte order, like the payload
 * structs themselves; a file from a host of the other order is recognised
 * by its byte-swapped version and refused with a clear message.
 */
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <byteswap.h>
#include <jansson.h>
#include <zlib.h>
#include "sinks/errline.h"
#include "sinks/jsonstr.h"
#include "sinks/record.h"

#define MAGIC_LEN	(sizeof(REC_MAGIC) - 1)
#define REC_HDR_LEN	8			/* u16 type | u16 len | u32 crc */
#define WRITE_BUF	(256 * 1024)		/* stdio buffer of the writer */
#define MAX_HEADER	(16 * 1024 * 1024)	/* sanity limit of the JSON header */

_Static_assert(sizeof(struct rec_thread) <= REC_MAX_PAYLOAD &&
		       sizeof(struct rec_cycle) <= REC_MAX_PAYLOAD &&
		       sizeof(struct rtsup_event) <= REC_MAX_PAYLOAD &&
		       sizeof(struct rec_interval) <= REC_MAX_PAYLOAD &&
		       sizeof(struct rec_stack) <= REC_MAX_PAYLOAD &&
		       sizeof(struct rec_module) <= REC_MAX_PAYLOAD,
	       "a record type does not fit REC_MAX_PAYLOAD");

struct rec_writer {
	FILE *f;
	char *path;
	int err;		/* first write error (errno), sticky */
};

struct rec_reader {
	FILE *f;
	char *path;
	__u64 off;		/* byte offset of the next record */
	int failed;		/* an error was reported: repeat it */
	char msg[512];
};

/* rec_size - the payload size of a record type, 0 if the type is unknown */
static size_t rec_size(unsigned int type)
{
	switch (type) {
	case REC_THREAD:
		return sizeof(struct rec_thread);
	case REC_CYCLE:
		return sizeof(struct rec_cycle);
	case REC_EVENT:
		return sizeof(struct rtsup_event);
	case REC_INTERVAL:
	case REC_END:
		return sizeof(struct rec_interval);
	case REC_STACK:
		return sizeof(struct rec_stack);
	case REC_MODULE:
		return sizeof(struct rec_module);
	}
	return 0;
}

/*
 * rec_older_size - a record of an older recording, shorter than today's:
 * an event before it carried its cause, or all of it (the rest reads as
 * zero), an interval with fewer counters (interval_from_c7)
 */
static bool rec_older_size(unsigned int type, size_t len)
{
	if (type == REC_EVENT)
		return len == REC_EVENT_NO_CAUSE || len == REC_EVENT_CAUSE_1 ||
		       len == REC_EVENT_CAUSE_2;
	return (type == REC_INTERVAL || type == REC_END) && len == REC_INTERVAL_C7;
}

_Static_assert(RTSUP_C_NR > 7, "an interval of 7 counters would read as today's");

/* interval_from_c7 - an interval of 7 counters: its overhead follows them */
static void interval_from_c7(void *buf)
{
	struct rec_interval *ri = buf;
	double overhead;

	memcpy(&overhead, &ri->counters[7], sizeof(overhead));
	memset(&ri->counters[7], 0, sizeof(ri->counters) - 7 * sizeof(__u64));
	ri->overhead_pct = overhead;
}

static const char *rec_type_name(unsigned int type)
{
	static const char *const names[] = {
		[REC_THREAD] = "thread", [REC_CYCLE] = "cycle", [REC_EVENT] = "event",
		[REC_INTERVAL] = "interval", [REC_END] = "end", [REC_STACK] = "stack",
		[REC_MODULE] = "module",
	};

	return type < sizeof(names) / sizeof(names[0]) && names[type] ? names[type]
								       : "unknown";
}

/* ---- writer ---- */

/* header_json - struct rec_header as a JSON object */
static json_t *header_json(const struct rec_header *h)
{
	json_t *o = json_object();

	if (!o)
		return NULL;
	if (json_object_set_new(o, "kernel", json_str(h->kernel, sizeof(h->kernel))) ||
	    json_object_set_new(o, "host", json_str(h->host, sizeof(h->host))) ||
	    json_object_set_new(o, "args", json_str(h->args, sizeof(h->args))) ||
	    json_object_set_new(o, "config_path",
				json_str(h->config_path, sizeof(h->config_path))) ||
	    json_object_set_new(o, "config_text", h->config_text
				? json_str(h->config_text, SIZE_MAX) : json_null()) ||
	    json_object_set_new(o, "start_real_ns", json_integer((json_int_t)h->start_real_ns)) ||
	    json_object_set_new(o, "start_mono_ns", json_integer((json_int_t)h->start_mono_ns)) ||
	    json_object_set_new(o, "interval_s", json_real(h->interval_s)) ||
	    json_object_set_new(o, "ewma_w", json_integer(h->ewma_w))) {
		json_decref(o);
		return NULL;
	}
	return o;
}

/* w_put - buffered write; the first error sticks */
static int w_put(struct rec_writer *w, const void *p, size_t n)
{
	if (w->err)
		return -1;
	if (n && fwrite_unlocked(p, 1, n, w->f) != n) {
		w->err = errno ? errno : EIO;
		return -1;
	}
	return 0;
}

static int w_fail(struct rec_writer *w, char *err, size_t errlen)
{
	seterr(err, errlen, "%s: write: %s", w->path, strerror(w->err));
	return -1;
}

int rec_create(struct rec_writer **wp, const char *path, const struct rec_header *h,
	       char *err, size_t errlen)
{
	__u32 v[2] = { REC_VERSION, 0 };
	struct rec_writer *w;
	char *text = NULL;
	json_t *o;

	*wp = NULL;
	o = header_json(h);
	if (o)
		text = json_dumps(o, JSON_COMPACT);
	json_decref(o);
	if (!text) {
		seterr(err, errlen, "%s: cannot encode the header", path);
		return -1;
	}
	if (strlen(text) > MAX_HEADER) {
		seterr(err, errlen, "%s: header too large (%zu bytes)", path, strlen(text));
		free(text);
		return -1;
	}
	v[1] = strlen(text);
	w = calloc(1, sizeof(*w));
	if (!w || !(w->path = strdup(path))) {
		seterr(err, errlen, "%s: %s", path, strerror(ENOMEM));
		goto fail;
	}
	w->f = fopen(path, "wbe");
	if (!w->f) {
		seterr(err, errlen, "%s: %s", path, strerror(errno));
		goto fail;
	}
	setvbuf(w->f, NULL, _IOFBF, WRITE_BUF);
	errno = 0;
	if (w_put(w, REC_MAGIC, MAGIC_LEN) || w_put(w, v, sizeof(v)) ||
	    w_put(w, text, v[1])) {
		w_fail(w, err, errlen);
		fclose(w->f);
		goto fail;
	}
	free(text);
	*wp = w;
	return 0;
fail:
	free(text);
	if (w)
		free(w->path);
	free(w);
	return -1;
}

int rec_write(struct rec_writer *w, enum rec_type type, const void *payload, size_t len,
	      char *err, size_t errlen)
{
	unsigned char hdr[REC_HDR_LEN];
	size_t want = rec_size(type);
	__u16 t16 = type, l16 = len;
	__u32 crc;

	if (!want) {
		seterr(err, errlen, "%s: unknown record type %d", w->path, (int)type);
		return -1;
	}
	if (len != want || !payload) {
		seterr(err, errlen, "%s: %s record of %zu bytes, expected %zu", w->path,
		       rec_type_name(type), len, want);
		return -1;
	}
	if (w->err)
		return w_fail(w, err, errlen);
	crc = crc32(0L, payload, len);
	memcpy(hdr, &t16, 2);
	memcpy(hdr + 2, &l16, 2);
	memcpy(hdr + 4, &crc, 4);
	errno = 0;
	if (w_put(w, hdr, sizeof(hdr)) || w_put(w, payload, len))
		return w_fail(w, err, errlen);
	return 0;
}

int rec_close(struct rec_writer *w, char *err, size_t errlen)
{
	int e;

	if (!w)
		return 0;
	e = w->err;
	errno = 0;
	if (!e && fflush(w->f))
		e = errno ? errno : EIO;
	/* pipes and character devices cannot be synced: not an error */
	if (!e && fsync(fileno(w->f)) && errno != EINVAL && errno != EROFS &&
	    errno != ENOTSUP)
		e = errno;
	if (fclose(w->f) && !e)
		e = errno ? errno : EIO;
	if (e)
		seterr(err, errlen, "%s: write: %s", w->path, strerror(e));
	free(w->path);
	free(w);
	return e ? -1 : 0;
}

/* ---- reader ---- */

/*
 * The fuzz build (tests/fuzz) takes any checksum: a mutated payload then
 * reaches replay's handlers instead of stopping at the crc.
 */
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
#define REC_FUZZING	1
#else
#define REC_FUZZING	0
#endif

/* r_read - read n bytes: how many were read; a read error sets *e */
static size_t r_read(struct rec_reader *r, void *p, size_t n, int *e)
{
	size_t got = fread_unlocked(p, 1, n, r->f);

	*e = got < n && ferror_unlocked(r->f) ? (errno ? errno : EIO) : 0;
	return got;
}

/* get_str - copy a string field (missing = ""); -1 if it is not a string */
static int get_str(json_t *o, const char *key, char *dst, size_t size)
{
	json_t *v = json_object_get(o, key);

	dst[0] = '\0';
	if (!v || json_is_null(v))
		return 0;
	if (!json_is_string(v))
		return -1;
	snprintf(dst, size, "%s", json_string_value(v));
	return 0;
}

/* get_int - an integer field (missing = 0); -1 if it is not an integer */
static int get_int(json_t *o, const char *key, __u64 *dst)
{
	json_t *v = json_object_get(o, key);

	*dst = 0;
	if (!v)
		return 0;
	if (!json_is_integer(v))
		return -1;
	*dst = (__u64)json_integer_value(v);
	return 0;
}

/* parse_header - the JSON header into h; the name of a bad field, or NULL */
static const char *parse_header(json_t *o, struct rec_header *h)
{
	json_t *v;
	__u64 x;

	if (get_str(o, "kernel", h->kernel, sizeof(h->kernel)))
		return "kernel";
	if (get_str(o, "host", h->host, sizeof(h->host)))
		return "host";
	if (get_str(o, "args", h->args, sizeof(h->args)))
		return "args";
	if (get_str(o, "config_path", h->config_path, sizeof(h->config_path)))
		return "config_path";
	if (get_int(o, "start_real_ns", &h->start_real_ns))
		return "start_real_ns";
	if (get_int(o, "start_mono_ns", &h->start_mono_ns))
		return "start_mono_ns";
	if (get_int(o, "ewma_w", &x) || x > UINT32_MAX)
		return "ewma_w";
	h->ewma_w = x;
	v = json_object_get(o, "interval_s");
	if (v && !json_is_number(v))
		return "interval_s";
	h->interval_s = v ? json_number_value(v) : 0;
	v = json_object_get(o, "config_text");
	if (v && !json_is_null(v)) {
		if (!json_is_string(v))
			return "config_text";
		h->config_text = strdup(json_string_value(v));
		if (!h->config_text)
			return "config_text (out of memory)";
	}
	return NULL;
}

int rec_open(struct rec_reader **rp, const char *path, struct rec_header *h, char *err,
	     size_t errlen)
{
	char magic[MAGIC_LEN], *text = NULL;
	struct rec_reader *r;
	json_error_t jerr;
	const char *bad;
	__u32 v[2];
	size_t n;
	json_t *o;
	int e;

	*rp = NULL;
	memset(h, 0, sizeof(*h));
	r = calloc(1, sizeof(*r));
	if (!r || !(r->path = strdup(path))) {
		seterr(err, errlen, "%s: %s", path, strerror(ENOMEM));
		goto fail;
	}
	r->f = fopen(path, "rbe");
	if (!r->f) {
		seterr(err, errlen, "%s: %s", path, strerror(errno));
		goto fail;
	}
	n = r_read(r, magic, MAGIC_LEN, &e);
	if (e) {
		seterr(err, errlen, "%s: read: %s", path, strerror(e));
		goto fail;
	}
	if (n == 0) {
		seterr(err, errlen, "%s: not an rtsup trace (empty file)", path);
		goto fail;
	}
	if (n < MAGIC_LEN || memcmp(magic, REC_MAGIC, MAGIC_LEN)) {
		seterr(err, errlen, "%s: not an rtsup trace (bad magic)", path);
		goto fail;
	}
	n = r_read(r, v, sizeof(v), &e);
	if (e) {
		seterr(err, errlen, "%s: read: %s", path, strerror(e));
		goto fail;
	}
	if (n >= sizeof(v[0]) && v[0] != REC_VERSION) {
		if (v[0] == bswap_32(REC_VERSION))
			seterr(err, errlen,
			       "%s: recorded on a host of the other byte order, "
			       "this rtsup-trace cannot read it", path);
		else
			seterr(err, errlen, "%s: version %u, this rtsup-trace reads %d", path,
			       v[0], REC_VERSION);
		goto fail;
	}
	if (n < sizeof(v)) {
		seterr(err, errlen, "%s: header truncated", path);
		goto fail;
	}
	if (v[1] > MAX_HEADER) {
		seterr(err, errlen, "%s: header length %u too large (damaged file?)", path,
		       v[1]);
		goto fail;
	}
	text = malloc(v[1] + 1);
	if (!text) {
		seterr(err, errlen, "%s: %s", path, strerror(ENOMEM));
		goto fail;
	}
	n = r_read(r, text, v[1], &e);
	if (e) {
		seterr(err, errlen, "%s: read: %s", path, strerror(e));
		goto fail;
	}
	if (n < v[1]) {
		seterr(err, errlen, "%s: header truncated (%zu of %u bytes)", path, n, v[1]);
		goto fail;
	}
	o = json_loadb(text, v[1], JSON_REJECT_DUPLICATES, &jerr);
	if (!o) {
		seterr(err, errlen, "%s: header is not valid JSON: %s (position %d)", path,
		       jerr.text, jerr.position);
		goto fail;
	}
	if (!json_is_object(o)) {
		json_decref(o);
		seterr(err, errlen, "%s: header is not a JSON object", path);
		goto fail;
	}
	bad = parse_header(o, h);
	json_decref(o);
	if (bad) {
		seterr(err, errlen, "%s: header field %s has the wrong type", path, bad);
		goto fail;
	}
	free(text);
	r->off = MAGIC_LEN + sizeof(v) + v[1];
	*rp = r;
	return 0;
fail:
	free(text);
	free(h->config_text);
	h->config_text = NULL;
	rec_free(r);
	return -1;
}

/* r_fail - remember the error: rec_next repeats it from now on */
__attribute__((format(printf, 2, 3)))
static int r_fail(struct rec_reader *r, const char *fmt, ...)
{
	char what[256];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(what, sizeof(what), fmt, ap);
	va_end(ap);
	seterr(r->msg, sizeof(r->msg), "%s: offset %llu: %s", r->path,
	       (unsigned long long)r->off, what);
	r->failed = 1;
	return -1;
}

int rec_next(struct rec_reader *r, enum rec_type *type, void *buf, size_t *len,
	     char *err, size_t errlen)
{
	unsigned char hdr[REC_HDR_LEN];
	__u16 t16, l16;
	__u32 crc;
	size_t n, want;
	int e;

	if (r->failed)
		goto out;
	n = r_read(r, hdr, sizeof(hdr), &e);
	if (e) {
		r_fail(r, "read: %s", strerror(e));
		goto out;
	}
	if (n == 0)
		return 0;	/* clean end right after a complete record */
	if (n < sizeof(hdr)) {
		r_fail(r, "record header truncated (%zu of %d bytes)", n, REC_HDR_LEN);
		goto out;
	}
	memcpy(&t16, hdr, 2);
	memcpy(&l16, hdr + 2, 2);
	memcpy(&crc, hdr + 4, 4);
	want = rec_size(t16);
	if (!want) {
		r_fail(r, "unknown record type %u", t16);
		goto out;
	}
	if (l16 > REC_MAX_PAYLOAD) {
		r_fail(r, "record length %u over the maximum %d", l16, REC_MAX_PAYLOAD);
		goto out;
	}
	if (l16 != want && !rec_older_size(t16, l16)) {
		r_fail(r, "%s record of %u bytes, expected %zu", rec_type_name(t16), l16,
		       want);
		goto out;
	}
	n = r_read(r, buf, l16, &e);
	if (e) {
		r_fail(r, "read: %s", strerror(e));
		goto out;
	}
	if (n < l16) {
		r_fail(r, "payload truncated (%zu of %u bytes)", n, l16);
		goto out;
	}
	if (crc32(0L, buf, l16) != crc && !REC_FUZZING) {
		r_fail(r, "record damaged (crc)");
		goto out;
	}
	*type = t16;
	*len = l16;
	r->off += sizeof(hdr) + l16;
	if (l16 < want) {
		memset((char *)buf + l16, 0, want - l16);
		*len = want;
	}
	if ((t16 == REC_INTERVAL || t16 == REC_END) && l16 == REC_INTERVAL_C7)
		interval_from_c7(buf);
	return 1;
out:
	seterr(err, errlen, "%s", r->msg);
	return -1;
}

void rec_tell(const struct rec_reader *r, __u64 *done, __u64 *total)
{
	struct stat st;

	*done = r->off;
	*total = !fstat(fileno(r->f), &st) && S_ISREG(st.st_mode) ? (__u64)st.st_size : 0;
}

void rec_free(struct rec_reader *r)
{
	if (!r)
		return;
	if (r->f)
		fclose(r->f);
	free(r->path);
	free(r);
}
