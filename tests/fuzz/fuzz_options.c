// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * fuzz_options.c - the command line (user/cli.c): the input is argv, one
 * argument per line, after "rtsup-trace"; every option value parser
 * (durations, ids, sizes, syscall lists, names) and argp's own errors,
 * which with ARGP_NO_EXIT return instead of exiting. Then the value
 * parser parse_duration on the whole input. argp's hidden --HANG is left out.
 */
#include <argp.h>
#include <string.h>
#include "options.h"
#include "fuzz.h"

#define MAX_ARGS 32

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	fuzz_quiet();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static char buf[4096];
	char *argv[MAX_ARGS + 1], *p;
	struct options o;
	int argc = 0;
	size_t n = size < sizeof(buf) - 1 ? size : sizeof(buf) - 1;

	memcpy(buf, data, n);
	buf[n] = '\0';
	parse_duration(buf);
	argv[argc++] = "rtsup-trace";
	for (p = buf; p && argc < MAX_ARGS; ) {
		char *nl = strchr(p, '\n');

		if (nl)
			*nl = '\0';
		/* glibc argp's own hidden --HANG[=SECS] sleeps (a debugging aid): not ours */
		if (!strncmp(p, "--H", 3))
			return 0;
		argv[argc++] = p;
		p = nl ? nl + 1 : NULL;
	}
	argv[argc] = NULL;
	options_parse_flags(argc, argv, &o, ARGP_NO_EXIT);
	return 0;
}
