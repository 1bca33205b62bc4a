// SPDX-License-Identifier: MIT
/*
 * ecmxf-util emergency - the newest CoE emergencies the master read
 * (COE_EMERGENCY).
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/slave_access.hpp>

namespace ecmxf_util {

const char *const kEmergencyHelp =
	"Usage: ecmxf-util [global options] emergency [-p N] [--json]\n"
	"\n"
	"The CoE emergency messages the master read from the slaves, newest first\n"
	"(COE_EMERGENCY keeps the newest 8): slave, sequence number, error code\n"
	"and its text (CiA 301 error code classes), error register and the 5\n"
	"manufacturer bytes. With -p only those of slave N. Without any, prints\n"
	"\"no emergencies\" (nothing with -q).\n"
	"\n"
	"Options:\n"
	"  -p, --position N  only the emergencies of slave N\n"
	"  --json            an array of {slave, sequence, error_code,\n"
	"                    error_register, data, text}\n"
	"  -h, --help        show this help\n";

std::string emergencyCodeText(std::uint16_t code)
{
	// CiA 301, table "Emergency error codes"
	switch (code) {
	case 0x0000: return "error reset or no error";
	case 0x1000: return "generic error";
	case 0x8110: return "CAN overrun (objects lost)";
	case 0x8120: return "CAN in error passive mode";
	case 0x8130: return "life guard error or heartbeat error";
	case 0x8140: return "recovered from bus off";
	case 0x8150: return "CAN-ID collision";
	case 0x8210: return "PDO not processed due to length error";
	case 0x8220: return "PDO length exceeded";
	case 0x8230: return "DAM MPDO not processed, destination object not available";
	case 0x8240: return "unexpected SYNC data length";
	case 0x8250: return "RPDO timeout";
	default: break;
	}
	switch (code >> 8) {
	case 0x20: case 0x21: case 0x22: case 0x23: return "current";
	case 0x30: case 0x31: case 0x32: case 0x33: return "voltage";
	case 0x40: case 0x41: case 0x42: return "temperature";
	case 0x50: return "device hardware";
	case 0x60: case 0x61: case 0x62: case 0x63: return "device software";
	case 0x70: return "additional modules";
	case 0x80: case 0x81: return "monitoring / communication";
	case 0x82: return "monitoring / protocol error";
	case 0x90: return "external error";
	case 0xF0: return "additional functions";
	case 0xFF: return "device specific";
	default: return "unknown error code";
	}
}

int cmdEmergency(Globals &g, const Args &args)
{
	std::optional<std::string> posText;
	const auto pos =
		parseArgs("emergency", args, g, kEmergencyHelp, { { "-p", "--position", nullptr, &posText } });
	if (!pos)
		return 0;
	if (!pos->empty())
		throw UsageError("emergency: unexpected argument '" + pos->front() +
				 "' (try 'ecmxf-util emergency --help')");
	// -1: all slaves
	const int position = posText ? parsePosition("emergency", posText) : -1;
	const bool one = position >= 0;

	const DevicePtr dev = openDevice(g);
	if (one)
		checkPosition(static_cast<unsigned>(position), ensureBus(*dev, BusNeed::Scan));
	std::vector<ecmxf::CoeEmergency> list;
	for (const ecmxf::CoeEmergency &e : dev->slaves().coeEmergencies(8))
		if (!one || e.slave == position)
			list.push_back(e);

	if (g.json) {
		std::printf("[");
		for (std::size_t i = 0; i < list.size(); i++) {
			const ecmxf::CoeEmergency &e = list[i];
			const std::vector<std::uint8_t> data(e.data.begin(), e.data.end());
			std::printf("%s\n  {\"slave\": %u, \"sequence\": %u, \"error_code\": %u, "
				    "\"error_register\": %u, \"data\": %s, \"text\": %s}",
				    i ? "," : "", e.slave, e.sequence, e.errorCode, e.errorRegister,
				    jsonString(hexBytes(data, "")).c_str(),
				    jsonString(emergencyCodeText(e.errorCode)).c_str());
		}
		std::printf("%s]\n", list.empty() ? "" : "\n");
		return 0;
	}
	if (list.empty()) {
		if (!g.quiet)
			std::printf("no emergencies\n");
		return 0;
	}
	std::printf("%-5s  %-5s  %-6s  %-3s  %-14s  %s\n", "SLAVE", "SEQ", "CODE", "REG", "DATA", "TEXT");
	for (const ecmxf::CoeEmergency &e : list) {
		const std::vector<std::uint8_t> data(e.data.begin(), e.data.end());
		std::printf("%-5u  %-5u  0x%04x  %02x   %-14s  %s\n", e.slave, e.sequence, e.errorCode,
			    e.errorRegister, hexBytes(data).c_str(), emergencyCodeText(e.errorCode).c_str());
	}
	return 0;
}

} // namespace ecmxf_util
