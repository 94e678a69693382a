// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_candump.c - lines of can-utils candump logs, good and malformed */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "offline/candump.h"
#include "can.h"

#define EFF	RTSUP_CAN_EFF_FLAG
#define RTR	RTSUP_CAN_RTR_FLAG

/* good - a line that must give a frame */
static struct candump_frame good(const char *line)
{
	struct candump_frame f;
	char err[256] = "";
	int ret;

	ret = candump_parse(line, &f, err, sizeof(err));
	if (ret != 1)
		print_error("'%s': %d %s\n", line, ret, err);
	assert_int_equal(ret, 1);
	assert_string_equal(err, "");
	return f;
}

/* skipped - a line that is no frame and no error */
static void skipped(const char *line)
{
	struct candump_frame f;
	char err[256] = "";

	assert_int_equal(candump_parse(line, &f, err, sizeof(err)), 0);
	assert_string_equal(err, "");
}

/* bad - a malformed line, with exactly this reason */
static void bad(const char *line, const char *msg)
{
	struct candump_frame f;
	char err[256] = "";
	int ret;

	ret = candump_parse(line, &f, err, sizeof(err));
	if (ret != -1 || strcmp(err, msg))
		print_error("'%s': %d '%s'\n", line, ret, err);
	assert_int_equal(ret, -1);
	assert_string_equal(err, msg);
}

/* data_is - the frame's payload */
static void data_is(const struct candump_frame *f, const char *hex)
{
	size_t i, n = strlen(hex) / 2;

	assert_int_equal(f->len, n);
	for (i = 0; i < n; i++) {
		unsigned int b;

		assert_int_equal(sscanf(hex + 2 * i, "%2x", &b), 1);
		assert_int_equal(f->data[i], b);
	}
	for (; i < sizeof(f->data); i++)
		assert_int_equal(f->data[i], 0);
}

static void test_candump_sff(void **state)
{
	struct candump_frame f;

	f = good("(1436509052.249713) vcan0 123#1122334455667788");
	assert_int_equal(f.ts_ns, 1436509052249713000ULL);
	assert_string_equal(f.iface, "vcan0");
	assert_int_equal(f.can_id, 0x123);
	assert_int_equal(f.kind, RTSUP_CAN_CC);
	assert_int_equal(f.fd_flags, 0);
	assert_int_equal(f.dir, -1);
	data_is(&f, "1122334455667788");

	f = good("(1436509052.250000) can1 7FF#");
	assert_int_equal(f.can_id, 0x7FF);
	assert_int_equal(f.len, 0);
	f = good("(1.000000) can0 000#00");
	assert_int_equal(f.can_id, 0);
	data_is(&f, "00");
	/* lower case hex, as parse_canframe takes it */
	f = good("(1.000000) can0 7ff#abcdef");
	assert_int_equal(f.can_id, 0x7FF);
	data_is(&f, "ABCDEF");
}

static void test_candump_eff(void **state)
{
	struct candump_frame f;

	f = good("(1436509052.251001) can0 12345678#DEADBE");
	assert_int_equal(f.can_id, 0x12345678 | EFF);
	assert_int_equal(f.kind, RTSUP_CAN_CC);
	data_is(&f, "DEADBE");
	/* 8 digits: 29-bit, however small */
	f = good("(1.0) can0 00000123#");
	assert_int_equal(f.can_id, 0x123 | EFF);
	assert_int_equal(f.len, 0);
	f = good("(1.0) can0 1FFFFFFF#01");
	assert_int_equal(f.can_id, 0x1FFFFFFF | EFF);
}

static void test_candump_rtr(void **state)
{
	struct candump_frame f;

	f = good("(1436509052.252002) can0 701#R");
	assert_int_equal(f.can_id, 0x701 | RTR);
	assert_int_equal(f.len, 0);
	assert_int_equal(f.kind, RTSUP_CAN_CC);
	f = good("(1436509052.253003) can0 602#R5");
	assert_int_equal(f.can_id, 0x602 | RTR);
	assert_int_equal(f.len, 5);
	data_is(&f, "0000000000");
	f = good("(1.0) can0 12345678#R0");
	assert_int_equal(f.can_id, 0x12345678 | EFF | RTR);
	assert_int_equal(f.len, 0);
	f = good("(1.0) can0 123#r8");
	assert_int_equal(f.can_id, 0x123 | RTR);
	assert_int_equal(f.len, 8);
	/* 8 and the raw DLC, as newer can-utils write it */
	f = good("(1.0) can0 123#R8_F");
	assert_int_equal(f.can_id, 0x123 | RTR);
	assert_int_equal(f.len, 8);
}

static void test_candump_fd(void **state)
{
	struct candump_frame f;
	char line[256];
	int i, o;

	f = good("(1436509052.254004) vcan10 181##50102030405060708090A0B0C");
	assert_string_equal(f.iface, "vcan10");
	assert_int_equal(f.can_id, 0x181);
	assert_int_equal(f.kind, RTSUP_CAN_FD);
	assert_int_equal(f.fd_flags, 5);
	data_is(&f, "0102030405060708090A0B0C");

	f = good("(1436509052.255005) vcan10 01ABCDEF##1");
	assert_int_equal(f.can_id, 0x01ABCDEF | EFF);
	assert_int_equal(f.kind, RTSUP_CAN_FD);
	assert_int_equal(f.fd_flags, 1);
	assert_int_equal(f.len, 0);

	f = good("(1.0) can0 123##F1122");
	assert_int_equal(f.fd_flags, 0xF);
	data_is(&f, "1122");

	/* every valid length */
	for (i = 0; i <= 64; i++) {
		struct candump_frame g;
		char err[64];
		int ret, k;

		o = snprintf(line, sizeof(line), "(1.0) can0 123##0");
		for (k = 0; k < i; k++)
			o += snprintf(line + o, sizeof(line) - o, "%02X", k);
		ret = candump_parse(line, &g, err, sizeof(err));
		if (i <= 8 || i == 12 || i == 16 || i == 20 || i == 24 || i == 32 || i == 48 ||
		    i == 64) {
			assert_int_equal(ret, 1);
			assert_int_equal(g.len, i);
			for (k = 0; k < i; k++)
				assert_int_equal(g.data[k], k);
		} else {
			char want[32];

			snprintf(want, sizeof(want), "bad CAN FD length %d", i);
			assert_int_equal(ret, -1);
			assert_string_equal(err, want);
		}
	}
}

static void test_candump_error_frame(void **state)
{
	struct candump_frame f;

	/* controller problem: rx error passive, error counters tx 127 rx 128 */
	f = good("(1436509052.256006) can0 20000004#0010000000007F80");
	assert_int_equal(f.can_id, RTSUP_CAN_ERR_FLAG | RTSUP_CAN_ERR_CRTL);
	assert_int_equal(f.can_id & EFF, 0);
	assert_int_equal(f.kind, RTSUP_CAN_CC);
	data_is(&f, "0010000000007F80");
	/* bus-off, and every class bit */
	f = good("(1.0) can0 20000040#0000000000000000");
	assert_int_equal(f.can_id, RTSUP_CAN_ERR_FLAG | RTSUP_CAN_ERR_BUSOFF);
	f = good("(1.0) can0 3FFFFFFF#");
	assert_int_equal(f.can_id, RTSUP_CAN_ERR_FLAG | RTSUP_CAN_EFF_MASK);
	assert_int_equal(f.len, 0);
}

/* '.' between the bytes, as candump writes without -l (sep = 1) */
static void test_candump_separators(void **state)
{
	struct candump_frame f;

	f = good("(1.0) can0 123#11.22.33.44.55.66.77.88");
	data_is(&f, "1122334455667788");
	f = good("(1.0) can0 123##1.11.22.33");
	assert_int_equal(f.fd_flags, 1);
	data_is(&f, "112233");
	f = good("(1.0) can0 123#.11");
	data_is(&f, "11");
	f = good("(1.0) can0 123#1122.33");
	data_is(&f, "112233");
}

/* candump -x: R received, T sent by this host */
static void test_candump_direction(void **state)
{
	struct candump_frame f;

	f = good("(1436509052.249713) can0 123#1122334455667788 R");
	assert_int_equal(f.dir, RTSUP_CAN_RX);
	data_is(&f, "1122334455667788");
	f = good("(1436509052.251001)   can0 12345678#DEADBE T");
	assert_int_equal(f.dir, RTSUP_CAN_TX);
	assert_int_equal(f.can_id, 0x12345678 | EFF);
	/* the direction after an RTR's R */
	f = good("(1436509052.252002)   can0 701#R R");
	assert_int_equal(f.can_id, 0x701 | RTR);
	assert_int_equal(f.dir, RTSUP_CAN_RX);
	f = good("(1.0) can0 701#R T\r\n");
	assert_int_equal(f.dir, RTSUP_CAN_TX);
	f = good("(1.0)\tcan0\t123#\tR \t\n");
	assert_int_equal(f.dir, RTSUP_CAN_RX);
}

/* blanks between fields and at the line's end */
static void test_candump_whitespace(void **state)
{
	struct candump_frame f;

	f = good("(1.5) can0 123#11\n");
	assert_int_equal(f.ts_ns, 1500000000);
	data_is(&f, "11");
	f = good("(1.5) can0 123#11\r\n");
	data_is(&f, "11");
	f = good("(1.5) can0 123#11   \t \r\n");
	data_is(&f, "11");
	/* candump pads names to the longest interface seen so far */
	f = good("(1436509053.000006)   can0 080#1081000000000000");
	assert_string_equal(f.iface, "can0");
	assert_int_equal(f.can_id, 0x080);
	f = good("  (1.5)  can0  123#11");
	assert_string_equal(f.iface, "can0");
	f = good("(1.5) can0 123#\n");
	assert_int_equal(f.len, 0);
	f = good("(1.5) can0 701#R\r\n");
	assert_int_equal(f.can_id, 0x701 | RTR);
	/* the longest interface name */
	f = good("(1.5) abcdefghijklmno 123#");
	assert_string_equal(f.iface, "abcdefghijklmno");
}

static void test_candump_skip(void **state)
{
	skipped("");
	skipped("\n");
	skipped("\r\n");
	skipped("   \t  \r\n");
	skipped("# a comment");
	skipped("#(1.0) can0 123#11\n");
	skipped("   # indented comment\n");
	/* candump -d -l writes its socket's drops into the log */
	skipped("DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 5)\n");
}

/* the timestamp, to the nanosecond, without floating point */
static void test_candump_timestamp(void **state)
{
	struct candump_frame f;

	f = good("(0.000001) can0 123#");
	assert_int_equal(f.ts_ns, 1000);
	/* candump -l -t z: relative to the first frame */
	f = good("(000.000000) can0 123#");
	assert_int_equal(f.ts_ns, 0);
	f = good("(1436509052.999999) can0 123#");
	assert_int_equal(f.ts_ns, 1436509052999999000ULL);
	f = good("(1.123456789) can0 123#");
	assert_int_equal(f.ts_ns, 1123456789);
	f = good("(1.5) can0 123#");
	assert_int_equal(f.ts_ns, 1500000000);
	f = good("(0000000001.000002) can0 123#");
	assert_int_equal(f.ts_ns, 1000002000);
	/* the largest time a __u64 of ns holds */
	f = good("(18446744073.709551615) can0 123#");
	assert_int_equal(f.ts_ns, 18446744073709551615ULL);
	bad("(18446744073.709551616) can0 123#", "timestamp out of range");
	bad("(18446744074.000000) can0 123#", "timestamp out of range");
	bad("(99999999999999999999999999.000000) can0 123#", "timestamp out of range");
}

static void test_candump_bad_timestamp(void **state)
{
	const char *want = "bad timestamp";

	bad("(1436509052) can0 123#", want);
	bad("(.5) can0 123#", want);
	bad("(1.) can0 123#", want);
	bad("(1.1234567890) can0 123#", want);
	bad("(1.5 can0 123#", want);
	bad("(1.5", want);
	bad("(", want);
	bad("(1.5)can0 123#", want);
	bad("(1a.5) can0 123#", want);
	bad("(-1.5) can0 123#", want);
	bad("(1.5x) can0 123#", want);
	bad("(1,5) can0 123#", want);
	bad("can0 123#11", "no timestamp (want '(SECONDS.MICROS) IFACE FRAME', "
	    "as candump -l writes)");
	bad(" (1436509052.249713)  can0  123   [8]  11 22 33 44 55 66 77 88",
	    "bad frame '123' (no '#')");
}

static void test_candump_bad_fields(void **state)
{
	bad("(1.0)", "no interface");
	bad("(1.0)   \r\n", "no interface");
	bad("(1.0) can0", "no frame");
	bad("(1.0) can0 \n", "no frame");
	bad("(1.0) abcdefghijklmnop 123#", "interface name 'abcdefghijklmnop' too long "
	    "(at most 15 characters)");
	bad("(1.0) can0 123#11 RX", "bad direction 'RX' (want R or T)");
	bad("(1.0) can0 123#11 r", "bad direction 'r' (want R or T)");
	bad("(1.0) can0 123#11 X", "bad direction 'X' (want R or T)");
	bad("(1.0) can0 123#11 R R", "unexpected 'R' after the direction");
	bad("(1.0) can0 123#11 R  extra\n", "unexpected 'extra' after the direction");
}

static void test_candump_bad_identifier(void **state)
{
	bad("(1.0) can0 123", "bad frame '123' (no '#')");
	bad("(1.0) can0 12X#11", "bad identifier '12X'");
	bad("(1.0) can0 12#11", "bad identifier '12'");
	bad("(1.0) can0 1234#11", "bad identifier '1234'");
	bad("(1.0) can0 123456789#11", "bad identifier '123456789'");
	bad("(1.0) can0 #11", "bad identifier ''");
	bad("(1.0) can0 1234567G#11", "bad identifier '1234567G'");
	bad("(1.0) can0 800#", "identifier '800' out of range (11-bit: 000..7FF)");
	bad("(1.0) can0 FFF#", "identifier 'FFF' out of range (11-bit: 000..7FF)");
	/* flags are not written in the identifier: above 0x3FFFFFFF is wrong */
	bad("(1.0) can0 80000123#",
	    "identifier '80000123' out of range (29-bit: 00000000..1FFFFFFF)");
	bad("(1.0) can0 40000123#",
	    "identifier '40000123' out of range (29-bit: 00000000..1FFFFFFF)");
	bad("(1.0) can0 E0000000#",
	    "identifier 'E0000000' out of range (29-bit: 00000000..1FFFFFFF)");
	/* unprintable bytes are shown escaped */
	bad("(1.0) can0 1\x01" "3#", "bad identifier '1\\x013'");
}

static void test_candump_bad_data(void **state)
{
	bad("(1.0) can0 123#1", "odd number of data digits");
	bad("(1.0) can0 123#112", "odd number of data digits");
	bad("(1.0) can0 123#1.22", "odd number of data digits");
	bad("(1.0) can0 123##01", "odd number of data digits");
	bad("(1.0) can0 123#GG", "bad data digit 'G'");
	bad("(1.0) can0 123#1G", "bad data digit 'G'");
	bad("(1.0) can0 123#11#22", "bad data digit '#'");
	bad("(1.0) can0 123#11..22", "misplaced '.' in data");
	bad("(1.0) can0 123#11.", "misplaced '.' in data");
	bad("(1.0) can0 123#.", "misplaced '.' in data");
	bad("(1.0) can0 123#1122334455667788AA", "data longer than 8 bytes");
	bad("(1.0) can0 12345678#112233445566778899", "data longer than 8 bytes");
	bad("(1.0) can0 20000004#001000000000000000", "data longer than 8 bytes");
	bad("(1.0) can0 123##0112233445566778899", "bad CAN FD length 9");
	bad("(1.0) can0 123##011223344556677889900", "bad CAN FD length 10");
	bad("(1.0) can0 123##0"
	    "00112233445566778899AABBCCDDEEFF00112233445566778899AABBCCDDEEFF"
	    "00112233445566778899AABBCCDDEEFF00112233445566778899AABBCCDDEEFF"
	    "00", "data longer than 64 bytes");
	bad("(1.0) can0 123##", "missing CAN FD flags after '##'");
	bad("(1.0) can0 123##X11", "bad CAN FD flags 'X'");
	bad("(1.0) can0 123##R", "bad CAN FD flags 'R'");
	bad("(1.0) can0 123##0_9", "bad data digit '_'");
	bad("(1.0) can0 20000004##0", "error frame as CAN FD");
}

static void test_candump_bad_rtr(void **state)
{
	bad("(1.0) can0 123#R9", "bad RTR length 'R9' (want R, or R0..R8)");
	bad("(1.0) can0 123#RX", "bad RTR length 'RX' (want R, or R0..R8)");
	bad("(1.0) can0 123#R11", "bad RTR length 'R11' (want R, or R0..R8)");
	bad("(1.0) can0 123#R5_9", "bad raw DLC '_9' (want _9.._F after 8 data bytes)");
	bad("(1.0) can0 20000004#R", "error frame with RTR");
}

/* the raw DLC 9..F of an 8-byte classical frame (CAN_CTRLMODE_CC_LEN8_DLC) */
static void test_candump_raw_dlc(void **state)
{
	struct candump_frame f;

	f = good("(1.0) can0 123#1122334455667788_9");
	data_is(&f, "1122334455667788");
	f = good("(1.0) can0 12345678#1122334455667788_F T");
	data_is(&f, "1122334455667788");
	assert_int_equal(f.dir, RTSUP_CAN_TX);
	bad("(1.0) can0 123#11_9", "bad raw DLC '_9' (want _9.._F after 8 data bytes)");
	bad("(1.0) can0 123#1122334455667788_8",
	    "bad raw DLC '_8' (want _9.._F after 8 data bytes)");
	bad("(1.0) can0 123#1122334455667788_", "bad raw DLC '_' (want _9.._F after 8 data bytes)");
	bad("(1.0) can0 123#1122334455667788_9A",
	    "bad raw DLC '_9A' (want _9.._F after 8 data bytes)");
	bad("(1.0) can0 123#1122334455667788._9", "misplaced '.' in data");
}

/* CAN XL, as lib.c writes it: VCID and priority, flags:SDT:AF, data */
static void test_candump_xl(void **state)
{
	struct candump_frame f;
	char *line;
	int i, o;

	f = good("(1.0) xl0 00123#80:00:11223344#AABBCC");
	assert_string_equal(f.iface, "xl0");
	assert_int_equal(f.kind, RTSUP_CAN_XL);
	assert_int_equal(f.can_id, 0x123);
	data_is(&f, "AABBCC");
	f = good("(1.0) xl0 AB7FF#81:03:DEADBEEF#00112233.44556677 T");
	assert_int_equal(f.can_id, 0x7FF);
	data_is(&f, "0011223344556677");
	assert_int_equal(f.dir, RTSUP_CAN_TX);

	/* 2048 bytes: len says so, the first 64 are kept */
	line = malloc(64 + 2 * 2049);
	assert_non_null(line);
	o = sprintf(line, "(1.0) xl0 00100#80:00:00000000#");
	for (i = 0; i < 2048; i++)
		o += sprintf(line + o, "%02X", i & 0xff);
	f = good(line);
	assert_int_equal(f.len, 2048);
	for (i = 0; i < 64; i++)
		assert_int_equal(f.data[i], i);
	sprintf(line + o, "FF");
	bad(line, "data longer than 2048 bytes");
	free(line);

	bad("(1.0) xl0 00800#80:00:11223344#AA", "CAN XL priority '800' out of range "
	    "(want 000..7FF)");
	bad("(1.0) xl0 00123#80:00:11223344#", "bad CAN XL length 0");
	bad("(1.0) xl0 00123#80-00:11223344#AA", "bad CAN XL header '80-00:11223344#' "
	    "(want FLAGS:SDT:AF#, e.g. 80:00:00000000#)");
	bad("(1.0) xl0 00123#80:00:1122334#AA", "bad CAN XL header '80:00:1122334#A' "
	    "(want FLAGS:SDT:AF#, e.g. 80:00:00000000#)");
	bad("(1.0) xl0 00123#80:00", "bad CAN XL header '80:00' "
	    "(want FLAGS:SDT:AF#, e.g. 80:00:00000000#)");
	bad("(1.0) xl0 00123#8G:00:11223344#AA", "bad CAN XL header '8G:00:11223344#' "
	    "(want FLAGS:SDT:AF#, e.g. 80:00:00000000#)");
	bad("(1.0) xl0 0012X#80:00:11223344#AA", "bad identifier '0012X'");
}

/* no err buffer: still -1, nothing written */
static void test_candump_no_err_buffer(void **state)
{
	struct candump_frame f;
	char err[4] = "abc";

	assert_int_equal(candump_parse("(1.0) can0 12X#", &f, NULL, 0), -1);
	assert_int_equal(candump_parse("(1.0) can0 12X#", &f, err, 0), -1);
	assert_string_equal(err, "abc");
	/* a short buffer gets a cut message */
	assert_int_equal(candump_parse("(1.0) can0 12X#", &f, err, sizeof(err)), -1);
	assert_string_equal(err, "bad");
}

/*
 * Real output: can-utils 2020.11.0 `candump -l -x any` (and -L without -x),
 * on this host with its frames fed through an LD_PRELOAD stand-in for the
 * CAN socket (the kernel here has no CAN): copied byte for byte from the
 * log file. The interface names are padded to the longest one seen.
 */
static const char real_log[] =
	"(1436509052.249713) can0 123#1122334455667788 R\n"
	"(1436509052.250000) vcan10 7FF# R\n"
	"(1436509052.251001)   can0 12345678#DEADBE T\n"
	"(1436509052.252002)   can0 701#R R\n"
	"(1436509052.253003)   can0 602#R5 R\n"
	"(1436509052.254004) vcan10 181##50102030405060708090A0B0C R\n"
	"(1436509052.255005) vcan10 01ABCDEF##1 T\n"
	"(1436509052.256006)   can0 20000004#0010000000007F80 R\n"
	"(1436509053.000006)   can0 080#1081000000000000 R\n"
	"(1436509053.999999) vcan10 100##4AA0000000000000000000000000000000000000"
	"000000000000000000000000000000000000000000000000000000000000000000000000"
	"00000000000000000 R\n"
	/* candump -L, without -x */
	"(1436509052.249713) can0 123#1122334455667788\n"
	"(1436509052.250000) vcan10 7FF#\n"
	"(1436509052.251001)   can0 12345678#DEADBE\n";

static void test_candump_real_log(void **state)
{
	static const struct {
		__u64 ts;
		const char *iface;
		__u32 id, len, kind;
		int dir;
	} want[] = {
		{ 1436509052249713000ULL, "can0", 0x123, 8, RTSUP_CAN_CC, RTSUP_CAN_RX },
		{ 1436509052250000000ULL, "vcan10", 0x7FF, 0, RTSUP_CAN_CC, RTSUP_CAN_RX },
		{ 1436509052251001000ULL, "can0", 0x12345678 | EFF, 3, RTSUP_CAN_CC,
		  RTSUP_CAN_TX },
		{ 1436509052252002000ULL, "can0", 0x701 | RTR, 0, RTSUP_CAN_CC, RTSUP_CAN_RX },
		{ 1436509052253003000ULL, "can0", 0x602 | RTR, 5, RTSUP_CAN_CC, RTSUP_CAN_RX },
		{ 1436509052254004000ULL, "vcan10", 0x181, 12, RTSUP_CAN_FD, RTSUP_CAN_RX },
		{ 1436509052255005000ULL, "vcan10", 0x01ABCDEF | EFF, 0, RTSUP_CAN_FD,
		  RTSUP_CAN_TX },
		{ 1436509052256006000ULL, "can0", 0x20000004, 8, RTSUP_CAN_CC, RTSUP_CAN_RX },
		{ 1436509053000006000ULL, "can0", 0x080, 8, RTSUP_CAN_CC, RTSUP_CAN_RX },
		{ 1436509053999999000ULL, "vcan10", 0x100, 64, RTSUP_CAN_FD, RTSUP_CAN_RX },
		{ 1436509052249713000ULL, "can0", 0x123, 8, RTSUP_CAN_CC, -1 },
		{ 1436509052250000000ULL, "vcan10", 0x7FF, 0, RTSUP_CAN_CC, -1 },
		{ 1436509052251001000ULL, "can0", 0x12345678 | EFF, 3, RTSUP_CAN_CC, -1 },
	};
	char line[512], err[128];
	const char *p = real_log, *nl;
	size_t n = 0;

	for (; (nl = strchr(p, '\n')); p = nl + 1, n++) {
		struct candump_frame f;

		assert_true(n < sizeof(want) / sizeof(want[0]));
		assert_true((size_t)(nl - p + 1) < sizeof(line));
		memcpy(line, p, nl - p + 1);
		line[nl - p + 1] = '\0';
		if (candump_parse(line, &f, err, sizeof(err)) != 1)
			print_error("line %zu: %s\n", n + 1, err);
		assert_int_equal(candump_parse(line, &f, err, sizeof(err)), 1);
		assert_int_equal(f.ts_ns, want[n].ts);
		assert_string_equal(f.iface, want[n].iface);
		assert_int_equal(f.can_id, want[n].id);
		assert_int_equal(f.len, want[n].len);
		assert_int_equal(f.kind, want[n].kind);
		assert_int_equal(f.dir, want[n].dir);
	}
	assert_int_equal(n, sizeof(want) / sizeof(want[0]));
}

/* xorshift64: a fixed sequence, the same on every run */
static __u64 rnd(__u64 *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

/* check_any - whatever the line, a sane answer (valgrind/ASan see the reads) */
static void check_any(const char *line)
{
	struct candump_frame f;
	char err[96];
	int ret;

	memset(err, 'x', sizeof(err));
	ret = candump_parse(line, &f, err, sizeof(err));
	assert_true(ret >= -1 && ret <= 1);
	assert_non_null(memchr(err, '\0', sizeof(err)));
	if (ret == -1)
		assert_true(err[0] != '\0');
	if (ret == 1) {
		assert_non_null(memchr(f.iface, '\0', sizeof(f.iface)));
		assert_true(f.iface[0] != '\0');
		assert_true(f.kind <= RTSUP_CAN_XL);
		assert_true(f.len <= (f.kind == RTSUP_CAN_XL ? 2048 : f.kind ? 64 : 8));
		assert_true(f.dir >= -1 && f.dir <= RTSUP_CAN_TX);
	}
}

/*
 * Every prefix of every real line, each in a buffer of exactly its size;
 * then random bytes, and real lines with random bytes changed.
 */
static void test_candump_fuzz(void **state)
{
	static const char alphabet[] = "0123456789ABCDEFabcdefRrTx#._:() \t\r\n-";
	const char *p = real_log, *nl;
	__u64 seed = 0x9e3779b97f4a7c15ULL;
	char lines[16][256];
	int nlines = 0, i, k;

	for (; (nl = strchr(p, '\n')) && nlines < 16; p = nl + 1, nlines++) {
		size_t n = nl - p, j;

		memcpy(lines[nlines], p, n);
		lines[nlines][n] = '\0';
		for (j = 0; j <= n; j++) {
			char *b = malloc(j + 1);

			assert_non_null(b);
			memcpy(b, p, j);
			b[j] = '\0';
			check_any(b);
			free(b);
		}
	}
	for (i = 0; i < 20000; i++) {
		size_t n = rnd(&seed) % 80, j;
		char *b = malloc(n + 1);

		assert_non_null(b);
		if (i & 1) {
			/* a real line with a few bytes changed, cut somewhere */
			const char *src = lines[rnd(&seed) % nlines];
			size_t len = strlen(src);

			n = n < len ? n : len;
			memcpy(b, src, n);
			for (k = rnd(&seed) % 4; k >= 0 && n; k--)
				b[rnd(&seed) % n] = i & 2 ? alphabet[rnd(&seed) % (sizeof(alphabet) - 1)]
							  : (char)(rnd(&seed) % 255 + 1);
		} else {
			for (j = 0; j < n; j++)
				b[j] = i & 2 ? alphabet[rnd(&seed) % (sizeof(alphabet) - 1)]
					     : (char)(rnd(&seed) % 255 + 1);
		}
		b[n] = '\0';
		check_any(b);
		free(b);
	}
}

#define T(name) cmocka_unit_test(test_candump_##name)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(sff),
		T(eff),
		T(rtr),
		T(fd),
		T(error_frame),
		T(separators),
		T(direction),
		T(whitespace),
		T(skip),
		T(timestamp),
		T(bad_timestamp),
		T(bad_fields),
		T(bad_identifier),
		T(bad_data),
		T(bad_rtr),
		T(raw_dlc),
		T(xl),
		T(no_err_buffer),
		T(real_log),
		T(fuzz),
	};

	return cmocka_run_group_tests_name("candump", tests, NULL, NULL);
}
