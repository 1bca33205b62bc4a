#!/bin/sh
# SPDX-License-Identifier: MIT
#
# make check-deb: the Debian packages of `make deb` installed on this
# machine and taken apart again (Documentation/building.rst, "Debian
# packages").  Needs root; runs in CI (.ci/run), not in make check: it
# installs packages system-wide.
#
#   scripts/check-deb.sh [--no-build] OUTDIR [JOBS]
#
# --no-build: test the packages already in OUTDIR (a second run while
# working on this script).
#
#  1. make deb: dpkg-buildpackage + lintian (no error, no warning);
#  2. dpkg -i of libecmxf0, libecmxf-dev, ecmxf-tools, python3-ecmxf,
#     ecmxf-dkms: DKMS
#     registers the module source;
#  3. DKMS has built and installed ecmxf.ko (AUTOINSTALL, from the
#     package's postinst) for the installed headers of Debian's normal and
#     PREEMPT_RT kernel (linux-headers-amd64 and -rt-amd64: the kernels
#     they depend on), and each module's vermagic names its kernel;
#  4. the installed ecmxf-util (no RUNPATH in /usr/bin) lists the
#     simulator's slaves and brings them to OP, also through an installed
#     ecmxf-sim over a Unix socket; the man pages are found by man -w;
#     the installed python3-ecmxf imports (no RUNPATH) and reads an object
#     of the simulator, an abort raising ecmxf.SdoAbort;
#  5. a consumer builds against the installed -dev package with CMake
#     (find_package(ecmxf), ecmxf::ecmxf, no standard of its own) and with
#     pkg-config, and runs;
#  6. dpkg --purge: no package left, nothing of ecmxf left on the file
#     system (every file the packages listed, /usr/src/ecmxf-*,
#     /var/lib/dkms/ecmxf, built modules), no group "ecmxf" if there was
#     none before.
# The packages are purged on any exit, pass or fail.
set -eu
build=1
[ "${1:-}" = --no-build ] && { build=0; shift; }
out=$1 jobs=${2:-2}
src=$(cd "$(dirname "$0")/.." && pwd)
pkgs="libecmxf0 libecmxf-dev ecmxf-tools python3-ecmxf ecmxf-dkms"

fail() { echo "check-deb: FAIL: $*" >&2; exit 1; }
t0=$(date +%s)
ok() { echo "check-deb: ok: $* [$(($(date +%s) - t0)) s]"; }

[ "$(id -u)" -eq 0 ] || fail "needs root (it installs and purges packages)"
for p in $pkgs; do
	if dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null | grep -q '^[ihU]'; then
		fail "$p is installed already: purge it first (dpkg --purge $pkgs)"
	fi
done

[ $build -eq 0 ] || "$src/scripts/make-deb.sh" "$out" "$jobs"
out=$(cd "$out" && pwd)
ok "make deb"
version=$(dpkg-parsechangelog -l "$src/debian/changelog" -S Version)
arch=$(dpkg --print-architecture)

work=$(mktemp -d)
had_group=0
getent group ecmxf >/dev/null && had_group=1
purge() {
	dpkg --purge $pkgs >"$work/purge.log" 2>&1 || { cat "$work/purge.log"; return 1; }
}
cleanup() {
	rc=$?
	# whatever happened: nothing of ours stays installed
	purge >/dev/null 2>&1 || true
	kill "${simpid:-}" 2>/dev/null || true
	rm -rf "$work"
	exit $rc
}
trap cleanup EXIT INT TERM

# what is there before, to compare after the purge
snapshot() {
	find /usr /etc /var/lib/dkms /opt -xdev 2>/dev/null | sort
}
snapshot >"$work/before"
# kernels with headers only (no modules.dep): DKMS's depmod creates the
# module indexes there, the purge's depmod leaves them; they go again
fresh_kdirs=""
for d in /lib/modules/*/; do
	[ -e "$d/modules.dep" ] || fresh_kdirs="$fresh_kdirs ${d%/}"
done

# ---- 2. install
debs=""
for p in libecmxf0 libecmxf-dev ecmxf-tools python3-ecmxf; do debs="$debs $out/${p}_${version}_${arch}.deb"; done
debs="$debs $out/ecmxf-dkms_${version}_all.deb"
# shellcheck disable=SC2086
dpkg -i $debs >"$work/install.log" 2>&1 || { cat "$work/install.log"; fail "dpkg -i"; }
sed 's/^/  | /' "$work/install.log" | grep -i 'dkms\|ecmxf\|kernel' | head -n 20
for p in $pkgs; do
	dpkg-query -W -f='${db:Status-Abbrev}' "$p" | grep -q '^ii' || fail "$p is not installed"
done
ok "installed: $pkgs"
dkms status -m ecmxf -v "$version" | grep -q . || fail "dkms does not know ecmxf/$version"
[ -f "/usr/src/ecmxf-$version/dkms.conf" ] || fail "no /usr/src/ecmxf-$version/dkms.conf"
grep -q '^AUTOINSTALL="yes"' "/usr/src/ecmxf-$version/dkms.conf" || fail "dkms.conf: no AUTOINSTALL"
getent group ecmxf >/dev/null || fail "no group ecmxf after install"
[ -f /lib/udev/rules.d/60-ecmxf.rules ] || fail "no udev rule"
for o in ecmxf-rpi-overlay.dts ecmxf-rpi-debian-overlay.dts; do
	[ -f "/usr/share/ecmxf/devicetree/$o" ] || fail "ecmxf-dkms does not ship the device tree overlay $o"
done
! dpkg-query -W -f='${Recommends}' ecmxf-dkms | grep -q 'linux-headers-generic' ||
	fail "ecmxf-dkms recommends linux-headers-generic (an Ubuntu name)"
ok "DKMS knows ecmxf/$version (AUTOINSTALL), udev rule and group ecmxf in place"

# ---- 3. DKMS against the normal and the RT kernel's headers
kernels=""
for meta in linux-headers-amd64 linux-headers-rt-amd64; do
	k=$(dpkg-query -W -f='${Depends}' "$meta" 2>/dev/null | sed -n 's/^linux-headers-\([^ ,]*\).*/\1/p')
	[ -n "$k" ] || fail "$meta is not installed (scripts/install-deps.sh --kernel)"
	kernels="$kernels $k"
done
for k in $kernels; do
	status=$(dkms status -m ecmxf -v "$version" -k "$k")
	case $status in
	*installed*) ;;
	*)
		# not built by the postinst: the headers came after? build it here
		echo "check-deb: dkms status for $k after install: '$status'; dkms install"
		dkms install -m ecmxf -v "$version" -k "$k" >"$work/dkms-$k.log" 2>&1 || {
			cat "$work/dkms-$k.log"
			cat "/var/lib/dkms/ecmxf/$version/build/make.log" 2>/dev/null || true
			fail "dkms install for $k"
		}
		;;
	esac
	ko=$(find "/lib/modules/$k/updates/dkms" -name 'ecmxf.ko*' 2>/dev/null | head -n 1)
	[ -n "$ko" ] || fail "DKMS: no ecmxf.ko in /lib/modules/$k/updates/dkms"
	vermagic=$(modinfo -F vermagic "$ko")
	case $vermagic in
	"$k "*) ;;
	*) fail "$ko has vermagic '$vermagic'" ;;
	esac
	ok "DKMS built and installed $ko, vermagic '$vermagic'"
done

# ---- 4. the installed tools
readelf -d /usr/bin/ecmxf-util | grep -q 'R.*PATH' && fail "/usr/bin/ecmxf-util has an RPATH/RUNPATH"
n=$(/usr/bin/ecmxf-util slaves | wc -l)
[ "$n" -eq 3 ] || fail "installed ecmxf-util slaves: $n lines, expected 3"
/usr/bin/ecmxf-util states OP | grep -c ' OP ' | grep -qx 3 || fail "installed ecmxf-util states OP"
ok "installed ecmxf-util: 3 slaves on sim:, all in OP"
sock=$work/sim.sock
/usr/bin/ecmxf-sim --socket "$sock" >"$work/sim.log" 2>&1 &
simpid=$!
i=0
while [ ! -S "$sock" ] && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
[ -S "$sock" ] || { cat "$work/sim.log"; fail "installed ecmxf-sim --socket: no socket"; }
n=$(/usr/bin/ecmxf-util -d "unix:$sock" slaves | wc -l)
[ "$n" -eq 3 ] || fail "installed ecmxf-util over unix:$sock: $n slaves"
kill "$simpid"
wait "$simpid" 2>/dev/null || true
simpid=
ok "installed ecmxf-util through an installed ecmxf-sim --socket: 3 slaves"
for m in ecmxf-util ecmxf-sim ecmxf-demo; do
	man -w "$m" >/dev/null 2>&1 || fail "man -w $m"
done
ok "man pages: ecmxf-util(1), ecmxf-sim(1), ecmxf-demo(1)"

# the installed Python module (python3-ecmxf), from outside the source tree
mod=$(find /usr/lib/python3/dist-packages/ecmxf -name '_ecmxf*.so' | head -n 1)
[ -n "$mod" ] || fail "python3-ecmxf: no _ecmxf*.so in /usr/lib/python3/dist-packages/ecmxf"
readelf -d "$mod" | grep -q 'R.*PATH' && fail "$mod has an RPATH/RUNPATH"
(cd "$work" && /usr/bin/python3 -c 'import ecmxf, sys
assert ecmxf.__file__.startswith("/usr/lib/python3/dist-packages/"), ecmxf.__file__
with ecmxf.open("sim:") as d:
    assert d.sdo.upload(0, 0x2001, 0) == 50000
    assert len(d.slaves()) == 3
try:
    ecmxf.open("sim:").sdo.upload(0, 0x2FFF, 0)
except ecmxf.SdoAbort as e:
    assert e.code == 0x06020000
else:
    sys.exit("no SdoAbort")') || fail "installed python3-ecmxf: import ecmxf and an SDO upload on sim:"
ok "installed python3-ecmxf: import ecmxf, SDO upload and abort on sim:"

# ---- 5. a consumer of libecmxf-dev
cmake -S "$src/tests/install/consumer" -B "$work/consumer" >"$work/consumer.log" 2>&1 &&
	cmake --build "$work/consumer" >>"$work/consumer.log" 2>&1 ||
	{ cat "$work/consumer.log"; fail "CMake consumer against the installed libecmxf-dev"; }
"$work/consumer/app" | grep -q '^libecmxf .*: 0 slaves' || fail "CMake consumer run"
# shellcheck disable=SC2046
c++ -o "$work/app-pc" "$src/tests/install/consumer/main.cpp" $(pkg-config --cflags --libs ecmxf) ||
	fail "pkg-config consumer"
"$work/app-pc" | grep -q '^libecmxf .*: 0 slaves' || fail "pkg-config consumer run"
ok "consumers built against libecmxf-dev (CMake, pkg-config) run"

# ---- 6. purge
files=$(dpkg -L $pkgs 2>/dev/null | sort -u)
purge || fail "dpkg --purge"
for p in $pkgs; do
	if dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null | grep -q '^[a-z][^n]'; then
		fail "$p still known to dpkg after purge: $(dpkg-query -W -f='${db:Status-Abbrev}' "$p")"
	fi
done
left=""
for f in $files; do
	# directories (/lib is a symlink to one) are shared
	[ -d "$f" ] && continue
	[ -e "$f" ] || [ -L "$f" ] || continue
	left="$left $f"
done
[ -z "$left" ] || fail "left after purge:$left"
[ ! -e "/usr/src/ecmxf-$version" ] || fail "/usr/src/ecmxf-$version left after purge"
[ ! -e /var/lib/dkms/ecmxf ] || fail "/var/lib/dkms/ecmxf left after purge"
[ -z "$(find /lib/modules -name 'ecmxf.ko*' 2>/dev/null)" ] || fail "a built ecmxf.ko left in /lib/modules"
if [ $had_group -eq 0 ] && getent group ecmxf >/dev/null; then
	fail "group ecmxf left after purge"
fi
# the package's postrm takes back the module indexes DKMS's depmod made
# in headers-only kernel folders
for d in $fresh_kdirs; do
	idx=$(find "$d" -maxdepth 1 -name 'modules.*' | tr '\n' ' ')
	[ -z "$idx" ] || fail "$d: module indexes left after purge (headers-only kernel): $idx"
	[ ! -d "$d/updates" ] || fail "$d/updates left after purge"
done
snapshot >"$work/after"
new=$(comm -13 "$work/before" "$work/after")
ours=$(printf '%s\n' "$new" | grep -i 'ecmxf' || true)
[ -z "$ours" ] || fail "left after purge: $ours"
if [ -n "$new" ]; then
	echo "check-deb: note: new on the system meanwhile, none of it ecmxf's (another process?):"
	printf '%s\n' "$new" | head -n 10 | sed 's/^/  /'
fi
ok "purged: no package, file, DKMS tree, module or group of ecmxf left"
