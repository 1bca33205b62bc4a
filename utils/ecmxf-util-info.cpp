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

namespace ecmxf_util {

const char *const kInfoHelp =
	"Usage: ecmxf-util [global options] info [--json]\n"
	"\n"
	"Show the chip's firmware (FW_VERSION_GET: version, series, build id), the\n"
	"SPI data section size (SPI_PACK_SIZE_GET), the check type, the ECAT state,\n"
	"the error-status and ECM-status bits by name, the SPI CRC and WKC error\n"
	"counts and the number of slaves found by the last ECAT_INIT_OP\n"
	"(SLV_CNT_GET). Nothing on the chip is changed.\n"
	"\n"
	"Options:\n"
	"  --json      one JSON object instead of the key: value table\n"
	"  -h, --help  show this help\n";

namespace {

struct BitName {
	unsigned bit;
	const char *name;
};

// response header 0x09 (Documentation/simulator.rst, "Response header")
constexpr BitName kErrBits[] = {
	{ 0, "link" },          { 1, "link at INIT_OP" }, { 3, "async error" },
	{ 4, "SPI error" },     { 5, "FIFO error" },      { 6, "SPI CRC error" },
	{ 7, "command error" },
};

// response header 0x0A; bits 1-0 are the check type
constexpr BitName kEcmBits[] = {
	{ 2, "DC stable" }, { 3, "Ethernet initialised" }, { 4, "PDO configured" },
	{ 5, "NOP" },       { 6, "FIFO enabled" },         { 7, "busy" },
};

template <std::size_t N>
std::vector<std::string> bitNames(std::uint8_t v, const BitName (&table)[N])
{
	std::vector<std::string> out;
	for (const BitName &b : table)
		if (v & (1u << b.bit))
			out.emplace_back(b.name);
	return out;
}

std::string joined(const std::vector<std::string> &names, const char *sep, bool json)
{
	std::string s;
	for (const std::string &n : names) {
		if (!s.empty())
			s += sep;
		s += json ? jsonString(n) : n;
	}
	return s;
}

const char *checkTypeName(unsigned t)
{
	static const char *const kNames[] = { "fixed", "CRC-8", "CRC-CCITT", "CRC-32" };
	return kNames[t & 3];
}

std::string seriesName(std::uint8_t s)
{
	// Only series 0 is documented (the simulator's ECM-XF); others by number.
	return s == 0 ? "ECM-XF" : "unknown";
}

} // namespace

int cmdInfo(Globals &g, const Args &args)
{
	if (parseFlags("info", args, g, kInfoHelp, {}))
		return 0;

	const std::unique_ptr<ecmxf::Device> dev = ecmxf::Device::open(g.device);

	const ecmxf::Response fw = dev->command(simpleCommand(kFwVersionGet));
	const std::uint8_t ext = fw.data.size() > 1 ? fw.data[1] : 0;
	const std::uint8_t series = fw.data.size() > 3 ? fw.data[3] : 0;
	std::string build;
	bool printable = true;
	for (std::size_t i = 4; i < fw.data.size() && i < 20 && fw.data[i] != 0; i++) {
		if (fw.data[i] < 0x20 || fw.data[i] > 0x7E)
			printable = false;
		build += static_cast<char>(fw.data[i]);
	}
	if (!printable) {
		build.clear();
		for (std::size_t i = 4; i < fw.data.size() && i < 20; i++) {
			char b[4];
			std::snprintf(b, sizeof(b), "%02x", fw.data[i]);
			build += b;
		}
	}

	const std::uint16_t dataSize =
		le16(dev->command(simpleCommand(kSpiPackSizeGet)), "SPI_PACK_SIZE_GET");
	const ecmxf::Response cnt = dev->command(simpleCommand(kSlvCntGet));
	const ecmxf::ResponseHeader h = dev->lastHeader();

	const auto errNames = bitNames(h.errStatus, kErrBits);
	const auto ecmNames = bitNames(h.ecmStatus, kEcmBits);

	if (g.json) {
		std::printf("{\n"
			    "  \"device\": %s,\n"
			    "  \"firmware_version\": %u,\n"
			    "  \"extended_version\": %u,\n"
			    "  \"series\": %u,\n"
			    "  \"series_name\": %s,\n"
			    "  \"build_id\": %s,\n"
			    "  \"data_size\": %u,\n"
			    "  \"check_type\": %s,\n"
			    "  \"ecat_state\": %u,\n"
			    "  \"ecat_state_name\": %s,\n"
			    "  \"error_status\": %u,\n"
			    "  \"error_bits\": [%s],\n"
			    "  \"ecm_status\": %u,\n"
			    "  \"ecm_bits\": [%s],\n"
			    "  \"spi_crc_errors\": %u,\n"
			    "  \"wkc_errors\": %u,\n"
			    "  \"slaves\": %u\n"
			    "}\n",
			    jsonString(g.device).c_str(), fw.ret, ext, series,
			    jsonString(seriesName(series)).c_str(), jsonString(build).c_str(), dataSize,
			    jsonString(checkTypeName(h.ecmStatus)).c_str(), h.ecatState,
			    jsonString(stateName(h.ecatState)).c_str(), h.errStatus,
			    joined(errNames, ", ", true).c_str(), h.ecmStatus,
			    joined(ecmNames, ", ", true).c_str(), h.crcErrCnt, h.wkcErrCnt, cnt.ret);
		return 0;
	}

	std::printf("device:            %s\n", g.device.c_str());
	std::printf("firmware version:  %u (0x%02x)\n", fw.ret, fw.ret);
	std::printf("extended version:  %u\n", ext);
	std::printf("series:            %u (%s)\n", series, seriesName(series).c_str());
	std::printf("build id:          %s\n", build.c_str());
	std::printf("data size:         %u\n", dataSize);
	std::printf("check type:        %s\n", checkTypeName(h.ecmStatus));
	std::printf("ECAT state:        %s (0x%02x)\n", stateName(h.ecatState).c_str(), h.ecatState);
	std::printf("error status:      0x%02x (%s)\n", h.errStatus,
		    errNames.empty() ? "none" : joined(errNames, ", ", false).c_str());
	std::printf("ECM status:        0x%02x (%s)\n", h.ecmStatus,
		    ecmNames.empty() ? "none" : joined(ecmNames, ", ", false).c_str());
	std::printf("SPI CRC errors:    %u\n", h.crcErrCnt);
	std::printf("WKC errors:        %u\n", h.wkcErrCnt);
	std::printf("slaves:            %u\n", cnt.ret);
	return 0;
}

} // namespace ecmxf_util
