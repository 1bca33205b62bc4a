# SPDX-License-Identifier: MIT
# Permissions (Documentation/uapi.rst): every class from a read-only open,
# root, a member of the device group, an outsider, and during a claim held
# by another file; each allowed row works, each forbidden one gets its errno.
/bin/ecmxf-guest-abuse perm /dev/ecmxf0 || fail "ecmxf-guest-abuse perm"
