#!/bin/sh
# SPDX-License-Identifier: MIT
#
# /init of the QEMU kernel tests (Documentation/kernel-testing.rst): load the
# virtual SPI controller, start the bridge, load ecmxf.ko, run the guest
# test, unload everything, print the marker, power off. Any failure prints
# "ECMXF-KTEST: FAIL <why>" and powers off without the marker.

export PATH=/bin:/sbin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev

fail() {
	echo "ECMXF-KTEST: FAIL $*"
	[ -f /tmp/bridge.log ] && sed 's/^/bridge: /' /tmp/bridge.log
	echo "ECMXF-KTEST: kernel log follows"
	dmesg
	poweroff -f
	sleep 10
}

echo "ECMXF-KTEST: guest up, kernel $(uname -r)"
insmod /lib/modules/ecmxf-vspi.ko || fail "insmod ecmxf-vspi.ko"
[ -c /dev/ecmxf-vspi ] || fail "no /dev/ecmxf-vspi"

/bin/ecmxf-bridge 2>/tmp/bridge.log &
bridge=$!
i=0
until grep -q "ready" /tmp/bridge.log 2>/dev/null; do
	i=$((i + 1))
	[ $i -gt 200 ] && fail "the bridge did not start"
	kill -0 $bridge 2>/dev/null || fail "the bridge exited"
	sleep 0.1
done

insmod /lib/modules/ecmxf.ko || fail "insmod ecmxf.ko"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after insmod ecmxf.ko"
for a in /sys/class/ecmxf/ecmxf0/*; do
	[ -f "$a" ] && echo "sysfs: ${a##*/} = $(head -n 1 "$a" 2>&1)"
done

/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test"
grep -i vspi /proc/interrupts

# remove with a file open, then probe again: the chip keeps the format
# the driver set (CRC-32), which the driver's first try finds
spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
exec 3<>/dev/ecmxf0
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev"
[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 still there after unbind"
exec 3>&-
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev again"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding again"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test after binding again"

# a dead bridge must cost failed commands, not a hung kernel
kill $bridge
wait $bridge || fail "the bridge failed"
sed 's/^/bridge: /' /tmp/bridge.log
/bin/ecmxf-guest-test --bridge-gone /dev/ecmxf0 || fail "ecmxf-guest-test --bridge-gone"

rmmod ecmxf || fail "rmmod ecmxf"
[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 still there after rmmod"
rmmod ecmxf-vspi || fail "rmmod ecmxf-vspi"

# the whole kernel log once more, at every level, for the host's scan
dmesg
echo "ECMXF-KTEST: PASS"
poweroff -f
sleep 10
