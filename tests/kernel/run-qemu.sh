#!/bin/sh
# SPDX-License-Identifier: MIT
#
# The QEMU kernel tests (Documentation/kernel-testing.rst):
#
#   tests/kernel/run-qemu.sh [--bench] [KERNEL]...
#
# KERNEL is one of Debian bookworm's kernels, <series>-<flavour>:
#   6.1-amd64 6.1-rt-amd64 6.12-amd64 6.12-rt-amd64         (qemu-system-x86_64)
#   6.1-arm64 6.1-rt-arm64 6.12-arm64 6.12-rt-arm64         (qemu-system-aarch64)
# or debug, the KASAN/UBSAN/lockdep kernel of scripts/build-debug-kernel.sh.
# amd64 and rt-amd64 are short for 6.1-amd64 and 6.1-rt-amd64, the default
# (`make check`). scripts/debian-kernel.sh resolves each name through its
# Debian meta-package (never "the newest headers installed") and fetches
# what is not installed. For each kernel: build ecmxf.ko and ecmxf-vspi.ko
# against its headers (cross-built for arm64), pack an initramfs with
# busybox, the guest programs (tests/kernel/*.cpp and the C example
# examples/ecmxf-sdo-read.c, static; cross-built for arm64) and the
# step scripts of the mode (tests/kernel/steps/check, or steps/bench with
# --bench), boot the kernel under QEMU (TCG) and check the console: the
# marker line must be there and no kernel warning may be. Each kernel's
# result line gives its boot and suite times. Environment:
#   BUILD               CMake build directory of the library (default build;
#                       the arm64 library is built in $BUILD-arm64)
#   ECMXF_KTEST_CACHE   kernel images and per-kernel outputs
#                       (default /var/tmp/ecmxf-ktest)
#   ECMXF_KTEST_TIMEOUT seconds one boot may take (default 1200: the PDO ring
#                       runs alone take 100 s of guest time; three times
#                       that on arm64 and on the debug kernel)
#   ECMXF_FUZZ_SEED     seed of the interface fuzzer (step 95-fuzz.sh; a seed
#                       a run printed replays it), ECMXF_FUZZ_SECONDS its run
#                       time (default 25 s, 120 s on the debug kernel);
#                       ECMXF_FUZZ_FORMAT_CHANGES=1: its --format-changes
#   ECMXF_KTEST_STEPS   a comma-separated list of step name prefixes (e.g.
#                       95,80) to run, no other: for iterating on steps, and
#                       CI's documented arm64 subset
#   ECMXF_KTEST_TIMES   a file each kernel's result line is appended to
#                       (make check-kernels' table)
#   ECMXF_KTEST_ICOUNT  QEMU -icount options (e.g. shift=1,sleep=off): the
#                       guest's clock counts the instructions it runs, so
#                       the host's scheduling of QEMU no longer shows in
#                       guest time (make bench's load step, kernel-testing.rst
#                       "Under load"); QEMU 7.2 then boots no second x86
#                       vCPU (it hangs at "Booting SMP configuration"):
#                       give ECMXF_KTEST_SMP=1 with it
#   ECMXF_KTEST_SMP     the guest's vCPUs (default 2)
set -eu

top=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD:-build}
case "$build" in /*) ;; *) build="$top/$build" ;; esac
cache=${ECMXF_KTEST_CACHE:-/var/tmp/ecmxf-ktest}
boot_timeout=${ECMXF_KTEST_TIMEOUT:-1200}
mode=check
if [ "${1:-}" = --bench ]; then
	mode=bench
	shift
fi
kernels=""
arches=""
for k in ${*:-amd64 rt-amd64}; do
	case "$k" in
	amd64 | rt-amd64) k=6.1-$k ;;
	esac
	case "$k" in
	debug | 6.1-amd64 | 6.1-rt-amd64 | 6.12-amd64 | 6.12-rt-amd64) a=amd64 ;;
	6.1-arm64 | 6.1-rt-arm64 | 6.12-arm64 | 6.12-rt-arm64) a=arm64 ;;
	*) echo "run-qemu: unknown kernel '$k' (see the head of $0)" >&2; exit 2 ;;
	esac
	kernels="$kernels $k"
	case " $arches " in *" $a "*) ;; *) arches="$arches $a" ;; esac
done

say() { echo "run-qemu: $*"; }
die() { echo "run-qemu: $*" >&2; exit 1; }
case "${ECMXF_KTEST_SMP:-2}" in
[1-8]) ;;
*) echo "run-qemu: ECMXF_KTEST_SMP='$ECMXF_KTEST_SMP': give 1 to 8 vCPUs" >&2; exit 2 ;;
esac
case "${ECMXF_KTEST_ICOUNT:-shift=0}" in
shift=*) ;;
*) echo "run-qemu: ECMXF_KTEST_ICOUNT='$ECMXF_KTEST_ICOUNT': give QEMU's -icount options, shift=N[,...]" >&2; exit 2 ;;
esac

# ---- packages: QEMU, busybox, cpio, kmod, the 6.1 amd64 headers; for
# arm64 guests the cross toolchain, arm64 -dev packages, qemu-system-arm
deps="--kernel --qemu"
case "$arches" in *arm64*) deps="$deps --arm64" ;; esac
# shellcheck disable=SC2086
"$top/scripts/install-deps.sh" $deps

# ---- userspace: the bridge and the guest programs, static, for one
# architecture (amd64: this machine's compiler; arm64: Debian's cross
# compiler and the :arm64 -dev packages), into $cache/bin[-arm64]
build_guest_programs() {
	garch=$1
	mkdir -p "$cache"
	if [ "$garch" = amd64 ]; then
		gbuild=$build
		bin="$cache/bin"
		cc=gcc
		cxxc=g++
		# 32-bit userspace on the 64-bit kernel (compat_ioctl): i386
		cxx32=i686-linux-gnu-g++
		tag=""
		cmake -S "$top" -B "$gbuild" >/dev/null
	else
		gbuild=$build-arm64
		bin="$cache/bin-arm64"
		cc=aarch64-linux-gnu-gcc
		cxxc=aarch64-linux-gnu-g++
		cxx32=arm-linux-gnueabihf-g++
		tag=-arm64
		# the guest's busybox: busybox-static:arm64, unpacked (it
		# cannot be installed beside the amd64 one)
		bbdir="$cache/busybox-arm64"
		if [ ! -x "$bbdir/bin/busybox" ]; then
			rm -rf "$bbdir"
			mkdir -p "$bbdir"
			(cd "$bbdir" && apt-get download -q busybox-static:arm64 >/dev/null 2>&1) ||
				die "apt-get download busybox-static:arm64 failed"
			dpkg-deb -x "$bbdir"/busybox-static_*.deb "$bbdir"
			rm -f "$bbdir"/*.deb
		fi
		# pkg-config must find the :arm64 libgpiod and libmnl; no Python
		# binding (the guest has no Python, and this machine no arm64
		# python3-dev)
		PKG_CONFIG_LIBDIR=/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig \
			cmake -S "$top" -B "$gbuild" -DCMAKE_SYSTEM_NAME=Linux -DCMAKE_SYSTEM_PROCESSOR=aarch64 \
			-DCMAKE_C_COMPILER=$cc -DCMAKE_CXX_COMPILER=$cxxc -DECMXF_BUILD_TESTS=OFF \
			-DECMXF_BUILD_PYTHON=OFF >/dev/null
	fi
	cmake --build "$gbuild" --target ecmxf_static -j "$(nproc)"
	lib="$gbuild/lib/libecmxf_static.a"
	[ -f "$lib" ] || die "$lib missing after the build"
	cxx="$cxxc -std=c++20 -O2 -static -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Wcast-qual -Wformat=2 -Wundef -Wold-style-cast -Werror -I$top/include -I$top/include/uapi -I$top/tests/kernel"
	mkdir -p "$bin"
	rm -f "$bin"/ecmxf-*
	for src in "$top"/tests/kernel/*.cpp; do
		name=$(basename "$src" .cpp)
		$cxx -o "$bin/ecmxf-$name" "$src" "$lib" -lgpiod -pthread || die "building $src failed"
	done
	# the uAPI's abuse tests as a 32-bit program (i386 for the amd64 guests,
	# armhf for the arm64 ones), static: steps/check/27-compat32.sh runs it
	# through the kernel's compat_ioctl (uapi.rst, "32-bit programs")
	command -v "$cxx32" >/dev/null || die "$cxx32 not found (scripts/install-deps.sh --qemu / --arm64)"
	# (-Wno-psabi: armhf notes that GCC 7.1 changed how some arguments
	# are passed, which a static program does not meet)
	# shellcheck disable=SC2086 # the flags of $cxx, split
	"$cxx32" ${cxx#"$cxxc"} -Wno-psabi -o "$bin/ecmxf-guest-abuse32" "$top/tests/kernel/guest-abuse.cpp" -pthread ||
		die "building tests/kernel/guest-abuse.cpp for 32 bits ($cxx32) failed"
	# the uAPI-only C example (examples/, Documentation/uapi.rst "Using the uAPI
	# from C"): C99 against include/uapi alone, no library
	$cc -std=c99 -O2 -static -Wall -Wextra -Werror -I"$top/include/uapi" -o "$bin/ecmxf-sdo-read" \
		"$top/examples/ecmxf-sdo-read.c" || die "building examples/ecmxf-sdo-read.c failed"
	# the library's integration suite (tests/integration/, Catch2 v2, header
	# only) as /bin/ecmxf-test-integration, and the network its steps give the
	# bridge as /bin/ecmxf-integration.net; objects kept between runs, ccache
	# when there is one
	iobj="$cache/obj-integration$tag"
	mkdir -p "$iobj"
	ccache=""
	command -v ccache >/dev/null 2>&1 && ccache=ccache
	iobjs=""
	for src in "$top"/tests/integration/*.cpp; do
		o="$iobj/$(basename "$src" .cpp).o"
		$ccache $cxx -DECMXF_TEST_DEFAULT_URI='"/dev/ecmxf0"' -c -o "$o" "$src" ||
			die "building $src failed"
		iobjs="$iobjs $o"
	done
	# shellcheck disable=SC2086
	$cxx -o "$bin/ecmxf-test-integration" $iobjs "$lib" -lgpiod -pthread || die "linking test-integration failed"
	cp "$top/tests/integration/est584x2-io-loopback.net" "$bin/ecmxf-integration.net"
	# ecmxf-util for the guest (the netlink step runs `ecmxf-util monitor`): it
	# links libmnl, which Debian ships only as a shared library, so it is
	# linked dynamically and mkinitramfs.sh copies its libraries along
	dyncxx="${cxx%% -static *} ${cxx#* -static }"
	uobj="$cache/obj-util$tag"
	mkdir -p "$uobj"
	uobjs=""
	for src in "$top"/utils/ecmxf-util*.cpp; do
		o="$uobj/$(basename "$src" .cpp).o"
		# shellcheck disable=SC2086
		$ccache $dyncxx -I"$top/utils" -c -o "$o" "$src" || die "building $src failed"
		uobjs="$uobjs $o"
	done
	# shellcheck disable=SC2086
	$dyncxx -o "$bin/ecmxf-util" $uobjs "$lib" -lgpiod -lmnl -pthread || die "linking ecmxf-util failed"
}

# the fuzzer's seed and time for the guest (kernel parameters the step reads)
fuzz_append=""
[ -n "${ECMXF_FUZZ_SEED:-}" ] && fuzz_append="$fuzz_append ecmxf_fuzz_seed=$ECMXF_FUZZ_SEED"
[ -n "${ECMXF_FUZZ_SECONDS:-}" ] && fuzz_append="$fuzz_append ecmxf_fuzz_seconds=$ECMXF_FUZZ_SECONDS"
[ "${ECMXF_FUZZ_FORMAT_CHANGES:-}" = 1 ] && fuzz_append="$fuzz_append ecmxf_fuzz_format_changes=1"
[ -n "${ECMXF_KTEST_STEPS:-}" ] && fuzz_append="$fuzz_append ecmxf_ktest_steps=$ECMXF_KTEST_STEPS"

# ---- one kernel
run_kernel() {
	kname=$1
	# 1 GiB: the initramfs (the static guest programs with their symbols,
	# which the bench's call-site tables read) unpacks to more than the
	# half of 512 MiB the kernel's rootfs may take ("Initramfs unpacking
	# failed: write error"); the arm64 guests have it too
	mem=1024
	timeout_f=$boot_timeout
	if [ "$kname" = debug ]; then
		# built (once; cached) from Debian's linux-source-6.1
		kinfo=$("$top/scripts/build-debug-kernel.sh") || die "building the debug kernel failed"
		karch=amd64
		# KASAN's shadow memory, and everything runs slower
		mem=1536
		timeout_f=$((boot_timeout * 3))
	else
		kinfo=$("$top/scripts/debian-kernel.sh" "$kname") || die "$kname: scripts/debian-kernel.sh failed"
		karch=$(printf '%s\n' "$kinfo" | sed -n 's/^DEB_ARCH=//p')
	fi
	kver=$(printf '%s\n' "$kinfo" | sed -n 's/^KVER=//p')
	kdir=$(printf '%s\n' "$kinfo" | sed -n 's/^KDIR=//p')
	vmlinuz=$(printf '%s\n' "$kinfo" | sed -n 's/^VMLINUZ=//p')
	[ -n "$kver" ] && [ -d "$kdir" ] && [ -f "$vmlinuz" ] || die "$kname: no KVER/KDIR/VMLINUZ"
	kbuild=""
	if [ "$karch" = arm64 ]; then
		kbuild="ARCH=arm64 CROSS_COMPILE=aarch64-linux-gnu-"
		# TCG emulates another instruction set: several times slower
		timeout_f=$((boot_timeout * 3))
	fi
	out="$cache/$kver"
	mkdir -p "$out"

	# the modules, W=1, from copies (kmod's symlinks followed)
	rm -rf "$out/kmod" "$out/vspi" "$out/ko"
	cp -rL "$top/kmod" "$out/kmod"
	cp -r "$top/tests/kernel/modules" "$out/vspi"
	mkdir -p "$out/ko"
	for m in kmod vspi; do
		# shellcheck disable=SC2086
		make -s -C "$kdir" M="$out/$m" $kbuild W=1 modules >"$out/$m.log" 2>&1 ||
			{ cat "$out/$m.log" >&2; die "$kver: building $m failed"; }
		if grep -E 'warning:|error:' "$out/$m.log"; then
			die "$kver: building $m gave warnings"
		fi
		cp "$out/$m"/*.ko "$out/ko/"
	done

	bin="$cache/bin"
	gbb=""
	if [ "$karch" = arm64 ]; then
		bin="$cache/bin-arm64"
		gbb="$cache/busybox-arm64/bin/busybox"
	fi
	# the bench's load (steps/bench/30-load.sh): this machine's stress-ng,
	# with its libraries, in an amd64 guest (install-deps.sh --bench)
	extra=""
	if [ "$mode" = bench ] && [ "$karch" != arm64 ]; then
		extra=$(command -v stress-ng) || die "the bench needs stress-ng (scripts/install-deps.sh --bench)"
	fi
	# shellcheck disable=SC2086 # $extra: none or one path
	ECMXF_GUEST_BUSYBOX=$gbb "$top/tests/kernel/mkinitramfs.sh" "$out/initramfs.cpio.gz" "$top/tests/kernel/guest-init.sh" \
		"$out/ko" "$top/tests/kernel/steps" "$bin"/ecmxf-* $extra

	# a narrowed run keeps its own console log (make bench boots twice)
	log="$out/console-$mode${ECMXF_KTEST_STEPS:+-$(echo "$ECMXF_KTEST_STEPS" | tr , -)}.log"
	say "$kver: booting under QEMU (TCG, mode $mode), console in $log"
	append="panic=-1 loglevel=7 ecmxf_ktest=$mode$fuzz_append"
	# the bench's sizes, when set here: the kernel hands NAME=VALUE words
	# of its command line to /init as its environment
	for v in ECMXF_BENCH_N ECMXF_BENCH_BLOCKS ECMXF_BENCH_LATE_N ECMXF_LOAD_N ECMXF_LOAD_SCALE; do
		eval "val=\${$v:-}"
		# shellcheck disable=SC2154 # val: set by the eval
		[ -n "$val" ] && append="$append $v=$val"
	done
	[ -n "${ECMXF_LOAD_HZ:-}" ] && append="$append ECMXF_LOAD_HZ=$(echo "$ECMXF_LOAD_HZ" | tr ' ' ,)"
	if [ "$karch" = arm64 ]; then
		# the virt board; a Cortex-A72 is the Raspberry Pi 4/CM4's core
		set -- qemu-system-aarch64 -M virt -cpu cortex-a72 -accel tcg -m 1024 \
			-append "console=ttyAMA0 $append"
	else
		set -- qemu-system-x86_64 -accel tcg -m "$mem" -append "console=ttyS0 $append"
	fi
	rc=0
	t0=$(date +%s)
	[ -n "${ECMXF_KTEST_ICOUNT:-}" ] && set -- "$@" -icount "$ECMXF_KTEST_ICOUNT"
	timeout "$timeout_f" "$@" -smp "${ECMXF_KTEST_SMP:-2}" -nographic -no-reboot -nic none \
		-kernel "$vmlinuz" -initrd "$out/initramfs.cpio.gz" >"$log" 2>&1 || rc=$?
	t1=$(date +%s)
	tr -d '\r' <"$log" >"$log.txt"
	grep -E '^(ECMXF-KTEST|guest-test|bench|bridge|sysfs|fuzz):' "$log.txt" || true
	[ "$rc" -eq 124 ] && die "$kver: QEMU did not finish within ${timeout_f}s (see $log)"
	# not a bare "lockdep": the debug kernel prints "RCU lockdep checking is
	# enabled" at every boot; lockdep's reports all carry WARNING:/BUG:
	bad=$(grep -nE 'WARNING:|BUG:|Oops|Call Trace|sleeping function called from invalid context|possible circular locking|possible recursive locking|locking correctness validator|lockdep is turned off|KASAN|UBSAN|general protection fault|kernel panic|Kernel panic|Internal error:|Unable to handle kernel' \
		"$log.txt" || true)
	if [ -n "$bad" ]; then
		echo "$bad" >&2
		die "$kver: kernel warnings on the console (see $log)"
	fi
	grep -qx 'ECMXF-KTEST: PASS' "$log.txt" || die "$kver: no pass marker on the console (see $log)"
	# the times: boot = the guest's uptime when /init starts, suite = its
	# uptime from there to the last step (TCG's guest clock is the host's)
	up=$(sed -n 's/^ECMXF-KTEST: guest up,.*uptime \([0-9.]*\) s$/\1/p' "$log.txt")
	done_at=$(sed -n 's/^ECMXF-KTEST: steps done, uptime \([0-9.]*\) s$/\1/p' "$log.txt")
	times=$(awk -v u="$up" -v d="$done_at" 'BEGIN { printf "boot %.0f s, suite %.0f s", u, d - u }')
	steps=$(grep -c '^ECMXF-KTEST: step ' "$log.txt" || true)
	line="$kname $kver: PASS, $times, QEMU $((t1 - t0)) s in all, $steps steps${ECMXF_KTEST_STEPS:+ (only $ECMXF_KTEST_STEPS)}"
	say "$line"
	[ -n "${ECMXF_KTEST_TIMES:-}" ] && echo "$line" >>"$ECMXF_KTEST_TIMES"
	return 0
}

for a in $arches; do
	build_guest_programs "$a"
done
# every kernel, also after one failed; each in a subshell of its own (its
# die ends only that kernel; run in the background and waited for, so
# that set -e holds inside it)
failed=""
for k in $kernels; do
	rc=0
	(run_kernel "$k") &
	wait $! || rc=$?
	if [ "$rc" -ne 0 ]; then
		failed="$failed $k"
		[ -n "${ECMXF_KTEST_TIMES:-}" ] && echo "$k: FAIL (see the output above)" >>"$ECMXF_KTEST_TIMES"
	fi
done
[ -z "$failed" ] || die "failed:$failed (passed: the others of$kernels)"
say "all passed ($mode:$kernels)"
