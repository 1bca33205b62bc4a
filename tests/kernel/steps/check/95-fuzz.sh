# SPDX-License-Identifier: MIT
# The interface fuzzer (tests/kernel/guest-fuzz.cpp, kernel-testing.rst
# "The interface fuzzer"): random opens, ioctls with mutated structures
# and bad pointers, ring mmaps at odd offsets and lengths, read/poll/close
# from several threads, unbind and bind of the device, for a bounded time;
# afterwards the device must still work. 25 s of guest time on Debian's
# kernels, 120 s on the debug kernel (KASAN, lockdep; its release ends in
# -ecmxf-debug, tests/kernel/debug.config). The kernel parameters
# ecmxf_fuzz_seed= and ecmxf_fuzz_seconds= (run-qemu.sh passes
# ECMXF_FUZZ_SEED and ECMXF_FUZZ_SECONDS) replay a seed the run printed;
# ecmxf_fuzz_format_changes=1 (ECMXF_FUZZ_FORMAT_CHANGES=1) adds
# --format-changes.
# Step 90 left no bridge: a fresh one, and the device bound to it.
spidev=$(basename "$(readlink /sys/class/ecmxf/ecmxf0/device)")
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev"
[ -n "$bridge" ] && bridge_stop
bridge_start
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 before the fuzzer"
fuzz_args="--seconds 25"
case "$(uname -r)" in
*-ecmxf-debug) fuzz_args="--seconds 120 --stall-ms 6000 --hang-s 240" ;;
esac
read -r cmdline </proc/cmdline
for a in $cmdline; do
	case "$a" in
	ecmxf_fuzz_seed=*) fuzz_args="$fuzz_args --seed ${a#ecmxf_fuzz_seed=}" ;;
	ecmxf_fuzz_seconds=*) fuzz_args="$fuzz_args --seconds ${a#ecmxf_fuzz_seconds=}" ;;
	ecmxf_fuzz_format_changes=1) fuzz_args="$fuzz_args --format-changes" ;;
	esac
done
# shellcheck disable=SC2086
/bin/ecmxf-guest-fuzz $fuzz_args /dev/ecmxf0 || fail "ecmxf-guest-fuzz $fuzz_args"
# and from a fresh probe, the end-to-end checks
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/unbind || fail "unbind $spidev after the fuzzer"
echo "$spidev" >/sys/bus/spi/drivers/ecmxf/bind || fail "bind $spidev after the fuzzer"
[ -c /dev/ecmxf0 ] || fail "no /dev/ecmxf0 after the fuzzer"
/bin/ecmxf-guest-test /dev/ecmxf0 || fail "ecmxf-guest-test after the fuzzer"
