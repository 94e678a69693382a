// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * fuzz_candump.c - candump log lines (user/offline/candump.c), then the whole log
 * through `rtsup-trace can-replay` (user/offline/canreplay.c): frame accounting,
 * interval boundaries, clock steps, the CAN checks and output.
 */
#include <string.h>
#include "offline/candump.h"
#include "offline/canreplay.h"
#include "config/config.h"
#include "options.h"
#include "judge/supervise.h"
#include "fuzz.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	fuzz_quiet();
	return 0;
}

/* lines - every line alone through candump_parse */
static void lines(const uint8_t *data, size_t size)
{
	struct candump_frame f;
	char line[1024], err[256];
	size_t i = 0, n;

	while (i < size) {
		for (n = 0; i + n < size && data[i + n] != '\n' && n < sizeof(line) - 1; n++)
			;
		memcpy(line, data + i, n);
		line[n] = '\0';
		if (candump_parse(line, &f, err, sizeof(err)) < 0 &&
		    (!memchr(err, '\0', sizeof(err)) || strchr(err, '\n')))
			abort();
		i += n + 1;
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct supervisor s;
	struct options o;
	struct config c;

	lines(data, size);
	memset(&o, 0, sizeof(o));
	o.interval = 1;
	o.ewma_w = 102;
	o.color = 0;
	o.fail_on = LEVEL_WARN;
	o.check = true;
	o.can = true;
	o.json = size & 1;
	o.can_replay_path = fuzz_file(data, size);
	config_defaults(&c);
	/* CANopen's SDO and heartbeat paths on every other input */
	c.can.canopen = size & 2;
	supervise_init(&s, &c);
	s.json = o.json;
	can_replay_run(&o, &s);
	supervise_free(&s);
	return 0;
}
