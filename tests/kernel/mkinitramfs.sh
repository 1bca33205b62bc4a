#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Pack the initramfs of the QEMU kernel tests (Documentation/kernel-testing.rst):
#
#   tests/kernel/mkinitramfs.sh <out.cpio.gz> <init-script> <modules-dir> <steps-dir> <bin>...
#
# busybox (static) with a symlink per applet, <init-script> as /init, the
# *.ko of <modules-dir> in /lib/modules, <steps-dir> as /steps, each <bin>
# in /bin.
set -eu

[ $# -ge 4 ] || { echo "usage: $0 out.cpio.gz init modules-dir steps-dir [bin...]" >&2; exit 2; }
out=$1 init=$2 mods=$3 steps=$4
shift 4

bb=/bin/busybox
[ -x "$bb" ] || { echo "mkinitramfs: $bb missing (apt-get install busybox-static)" >&2; exit 1; }
# the guest's busybox: another architecture's (ECMXF_GUEST_BUSYBOX, e.g.
# busybox-static:arm64's, unpacked) when the guest is not this machine's;
# its applets are this machine's busybox's list (the same Debian package)
gbb=${ECMXF_GUEST_BUSYBOX:-$bb}
[ -f "$gbb" ] || { echo "mkinitramfs: $gbb missing" >&2; exit 1; }

root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
mkdir -p "$root/bin" "$root/sbin" "$root/proc" "$root/sys" "$root/dev" "$root/tmp" \
	"$root/lib/modules" "$root/etc"
# mktemp -d made the root 0700: the guest's unprivileged users (the
# permission tests) must be able to reach /dev and /bin
chmod 755 "$root"
chmod 1777 "$root/tmp"
cp "$gbb" "$root/bin/busybox"
# `busybox --list` names busybox itself: a symlink for it would replace
# the binary (then: "No working init found", error -40)
for a in $("$bb" --list); do
	[ "$a" = busybox ] && continue
	ln -sf busybox "$root/bin/$a"
done
cp "$init" "$root/init"
chmod 755 "$root/init"
cp "$mods"/*.ko "$root/lib/modules/"
cp -r "$steps" "$root/steps"
for b in "$@"; do
	cp "$b" "$root/bin/"
done
# a dynamically linked program (ecmxf-util: libmnl has no static library
# in Debian) brings its shared libraries and loader: a program of this
# machine's architecture at the paths ldd names; an arm64 program (ldd
# cannot run it) by its ELF loader and DT_NEEDED entries, recursively,
# found in Debian's multiarch directories of the :arm64 packages
copy_lib() {
	mkdir -p "$root$(dirname "$1")"
	cp -L "$1" "$root$1"
}
arm64_needed() {
	for n in $(readelf -d "$1" 2>/dev/null | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
		[ -e "$root/lib/aarch64-linux-gnu/$n" ] && continue
		f=""
		for d in /lib/aarch64-linux-gnu /usr/lib/aarch64-linux-gnu; do
			[ -e "$d/$n" ] && { f=$d/$n; break; }
		done
		[ -n "$f" ] || { echo "mkinitramfs: $n (of $1) not found (apt-get install its :arm64 package)" >&2; exit 1; }
		mkdir -p "$root/lib/aarch64-linux-gnu"
		cp -L "$f" "$root/lib/aarch64-linux-gnu/$n"
		arm64_needed "$f"
	done
}
for b in "$@"; do
	if ldd "$b" >/dev/null 2>&1; then
		for l in $(ldd "$b" | grep -o '/[^ ]*'); do
			copy_lib "$l"
		done
	elif readelf -h "$b" 2>/dev/null | grep -q 'AArch64' &&
		readelf -l "$b" | grep -q 'interpreter'; then
		interp=$(readelf -l "$b" | sed -n 's/.*interpreter: \(.*\)\]/\1/p')
		copy_lib "$interp"
		arm64_needed "$b"
	fi	# else static: nothing to bring
done
(cd "$root" && find . -print0 | cpio --null -o -H newc --quiet) | gzip -1 >"$out"
