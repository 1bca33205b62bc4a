# SPDX-License-Identifier: MIT
# The kernel's generic netlink events (driver.rst, "Events (generic
# netlink)"): `ecmxf-util monitor --json` over /dev/ecmxf0 subscribes; the
# bus goes to OP; the bridge loses the link (bridge_ctl link-lost 1). The
# monitor must report the state change OP -> ERROR, with the three slaves
# of the default network not answering, and the link going down. Then the
# counters read over netlink must equal ECMXF_IOC_COUNTERS'. Afterwards the
# link is back and the bus in OP again for the following steps.
mon_out=/tmp/monitor.json
mon_err=/tmp/monitor.err

/bin/ecmxf-nl-helper op /dev/ecmxf0 || fail "bus to OP before the netlink test"

# joining the events group needs CAP_NET_ADMIN (a listener makes the worker
# poll the chip); reading the counters needs nothing
if /bin/ecmxf-nl-helper as 1000 /bin/ecmxf-util -d /dev/ecmxf0 monitor --json --count 1 \
	>/tmp/unpriv.out 2>/tmp/unpriv.err; then
	fail "an unprivileged user joined the events group"
fi
grep -q "joining the group 'events'.*not permitted" /tmp/unpriv.err || {
	cat /tmp/unpriv.err
	fail "an unprivileged join failed, but not with EPERM"
}
/bin/ecmxf-nl-helper as 1000 /bin/ecmxf-util -d /dev/ecmxf0 monitor --counters >/tmp/unpriv.counters ||
	fail "an unprivileged user could not read the netlink counters"
grep -q '^exchanges [0-9]' /tmp/unpriv.counters || fail "unprivileged counters: no exchanges line"
echo "guest-test: ok   netlink: joining the events group needs CAP_NET_ADMIN; counters need nothing"

/bin/ecmxf-util -d /dev/ecmxf0 monitor --json --count 50 >"$mon_out" 2>"$mon_err" &
mon=$!
wait_for "$mon_err" "listening" 30 || {
	cat "$mon_err"
	fail "ecmxf-util monitor did not subscribe to the events"
}

bridge_ctl link-lost 1
state='"type": "state", "from": 8, "to": 16'
link='"type": "link", "link_up": false'
if ! wait_for "$mon_out" "$state" 60 || ! wait_for "$mon_out" "$link" 30; then
	kill "$mon" 2>/dev/null
	sed 's/^/monitor: /' "$mon_out" "$mon_err"
	fail "ecmxf-util monitor did not report the link loss (state OP -> ERROR and link down)"
fi
kill "$mon"
wait "$mon" || fail "ecmxf-util monitor exited with an error after SIGTERM"
sed 's/^/guest-test: event: /' "$mon_out"
ev=$(grep "$state" "$mon_out" | head -n 1)
# the kernel read the slaves: 3 on the bus, none answering
case $ev in
*'"slave_count": 3'*'"position": 0, "answering": false'*'"position": 2, "answering": false'*) ;;
*) fail "the state event lacks the slaves: $ev" ;;
esac
case $ev in *'"device": "ecmxf0"'*) ;; *) fail "the state event names no device: $ev" ;; esac
echo "guest-test: ok   netlink: state OP -> ERROR with the slaves, and link down"

# counters: netlink (GET_COUNTERS do) against the ioctl, with nobody
# subscribed (so the worker does not poll in between)
/bin/ecmxf-util -d /dev/ecmxf0 monitor --counters >/tmp/counters.nl ||
	fail "ecmxf-util monitor --counters"
/bin/ecmxf-nl-helper counters /dev/ecmxf0 >/tmp/counters.ioctl || fail "ecmxf-nl-helper counters"
head -n 22 /tmp/counters.nl >/tmp/counters.nl22
if ! cmp -s /tmp/counters.nl22 /tmp/counters.ioctl; then
	diff /tmp/counters.ioctl /tmp/counters.nl22
	fail "netlink counters differ from ECMXF_IOC_COUNTERS"
fi
grep -q '^events [1-9]' /tmp/counters.nl || fail "netlink counters: no events counted"
echo "guest-test: ok   netlink counters equal ECMXF_IOC_COUNTERS ($(head -n 1 /tmp/counters.nl))"

# back to a working bus
bridge_ctl link-lost 0
/bin/ecmxf-nl-helper op /dev/ecmxf0 || fail "bus to OP after the link came back"

# A slave that answers with an AL status code: slave 0 to INIT (the bus
# state goes down to INIT), then INIT -> OP, which the slave refuses with
# AL status 0x0011 and its error bit (the bus state becomes ERROR); the
# STATE_SET ends with the async error bit (-EREMOTEIO)
: >"$mon_err"
/bin/ecmxf-util -d /dev/ecmxf0 monitor --json --count 50 >"$mon_out" 2>"$mon_err" &
mon=$!
wait_for "$mon_err" "listening" 30 || fail "ecmxf-util monitor did not subscribe (second time)"
/bin/ecmxf-nl-helper refused /dev/ecmxf0 || fail "the refused state change"
state='"type": "state", "from": 1, "to": 16'
async='"type": "async_error", "command": 12,'
if ! wait_for "$mon_out" "$state" 60 || ! wait_for "$mon_out" "$async" 30; then
	kill "$mon" 2>/dev/null
	sed 's/^/monitor: /' "$mon_out" "$mon_err"
	fail "ecmxf-util monitor did not report the refused state change"
fi
kill "$mon"
wait "$mon" || fail "ecmxf-util monitor exited with an error after SIGTERM (second time)"
sed 's/^/guest-test: event: /' "$mon_out"
ev=$(grep "$state" "$mon_out" | head -n 1)
# slave 0 answers: INIT + error, AL status 0x0011 (17); slaves 1, 2 in OP
case $ev in
*'"position": 0, "answering": true, "state": 1, "state_name": "INIT", "error": true, "al_status_code": 17,'*) ;;
*) fail "the state event lacks slave 0's AL status code 0x0011: $ev" ;;
esac
case $ev in *'"position": 1'*) fail "the state event lists slave 1, which is in OP: $ev" ;; esac
case $ev in *'"al_status_code": 17, "device"'*) ;; *) fail "no AL status code on the event: $ev" ;; esac
grep "$async" "$mon_out" | grep -q "\"status\": -121," || fail "the async error is not -EREMOTEIO (-121)"
echo "guest-test: ok   netlink: state INIT -> ERROR with slave 0's AL status 0x0011, async error of STATE_SET"
/bin/ecmxf-nl-helper op /dev/ecmxf0 || fail "bus to OP after the refused state change"
