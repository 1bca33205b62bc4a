#!/bin/sh
# SPDX-License-Identifier: MIT
#
# One of Debian bookworm's kernels, ready to build modules against and to
# boot under QEMU (Documentation/kernel-testing.rst, "The kernel matrix";
# Documentation/kernel-build.rst, "Cross-building for a board"):
#
#   scripts/debian-kernel.sh <series>-<flavour>
#
#   <series>   6.1 (bookworm's own kernel) or 6.12 (bookworm's newer one)
#   <flavour>  amd64, rt-amd64, arm64, rt-arm64
#
# e.g. 6.1-amd64, 6.12-rt-arm64.  The kernel is the one the Debian
# meta-package names: linux-headers-<flavour> for 6.1,
# linux-headers-6.12-<flavour> for 6.12; never a fixed ABI name.
#
# When that meta-package is installed for this machine's architecture
# (scripts/install-deps.sh --kernel installs 6.1 amd64 and rt-amd64), its
# kernel's installed headers are used.  Otherwise nothing is installed:
# the header packages are fetched with `apt-get download` and unpacked
# under ${ECMXF_KTEST_CACHE:-/var/tmp/ecmxf-ktest}/<kver>/headers:
#   linux-headers-<kver> (.config, Module.symvers, generated headers),
#   linux-headers-<...>-common[-rt] (the source headers and Makefiles),
#   linux-kbuild-<...> for THIS machine's architecture (fixdep, modpost,
#   genksyms, ...: Kbuild's host programs).
# Debian's header packages carry no host programs of their own, they
# link to the linux-kbuild package (Multi-Arch: foreign), so an arm64
# header tree with amd64's linux-kbuild is a working cross-build tree: no
# `modules_prepare` and no linux-source needed.  apt cannot install it
# (linux-headers-*-arm64 depends on gcc-12:arm64, which would replace the
# native compiler), hence the unpacking.  Cross-building against it:
#
#   make -C <KDIR> M=$PWD/kmod ARCH=arm64 CROSS_COMPILE=aarch64-linux-gnu- modules
#
# The kernel image (and, for the arm64 guests, the modules they load) come
# from linux-image-<kver>, unpacked under <cache>/<kver>/image.  Both are
# fetched once; a second call costs well under a second.
#
# Progress goes to stderr.  On success, stdout is exactly:
#
#   KVER=<kernel release, e.g. 6.12.117+deb12-rt-arm64>
#   KDIR=<header tree for `make -C $KDIR M=<dir> modules`>
#   VMLINUZ=<the kernel image>
#   DEB_ARCH=<Debian architecture: amd64 or arm64>
#   MODULES=<the image's /lib/modules/<kver> (unpacked; arm64 only)>
#   DTBS=<the image's device trees, /usr/lib/linux-image-<kver> (arm64 only)>
#
# --headers-only skips the image (VMLINUZ=, MODULES=, DTBS= are then empty).
set -eu

exec 3>&1 1>&2

cache=${ECMXF_KTEST_CACHE:-/var/tmp/ecmxf-ktest}
say() { echo "debian-kernel: $*"; }
die() { echo "debian-kernel: $*"; exit 1; }

headers_only=""
if [ "${1:-}" = --headers-only ]; then
	headers_only=1
	shift
fi
[ $# -eq 1 ] || die "usage: $0 [--headers-only] <6.1|6.12>-<amd64|rt-amd64|arm64|rt-arm64>"
name=$1
series=${name%%-*}
flavour=${name#*-}
case "$series" in
6.1) meta=linux-headers-$flavour ;;
6.12) meta=linux-headers-6.12-$flavour ;;
*) die "unknown kernel series '$series' in '$name' (6.1 or 6.12)" ;;
esac
case "$flavour" in
amd64 | rt-amd64) arch=amd64 ;;
arm64 | rt-arm64) arch=arm64 ;;
*) die "unknown flavour '$flavour' in '$name' (amd64, rt-amd64, arm64, rt-arm64)" ;;
esac
host=$(dpkg --print-architecture)

# the package names a Depends: field lists (versions and alternatives off)
deps_of() {
	printf '%s\n' "$1" | tr ',' '\n' | sed 's/|.*//; s/(.*//; s/:.*//; s/[[:space:]]//g' | sed '/^$/d'
}

# apt's package lists must know the other architecture's packages
if [ "$arch" != "$host" ] && ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
	[ "$(id -u)" -eq 0 ] || die "dpkg does not know the architecture $arch (as root: dpkg --add-architecture $arch; apt-get update)"
	say "dpkg --add-architecture $arch"
	dpkg --add-architecture "$arch"
	apt-get update -qq
fi

# ---- which kernel: the meta-package's dependency
installed=""
if [ "$arch" = "$host" ] &&
	dpkg-query -W -f='${db:Status-Abbrev}' "$meta" 2>/dev/null | grep -q '^ii'; then
	installed=1
	hpkg=$(deps_of "$(dpkg-query -W -f='${Depends}' "$meta")" | grep '^linux-headers-' | head -n 1)
else
	field=$(apt-cache show --no-all-versions "$meta:$arch" 2>/dev/null | sed -n 's/^Depends: //p' | head -n 1)
	[ -n "$field" ] || die "apt knows no package $meta:$arch (apt-get update?)"
	hpkg=$(deps_of "$field" | grep '^linux-headers-' | head -n 1)
fi
kver=${hpkg#linux-headers-}
[ -n "$kver" ] && [ "$kver" != "$hpkg" ] || die "cannot tell the kernel of $meta"
out="$cache/$kver"
mkdir -p "$out"

# fetch <dir> <package:arch>...: apt-get download into <dir>, once
fetch() {
	dir=$1
	shift
	mkdir -p "$dir"
	for p in "$@"; do
		n=${p%%:*}
		ls "$dir/${n}_"*.deb >/dev/null 2>&1 && continue
		say "$kver: fetching $p"
		(cd "$dir" && apt-get download -q "$p" >/dev/null 2>&1) || die "apt-get download $p failed"
	done
}

# ---- the header tree
if [ -n "$installed" ]; then
	kdir=/lib/modules/$kver/build
	[ -f "$kdir/Makefile" ] || die "$hpkg is installed but $kdir has no Makefile"
else
	root="$out/headers"
	kdir="$root/usr/src/linux-headers-$kver"
	if [ ! -f "$root/.stamp" ]; then
		rm -rf "$root" "$out/debs-headers"
		hfield=$(apt-cache show --no-all-versions "$hpkg:$arch" | sed -n 's/^Depends: //p' | head -n 1)
		pkgs="$hpkg:$arch"
		for d in $(deps_of "$hfield"); do
			case "$d" in
			# the source headers: Architecture all
			linux-headers-*) pkgs="$pkgs $d" ;;
			# Kbuild's host programs: this machine's architecture
			linux-kbuild-*) pkgs="$pkgs $d:$host" ;;
			esac
		done
		fetch "$out/debs-headers" $pkgs
		mkdir -p "$root"
		for deb in "$out/debs-headers"/*.deb; do
			dpkg-deb -x "$deb" "$root"
		done
		# the flavour's Makefile includes the common tree by its
		# absolute /usr/src path; the other links are relative
		sed -i "s|^include /usr/src/|include $root/usr/src/|" "$kdir/Makefile"
		[ -x "$kdir/scripts/basic/fixdep" ] || die "$kdir: no scripts/basic/fixdep after unpacking"
		rm -rf "$out/debs-headers"
		touch "$root/.stamp"
	fi
fi

# ---- the image (and its modules)
vmlinuz=""
modules=""
dtbs=""
if [ -z "$headers_only" ]; then
	vmlinuz="$out/image/boot/vmlinuz-$kver"
	modules="$out/image/lib/modules/$kver"
	dtbs="$out/image/usr/lib/linux-image-$kver"
	if { [ "$arch" = "$host" ] && [ ! -f "$vmlinuz" ]; } ||
		{ [ "$arch" != "$host" ] && { [ ! -f "$out/image/.stamp" ] || [ ! -d "$dtbs" ]; }; }; then
		rm -rf "$out/image" "$out/debs-image"
		fetch "$out/debs-image" "linux-image-$kver:$arch"
		mkdir -p "$out/image"
		if [ "$arch" = "$host" ]; then
			# only the kernel: the amd64 guests load none of Debian's modules
			dpkg-deb --fsys-tarfile "$out"/debs-image/*.deb |
				tar -x -C "$out/image" "./boot/vmlinuz-$kver"
		else
			dpkg-deb --fsys-tarfile "$out"/debs-image/*.deb |
				tar -x -C "$out/image" "./boot/vmlinuz-$kver" "./lib/modules/$kver" \
				"./usr/lib/linux-image-$kver"
		fi
		rm -rf "$out/debs-image"
		touch "$out/image/.stamp"
	fi
	[ -f "$vmlinuz" ] || die "$vmlinuz missing after unpacking"
	[ -d "$modules" ] || modules=""
	[ -d "$dtbs" ] || dtbs=""
fi

printf 'KVER=%s\nKDIR=%s\nVMLINUZ=%s\nDEB_ARCH=%s\nMODULES=%s\nDTBS=%s\n' "$kver" "$kdir" "$vmlinuz" "$arch" "$modules" "$dtbs" >&3
