# SPDX-License-Identifier: MIT
# INT1 in the interrupt form (driver.rst "INT0 and INT1"): ecmxf-vspi
# gives INT1 as the device's one unnamed interrupt (spi_board_info.irq,
# the board-code form), level low, then falling edge, then without a
# trigger type (refused); INT0 stays a GPIO. Named interrupts
# ("interrupts" + "interrupt-names") need DT or ACPI, which Debian's x86
# kernels cannot give a test device (kernel-testing.rst). Also: the
# driver's spi->rt puts the controller's message pump at SCHED_FIFO.
# Afterwards the GPIO form again.
probe_says() {
	dmesg | grep -q "$1" || fail "the probe message does not say '$1'"
	echo "guest-test: ok   probe: $(dmesg | grep -m1 -o 'INT0 .*')"
}

vspi_reload int1=irq-level
ecmxf_load
probe_says "INT0 GPIO IRQ [0-9]*, rising edge, INT1 interrupt IRQ [0-9]*, level low$"
[ "$(cat /sys/class/ecmxf/ecmxf0/int1)" = wired ] || fail "sysfs int1 is not 'wired' with the interrupt form"
/bin/ecmxf-guest-test --int1-level /dev/ecmxf0 || fail "ecmxf-guest-test --int1-level"
grep ecmxf-int /proc/interrupts | sed 's/^/guest-test: info /'

# spi->rt = true before spi_setup(): the SPI core runs the controller's
# message pump (kthread "spiN") at SCHED_FIFO
dmesg | grep -q "will run message pump with realtime priority" ||
	fail "the SPI core did not put the message pump at realtime priority"
ctlr=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
ctlr=${ctlr%%.*}
pump=""
for c in /proc/[0-9]*/comm; do
	[ "$(cat "$c" 2>/dev/null)" = "$ctlr" ] || continue
	pol=$(/bin/ecmxf-chrt -p "$(basename "${c%/comm}")")
	case "$pol" in SCHED_FIFO*) ;; *) fail "message pump $ctlr runs $pol" ;; esac
	echo "guest-test: ok   spi->rt: message pump $ctlr runs $pol"
	pump=$c
done
[ -n "$pump" ] || fail "no message pump thread $ctlr"
# driver.rst "Threads and their priorities": by default what the worker
# waits for (the message pump, ecmxf's IRQ threads where the handlers are
# threaded, as on PREEMPT_RT) runs at least at the worker's priority
rt_prio() { cut -d' ' -f18 "$1/stat" | sed 's/^-//' | awk '{ print $1 - 1 }'; }
wprio=""
for c in /proc/[0-9]*/comm; do
	[ "$(cat "$c" 2>/dev/null)" = ecmxf0 ] && wprio=$(rt_prio "${c%/comm}")
done
[ -n "$wprio" ] || fail "no ecmxf0 worker thread"
nirq=0
for c in /proc/[0-9]*/comm; do
	name=$(cat "$c" 2>/dev/null) || continue
	# a comm is cut at 15 characters: irq/NN-ecmxf-int0 -> irq/NN-ecmxf-in
	case "$name" in "$ctlr") ;; irq/*-ecmxf-i*) nirq=$((nirq + 1)) ;; *) continue ;; esac
	p=$(rt_prio "${c%/comm}")
	[ "$p" -ge "$wprio" ] || fail "$name runs at real-time priority $p, below the worker's $wprio"
done
echo "guest-test: ok   the message pump $ctlr and $nirq ecmxf IRQ thread(s) at or above the worker's priority $wprio"

vspi_reload int1=irq-edge
ecmxf_load
probe_says "INT1 interrupt IRQ [0-9]*, falling edge$"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test with INT1 as an edge interrupt"

# an interrupt without a trigger type: level or edge decides how the
# driver handles it, so the probe refuses it
vspi_reload int1=irq-none
insmod /lib/modules/ecmxf.ko || fail "insmod ecmxf.ko"
[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 exists with an INT1 interrupt without a trigger type"
# dev_err_probe() prints the errno by name with CONFIG_SYMBOLIC_ERRNAME
# (Debian's kernels), as a number without it (the debug kernel)
dmesg | grep -Eq "error -(EINVAL|22): the int1 interrupt \(IRQ [0-9]+\) has no trigger type" ||
	fail "no probe failure reason for the INT1 interrupt without a trigger type"
echo "guest-test: ok   $(dmesg | grep -m1 -Eo 'error -(EINVAL|22): the int1 interrupt.*')"

vspi_reload
ecmxf_load
probe_says "INT0 GPIO IRQ [0-9]*, rising edge, INT1 GPIO IRQ [0-9]*, falling edge$"
