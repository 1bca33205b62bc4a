# SPDX-License-Identifier: MIT
# The library's integration suite (tests/integration/) through /dev/ecmxf0.
# The bridge runs the suite's network for it (the default network with the
# dio's inputs looped back to its outputs); the default one is back after.
ecmxf_unload
bridge_stop
bridge_start /bin/ecmxf-integration.net
ecmxf_load
# the command round trip before and after the suite, on the same binding
# (figures only, no pass/fail: a path that slows down as it is used shows)
/bin/ecmxf-guest-bench kernel 200 /dev/ecmxf0 || fail "ecmxf-guest-bench before the suite"
rc=0
ECMXF_TEST_URI=/dev/ecmxf0 /bin/ecmxf-test-integration -d yes >/tmp/integ.log 2>&1 || rc=$?
sed 's/^/guest-test: integ(kernel): /' /tmp/integ.log
[ "$rc" -eq 0 ] || fail "test-integration through /dev/ecmxf0 (exit $rc)"
/bin/ecmxf-guest-bench kernel 200 /dev/ecmxf0 || fail "ecmxf-guest-bench after the suite"
ecmxf_unload
bridge_stop
bridge_start
ecmxf_load
