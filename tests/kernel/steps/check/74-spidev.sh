# SPDX-License-Identifier: MIT
# The spidev transport end to end: the SPI device taken from ecmxf.ko and
# given to spidev (driver_override), the integration suite run over
# /dev/spidevB.C with libgpiod 1.6 waiting on the vspi's INT0/INT1 lines,
# then ecmxf.ko bound again and checked. The bridge runs the suite's
# network (the dio looped back); ecmxf.ko probes it first, so the chip
# speaks the CRC-32 check word the driver set, which the URI says
# (check=crc32). The default network is back afterwards.
. /steps/spidev.sh
ecmxf_unload
bridge_stop
bridge_start /bin/ecmxf-integration.net
ecmxf_load
spidev_take
grep -i vspi /proc/interrupts
rc=0
ECMXF_TEST_URI="spidev:$node?int0=$chip:0&int1=$chip:1&check=crc32" /bin/ecmxf-test-integration -d yes \
	>/tmp/integ-spidev.log 2>&1 || rc=$?
sed 's/^/guest-test: integ(spidev): /' /tmp/integ-spidev.log
[ "$rc" -eq 0 ] || fail "test-integration through spidev (exit $rc)"
grep -i vspi /proc/interrupts
spidev_give_back
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test after spidev"
