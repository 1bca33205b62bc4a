#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Runs one example and checks its exit status and its output (stdout and
# stderr together): the ctest of each example (examples/CMakeLists.txt).
#
#   test-example.sh STATUS PATTERN PROGRAM [ARGS...]
set -u
want=$1
pattern=$2
shift 2
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$@" >"$out" 2>&1
rc=$?
sed 's/^/    /' "$out"
if [ "$rc" -ne "$want" ]; then
	echo "FAIL: $*: exit status $rc (want $want)"
	exit 1
fi
if ! grep -q -- "$pattern" "$out"; then
	echo "FAIL: $*: no line matches: $pattern"
	exit 1
fi
echo "ok: $*: status $rc"
