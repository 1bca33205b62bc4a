// SPDX-License-Identifier: MIT
/*
 * ecmxf-util slaves - the slaves the chip found, one line each, as
 * `ethercat slaves` prints them.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/error.hpp>

namespace ecmxf_util {

const char *const kSlavesHelp =
	"Usage: ecmxf-util [global options] slaves [-p N] [-v] [--json]\n"
	"\n"
	"List the slaves found by the last ECAT_INIT_OP, in bus order:\n"
	"  POSITION  ALIAS:RELATIVE-POSITION  STATE  +/E  VENDOR:PRODUCT  NAME\n"
	"E marks a slave whose AL status has the error bit set. When the chip has\n"
	"no network yet (no slaves, ECAT state NONE, e.g. a fresh simulator), it\n"
	"first runs ECAT_INIT_OP (all slaves, FIFO off, no DC, SYNC0 1 ms) to scan\n"
	"the bus; the slaves are then in INIT.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  only the slave at bus position N (or a list: 0,2, a range:\n"
	"                    0-3)\n"
	"  -v, --verbose  add revision, configured station address, AL status code,\n"
	"                 output/input process data bytes and the distributed\n"
	"                 clock (SLV_INFO_GET codes 10..13): DC support, SYNC0\n"
	"                 cycle and shift in ns, SYNC0 active (\"-\" where the\n"
	"                 firmware refuses the codes; DC support then comes from\n"
	"                 the ESC feature register 0x0008 bit 2, read with FPRD);\n"
	"                 a slave whose AL status code is not 0 gets a second line\n"
	"                 with the code's text; say on stderr when the bus is scanned\n"
	"  --json         a JSON array of objects with every field\n"
	"  -h, --help     show this help\n";

namespace {

struct SlaveInfo {
	unsigned position = 0;
	std::uint16_t alias = 0;
	std::uint16_t aliasBase = 0; ///< alias of the last slave with one at or before it
	unsigned relative = 0;       ///< position after that slave (IgH's alias:position)
	std::uint8_t state = 0;
	bool error = false;
	std::uint32_t vendor = 0, product = 0, revision = 0;
	std::string name;
	std::uint16_t station = 0, alCode = 0, outBytes = 0, inBytes = 0;
	std::optional<bool> dc; ///< SLV_INFO_GET 10 or ESC feature bit 2; unset when unknown
	std::optional<ecmxf::SlaveDc> dcInfo; ///< SLV_INFO_GET 10..13; unset when refused
};

/// SLV_INFO_GET codes 10..13; nullopt when the firmware refuses them.
std::optional<ecmxf::SlaveDc> readDcInfo(ecmxf::Device &dev, unsigned pos)
{
	try {
		return dev.bus().slaveDc(static_cast<std::uint8_t>(pos));
	} catch (const ecmxf::Error &) {
		return std::nullopt;
	}
}

/// DC support: ESC feature register 0x0008 bit 2 (ETG.1000.4), by FPRD.
std::optional<bool> readDc(ecmxf::Device &dev, std::uint16_t station)
{
	try {
		ecmxf::Datagram d;
		d.command = ecmxf::DatagramCommand::FPRD;
		d.adp = station;
		d.ado = 0x0008;
		d.data.assign(2, 0);
		const ecmxf::DatagramResult r = dev.slaves().rawDatagram(d);
		if (r.workingCounter != 1 || r.data.empty())
			return std::nullopt;
		return (r.data[0] & 0x04) != 0;
	} catch (const ecmxf::Error &) {
		return std::nullopt;
	}
}

/// ECAT_INIT_OP for all slaves: 0xFF, 0x81 (FIFO off), AssignActivate 0,
/// SYNC0 1 ms, SYNC1 0, shift 0; data length field 16.
ecmxf::Command initOp()
{
	ecmxf::Command c = simpleCommand(kInitOp);
	c.payload = { 0xFF, 0x81, 0x00, 0x00 };
	const std::uint32_t sync0 = 1'000'000;
	for (unsigned i = 0; i < 4; i++)
		c.payload.push_back(static_cast<std::uint8_t>(sync0 >> (8 * i)));
	c.payload.resize(16, 0); // SYNC1 and shift
	c.len = 16;
	return c;
}

ecmxf::Response slvInfo(ecmxf::Device &dev, unsigned pos, std::uint8_t item)
{
	ecmxf::Command c = simpleCommand(kSlvInfoGet, static_cast<std::uint8_t>(pos));
	c.data[0] = item;
	return dev.command(c);
}

SlaveInfo readSlave(ecmxf::Device &dev, unsigned pos)
{
	SlaveInfo s;
	s.position = pos;
	s.vendor = le32(slvInfo(dev, pos, 0), "SLV_INFO_GET vendor");
	s.product = le32(slvInfo(dev, pos, 1), "SLV_INFO_GET product");
	s.revision = le32(slvInfo(dev, pos, 2), "SLV_INFO_GET revision");
	const ecmxf::Response name = slvInfo(dev, pos, 3);
	s.name.assign(name.data.begin(), name.data.end());
	s.station = le16(slvInfo(dev, pos, 4), "SLV_INFO_GET station address");
	s.alias = le16(slvInfo(dev, pos, 5), "SLV_INFO_GET alias");
	const ecmxf::Response st = slvInfo(dev, pos, 6);
	if (st.data.empty())
		throw std::runtime_error("SLV_INFO_GET AL state: empty answer");
	s.state = static_cast<std::uint8_t>(st.data[0] & 0x0F);
	s.alCode = le16(slvInfo(dev, pos, 7), "SLV_INFO_GET AL status code");
	s.outBytes = le16(slvInfo(dev, pos, 8), "SLV_INFO_GET output bytes");
	s.inBytes = le16(slvInfo(dev, pos, 9), "SLV_INFO_GET input bytes");
	// SLV_INFO_GET 6 gives the state without the error bit; STATE_GET
	// for one slave gives its last read AL status with it (bit 4).
	s.error = (dev.command(simpleCommand(kStateGet, static_cast<std::uint8_t>(pos))).ret & 0x10) != 0;
	return s;
}

} // namespace

int cmdSlaves(Globals &g, const Args &args)
{
	bool verbose = false;
	std::optional<std::string> posText;
	const auto rest = parseArgs("slaves", args, g, kSlavesHelp,
				   { { "-v", "--verbose", &verbose, nullptr }, { "-p", "--position", nullptr, &posText } });
	if (!rest)
		return 0;
	if (!rest->empty())
		throw UsageError("slaves: unexpected argument '" + rest->front() + "' (try 'ecmxf-util slaves --help')");
	const std::optional<Positions> only =
		posText ? std::optional(parsePositions("slaves", *posText)) : std::nullopt;

	const DevicePtr dev = openDevice(g);
	unsigned count = dev->command(simpleCommand(kSlvCntGet)).ret;
	if (count == 0 && dev->lastHeader().ecatState == 0) {
		if (verbose)
			std::fprintf(stderr, "ecmxf-util: no network scanned yet, running ECAT_INIT_OP\n");
		dev->command(initOp());
		count = dev->command(simpleCommand(kSlvCntGet)).ret;
	}

	std::vector<SlaveInfo> slaves;
	unsigned relative = 0;
	std::uint16_t lastAlias = 0;
	for (unsigned pos = 0; pos < count; pos++) {
		SlaveInfo s = readSlave(*dev, pos);
		if (s.alias != 0) {
			lastAlias = s.alias;
			relative = 0;
		}
		s.aliasBase = lastAlias;
		s.relative = relative++;
		if (!only || only->has(pos)) {
			s.dcInfo = readDcInfo(*dev, pos);
			s.dc = s.dcInfo ? std::optional<bool>(s.dcInfo->hasDc) : readDc(*dev, s.station);
			slaves.push_back(std::move(s));
		}
	}
	if (only)
		checkPositions(*only, count);

	if (g.json) {
		std::printf("[");
		for (std::size_t i = 0; i < slaves.size(); i++) {
			const SlaveInfo &s = slaves[i];
			std::printf("%s\n  {\"position\": %u, \"alias\": %u, \"relative_position\": %u, "
				    "\"state\": %s, \"al_state\": %u, \"error\": %s, \"vendor_id\": %u, "
				    "\"product_code\": %u, \"revision\": %u, \"name\": %s, "
				    "\"station_address\": %u, \"al_status_code\": %u, "
				    "\"al_status_text\": %s, \"output_bytes\": %u, \"input_bytes\": %u, \"dc\": %s, "
				    "\"dc_cycle_ns\": %s, \"dc_shift_ns\": %s, \"dc_active\": %s}",
				    i ? "," : "", s.position, s.alias, s.relative,
				    jsonString(stateName(s.state)).c_str(), s.state,
				    s.error ? "true" : "false", s.vendor, s.product, s.revision,
				    jsonString(s.name).c_str(), s.station, s.alCode,
				    jsonString(ecmxf::alStatusText(s.alCode)).c_str(), s.outBytes, s.inBytes,
				    s.dc ? (*s.dc ? "true" : "false") : "null",
				    s.dcInfo ? std::to_string(s.dcInfo->cycleNs).c_str() : "null",
				    s.dcInfo ? std::to_string(s.dcInfo->shiftNs).c_str() : "null",
				    s.dcInfo ? (s.dcInfo->active ? "true" : "false") : "null");
		}
		std::printf("%s]\n", slaves.empty() ? "" : "\n");
		return 0;
	}

	if (verbose)
		std::printf("%-3s  %-7s  %-8s  %-21s  %-10s  %-6s  %-7s  %4s  %4s  %-3s  %10s  %10s  %-3s  %s\n",
			    "POS", "ALIAS", "STATE", "VENDOR:PRODUCT", "REVISION", "ADDR", "AL CODE", "OUT", "IN", "DC",
			    "CYCLE NS", "SHIFT NS", "ACT", "NAME");
	for (const SlaveInfo &s : slaves) {
		const std::string alias = std::to_string(s.aliasBase) + ":" + std::to_string(s.relative);
		std::printf("%-3u  %-7s  %-6s %c  0x%08x:0x%08x", s.position, alias.c_str(),
			    stateName(s.state).c_str(), s.error ? 'E' : '+', s.vendor, s.product);
		if (verbose) {
			std::printf("  0x%08x  0x%04x  0x%04x   %4u  %4u  %-3s", s.revision, s.station, s.alCode,
				    s.outBytes, s.inBytes, s.dc ? (*s.dc ? "yes" : "no") : "?");
			if (s.dcInfo)
				std::printf("  %10d  %10d  %-3s", static_cast<int>(s.dcInfo->cycleNs),
					    static_cast<int>(s.dcInfo->shiftNs), s.dcInfo->active ? "yes" : "no");
			else
				std::printf("  %10s  %10s  %-3s", "-", "-", "-");
		}
		std::printf("  %s\n", s.name.c_str());
		if (verbose && s.alCode)
			std::printf("     AL status 0x%04x: %.*s\n", s.alCode,
				    static_cast<int>(ecmxf::alStatusText(s.alCode).size()),
				    ecmxf::alStatusText(s.alCode).data());
	}
	return 0;
}

} // namespace ecmxf_util
