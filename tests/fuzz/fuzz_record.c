// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * fuzz_record.c - the recorded trace reader (user/sinks/record.c) through
 * `rtsup-trace replay` (user/offline/replay.c): header, records, the model, the
 * checks, the table or JSON output and a Perfetto trace. The fuzz build
 * takes any record checksum (REC_FUZZING in record.c).
 */
#include <string.h>
#include "config/config.h"
#include "options.h"
#include "offline/replay.h"
#include "judge/supervise.h"
#include "fuzz.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	fuzz_quiet();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct supervisor s;
	struct options o;
	struct config c;

	memset(&o, 0, sizeof(o));
	o.interval = 1;
	o.ewma_w = 102;
	o.max_threads = RTSUP_DEFAULT_THREADS;
	o.color = 0;
	o.fail_on = LEVEL_WARN;
	o.check = true;
	/* the table and the JSON output both, by the input's length */
	o.json = size & 1;
	o.perfetto_path = "/dev/null";
	o.replay_path = fuzz_file(data, size);
	config_defaults(&c);
	supervise_init(&s, &c);
	s.json = o.json;
	replay_run(&o, &s);
	supervise_free(&s);
	return 0;
}
