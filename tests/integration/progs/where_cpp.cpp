// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * where_cpp - the C++ case of test_where.py: a member function of a class
 * in a namespace allocates inside the cycle (operator new of a big block:
 * glibc's malloc maps it, and unmaps it at delete). Built -O2 -g without
 * frame pointers.
 *
 * where_cpp CYCLES PERIOD_US: prints {"tid", "news"} on stderr at the end.
 */
#include <malloc.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

namespace ctrl {

class Loop {
public:
	explicit Loop(long cycles, long period_ns) : cycles_(cycles), period_ns_(period_ns) {}
	__attribute__((noinline)) void run();
	long news = 0;

private:
	__attribute__((noinline)) void update(long i);
	long cycles_, period_ns_;
	volatile char sink_ = 0;
};

/* update - a block big enough for malloc to mmap it, every other cycle */
void Loop::update(long i)
{
	if (i % 2)
		return;
	char *p = new char[1 << 20];	/* CPP_NEW */
	/* p escapes: the compiler may not elide the allocation */
	__asm__ volatile("" : : "r"(p) : "memory");
	news++;
	delete[] p;
	news += 0;
}

void Loop::run()
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	for (long i = 0; i < cycles_; i++) {
		t.tv_nsec += period_ns_;
		while (t.tv_nsec >= 1000000000L) {
			t.tv_nsec -= 1000000000L;
			t.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr);
		update(i);	/* CPP_CALL */
	}
}

} // namespace ctrl

static pid_t ctrl_tid;

static void *ctrl_main(void *arg)
{
	ctrl_tid = gettid();
	static_cast<ctrl::Loop *>(arg)->run();
	return nullptr;
}

int main(int argc, char **argv)
{
	pthread_t th;

	if (argc != 3)
		return 1;
	/* a fixed threshold: glibc's own would rise after the first free */
	mallopt(M_MMAP_THRESHOLD, 128 * 1024);
	ctrl::Loop loop(atol(argv[1]), atol(argv[2]) * 1000);
	pthread_create(&th, nullptr, ctrl_main, &loop);
	pthread_join(th, nullptr);
	fprintf(stderr, "{\"tid\": %d, \"news\": %ld}\n", (int)ctrl_tid, loop.news);
	return 0;
}
