/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * promexp.h - the two Prometheus exporters: a node_exporter textfile
 * (--prom-textfile, replaced atomically by rename) and HTTP /metrics
 * (--listen, libmicrohttpd's own thread). The main loop renders the text
 * once per interval and hands it over with promexp_update(); the HTTP
 * thread serves a copy of the last snapshot taken under a mutex, so a slow
 * scraper never blocks the main loop.
 */
#ifndef RTSUP_PROMEXP_H
#define RTSUP_PROMEXP_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <sys/socket.h>

struct MHD_Daemon;

struct promexp {
	const char *textfile;	/* NULL: no textfile */
	char *tmp;		/* textfile + ".tmp": same directory, so rename is atomic */
	bool text_failing;	/* the last write failed (said once) */
	struct MHD_Daemon *mhd;	/* NULL: no HTTP */
	pthread_mutex_t lock;
	char *snap;		/* last snapshot, under lock */
	size_t snap_len;
	bool locked_init;
};

/*
 * promexp_parse_listen - "ADDR:PORT", "[ADDR6]:PORT", ":PORT" or "PORT"
 * (address 127.0.0.1) into a socket address; -1 with a reason in err
 */
int promexp_parse_listen(const char *spec, struct sockaddr_storage *ss, socklen_t *len,
			 char *err, size_t errlen);
/* promexp_open - start what the options ask for; -1 with one line on stderr */
int promexp_open(struct promexp *e, const char *textfile, const char *listen);
/* promexp_update - the new exposition text: snapshot for HTTP, textfile rewritten */
void promexp_update(struct promexp *e, const char *text, size_t len);
/* promexp_close - stop HTTP, remove the textfile (its numbers would go stale) */
void promexp_close(struct promexp *e);

#endif
