#!/bin/sh
# SPDX-License-Identifier: MIT
#
# scripts/check-layers.py on small trees, one per rule: each bad tree must
# fail with the message that names the fault, the good one must pass.
# Usage: test-check-layers.sh PATH/TO/check-layers.py
set -u
script=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0

# a tree of three layers: base < link < device
mktree() {
	rm -rf "$tmp/t"
	mkdir -p "$tmp/t/Documentation" "$tmp/t/lib/base" "$tmp/t/lib/link" "$tmp/t/lib/device" \
		"$tmp/t/include/ecmxf/link"
	cat >"$tmp/t/Documentation/architecture.rst" <<'DOC'
Layers
======

.. layer table begin

::

  base     lib/base include/ecmxf/error.hpp
  link     lib/link include/ecmxf/link
  device   lib/device include/ecmxf/device.hpp

.. layer table end

.. syscall ioctl lib/link/kernel_link.cpp
.. syscall mmap lib/base/os.cpp
DOC
	printf '#pragma once\n' >"$tmp/t/include/ecmxf/error.hpp"
	printf '#pragma once\n#include <ecmxf/error.hpp>\n' >"$tmp/t/include/ecmxf/link/link.hpp"
	printf '#pragma once\n#include <ecmxf/link/link.hpp>\n' >"$tmp/t/include/ecmxf/device.hpp"
	printf '#include <ecmxf/error.hpp>\n#include "base/os.hpp"\nint f() { return ::mmap(0); }\n' \
		>"$tmp/t/lib/base/os.cpp"
	printf '#pragma once\n' >"$tmp/t/lib/base/os.hpp"
	printf '#include <ecmxf/link/link.hpp>\n#include "base/os.hpp"\n// ioctl() in a comment\nint g() { return ::ioctl(1); }\n' \
		>"$tmp/t/lib/link/kernel_link.cpp"
	printf '#include <ecmxf/device.hpp>\n#include <ecmxf/link/link.hpp>\nconst char *s = "ioctl(";\n' \
		>"$tmp/t/lib/device/device.cpp"
}

# expect NAME EXIT-STATUS PATTERN: run the check on the tree
expect() {
	out=$(python3 "$script" --root "$tmp/t" 2>&1)
	rc=$?
	if [ "$rc" -ne "$2" ] || ! printf '%s\n' "$out" | grep -q -- "$3"; then
		echo "FAIL $1: exit $rc (want $2), output:"
		printf '%s\n' "$out" | sed 's/^/    /'
		failures=$((failures + 1))
	else
		echo "ok   $1"
		passed=$((passed + 1))
	fi
}

mktree
expect "good tree" 0 "3 layers (base < link < device), 7 files, .* 0 cycles between folders, 0 violations"

mktree
printf '#include <ecmxf/device.hpp>\n' >>"$tmp/t/lib/link/kernel_link.cpp"
expect "back-arrow" 1 "lib/link/kernel_link.cpp:5: back-arrow: layer 'link' includes include/ecmxf/device.hpp of layer 'device'"

mktree
printf '#include "device/x.hpp"\n' >"$tmp/t/lib/base/cyc.cpp"
printf '#pragma once\n#include "base/os.hpp"\n' >"$tmp/t/lib/device/x.hpp"
expect "cycle between folders" 1 "include cycle between folders: lib/base <-> lib/device"

mktree
mkdir -p "$tmp/t/lib/extra"
printf 'int x;\n' >"$tmp/t/lib/extra/x.cpp"
expect "file in no layer" 1 "lib/extra/x.cpp: in no layer"

mktree
printf 'void h(Link *l) { auto *k = dynamic_cast<KernelLink *>(l); }\n' >>"$tmp/t/lib/device/device.cpp"
expect "downcast of a link" 1 "lib/device/device.cpp:4: downcast to KernelLink outside lib/link/"

mktree
printf 'void h(ByteChannel &c) { static_cast<const SpidevChannel &>(c); }\n' >>"$tmp/t/lib/device/device.cpp"
expect "downcast of a channel" 1 "downcast to SpidevChannel outside lib/link/"

mktree
printf 'int k() { return ioctl(3, 4); }\n' >>"$tmp/t/lib/device/device.cpp"
expect "ioctl out of its place" 1 "lib/device/device.cpp:4: ioctl() outside lib/link/kernel_link.cpp"

mktree
printf 'int m() { return ::mmap(0); }\n' >>"$tmp/t/lib/link/kernel_link.cpp"
expect "mmap out of its place" 1 "lib/link/kernel_link.cpp:5: mmap() outside lib/base/os.cpp"

mktree
sed -i '/layer table begin/d' "$tmp/t/Documentation/architecture.rst"
expect "no table" 2 "no layer table"

mktree
printf '  base     lib/x\n' >"$tmp/t/row"
sed -i '/^  device/r '"$tmp/t/row" "$tmp/t/Documentation/architecture.rst"
rm "$tmp/t/row"
expect "layer named twice" 2 "a layer is named twice"

mktree
rm "$tmp/t/Documentation/architecture.rst"
expect "no page" 2 "cannot read"

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
