# SPDX-License-Identifier: MIT
# Abuse tests of /dev/ecmxf0 (tests/kernel/guest-abuse.cpp): unknown ioctl
# numbers and sizes, reserved fields, flags, lengths, bad user pointers,
# read()/poll()/write()/lseek()/mmap(), resets, the claim, the open limit.
/bin/ecmxf-guest-abuse args /dev/ecmxf0 || fail "ecmxf-guest-abuse args"
