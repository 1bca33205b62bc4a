# SPDX-License-Identifier: MIT
# Concurrent openers: four threads of sync commands (two sharing a file) and
# two processes submitting async and immediate commands, every answer checked.
/bin/ecmxf-guest-abuse concurrency /dev/ecmxf0 || fail "ecmxf-guest-abuse concurrency"
