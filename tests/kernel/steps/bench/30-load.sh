# SPDX-License-Identifier: MIT
# The three cyclic paths under load (kernel-testing.rst "Benchmarks",
# "Under load"): stress-ng in the guest (a CPU hog per vCPU, context
# switches and pipe ping-pong as a hackbench-like scheduler load, and a
# memory worker), meanwhile /bin/ecmxf-guest-load-bench runs the kernel's
# rings, the ioctl loop and spidev one after the other, ECMXF_LOAD_N
# cycles (default 10^5) at each bus rate of ECMXF_LOAD_HZ (default
# 4000,8000), with the chip's clock ECMXF_LOAD_SCALE (default 4) times
# slower than the guest's (bridge --time-scale: the application's period
# is K/HZ of guest time). make bench boots this step alone on one vCPU
# whose clock counts instructions (QEMU -icount), with K 1: the chip's own
# rates, and no host scheduling in guest time; on two plain TCG vCPUs
# (run-qemu.sh --bench without those settings) K 4 is the default, and
# the host's stalls of QEMU's threads dominate. It prints the table: late
# cycles, the wake-up's 99.9th percentile and worst, output frames lost,
# and the rings' late cycles against spidev's; and per path the chip's
# RxFIFO underruns (bus cycles that found no new frame). The default
# bridge and ecmxf.ko are back afterwards.
. /steps/spidev.sh
n=${ECMXF_LOAD_N:-100000}
rates=$(echo "${ECMXF_LOAD_HZ:-4000,8000}" | tr , " ")
k=${ECMXF_LOAD_SCALE:-4}
command -v stress-ng >/dev/null || fail "no stress-ng in the guest"
underruns() { bridge_ctl state | sed -n 's/.*rx-underruns=\([0-9]*\).*/\1/p'; }
rebridge() {
	spi=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
	echo "$spi" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spi"
	bridge_stop
	bridge_start "$@"
	echo "$spi" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spi"
	[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after binding $spi again"
}
rebridge --time-scale "$k"
rm -f /tmp/ecmxf-load-results
stress-ng --cpu 2 --switch 1 --pipe 1 --vm 1 --vm-bytes 48M --timeout 3600 >/tmp/stress.log 2>&1 &
spid=$!
sleep 2
kill -0 "$spid" 2>/dev/null || fail "stress-ng did not start: $(cat /tmp/stress.log)"
echo "bench: load: stress-ng --cpu 2 --switch 1 --pipe 1 --vm 1 --vm-bytes 48M runs (pid $spid)"
for hz in $rates; do
	for p in rings ioctl; do
		u0=$(underruns)
		/bin/ecmxf-guest-load-bench "$p" "$hz" "$n" "$k" /dev/ecmxf0 || fail "ecmxf-guest-load-bench $p $hz"
		echo "bench: load $p $hz Hz: the chip's RxFIFO underruns $(($(underruns) - u0))"
	done
	spidev_take
	u0=$(underruns)
	/bin/ecmxf-guest-load-bench spidev "$hz" "$n" "$k" "spidev:$node?int0=$chip:0&int1=$chip:1&check=crc32" ||
		fail "ecmxf-guest-load-bench spidev $hz"
	echo "bench: load spidev $hz Hz: the chip's RxFIFO underruns $(($(underruns) - u0))"
	spidev_give_back --time-scale "$k"
done
kill "$spid"
wait "$spid" 2>/dev/null
echo "bench: load: under stress-ng, $n cycles per path and rate, the chip's clock K $k times slower than the guest's (1: its own rates):"
echo "bench: load:   path     Hz     late  wake p99.9 us  wake max us  frames lost"
while read -r p hz cyc late p999 worst lost; do
	printf 'bench: load:   %-7s %5s %8s %14s %12s %12s\n' "$p" "$hz" "$late" "$p999" "$worst" "$lost"
done </tmp/ecmxf-load-results
for hz in $rates; do
	rl=$(awk -v h="$hz" '$1 == "rings" && $2 == h { print $4 }' /tmp/ecmxf-load-results)
	sl=$(awk -v h="$hz" '$1 == "spidev" && $2 == h { print $4 }' /tmp/ecmxf-load-results)
	rlost=$(awk -v h="$hz" '$1 == "rings" && $2 == h { print $7 }' /tmp/ecmxf-load-results)
	echo "bench: load $hz Hz: rings late $rl vs spidev late $sl (target: rings <= spidev / 5), rings frames lost $rlost (target 0)"
done
rebridge
/bin/ecmxf-guest-test /dev/ecmxf0 >/dev/null || fail "ecmxf-guest-test after the load bench"
