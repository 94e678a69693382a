// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_promexp.c - user/sinks/promexp.c: --listen address forms, the textfile
 * replaced atomically, and HTTP /metrics served on loopback from the
 * last snapshot.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/stat.h>
#include <cmocka.h>

#include "sinks/promexp.h"

static void test_promexp_parse_listen(void **state)
{
	struct sockaddr_storage ss;
	struct sockaddr_in *in4 = (struct sockaddr_in *)&ss;
	struct sockaddr_in6 *in6 = (struct sockaddr_in6 *)&ss;
	socklen_t len;
	char err[128], a[64];

	assert_int_equal(promexp_parse_listen("127.0.0.1:9101", &ss, &len, err, sizeof(err)), 0);
	assert_int_equal(ss.ss_family, AF_INET);
	assert_int_equal(ntohs(in4->sin_port), 9101);
	/* no address: loopback, never every interface */
	assert_int_equal(promexp_parse_listen(":9102", &ss, &len, err, sizeof(err)), 0);
	assert_string_equal(inet_ntop(AF_INET, &in4->sin_addr, a, sizeof(a)), "127.0.0.1");
	assert_int_equal(ntohs(in4->sin_port), 9102);
	assert_int_equal(promexp_parse_listen("9103", &ss, &len, err, sizeof(err)), 0);
	assert_string_equal(inet_ntop(AF_INET, &in4->sin_addr, a, sizeof(a)), "127.0.0.1");
	assert_int_equal(promexp_parse_listen("0.0.0.0:9104", &ss, &len, err, sizeof(err)), 0);
	assert_string_equal(inet_ntop(AF_INET, &in4->sin_addr, a, sizeof(a)), "0.0.0.0");
	assert_int_equal(promexp_parse_listen("[::1]:9105", &ss, &len, err, sizeof(err)), 0);
	assert_int_equal(ss.ss_family, AF_INET6);
	assert_int_equal(ntohs(in6->sin6_port), 9105);
	assert_int_equal(promexp_parse_listen("127.0.0.1:0", &ss, &len, err, sizeof(err)), -1);
	assert_int_equal(promexp_parse_listen("127.0.0.1:70000", &ss, &len, err, sizeof(err)), -1);
	assert_int_equal(promexp_parse_listen("127.0.0.1:", &ss, &len, err, sizeof(err)), -1);
	assert_int_equal(promexp_parse_listen("[::1]9105", &ss, &len, err, sizeof(err)), -1);
	assert_int_equal(promexp_parse_listen("256.1.1.1:80", &ss, &len, err, sizeof(err)), -1);
}

static void test_promexp_textfile_atomic(void **state)
{
	char dir[] = "/tmp/test_promexp.XXXXXX", path[256], tmp[300], buf[64];
	struct promexp e;
	struct stat st;
	FILE *f;
	size_t n;

	assert_non_null(mkdtemp(dir));
	snprintf(path, sizeof(path), "%s/rtsup.prom", dir);
	snprintf(tmp, sizeof(tmp), "%s.tmp", path);
	assert_int_equal(promexp_open(&e, path, NULL), 0);
	promexp_update(&e, "a 1\n", 4);
	promexp_update(&e, "a 2\n", 4);
	f = fopen(path, "r");
	assert_non_null(f);
	n = fread(buf, 1, sizeof(buf) - 1, f);
	buf[n] = '\0';
	fclose(f);
	assert_string_equal(buf, "a 2\n");
	/* the temporary file never stays behind */
	assert_int_equal(stat(tmp, &st), -1);
	/* a stopped exporter leaves no stale numbers */
	promexp_close(&e);
	assert_int_equal(stat(path, &st), -1);
	/* a directory that is not there: the run goes on, said on stderr */
	snprintf(path, sizeof(path), "%s/missing/rtsup.prom", dir);
	assert_int_equal(promexp_open(&e, path, NULL), 0);
	promexp_update(&e, "a 1\n", 4);
	assert_true(e.text_failing);
	promexp_close(&e);
	rmdir(dir);
}

/* http_get - one request on loopback; the response into buf */
static int http_get(int port, const char *req, char *buf, size_t len)
{
	struct sockaddr_in a = { .sin_family = AF_INET, .sin_port = htons(port) };
	size_t off = 0;
	ssize_t n;
	int fd = socket(AF_INET, SOCK_STREAM, 0);

	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	if (fd < 0)
		return -1;
	if (connect(fd, (struct sockaddr *)&a, sizeof(a)) ||
	    write(fd, req, strlen(req)) != (ssize_t)strlen(req)) {
		close(fd);
		return -1;
	}
	while (off < len - 1 && (n = read(fd, buf + off, len - 1 - off)) > 0)
		off += n;
	buf[off] = '\0';
	close(fd);
	return 0;
}

static void test_promexp_http(void **state)
{
	struct promexp e;
	char buf[4096], spec[32];
	int port, tries;

	/* a free port in the ephemeral range: try a few */
	for (tries = 0; tries < 20; tries++) {
		port = 20000 + (getpid() * 7 + tries * 131) % 20000;
		snprintf(spec, sizeof(spec), "127.0.0.1:%d", port);
		if (!promexp_open(&e, NULL, spec))
			break;
		promexp_close(&e);
	}
	assert_true(tries < 20);
	/* before the first update: an empty exposition */
	assert_int_equal(http_get(port, "GET /metrics HTTP/1.0\r\n\r\n", buf, sizeof(buf)), 0);
	assert_non_null(strstr(buf, "200 OK"));
	promexp_update(&e, "rtsup_up 1\n", 11);
	assert_int_equal(http_get(port, "GET /metrics HTTP/1.0\r\n\r\n", buf, sizeof(buf)), 0);
	assert_non_null(strstr(buf, "200 OK"));
	assert_non_null(strstr(buf, "text/plain; version=0.0.4"));
	assert_non_null(strstr(buf, "\r\n\r\nrtsup_up 1\n"));
	assert_int_equal(http_get(port, "GET /nope HTTP/1.0\r\n\r\n", buf, sizeof(buf)), 0);
	assert_non_null(strstr(buf, "404"));
	assert_int_equal(http_get(port, "POST /metrics HTTP/1.0\r\nContent-Length: 0\r\n\r\n",
				  buf, sizeof(buf)), 0);
	assert_non_null(strstr(buf, "405"));
	promexp_close(&e);
	/* stopped: nobody listens any more */
	assert_int_equal(http_get(port, "GET /metrics HTTP/1.0\r\n\r\n", buf, sizeof(buf)), -1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_promexp_parse_listen),
		cmocka_unit_test(test_promexp_textfile_atomic),
		cmocka_unit_test(test_promexp_http),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
