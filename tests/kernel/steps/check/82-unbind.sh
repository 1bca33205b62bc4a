# SPDX-License-Identifier: MIT
# The chip unbound under its users (tests/kernel/guest-unbind.cpp,
# kernel-testing.rst "Unbind under load"): close() with the rings mapped
# keeps the claim until the last munmap(); then the program unbinds the
# chip while a cyclic loop runs on the mapped rings, commands block, a
# poll()er and a reader sleep: each sees the documented error (uapi.rst
# "When the chip goes away"), the mapping stays valid until munmap(). Then
# binding again works, and the module unloads and loads again.
spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
/bin/ecmxf-guest-unbind /dev/ecmxf0 "$spidev" || fail "ecmxf-guest-unbind"
[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 still there after the unbind"
# the chip still runs the stuck async command: a fresh one
bridge_stop
bridge_start
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev after the unbind under load"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding again"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test after binding again"
echo "guest-test: ok   bind again after the unbind under load: /dev/ecmxf0 works"
# unbind during a link reset's format search (every answer "not ready"):
# the worker stops at the next exchange instead of finishing the search
/bin/ecmxf-guest-abuse unbind-reset /dev/ecmxf0 "$spidev" || fail "ecmxf-guest-abuse unbind-reset"
bridge_ctl clear
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev after the unbind during a link reset"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding again"
/bin/ecmxf-guest-abuse smoke /dev/ecmxf0 || fail "ecmxf-guest-abuse smoke after the unbind during a link reset"
# every file closed and unmapped: the module unloads (removing the chip)
# and loads again (the chip keeps the bus the guest test scanned)
rmmod ecmxf || fail "rmmod ecmxf after the unbind under load"
grep -q '^ecmxf ' /proc/modules && fail "ecmxf still loaded after rmmod"
echo "guest-test: ok   rmmod ecmxf after the unbind under load"
ecmxf_load
/bin/ecmxf-guest-abuse smoke /dev/ecmxf0 || fail "ecmxf-guest-abuse smoke after loading the module again"
