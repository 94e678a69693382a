# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
# rtsup - one Makefile: bpf/*.bpf.c -> .bpf.o -> skeleton -> build/rtsup-trace.
# Quiet by default; V=1 prints every command.

OUT      := build
CLANG    ?= clang
CC       ?= cc
BPFTOOL  ?= bpftool
# the apt-installed interpreter: its pytest and matplotlib come from install-deps
PYTHON   ?= /usr/bin/python3
ARCH     := $(shell uname -m | sed 's/x86_64/x86/;s/aarch64/arm64/;s/ppc64le/powerpc/;s/riscv64/riscv/;s/s390x/s390/')
VMLINUX_BTF ?= /sys/kernel/btf/vmlinux
PREFIX   ?= /usr/local
SYSCONFDIR ?= /etc
UNITDIR  ?= $(PREFIX)/lib/systemd/system

CFLAGS   ?= -O2 -g
WARN     := -Wall -Wextra -Wno-unused-parameter
INCLUDES := -Iinclude -I$(OUT) -I/usr/include/libnl3
USER_LIBS := -lbpf -lelf -lz -ljansson -lyaml -lnl-route-3 -lnl-3 -lsystemd -lpthread
CPPFLAGS += -D_GNU_SOURCE -MMD -MP

ifeq ($(V),1)
Q =
msg =
else
Q = @
msg = @printf '  %-8s %s\n' "$(1)" "$(2)";
endif

USER_SRCS := $(wildcard user/*.c)
USER_OBJS := $(patsubst user/%.c,$(OUT)/user/%.o,$(USER_SRCS))
UNIT_SRCS := $(wildcard tests/unit/test_*.c)
UNIT_BINS := $(patsubst tests/unit/%.c,$(OUT)/tests/%,$(UNIT_SRCS))

.PHONY: all clean test unit integration test-noisy deps demo bench format-check install soak
.DELETE_ON_ERROR:
# keep the BPF objects: the skeleton and the benchmark use them
.SECONDARY:

all: $(OUT)/rtsup-trace $(OUT)/rtsup-loadgen $(OUT)/rtsup-cansim $(OUT)/rtsup-noise \
     $(OUT)/progs/usleep_loop $(OUT)/progs/timerfd_loop $(OUT)/progs32/abi32_loop

$(OUT) $(OUT)/user $(OUT)/tests:
	$(Q)mkdir -p $@

# vmlinux.h from the build host's BTF; bpf/vmlinux.h is a pinned fallback.
$(OUT)/vmlinux.h: | $(OUT)
	$(call msg,GEN,$@)
	$(Q)if [ -r $(VMLINUX_BTF) ]; then \
		$(BPFTOOL) btf dump file $(VMLINUX_BTF) format c > $@; \
	else \
		xz -dc bpf/vmlinux.h.xz > $@; \
	fi

$(OUT)/%.bpf.o: bpf/%.bpf.c $(OUT)/vmlinux.h | $(OUT)
	$(call msg,BPF,$@)
	$(Q)$(CLANG) -g -O2 -target bpf -D__TARGET_ARCH_$(ARCH) -MMD -MP \
		$(INCLUDES) -Ibpf -c $< -o $@

# The floor for the benchmark: the same hooks with empty programs.
$(OUT)/rtsup_empty.bpf.o: bpf/rtsup.bpf.c $(OUT)/vmlinux.h | $(OUT)
	$(call msg,BPF,$@)
	$(Q)$(CLANG) -g -O2 -target bpf -D__TARGET_ARCH_$(ARCH) -DRTSUP_EMPTY -MMD -MP \
		$(INCLUDES) -Ibpf -c $< -o $@

$(OUT)/%.skel.h: $(OUT)/%.bpf.o
	$(call msg,GEN-SKEL,$@)
	$(Q)$(BPFTOOL) gen skeleton $< name $(subst -,_,$*)_bpf > $@

# Syscall names of the build architecture, from the C library's headers.
$(OUT)/syscall_table.h: scripts/gen-syscalls | $(OUT)
	$(call msg,GEN,$@)
	$(Q)CC="$(CC)" scripts/gen-syscalls > $@

# Each architecture's table, for the unit test that checks them.
$(OUT)/syscall_table_%.h: scripts/gen-syscalls | $(OUT)
	$(call msg,GEN,$@)
	$(Q)CC="$(CC)" scripts/gen-syscalls $* > $@

$(OUT)/tests/test_syscall_tables: $(OUT)/syscall_table_x86_64.h $(OUT)/syscall_table_i386.h \
	$(OUT)/syscall_table_arm64.h

$(USER_OBJS): $(OUT)/rtsup.skel.h $(OUT)/rtsup_empty.skel.h $(OUT)/syscall_table.h

$(OUT)/user/%.o: user/%.c | $(OUT)/user
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(INCLUDES) -c $< -o $@

$(OUT)/rtsup-trace: $(USER_OBJS)
	$(call msg,LINK,$@)
	$(Q)$(CC) $(CFLAGS) $^ $(USER_LIBS) -lm -o $@

$(OUT)/rtsup-loadgen: scripts/loadgen/loadgen.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $< -lpthread -ljansson -o $@

$(OUT)/rtsup-noise: scripts/noise/noise.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $< -lpthread -o $@

$(OUT)/rtsup-cansim: scripts/cansim/cansim.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $< -lpthread -ljansson -o $@

# Small real programs the integration tests trace (tests/integration/progs).
$(OUT)/progs/%: tests/integration/progs/%.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $< -o $@

# The same, built for the 32-bit ABI (gcc-multilib): other syscall numbers.
$(OUT)/progs32/%: tests/integration/progs/%.c
	@mkdir -p $(@D)
	$(call msg,CC-32,$@)
	$(Q)$(CC) -m32 $(CFLAGS) $(WARN) $< -o $@

# Unit tests: plain C from include/ and user/, no kernel, no root.
UNIT_DEPS_test_model  := user/model.c
UNIT_DEPS_test_eventlog := user/eventlog.c
UNIT_DEPS_test_histdraw := user/histdraw.c
UNIT_DEPS_test_progress := user/progress.c
UNIT_DEPS_test_syscalls := user/syscalls.c
UNIT_DEPS_test_config := user/config.c user/syscalls.c user/actionspec.c user/status.c
UNIT_LIBS_test_config := -lyaml
UNIT_DEPS_test_record := user/record.c user/jsonstr.c user/errline.c
UNIT_LIBS_test_record := -lz -ljansson
UNIT_DEPS_test_perfetto := user/perfetto.c user/jsonstr.c user/errline.c
UNIT_LIBS_test_perfetto := -ljansson
UNIT_DEPS_test_checks := user/checks.c user/model.c user/status.c
UNIT_DEPS_test_status := user/status.c
UNIT_DEPS_test_actionspec := user/actionspec.c user/status.c
UNIT_DEPS_test_actions := user/actions.c user/actionspec.c user/status.c user/config.c user/syscalls.c
UNIT_LIBS_test_actions := -ljansson -lyaml
UNIT_DEPS_test_targets := user/targets.c
UNIT_DEPS_test_pidns := user/pidns.c
UNIT_DEPS_test_candump := user/candump.c
UNIT_DEPS_test_prom := user/prom.c user/model.c user/status.c user/syscalls.c
UNIT_DEPS_test_service := user/service.c user/status.c
UNIT_LIBS_test_service := -lsystemd
UNIT_DEPS_test_promexp := user/promexp.c
UNIT_LIBS_test_promexp := -lpthread
UNIT_DEPS_test_canmodel := user/canmodel.c user/model.c user/status.c user/config.c user/syscalls.c user/actionspec.c
UNIT_LIBS_test_canmodel := -lyaml
.SECONDEXPANSION:
$(OUT)/tests/%: tests/unit/%.c $$(UNIT_DEPS_$$*) $(OUT)/syscall_table.h | $(OUT)/tests
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(INCLUDES) -Iuser $< $(UNIT_DEPS_$*) -lcmocka -lm $(UNIT_LIBS_$*) -o $@

# every binary runs even when one fails; make fails at the end
unit: $(UNIT_BINS)
	$(Q)fail=0; for t in $(UNIT_BINS); do $$t || fail=1; done; exit $$fail

integration: all
	$(Q)$(PYTHON) -m pytest -v -rs --durations=15 tests/integration

# The host integration tests with our own noise on every CPU (scripts/noise):
# a SCHED_FIFO 99 thread per CPU burns 3 ms every 30 ms (+-25 %).
test-noisy: all
	$(Q)RTSUP_TEST_NOISE="-b 3ms -e 30ms" $(PYTHON) -m pytest -v -rs tests/integration \
		--ignore=tests/integration/test_guest.py --ignore=tests/integration/test_can.py \
		--ignore=tests/integration/test_cansim.py \
		-k "not test_service_under_systemd_in_vm"

# What CI runs: every test, unit and integration.
test: unit integration

demo: all
	$(Q)scripts/demo

deps:
	$(Q)scripts/install-deps

# Overhead against the floor and peer tools; installs the peers first (not in make deps).
bench: all $(OUT)/rtsup_empty.bpf.o
	$(Q)scripts/install-bench-deps
	$(Q)scripts/bench

format-check:
	$(Q)clang-format --dry-run --Werror include/*.h user/*.c user/*.h bpf/*.c bpf/*.h

install: all
	install -D -m 0755 $(OUT)/rtsup-trace $(DESTDIR)$(PREFIX)/bin/rtsup-trace
	install -D -m 0755 $(OUT)/rtsup-loadgen $(DESTDIR)$(PREFIX)/bin/rtsup-loadgen
	install -D -m 0644 docs/rtsup-trace.8 $(DESTDIR)$(PREFIX)/share/man/man8/rtsup-trace.8
	@# the unit and its configuration (docs/robot.md); a site's /etc files are kept
	install -d $(DESTDIR)$(UNITDIR) $(DESTDIR)$(SYSCONFDIR)/rtsup
	sed 's|@BINDIR@|$(PREFIX)/bin|g' systemd/rtsup-trace.service.in > $(DESTDIR)$(UNITDIR)/rtsup-trace.service
	chmod 0644 $(DESTDIR)$(UNITDIR)/rtsup-trace.service
	test -e $(DESTDIR)$(SYSCONFDIR)/rtsup/rtsup.yaml || \
		install -m 0644 examples/rtsup-1khz.yaml $(DESTDIR)$(SYSCONFDIR)/rtsup/rtsup.yaml
	test -e $(DESTDIR)$(SYSCONFDIR)/rtsup/rtsup-trace.env || \
		install -m 0644 systemd/rtsup-trace.env $(DESTDIR)$(SYSCONFDIR)/rtsup/rtsup-trace.env
	sed 's|@BINDIR@|$(PREFIX)/bin|g' systemd/listen.conf > $(DESTDIR)$(SYSCONFDIR)/rtsup/listen.conf.example

# Weeks without a restart, in 10 minutes: thread churn under the tool (not in make test).
soak: all
	$(Q)scripts/soak

clean:
	$(Q)rm -rf $(OUT)

-include $(wildcard $(OUT)/*.d $(OUT)/user/*.d $(OUT)/tests/*.d)
