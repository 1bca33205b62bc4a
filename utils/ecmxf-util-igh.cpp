// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - the commands of IgH's `ethercat` tool that an engineer
 * reaches for: reg_read / reg_write (ESC registers through one raw
 * datagram), sii_write (an SII image file into the EEPROM) and master (the
 * master's phase, link and error counters); and, for every other IgH
 * command the ECM-XF cannot do, the answer what to use instead.
 */
#include "ecmxf-util.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/model/status.hpp>
#include <ecmxf/model/types_chip.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>

namespace ecmxf_util {

const char *const kRegReadHelp =
	"Usage: ecmxf-util [global options] reg_read -p N [-t TYPE] ADDRESS [SIZE] [--json]\n"
	"\n"
	"Read SIZE bytes (1..256) from the ESC register ADDRESS of the slave at\n"
	"position N with one auto-increment datagram (APRD through\n"
	"RAW_ECAT_FUNC_REQ), as IgH's ethercat reg_read does. With -t TYPE the\n"
	"size is the type's and the value is printed as that type; without, the\n"
	"bytes in hex. A slave that does not answer (working counter 0) fails.\n"
	"\n"
	"A fresh bus is scanned first (ECAT_INIT_OP).\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  -t, --type TYPE   the register's data type (as upload -t)\n"
	"  --json            {position, address, size, wkc, value, hex}\n"
	"  -h, --help        show this help\n"
	"\n"
	"Example: ecmxf-util reg_read -p 0 -t uint16 0x0130   (AL status)\n";

const char *const kRegWriteHelp =
	"Usage: ecmxf-util [global options] reg_write -p N [-t TYPE] ADDRESS DATA\n"
	"\n"
	"Write DATA to the ESC register ADDRESS of the slave at position N with\n"
	"one auto-increment datagram (APWR through RAW_ECAT_FUNC_REQ). With\n"
	"-t TYPE, DATA is a value of that type; without, hex bytes (0a0b or\n"
	"0a:0b). A working counter other than 1 fails. Prints nothing on success.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  -t, --type TYPE   the register's data type (as download -t)\n"
	"  -h, --help        show this help\n";

const char *const kSiiWriteHelp =
	"Usage: ecmxf-util [global options] sii_write -p N [--force] FILE\n"
	"\n"
	"Write the SII image FILE (binary, little-endian words, as sii_read\n"
	"writes it into a file) into the EEPROM of the slave at position N, one\n"
	"word per EEPROM_REQ, as IgH's ethercat sii_write does. FILE must be an\n"
	"even number of bytes, at least the 8 words of the configuration area and\n"
	"at most the 64 Ki words of an EEPROM; its configuration area checksum\n"
	"(word 7, CRC-8 of words 0..6) must be right unless --force. \"-\" reads\n"
	"standard input.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  --force           write even with a wrong checksum\n"
	"  -h, --help        show this help\n";

const char *const kMasterHelp =
	"Usage: ecmxf-util [global options] master [--json]\n"
	"\n"
	"The master as IgH's ethercat master shows it, from the chip's response\n"
	"header: the phase (the EtherCAT state of the bus), the slave count, the\n"
	"link, and the error counters (SPI CRC errors, working-counter errors) and\n"
	"FIFO levels. 'ecmxf-util info' has the firmware and more; 'ecmxf-util -d\n"
	"/dev/ecmxfN monitor --counters' the kernel's frame and error counters.\n"
	"\n"
	"Options:\n"
	"  --json      one JSON object\n"
	"  -h, --help  show this help\n";

namespace {

std::size_t regSize(std::string_view cmd, std::optional<DataType> type, const std::vector<std::string> &pos)
{
	if (type && typeSize(*type)) {
		if (pos.size() > 1 && parseUnsigned(cmd, "SIZE", pos[1], 256, 1) != typeSize(*type))
			throw UsageError(std::string(cmd).append(": SIZE ").append(pos[1]).append(
				" does not match type ").append(typeName(*type)));
		return typeSize(*type);
	}
	if (pos.size() < 2)
		throw UsageError(std::string(cmd).append(": how many bytes? give SIZE or -t TYPE"));
	return parseUnsigned(cmd, "SIZE", pos[1], 256, 1);
}

/// CRC-8 of the SII configuration area (ETG.2010: polynomial 0x07,
/// initial value 0xFF, over bytes 0..13).
std::uint8_t siiChecksum(const std::vector<std::uint8_t> &b)
{
	std::uint8_t crc = 0xFF;
	for (std::size_t i = 0; i < 14; i++) {
		crc ^= b[i];
		for (int k = 0; k < 8; k++)
			crc = static_cast<std::uint8_t>(crc & 0x80 ? (crc << 1) ^ 0x07 : crc << 1);
	}
	return crc;
}

/// UsageError unless @p size bytes from @p address stay in the slave's
/// 64 KiB register space.
void checkRegisterRange(const char *cmd, std::uint16_t address, std::size_t size)
{
	if (address + size > 0x10000)
		throw UsageError(std::string(cmd) + ": " + std::to_string(size) + " bytes from " +
				 hexString(address, 4) + " pass register 0xffff");
}

/// reg_read's APRD or reg_write's APWR of @p data at @p address of the
/// slave at @p position (a fresh bus is scanned first; selectSlave() may
/// settle the position, which @p position then holds).
ecmxf::DatagramResult registerDatagram(Globals &g, std::uint8_t &position, ecmxf::DatagramCommand command,
				       std::uint16_t address, std::vector<std::uint8_t> data)
{
	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::Scan));
	ecmxf::Datagram d;
	d.command = command;
	d.adp = ecmxf::autoIncrementAddress(position);
	d.ado = address;
	d.data = std::move(data);
	return dev->slaves().rawDatagram(d);
}

} // namespace

int cmdRegRead(Globals &g, const Args &args)
{
	std::optional<std::string> posText, typeText;
	const auto pos = parseArgs("reg_read", args, g, kRegReadHelp,
				   { { "-p", "--position", nullptr, &posText }, { "-t", "--type", nullptr, &typeText } });
	if (!pos)
		return 0;
	if (pos->empty() || pos->size() > 2)
		throw UsageError(pos->empty() ? "reg_read: which register? (reg_read -p N ADDRESS [SIZE])"
					      : "reg_read: too many arguments (try 'ecmxf-util reg_read --help')");
	std::uint8_t position = parsePosition("reg_read", posText);
	const auto address = static_cast<std::uint16_t>(parseUnsigned("reg_read", "ADDRESS", (*pos)[0], 0xFFFF));
	const std::optional<DataType> type =
		typeText ? std::optional<DataType>(parseType("reg_read", *typeText)) : std::nullopt;
	const std::size_t size = regSize("reg_read", type, *pos);
	checkRegisterRange("reg_read", address, size);

	const ecmxf::DatagramResult r = registerDatagram(g, position, ecmxf::DatagramCommand::APRD, address,
							 std::vector<std::uint8_t>(size, 0));
	if (r.workingCounter == 0)
		throw ecmxf::Error("slave " + std::to_string(position) + " did not answer APRD " +
					   hexString(address, 4) + " (working counter 0)",
				   EIO);
	if (g.json) {
		std::printf("{\"position\": %u, \"address\": %u, \"size\": %zu, \"wkc\": %u, \"value\": %s, "
			    "\"hex\": %s}\n",
			    position, address, size, r.workingCounter, jsonValue(type, r.data).c_str(),
			    jsonString(hexBytes(r.data, "")).c_str());
		return 0;
	}
	std::printf("%s\n", type ? formatValue(type, r.data).c_str() : hexBytes(r.data).c_str());
	return 0;
}

int cmdRegWrite(Globals &g, const Args &args)
{
	std::optional<std::string> posText, typeText;
	const auto pos = parseArgs("reg_write", args, g, kRegWriteHelp,
				   { { "-p", "--position", nullptr, &posText }, { "-t", "--type", nullptr, &typeText } });
	if (!pos)
		return 0;
	if (pos->size() != 2)
		throw UsageError(pos->size() < 2 ? "reg_write: needs ADDRESS DATA (reg_write -p N ADDRESS DATA)"
						 : "reg_write: too many arguments (try 'ecmxf-util reg_write --help')");
	std::uint8_t position = parsePosition("reg_write", posText);
	const auto address = static_cast<std::uint16_t>(parseUnsigned("reg_write", "ADDRESS", (*pos)[0], 0xFFFF));
	const DataType type = typeText ? parseType("reg_write", *typeText) : DataType::OctetString;
	const std::vector<std::uint8_t> data = encodeValue("reg_write", type, (*pos)[1]);
	if (data.empty() || data.size() > 256)
		throw UsageError("reg_write: DATA has " + std::to_string(data.size()) + " bytes: 1..256");
	checkRegisterRange("reg_write", address, data.size());

	const ecmxf::DatagramResult r = registerDatagram(g, position, ecmxf::DatagramCommand::APWR, address, data);
	if (r.workingCounter != 1)
		throw ecmxf::Error("slave " + std::to_string(position) + " APWR " + hexString(address, 4) +
					   ": working counter " + std::to_string(r.workingCounter) + ", expected 1",
				   EIO);
	return 0;
}

int cmdSiiWrite(Globals &g, const Args &args)
{
	std::optional<std::string> posText;
	bool force = false;
	const auto pos = parseArgs("sii_write", args, g, kSiiWriteHelp,
				   { { "-p", "--position", nullptr, &posText }, { "", "--force", &force, nullptr } });
	if (!pos)
		return 0;
	if (pos->size() != 1)
		throw UsageError(pos->empty() ? "sii_write: which file? (sii_write -p N FILE)"
					      : "sii_write: one FILE only (try 'ecmxf-util sii_write --help')");
	std::uint8_t position = parsePosition("sii_write", posText);
	const std::string &file = pos->front();
	constexpr std::size_t kMaxBytes = 0x10000 * 2;
	std::vector<std::uint8_t> b;
	{
		std::error_code ec;
		if (file != "-" && std::filesystem::is_directory(file, ec))
			throw ecmxf::Error("\"" + file + "\" is a directory, not a file", EISDIR);
		std::FILE *f = file == "-" ? stdin : std::fopen(file.c_str(), "rb");
		if (!f)
			throw ecmxf::Error("cannot open \"" + file + "\": " + std::strerror(errno), errno);
		char buf[4096];
		std::size_t n;
		while ((n = std::fread(buf, 1, sizeof(buf), f)) > 0) {
			if (b.size() + n > kMaxBytes) {
				if (f != stdin)
					std::fclose(f);
				throw ecmxf::Error("\"" + file + "\" is larger than an SII EEPROM (65536 words)", EFBIG);
			}
			b.insert(b.end(), buf, buf + n);
		}
		const bool bad = std::ferror(f);
		if (f != stdin)
			std::fclose(f);
		if (bad)
			throw ecmxf::Error("cannot read \"" + file + "\"", EIO);
	}
	if (b.size() % 2)
		throw ecmxf::Error("\"" + file + "\" has " + std::to_string(b.size()) +
					   " bytes: an SII image is whole 16-bit words",
				   EINVAL);
	if (b.size() < 16)
		throw ecmxf::Error("\"" + file + "\" has " + std::to_string(b.size() / 2) +
					   " words: an SII image has at least the 8 words of the configuration area",
				   EINVAL);
	const std::uint8_t crc = siiChecksum(b);
	if (b[14] != crc && !force)
		throw ecmxf::Error("\"" + file + "\": configuration area checksum (word 7) is " + hexString(b[14], 2) +
					   ", CRC-8 of words 0..6 is " + hexString(crc, 2) +
					   ": not an SII image? (--force writes it anyway)",
				   EINVAL);

	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::Scan));
	Progress progress(g, "sii_write", "words");
	for (std::size_t w = 0; w < b.size() / 2; w++) {
		dev->slaves().eepromWrite(position, static_cast<std::uint16_t>(w),
					  static_cast<std::uint16_t>(b[2 * w] | b[2 * w + 1] << 8));
		progress(w + 1, b.size() / 2);
	}
	if (!g.quiet)
		std::fprintf(stderr, "ecmxf-util: sii_write: %zu words written to slave %u\n", b.size() / 2,
			     position);
	return 0;
}

int cmdMaster(Globals &g, const Args &args)
{
	if (parseFlags("master", args, g, kMasterHelp, {}))
		return 0;
	const DevicePtr dev = openDevice(g);
	const unsigned slaves = dev->bus().slaveCount();
	const ecmxf::ResponseHeader h = dev->lastHeader();
	const bool link = (h.errStatus & 0x01) != 0;
	const std::string phase = h.ecatState == 0 ? "Idle (no network initialised)" : stateName(h.ecatState);
	if (g.json) {
		std::printf("{\"device\": %s, \"phase\": %s, \"ecat_state\": %u, \"slaves\": %u, \"link\": %s, "
			    "\"spi_crc_errors\": %u, \"wkc_errors\": %u, \"tx_fifo\": %u, \"rx_fifo\": %u, "
			    "\"error_status\": %u, \"ecm_status\": %u}\n",
			    jsonString(g.device).c_str(), jsonString(phase).c_str(), h.ecatState, slaves,
			    link ? "true" : "false", h.crcErrCnt, h.wkcErrCnt, h.txFifoCnt, h.rxFifoCnt, h.errStatus,
			    h.ecmStatus);
		return 0;
	}
	std::printf("Master0\n"
		    "  Device: %s\n"
		    "  Phase: %s\n"
		    "  Slaves: %u\n"
		    "  Link: %s\n"
		    "  Error status: %s\n"
		    "  Counters:\n"
		    "    SPI CRC errors: %u\n"
		    "    WKC errors: %u\n"
		    "  FIFO: TxPDO %u, RxPDO %u\n",
		    g.device.c_str(), phase.c_str(), slaves, link ? "UP" : "DOWN",
		    // bits 0 and 1 are the link (the Link line), not errors
		    ecmxf::describeErrorStatus(static_cast<std::uint8_t>(h.errStatus & ~0x03u)).c_str(), h.crcErrCnt,
		    h.wkcErrCnt, h.txFifoCnt,
		    h.rxFifoCnt);
	return 0;
}

std::optional<std::string> ighAlternative(std::string_view name)
{
	struct Entry {
		std::string_view name;
		std::string_view what;
	};
	static constexpr Entry kIgh[] = {
		{ "alias", "the ECM-XF addresses slaves by bus position (-p N); a slave's station alias is SII word 4: "
			   "'ecmxf-util eeprom -p N write 4 ALIAS --force' writes it, 'sii_read -p N -v' shows it" },
		{ "config", "the ECM-XF configures the slaves itself at bring-up: 'ecmxf-util pdos' shows the PDO "
			    "mapping, 'ecmxf-util slaves -v' the slaves" },
		{ "crc", "'ecmxf-util master' and 'ecmxf-util info' show the chip's CRC and working-counter error "
			 "counters; 'ecmxf-util monitor' reports them as they rise" },
		{ "debug", "'ecmxf-util --trace FILE COMMAND' records every exchange with the chip, 'ecmxf-util "
			   "decode FILE' shows it" },
		{ "domains", "the ECM-XF has one process image and no domains: 'ecmxf-util pdos', and ecmxf::Cyclic "
			     "in the library (Documentation/process-data.rst)" },
		{ "eoe", "the ECM-XF has no Ethernet over EtherCAT (EoE)" },
		{ "graph", "the ECM-XF does not report the bus topology: 'ecmxf-util slaves' lists the slaves in bus "
			   "order" },
		{ "ip", "the ECM-XF has no Ethernet over EtherCAT (EoE), so no IP parameters" },
		{ "rescan", "'ecmxf-util reset' (ASYNCCMD_RESET), then any bus command scans the bus again "
			    "(ECAT_INIT_OP)" },
		{ "sdos", "the ECM-XF has no SDO information service to list a slave's object dictionary: take "
			  "the objects from the slave's ESI file and read them with 'ecmxf-util upload -p N INDEX:SUB "
			  "-t TYPE'" },
		{ "soe_read", "the ECM-XF has no Servo Drive over EtherCAT (SoE); CoE: 'ecmxf-util upload'" },
		{ "soe_write", "the ECM-XF has no Servo Drive over EtherCAT (SoE); CoE: 'ecmxf-util download'" },
	};
	for (const Entry &e : kIgh)
		if (e.name == name)
			return std::string("'").append(name).append("' is an IgH ethercat command that ecmxf-util does "
								    "not have: ").append(e.what);
	return std::nullopt;
}

} // namespace ecmxf_util
