# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
# cross.mk - settings of a cross build, included by the Makefile when ARCH
# is not the build host's: `make ARCH=arm64 [all|unit]` (docs/arm64.md).
#
# The compiler is clang with the target's triplet, linking with Debian's
# cross binutils and the target's libraries installed through multiarch
# (scripts/install-deps-arm64). Debian 12's gcc-aarch64-linux-gnu cannot be
# used here: it conflicts with gcc-multilib, which the x86 build needs.

# ARCH -> GNU triplet, qemu-user binary, gen-syscalls name, pinned vmlinux.h
TRIPLET_arm64  := aarch64-linux-gnu
QEMU_USER_arm64 := qemu-aarch64-static
SYSCALLS_arm64 := arm64

TRIPLET := $(TRIPLET_$(ARCH))
ifeq ($(TRIPLET),)
$(error ARCH=$(ARCH): no cross build for it (known: arm64))
endif

OUT := build-$(ARCH)
# an explicit CC=... (e.g. aarch64-linux-gnu-gcc on a machine without
# gcc-multilib) still wins: command-line variables override this
CC = $(CLANG) --target=$(TRIPLET)
# this host's BTF describes another kernel: the target's pinned copy only
VMLINUX_BTF :=
VMLINUX_PIN := bpf/vmlinux-$(ARCH).h.xz
# the target's syscall numbers, not the C library headers of the build host
SYSCALL_ARCH := $(SYSCALLS_$(ARCH))
UNIT_RUN := $(QEMU_USER_$(ARCH))
# gcc-multilib's 32-bit x86 program has no arm64 counterpart here
PROGS32 :=
# test_where.py runs on x86 only (its program makes its syscall in x86 asm;
# the page-fault stack hook is x86's exceptions:page_fault_user)
WHERE_PROGS :=
