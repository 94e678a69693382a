// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * where_lib - libwhere.so for where_loop_lib (test_where.py): the unsafe
 * calls are made inside a shared library of ours, called from the program.
 */
#include <stddef.h>
#include <sys/mman.h>

/* lib_map, lib_unmap - a page, mapped and unmapped here */
__attribute__((noinline)) void *lib_map(size_t len)
{
	void *p = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);	/* LIB_MMAP */

	/* the result used after the call: no tail call, this frame stays */
	return p == MAP_FAILED ? NULL : p;
}

__attribute__((noinline)) int lib_unmap(void *p, size_t len)
{
	int r = munmap(p, len);	/* LIB_MUNMAP */

	return r ? -1 : 0;
}
