#!/bin/sh
# SPDX-License-Identifier: MIT
#
# /init of the QEMU kernel tests (Documentation/kernel-testing.rst): load the
# virtual SPI controller, start the bridge, load ecmxf.ko, run every step
# script of /steps/<mode> in name order, unload everything, print the
# marker, power off. The mode is the kernel parameter ecmxf_ktest= (check,
# the default, or bench). Any failure prints "ECMXF-KTEST: FAIL <why>" and
# powers off without the marker.
#
# The steps are sourced: they may call fail, bridge_start, bridge_stop,
# bridge_ctl, ecmxf_load, ecmxf_unload, vspi_reload, and must leave ecmxf.ko loaded and bound to the
# virtual controller with a bridge running (or call bridge_start again).

export PATH=/bin:/sbin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev

fail() {
	echo "ECMXF-KTEST: FAIL $*"
	[ -f /tmp/bridge.log ] && sed 's/^/bridge: /' /tmp/bridge.log
	echo "ECMXF-KTEST: kernel log follows"
	dmesg
	poweroff -f
	sleep 10
}

# bridge_start [args...]: the simulated chip behind the virtual controller
bridge=""
bridge_start() {
	[ -n "$bridge" ] && fail "bridge_start: a bridge is already running"
	# the wait below looks for "ready" in the log: not the old bridge's
	rm -f /tmp/bridge.log
	/bin/ecmxf-bridge "$@" 2>/tmp/bridge.log &
	bridge=$!
	i=0
	until grep -q "ready" /tmp/bridge.log 2>/dev/null; do
		i=$((i + 1))
		[ $i -gt 200 ] && fail "the bridge did not start"
		kill -0 "$bridge" 2>/dev/null || fail "the bridge exited"
		sleep 0.1
	done
}

# bridge_stop: SIGTERM; the bridge prints its counters and must exit 0
bridge_stop() {
	[ -n "$bridge" ] || fail "bridge_stop: no bridge running"
	kill "$bridge"
	wait "$bridge" || fail "the bridge failed"
	bridge=""
	sed 's/^/bridge: /' /tmp/bridge.log
}

# bridge_ctl CMD [ARG]: a control command to the running bridge (fault
# injection, see tests/kernel/bridge.cpp); prints the bridge's reply
bridge_ctl() {
	/bin/ecmxf-bridge ctl "$@" || fail "bridge_ctl $*"
}

# wait_for FILE PATTERN SECONDS: until grep -q finds PATTERN in FILE;
# status 1 when it did not within SECONDS
wait_for() {
	n=0
	until grep -q "$2" "$1" 2>/dev/null; do
		n=$((n + 1))
		[ "$n" -gt $(($3 * 10)) ] && return 1
		sleep 0.1
	done
	return 0
}

ecmxf_load() {
	insmod /lib/modules/ecmxf.ko "$@" || fail "insmod ecmxf.ko $*"
	[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after insmod ecmxf.ko"
}

# vspi_reload [args...]: ecmxf-vspi loaded again with these parameters
# (ecmxf.ko unloaded first when loaded, the bridge restarted, the kernel
# log emptied); ecmxf.ko is not loaded again
vspi_reload() {
	lsmod | grep -q '^ecmxf ' && ecmxf_unload
	bridge_stop
	rmmod ecmxf-vspi || fail "rmmod ecmxf-vspi"
	insmod /lib/modules/ecmxf-vspi.ko "$@" || fail "insmod ecmxf-vspi.ko $*"
	bridge_start
	dmesg -c >/dev/null
}

ecmxf_unload() {
	rmmod ecmxf || fail "rmmod ecmxf"
	[ -e /dev/ecmxf0 ] && fail "/dev/ecmxf0 still there after rmmod"
}

mode=check
for a in $(cat /proc/cmdline); do
	case "$a" in
	ecmxf_ktest=*) mode=${a#ecmxf_ktest=} ;;
	ecmxf_ktest_steps=*) only=${a#ecmxf_ktest_steps=} ;;
	esac
done
[ -d "/steps/$mode" ] || fail "no steps for mode '$mode'"

# guest uptime (under TCG it follows the host's clock): run-qemu.sh takes
# the boot time from this line and the suite's from the "steps done" line
uptime_s() { cut -d' ' -f1 /proc/uptime; }
echo "ECMXF-KTEST: guest up, kernel $(uname -r) $(uname -m), mode $mode, uptime $(uptime_s) s"
insmod /lib/modules/ecmxf-vspi.ko || fail "insmod ecmxf-vspi.ko"
[ -c /dev/ecmxf-vspi ] || fail "no /dev/ecmxf-vspi"
bridge_start
ecmxf_load

# ecmxf_ktest_steps=95,80 (run-qemu.sh's ECMXF_KTEST_STEPS, for iterating
# on a step): only the steps whose names begin with one of these
[ -n "${only:-}" ] && echo "ECMXF-KTEST: only the steps $only (a narrowed run)"
for step in /steps/"$mode"/*.sh; do
	[ -f "$step" ] || continue
	if [ -n "${only:-}" ]; then
		keep=""
		for o in $(echo "$only" | tr , ' '); do
			case "${step##*/}" in "$o"*) keep=1 ;; esac
		done
		[ -n "$keep" ] || continue
	fi
	echo "ECMXF-KTEST: step ${step##*/} (uptime $(uptime_s) s)"
	. "$step"
done

[ -n "$bridge" ] && bridge_stop
lsmod | grep -q '^ecmxf ' && ecmxf_unload
rmmod ecmxf-vspi || fail "rmmod ecmxf-vspi"

echo "ECMXF-KTEST: steps done, uptime $(uptime_s) s"
# the whole kernel log once more, at every level, for the host's scan
dmesg
echo "ECMXF-KTEST: PASS"
poweroff -f
sleep 10
