# SPDX-License-Identifier: MIT
# The cyclic exchange per cycle over three paths: the library's Cyclic over
# the kernel's PDO rings, a loop of synchronous ECMXF_IOC_CMD
# ECAT_PDO_DATA_FIFO_OP, and the library's Cyclic over spidev (the same FIFO
# commands from userspace); /bin/ecmxf-guest-cyclic-bench counts the system
# calls per cycle (ptrace) and the CPU time per cycle and prints the ratios.
# ecmxf.ko is bound again afterwards.
. /steps/spidev.sh
n=${ECMXF_BENCH_N:-1000}
/bin/ecmxf-guest-cyclic-bench kernel "$n" /dev/ecmxf0 || fail "ecmxf-guest-cyclic-bench kernel"
spidev_take
/bin/ecmxf-guest-cyclic-bench spidev "$n" "spidev:$node?int0=$chip:0&int1=$chip:1&check=crc32" ||
	fail "ecmxf-guest-cyclic-bench spidev"
spidev_give_back
/bin/ecmxf-guest-test /dev/ecmxf0 >/dev/null || fail "ecmxf-guest-test after the cyclic bench"
