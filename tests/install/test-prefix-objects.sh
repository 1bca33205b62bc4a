#!/bin/sh
# SPDX-License-Identifier: MIT
# The install prefix is compiled into one object only (lib/sim/network.cpp,
# the installed networks' directory): another PREFIX (make install
# PREFIX=X, then make demo) must not recompile the library. Reads the
# build tree's generated Makefiles (skipped, 77, for other generators).
#
#   test-prefix-objects.sh BUILD-DIR
set -eu
build=$1
fail() { echo "FAIL: $*"; exit 1; }
prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build/CMakeCache.txt")
[ -n "$prefix" ] || fail "no CMAKE_INSTALL_PREFIX in $build/CMakeCache.txt"
ls "$build"/lib/CMakeFiles/*/flags.make >/dev/null 2>&1 || { echo "not a Makefile build: skipped"; exit 77; }
# the flags every object of a target is compiled with
# (not the comment lines: CMake lists the per-source defines there)
bad=$(for f in "$build"/lib/CMakeFiles/*/flags.make; do
	grep -v '^#' "$f" | grep -q -e "ECMXF_NETWORK_DIR" -e "$prefix/share" && echo "$f"
done || true)
[ -z "$bad" ] || fail "the prefix is in the flags of every object of: $bad"
# network.cpp alone has it
n=$(grep -c 'ECMXF_NETWORK_DIR' "$build/lib/CMakeFiles/ecmxf_sim.dir/build.make" || true)
[ "$n" -ge 1 ] || fail "lib/sim/network.cpp is not compiled with ECMXF_NETWORK_DIR"
others=$(grep -rl 'ECMXF_NETWORK_DIR' "$build"/lib/CMakeFiles/*/build.make | grep -v '/ecmxf_sim.dir/' || true)
[ -z "$others" ] || fail "other objects compiled with the prefix: $others"
echo "ok: the prefix ($prefix) is compiled into lib/sim/network.cpp alone"
