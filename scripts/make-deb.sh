#!/bin/sh
# SPDX-License-Identifier: MIT
#
# make deb: the Debian binary packages (libecmxf0, libecmxf-dev,
# ecmxf-tools, ecmxf-dkms) with Debian's own tools, dpkg-buildpackage and
# debhelper (debian/), then lintian over them.
#
#   scripts/make-deb.sh OUTDIR [JOBS]
#
# The source tree is copied to OUTDIR/ecmxf-VERSION first (the files git
# knows, committed or not, or the whole tree without build directories
# outside git), so the build writes nothing into the checkout and the
# packages land in OUTDIR.  lintian fails the run on any error or warning;
# the informational tags it prints are explained in
# Documentation/building.rst ("Debian packages").
set -eu
out=$1 jobs=${2:-2}
src=$(cd "$(dirname "$0")/.." && pwd)

version=$(dpkg-parsechangelog -l "$src/debian/changelog" -S Version)
cmake_version=$(sed -n 's/^project(ecmxf VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
[ "${version%%-*}" = "$cmake_version" ] || {
	echo "make-deb.sh: debian/changelog says $version, CMakeLists.txt $cmake_version" >&2
	exit 1
}

mkdir -p "$out"
out=$(cd "$out" && pwd)
tree=$out/ecmxf-$version
rm -rf "$tree" "$out"/*.deb "$out"/*.changes "$out"/*.buildinfo
mkdir -p "$tree"
if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
	# committed and uncommitted files alike, not what .gitignore hides
	(cd "$src" && git ls-files -z --cached --others --exclude-standard |
		xargs -0 sh -c 'for f; do [ -e "$f" ] || [ -L "$f" ] && printf "%s\0" "$f"; done' sh |
		tar --null -T - -cf -) | tar -C "$tree" -xf -
else
	(cd "$src" && tar --exclude='./build*' --exclude='./.git' -cf - .) | tar -C "$tree" -xf -
fi

# ccache when there is one: the packages compile the library with
# Debian's flags, a second run hits the cache.
if command -v ccache >/dev/null 2>&1; then
	export CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache
fi
echo "make-deb.sh: dpkg-buildpackage in $tree"
(cd "$tree" && DEB_BUILD_OPTIONS="parallel=$jobs nocheck" dpkg-buildpackage -b -us -uc) >"$out/build.log" 2>&1 || {
	tail -n 60 "$out/build.log"
	echo "make-deb.sh: dpkg-buildpackage failed, the whole log: $out/build.log" >&2
	exit 1
}
rm -rf "$tree"
ls -1 "$out"/*.deb

changes=$(ls "$out"/ecmxf_"$version"_*.changes)
echo "make-deb.sh: lintian (--fail-on error,warning; informational tags shown with -I)"
lintian -I --fail-on error,warning "$changes"
