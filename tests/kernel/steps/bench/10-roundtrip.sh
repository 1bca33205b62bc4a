# SPDX-License-Identifier: MIT
# The synchronous round trip of FW_VERSION_GET through /dev/ecmxf0 (the
# library's KernelLink, and the bare ECMXF_IOC_CMD) and through spidev
# (the library's SpidevChannel, INT0 by libgpiod) on the same virtual
# controller and chip, in interleaved blocks: /bin/ecmxf-guest-bench hands
# the SPI device between ecmxf and spidev itself (sysfs unbind,
# driver_override, bind) and prints the figures, the system calls per
# command and the kernel/spidev ratios. ecmxf is bound again at the end.
n=${ECMXF_BENCH_N:-1000}
blocks=${ECMXF_BENCH_BLOCKS:-20}
spi=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
[ -n "$spi" ] || fail "no SPI device behind /dev/ecmxf0"
chip=""
for c in /sys/bus/gpio/devices/gpiochip*; do
	case "$(readlink -f "$c")" in */ecmxf-vspi*/gpiochip*) chip=${c##*/} ;; esac
done
[ -n "$chip" ] || fail "no gpiochip of ecmxf-vspi under /sys/bus/gpio/devices"
/bin/ecmxf-guest-bench "$n" "$blocks" "$spi" "$chip" || fail "ecmxf-guest-bench"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after the bench"
/bin/ecmxf-guest-test /dev/ecmxf0 >/dev/null || fail "ecmxf-guest-test after the bench"
