# SPDX-License-Identifier: MIT
#
# ecmxf top-level Makefile.  Userspace builds with CMake underneath; the
# kernel module with Kbuild.  Every target installs missing Debian
# packages first (scripts/install-deps.sh), so on a fresh Debian bookworm
# machine, as root, `make check` and `make demo` work alone.

BUILD      ?= build
ASAN_BUILD ?= build-asan
FUZZ_BUILD ?= build-fuzz
BENCH_BUILD ?= build-bench
PREFIX     ?= /usr/local
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
WERROR     ?= ON
CMAKE_ARGS ?=
FUZZ_SECONDS ?= 12
FUZZ_LONG_SECONDS ?= 600
FUZZ_LONG_CORPUS ?= /var/tmp/ecmxf-fuzz-corpus
# Kernel headers: the running kernel's if installed, else the newest
# Debian headers under /lib/modules.
KDIR ?= $(firstword $(wildcard /lib/modules/$(shell uname -r)/build) \
	$(lastword $(sort $(wildcard /lib/modules/*/build))))

DEPS := scripts/install-deps.sh

.PHONY: all python deps configure check check-user check-stress check-debug-kernel check-asan asan-build fuzz fuzz-long fuzz-build soak demo bench kmod kmod-deps \
	kmod-check kmod-check-all kmod-check-kernels checkpatch dt-check kernel-lint check-kernel check-kernels \
	kmod-clean install install-udev deb check-deb clean help

all: configure
	cmake --build $(BUILD) -j $(JOBS)

# The Python binding alone (lib/python, Documentation/python.rst): the
# package in $(BUILD)/python, so PYTHONPATH=$(BUILD)/python python3 finds
# `import ecmxf`.  make all builds it too.
python: configure
	cmake --build $(BUILD) -j $(JOBS) --target ecmxf_python

deps:
	@$(DEPS)

# The prefix goes to CMake only when given (make install PREFIX=X): a later
# make or make demo without it keeps the configured one, and so rebuilds
# nothing (the prefix is compiled into lib/sim/network.cpp alone).
PREFIX_ARG = $(if $(filter command line environment,$(origin PREFIX)),-DCMAKE_INSTALL_PREFIX=$(PREFIX))
configure: deps
	cmake -S . -B $(BUILD) -DECMXF_WERROR=$(WERROR) $(PREFIX_ARG) $(CMAKE_ARGS)

# Every test: the userspace suites (ctest), then the kernel module under
# QEMU on Debian's normal and PREEMPT_RT kernels (check-kernel).
check: check-user check-kernel

# The userspace suites only (ctest).
check-user: all
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# The userspace suite repeated STRESS_ROUNDS times per test under load:
# every core busy (stress-ng), then pinned to one core (taskset); zero
# failures is the bar (scripts/check-stress.sh).  Not in CI: run it before
# merging anything that touches threads or timing.
STRESS_ROUNDS ?= 20
check-stress: all
	scripts/check-stress.sh $(BUILD) $(STRESS_ROUNDS)

# The soak (tests/soak/soak.cpp, Documentation/building.rst "Soak"):
# ecmxf::Cyclic over the simulator with a seeded fault schedule and
# per-cycle invariants, SOAK_CYCLES on the default network at 8 kHz, then
# SOAK_CYCLES_128 on the 128-slave network.  The seed is printed; replay a
# run with SOAK_SEED=.  Not in CI (make check runs 10^5 cycles).
SOAK_CYCLES ?= 10000000
SOAK_CYCLES_128 ?= $(shell expr $(SOAK_CYCLES) / 10)
SOAK_SEED ?= $(shell date +%s)
soak: configure
	cmake --build $(BUILD) -j $(JOBS) --target ecmxf-soak
	$(BUILD)/tests/soak/ecmxf-soak --cycles $(SOAK_CYCLES) --seed $(SOAK_SEED) --network default
	$(BUILD)/tests/soak/ecmxf-soak --cycles $(SOAK_CYCLES_128) --seed $(SOAK_SEED) --network 128

# The same tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (asan-build only builds them: CI builds while a QEMU guest runs).
check-asan: asan-build
	ctest --test-dir $(ASAN_BUILD) --output-on-failure -j $(JOBS)

asan-build: deps
	cmake -S . -B $(ASAN_BUILD) -DECMXF_WERROR=$(WERROR) -DECMXF_SANITIZE=address,undefined \
		-DCMAKE_BUILD_TYPE=Debug $(CMAKE_ARGS)
	cmake --build $(ASAN_BUILD) -j $(JOBS)

# libFuzzer targets (clang), each run for FUZZ_SECONDS (CI: bounded),
# FUZZ_JOBS at a time (one per core).
FUZZ_JOBS ?= $(JOBS)
fuzz: fuzz-build
	FUZZ_JOBS=$(FUZZ_JOBS) tests/fuzz/run-fuzzers.sh $(FUZZ_BUILD) $(FUZZ_SECONDS)

# The same for FUZZ_LONG_SECONDS each (default 10 min: 13 targets, about 2.2
# hours), at nice 19, one fuzzer at a time, the corpora kept in
# FUZZ_LONG_CORPUS between runs.  Not in CI; prints execs/s per target and
# the total (Documentation/building.rst, "Fuzzing").
fuzz-long: fuzz-build
	nice -n 19 tests/fuzz/run-fuzzers.sh $(FUZZ_BUILD) $(FUZZ_LONG_SECONDS) $(FUZZ_LONG_CORPUS)

fuzz-build:
	@$(DEPS) --ci
	CC=clang CXX=clang++ cmake -S . -B $(FUZZ_BUILD) -DECMXF_BUILD_FUZZ=ON \
		-DECMXF_BUILD_TESTS=OFF -DECMXF_BUILD_PYTHON=OFF -DECMXF_WERROR=$(WERROR) -DCMAKE_BUILD_TYPE=RelWithDebInfo
	cmake --build $(FUZZ_BUILD) -j $(JOBS)

# make bench ends with the in-guest benchmarks under QEMU
# (Documentation/kernel-testing.rst, "Benchmarks"); KBENCH_FLAVOURS= picks
# the kernels. Two boots per kernel: the round trip and the cyclic paths
# (steps 10, 20) on two vCPUs; the paths under load (step 30) on one vCPU
# whose clock counts instructions (-icount), at the chip's own rates, so
# that the host's scheduling of QEMU does not show in guest time.
KBENCH_FLAVOURS ?= amd64 rt-amd64
KBENCH_LOAD_ENV = ECMXF_KTEST_STEPS=30 ECMXF_KTEST_SMP=1 ECMXF_KTEST_ICOUNT=shift=1,sleep=off ECMXF_LOAD_SCALE=1
bench:
	@$(DEPS) --bench
	cmake -S . -B $(BENCH_BUILD) -DECMXF_BUILD_BENCH=ON -DECMXF_BUILD_TESTS=OFF \
		-DECMXF_WERROR=$(WERROR) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BENCH_BUILD) -j $(JOBS)
	$(BENCH_BUILD)/tests/bench/bench-core
	$(BENCH_BUILD)/tests/bench/bench-sim
	$(BENCH_BUILD)/tests/bench/bench-sdo
	$(BENCH_BUILD)/tests/bench/bench-cyclic
	$(BENCH_BUILD)/tests/bench/bench-sk
	$(BENCH_BUILD)/tests/bench/bench-trace
	python3 tests/bench/bench-python.py $(BENCH_BUILD)
	BUILD=$(BENCH_BUILD) ECMXF_KTEST_STEPS=10,20 tests/kernel/run-qemu.sh --bench $(KBENCH_FLAVOURS)
	BUILD=$(BENCH_BUILD) $(KBENCH_LOAD_ENV) tests/kernel/run-qemu.sh --bench $(KBENCH_FLAVOURS)

# The tour of the stack on the simulator (utils/ecmxf-demo.cpp), paced in
# real time; DEMO_ARGS=--fast skips the pacing.
DEMO_ARGS ?=
demo: all
	$(BUILD)/utils/ecmxf-demo $(DEMO_ARGS)

kmod-deps:
	@$(DEPS) --kernel
	@test -n "$(KDIR)" || { echo "make: no kernel headers found; set KDIR=" >&2; exit 1; }

# The module (see Documentation/kernel-build.rst).  `make kmod C=2` adds
# sparse: command-line variables reach Kbuild through MAKEFLAGS.
kmod: kmod-deps
	$(MAKE) -C $(KDIR) M=$(CURDIR)/kmod W=1 modules

# From scratch with W=1 and sparse (C=2), then kernel-doc over lib/core
# and kmod, headers included; fails on any warning.
kmod-check: kmod-deps
	MAKE="$(MAKE)" scripts/kmod-check.sh $(KDIR)

# kmod-check against every installed header tree (Debian: the normal and
# the PREEMPT_RT kernel).
kmod-check-all: kmod-deps
	@for k in $(sort $(wildcard /lib/modules/*/build)); do \
		echo "== $$k"; \
		MAKE="$(MAKE)" scripts/kmod-check.sh $$k || exit 1; \
	done

# kmod-check against the matrix's other kernels (Documentation/
# kernel-testing.rst, "The kernel matrix"): Debian's 6.12 for amd64, and
# 6.1 and 6.12 for arm64, cross-built (ARCH=arm64 CROSS_COMPILE=
# aarch64-linux-gnu-; sparse checks as arm64).  Their header trees are
# unpacked from Debian's packages by scripts/debian-kernel.sh (cached).
KMOD_CHECK_KERNELS ?= 6.12-amd64 6.1-arm64 6.12-arm64
kmod-check-kernels: kmod-deps
	@$(DEPS) --arm64
	@for k in $(KMOD_CHECK_KERNELS); do \
		kdir=$$(scripts/debian-kernel.sh --headers-only $$k | sed -n 's/^KDIR=//p'); \
		test -n "$$kdir" || exit 1; \
		case $$k in *arm64) cross="ARCH=arm64 CROSS_COMPILE=aarch64-linux-gnu-" ;; *) cross= ;; esac; \
		echo "== $$k: $$kdir"; \
		MAKE="$(MAKE)" scripts/kmod-check.sh $$kdir $$cross || exit 1; \
	done

# checkpatch.pl --strict over lib/core and kmod; the script fetches it
# from Debian's linux-source-6.1 into ECMXF_CACHE (default /var/cache/ecmxf).
checkpatch:
	scripts/checkpatch.sh

# The DT binding (dt-doc-validate, its examples through dt-validate) and
# the Raspberry Pi overlay (dtc, applied with fdtoverlay, its node through
# dt-validate): scripts/dt-check.sh.
dt-check: kmod-deps
	scripts/dt-check.sh

# Everything the kernel asks of kernel code, before review: on Debian's
# 6.1 amd64 kernel (kmod-check) and on the matrix's others
# (kmod-check-kernels).  kmod-check runs last: it leaves kmod/ built for
# the host, as `make kmod` would.
kernel-lint: checkpatch dt-check
	$(MAKE) kmod-check-kernels
	$(MAKE) kmod-check

# ecmxf.ko under QEMU on a virtual SPI controller, with the simulator as the
# chip, on Debian's normal and PREEMPT_RT kernels (Documentation/
# kernel-testing.rst).  Part of `make check`.  KTEST_FLAVOURS= picks the
# kernels (amd64 rt-amd64).
KTEST_FLAVOURS ?=
check-kernel: configure
	BUILD=$(BUILD) tests/kernel/run-qemu.sh $(KTEST_FLAVOURS)

# The kernel matrix (Documentation/kernel-testing.rst, "The kernel
# matrix"): the guest tests on Debian's 6.1 and 6.12, normal and
# PREEMPT_RT, amd64 and arm64 (qemu-system-aarch64, cross-built guest
# programs and modules).  KERNELS= picks a part of it.  Every kernel is run
# even when one fails; the table of boot and suite times (and failures)
# ends the output and stays in $(BUILD)/check-kernels.txt.
KERNELS ?= 6.1-amd64 6.1-rt-amd64 6.12-amd64 6.12-rt-amd64 6.1-arm64 6.1-rt-arm64 6.12-arm64 6.12-rt-arm64
check-kernels: configure
	@rm -f $(abspath $(BUILD))/check-kernels.txt
	@BUILD=$(BUILD) ECMXF_KTEST_TIMES=$(abspath $(BUILD))/check-kernels.txt \
		tests/kernel/run-qemu.sh $(KERNELS); rc=$$?; \
		echo "== make check-kernels:"; cat $(abspath $(BUILD))/check-kernels.txt; exit $$rc

# The same guest tests on a KASAN + UBSAN + lockdep kernel built from
# Debian's linux-source-6.1 (scripts/build-debug-kernel.sh; built once,
# cached in /var/tmp/ecmxf-ktest).
check-debug-kernel: configure
	BUILD=$(BUILD) tests/kernel/run-qemu.sh debug

kmod-clean:
	@test -z "$(KDIR)" || $(MAKE) -C $(KDIR) M=$(CURDIR)/kmod clean

install: all
	cmake --install $(BUILD)

# The udev rule for /dev/ecmxfN (group "ecmxf", mode 0660); udev reads
# /etc/udev/rules.d whatever PREFIX is, so it is installed on its own.
install-udev:
	install -D -m 0644 kmod/60-ecmxf.rules $(DESTDIR)/etc/udev/rules.d/60-ecmxf.rules

# Debian packages (debian/): libecmxf0, libecmxf-dev, ecmxf-tools and
# ecmxf-dkms, built by dpkg-buildpackage from a copy of the tree into
# DEB_OUT, then lintian (Documentation/building.rst, "Debian packages").
DEB_OUT ?= $(BUILD)/deb
deb:
	@$(DEPS) --deb
	scripts/make-deb.sh $(DEB_OUT) $(JOBS)

# make deb, then the packages installed on this machine (root): DKMS
# builds ecmxf.ko for Debian's normal and RT kernel headers, the installed
# tools run against the simulator, a consumer builds against -dev, and the
# purge leaves nothing behind (scripts/check-deb.sh).  Not in make check
# (it installs system-wide); CI runs it (.ci/run).
check-deb:
	@$(DEPS) --deb --kernel
	scripts/check-deb.sh $(DEB_OUT) $(JOBS)

clean: kmod-clean
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD) $(BENCH_BUILD)

help:
	@echo "make [all]     build the library, ecmxf-util and the tests"
	@echo "make python    the Python binding alone, into $(BUILD)/python (PYTHONPATH=$(BUILD)/python)"
	@echo "make check     build and run every test: ctest, then check-kernel"
	@echo "make check-user    the userspace tests only (ctest)"
	@echo "make check-stress  the userspace tests STRESS_ROUNDS (20) times each under load, then on one core"
	@echo "make soak      the cyclic exchange under a seeded fault schedule, 10^7 cycles at 8 kHz"
	@echo "               (SOAK_CYCLES=, SOAK_SEED= replays a run)"
	@echo "make fuzz      every libFuzzer target for FUZZ_SECONDS (CI); make fuzz-long: FUZZ_LONG_SECONDS each"
	@echo "make demo      ecmxf-demo: a tour of the stack on the simulator (DEMO_ARGS=--fast)"
	@echo "make bench     build and run the benchmarks (also in the QEMU guest: KBENCH_FLAVOURS=)"
	@echo "make kmod      build kmod/ecmxf.ko (KDIR=/path/to/headers)"
	@echo "make kernel-lint  checkpatch --strict, W=1, sparse and kernel-doc"
	@echo "               over lib/core and kmod, and the DT binding and overlay"
	@echo "               (also: make checkpatch, make kmod-check, make dt-check)"
	@echo "make check-kernel  ecmxf.ko under QEMU (normal + PREEMPT_RT kernel)"
	@echo "make check-kernels  the same on Debian's 6.1 and 6.12, normal and RT, amd64 and arm64"
	@echo "               (KERNELS= picks some; make kmod-check-kernels: W=1 + sparse on them)"
	@echo "make check-debug-kernel  the same on a KASAN/UBSAN/lockdep kernel (built once)"
	@echo "make install   install to PREFIX (default /usr/local)"
	@echo "make deb       Debian packages (library, -dev, tools, DKMS) into DEB_OUT, lintian-checked"
	@echo "make check-deb make deb, then install, DKMS build for both kernels, run, purge (root)"
	@echo "make install-udev  the udev rule for /dev/ecmxfN (DESTDIR=)"
	@echo "make clean     remove build trees"
