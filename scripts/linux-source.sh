# SPDX-License-Identifier: MIT
# shellcheck shell=sh
#
# Sourced by scripts/checkpatch.sh and scripts/dt-check.sh: files of the
# kernel's source tree, taken from Debian's linux-source package without
# installing it.  The .deb is fetched once with `apt-get download` into
# $ECMXF_CACHE/debs (default /var/cache/ecmxf; kept for the next caller),
# and each caller's files are extracted from its source tarball once into
# a directory of their own.  Deleting any of it is always safe.
#
#   ECMXF_CACHE=/var/cache/ecmxf         the cache directory
#   ECMXF_LINUX_SOURCE=linux-source-6.1  the Debian package
#
# The caller defines die() (message, exit 1).

ls_cache=${ECMXF_CACHE:-/var/cache/ecmxf}
ls_pkg=${ECMXF_LINUX_SOURCE:-linux-source-6.1}

# The cached .deb of the package (the last in sort order), or nothing.
ls_cached_deb() {
	last=
	for d in "$ls_cache/debs/${ls_pkg}_"*.deb; do
		[ -f "$d" ] && last=$d
	done
	echo "$last"
}

# Print the path of the package's .deb, downloading it if it is not cached.
linux_source_deb() {
	deb=$(ls_cached_deb)
	if [ -z "$deb" ]; then
		command -v apt-get >/dev/null || die "apt-get not found; set ECMXF_CACHE= to a cache with $ls_pkg"
		mkdir -p "$ls_cache/debs" || die "cannot create $ls_cache/debs; set ECMXF_CACHE="
		echo "$(basename "$0"): downloading $ls_pkg into $ls_cache/debs" >&2
		if ! (cd "$ls_cache/debs" && apt-get download -q "$ls_pkg" >&2); then
			# stale package lists: refresh them once (needs root)
			apt-get update -qq >&2 || die "apt-get update failed"
			(cd "$ls_cache/debs" && apt-get download -q "$ls_pkg" >&2) ||
				die "apt-get download $ls_pkg failed"
		fi
		deb=$(ls_cached_deb)
		[ -n "$deb" ] || die "apt-get download left no $ls_pkg .deb in $ls_cache/debs"
	fi
	echo "$deb"
}

# linux_source_files NAME STRIP PATTERN...: extract the files matching the
# patterns (tar --wildcards, --strip-components=STRIP) from the source
# tarball into $ls_cache/NAME-<package version> once, and print that
# directory.  It has a VERSION file once complete; the caller checks that
# the files it needs are there.
linux_source_files() {
	name=$1
	strip=$2
	shift 2
	deb=$(linux_source_deb)
	ver=$(dpkg-deb -f "$deb" Version)
	dir=$ls_cache/$name-$ver
	if [ ! -f "$dir/VERSION" ]; then
		echo "$(basename "$0"): extracting $name files from $deb" >&2
		tmp=$(mktemp -d "$ls_cache/.$name.XXXXXX")
		chmod 755 "$tmp"
		if ! dpkg-deb --fsys-tarfile "$deb" |
			tar -xO --wildcards './usr/src/linux-source-*.tar.xz' |
			tar -xJ -C "$tmp" --strip-components="$strip" --wildcards "$@"; then
			rm -rf "$tmp"
			die "extracting $* from $deb failed"
		fi
		echo "$ver" >"$tmp/VERSION"
		# another run may have won the race; either copy is good
		mv -T "$tmp" "$dir" 2>/dev/null || rm -rf "$tmp"
	fi
	echo "$dir"
}
