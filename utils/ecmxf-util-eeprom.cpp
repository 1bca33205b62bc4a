// SPDX-License-Identifier: MIT
/*
 * ecmxf-util eeprom - read or write words of a slave's SII EEPROM.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/slave_access.hpp>

namespace ecmxf_util {

const char *const kEepromHelp =
	"Usage: ecmxf-util [global options] eeprom -p N read WORDADDR [WORDS] [--json]\n"
	"       ecmxf-util [global options] eeprom -p N write WORDADDR VALUE... --force\n"
	"\n"
	"Read WORDS words (default 1) of the SII EEPROM of the slave at position N\n"
	"from word WORDADDR on, or write the VALUEs (16-bit words, decimal or 0x\n"
	"hex) to consecutive words from WORDADDR on (EEPROM_REQ / EEPROM_GET, one\n"
	"request per word). Writing changes the slave's non-volatile identity and\n"
	"configuration (a wrong word 0x00..0x07 checksum makes the slave ignore\n"
	"its alias): it needs --force. A write prints nothing.\n"
	"\n"
	"A fresh bus is scanned first (ECAT_INIT_OP); the EEPROM needs no more.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  --force           allow the write\n"
	"  --json            read: {position, address, words: [...]}\n"
	"  -h, --help        show this help\n";

int cmdEeprom(Globals &g, const Args &args)
{
	std::optional<std::string> posText;
	bool force = false;
	const auto pos = parseArgs("eeprom", args, g, kEepromHelp,
				   { { "-p", "--position", nullptr, &posText }, { "", "--force", &force, nullptr } });
	if (!pos)
		return 0;
	if (pos->empty())
		throw UsageError("eeprom: read or write? (eeprom -p N read WORDADDR [WORDS] | write WORDADDR VALUE...)");
	const std::string &op = (*pos)[0];
	if (op != "read" && op != "write")
		throw UsageError("eeprom: unknown operation '" + op + "' (read or write)");
	if (pos->size() < 2)
		throw UsageError("eeprom: " + op + " needs WORDADDR (try 'ecmxf-util eeprom --help')");
	std::uint8_t position = parsePosition("eeprom", posText);
	const auto addr = static_cast<std::uint16_t>(parseUnsigned("eeprom", "WORDADDR", (*pos)[1], 0xFFFF));

	if (op == "read") {
		if (pos->size() > 3)
			throw UsageError("eeprom: read takes WORDADDR [WORDS] (try 'ecmxf-util eeprom --help')");
		const std::size_t n = pos->size() == 3
					      ? static_cast<std::size_t>(parseUnsigned("eeprom", "WORDS", (*pos)[2],
										       0x10000u - addr, 1))
					      : 1;
		const DevicePtr dev = openDevice(g);
		position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::Scan));
		const std::vector<std::uint16_t> words = dev->slaves().eepromReadWords(position, addr, n);
		if (g.json) {
			std::printf("{\"position\": %u, \"address\": %u, \"words\": [", position, addr);
			for (std::size_t i = 0; i < words.size(); i++)
				std::printf("%s%u", i ? ", " : "", words[i]);
			std::printf("]}\n");
			return 0;
		}
		for (std::size_t i = 0; i < words.size(); i += 8) {
			std::printf("0x%04zx:", addr + i);
			for (std::size_t k = i; k < i + 8 && k < words.size(); k++)
				std::printf(" %04x", words[k]);
			std::printf("\n");
		}
		return 0;
	}

	if (pos->size() < 3)
		throw UsageError("eeprom: write needs WORDADDR VALUE... (try 'ecmxf-util eeprom --help')");
	std::vector<std::uint16_t> values;
	for (std::size_t i = 2; i < pos->size(); i++)
		values.push_back(static_cast<std::uint16_t>(parseUnsigned("eeprom", "VALUE", (*pos)[i], 0xFFFF)));
	if (addr + values.size() > 0x10000u)
		throw UsageError("eeprom: write: " + std::to_string(values.size()) + " words from " +
				 hexString(addr, 4) + " pass word 0xffff");
	if (!force)
		throw UsageError("eeprom: write changes the slave's SII EEPROM (its identity and "
				 "configuration): add --force to do it");
	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::Scan));
	for (std::size_t i = 0; i < values.size(); i++)
		dev->slaves().eepromWrite(position, static_cast<std::uint16_t>(addr + i), values[i]);
	return 0;
}

} // namespace ecmxf_util
