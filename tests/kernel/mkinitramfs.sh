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

root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
mkdir -p "$root/bin" "$root/sbin" "$root/proc" "$root/sys" "$root/dev" "$root/tmp" \
	"$root/lib/modules" "$root/etc"
# mktemp -d made the root 0700: the guest's unprivileged users (the
# permission tests) must be able to reach /dev and /bin
chmod 755 "$root"
chmod 1777 "$root/tmp"
cp "$bb" "$root/bin/busybox"
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
# in Debian) brings its shared libraries and loader, at the paths ldd names
for b in "$@"; do
	ldd "$b" >/dev/null 2>&1 || continue	# static: "not a dynamic executable"
	for l in $(ldd "$b" | grep -o '/[^ ]*'); do
		mkdir -p "$root$(dirname "$l")"
		cp -L "$l" "$root$l"
	done
done
(cd "$root" && find . -print0 | cpio --null -o -H newc --quiet) | gzip -1 >"$out"
