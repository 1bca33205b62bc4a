# SPDX-License-Identifier: MIT
# Injected faults through the bridge's control channel: bit errors both ways
# and the retry counters, "not ready", INT0 stuck, a silent chip.
# The plain FIFO interface first: a line echoed into it is applied in order.
echo "not-ready 5" >/tmp/bridge.ctl
state=$(bridge_ctl state)
echo "guest-test: info bridge $state"
case "$state" in
*" not-ready=5 "*) echo "guest-test: ok   echo into /tmp/bridge.ctl: not-ready=5" ;;
*) fail "echo 'not-ready 5' >/tmp/bridge.ctl not applied: $state" ;;
esac
bridge_ctl "not-ready 0" >/dev/null
if /bin/ecmxf-bridge ctl "no-such-command 1" >/tmp/ctl.out; then
	fail "bridge_ctl accepted an unknown command: $(cat /tmp/ctl.out)"
fi
echo "guest-test: ok   unknown bridge command refused: $(cat /tmp/ctl.out)"
/bin/ecmxf-guest-abuse faults /dev/ecmxf0 || fail "ecmxf-guest-abuse faults"
bridge_ctl clear >/dev/null
