#!/bin/sh
# SPDX-License-Identifier: MIT
# The install prefix reaches one object only: lib/sim/network.cpp, through
# the generated ecmxf_network_dir.h (the installed networks' directory).
# No target's compile flags hold it, so another PREFIX (make install
# PREFIX=X, then make demo) does not recompile the library. Reads the
# build tree's generated Makefiles (skipped, 77, for other generators).
#
#   test-prefix-objects.sh BUILD-DIR
set -eu
build=$1
fail() { echo "FAIL: $*"; exit 1; }
prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build/CMakeCache.txt")
[ -n "$prefix" ] || fail "no CMAKE_INSTALL_PREFIX in $build/CMakeCache.txt"
ls "$build"/lib/CMakeFiles/*/flags.make >/dev/null 2>&1 || { echo "not a Makefile build: skipped"; exit 77; }
# a change of a target's flags.make recompiles every object of the target
bad=$(grep -l -e "ECMXF_NETWORK_DIR" -e "$prefix/share" "$build"/lib/CMakeFiles/*/flags.make || true)
[ -z "$bad" ] || fail "the prefix is in the compile flags of: $bad"
hdr="$build/lib/generated/ecmxf_network_dir.h"
grep -qF "\"$prefix/share/ecmxf/networks\"" "$hdr" || fail "$hdr does not name $prefix/share/ecmxf/networks"
users=$(grep -rl 'ecmxf_network_dir.h' "$(dirname "$0")/../../lib" --include='*.cpp' --include='*.hpp' || true)
[ "$(echo "$users" | wc -l)" -eq 1 ] && case $users in */lib/sim/network.cpp) true ;; *) false ;; esac ||
	fail "ecmxf_network_dir.h is included by: $users (lib/sim/network.cpp alone should)"
echo "ok: the prefix ($prefix) reaches lib/sim/network.cpp alone, through $hdr"
