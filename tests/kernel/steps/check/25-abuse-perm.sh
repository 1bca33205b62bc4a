# SPDX-License-Identifier: MIT
# Permissions: a read-only open (bus-changing and destructive commands
# refused), and a child that drops every capability by setuid(65534) after
# opening (destructive commands only with the claim).
/bin/ecmxf-guest-abuse perm /dev/ecmxf0 || fail "ecmxf-guest-abuse perm"
