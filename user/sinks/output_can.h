/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* output_can.h - the CAN part of the table and of the JSON objects */
#ifndef RTSUP_OUTPUT_CAN_H
#define RTSUP_OUTPUT_CAN_H

#include <stdbool.h>
#include <jansson.h>
#include "model/canmodel.h"
#include "config/config.h"

/* can_table - interfaces, then identifiers and nodes; window or totals */
void can_table(const struct can_model *m, const struct config *cfg, __u64 now,
	       double interval_s, bool total);
/* can_json - the same as a JSON object */
json_t *can_json(const struct can_model *m, const struct config *cfg, __u64 now,
		 double interval_s, bool total);

#endif
