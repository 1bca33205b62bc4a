#!/bin/sh
# SPDX-License-Identifier: MIT
#
# The QEMU kernel tests (Documentation/kernel-testing.rst):
#
#   tests/kernel/run-qemu.sh [--bench] [amd64|rt-amd64|debug]...
#
# (default: amd64 rt-amd64). amd64 and rt-amd64 are Debian's kernels, debug
# the KASAN/UBSAN/lockdep kernel of scripts/build-debug-kernel.sh. For each:
# build ecmxf.ko and ecmxf-vspi.ko against its headers, pack an initramfs
# with busybox, the guest programs (tests/kernel/*.cpp and the C example
# examples/ecmxf-sdo-read.c, static) and the
# step scripts of the mode (tests/kernel/steps/check, or steps/bench with
# --bench), boot the kernel under QEMU (TCG) and check the console: the
# marker line must be there and no kernel warning may be. Environment:
#   BUILD               CMake build directory of the library (default build)
#   ECMXF_KTEST_CACHE   kernel images and per-kernel outputs
#                       (default /var/tmp/ecmxf-ktest)
#   ECMXF_KTEST_TIMEOUT seconds one boot may take (default 1200: the PDO ring
#                       runs alone take 100 s of guest time)
#   ECMXF_FUZZ_SEED     seed of the interface fuzzer (step 95-fuzz.sh; a seed
#                       a run printed replays it), ECMXF_FUZZ_SECONDS its run
#                       time (default 25 s, 120 s on the debug kernel);
#                       ECMXF_FUZZ_FORMAT_CHANGES=1: its --format-changes
#   ECMXF_KTEST_STEPS   for iterating on steps only: a comma-separated list
#                       of step name prefixes (e.g. 95,80) to run, no other
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
flavours=${*:-amd64 rt-amd64}

say() { echo "run-qemu: $*"; }
die() { echo "run-qemu: $*" >&2; exit 1; }

# ---- packages: QEMU, busybox, cpio, kmod and both header packages
"$top/scripts/install-deps.sh" --kernel
need=""
for p in qemu-system-x86 busybox-static cpio; do
	dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null | grep -q '^ii' || need="$need $p"
done
if [ -n "$need" ]; then
	[ "$(id -u)" -eq 0 ] || die "missing packages:$need (run as root)"
	say "installing$need"
	export DEBIAN_FRONTEND=noninteractive
	apt-get update -qq
	# shellcheck disable=SC2086
	apt-get install -y -qq --no-install-recommends $need >/dev/null
fi

# ---- userspace: the bridge and the guest programs, static
mkdir -p "$cache"
cmake -S "$top" -B "$build" >/dev/null
cmake --build "$build" --target ecmxf_static -j "$(nproc)"
lib="$build/lib/libecmxf_static.a"
[ -f "$lib" ] || die "$lib missing after the build"
cxx="g++ -std=c++20 -O2 -static -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Wcast-qual -Wformat=2 -Wundef -Wold-style-cast -Werror -I$top/include -I$top/include/uapi -I$top/tests/kernel"
bin="$cache/bin"
mkdir -p "$bin"
rm -f "$bin"/ecmxf-*
for src in "$top"/tests/kernel/*.cpp; do
	name=$(basename "$src" .cpp)
	$cxx -o "$bin/ecmxf-$name" "$src" "$lib" -lgpiod -pthread || die "building $src failed"
done
# the uAPI-only C example (examples/, Documentation/uapi.rst "Using the uAPI
# from C"): C99 against include/uapi alone, no library
gcc -std=c99 -O2 -static -Wall -Wextra -Werror -I"$top/include/uapi" -o "$bin/ecmxf-sdo-read" \
	"$top/examples/ecmxf-sdo-read.c" || die "building examples/ecmxf-sdo-read.c failed"
# the library's integration suite (tests/integration/, Catch2 v2, header
# only) as /bin/ecmxf-test-integration, and the network its steps give the
# bridge as /bin/ecmxf-integration.net; objects kept between runs, ccache
# when there is one
iobj="$cache/obj-integration"
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
uobj="$cache/obj-util"
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

# the fuzzer's seed and time for the guest (kernel parameters the step reads)
fuzz_append=""
[ -n "${ECMXF_FUZZ_SEED:-}" ] && fuzz_append="$fuzz_append ecmxf_fuzz_seed=$ECMXF_FUZZ_SEED"
[ -n "${ECMXF_FUZZ_SECONDS:-}" ] && fuzz_append="$fuzz_append ecmxf_fuzz_seconds=$ECMXF_FUZZ_SECONDS"
[ "${ECMXF_FUZZ_FORMAT_CHANGES:-}" = 1 ] && fuzz_append="$fuzz_append ecmxf_fuzz_format_changes=1"
[ -n "${ECMXF_KTEST_STEPS:-}" ] && fuzz_append="$fuzz_append ecmxf_ktest_steps=$ECMXF_KTEST_STEPS"

# ---- one kernel flavour
run_flavour() {
	flavour=$1
	mem=512
	timeout_f=$boot_timeout
	if [ "$flavour" = debug ]; then
		# built (once; cached) from Debian's linux-source-6.1
		kinfo=$("$top/scripts/build-debug-kernel.sh") || die "building the debug kernel failed"
		kver=$(printf '%s\n' "$kinfo" | sed -n 's/^KVER=//p')
		kdir=$(printf '%s\n' "$kinfo" | sed -n 's/^KDIR=//p')
		vmlinuz=$(printf '%s\n' "$kinfo" | sed -n 's/^VMLINUZ=//p')
		[ -n "$kver" ] && [ -d "$kdir" ] && [ -f "$vmlinuz" ] ||
			die "build-debug-kernel.sh gave no KVER/KDIR/VMLINUZ"
		# KASAN's shadow memory, and everything runs slower
		mem=1024
		timeout_f=$((boot_timeout * 3))
	else
		# the newest installed headers of this flavour; never a fixed ABI name
		kver=""
		for d in /lib/modules/*-"$flavour"; do
			v=${d##*/}
			[ -d "$d/build" ] || continue
			# "amd64" must not pick the rt-amd64 kernels
			[ "$flavour" = amd64 ] && case "$v" in *-rt-amd64) continue ;; esac
			kver=$(printf '%s\n%s\n' "$kver" "$v" | sed '/^$/d' | sort -V | tail -n 1)
		done
		[ -n "$kver" ] || die "no kernel headers of flavour $flavour under /lib/modules"
		kdir=/lib/modules/$kver/build
		vmlinuz=""
	fi
	out="$cache/$kver"
	mkdir -p "$out"

	# the kernel image from Debian's package, unpacked (no initrd builds)
	[ -n "$vmlinuz" ] || vmlinuz="$out/image/boot/vmlinuz-$kver"
	if [ ! -f "$vmlinuz" ]; then
		say "$kver: fetching linux-image-$kver"
		(cd "$out" && rm -f ./*.deb && apt-get download -q "linux-image-$kver" >/dev/null 2>&1) ||
			die "apt-get download linux-image-$kver failed"
		# only the kernel: the guest needs none of Debian's modules
		mkdir -p "$out/image"
		dpkg-deb --fsys-tarfile "$out"/linux-image-"$kver"_*.deb |
			tar -x -C "$out/image" "./boot/vmlinuz-$kver"
		rm -f "$out"/*.deb
	fi

	# the modules, W=1, from copies (kmod's symlinks followed)
	rm -rf "$out/kmod" "$out/vspi" "$out/ko"
	cp -rL "$top/kmod" "$out/kmod"
	cp -r "$top/tests/kernel/modules" "$out/vspi"
	mkdir -p "$out/ko"
	for m in kmod vspi; do
		make -s -C "$kdir" M="$out/$m" W=1 modules >"$out/$m.log" 2>&1 ||
			{ cat "$out/$m.log" >&2; die "$kver: building $m failed"; }
		if grep -E 'warning:|error:' "$out/$m.log"; then
			die "$kver: building $m gave warnings"
		fi
		cp "$out/$m"/*.ko "$out/ko/"
	done

	"$top/tests/kernel/mkinitramfs.sh" "$out/initramfs.cpio.gz" "$top/tests/kernel/guest-init.sh" \
		"$out/ko" "$top/tests/kernel/steps" "$bin"/ecmxf-*

	log="$out/console-$mode.log"
	say "$kver: booting under QEMU (TCG, mode $mode), console in $log"
	rc=0
	timeout "$timeout_f" qemu-system-x86_64 -accel tcg -m "$mem" -smp 2 -nographic -no-reboot \
		-nic none -kernel "$vmlinuz" -initrd "$out/initramfs.cpio.gz" \
		-append "console=ttyS0 panic=-1 loglevel=7 ecmxf_ktest=$mode$fuzz_append" >"$log" 2>&1 || rc=$?
	tr -d '\r' <"$log" >"$log.txt"
	grep -E '^(ECMXF-KTEST|guest-test|bench|bridge|sysfs|fuzz):' "$log.txt" || true
	[ "$rc" -eq 124 ] && die "$kver: QEMU did not finish within ${timeout_f}s (see $log)"
	# not a bare "lockdep": the debug kernel prints "RCU lockdep checking is
	# enabled" at every boot; lockdep's reports all carry WARNING:/BUG:
	bad=$(grep -nE 'WARNING:|BUG:|Oops|Call Trace|sleeping function called from invalid context|possible circular locking|possible recursive locking|locking correctness validator|lockdep is turned off|KASAN|UBSAN|general protection fault|kernel panic|Kernel panic' \
		"$log.txt" || true)
	if [ -n "$bad" ]; then
		echo "$bad" >&2
		die "$kver: kernel warnings on the console (see $log)"
	fi
	grep -qx 'ECMXF-KTEST: PASS' "$log.txt" || die "$kver: no pass marker on the console (see $log)"
	say "$kver: PASS${ECMXF_KTEST_STEPS:+ (only the steps $ECMXF_KTEST_STEPS)}"
}

for f in $flavours; do
	run_flavour "$f"
done
say "all passed ($mode: $flavours)"
