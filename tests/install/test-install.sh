#!/bin/sh
# SPDX-License-Identifier: MIT
# `cmake --install` of a built tree into a temporary prefix installs the
# library, headers, pkg-config and CMake files, the simulator networks,
# ecmxf-util, ecmxf-sim, the man page and the bash completion; a tiny
# program builds against the installed tree with pkg-config alone and
# opens "sim:".
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

cat >"$prefix/hello.cpp" <<'CPP'
#include <cstdio>
#include <ecmxf/device.hpp>
#include <ecmxf/protocol.hpp>

int main()
{
	const auto dev = ecmxf::Device::open("sim:");
	ecmxf::Command c;
	c.code = 16; // ECAT_SLV_CNT_GET: no network before ECAT_INIT_OP
	const ecmxf::Response r = dev->command(c);
	std::printf("libecmxf %.*s: %u slaves, error status 0x%02x\n",
		    static_cast<int>(ecmxf::version().size()), ecmxf::version().data(), r.ret,
		    dev->lastHeader().errStatus);
	return 0;
}
CPP
# shellcheck disable=SC2086
"$cxx" -o "$prefix/hello" "$prefix/hello.cpp" $flags $extra || fail "building against the installed tree"
out=$(LD_LIBRARY_PATH=$libdir "$prefix/hello") || fail "running the program"
echo "ok: $out"
case $out in
"libecmxf "*": 0 slaves, error status 0x01") ;;
*) fail "unexpected output: $out" ;;
esac

out=$(LD_LIBRARY_PATH=$libdir "$prefix/bin/ecmxf-util" slaves) || fail "installed ecmxf-util slaves"
[ "$(echo "$out" | wc -l)" -eq 3 ] || fail "installed ecmxf-util slaves: $out"
echo "ok: installed ecmxf-util lists 3 slaves"
rm -rf "$prefix" "$prefix.log"
