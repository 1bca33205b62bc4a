# SPDX-License-Identifier: MIT
# Signals during blocking waits (with and without SA_RESTART), per-command
# timeouts and their recovery by ECMXF_IOC_RESET, close with commands
# pending. Uses the bridge's async-stuck fault.
/bin/ecmxf-guest-abuse signals /dev/ecmxf0 || fail "ecmxf-guest-abuse signals"
bridge_ctl clear >/dev/null
