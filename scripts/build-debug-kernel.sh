#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Build (once) the debug kernel of `make check-debug-kernel`
# (Documentation/kernel-testing.rst, "The debug kernel"):
#
#   scripts/build-debug-kernel.sh
#
# Debian's linux-source-6.1, `make allnoconfig` plus the fragment
# tests/kernel/debug.config (KASAN, UBSAN, PROVE_LOCKING,
# DEBUG_ATOMIC_SLEEP, ... and only what the QEMU guest tests need), built
# in ${ECMXF_KTEST_CACHE:-/var/tmp/ecmxf-ktest}/debug-<key>, where <key>
# hashes the fragment, the linux-source-6.1 package version, the compiler
# and this script. A finished build (its stamp file, written last) is
# reused as it is: a second call costs well under a second. Installs the
# Debian packages it needs when they are missing (as root).
#
# Progress goes to stderr, the build log to <dir>/build.log. On success,
# stdout is exactly:
#
#   KVER=<kernel release>
#   KDIR=<tree for `make -C $KDIR M=<dir> modules`>
#   VMLINUZ=<bzImage>
#
# Environment: ECMXF_KTEST_CACHE (see above), ECMXF_KTEST_JOBS (make -j,
# default nproc).
set -eu

# stdout carries only the three result lines: everything else to stderr
exec 3>&1 1>&2

top=$(cd "$(dirname "$0")/.." && pwd)
self="$top/scripts/build-debug-kernel.sh"
frag="$top/tests/kernel/debug.config"
tarball=/usr/src/linux-source-6.1.tar.xz
cache=${ECMXF_KTEST_CACHE:-/var/tmp/ecmxf-ktest}
jobs=${ECMXF_KTEST_JOBS:-$(nproc 2>/dev/null || echo 2)}

say() { echo "build-debug-kernel: $*"; }
die() { echo "build-debug-kernel: $*"; exit 1; }

[ -f "$frag" ] || die "$frag missing"

# ---- packages: the source and what building it takes
need=""
for p in linux-source-6.1 build-essential flex bison bc libelf-dev libssl-dev cpio xz-utils kmod; do
	dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null | grep -q '^ii' || need="$need $p"
done
if [ -n "$need" ]; then
	[ "$(id -u)" -eq 0 ] || die "missing packages:$need (run as root)"
	say "installing$need"
	export DEBIAN_FRONTEND=noninteractive
	apt-get update -qq
	# shellcheck disable=SC2086
	apt-get install -y -qq --no-install-recommends $need </dev/null >/dev/null
fi
[ -f "$tarball" ] || die "$tarball missing after installing linux-source-6.1"

# ---- the cache key: what the build depends on
srcver=$(dpkg-query -W -f='${Version}' linux-source-6.1)
ccver=$(gcc --version | head -n 1)
key=$({
	cat "$frag"
	echo "linux-source-6.1 $srcver"
	echo "$ccver"
	cat "$self"
} | sha256sum | cut -c1-12)
dir="$cache/debug-$key"
src="$dir/linux"
log="$dir/build.log"
stamp="$dir/stamp"

result() {
	kver=$(cat "$dir/kernelrelease")
	printf 'KVER=%s\nKDIR=%s\nVMLINUZ=%s\n' "$kver" "$src" "$src/arch/x86/boot/bzImage" >&3
}

if [ -f "$stamp" ]; then
	say "cached: $dir"
	result
	exit 0
fi

mkdir -p "$dir"
# one build at a time per key; a second caller waits and then finds the stamp
exec 9>"$dir/lock"
flock 9
if [ -f "$stamp" ]; then
	say "cached: $dir (built while waiting)"
	result
	exit 0
fi

start=$(date +%s)
say "no finished build under $dir: building (linux-source-6.1 $srcver, $jobs jobs; log: $log)"

# the make of a caller (the top-level Makefile) must not leak in:
# variables such as W=1 or C=2 would reach every kernel object
kmake() {
	env -u MAKEFLAGS -u MAKELEVEL -u MFLAGS -u KBUILD_OUTPUT -u ARCH -u CROSS_COMPILE \
		KBUILD_BUILD_USER=ecmxf KBUILD_BUILD_HOST=ktest \
		make -C "$src" "$@"
}

fail() {
	echo "build-debug-kernel: $* failed; the end of $log:"
	tail -n 40 "$log"
	exit 1
}

# the source, unpacked whole (an interrupted unpack is started again)
if [ ! -f "$src/Makefile" ]; then
	rm -rf "$src" "$dir/unpack"
	mkdir -p "$dir/unpack"
	say "unpacking $tarball"
	tar -xf "$tarball" -C "$dir/unpack"
	mv "$dir/unpack/linux-source-6.1" "$src"
	rmdir "$dir/unpack"
fi

# the configuration: allnoconfig + the fragment, then every line of the
# fragment must hold in the result
: >"$log"
say "configuring: allnoconfig + ${frag#"$top"/}"
kmake KCONFIG_ALLCONFIG="$frag" allnoconfig >>"$log" 2>&1 || fail "make allnoconfig"
kmake olddefconfig >>"$log" 2>&1 || fail "make olddefconfig"
bad=""
while IFS= read -r line; do
	case "$line" in
	CONFIG_*=*)
		sym=${line%%=*}
		grep -qxF "$line" "$src/.config" ||
			bad="$bad
  wanted $line, got: $(grep "^$sym=" "$src/.config" || echo "# $sym is not set")"
		;;
	"# CONFIG_"*" is not set")
		sym=${line#"# "}
		sym=${sym%% *}
		if grep -q "^$sym=" "$src/.config"; then
			bad="$bad
  wanted $sym off, got: $(grep "^$sym=" "$src/.config")"
		fi
		;;
	esac
done <"$frag"
[ -z "$bad" ] || die "the configuration lacks options of ${frag#"$top"/} (a dependency missing?):$bad"

# the kernel and the modules (Module.symvers, scripts and headers for
# out-of-tree modules)
say "building bzImage and modules (some minutes)"
kmake -j "$jobs" bzImage modules >>"$log" 2>&1 || fail "the kernel build"
cp "$src/include/config/kernel.release" "$dir/kernelrelease" || fail "the kernel build (no kernel.release)"
[ -f "$src/arch/x86/boot/bzImage" ] || fail "the kernel build (no bzImage)"
[ -f "$src/Module.symvers" ] || fail "the kernel build (no Module.symvers)"

# the intermediate link outputs are large and nothing needs them again
rm -f "$src/vmlinux.o" "$src"/.tmp_vmlinux*

date -u +%Y-%m-%dT%H:%M:%SZ >"$stamp"
say "built $(cat "$dir/kernelrelease") in $(($(date +%s) - start)) s, $(du -sh "$dir" | cut -f1) in $dir"
result
