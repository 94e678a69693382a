# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
# rtsup - one Makefile: bpf/*.bpf.c -> .bpf.o -> skeleton -> build/rtsup-trace.
# Quiet by default; V=1 prints every command.

OUT      := build
CLANG    ?= clang
CC       ?= cc
BPFTOOL  ?= bpftool
IDLC     ?= idlc
# the apt-installed interpreter: its pytest and matplotlib come from install-deps
PYTHON   ?= /usr/bin/python3
HOST_ARCH := $(shell uname -m | sed 's/x86_64/x86/;s/aarch64/arm64/;s/ppc64le/powerpc/;s/riscv64/riscv/;s/s390x/s390/')
# the target: make ARCH=arm64 cross-builds into build-arm64/ (cross.mk)
ARCH     := $(HOST_ARCH)
HOSTCC   ?= cc
VMLINUX_BTF ?= /sys/kernel/btf/vmlinux
VMLINUX_PIN ?= bpf/vmlinux.h.xz
# gen-syscalls' argument for syscall_table.h: none, the C library's own
SYSCALL_ARCH ?=
# a command that runs the unit tests' binaries (qemu-user when cross-built)
UNIT_RUN ?=
# the 32-bit ABI test program (gcc-multilib): x86 only
PROGS32  := $(OUT)/progs32/abi32_loop
# test_where.py's programs: where_loop.c makes its own syscall in x86 asm
WHERE_PROGS := $(OUT)/progs/where_loop_fp $(OUT)/progs/where_loop_dwarf \
	$(OUT)/progs/where_loop_lib $(OUT)/progs/where_cpp $(OUT)/progs/where_nolibc \
	$(OUT)/progs/where_vdso $(OUT)/progs/where_vdso_fp

ifneq ($(ARCH),$(HOST_ARCH))
include cross.mk
endif
PREFIX   ?= /usr/local
SYSCONFDIR ?= /etc
UNITDIR  ?= $(PREFIX)/lib/systemd/system

CFLAGS   ?= -O2 -g
WARN     := -Wall -Wextra -Wno-unused-parameter
INCLUDES := -Iinclude -I$(OUT) -I/usr/include/libnl3
USER_INC := -Iuser
USER_LIBS := -lbpf -ldw -lelf -lstdc++ -lz -ljansson -lyaml -lnl-route-3 -lnl-3 -lsystemd -lpthread
CPPFLAGS += -D_GNU_SOURCE -MMD -MP

ifeq ($(V),1)
Q =
msg =
else
Q = @
msg = @printf '  %-8s %s\n' "$(1)" "$(2)";
endif

# user/ has one folder per pipeline stage (docs/design.md); #include "stage/x.h"
USER_SRCS := $(wildcard user/*.c user/*/*.c)
USER_OBJS := $(patsubst user/%.c,$(OUT)/user/%.o,$(USER_SRCS))
# tests/unit/ has the same folders; the binaries share one directory
UNIT_SRCS := $(wildcard tests/unit/*/test_*.c)
UNIT_BINS := $(patsubst %.c,$(OUT)/tests/%,$(notdir $(UNIT_SRCS)))

.PHONY: all clean test unit integration test-noisy deps demo bench format-check install soak \
	fuzz fuzz-build fuzz-regress sanitize sanitize-sinks ros2-venv deb deps-arm64 cross-arm64 \
	test-builds unit-bins
.DELETE_ON_ERROR:
# keep the BPF objects: the skeleton and the benchmark use them
.SECONDARY:

all: $(OUT)/rtsup-trace $(OUT)/rtsup-loadgen $(OUT)/rtsup-cansim $(OUT)/rtsup-noise \
     $(OUT)/progs/usleep_loop $(OUT)/progs/timerfd_loop $(PROGS32) $(WHERE_PROGS) \
     $(OUT)/progs/why_late \
     $(OUT)/progs/unsafe_flood $(OUT)/progs/thread_storm $(OUT)/progs/realtime_loop

$(OUT) $(OUT)/tests:
	$(Q)mkdir -p $@

# vmlinux.h from the build host's BTF; $(VMLINUX_PIN) is a pinned fallback
# (a cross build's only source: scripts/gen-vmlinux-h).
$(OUT)/vmlinux.h: | $(OUT)
	$(call msg,GEN,$@)
	$(Q)if [ -r "$(VMLINUX_BTF)" ]; then \
		$(BPFTOOL) btf dump file $(VMLINUX_BTF) format c > $@; \
	else \
		xz -dc $(VMLINUX_PIN) > $@; \
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

# Syscall names of the build architecture, from the C library's headers
# (a cross build: the target's, from gen-syscalls $(SYSCALL_ARCH)).
$(OUT)/syscall_table.h: scripts/gen-syscalls | $(OUT)
	$(call msg,GEN,$@)
	$(Q)CC="$(if $(SYSCALL_ARCH),$(HOSTCC),$(CC))" TABLE=syscall_table \
		scripts/gen-syscalls $(SYSCALL_ARCH) > $@

# Each architecture's table, for the unit test that checks them (the
# kernel's uapi headers of the build host: not a cross compiler's paths).
$(OUT)/syscall_table_%.h: scripts/gen-syscalls | $(OUT)
	$(call msg,GEN,$@)
	$(Q)CC="$(HOSTCC)" scripts/gen-syscalls $* > $@

$(OUT)/tests/test_syscall_tables: $(OUT)/syscall_table_x86_64.h $(OUT)/syscall_table_i386.h \
	$(OUT)/syscall_table_arm64.h

$(USER_OBJS): $(OUT)/rtsup.skel.h $(OUT)/rtsup_empty.skel.h $(OUT)/rtsup_tasks.skel.h \
	$(OUT)/syscall_table.h \
	$(OUT)/idl/diagnostics.h

# ROS 2's diagnostic types for Cyclone DDS (robot/ros2diag.c), from their IDL
$(OUT)/idl/diagnostics.c $(OUT)/idl/diagnostics.h &: user/robot/diagnostics.idl
	@mkdir -p $(@D)
	$(call msg,IDLC,$@)
	$(Q)$(IDLC) -o $(OUT)/idl $<

$(OUT)/user/%.o: user/%.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(INCLUDES) $(USER_INC) -c $< -o $@

$(OUT)/rtsup-trace: $(USER_OBJS)
	$(call msg,LINK,$@)
	$(Q)$(CC) $(CFLAGS) $(LDFLAGS) $^ $(USER_LIBS) -lm -o $@

$(OUT)/rtsup-loadgen: scripts/loadgen/loadgen.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(LDFLAGS) $< -lpthread -ljansson -o $@

$(OUT)/rtsup-noise: scripts/noise/noise.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $< -lpthread -o $@

# A recorded trace of many threads, made up, for the bench's replayed userspace
$(OUT)/rtsup-synth-trace: scripts/bench.d/synth-trace.c user/sinks/record.c user/sinks/jsonstr.c \
		user/sinks/errline.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(INCLUDES) $(USER_INC) $(LDFLAGS) $^ -ljansson -lz \
		-o $@

$(OUT)/rtsup-cansim: scripts/cansim/cansim.c | $(OUT)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(LDFLAGS) $< -lpthread -ljansson -o $@

# Small real programs the integration tests trace (tests/integration/progs).
$(OUT)/progs/%: tests/integration/progs/%.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $< -o $@

# test_where.py: the same loop with frame pointers as Fedora and Ubuntu 24.04
# build (its mmap a syscall of its own: a frameless libc wrapper would hide
# its caller from a frame-pointer walk), and -O2 -g without
$(OUT)/progs/where_loop_fp: tests/integration/progs/where_loop.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g -fno-omit-frame-pointer -mno-omit-leaf-frame-pointer \
		-DWHERE_RAW_SYSCALL $(WARN) $< -lpthread -o $@

$(OUT)/progs/where_loop_dwarf: tests/integration/progs/where_loop.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g -fomit-frame-pointer $(WARN) $< -lpthread -o $@

$(OUT)/progs/libwhere.so: tests/integration/progs/where_lib.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g -fPIC -shared $(WARN) $< -o $@

# the unsafe calls inside a shared library of ours, found next to the program
$(OUT)/progs/where_loop_lib: tests/integration/progs/where_loop.c $(OUT)/progs/libwhere.so
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g -DWHERE_LIB $(WARN) $< -L$(OUT)/progs -lwhere -Wl,-rpath,'$$ORIGIN' \
		-lpthread -o $@

# --stacks auto's fp case: no C library, frame pointers, static (x86 asm)
$(OUT)/progs/where_nolibc: tests/integration/progs/where_nolibc.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g -fno-omit-frame-pointer -mno-omit-leaf-frame-pointer -static -nostdlib \
		-ffreestanding -fno-stack-protector -fno-pie -no-pie $(WARN) $< -o $@

$(OUT)/progs/where_vdso: tests/integration/progs/where_vdso.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g $(WARN) $< -lpthread -o $@

# --stacks auto's DWARF case: the program keeps frame pointers, glibc does not
$(OUT)/progs/where_vdso_fp: tests/integration/progs/where_vdso.c
	@mkdir -p $(@D)
	$(call msg,CC,$@)
	$(Q)$(CC) -O2 -g -fno-omit-frame-pointer -mno-omit-leaf-frame-pointer $(WARN) $< \
		-lpthread -o $@

# the C++ case: a member function in a namespace, -O2 -g without frame pointers
$(OUT)/progs/where_cpp: tests/integration/progs/where_cpp.cpp
	@mkdir -p $(@D)
	$(call msg,CXX,$@)
	$(Q)$(CXX) -O2 -g $(WARN) $< -lpthread -o $@

# The same, built for the 32-bit ABI (gcc-multilib): other syscall numbers.
$(OUT)/progs32/%: tests/integration/progs/%.c
	@mkdir -p $(@D)
	$(call msg,CC-32,$@)
	$(Q)$(CC) -m32 $(CFLAGS) $(WARN) $< -o $@

# Unit tests: plain C from include/ and user/, no kernel, no root.
# the configuration module: user/config/ but actionspec.c (docs/design.md)
CONFIG_SRCS := user/config/config.c user/config/yamlwalk.c user/config/values.c \
	user/config/canconfig.c user/config/print.c user/config/stackopt.c
UNIT_DEPS_test_model  := user/model/model.c
UNIT_DEPS_test_eventlog := user/model/eventlog.c
UNIT_DEPS_test_causes := user/model/causes.c user/model/syscalls.c user/model/model.c
UNIT_DEPS_test_histdraw := user/sinks/histdraw.c
UNIT_DEPS_test_rowcut := user/sinks/rowcut.c
UNIT_DEPS_test_jsonw := user/sinks/jsonw.c user/sinks/jsonstr.c user/sinks/textbuf.c
UNIT_LIBS_test_jsonw := -ljansson
UNIT_DEPS_test_progress := user/sinks/progress.c
UNIT_DEPS_test_syscalls := user/model/syscalls.c
UNIT_DEPS_test_syshooks := user/model/syshooks.c user/model/syscalls.c
UNIT_DEPS_test_config := $(CONFIG_SRCS) user/model/syscalls.c user/config/actionspec.c user/judge/status.c
UNIT_LIBS_test_config := -lyaml
UNIT_DEPS_test_record := user/sinks/record.c user/sinks/jsonstr.c user/sinks/errline.c
UNIT_LIBS_test_record := -lz -ljansson
UNIT_DEPS_test_perfetto := user/sinks/perfetto.c user/sinks/jsonstr.c user/sinks/errline.c \
	user/model/causes.c user/model/syscalls.c user/model/model.c
UNIT_LIBS_test_perfetto := -ljansson
UNIT_DEPS_test_checks := user/judge/checks.c user/model/model.c user/judge/status.c
UNIT_DEPS_test_supervise := user/judge/supervise.c user/judge/checks.c user/model/model.c \
	user/model/canmodel.c user/judge/status.c $(CONFIG_SRCS) user/model/syscalls.c \
	user/config/actionspec.c
UNIT_LIBS_test_supervise := -lyaml
UNIT_DEPS_test_status := user/judge/status.c
UNIT_DEPS_test_health := user/judge/health.c
UNIT_DEPS_test_actionspec := user/config/actionspec.c user/judge/status.c
UNIT_DEPS_test_actions := user/robot/actions.c user/config/actionspec.c user/judge/status.c $(CONFIG_SRCS) user/model/syscalls.c
UNIT_LIBS_test_actions := -ljansson -lyaml
UNIT_DEPS_test_targets := user/collect/targets.c
UNIT_DEPS_test_pidns := user/collect/pidns.c
UNIT_DEPS_test_selfsched := user/collect/selfsched.c user/collect/procfile.c
UNIT_DEPS_test_clockwatch := user/collect/clockwatch.c
UNIT_DEPS_test_clockoff := user/collect/clockoff.c
UNIT_DEPS_test_procmaps := user/collect/procmaps.c
UNIT_DEPS_test_fpcheck := user/collect/fpcheck.c
UNIT_DEPS_test_taskattrs := user/collect/taskattrs.c user/collect/targets.c user/collect/iterread.c \
			  user/collect/procfile.c
UNIT_LIBS_test_taskattrs := -lbpf
UNIT_LIBS_test_fpcheck := -ldw -lelf
UNIT_DEPS_test_stackagg := user/model/stackagg.c
UNIT_DEPS_test_candump := user/offline/candump.c
UNIT_DEPS_test_prom := user/sinks/prom.c user/sinks/textbuf.c user/model/model.c user/judge/status.c user/model/syscalls.c
UNIT_DEPS_test_service := user/robot/service.c user/judge/status.c
UNIT_LIBS_test_service := -lsystemd
UNIT_DEPS_test_promexp := user/sinks/promexp.c
UNIT_LIBS_test_promexp := -lpthread
UNIT_LIBS_test_can := -lpthread
UNIT_DEPS_test_canmodel := user/model/canmodel.c user/model/model.c user/judge/status.c $(CONFIG_SRCS) user/model/syscalls.c user/config/actionspec.c
UNIT_LIBS_test_canmodel := -lyaml
UNIT_DEPS_test_ros2diag := user/robot/ros2diag.c user/robot/diagtypes.c user/model/canmodel.c \
	user/model/model.c user/judge/status.c $(CONFIG_SRCS) user/model/syscalls.c \
	user/config/actionspec.c
UNIT_LIBS_test_ros2diag := -lyaml
$(OUT)/tests/test_ros2diag: $(OUT)/idl/diagnostics.h
.SECONDEXPANSION:
$(OUT)/tests/%: $$(wildcard tests/unit/*/$$*.c) $$(UNIT_DEPS_$$*) $(OUT)/syscall_table.h | $(OUT)/tests
	$(call msg,CC,$@)
	$(Q)$(CC) $(CFLAGS) $(WARN) $(CPPFLAGS) $(INCLUDES) $(USER_INC) $< $(UNIT_DEPS_$*) -lcmocka -lm $(UNIT_LIBS_$*) -o $@
	@# -MMD names one .d after -o: the last source's headers only; this lists every source's
	$(Q)$(CC) $(filter-out -MMD -MP,$(CPPFLAGS)) $(INCLUDES) $(USER_INC) -MM -MP -MT $@ \
		$< $(UNIT_DEPS_$*) > $@.d

# every binary runs even when one fails; make fails at the end
unit: $(UNIT_BINS)
	$(Q)fail=0; for t in $(UNIT_BINS); do $(UNIT_RUN) $$t || fail=1; done; exit $$fail

# the ROS 2 test's subscriber comes from PyPI into build/venv (made once);
# without it test_ros2.py skips, or fails with CI=true
ros2-venv:
	$(Q)scripts/ros2-venv >/dev/null

integration: all
	$(Q)scripts/ros2-venv >/dev/null || echo "integration: no venv for test_ros2.py" >&2
	$(Q)$(PYTHON) -m pytest -v -rs --durations=15 tests/integration

# The host integration tests with our own noise on every CPU (scripts/noise):
# a SCHED_FIFO 99 thread per CPU burns 3 ms every 30 ms (+-25 %).
test-noisy: all
	$(Q)RTSUP_TEST_NOISE="-b 3ms -e 30ms" $(PYTHON) -m pytest -v -rs tests/integration \
		--ignore=tests/integration/test_guest.py --ignore=tests/integration/test_can.py \
		--ignore=tests/integration/test_cansim.py --ignore=tests/integration/test_deb.py \
		--ignore=tests/integration/test_guest_arm64.py \
		-k "not test_service_under_systemd_in_vm"

# What CI runs: every test: unit, fuzz regressions, sanitizers, integration
# (with the arm64 guest's, tests/integration/test_guest_arm64.py).
test: test-builds unit cross-arm64 fuzz-regress sanitize integration

# Everything make test compiles (the x86, sanitizer and arm64 builds, unit
# tests, fuzz targets), first and JOBS at a time: the steps after it find
# it built and only run it. 253 s of steps became 168 s on 2 CPUs.
JOBS ?= $(shell nproc)
test-builds:
	$(Q)$(MAKE) --no-print-directory -j$(JOBS) all unit-bins $(FUZZ_BINS)
	$(Q)$(MAKE) --no-print-directory -j$(JOBS) OUT=$(SAN_OUT) CFLAGS="$(SAN_CFLAGS)" all unit-bins
	$(Q)$(MAKE) --no-print-directory -j$(JOBS) ARCH=arm64 all unit-bins

unit-bins: $(UNIT_BINS)

# arm64: everything cross-built into build-arm64/, its unit tests under
# qemu-user (cross.mk, docs/arm64.md)
cross-arm64:
	$(Q)$(MAKE) --no-print-directory ARCH=arm64 all unit

# Fuzz targets (tests/fuzz, docs/reliability.md): libFuzzer with ASan and
# UBSan, every userspace module but main.c linked into each target.
FUZZ_TIME ?= 60
FUZZ_CC    := $(CLANG)
FUZZ_SAN   := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
FUZZ_FLAGS := -O1 -g $(FUZZ_SAN) -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
FUZZ_TARGETS := config record candump options proc
FUZZ_OBJS := $(patsubst user/%.c,$(OUT)/fuzz/user/%.o,$(filter-out user/main.c,$(USER_SRCS)))
FUZZ_BINS := $(patsubst %,$(OUT)/fuzz/fuzz_%,$(FUZZ_TARGETS))

$(FUZZ_OBJS): $(OUT)/rtsup.skel.h $(OUT)/rtsup_empty.skel.h $(OUT)/rtsup_tasks.skel.h \
	$(OUT)/syscall_table.h \
	$(OUT)/idl/diagnostics.h

$(OUT)/fuzz/user/%.o: user/%.c
	@mkdir -p $(@D)
	$(call msg,CC-FUZZ,$@)
	$(Q)$(FUZZ_CC) $(FUZZ_FLAGS) -fsanitize=fuzzer-no-link $(WARN) $(CPPFLAGS) $(INCLUDES) $(USER_INC) -c $< -o $@

$(OUT)/fuzz/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz.h $(FUZZ_OBJS)
	$(call msg,LINK,$@)
	$(Q)$(FUZZ_CC) $(FUZZ_FLAGS) -fsanitize=fuzzer $(WARN) $(CPPFLAGS) $(INCLUDES) $(USER_INC) \
		$< $(FUZZ_OBJS) $(USER_LIBS) -lm -o $@

fuzz-build: $(FUZZ_BINS)

# Each target for FUZZ_TIME seconds from its seeds; what it learns stays in
# $(OUT)/fuzz/corpus, a crash input in $(OUT)/fuzz/ (then: tests/fuzz/regress/).
fuzz: $(FUZZ_BINS)
	$(Q)for t in $(FUZZ_TARGETS); do \
		mkdir -p $(OUT)/fuzz/corpus/$$t tests/fuzz/corpus/$$t; \
		echo "  FUZZ     $$t ($(FUZZ_TIME) s)"; \
		$(OUT)/fuzz/fuzz_$$t -max_total_time=$(FUZZ_TIME) -timeout=10 -close_fd_mask=3 \
			-print_final_stats=1 -artifact_prefix=$(OUT)/fuzz/$$t- \
			$(OUT)/fuzz/corpus/$$t tests/fuzz/corpus/$$t >$(OUT)/fuzz/fuzz-$$t.log 2>&1; \
		rc=$$?; \
		grep -E '^(#[0-9]+[[:space:]]+DONE|stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb))|ERROR|SUMMARY|Test unit written' \
			$(OUT)/fuzz/fuzz-$$t.log; \
		test $$rc = 0 || { tail -60 $(OUT)/fuzz/fuzz-$$t.log; exit 1; }; \
	done

# Every seed and every input that once crashed, run once through its target.
fuzz-regress: $(FUZZ_BINS)
	$(Q)for t in $(FUZZ_TARGETS); do \
		files=$$(find tests/fuzz/corpus/$$t tests/fuzz/regress/$$t -type f 2>/dev/null); \
		test -n "$$files" || continue; \
		echo "  REGRESS  $$t ($$(echo "$$files" | wc -l) inputs)"; \
		$(OUT)/fuzz/fuzz_$$t -timeout=10 -close_fd_mask=1 $$files >$(OUT)/fuzz/regress-$$t.log 2>&1 || \
			{ grep -v '^Running\|^Executed' $(OUT)/fuzz/regress-$$t.log | tail -40; exit 1; }; \
	done

# Userspace and unit tests under ASan+UBSan in their own directory, then a
# short live-BPF integration subset with those binaries (RTSUP_BUILD).
SAN_OUT    ?= build-san
SAN_CFLAGS := -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
SAN_TESTS  ?= tests/integration/test_trace.py::test_clean_load_period_and_cycles \
	tests/integration/test_trace.py::test_injected_faults_reported_exactly \
	tests/integration/test_trace.py::test_exit_is_reported_and_tracing_goes_on \
	tests/integration/test_status.py::test_check_faults_exit_2_with_messages \
	tests/integration/test_status.py::test_sighup_reload_turns_ok_into_warn \
	tests/integration/test_status.py::test_record_replay_same_numbers_and_verdicts \
	tests/integration/test_status.py::test_corrupt_trace_errors_cleanly \
	tests/integration/test_status.py::test_perfetto_export_is_valid \
	tests/integration/test_status.py::test_check_config \
	tests/integration/test_status.py::test_can_replay_clock_step_finishes
# Every report goes to $(SAN_OUT)/san-report.PID: any such file fails the run,
# whatever exit code the test saw. The integration subset runs the sanitized
# rtsup-trace against the shipped generators (RTSUP_TRACE): ASan's shadow
# memory faults would break the generator's own truth; the sanitized
# generators run once each on their own.
SAN_ENV := ASAN_OPTIONS=detect_leaks=1:log_path=$(CURDIR)/$(SAN_OUT)/san-report \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:log_path=$(CURDIR)/$(SAN_OUT)/san-report
sanitize: all
	$(Q)$(MAKE) --no-print-directory OUT=$(SAN_OUT) CFLAGS="$(SAN_CFLAGS)" all unit
	$(Q)rm -f $(SAN_OUT)/san-report.*
	$(Q)$(SAN_ENV) $(SAN_OUT)/rtsup-loadgen -n 2 -c 300 -f overrun@20 -f mmap/50 \
		-f pagefault:2@30 -f block@40 -f exit@250,thread=1 -s /dev/null
	$(Q)$(SAN_ENV) $(SAN_OUT)/rtsup-noise gauge -d 0.5s >/dev/null
	$(Q)RTSUP_TRACE=$(SAN_OUT)/rtsup-trace $(SAN_ENV) $(PYTHON) -m pytest -v -rs $(SAN_TESTS)
	$(Q)if ls $(SAN_OUT)/san-report.* >/dev/null 2>&1; then \
		cat $(SAN_OUT)/san-report.*; echo "sanitize: reports above" >&2; exit 1; fi

# A 60 s live run with every sink on under ASan+UBSan, then its replay (not
# in make test: a minute; docs/reliability.md)
sanitize-sinks: sanitize
	$(Q)SAN_OUT=$(CURDIR)/$(SAN_OUT) scripts/sanitize-sinks 60

demo: all
	$(Q)scripts/demo

deps:
	$(Q)scripts/install-deps

deps-arm64:
	$(Q)scripts/install-deps-arm64

# Overhead against the floor and peer tools; installs the peers first (not in make deps).
bench: all $(OUT)/rtsup_empty.bpf.o $(OUT)/rtsup-synth-trace
	$(Q)scripts/install-bench-deps
	$(Q)scripts/bench

format-check:
	$(Q)clang-format --dry-run --Werror include/*.h user/*.[ch] user/*/*.[ch] bpf/*.c bpf/*.h

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
	install -m 0644 systemd/ros2-diagnostics.conf $(DESTDIR)$(SYSCONFDIR)/rtsup/ros2-diagnostics.conf.example

# The Debian packages rtsup and rtsup-tools (debian/): dpkg-buildpackage on a
# copy of the tree in $(OUT)/deb, where the .deb files land; lintian must
# find no error.
DEB_DIR := $(OUT)/deb
deb:
	$(Q)rm -rf $(DEB_DIR) && mkdir -p $(DEB_DIR)/rtsup
	$(Q)tar --exclude=./build --exclude=./build-san --exclude=./.git --exclude=.pytest_cache \
		--exclude=__pycache__ -cf - . | tar -xf - -C $(DEB_DIR)/rtsup
	$(call msg,DEB,$(DEB_DIR))
	$(Q)cd $(DEB_DIR)/rtsup && dpkg-buildpackage -b -us -uc >../build.log 2>&1 || \
		{ tail -40 ../build.log; exit 1; }
	$(call msg,LINTIAN,$(DEB_DIR))
	$(Q)lintian --fail-on error $(DEB_DIR)/*.changes
	$(Q)ls $(DEB_DIR)/*.deb

# Weeks without a restart, in 10 minutes: thread churn under the tool (not in make test).
soak: all
	$(Q)scripts/soak

clean:
	$(Q)rm -rf $(OUT) $(SAN_OUT)

-include $(wildcard $(OUT)/*.d $(OUT)/user/*.d $(OUT)/user/*/*.d $(OUT)/tests/*.d \
	$(OUT)/fuzz/*.d $(OUT)/fuzz/user/*.d $(OUT)/fuzz/user/*/*.d)
