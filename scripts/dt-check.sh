#!/bin/sh
# SPDX-License-Identifier: MIT
#
# Check the devicetree files of Documentation/devicetree/ as the kernel's
# `make dt_binding_check` / `make dtbs_check` would (Debian packages
# dt-schema and device-tree-compiler; scripts/install-deps.sh --kernel):
#
#   1. dt-doc-validate: nextw,ecm-xf.yaml against the meta-schemas, in a
#      schema tree laid out as the kernel's (net/nextw,ecm-xf.yaml, as its
#      $id says, beside the kernel's spi/*-props.yaml it refers to);
#   2. dt-mk-schema: that tree plus dt-schema's core schemas, processed;
#   3. the binding's examples: dt-extract-example, cpp with the kernel's
#      include/dt-bindings, dtc, dt-validate (every example's node must
#      match the binding); then nodes the binding must refuse (the
#      interrupt names out of order or twice, an ECM-XFU with another data
#      section size, bad packet formats): each must
#      make dt-validate complain;
#   4. the overlay ecmxf-rpi-overlay.dts: dtc -@ (as the file's header
#      says to build it), applied with fdtoverlay to a small stand-in for
#      the Raspberry Pi's base tree (the labels it targets: gpio, spi0,
#      spidev0), and the merged tree's ethercat node validated against
#      the binding (dt-validate cannot follow an unapplied overlay's
#      fragments);
#   5. the overlay ecmxf-rpi-debian-overlay.dts (for the kernel's own
#      device trees): dtc -@, applied with fdtoverlay to the Raspberry Pi
#      4, 400 and CM4 trees of Debian's arm64 6.12 kernel (ECMXF_DT_KERNELS;
#      scripts/debian-kernel.sh fetches the image once), each merged
#      tree's ethercat node validated.  6.1's trees have no __symbols__
#      (built without -@): no overlay applies to them.
#
# dt-validate exits 0 even when a node fails its schema: any line it
# prints is an error here, and so is any dtc warning.
#
# The kernel files (spi-peripheral-props.yaml and the three per-vendor
# schemas it refers to; include/dt-bindings for the examples) come from
# Debian's linux-source-6.1, through the same cache as scripts/checkpatch.sh
# (ECMXF_CACHE, default /var/cache/ecmxf).  Called by `make dt-check` and
# `make kernel-lint`.
set -eu

cd "$(dirname "$0")/.."

binding=Documentation/devicetree/nextw,ecm-xf.yaml
overlay=Documentation/devicetree/ecmxf-rpi-overlay.dts
doverlay=Documentation/devicetree/ecmxf-rpi-debian-overlay.dts
# the arm64 kernels whose Raspberry Pi device trees step 5 uses
# (not 6.1: its device trees are built without -@, have no __symbols__,
# and take no overlay at all)
dt_kernels=${ECMXF_DT_KERNELS:-6.12-arm64}
t0=$(date +%s.%N)

die() {
	echo "dt-check.sh: $*" >&2
	exit 1
}

for c in dt-doc-validate dt-mk-schema dt-extract-example dt-validate dtc fdtoverlay cpp; do
	command -v "$c" >/dev/null ||
		die "$c not found (scripts/install-deps.sh --kernel: dt-schema, device-tree-compiler)"
done

# ---- the kernel's files, from the linux-source .deb (cached)
# shellcheck source=scripts/linux-source.sh
. scripts/linux-source.sh
kfiles=$(linux_source_files dt 1 \
	'*/Documentation/devicetree/bindings/spi/*-peripheral-props.yaml' '*/include/dt-bindings/*')
[ -f "$kfiles/Documentation/devicetree/bindings/spi/spi-peripheral-props.yaml" ] ||
	die "spi-peripheral-props.yaml not found in $kfiles"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
schemas=$work/schemas
mkdir -p "$schemas/spi" "$schemas/net"
cp "$kfiles"/Documentation/devicetree/bindings/spi/*-peripheral-props.yaml "$schemas/spi/"
cp "$binding" "$schemas/net/"

# every line a tool prints is a finding; paths back to the checkout's
check_quiet() {
	what=$1
	shift
	out=$("$@" 2>&1) || { printf '%s\n' "$out" | sed "s|$schemas/net/|Documentation/devicetree/|g" >&2; die "$what failed"; }
	if [ -n "$out" ]; then
		printf '%s\n' "$out" | sed "s|$schemas/net/|Documentation/devicetree/|g" >&2
		die "$what: see above"
	fi
}

# 1. the binding against the meta-schemas
check_quiet "dt-doc-validate $binding" dt-doc-validate -u "$schemas" "$schemas/net/nextw,ecm-xf.yaml"

# 2. processed schema: core + the kernel's SPI props + ours
dt-mk-schema -j "$schemas" >"$work/processed.json" || die "dt-mk-schema failed"

# 3. the examples
dt-extract-example "$binding" >"$work/examples.dts" || die "dt-extract-example failed"
cpp -nostdinc -I "$kfiles/include" -undef -D__DTS__ -x assembler-with-cpp \
	"$work/examples.dts" >"$work/examples.pp.dts" 2>"$work/cpp.log" ||
	{ cat "$work/cpp.log" >&2; die "cpp over the examples failed"; }
# the wrapper dt-extract-example puts around each example has cells the
# example may not need (the kernel's dt_binding_check silences this too)
check_quiet "dtc (examples)" dtc -Wno-avoid_unnecessary_addr_size -I dts -O dtb \
	-o "$work/examples.dtb" "$work/examples.pp.dts"
check_quiet "dt-validate (examples)" dt-validate -s "$work/processed.json" "$work/examples.dtb"
nex=$(dt-validate -M -l nextw -s "$work/processed.json" "$work/examples.dtb" 2>&1 |
	grep -c 'matched on schema' || true)
nex_want=$(grep -c '^  - |' "$binding")
[ "$nex" -ge "$nex_want" ] || die "dt-validate matched $nex example node(s) to the binding, want $nex_want"

# 3b. nodes the binding must refuse: each must make dt-validate complain
# (interrupt-names is fixed items: no other order, no duplicate; the
# ECM-XFU's data section is 992 bytes; the packet format's values)
bad_node() {
	{
		echo '/dts-v1/;'
		echo '/ { compatible = "ecmxf,test"; model = "test"; #address-cells = <1>; #size-cells = <1>; gpio: gpio { gpio-controller; #gpio-cells = <2>; interrupt-controller; #interrupt-cells = <2>; #address-cells = <0>; };'
		echo '  spi { #address-cells = <1>; #size-cells = <0>; ethercat@0 { reg = <0>;'
		for l in "$@"; do echo "    $l"; done
		echo '  }; }; };'
	} >"$work/bad.dts"
	check_quiet "dtc (node: $name)" dtc -I dts -O dtb -o "$work/bad.dtb" "$work/bad.dts"
	dt-validate -s "$work/processed.json" "$work/bad.dtb" 2>&1 || true
}
refuse() {
	name=$1
	shift
	[ -n "$(bad_node "$@")" ] || die "the binding accepts a node with $name"
	nbad=$((nbad + 1))
}
nbad=0
irq='interrupt-parent = <&gpio>; interrupts = <25 1>, <24 8>;'
# the same harness with good nodes first: what refuse() sees is the change
for good in '"nextw,ecm-xf";'"|$irq"'|interrupt-names = "int0", "int1";' \
	'"nextw,ecm-xfu";|nextw,data-size = <992>;|nextw,check-type = "crc8";' \
	'"nextw,ecm-xm";|interrupt-parent = <&gpio>; interrupts = <24 8>;|interrupt-names = "int1";'; do
	IFS='|' read -r c l1 l2 <<EOT
$good
EOT
	name="a good node"
	out=$(bad_node "compatible = $c" "$l1" "$l2")
	[ -z "$out" ] || { printf '%s\n' "$out" >&2; die "the binding refuses a good node ($good)"; }
done
refuse "interrupt-names in the other order" 'compatible = "nextw,ecm-xf";' "$irq" 'interrupt-names = "int1", "int0";'
refuse "interrupt-names twice int0" 'compatible = "nextw,ecm-xf";' "$irq" 'interrupt-names = "int0", "int0";'
refuse "an interrupt name other than int0/int1" 'compatible = "nextw,ecm-xf";' 'interrupt-parent = <&gpio>; interrupts = <25 1>;' 'interrupt-names = "ready";'
refuse "an ECM-XFU with a 256-byte data section" 'compatible = "nextw,ecm-xfu";' 'nextw,data-size = <256>;'
refuse "a data section of 16 bytes" 'compatible = "nextw,ecm-xf";' 'nextw,data-size = <16>;'
refuse "a check type crc64" 'compatible = "nextw,ecm-xf";' 'nextw,check-type = "crc64";'

# 4. the overlay, applied to a stand-in base tree
check_quiet "dtc -@ $overlay" dtc -@ -I dts -O dtb -o "$work/ecmxf.dtbo" "$overlay"
cat >"$work/base.dts" <<'EOF'
/dts-v1/;
/* stand-in for a Raspberry Pi base tree: the labels the overlay targets */
/ {
	compatible = "brcm,bcm2835";
	model = "ecmxf dt-check base";
	#address-cells = <1>;
	#size-cells = <1>;

	gpio: gpio@7e200000 {
		compatible = "brcm,bcm2835-gpio";
		reg = <0x7e200000 0xb4>;
		gpio-controller;
		#gpio-cells = <2>;
		interrupt-controller;
		#interrupt-cells = <2>;
		#address-cells = <0>;
	};

	spi0: spi@7e204000 {
		compatible = "brcm,bcm2835-spi";
		reg = <0x7e204000 0x200>;
		#address-cells = <1>;
		#size-cells = <0>;
		status = "disabled";

		spidev0: spidev@0 {
			compatible = "rohm,dh2228fv";
			reg = <0>;
			spi-max-frequency = <125000000>;
		};
	};
};
EOF
check_quiet "dtc (base)" dtc -@ -I dts -O dtb -o "$work/base.dtb" "$work/base.dts"
check_quiet "fdtoverlay" fdtoverlay -i "$work/base.dtb" -o "$work/merged.dtb" "$work/ecmxf.dtbo"
check_quiet "dt-validate (overlay applied)" dt-validate -l nextw -s "$work/processed.json" "$work/merged.dtb"
dt-validate -M -l nextw -s "$work/processed.json" "$work/merged.dtb" 2>&1 |
	grep -q 'ethercat@0: matched on schema' ||
	die "the overlay's ethercat@0 node was not validated against the binding"

# 5. the overlay for the kernel's own device trees, applied to the real
#    ones: the Raspberry Pi 4, 400 and CM4 trees of Debian's arm64 kernel
#    images (scripts/debian-kernel.sh unpacks them, cached), each merged
#    tree's ethercat node validated against the binding
check_quiet "dtc -@ $doverlay" dtc -@ -I dts -O dtb -o "$work/ecmxf-debian.dtbo" "$doverlay"
ndt=0
for k in $dt_kernels; do
	dtbs=$(scripts/debian-kernel.sh "$k" | sed -n 's/^DTBS=//p') || die "scripts/debian-kernel.sh $k failed"
	[ -d "$dtbs/broadcom" ] || die "$k: no device trees in its image ($dtbs)"
	for b in bcm2711-rpi-4-b bcm2711-rpi-400 bcm2711-rpi-cm4-io; do
		[ -f "$dtbs/broadcom/$b.dtb" ] || die "$k: broadcom/$b.dtb missing"
		m="$work/$k-$b.dtb"
		check_quiet "fdtoverlay ($k $b)" fdtoverlay -i "$dtbs/broadcom/$b.dtb" -o "$m" "$work/ecmxf-debian.dtbo"
		dt-validate -M -l nextw -s "$work/processed.json" "$m" >"$work/v.log" 2>&1 || true
		grep -q 'ethercat@0: matched on schema' "$work/v.log" ||
			{ cat "$work/v.log" >&2; die "$k $b: the overlay's ethercat@0 node did not validate"; }
		if grep -v 'matched on schema' "$work/v.log" | grep -q 'ethercat'; then
			cat "$work/v.log" >&2
			die "$k $b: dt-validate reports on the ethercat node"
		fi
		ndt=$((ndt + 1))
	done
done

secs=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
echo "dt-check.sh: $binding valid (dt-schema $(dt-validate -V 2>&1)), its $nex_want examples validate, $nbad bad nodes are refused, the overlay's node (applied with fdtoverlay) validate against it; ${doverlay##*/} applied to $ndt Raspberry Pi trees of Debian's arm64 kernels ($dt_kernels), its node valid, ${secs} s"
