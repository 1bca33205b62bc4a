#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Run every libFuzzer binary of a build for a while.
#
#   tests/fuzz/run-fuzzers.sh BUILD_DIR SECONDS [CORPUS_DIR]
#
# Each BUILD_DIR/tests/fuzz/fuzz-* runs for SECONDS on a scratch copy of
# its seed corpus (tests/fuzz/corpus/<name>/ if it exists, else
# tests/fuzz/corpus/), so new corpus entries never land in the source
# tree.  A crash, leak, timeout or out-of-memory makes libFuzzer exit
# non-zero; the reproducer is kept under the scratch directory, whose path
# is printed, and this script exits 1.  Exit 0 when all fuzzers ran clean.
# With CORPUS_DIR (make fuzz-long) each fuzzer's corpus lives on in
# CORPUS_DIR/<name>/ between runs (seeded from the source tree), so that
# long runs build on each other.  FUZZ_JOBS fuzzers run at a time (default
# 1; make fuzz runs one per core); the summary gives execs/s per target,
# in the order of their names, and the total of execs.
set -u

if [ $# -ne 2 ] && [ $# -ne 3 ]; then
	echo "usage: $0 BUILD_DIR SECONDS [CORPUS_DIR]" >&2
	exit 2
fi
build=$1
seconds=$2
keep=${3:-}
case "$seconds" in
''|*[!0-9]*) echo "run-fuzzers.sh: SECONDS must be a number" >&2; exit 2 ;;
esac

srcdir=$(cd "$(dirname "$0")" && pwd)
bindir="$build/tests/fuzz"
fuzzers=$(find "$bindir" -maxdepth 1 -type f -name 'fuzz-*' -perm -u+x 2>/dev/null | sort)
if [ -z "$fuzzers" ]; then
	echo "run-fuzzers.sh: no fuzz-* binaries in $bindir (configure with -DECMXF_BUILD_FUZZ=ON)" >&2
	exit 1
fi

scratch=$(mktemp -d "${TMPDIR:-/tmp}/ecmxf-fuzz.XXXXXX")
failed=0
summary=""
total=0

jobs=${FUZZ_JOBS:-1}
case "$jobs" in
''|*[!0-9]*|0) echo "run-fuzzers.sh: FUZZ_JOBS must be a positive number, not '$jobs'" >&2; exit 2 ;;
esac

# one fuzzer: its log, its summary line in $work/line and its exit code
# in $work/rc
run_one() {
	bin=$1
	name=$(basename "$bin")
	short=${name#fuzz-}
	seeds="$srcdir/corpus/$short"
	[ -d "$seeds" ] || seeds="$srcdir/corpus"
	work="$scratch/$name"
	mkdir -p "$work/artifacts"
	if [ -n "$keep" ]; then
		mkdir -p "$keep/$name"
		ln -s "$(cd "$keep/$name" && pwd)" "$work/corpus"
	else
		mkdir -p "$work/corpus"
	fi
	# seed files only (not the subdirectories of other targets)
	find "$seeds" -maxdepth 1 -type f -exec cp {} "$work/corpus/" \;
	nseeds=$(find "$work/corpus/" -type f | wc -l)

	echo "==> $name: $seconds s, $nseeds seeds, log $work/log"
	"$bin" -max_total_time="$seconds" -print_final_stats=1 -timeout=10 \
		-max_len=8192 -rss_limit_mb=2048 \
		-artifact_prefix="$work/artifacts/" \
		"$work/corpus" >"$work/log" 2>&1
	rc=$?

	execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log" | tail -n 1)
	rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$work/log" | tail -n 1)
	cov=$(grep -o 'cov: [0-9]*' "$work/log" | tail -n 1 | sed 's/cov: //')
	ft=$(grep -o 'ft: [0-9]*' "$work/log" | tail -n 1 | sed 's/ft: //')
	corp=$(find "$work/corpus/" -type f | wc -l)
	stats="execs ${execs:-?} (${rate:-?}/s), cov ${cov:-?}, ft ${ft:-?}, corpus $nseeds -> $corp"
	echo "${execs:-0}" >"$work/execs"
	echo "$rc" >"$work/rc"
	if [ "$rc" -eq 0 ]; then
		echo "$name: OK, $stats" >"$work/line"
	else
		echo "$name: FAILED (exit $rc), $stats" >"$work/line"
	fi
	cat "$work/line"
}

# FUZZ_JOBS lanes, each running every FUZZ_JOBS-th fuzzer in turn
lane=0
while [ "$lane" -lt "$jobs" ]; do
	(
		i=0
		for bin in $fuzzers; do
			[ $((i % jobs)) -eq "$lane" ] && run_one "$bin"
			i=$((i + 1))
		done
	) &
	lane=$((lane + 1))
done
wait

for bin in $fuzzers; do
	name=$(basename "$bin")
	work="$scratch/$name"
	line=$(cat "$work/line" 2>/dev/null || echo "$name: FAILED (did not run)")
	rc=$(cat "$work/rc" 2>/dev/null || echo 1)
	total=$((total + $(cat "$work/execs" 2>/dev/null || echo 0)))
	if [ "$rc" -ne 0 ]; then
		failed=1
		echo "---- $name: last lines of $work/log:"
		tail -n 60 "$work/log" 2>/dev/null
		for a in "$work"/artifacts/*; do
			[ -e "$a" ] && echo "---- reproducer: $a (replay: $bin $a)"
		done
	fi
	summary="$summary$line
"
done

echo "==== fuzz summary (${seconds}s each)"
printf '%s' "$summary"
echo "total: $total execs"
if [ "$failed" -ne 0 ]; then
	echo "run-fuzzers.sh: FAILED; logs and reproducers kept in $scratch"
	exit 1
fi
rm -rf "$scratch"
echo "run-fuzzers.sh: all fuzzers ran clean"
exit 0
