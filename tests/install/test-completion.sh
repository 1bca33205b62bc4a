#!/bin/bash
# SPDX-License-Identifier: MIT
# The bash completion of ecmxf-util: sources it and checks the exact
# completions for command lines, split into COMP_WORDS the way bash does
# (blanks, and ':' as its own word since COMP_WORDBREAKS contains it).
#
#   test-completion.sh COMPLETION-FILE
set -u
. "$1"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/dev" "$tmp/files"
touch "$tmp/dev/ecmxf0" "$tmp/dev/ecmxf1" "$tmp/dev/spidev0.0" "$tmp/files/a.trace" \
	"$tmp/files/a.bin" "$tmp/files/b.net"
export ECMXF_UTIL_DEVDIR=$tmp/dev
COMP_WORDBREAKS=$' \t\n"\'><=;|&(:'
fail=0

# comp LINE EXPECTED... : completions for LINE with the cursor at its end
comp()
{
	local line=$1 tok part
	shift
	local -a toks words=()
	read -ra toks <<<"$line"
	for tok in "${toks[@]}"; do
		while [[ $tok == *:* ]]; do
			part=${tok%%:*}
			[[ -n $part ]] && words+=("$part")
			words+=(":")
			tok=${tok#*:}
		done
		[[ -n $tok ]] && words+=("$tok")
	done
	[[ $line == *" " ]] && words+=("")
	COMP_LINE=$line
	COMP_POINT=${#line}
	COMP_WORDS=("${words[@]}")
	COMP_CWORD=$((${#words[@]} - 1))
	COMPREPLY=()
	_ecmxf_util
	local got want
	got=$( ((${#COMPREPLY[@]})) && printf '%s\n' "${COMPREPLY[@]}" | sort | paste -sd' ')
	want=$( (($#)) && printf '%s\n' "$@" | sort | paste -sd' ')
	if [[ $got != "$want" ]]; then
		echo "FAIL: '$line': got [$got], expected [$want]"
		fail=1
	else
		echo "ok: '$line' -> [$got]"
	fi
}

all="adc cia402 commands cstruct dac data decode download eeprom emergency foe_read foe_write gpio info
master monitor pdos qei raw reg_read reg_write reset scope sii_read sii_write slaves states upload version xml"
# shellcheck disable=SC2086
comp "ecmxf-util " $all help
comp "ecmxf-util s" scope sii_read sii_write slaves states
comp "ecmxf-util foe" foe_read foe_write
comp "ecmxf-util -" -d --device --json --trace -q --quiet --progress -h --help -V --version
comp "ecmxf-util --j" --json
comp "ecmxf-util --json -d sim: st" states
comp "ecmxf-util help mon" monitor
# devices
comp "ecmxf-util -d " sim: unix: "$tmp/dev/ecmxf0" "$tmp/dev/ecmxf1" "spidev:$tmp/dev/spidev0.0"
comp "ecmxf-util -d s" sim: "spidev:$tmp/dev/spidev0.0"
comp "ecmxf-util --device $tmp/dev/e" "$tmp/dev/ecmxf0" "$tmp/dev/ecmxf1"
comp "ecmxf-util -d sim:$tmp/files/b" "$tmp/files/b.net"
comp "ecmxf-util -d u" unix:
comp "ecmxf-util -d unix:$tmp/files/b" "$tmp/files/b.net"
comp "ecmxf-util -d spidev:$tmp/dev/sp" "$tmp/dev/spidev0.0"
# per command
comp "ecmxf-util states " INIT PREOP SAFEOP OP BOOT
comp "ecmxf-util states -p 1 S" SAFEOP
comp "ecmxf-util states OP " 
comp "ecmxf-util upload -p 0 0x6064 -t " bool int8 int16 int32 int64 uint8 uint16 uint32 uint64 \
	float double string octet_string sint8 sint16 sint32 sint64 real32 real64
comp "ecmxf-util upload -p 0 0x6064:00 -t uint" uint8 uint16 uint32 uint64
comp "ecmxf-util up -" -h --help -p --position -t --type -v --json
comp "ecmxf-util slaves -" -h --help -p --position -v --verbose --json
comp "ecmxf-util cia402 -p 0 " status enable disable fault-reset quick-stop move home
comp "ecmxf-util cia402 -p 0 move --" --help --position --pp --pv --csp --velocity --accel \
	--relative --time --plot --csv
comp "ecmxf-util cia402 -p 0 move --csp 100 --plot $tmp/files/a." "$tmp/files/a.bin" "$tmp/files/a.trace"
comp "ecmxf-util scope --" --help --cycles --time --trigger --pre --timeout --buffer --csv --svg --title --json --live --no-live
comp "ecmxf-util scope 0:wkc --svg $tmp/files/b" "$tmp/files/b.net"
comp "ecmxf-util scope wkc --cycles "
comp "ecmxf-util cia402 -p 0 home --" --help --position --method
comp "ecmxf-util gpio " get set config
comp "ecmxf-util gpio config 3 " in out
comp "ecmxf-util eeprom -p 0 " read write
comp "ecmxf-util raw --datagram F" FPRD FPWR FPRW FRMW
comp "ecmxf-util raw --" --help --param --data --payload --len --datagram --json
comp "ecmxf-util monitor --" --help --count --duration --interval --tx-high --rx-low --counters --json
comp "ecmxf-util reset --" --help --async --warm --force
comp "ecmxf-util --trace $tmp/files/a" "$tmp/files/a.bin" "$tmp/files/a.trace"
comp "ecmxf-util decode $tmp/files/a." "$tmp/files/a.bin" "$tmp/files/a.trace"
comp "ecmxf-util foe_write -p 0 $tmp/files/b" "$tmp/files/b.net"
comp "ecmxf-util foe_read -p 0 -o $tmp/files/a.t" "$tmp/files/a.trace"
comp "ecmxf-util frobnicate " 
exit $fail
