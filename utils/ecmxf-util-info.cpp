// SPDX-License-Identifier: MIT
/*
 * ecmxf-util info - what the chip says about itself: firmware, packet
 * format, header status bits and counters, slave count.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/model/status.hpp>

namespace ecmxf_util {

const char *const kInfoHelp =
	"Usage: ecmxf-util [global options] info [--json]\n"
	"\n"
	"Show the chip's firmware (FW_VERSION_GET: version, extended version,\n"
	"series, build id), the SPI data section size (SPI_PACK_SIZE_GET) and\n"
	"packet size, the check type and which bytes the chip's CRC covers (frame:\n"
	"the whole data section, as manual 050; valid: the valid data length, as\n"
	"NEXTW's example code; unknown until a CRC was in force), the ECAT state,\n"
	"the error-status and\n"
	"ECM-status bits by name, the SPI CRC and WKC error counts, the continuous\n"
	"WKC error count and its limit (ECAT_WKC_CONTI_ERR_CNT_GET / _MAX_GET) and\n"
	"the number of slaves found by the last ECAT_INIT_OP (SLV_CNT_GET).\n"
	"Nothing on the chip is changed.\n"
	"\n"
	"Options:\n"
	"  --json      one JSON object instead of the key: value table\n"
	"  -h, --help  show this help\n";

namespace {

std::string joined(const std::vector<ecmxf::StatusBit> &bits, bool json)
{
	std::string s;
	for (const ecmxf::StatusBit &b : bits) {
		if (!s.empty())
			s += ", ";
		s += json ? jsonString(b.name) : std::string(b.name);
	}
	return s;
}

} // namespace

int cmdInfo(Globals &g, const Args &args)
{
	if (parseFlags("info", args, g, kInfoHelp, {}))
		return 0;

	const DevicePtr dev = openDevice(g);
	const ecmxf::ChipInfo ci = dev->chip().info();
	const unsigned slaves = dev->bus().slaveCount();
	const ecmxf::ResponseHeader h = dev->lastHeader();
	const ecmxf::FirmwareVersion &fw = ci.firmware;
	const std::string series = ecmxf::masterSeriesName(fw.seriesCode);
	const std::string_view check = ecmxf::checkTypeName(ci.checkType);
	const std::string_view coverage = ecmxf::crcCoverageName(ci.crcCoverage);
	const auto errBits = ecmxf::errorStatusBits(h.errStatus);
	const auto ecmBits = ecmxf::ecmStatusBits(h.ecmStatus);
	const std::string wkcConti = ci.wkcContinuousErrors ? std::to_string(*ci.wkcContinuousErrors) : "";
	const std::string wkcLimit = ci.wkcErrorLimit == ecmxf::kWkcNoLimit ? "none" : std::to_string(ci.wkcErrorLimit);

	if (g.json) {
		std::printf("{\n"
			    "  \"device\": %s,\n"
			    "  \"firmware_version\": %u,\n"
			    "  \"detailed\": %s,\n"
			    "  \"extended_version\": %u,\n"
			    "  \"series\": %u,\n"
			    "  \"series_name\": %s,\n"
			    "  \"build_id\": %s,\n"
			    "  \"data_size\": %u,\n"
			    "  \"packet_size\": %zu,\n"
			    "  \"check_type\": %s,\n"
			    "  \"crc_coverage\": %s,\n"
			    "  \"ecat_state\": %u,\n"
			    "  \"ecat_state_name\": %s,\n"
			    "  \"error_status\": %u,\n"
			    "  \"error_bits\": [%s],\n"
			    "  \"ecm_status\": %u,\n"
			    "  \"ecm_bits\": [%s],\n"
			    "  \"spi_crc_errors\": %u,\n"
			    "  \"wkc_errors\": %u,\n"
			    "  \"wkc_continuous_errors\": %s,\n"
			    "  \"wkc_error_limit\": %u,\n"
			    "  \"slaves\": %u\n"
			    "}\n",
			    jsonString(g.device).c_str(), fw.version, fw.detailed ? "true" : "false",
			    fw.extendedVersion, fw.seriesCode, jsonString(series).c_str(),
			    jsonString(fw.buildId).c_str(), ci.dataSize, ci.packetSize, jsonString(check).c_str(),
			    jsonString(coverage).c_str(),
			    h.ecatState, jsonString(ecmxf::ecatStateName(h.ecatState)).c_str(), h.errStatus,
			    joined(errBits, true).c_str(), h.ecmStatus, joined(ecmBits, true).c_str(), h.crcErrCnt,
			    h.wkcErrCnt, wkcConti.empty() ? "null" : wkcConti.c_str(), ci.wkcErrorLimit, slaves);
		return 0;
	}

	std::printf("device:            %s\n", g.device.c_str());
	std::printf("firmware version:  %u (0x%02x)\n", fw.version, fw.version);
	if (fw.detailed) {
		std::printf("extended version:  %u\n", fw.extendedVersion);
		std::printf("series:            %u (%s)\n", fw.seriesCode, series.c_str());
		std::printf("build id:          %s\n", fw.buildId.c_str());
	} else {
		std::printf("extended version:  - (firmware of manual ver. 038 reports the version only)\n");
	}
	std::printf("data size:         %u (packet %zu bytes)\n", ci.dataSize, ci.packetSize);
	std::printf("check type:        %.*s\n", static_cast<int>(check.size()), check.data());
	std::printf("CRC coverage:      %.*s\n", static_cast<int>(coverage.size()), coverage.data());
	std::printf("ECAT state:        %s (0x%02x)\n", ecmxf::ecatStateName(h.ecatState).c_str(), h.ecatState);
	std::printf("error status:      0x%02x (%s)\n", h.errStatus,
		    errBits.empty() ? "none" : joined(errBits, false).c_str());
	std::printf("ECM status:        0x%02x (%s)\n", h.ecmStatus,
		    ecmBits.empty() ? "none" : joined(ecmBits, false).c_str());
	std::printf("SPI CRC errors:    %u\n", h.crcErrCnt);
	std::printf("WKC errors:        %u\n", h.wkcErrCnt);
	std::printf("WKC continuous:    %s (limit %s)\n",
		    wkcConti.empty() ? "- (not in this firmware)" : wkcConti.c_str(), wkcLimit.c_str());
	std::printf("slaves:            %u\n", slaves);
	return 0;
}

} // namespace ecmxf_util
