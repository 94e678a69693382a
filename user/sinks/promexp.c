// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* promexp.c - node_exporter textfile and HTTP /metrics (libmicrohttpd) */
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <microhttpd.h>
#include "sinks/promexp.h"

#define CONTENT_TYPE "text/plain; version=0.0.4; charset=utf-8"

/*
 * libmicrohttpd is opened only for --listen: linked, it loads GnuTLS,
 * p11-kit, nettle and gmp into every run, 2.3 MiB resident that a robot
 * without an HTTP endpoint pays for nothing (docs/performance.md).
 */
#define MHD_SONAME "libmicrohttpd.so.12"

static struct {
	void *h;
	__typeof__(MHD_start_daemon) *start_daemon;
	__typeof__(MHD_stop_daemon) *stop_daemon;
	__typeof__(MHD_create_response_from_buffer) *response_from_buffer;
	__typeof__(MHD_add_response_header) *add_response_header;
	__typeof__(MHD_queue_response) *queue_response;
	__typeof__(MHD_destroy_response) *destroy_response;
} mhd;

/* mhd_load - the library and its six functions; one line on stderr, -1 */
static int mhd_load(const char *listen)
{
	void *h;

	if (mhd.h)
		return 0;
	h = dlopen(MHD_SONAME, RTLD_NOW | RTLD_LOCAL);
	if (!h) {
		fprintf(stderr, "rtsup-trace: --listen '%s' needs %s (Debian: apt install "
			"libmicrohttpd12): %s\n", listen, MHD_SONAME, dlerror());
		return -1;
	}
	*(void **)&mhd.start_daemon = dlsym(h, "MHD_start_daemon");
	*(void **)&mhd.stop_daemon = dlsym(h, "MHD_stop_daemon");
	*(void **)&mhd.response_from_buffer = dlsym(h, "MHD_create_response_from_buffer");
	*(void **)&mhd.add_response_header = dlsym(h, "MHD_add_response_header");
	*(void **)&mhd.queue_response = dlsym(h, "MHD_queue_response");
	*(void **)&mhd.destroy_response = dlsym(h, "MHD_destroy_response");
	if (!mhd.start_daemon || !mhd.stop_daemon || !mhd.response_from_buffer ||
	    !mhd.add_response_header || !mhd.queue_response || !mhd.destroy_response) {
		fprintf(stderr, "rtsup-trace: --listen '%s': %s lacks a function rtsup-trace "
			"calls\n", listen, MHD_SONAME);
		dlclose(h);
		return -1;
	}
	mhd.h = h;
	return 0;
}

int promexp_parse_listen(const char *spec, struct sockaddr_storage *ss, socklen_t *len,
			 char *err, size_t errlen)
{
	struct addrinfo hints = { .ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM,
				  .ai_flags = AI_PASSIVE | AI_NUMERICSERV };
	struct addrinfo *res;
	char host[256] = "127.0.0.1", port[16];
	const char *colon;
	char *end;
	long p;
	int rc;

	if (spec[0] == '[') {
		const char *close = strchr(spec, ']');

		if (!close || close[1] != ':' || close - spec - 1 >= (long)sizeof(host)) {
			snprintf(err, errlen, "want [ADDRESS]:PORT for IPv6");
			return -1;
		}
		snprintf(host, sizeof(host), "%.*s", (int)(close - spec - 1), spec + 1);
		colon = close + 1;
	} else {
		colon = strrchr(spec, ':');
		if (colon && colon != spec) {
			if (colon - spec >= (long)sizeof(host)) {
				snprintf(err, errlen, "address too long");
				return -1;
			}
			snprintf(host, sizeof(host), "%.*s", (int)(colon - spec), spec);
		}
	}
	errno = 0;
	p = strtol(colon ? colon + 1 : spec, &end, 10);
	if (errno || *end || end == (colon ? colon + 1 : spec) || p < 1 || p > 65535) {
		snprintf(err, errlen, "want ADDRESS:PORT with a port from 1 to 65535");
		return -1;
	}
	snprintf(port, sizeof(port), "%ld", p);
	rc = getaddrinfo(host, port, &hints, &res);
	if (rc) {
		snprintf(err, errlen, "%s", gai_strerror(rc));
		return -1;
	}
	memcpy(ss, res->ai_addr, res->ai_addrlen);
	*len = res->ai_addrlen;
	freeaddrinfo(res);
	return 0;
}

/* on_request - GET /metrics: the last snapshot; anything else: 404 or 405 */
static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn, const char *url,
				  const char *method, const char *version,
				  const char *upload_data, size_t *upload_size, void **con_cls)
{
	static const char index[] = "rtsup-trace: metrics at /metrics\n";
	struct promexp *e = cls;
	struct MHD_Response *r;
	enum MHD_Result ret;
	unsigned int code = MHD_HTTP_OK;

	if (strcmp(method, "GET") && strcmp(method, "HEAD")) {
		r = mhd.response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
		code = MHD_HTTP_METHOD_NOT_ALLOWED;
	} else if (!strcmp(url, "/metrics")) {
		pthread_mutex_lock(&e->lock);
		r = mhd.response_from_buffer(e->snap_len, e->snap ? e->snap : (void *)"",
						    MHD_RESPMEM_MUST_COPY);
		pthread_mutex_unlock(&e->lock);
		if (r)
			mhd.add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, CONTENT_TYPE);
	} else if (!strcmp(url, "/")) {
		r = mhd.response_from_buffer(sizeof(index) - 1, (void *)index,
						    MHD_RESPMEM_PERSISTENT);
	} else {
		r = mhd.response_from_buffer(10, (void *)"not found\n",
						    MHD_RESPMEM_PERSISTENT);
		code = MHD_HTTP_NOT_FOUND;
	}
	if (!r)
		return MHD_NO;
	ret = mhd.queue_response(conn, code, r);
	mhd.destroy_response(r);
	return ret;
}

int promexp_open(struct promexp *e, const char *textfile, const char *listen)
{
	struct sockaddr_storage ss;
	socklen_t len;
	char err[128];

	memset(e, 0, sizeof(*e));
	pthread_mutex_init(&e->lock, NULL);
	e->locked_init = true;
	if (textfile) {
		e->textfile = textfile;
		if (asprintf(&e->tmp, "%s.tmp", textfile) < 0) {
			e->tmp = NULL;
			return -1;
		}
	}
	if (!listen)
		return 0;
	if (promexp_parse_listen(listen, &ss, &len, err, sizeof(err))) {
		fprintf(stderr, "rtsup-trace: --listen '%s': %s\n", listen, err);
		return -1;
	}
	if (mhd_load(listen))
		return -1;
	/* no MHD_USE_ERROR_LOG: its lines ("Failed to bind...", a client's
	 * errors) would come next to ours, and a hostile client could fill stderr */
	e->mhd = mhd.start_daemon(MHD_USE_INTERNAL_POLLING_THREAD |
				  (ss.ss_family == AF_INET6 ? MHD_USE_IPv6 : 0),
				  0, NULL, NULL, on_request, e,
				  MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&ss,
				  MHD_OPTION_CONNECTION_LIMIT, 16U,
				  MHD_OPTION_CONNECTION_TIMEOUT, 10U,
				  MHD_OPTION_END);
	if (!e->mhd) {
		fprintf(stderr, "rtsup-trace: --listen '%s': cannot serve HTTP there: %s\n",
			listen, errno ? strerror(errno) : "libmicrohttpd failed");
		return -1;
	}
	return 0;
}

/* write_textfile - write the temporary file, then rename it over the real one */
static int write_textfile(struct promexp *e, const char *text, size_t len)
{
	size_t off = 0;
	int fd = open(e->tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);

	if (fd < 0)
		return -1;
	while (off < len) {
		ssize_t w = write(fd, text + off, len - off);

		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0) {
			int saved = w < 0 ? errno : ENOSPC;

			close(fd);
			unlink(e->tmp);
			errno = saved;
			return -1;
		}
		off += w;
	}
	if (close(fd) || rename(e->tmp, e->textfile)) {
		int saved = errno;

		unlink(e->tmp);
		errno = saved;
		return -1;
	}
	return 0;
}

void promexp_update(struct promexp *e, const char *text, size_t len)
{
	if (e->mhd) {
		char *copy = malloc(len + 1);

		if (copy) {
			memcpy(copy, text, len);
			copy[len] = '\0';
			pthread_mutex_lock(&e->lock);
			free(e->snap);
			e->snap = copy;
			e->snap_len = len;
			pthread_mutex_unlock(&e->lock);
		}
	}
	if (!e->textfile || !e->tmp)
		return;
	/* a failing file is said once, and once when it works again; the run goes on */
	if (write_textfile(e, text, len)) {
		if (!e->text_failing)
			fprintf(stderr, "rtsup-trace: --prom-textfile %s: %s (retrying every interval)\n",
				e->textfile, strerror(errno));
		e->text_failing = true;
	} else if (e->text_failing) {
		fprintf(stderr, "rtsup-trace: --prom-textfile %s: written again\n", e->textfile);
		e->text_failing = false;
	}
}

void promexp_close(struct promexp *e)
{
	if (e->mhd)
		mhd.stop_daemon(e->mhd);
	e->mhd = NULL;
	if (e->textfile)
		unlink(e->textfile);
	e->textfile = NULL;
	free(e->tmp);
	e->tmp = NULL;
	free(e->snap);
	e->snap = NULL;
	if (e->locked_init)
		pthread_mutex_destroy(&e->lock);
	e->locked_init = false;
}
