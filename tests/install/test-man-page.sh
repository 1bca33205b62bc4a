#!/bin/sh
# SPDX-License-Identifier: MIT
# The man page renders without a single groff warning (-ww: all warnings).
#   test-man-page.sh MAN-PAGE
set -eu
if ! command -v groff >/dev/null 2>&1; then
	echo "groff is not installed (Debian: groff-base, priority important)"
	exit 77
fi
out=$(groff -man -ww -z "$1" 2>&1)
if [ -n "$out" ]; then
	echo "FAIL: groff warnings:"
	echo "$out"
	exit 1
fi
# and the page is about ecmxf-util
groff -man -Tascii "$1" 2>/dev/null | grep -q 'ecmxf-util - query and control' ||
	{ echo "FAIL: NAME section missing"; exit 1; }
echo "ok: $1 renders cleanly"
