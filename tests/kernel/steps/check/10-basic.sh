# SPDX-License-Identifier: MIT
# The end-to-end checks through /dev/ecmxf0 (tests/kernel/guest-test.cpp),
# with the sysfs attributes printed first.
for a in /sys/class/ecmxf/ecmxf0/*; do
	[ -f "$a" ] && echo "sysfs: ${a##*/} = $(head -n 1 "$a" 2>&1)"
done
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test"
grep -i vspi /proc/interrupts
