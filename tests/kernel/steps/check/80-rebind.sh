# SPDX-License-Identifier: MIT
# Remove with a file open, then probe again: the chip keeps the format the
# driver set (CRC-32), which the driver's first try finds.
spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
exec 3<>/dev/ecmxf0
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev"
[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 still there after unbind"
exec 3>&-
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev again"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding again"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test after binding again"
