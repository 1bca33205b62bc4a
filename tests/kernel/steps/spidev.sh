# SPDX-License-Identifier: MIT
# Helpers for the steps that hand the SPI device from ecmxf.ko to spidev and
# back (sourced by steps/check/74-spidev.sh and steps/bench/*; not a step
# itself: only steps/<mode>/*.sh run).
#
# spidev_take: unbind ecmxf from the SPI device behind /dev/ecmxf0, bind
#   spidev to it through driver_override; sets spi (e.g. spi0.0), node
#   (/dev/spidev0.0) and chip (the vspi's gpiochipN).
# spidev_give_back [bridge args]: unbind spidev, clear driver_override,
#   restart the bridge with the given arguments (none: the default
#   network), bind ecmxf again; /dev/ecmxf0 must be back.

spidev_take() {
	spi=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
	[ -n "$spi" ] || fail "no SPI device behind /dev/ecmxf0"
	echo "$spi" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spi from ecmxf"
	[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 still there after unbind"
	echo spidev >"/sys/bus/spi/devices/$spi/driver_override" || fail "driver_override of $spi"
	echo "$spi" >/sys/bus/spi/drivers/spidev/bind || fail "bind $spi to spidev"
	node=/dev/spidev${spi#spi}
	i=0
	until [ -c "$node" ]; do
		i=$((i + 1))
		[ $i -gt 50 ] && fail "no $node after binding spidev"
		sleep 0.1
	done
	# the gpiochip whose parent is the vspi platform device (its label is
	# ecmxf-vspi, which libgpiod would also take)
	chip=""
	for c in /sys/bus/gpio/devices/gpiochip*; do
		case "$(readlink -f "$c")" in */ecmxf-vspi*/gpiochip*) chip=${c##*/} ;; esac
	done
	[ -n "$chip" ] || fail "no gpiochip of ecmxf-vspi under /sys/bus/gpio/devices"
	[ -c "/dev/$chip" ] || fail "no /dev/$chip"
	echo "guest-test: spidev: $spi bound to spidev as $node, INT0/INT1 on /dev/$chip"
}

spidev_give_back() {
	echo "$spi" >/sys/bus/spi/drivers/spidev/unbind || fail "unbind $spi from spidev"
	[ -e "$node" ] && fail "$node still there after unbind"
	echo >"/sys/bus/spi/devices/$spi/driver_override" || fail "clear driver_override of $spi"
	bridge_stop
	bridge_start "$@"
	echo "$spi" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spi to ecmxf again"
	[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding ecmxf again"
}
