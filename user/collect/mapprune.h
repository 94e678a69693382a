/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* mapprune.h - delete the entries of a BPF hash map that are gone */
#ifndef RTSUP_MAPPRUNE_H
#define RTSUP_MAPPRUNE_H

#include <stdbool.h>
#include <stddef.h>

/* map_batch_unsupported - errno of a first batch call: the kernel has none (< 5.6) */
bool map_batch_unsupported(int err);

/* is the entry (key, value) gone? */
typedef bool (*prune_gone)(const void *key, const void *value, void *ctx);

/*
 * map_prune - delete every entry of hash map fd (keys of ksz bytes, values
 * of vsz) that gone() names: the whole map read first, the deletes after
 * (mapprune.c says why). 0, or a negative errno: nothing was deleted, the
 * next call tries again.
 */
int map_prune(int fd, size_t ksz, size_t vsz, prune_gone gone, void *ctx);

#endif
