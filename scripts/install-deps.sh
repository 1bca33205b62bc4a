#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Install what ecmxf needs from Debian bookworm, idempotently.
#
#   scripts/install-deps.sh            build + test dependencies
#   scripts/install-deps.sh --ci       also clang (fuzzing, sanitizers)
#   scripts/install-deps.sh --bench    also Google Benchmark and stress-ng (the
#                                      guest bench under load)
#   scripts/install-deps.sh --stress   also stress-ng (make check-stress)
#   scripts/install-deps.sh --kernel   also Debian's 6.1 kernel headers, normal
#                                      and PREEMPT_RT (make kmod), sparse, the
#                                      DT tools (make dt-check), and pahole
#                                      (Kbuild of the 6.12 kernels runs it)
#   scripts/install-deps.sh --qemu     also QEMU, busybox, cpio, the i386 cross
#                                      compiler (make check-kernel)
#   scripts/install-deps.sh --arm64    also the arm64 side of make check-kernels
#                                      and make kmod-check-arm64: dpkg's arm64
#                                      architecture, the cross toolchains
#                                      (crossbuild-essential-arm64, -armhf for
#                                      the 32-bit uAPI test), the :arm64
#                                      -dev packages the guest programs link,
#                                      and qemu-system-aarch64
#   scripts/install-deps.sh --deb      also debhelper, dh-dkms, dkms, dh-python, lintian
#                                      (make deb, make check-deb)
#   scripts/install-deps.sh --debug-kernel
#                                      also linux-source-6.1 and what building
#                                      it takes (make check-debug-kernel)
#
# It asks dpkg first and calls apt-get only for what is missing, so
# running it on every `make` costs a few milliseconds.
set -eu

# the Python binding (lib/python, tests/python): pybind11, the headers,
# pytest and numpy (the buffer-protocol tests); the scope's SVG checked by
# xmllint (libxml2-utils) and rendered by rsvg-convert (librsvg2-bin); the
# pcapng traces read by tshark with the generated Lua dissector
# (tests/trace, Documentation/trace.rst)
pkgs="build-essential cmake pkg-config catch2 libgpiod-dev libmnl-dev python3-docutils pybind11-dev python3-dev python3-pytest python3-numpy libxml2-utils librsvg2-bin tshark"
arm64=""
for arg in "$@"; do
	case "$arg" in
	--ci) pkgs="$pkgs clang libclang-rt-14-dev llvm" ;;
	--bench) pkgs="$pkgs libbenchmark-dev stress-ng" ;;
	--stress) pkgs="$pkgs stress-ng" ;;
	--kernel) pkgs="$pkgs linux-headers-amd64 linux-headers-rt-amd64 kmod sparse dt-schema device-tree-compiler pahole" ;;
	# crossbuild-essential-i386: the guest's 32-bit uAPI test (compat_ioctl)
	--qemu) pkgs="$pkgs qemu-system-x86 busybox-static cpio crossbuild-essential-i386" ;;
	# the arm64 kernels' headers and images are not installed but
	# unpacked from their .debs (scripts/debian-kernel.sh)
	--arm64)
		arm64=1
		pkgs="$pkgs crossbuild-essential-arm64 crossbuild-essential-armhf libgpiod-dev:arm64 libmnl-dev:arm64 qemu-system-arm busybox-static cpio"
		;;
	--deb) pkgs="$pkgs debhelper dh-dkms dkms dh-python lintian fakeroot adduser man-db" ;;
	--debug-kernel) pkgs="$pkgs linux-source-6.1 flex bison bc libelf-dev libssl-dev cpio xz-utils kmod" ;;
	*) echo "install-deps.sh: unknown option '$arg'" >&2; exit 2 ;;
	esac
done

missing=""
for p in $pkgs; do
	status=$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null || true)
	case "$status" in
	ii*) ;;
	*) missing="$missing $p" ;;
	esac
done
[ -z "$missing" ] && exit 0

if [ "$(id -u)" -ne 0 ]; then
	echo "install-deps.sh: missing packages:$missing" >&2
	echo "install-deps.sh: run as root (or: sudo apt-get install$missing)" >&2
	exit 1
fi
echo "install-deps.sh: installing$missing"
export DEBIAN_FRONTEND=noninteractive
# the :arm64 packages: apt must know dpkg's arm64 architecture first
if [ -n "$arm64" ] && ! dpkg --print-foreign-architectures | grep -qx arm64; then
	echo "install-deps.sh: dpkg --add-architecture arm64"
	dpkg --add-architecture arm64
fi
# tshark's wireshark-common asks whether non-root users may capture
# (a setuid dumpcap): no, and no question
echo "wireshark-common wireshark-common/install-setuid boolean false" | debconf-set-selections
apt-get update -qq
# shellcheck disable=SC2086
apt-get install -y -qq --no-install-recommends $missing
