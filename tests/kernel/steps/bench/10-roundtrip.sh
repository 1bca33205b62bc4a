# SPDX-License-Identifier: MIT
# The synchronous round trip of FW_VERSION_GET through /dev/ecmxf0 (the
# library's KernelTransport, and the bare ECMXF_IOC_CMD) and through spidev
# (the library's SpidevTransport, INT0 by libgpiod) on the same virtual
# controller and chip; /bin/ecmxf-guest-bench prints the figures and the
# kernel/spidev ratio. ecmxf.ko is bound again afterwards.
. /steps/spidev.sh
n=${ECMXF_BENCH_N:-1000}
/bin/ecmxf-guest-bench kernel "$n" /dev/ecmxf0 || fail "ecmxf-guest-bench kernel"
spidev_take
/bin/ecmxf-guest-bench spidev "$n" "spidev:$node?int0=$chip:0&int1=$chip:1&check=crc32" ||
	fail "ecmxf-guest-bench spidev"
spidev_give_back
/bin/ecmxf-guest-test /dev/ecmxf0 >/dev/null || fail "ecmxf-guest-test after the bench"
