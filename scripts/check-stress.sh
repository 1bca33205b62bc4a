#!/bin/sh
# SPDX-License-Identifier: MIT
#
# make check-stress: the userspace suite repeated under load, to find tests
# that depend on scheduling luck (Documentation/building.rst, "A suite that
# never flakes").
#
#   scripts/check-stress.sh [BUILD] [ROUNDS]
#
# 1. every core loaded by stress-ng (one CPU worker per core), each test run
#    ROUNDS times (ctest --repeat until-fail:ROUNDS) with as many tests at
#    once as there are cores;
# 2. the same pinned to one core (taskset -c 0), with a stress-ng worker on
#    that core too: threads of a test then only run when the scheduler
#    switches, never side by side.
# Zero failures is the bar; the first failure stops the round and the
# script exits non-zero.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
rounds=${2:-20}
case "$build" in /*) ;; *) build="$top/$build" ;; esac
[ -f "$build/CTestTestfile.cmake" ] || { echo "check-stress: no ctest tree in $build (make all first)" >&2; exit 1; }
case "$rounds" in ''|*[!0-9]*|0) echo "check-stress: ROUNDS must be a positive number, not '$rounds'" >&2; exit 2 ;; esac
"$top/scripts/install-deps.sh" --stress

cores=$(nproc)
stress_pid=""
stop_stress() { [ -z "$stress_pid" ] || kill "$stress_pid" 2>/dev/null || true; wait 2>/dev/null || true; stress_pid=""; }
trap stop_stress EXIT INT TERM

run() {
	label=$1
	shift
	start=$(date +%s)
	if ! "$@" ctest --test-dir "$build" --output-on-failure --repeat until-fail:"$rounds" \
		-j "$cores" >"$build/check-stress-$label.log" 2>&1; then
		tail -n 60 "$build/check-stress-$label.log"
		echo "check-stress: $label: a test failed (log: $build/check-stress-$label.log)" >&2
		exit 1
	fi
	summary=$(grep -E 'tests passed' "$build/check-stress-$label.log" | tail -n 1)
	echo "check-stress: $label: $rounds rounds, $summary ($(( $(date +%s) - start )) s)"
}

echo "check-stress: $rounds rounds per test, $cores cores"
stress-ng --cpu "$cores" --timeout 0 --quiet &
stress_pid=$!
run loaded
stop_stress

taskset -c 0 stress-ng --cpu 1 --timeout 0 --quiet &
stress_pid=$!
run pinned taskset -c 0
stop_stress
echo "check-stress: 0 failures"
