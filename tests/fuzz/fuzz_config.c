// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * fuzz_config.c - the YAML configuration (user/config/config.c): config_load as
 * --config and --check-config do (then config_print), lookups of the loaded
 * rules, and a SIGHUP reload over a running supervisor's configuration.
 */
#include <string.h>
#include "config/config.h"
#include "judge/supervise.h"
#include "fuzz.h"

static FILE *devnull;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	devnull = fopen("/dev/null", "w");
	if (!devnull)
		abort();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct supervisor s;
	struct config base, c;
	struct rule eff;
	char err[512];

	if (config_load(fuzz_file(data, size), &c, err, sizeof(err))) {
		/* one line, terminated: what rtsup-trace prints */
		if (!memchr(err, '\0', sizeof(err)) || strchr(err, '\n'))
			abort();
		return 0;
	}
	config_print(&c, devnull);
	config_match(&c, "ctrl", "ctrl-loop", "/robot.slice/ctrl.service", &eff);
	config_match(&c, "", "", "", &eff);
	config_can_node(&c, "can0", 0x181, 0);
	config_can_node(&c, "vcan1", 0x18ff50e5 | 0x80000000U, 1);
	/* SIGHUP: the new rules replace a running supervisor's */
	config_defaults(&base);
	supervise_init(&s, &base);
	supervise_reload(&s, &c);
	supervise_free(&s);
	return 0;
}
