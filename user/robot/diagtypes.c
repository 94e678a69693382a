// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * diagtypes.c - the topic descriptors idlc generates from diagnostics.idl
 * (ops, keys, XTypes type information): data only, no call into libddsc, so
 * the binary does not link it. Built here so that every build of user/
 * (fuzz and sanitizer ones too) has them.
 */
#include "idl/diagnostics.c"
