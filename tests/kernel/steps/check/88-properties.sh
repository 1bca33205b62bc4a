# SPDX-License-Identifier: MIT
# Per-chip settings from device properties (driver.rst "Per-chip settings"):
# ecmxf-vspi gives the device a software node with nextw,data-size and
# nextw,check-type, or another modalias (the master series); the module
# parameters are only the defaults, and the timing parameters are
# read-only. Afterwards the default device again.
attr_is() {
	v=$(cat "/sys/class/ecmxf/ecmxf0/$1") || fail "no sysfs $1"
	[ "$v" = "$2" ] || fail "sysfs $1 is '$v', want '$2' ($3)"
	echo "guest-test: ok   sysfs $1 = $2 ($3)"
}
probe_refuses() {
	insmod /lib/modules/ecmxf.ko || fail "insmod ecmxf.ko"
	[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 exists with $1"
	# dev_err_probe() prints the errno by name with CONFIG_SYMBOLIC_ERRNAME
	# (Debian's kernels), as a number without it (the debug kernel)
	dmesg | grep -Eq "error -(EINVAL|22): $2" || fail "no probe failure reason '$2' for $1"
	echo "guest-test: ok   $1 refused: $(dmesg | grep -m1 -Eo "$2.*")"
	ecmxf_unload_quiet
}
ecmxf_unload_quiet() { rmmod ecmxf || fail "rmmod ecmxf"; }

# the properties win over the module parameters (data_size 0: keep the
# chip's; check_type 3: CRC-32)
vspi_reload data_size_prop=256 check_type_prop=crc8
ecmxf_load
attr_is data_size 256 "nextw,data-size = 256"
attr_is check_type crc8 "nextw,check-type = \"crc8\""
attr_is variant ECM-XF "modalias ecm-xf"
# the probe read the firmware version again in the new format
attr_is fw_version 48 "FW_VERSION_GET answered in the properties' format"
ecmxf_unload
# the module parameter is a default: the property still wins
vspi_reload data_size_prop=256
ecmxf_load data_size=512
attr_is data_size 256 "nextw,data-size = 256 beside data_size=512"
ecmxf_unload

# bad property values: the probe fails and says which property and why
vspi_reload data_size_prop=20
probe_refuses "nextw,data-size = 20" "nextw,data-size = 20: not a data section size"
vspi_reload data_size_prop=1412
probe_refuses "nextw,data-size = 1412" "nextw,data-size = 1412: not a data section size"
vspi_reload check_type_prop=crc64
probe_refuses "nextw,check-type = crc64" "nextw,check-type = \"crc64\": none of"

# the series from the SPI id: an ECM-XFU's data section is fixed (992
# bytes): no SPI_RECONFIG_OP whatever data_size says, a property that
# differs is refused (the simulated chip is no XFU: it keeps its 112)
vspi_reload modalias=ecm-xfu
ecmxf_load data_size=256
attr_is variant ECM-XFU "modalias ecm-xfu"
attr_is data_size 112 "ECM-XFU: data_size=256 not applied, the chip's kept"
ecmxf_unload
vspi_reload modalias=ecm-xfu data_size_prop=256
probe_refuses "nextw,data-size = 256 on an ECM-XFU" "nextw,data-size = 256: the ECM-XFU's data section is fixed at 992 bytes"
vspi_reload modalias=ecm-xm
ecmxf_load
attr_is variant ECM-XM "modalias ecm-xm"
ecmxf_unload

# the timing parameters are read at probe and read-only afterwards;
# out of range fails the load
vspi_reload
ecmxf_load pump_timeout_ms=2000
[ "$(cat /sys/module/ecmxf/parameters/pump_timeout_ms)" = 2000 ] || fail "pump_timeout_ms is not 2000"
if echo 600 >/sys/module/ecmxf/parameters/pump_timeout_ms 2>/dev/null; then
	fail "pump_timeout_ms was writable at run time"
fi
if echo 50 >/sys/module/ecmxf/parameters/event_poll_ms 2>/dev/null; then
	fail "event_poll_ms was writable at run time"
fi
echo "guest-test: ok   pump_timeout_ms and event_poll_ms are read-only at run time"
ecmxf_unload
if insmod /lib/modules/ecmxf.ko pump_timeout_ms=5 2>/dev/null; then
	fail "pump_timeout_ms=5 was accepted"
fi
dmesg | grep -q "pump_timeout_ms=5 is out of range (10..60000)" || fail "no reason for pump_timeout_ms=5"
echo "guest-test: ok   pump_timeout_ms=5 refused at load"
ecmxf_load
