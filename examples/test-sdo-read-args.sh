#!/bin/sh
# SPDX-License-Identifier: MIT
#
# ecmxf-sdo-read without a chip: every bad argument is refused with exit
# status 2 and a message that names it, before the device is opened; a
# device that is missing or not an ecmxf chip fails with status 1 and says
# which call failed.
#
#   test-sdo-read-args.sh PATH/TO/ecmxf-sdo-read
set -u
prog=$1
failures=0
out=$(mktemp)
trap 'rm -f "$out"' EXIT

# expect STATUS PATTERN ARGS...: exit status STATUS, stderr matching PATTERN
expect() {
	want=$1
	pattern=$2
	shift 2
	"$prog" "$@" >/dev/null 2>"$out"
	rc=$?
	if [ "$rc" -ne "$want" ] || ! grep -q -- "$pattern" "$out"; then
		echo "FAIL: ecmxf-sdo-read $*: status $rc (want $want), stderr:"
		sed 's/^/    /' "$out"
		echo "    (want a line matching: $pattern)"
		failures=$((failures + 1))
	else
		echo "ok: ecmxf-sdo-read $*: status $rc, $(head -n 1 "$out")"
	fi
}

expect 2 '^usage:'
expect 2 '^usage:' /dev/null
expect 2 '^usage:' /dev/null 0x2001:0 0 extra
expect 2 'expected INDEX:SUB' /dev/null 0x2001
expect 2 'INDEX must be 0..0xffff' /dev/null 0x10000:0
expect 2 'INDEX must be 0..0xffff' /dev/null 0x2001:0x100
expect 2 'INDEX must be 0..0xffff' /dev/null :0
expect 2 'INDEX must be 0..0xffff' /dev/null 0x2001:
expect 2 'INDEX must be 0..0xffff' /dev/null -1:0
expect 2 'INDEX must be 0..0xffff' /dev/null 0x2001:1x
expect 2 'INDEX must be 0..0xffff' /dev/null 0x2001:0:0
expect 2 "slave position '255'" /dev/null 0x2001:0 255
expect 2 "slave position 'x'" /dev/null 0x2001:0 x
expect 2 "slave position '-1'" /dev/null 0x2001:0 -1
# not there; not an ecmxf device (the ioctl is refused with ENOTTY)
expect 1 'cannot open /nonexistent/ecmxf9: No such file or directory' /nonexistent/ecmxf9 0x2001:0
expect 1 'ECMXF_IOC_GET_VERSION failed: .*(not an ecmxf device?)' /dev/null 0x2001:0

[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "all passed"
