#!/bin/sh
# SPDX-License-Identifier: MIT
#
# scripts/check-docs.py on small pages made for each problem it finds: each
# bad page fails naming its file and line, the good one passes.
#
#   test-check-docs.sh <check-docs.py>
set -eu
check=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fails=0

expect() { # expect <ok|bad> <file> <text in the output>
	out=$(/usr/bin/python3 "$check" "$2" 2>&1) && rc=0 || rc=$?
	case $1 in
	ok) [ "$rc" -eq 0 ] || { echo "FAIL: $2 should pass: $out"; fails=$((fails + 1)); return; } ;;
	bad) [ "$rc" -eq 1 ] || { echo "FAIL: $2 should fail (rc $rc): $out"; fails=$((fails + 1)); return; } ;;
	esac
	case $out in
	*"$3"*) echo "ok: $(basename "$2")" ;;
	*) echo "FAIL: $2: expected '$3' in: $out"; fails=$((fails + 1)) ;;
	esac
}

cat >"$dir/good.rst" <<'RST'
Title
=====

=====  =====
a      b
=====  =====

1. one
2. two
RST
expect ok "$dir/good.rst" "1 pages, 0 problems"

cat >"$dir/table.rst" <<'RST'
Title
=====

=====  =====
a      b
overlong   b
=====  =====
RST
expect bad "$dir/table.rst" "table.rst:6: (ERROR/3) Malformed table"

cat >"$dir/underline.rst" <<'RST'
A long title
=====

text
RST
expect bad "$dir/underline.rst" "underline.rst:2: (WARNING/2) Title underline too short"

cat >"$dir/list.rst" <<'RST'
Title
=====

1. one
2. two
4. four
3. three
RST
expect bad "$dir/list.rst" "list.rst:5: (WARNING/2) Enumerated list ends without a blank line"

cat >"$dir/shared.rst" <<'RST'
Title
=====

See ``../shared/spec/ecm-xf.md``.
RST
expect bad "$dir/shared.rst" "shared.rst:4: points outside the project (../shared/)"

cat >"$dir/link.rst" <<'RST'
Title
=====

See `Nowhere`_.
RST
expect bad "$dir/link.rst" "link.rst:4: (ERROR/3) Unknown target name"

# without FILE arguments: the pages of Documentation/ and every file git
# tracks (a source comment may not point outside either)
mkdir -p "$dir/tree/Documentation" "$dir/tree/lib"
cp "$dir/good.rst" "$dir/tree/Documentation/"
printf '// see ../shared/seeds/000_x.txt\n' >"$dir/tree/lib/a.c"
git -C "$dir/tree" init -q && git -C "$dir/tree" add .
out=$(/usr/bin/python3 "$check" --root "$dir/tree" 2>&1) && rc=0 || rc=$?
case $rc:$out in
1:*"lib/a.c:1: points outside the project (../shared/)"*"1 pages and 1 other files, 1 problems"*) echo "ok: tree" ;;
*) echo "FAIL: tree (rc $rc): $out"; fails=$((fails + 1)) ;;
esac

[ "$fails" -eq 0 ] && echo "all cases passed" || { echo "$fails case(s) failed"; exit 1; }
