// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * abi32_loop - a 32-bit (ia32) periodic loop: N cycles of 2 ms to absolute
 * releases (glibc's 32-bit clock_nanosleep is clock_nanosleep_time64), each
 * writing a byte to /dev/null. Its syscall numbers are i386's: on x86_64
 * write (4) is stat's number and close (6) lstat's, so a tracer that took
 * them for its own would see RT-unsafe file calls. Prints its own counts
 * as JSON: {"tid", "cycles", "writes"}.
 *
 *   abi32_loop N
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#include <sys/syscall.h>

int main(int argc, char **argv)
{
	long n = argc > 1 ? atol(argv[1]) : 500, i, writes = 0;
	int fd = open("/dev/null", O_WRONLY);
	struct timespec t;

	if (fd < 0)
		return 1;
	clock_gettime(CLOCK_MONOTONIC, &t);
	for (i = 0; i < n; i++) {
		t.tv_nsec += 2000000;
		if (t.tv_nsec >= 1000000000) {
			t.tv_nsec -= 1000000000;
			t.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, NULL);
		writes += write(fd, "x", 1) == 1;
	}
	printf("{\"tid\": %ld, \"cycles\": %ld, \"writes\": %ld}\n", (long)syscall(SYS_gettid),
	       n, writes);
	return 0;
}
