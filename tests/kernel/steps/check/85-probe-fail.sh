# SPDX-License-Identifier: MIT
# A chip that does not answer fails the probe with a reason in the kernel
# log (dev_err_probe, driver.rst "Probe"), and no /dev/ecmxf0; with the
# chip back, binding again works.
spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev"
bridge_stop
dmesg -c >/dev/null
if echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind 2>/dev/null; then
	fail "binding $spidev without a chip succeeded"
fi
[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 exists after a failed probe"
dmesg | grep -q "the chip does not answer FW_VERSION_GET in any known packet format" ||
	fail "no probe failure reason in the kernel log"
echo "guest-test: ok   probe without a chip fails: $(dmesg | grep -m1 'does not answer' | sed 's/^\[[^]]*\] //')"
bridge_start
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev with the chip back"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding with the chip back"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test after a failed probe"
