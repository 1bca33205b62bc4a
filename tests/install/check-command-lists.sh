#!/bin/bash
# SPDX-License-Identifier: MIT
# The commands of ecmxf-util, its man page and its bash completion agree:
#  - the man page has one .SS section per command of the CLI contract
#    (docs: ecmxf-util.rst, "commands"), no more, no fewer;
#  - the completion's command list is the same list;
#  - every command `ecmxf-util --help` lists is in that list. With
#    --strict (once every command exists) the CLI's list must be equal too.
#
#   check-command-lists.sh ECMXF-UTIL MAN-PAGE COMPLETION [--strict]
set -u
util=$1 man=$2 comp=$3 strict=${4:-}

# the CLI contract's commands (Documentation/ecmxf-util.rst)
full="adc cia402 commands cstruct dac data decode download eeprom emergency foe_read foe_write gpio info
master monitor pdos qei raw reg_read reg_write reset scope sii_read sii_write slaves states upload version xml"
sorted() { tr ' \n' '\n\n' | sed '/^$/d' | sort -u | paste -sd' '; }
full=$(echo "$full" | sorted)

# man page: the .SS headings between .SH COMMANDS and the next .SH
man_cmds=$(awk '/^\.SH /{in_cmds = ($2 == "COMMANDS")} in_cmds && /^\.SS /{print $2}' "$man" |
	tr -d '"' | sorted)
# completion: _ecmxf_util_commands="..."
comp_cmds=$(bash -c '. "$1"; echo $_ecmxf_util_commands' _ "$comp" | sorted)
# CLI: the lines of --help between "Commands" and the blank line after them
cli_cmds=$("$util" --help | awk '/^Commands/{on=1; next} on && /^$/{exit} on{print $1}' | sorted)

fail=0
if [[ $man_cmds != "$full" ]]; then
	echo "FAIL: man page commands [$man_cmds] != contract [$full]"
	fail=1
fi
if [[ $comp_cmds != "$full" ]]; then
	echo "FAIL: completion commands [$comp_cmds] != contract [$full]"
	fail=1
fi
if [[ -z $cli_cmds ]]; then
	echo "FAIL: no command list in '$util --help'"
	fail=1
fi
for c in $cli_cmds; do
	if [[ " $full " != *" $c "* ]]; then
		echo "FAIL: '$util --help' has '$c', which the man page and the completion lack"
		fail=1
	fi
done
missing=
for c in $full; do
	[[ " $cli_cmds " != *" $c "* ]] && missing="$missing $c"
done
if [[ -n $missing ]]; then
	if [[ $strict == --strict ]]; then
		echo "FAIL: the CLI lacks:$missing"
		fail=1
	else
		echo "note: not in the CLI yet:$missing"
	fi
fi
((fail == 0)) && echo "ok: man page, completion and CLI agree ($(echo $full | wc -w) commands)"
exit $fail
