# SPDX-License-Identifier: MIT
# The end-to-end checks through /dev/ecmxf0 (tests/kernel/guest-test.cpp),
# with the sysfs attributes printed first.
for a in /sys/class/ecmxf/ecmxf0/*; do
	[ -f "$a" ] && echo "sysfs: ${a##*/} = $(head -n 1 "$a" 2>&1)"
done
# CRC-32 set at probe; the bridge's chip covers the whole data section
# (manual 050; protocol-core.rst, "Firmware variants")
cov=$(cat /sys/class/ecmxf/ecmxf0/crc_coverage) || fail "no sysfs crc_coverage"
[ "$cov" = frame ] || fail "sysfs crc_coverage is '$cov', not 'frame'"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test"
grep -i vspi /proc/interrupts
