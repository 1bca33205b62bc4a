#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Every protocol-number macro of <linux/ecmxf.h> (ECMXF_CMD_*, _RSV_, _CTL_,
# _ERR_, _STS_, _ECAT_, _INT_; not the ECMXF_CMD_F_* ioctl flags) has its
# line in uapi_numbers.def, and every line there names a macro of the
# header: the compile-time checks of test-uapi then cover all of them.
#
#   check_numbers.sh CC UAPI_INCLUDE_DIR uapi_numbers.def
set -eu
cc=$1
inc=$2
def=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

$cc -dM -E -I"$inc" -include linux/ecmxf.h -x c /dev/null >"$tmp/macros" ||
	{ echo "check_numbers.sh: $cc could not preprocess <linux/ecmxf.h>" >&2; exit 1; }
sed -n 's/^#define \(ECMXF_\(CMD\|RSV\|CTL\|ERR\|STS\|ECAT\|INT\)_[A-Za-z0-9_]*\) .*/\1/p' "$tmp/macros" |
	grep -v '^ECMXF_CMD_F_' | sort >"$tmp/header"
sed -n 's/^UAPI_NUMBER([A-Z]*, *\([A-Za-z0-9_]*\), .*/\1/p' "$def" | sort >"$tmp/def"
[ -s "$tmp/header" ] || { echo "check_numbers.sh: no protocol macros found in the header" >&2; exit 1; }
if ! cmp -s "$tmp/header" "$tmp/def"; then
	echo "check_numbers.sh: <linux/ecmxf.h> and uapi_numbers.def list different macros" >&2
	echo "  only in the header: $(comm -23 "$tmp/header" "$tmp/def" | tr '\n' ' ')" >&2
	echo "  only in uapi_numbers.def: $(comm -13 "$tmp/header" "$tmp/def" | tr '\n' ' ')" >&2
	exit 1
fi
echo "check_numbers.sh: $(wc -l <"$tmp/header") protocol macros, all in uapi_numbers.def"
