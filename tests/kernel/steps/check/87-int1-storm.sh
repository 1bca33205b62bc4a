# SPDX-License-Identifier: MIT
# A level INT1 held asserted while the PDO rings run (kernel-testing.rst
# "PDO rings"; driver.rst "INT0 and INT1"): ecmxf-vspi gives INT1 as a
# level-low interrupt, the bridge runs the rings network at the guest's
# time, and the EtherCAT-frame flag, enabled and never cleared, holds the
# line asserted. The pump's FIFO commands clear only the FIFO flags, after
# which the worker unmasks INT1 and it fires again at once: the pump's
# commands must stay at its own rate (ecmxf-guest-rings int1-storm), with
# and without ECMXF_RING_F_FIFO_NEXT. Afterwards the GPIO form and the
# default bridge again.
lsmod | grep -q '^ecmxf ' && ecmxf_unload
bridge_stop
rmmod ecmxf-vspi || fail "rmmod ecmxf-vspi"
insmod /lib/modules/ecmxf-vspi.ko int1=irq-level || fail "insmod ecmxf-vspi.ko int1=irq-level"
/bin/ecmxf-guest-rings --network >/tmp/storm.net
bridge_start /tmp/storm.net
ecmxf_load
/bin/ecmxf-guest-rings int1-storm /dev/ecmxf0 100 300 || fail "ecmxf-guest-rings int1-storm"
/bin/ecmxf-guest-rings int1-storm /dev/ecmxf0 100 300 fifo-next || fail "ecmxf-guest-rings int1-storm fifo-next"
ecmxf_unload
bridge_stop
rmmod ecmxf-vspi || fail "rmmod ecmxf-vspi"
insmod /lib/modules/ecmxf-vspi.ko || fail "insmod ecmxf-vspi.ko"
bridge_start
ecmxf_load
