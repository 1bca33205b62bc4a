# SPDX-License-Identifier: MIT
# 32-bit userspace on the 64-bit kernel (uapi.rst, "32-bit programs"), as
# Raspberry Pi OS long ran a 32-bit userland on 64-bit kernels:
# ecmxf-guest-abuse built for i386 (amd64 guests) or armhf (arm64 guests),
# statically (run-qemu.sh), runs its smoke, args and perm parts through the
# kernel's compat_ioctl (compat_ptr_ioctl) and 32-bit mmap(): every ioctl
# with good and bad arguments, the rings mapped, the permission table.
[ -x /bin/ecmxf-guest-abuse32 ] || fail "no /bin/ecmxf-guest-abuse32"
/bin/ecmxf-guest-abuse32 smoke /dev/ecmxf0 || fail "ecmxf-guest-abuse32 smoke (a 32-bit program)"
/bin/ecmxf-guest-abuse32 args /dev/ecmxf0 || fail "ecmxf-guest-abuse32 args (a 32-bit program)"
/bin/ecmxf-guest-abuse32 perm /dev/ecmxf0 || fail "ecmxf-guest-abuse32 perm (a 32-bit program)"
echo "guest-test: ok   the uAPI's abuse tests as a 32-bit program ($(uname -m) kernel)"
