# SPDX-License-Identifier: MIT
# The uAPI-only C example (examples/ecmxf-sdo-read.c, built static against
# include/uapi alone) against /dev/ecmxf0 and the bridge's default network
# (EST-584, EST-584, digital I/O): it brings the bus up to OP and reads an
# SDO with ioctls only. The values are the simulated slaves' object
# dictionary (lib/sim/slaves/est584.cpp; EST-584 manual 4.3.1: 0x2001:00
# pulses per revolution, default 50000; 0x2000:00 peak current, 3200 mA).
# Then the documented failures: an object the slave lacks (SDO abort
# 0x06020000), a slave position beyond the bus, the I/O terminal, which
# has no CoE mailbox (abort 0x08000023).

# c_example_read WANT ARGS...: the one line on stdout must be WANT
c_example_read() {
	want=$1
	shift
	out=$(/bin/ecmxf-sdo-read "$@" 2>/tmp/c-example.err) ||
		{ sed 's/^/c-example: /' /tmp/c-example.err; fail "ecmxf-sdo-read $* failed"; }
	sed 's/^/c-example: /' /tmp/c-example.err
	[ "$out" = "$want" ] || fail "ecmxf-sdo-read $* printed '$out', want '$want'"
	echo "guest-test: ok   C example: $out"
}

# c_example_fails PATTERN ARGS...: exit status 1, stderr matching PATTERN
c_example_fails() {
	pattern=$1
	shift
	rc=0
	out=$(/bin/ecmxf-sdo-read "$@" 2>/tmp/c-example.err) || rc=$?
	sed 's/^/c-example: /' /tmp/c-example.err
	[ "$rc" -eq 1 ] || fail "ecmxf-sdo-read $*: status $rc, want 1 (stdout '$out')"
	[ -z "$out" ] || fail "ecmxf-sdo-read $*: printed '$out' although it failed"
	grep -q "$pattern" /tmp/c-example.err || fail "ecmxf-sdo-read $*: no '$pattern' in its message"
	echo "guest-test: ok   C example fails as documented: $*: $(tail -n 1 /tmp/c-example.err)"
}

c_example_read "0x2001:00 of slave 0 = 50000 (0xc350, 2 bytes)" /dev/ecmxf0 0x2001:0
c_example_read "0x2000:00 of slave 1 = 3200 (0xc80, 2 bytes)" /dev/ecmxf0 0x2000:00 1
c_example_fails "SDO abort code 0x06020000" /dev/ecmxf0 0x2fff:0 0
c_example_fails "no slave at position 3: the bus has 3 slaves" /dev/ecmxf0 0x2001:0 3
c_example_fails "ECAT_SDO_REQ upload of 0x2001:00 from slave 2 failed: SDO abort code 0x08000023" /dev/ecmxf0 0x2001:0 2
