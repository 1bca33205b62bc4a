# SPDX-License-Identifier: MIT
# rmmod while /dev/ecmxf0 is open must fail (the open file holds the
# module) and leave the device working; after the close the reference is
# gone again.
base=$(cat /sys/module/ecmxf/refcnt)
exec 3<>/dev/ecmxf0
held=$(cat /sys/module/ecmxf/refcnt)
# chrdev_open() takes two: the cdev's owner and the fops' owner
[ "$held" -gt "$base" ] || fail "ecmxf refcnt $held with /dev/ecmxf0 open, want more than $base"
if rmmod ecmxf 2>/tmp/rmmod.err; then
	fail "rmmod ecmxf succeeded while /dev/ecmxf0 was open"
fi
echo "guest-test: ok   rmmod ecmxf with /dev/ecmxf0 open refused: $(cat /tmp/rmmod.err)"
grep -q '^ecmxf ' /proc/modules || fail "ecmxf gone after the refused rmmod"
[ -c /dev/ecmxf0 ] || fail "/dev/ecmxf0 gone after the refused rmmod"
/bin/ecmxf-guest-abuse smoke /dev/ecmxf0 || fail "ecmxf-guest-abuse smoke after the refused rmmod"
exec 3>&-
[ "$(cat /sys/module/ecmxf/refcnt)" -eq "$base" ] ||
	fail "ecmxf refcnt $(cat /sys/module/ecmxf/refcnt) after the close, want $base"
echo "guest-test: ok   ecmxf refcnt back to $base after the close (held: $held)"
