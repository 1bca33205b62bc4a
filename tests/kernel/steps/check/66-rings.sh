# SPDX-License-Identifier: MIT
# The cyclic path through the kernel's mmap()ed PDO rings
# (tests/kernel/guest-rings.cpp), with the library's Cyclic over
# /dev/ecmxf0, on a network with a loopback I/O terminal
# (kernel-testing.rst "PDO rings"):
#  - lock-step: 10 000 bus cycles at 1 kHz and at 8 kHz with the bridge's
#    lock-step bus (bridge --lockstep), the application clocked by its
#    inputs: strict, no frame lost, repeated or reordered, every count 0;
#    the 8 kHz run with ECMXF_RING_F_FIFO_NEXT (one exchange per pump
#    command);
#  - ratio mode: 2 000 bus cycles at each rate with the chip's clock
#    scaled by K (bridge --time-scale), the application timer-clocked:
#    every loss counted; the claim and ring-overflow checks; the 8 kHz run
#    with ECMXF_RING_F_FIFO_NEXT.
# Afterwards the default bridge again.
rings_bridge() {
	spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
	echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev"
	bridge_stop
	/bin/ecmxf-guest-rings --network >/tmp/rings.net
	bridge_start "$@" /tmp/rings.net
	echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev"
	[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 with the rings network"
}
rings_lockstep() {
	hz=$1
	rings_bridge --lockstep
	t0=$(cut -d' ' -f1 /proc/uptime)
	# shellcheck disable=SC2086 # $2: an optional mode word
	/bin/ecmxf-guest-rings run-lockstep /dev/ecmxf0 "$hz" 10000 ${2:-} || fail "ecmxf-guest-rings lock-step at $hz Hz ${2:-}"
	t1=$(cut -d' ' -f1 /proc/uptime)
	echo "guest-test: info lock-step $hz Hz: $t0 s -> $t1 s of guest uptime"
	bridge_ctl state
}
# the ratio-mode run; with "monitor", `ecmxf-util monitor` listens and must
# report the input ring's overflow (which the run provokes) as a PDO_LOSS
# event with the kernel's count; with "fifo-next" the pump runs with
# ECMXF_RING_F_FIFO_NEXT
rings_with() {
	hz=$1 scale=$2
	rings_bridge --time-scale "$scale"
	if [ "${3:-}" = monitor ]; then
		/bin/ecmxf-util -d /dev/ecmxf0 monitor --json >/tmp/rings-mon.json 2>/tmp/rings-mon.err &
		rmon=$!
		wait_for /tmp/rings-mon.err listening 30 || fail "ecmxf-util monitor did not subscribe"
	fi
	mode=
	[ "${3:-}" = fifo-next ] && mode=fifo-next
	# shellcheck disable=SC2086 # $mode: an optional mode word
	/bin/ecmxf-guest-rings run /dev/ecmxf0 "$hz" 2000 "$scale" $mode || fail "ecmxf-guest-rings at $hz Hz $mode"
	bridge_ctl state
	if [ "${3:-}" = monitor ]; then
		# the run overflowed the input ring: events up to the kernel's
		# final count (the rate limit never drops the last one)
		want=$(cat /sys/class/ecmxf/ecmxf0/counters/in_ring_overruns)
		[ "$want" -gt 0 ] || fail "in_ring_overruns is $want after the overflow check"
		loss="\"type\": \"pdo_loss\", \"loss\": \"in_ring_overrun\", \"increase\": [0-9]*, \"total\": $want[,}]"
		if ! wait_for /tmp/rings-mon.json "$loss" 30; then
			kill "$rmon" 2>/dev/null
			sed 's/^/monitor: /' /tmp/rings-mon.json /tmp/rings-mon.err
			fail "ecmxf-util monitor reported no PDO_LOSS in_ring_overrun event with the total $want"
		fi
		kill "$rmon"
		wait "$rmon" || fail "ecmxf-util monitor exited with an error after SIGTERM"
		grep '"pdo_loss"' /tmp/rings-mon.json | sed 's/^/guest-test: event: /'
		echo "guest-test: ok   ecmxf-util monitor: PDO_LOSS in_ring_overrun events up to the kernel's in_ring_overruns ($want)"
	fi
}
# the worker's scheduling: sched_set_fifo() at probe (SCHED_FIFO 50), tuned
# from userspace with chrt as for any kthread (driver.rst "Locking and
# PREEMPT_RT"; busybox has no chrt: /bin/ecmxf-chrt does its system calls).
# /proc/PID/stat field 18 is -1 - rt_priority for a real-time task.
worker_pid() {
	for c in /proc/[0-9]*/comm; do
		[ "$(cat "$c" 2>/dev/null)" = ecmxf0 ] || continue
		c=${c%/comm}
		echo "${c#/proc/}"
		return
	done
	fail "no ecmxf0 worker thread"
}
worker_prio_is() {
	p=$(cut -d' ' -f18 "/proc/$wpid/stat")
	[ "$p" = "$((-1 - $1))" ] || fail "worker priority field $p, want $((-1 - $1))"
	[ "$(/bin/ecmxf-chrt -p "$wpid")" = "SCHED_FIFO $1" ] ||
		fail "ecmxf-chrt -p: $(/bin/ecmxf-chrt -p "$wpid"), want SCHED_FIFO $1"
	echo "guest-test: ok   worker ecmxf0 (pid $wpid) runs SCHED_FIFO at priority $1 (stat field 18: $p)"
}
wpid=$(worker_pid)
[ -e /sys/class/ecmxf/ecmxf0/worker_priority ] && fail "the sysfs worker_priority knob is still there"
[ -e /sys/module/ecmxf/parameters/worker_prio ] && fail "the worker_prio module parameter is still there"
worker_prio_is 50
/bin/ecmxf-chrt -f -p 70 "$wpid" || fail "chrt -f -p 70 on the worker"
worker_prio_is 70
if /bin/ecmxf-chrt -f -p 0 "$wpid" 2>/dev/null; then fail "SCHED_FIFO 0 accepted"; fi
if /bin/ecmxf-chrt -f -p 100 "$wpid" 2>/dev/null; then fail "SCHED_FIFO 100 accepted"; fi
worker_prio_is 70
echo "guest-test: ok   the kernel refuses SCHED_FIFO 0 and 100 for the worker"
# a slow guest is not what is tested: the pump's commands get 10 s
# (a failed one loses its frames, which the strict runs would report);
# the parameter is read at probe, read-only afterwards (88-properties.sh)
ecmxf_unload
ecmxf_load pump_timeout_ms=10000
rings_lockstep 1000
# the 8 kHz run with a reader hammering the counters (sysfs and netlink
# GET_COUNTERS): they are a snapshot the worker publishes and readers copy
# without the worker's lock (driver.rst "Locking and PREEMPT_RT"); the strict
# run must keep its bar, and every counter read must be whole (never
# smaller than the one before: a torn copy would be)
counters_hammer() {
	prev=0
	while [ ! -e /tmp/hammer.stop ]; do
		for f in /sys/class/ecmxf/ecmxf0/counters/*; do cat "$f" >/dev/null; done
		v=$(cat /sys/class/ecmxf/ecmxf0/counters/exchanges)
		if [ "$v" -lt "$prev" ]; then
			echo "sysfs exchanges went back: $prev -> $v" >>/tmp/hammer.fail
		fi
		prev=$v
		/bin/ecmxf-util -d /dev/ecmxf0 monitor --counters >/tmp/hammer.nl 2>&1 ||
			echo "monitor --counters failed: $(cat /tmp/hammer.nl)" >>/tmp/hammer.fail
		n=$(sed -n 's/^exchanges *//p' /tmp/hammer.nl)
		if [ -n "$n" ] && [ "$n" -lt "$v" ]; then
			echo "netlink exchanges $n below the sysfs value read before it ($v)" >>/tmp/hammer.fail
		fi
		reads=$((reads + 1))
		echo "$reads" >/tmp/hammer.reads
	done
}
rm -f /tmp/hammer.stop /tmp/hammer.fail /tmp/hammer.reads
reads=0
rings_bridge --lockstep
counters_hammer &
hpid=$!
/bin/ecmxf-guest-rings run-lockstep /dev/ecmxf0 8000 10000 fifo-next ||
	fail "ecmxf-guest-rings lock-step at 8000 Hz fifo-next, counters read meanwhile"
touch /tmp/hammer.stop
wait "$hpid"
bridge_ctl state
[ -s /tmp/hammer.fail ] && fail "counters under the 8 kHz run: $(head -3 /tmp/hammer.fail)"
echo "guest-test: ok   $(cat /tmp/hammer.reads 2>/dev/null || echo 0) rounds of sysfs + netlink counter reads during the 8 kHz lock-step run, each whole"
rings_with 1000 5 monitor
rings_with 8000 40 fifo-next
ecmxf_unload
ecmxf_load
# the rings rebound the device: a new worker, which starts at 50 again
# (chrt must be applied again after every probe, driver.rst)
wpid=$(worker_pid)
worker_prio_is 50
failures=$(cat /sys/class/ecmxf/ecmxf0/ring_failures) || fail "no sysfs ring_failures"
echo "guest-test: info pump commands failed (ring_failures): $failures"
spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev"
bridge_stop
bridge_start
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev (default bridge)"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after the rings"
