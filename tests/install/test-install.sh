#!/bin/sh
# SPDX-License-Identifier: MIT
# `cmake --install` of a built tree into a temporary prefix installs the
# library, headers, pkg-config and CMake files, the simulator networks,
# ecmxf-util, ecmxf-sim, the man pages and the bash completion.  Against
# the installed tree: a consumer project (tests/install/consumer) builds
# with CMake (find_package, ecmxf::ecmxf, no C++ standard of its own) and
# the same program with pkg-config alone, and both open "sim:"; below
# C++20 the headers stop with one #error; the installed ecmxf-util and
# ecmxf-sim start without LD_LIBRARY_PATH (RUNPATH $ORIGIN/../LIBDIR);
# the Python package (when built) imports from the prefix.
#
#   test-install.sh BUILD-DIR PREFIX CXX [EXTRA-FLAGS]
#
# EXTRA-FLAGS: what the build's own programs were compiled with that the
# tiny program needs too (-fsanitize=... in a sanitizer build, whose
# libecmxf needs the sanitizer runtime linked first).
set -eu
build=$1 prefix=$2 cxx=$3 extra=${4:-}

fail() { echo "FAIL: $*"; exit 1; }

rm -rf "$prefix"
cmake --install "$build" --prefix "$prefix" >"$prefix.log" 2>&1 ||
	{ cat "$prefix.log"; fail "cmake --install $build --prefix $prefix"; }

# one path per pattern, relative to the prefix (lib may be lib64 or lib/<triplet>)
need() {
	found=$(cd "$prefix" && find . -path "./$1" | head -n 1)
	[ -n "$found" ] || fail "nothing installed at $1"
	echo "ok: $found"
}
need 'lib*/libecmxf.so'
need 'lib*/libecmxf.so.0'
need 'include/ecmxf/device.hpp'
need 'include/ecmxf/link/link.hpp'
need 'include/ecmxf/link/sim_channel.hpp'
need 'include/linux/ecmxf.h'
need 'include/linux/ecmxf_netlink.h'
need 'include/ecmxf/events/events.hpp'
need 'lib*/pkgconfig/ecmxf.pc'
need 'lib*/cmake/ecmxf/ecmxfConfig.cmake'
need 'lib*/cmake/ecmxf/ecmxfConfigVersion.cmake'
need 'share/ecmxf/networks/est584x2-io.net'
need 'share/ecmxf/networks/servo-io.net'
need 'bin/ecmxf-util'
need 'bin/ecmxf-sim'
need 'share/man/man1/ecmxf-util.1'
need 'share/man/man1/ecmxf-sim.1'
need 'share/man/man1/ecmxf-demo.1'
need 'share/bash-completion/completions/ecmxf-util'
# nothing of the tests or internals
[ -z "$(cd "$prefix" && find . -name 'ecmxf-proto.h' -o -name 'catch*' -o -name 'test-*')" ] ||
	fail "internal or test files installed"

pc=$(cd "$prefix" && find . -path './lib*/pkgconfig/ecmxf.pc' | head -n 1)
pcdir=$prefix/$(dirname "$pc")
libdir=$(dirname "$pcdir")
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --define-variable=prefix="$prefix" --cflags --libs ecmxf) ||
	fail "pkg-config --cflags --libs ecmxf"
echo "ok: pkg-config: $flags"
case $flags in
*"-I$prefix/include"*) ;;
*) fail "pkg-config cflags do not point into $prefix/include: $flags" ;;
esac

here=$(cd "$(dirname "$0")" && pwd)
want='libecmxf '*': 0 slaves, error status 0x01'

# pkg-config alone
# shellcheck disable=SC2086
"$cxx" -o "$prefix/hello" "$here/consumer/main.cpp" $flags $extra || fail "building against the installed tree"
out=$(LD_LIBRARY_PATH=$libdir "$prefix/hello") || fail "running the program"
echo "ok: pkg-config consumer: $out"
case $out in
$want) ;;
*) fail "unexpected output: $out" ;;
esac

# CMake: find_package(ecmxf) + ecmxf::ecmxf, the consumer sets no standard
cbuild=$prefix/consumer-build
cmake -S "$here/consumer" -B "$cbuild" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" \
	-DCMAKE_CXX_FLAGS="$extra" -DCMAKE_EXE_LINKER_FLAGS="$extra" >"$cbuild.log" 2>&1 &&
	cmake --build "$cbuild" >>"$cbuild.log" 2>&1 ||
	{ cat "$cbuild.log"; fail "CMake consumer (find_package(ecmxf), ecmxf::ecmxf) does not build"; }
grep -q -- '-std=gnu++20\|-std=c++20' "$cbuild/CMakeFiles/app.dir/flags.make" ||
	fail "ecmxf::ecmxf did not bring C++20: $(grep CXX_FLAGS "$cbuild/CMakeFiles/app.dir/flags.make")"
out=$("$cbuild/app") || fail "running the CMake consumer"
echo "ok: CMake consumer (C++20 from ecmxf::ecmxf): $out"
case $out in
$want) ;;
*) fail "unexpected output: $out" ;;
esac

# below C++20: one clear #error, and nothing after it but the stop
if "$cxx" -std=c++17 -fsyntax-only -I"$prefix/include" "$here/consumer/main.cpp" >"$prefix/c17.log" 2>&1; then
	fail "the headers compiled below C++20"
fi
grep -q 'libecmxf needs C++20' "$prefix/c17.log" || { cat "$prefix/c17.log"; fail "no #error below C++20"; }
nerr=$(grep -c 'error:' "$prefix/c17.log")
[ "$nerr" -le 2 ] || { cat "$prefix/c17.log"; fail "$nerr errors below C++20, not one #error"; }
echo "ok: -std=c++17 stops at the #error ($nerr error lines)"

# the installed tools start under a non-system prefix without LD_LIBRARY_PATH
readelf -d "$prefix/bin/ecmxf-util" | grep -q 'RUNPATH.*\$ORIGIN/\.\./lib' ||
	fail "ecmxf-util has no RUNPATH \$ORIGIN/../LIBDIR: $(readelf -d "$prefix/bin/ecmxf-util" | grep PATH)"
out=$(env -u LD_LIBRARY_PATH "$prefix/bin/ecmxf-util" slaves) || fail "installed ecmxf-util slaves"
[ "$(echo "$out" | wc -l)" -eq 3 ] || fail "installed ecmxf-util slaves: $out"
echo "ok: installed ecmxf-util starts without LD_LIBRARY_PATH and lists 3 slaves"
env -u LD_LIBRARY_PATH "$prefix/bin/ecmxf-sim" --help >/dev/null || fail "installed ecmxf-sim --help"
echo "ok: installed ecmxf-sim starts"

# an installed network by name, from anywhere: <prefix>/bin/../share/ecmxf/networks
out=$(cd / && env -u LD_LIBRARY_PATH -u ECMXF_NETWORK_PATH "$prefix/bin/ecmxf-util" -d sim:servo-io.net slaves) ||
	fail "installed ecmxf-util -d sim:servo-io.net slaves (from /)"
case $out in
*"servo"*|*"Servo"*) ;;
*) fail "sim:servo-io.net is not the servo network: $out" ;;
esac
out=$(cd / && env -u LD_LIBRARY_PATH "$prefix/bin/ecmxf-util" -d sim:servo-io slaves) ||
	fail "installed ecmxf-util -d sim:servo-io slaves (without .net)"
echo "ok: installed networks found by name (sim:servo-io.net, sim:servo-io)"

# the man page names the networks where the configured prefix puts them
cprefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build/CMakeCache.txt")
if [ -n "$cprefix" ] && [ "$cprefix" != /usr ]; then
	grep -qF "$cprefix/share/ecmxf/networks" "$prefix/share/man/man1/ecmxf-util.1" ||
		fail "the installed man page does not name $cprefix/share/ecmxf/networks"
	! grep -qF "/usr/share/ecmxf/networks" "$prefix/share/man/man1/ecmxf-util.1" ||
		fail "the installed man page names /usr/share/ecmxf/networks under the prefix $cprefix"
	echo "ok: the man page names $cprefix/share/ecmxf/networks"
fi

# the Python package, where the build made one (not in sanitizer builds):
# under the prefix's lib/python3.X/dist-packages, importable from there
# without LD_LIBRARY_PATH (RUNPATH to LIBDIR)
if [ -d "$build/python/ecmxf" ]; then
	need 'lib/python3*/dist-packages/ecmxf/__init__.py'
	need 'lib/python3*/dist-packages/ecmxf/__init__.pyi'
	need 'lib/python3*/dist-packages/ecmxf/_ecmxf*.so'
	pydir=$(cd "$prefix" && find . -path './lib/python3*/dist-packages' | head -n 1)
	out=$(cd / && env -u LD_LIBRARY_PATH PYTHONPATH="$prefix/$pydir" /usr/bin/python3 -c \
		'import ecmxf; print(ecmxf.__file__); print(ecmxf.open("sim:").sdo.upload(0, 0x2001, 0))') ||
		fail "the installed Python package does not import"
	case $out in
	"$prefix/"*"/ecmxf/__init__.py
50000") ;;
	*) fail "installed Python package: $out" ;;
	esac
	echo "ok: the installed Python package imports and reads 0x2001:00"
fi
rm -rf "$prefix" "$prefix.log"
