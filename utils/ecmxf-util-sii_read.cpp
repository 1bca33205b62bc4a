// SPDX-License-Identifier: MIT
/*
 * ecmxf-util sii_read - a slave's SII EEPROM: hex dump, binary or the
 * decoded identity fields.
 */
#include "ecmxf-util.hpp"

#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/error.hpp>

namespace ecmxf_util {

const char *const kSiiReadHelp =
	"Usage: ecmxf-util [global options] sii_read -p N [--offset WORD] [--length WORDS]\n"
	"                                             [--raw | --hex] [-v] [--json]\n"
	"\n"
	"Read the SII EEPROM of the slave at position N (EEPROM_REQ, one word per\n"
	"request). As IgH's ethercat does, standard output that is a pipe or a\n"
	"file gets the binary image (little-endian words, for sii_write and\n"
	"siitool); a terminal gets a hex dump: the word address, then 8 words.\n"
	"Without --length the dump ends with the category list (the end marker\n"
	"0xFFFF after the categories from word 0x40 on), at most the EEPROM's size\n"
	"(word 0x3E).\n"
	"\n"
	"A fresh bus is scanned first (ECAT_INIT_OP); the EEPROM needs no more.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  --offset WORD     first word (default 0)\n"
	"  --length WORDS    number of words\n"
	"  --raw             the binary image, also on a terminal\n"
	"  --hex             the hex dump, also into a pipe or a file\n"
	"  -v, --verbose     the decoded identity fields instead of the dump:\n"
	"                    alias, vendor id, product code, revision, serial,\n"
	"                    mailboxes, mailbox protocols, EEPROM size, version\n"
	"  --json            {position, offset, words: [...]} (with -v also the\n"
	"                    identity fields)\n"
	"  -h, --help        show this help\n";

namespace {

constexpr std::uint16_t kCategoriesStart = 0x40;

/// Words from @p offset to the end of the category list (inclusive of
/// the end marker), at most @p limit words in all.
std::size_t lengthToCategoryEnd(ecmxf::Device &dev, unsigned slave, std::size_t eepromWords)
{
	std::size_t w = kCategoriesStart;
	while (w + 1 < eepromWords) {
		const std::uint16_t type = dev.slaves().eepromRead(slave, static_cast<std::uint16_t>(w));
		if (type == 0xFFFF)
			return w + 1;
		const std::uint16_t size = dev.slaves().eepromRead(slave, static_cast<std::uint16_t>(w + 1));
		w += 2 + size;
	}
	return eepromWords;
}

std::uint32_t word32(const std::vector<std::uint16_t> &w, std::size_t at)
{
	return static_cast<std::uint32_t>(w[at]) | static_cast<std::uint32_t>(w[at + 1]) << 16;
}

std::string protocols(std::uint16_t p)
{
	static const char *const kNames[] = { "AoE", "EoE", "CoE", "FoE", "SoE" };
	std::string s;
	for (unsigned b = 0; b < 5; b++)
		if (p & (1u << b))
			s.append(s.empty() ? "" : ", ").append(kNames[b]);
	if (p & 0x20)
		s.append(s.empty() ? "" : ", ").append("VoE");
	return s.empty() ? "none" : s;
}

} // namespace

int cmdSiiRead(Globals &g, const Args &args)
{
	std::optional<std::string> posText, offText, lenText;
	bool raw = false, hex = false, verbose = false;
	const auto pos = parseArgs("sii_read", args, g, kSiiReadHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "", "--offset", nullptr, &offText },
				     { "", "--length", nullptr, &lenText },
				     { "", "--raw", &raw, nullptr },
				     { "", "--hex", &hex, nullptr },
				     { "-v", "--verbose", &verbose, nullptr } });
	if (!pos)
		return 0;
	if (!pos->empty())
		throw UsageError("sii_read: unexpected argument '" + pos->front() +
				 "' (try 'ecmxf-util sii_read --help')");
	std::uint8_t position = parsePosition("sii_read", posText);
	const auto offset = static_cast<std::uint16_t>(offText ? parseUnsigned("sii_read", "--offset", *offText, 0xFFFF) : 0);
	std::optional<std::size_t> length;
	if (lenText)
		length = static_cast<std::size_t>(parseUnsigned("sii_read", "--length", *lenText, 0x10000u - offset, 1));

	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::Scan));

	std::vector<std::uint16_t> identity;
	if (verbose)
		identity = dev->slaves().eepromReadWords(position, 0, 0x40);
	if (!length && verbose) {
		length = 0; // identity only
	} else if (!length) {
		const std::uint16_t sizeWord = dev->slaves().eepromRead(position, 0x3E);
		const std::size_t words = (static_cast<std::size_t>(sizeWord) + 1) * 1024 / 16;
		const std::size_t end = lengthToCategoryEnd(*dev, position, words);
		length = end > offset ? end - offset : 0;
	}
	std::vector<std::uint16_t> words;
	if (*length)
		words = dev->slaves().eepromReadWords(position, offset, *length);

	if (raw && hex)
		throw UsageError("sii_read: --raw and --hex exclude each other");
	// as IgH's ethercat: the binary image into a pipe or a file, the hex
	// dump on a terminal
	if (!hex && !verbose && !g.json && !isatty(STDOUT_FILENO))
		raw = true;
	if (raw) {
		for (const std::uint16_t w : words) {
			std::putchar(w & 0xFF);
			std::putchar(w >> 8);
		}
		return 0;
	}

	struct Field {
		const char *key, *label;
		std::uint64_t value;
		int digits;
	};
	std::vector<Field> fields;
	std::string protos;
	if (verbose) {
		const auto &w = identity;
		fields = {
			{ "alias", "station alias", w[0x04], 4 },
			{ "vendor_id", "vendor id", word32(w, 0x08), 8 },
			{ "product_code", "product code", word32(w, 0x0A), 8 },
			{ "revision", "revision", word32(w, 0x0C), 8 },
			{ "serial", "serial number", word32(w, 0x0E), 8 },
			{ "bootstrap_rx_mailbox_offset", "bootstrap mailbox out", w[0x14], 4 },
			{ "bootstrap_rx_mailbox_size", "", w[0x15], 0 },
			{ "bootstrap_tx_mailbox_offset", "bootstrap mailbox in", w[0x16], 4 },
			{ "bootstrap_tx_mailbox_size", "", w[0x17], 0 },
			{ "std_rx_mailbox_offset", "standard mailbox out", w[0x18], 4 },
			{ "std_rx_mailbox_size", "", w[0x19], 0 },
			{ "std_tx_mailbox_offset", "standard mailbox in", w[0x1A], 4 },
			{ "std_tx_mailbox_size", "", w[0x1B], 0 },
			{ "mailbox_protocols", "mailbox protocols", w[0x1C], 4 },
			{ "size", "EEPROM size", w[0x3E], 0 },
			{ "version", "version", w[0x3F], 0 },
		};
		protos = protocols(w[0x1C]);
	}

	if (g.json) {
		std::printf("{\"position\": %u, \"offset\": %u, \"words\": [", position, offset);
		for (std::size_t i = 0; i < words.size(); i++)
			std::printf("%s%u", i ? ", " : "", words[i]);
		std::printf("]");
		for (const Field &f : fields)
			std::printf(", \"%s\": %llu", f.key, static_cast<unsigned long long>(f.value));
		std::printf("}\n");
		return 0;
	}
	if (verbose) {
		for (std::size_t i = 0; i < fields.size(); i++) {
			const Field &f = fields[i];
			const std::string_view key = f.key;
			if (!*f.label || key == "size" || key == "version")
				continue;
			std::printf("%-22s %s", (std::string(f.label) + ":").c_str(),
				    hexString(f.value, f.digits).c_str());
			if (i + 1 < fields.size() && !*fields[i + 1].label)
				std::printf(", %llu bytes", static_cast<unsigned long long>(fields[i + 1].value));
			if (key == "mailbox_protocols")
				std::printf(" (%s)", protos.c_str());
			std::printf("\n");
		}
		std::printf("%-22s %u (%u KiB)\n", "EEPROM size:", identity[0x3E],
			    (identity[0x3E] + 1u) / 8u);
		std::printf("%-22s %u\n", "version:", identity[0x3F]);
	}
	for (std::size_t i = 0; i < words.size(); i += 8) {
		std::printf("0x%04zx:", offset + i);
		for (std::size_t k = i; k < i + 8 && k < words.size(); k++)
			std::printf(" %04x", words[k]);
		std::printf("\n");
	}
	return 0;
}

} // namespace ecmxf_util
