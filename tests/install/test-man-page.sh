#!/bin/sh
# SPDX-License-Identifier: MIT
# Each man page renders without a single warning: man --warnings (groff
# -ww, every warning) as man(1) formats it, and groff -man -ww -z for the
# groff-only ones; its NAME line names the page.
#   test-man-page.sh MAN-PAGE...
set -eu
if ! command -v groff >/dev/null 2>&1; then
	echo "groff is not installed (Debian: groff-base, priority important)"
	exit 77
fi
for page in "$@"; do
	name=$(basename "$page" .1)
	out=$(groff -man -ww -z "$page" 2>&1)
	if [ -n "$out" ]; then
		echo "FAIL: $page: groff warnings:"
		echo "$out"
		exit 1
	fi
	if command -v man >/dev/null 2>&1; then
		out=$(MANWIDTH=80 man --warnings -E UTF-8 -l "$page" 2>&1 >/dev/null)
		if [ -n "$out" ]; then
			echo "FAIL: $page: man --warnings:"
			echo "$out"
			exit 1
		fi
	else
		echo "note: man(1) is not installed (Debian: man-db); groff alone checked $page"
	fi
	# and the page is about its program
	groff -man -Tascii "$page" 2>/dev/null | grep -Eq "^ *$name +- " ||
		{ echo "FAIL: $page: NAME section does not name $name"; exit 1; }
	echo "ok: $page renders cleanly"
done
