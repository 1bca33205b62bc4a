# SPDX-License-Identifier: MIT
# A dead bridge must cost failed commands, not a hung kernel.
bridge_stop
/bin/ecmxf-guest-test --bridge-gone /dev/ecmxf0 || fail "ecmxf-guest-test --bridge-gone"
