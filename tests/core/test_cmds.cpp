// SPDX-License-Identifier: MIT
// The command table against the manuals' command list (ECM-XF EtherCAT
// Master Chip User Manual ver. 038, Chinese ver. 050), as
// Documentation/commands-chip.rst and commands-bus.rst give it.

#include <catch2/catch.hpp>

#include <cstring>
#include <map>
#include <set>
#include <string>

#include <ecmxf/protocol.hpp>

#include "ecmxf-proto.h"

namespace {

// Copied by hand from the digest's list of command codes.
const std::map<unsigned, std::string> kDigest = {
	{ 0, "INFO_UPDATE_OP" }, { 1, "ECAT_INIT_OP" }, { 2, "ECAT_RECONFIG_OP" },
	{ 3, "ECAT_INIT_DC_OP" }, { 4, "ECAT_PDO_WC_GET" }, { 5, "ECAT_PDO_DATA_FIFO_OP" },
	{ 6, "ECAT_PDO_DATA_OP" }, { 7, "ECAT_PDO_CONFIG_SET" }, { 8, "ECAT_PDO_CONFIG_REQ" },
	{ 9, "ECAT_PDO_CONFIG_GET" }, { 10, "ECAT_SDO_REQ" }, { 11, "ECAT_SDO_GET" },
	{ 12, "ECAT_STATE_SET" }, { 13, "ECAT_STATE_GET" }, { 15, "ECAT_SLV_INFO_GET" },
	{ 16, "ECAT_SLV_CNT_GET" }, { 18, "FIFO_ENABLE" }, { 19, "FIFO_PACK_SIZE_GET" },
	{ 20, "SPI_PACK_SIZE_GET" }, { 23, "SPI_RECONFIG_OP" }, { 24, "CRC_ERR_CNT_CLR" },
	{ 25, "CRC_TYPE_SET" }, { 26, "402_CONFIG_SET" }, { 27, "402_STATE_SET" },
	{ 28, "402_STATE_GET" }, { 29, "402_CTL_SET" }, { 30, "402_CTL_GET" },
	{ 31, "GPIO_CONFIG_SET" }, { 32, "GPIO_FUNC_OP" }, { 33, "QEI_FUNC_OP" },
	{ 34, "DAC_FUNC_OP" }, { 35, "ADC_FUNC_OP" }, { 38, "EEPROM_REQ" }, { 39, "EEPROM_GET" },
	{ 41, "ECAT_STATE_CHECK" }, { 50, "ECAT_DCSYNC" }, { 51, "FIFO_CLR_OP" },
	{ 52, "FIFO_SET_TX_CNT" }, { 53, "FIFO_GET_TX_CNT" }, { 54, "FIFO_SET_RX_CNT" },
	{ 55, "FIFO_GET_RX_CNT" }, { 56, "FW_VERSION_GET" }, { 57, "ECAT_STATE_UPDATE" },
	{ 58, "ECAT_INT_SET_ENABLE" }, { 59, "ECAT_INT_GET_ENABLE" }, { 66, "FIFO_INIT" },
	{ 69, "ECAT_SDO_ABORTCODE_GET" }, { 70, "ECAT_SET_FIFO_TH" }, { 71, "ECAT_CONFIG_SM" },
	{ 72, "ECAT_CONFIG_FMMU" }, { 73, "ECAT_CONFIG_MAP" }, { 74, "402_GET_STATUSWORD" },
	{ 75, "ASYNCCMD_RESET" }, { 81, "MDIO" }, { 82, "DIRECT_ASSIGN" }, { 83, "COE_EMERGENCY" },
	{ 127, "WARM_RESET" }, { 130, "ECAT_WKC_CONTI_ERR_CNT_GET" },
	{ 131, "ECAT_WKC_CONTI_ERR_MAX_GET" }, { 132, "ECAT_WKC_CONTI_ERR_MAX_SET" },
	{ 137, "RAW_ECAT_FUNC_REQ" }, { 138, "RAW_ECAT_FUNC_GET" }, { 139, "FOE_FUNC_REQ" },
	{ 140, "FOE_FUNC_GET" }, { 142, "ENABLE_LRW" }, { 143, "RECV_MAILBOX" }, { 144, "MBX_STAT" },
};

// The digest's async list (RECV_MAILBOX only with parameter 0).
const std::set<unsigned> kAsync = { 1, 2, 3, 7, 8, 10, 12, 38, 41, 50, 57, 73, 137, 139, 143, 127 };

// *_REQ -> *_GET partners named by the digest.
const std::map<unsigned, unsigned> kFetch = { { 10, 11 }, { 8, 9 }, { 38, 39 }, { 137, 138 },
					      { 139, 140 } };

} // namespace

TEST_CASE("command table: exactly the digest's codes, with the digest's names", "[cmds]")
{
	std::size_t n = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&n);
	REQUIRE(n == kDigest.size());
	for (std::size_t i = 0; i < n; i++) {
		INFO("code " << static_cast<unsigned>(t[i].code));
		if (i)
			CHECK(t[i].code > t[i - 1].code); // sorted, unique
		auto it = kDigest.find(t[i].code);
		REQUIRE(it != kDigest.end());
		CHECK(it->second == t[i].name);
		CHECK(ecmxf_cmd_lookup(t[i].code) == &t[i]);
		CHECK((t[i].flags & (ECMXF_CMDF_V038 | ECMXF_CMDF_V050)) != 0);
		CHECK(t[i].timeout_ms > 0);
	}
	for (unsigned code = 0; code < 256; code++)
		CHECK((ecmxf_cmd_lookup(code) != nullptr) == (kDigest.count(code) == 1));
}

// Every ECMXF_CMD_* macro of <linux/ecmxf.h> with its name as a string:
// the table's codes and names must be these (the uAPI is the one list of
// codes; tests/uapi checks the uAPI's numbers against the manuals).
#define UAPI_CMD(n) { ECMXF_CMD_##n, #n }
const std::map<unsigned, std::string> kUapi = {
	UAPI_CMD(INFO_UPDATE_OP), UAPI_CMD(ECAT_INIT_OP), UAPI_CMD(ECAT_RECONFIG_OP),
	UAPI_CMD(ECAT_INIT_DC_OP), UAPI_CMD(ECAT_PDO_WC_GET), UAPI_CMD(ECAT_PDO_DATA_FIFO_OP),
	UAPI_CMD(ECAT_PDO_DATA_OP), UAPI_CMD(ECAT_PDO_CONFIG_SET), UAPI_CMD(ECAT_PDO_CONFIG_REQ),
	UAPI_CMD(ECAT_PDO_CONFIG_GET), UAPI_CMD(ECAT_SDO_REQ), UAPI_CMD(ECAT_SDO_GET),
	UAPI_CMD(ECAT_STATE_SET), UAPI_CMD(ECAT_STATE_GET), UAPI_CMD(ECAT_SLV_INFO_GET),
	UAPI_CMD(ECAT_SLV_CNT_GET), UAPI_CMD(FIFO_ENABLE), UAPI_CMD(FIFO_PACK_SIZE_GET),
	UAPI_CMD(SPI_PACK_SIZE_GET), UAPI_CMD(SPI_RECONFIG_OP), UAPI_CMD(CRC_ERR_CNT_CLR),
	UAPI_CMD(CRC_TYPE_SET), UAPI_CMD(402_CONFIG_SET), UAPI_CMD(402_STATE_SET),
	UAPI_CMD(402_STATE_GET), UAPI_CMD(402_CTL_SET), UAPI_CMD(402_CTL_GET),
	UAPI_CMD(GPIO_CONFIG_SET), UAPI_CMD(GPIO_FUNC_OP), UAPI_CMD(QEI_FUNC_OP),
	UAPI_CMD(DAC_FUNC_OP), UAPI_CMD(ADC_FUNC_OP), UAPI_CMD(EEPROM_REQ), UAPI_CMD(EEPROM_GET),
	UAPI_CMD(ECAT_STATE_CHECK), UAPI_CMD(ECAT_DCSYNC), UAPI_CMD(FIFO_CLR_OP),
	UAPI_CMD(FIFO_SET_TX_CNT), UAPI_CMD(FIFO_GET_TX_CNT), UAPI_CMD(FIFO_SET_RX_CNT),
	UAPI_CMD(FIFO_GET_RX_CNT), UAPI_CMD(FW_VERSION_GET), UAPI_CMD(ECAT_STATE_UPDATE),
	UAPI_CMD(ECAT_INT_SET_ENABLE), UAPI_CMD(ECAT_INT_GET_ENABLE), UAPI_CMD(FIFO_INIT),
	UAPI_CMD(ECAT_SDO_ABORTCODE_GET), UAPI_CMD(ECAT_SET_FIFO_TH), UAPI_CMD(ECAT_CONFIG_SM),
	UAPI_CMD(ECAT_CONFIG_FMMU), UAPI_CMD(ECAT_CONFIG_MAP), UAPI_CMD(402_GET_STATUSWORD),
	UAPI_CMD(ASYNCCMD_RESET), UAPI_CMD(MDIO), UAPI_CMD(DIRECT_ASSIGN), UAPI_CMD(COE_EMERGENCY),
	UAPI_CMD(WARM_RESET), UAPI_CMD(ECAT_WKC_CONTI_ERR_CNT_GET),
	UAPI_CMD(ECAT_WKC_CONTI_ERR_MAX_GET), UAPI_CMD(ECAT_WKC_CONTI_ERR_MAX_SET),
	UAPI_CMD(RAW_ECAT_FUNC_REQ), UAPI_CMD(RAW_ECAT_FUNC_GET), UAPI_CMD(FOE_FUNC_REQ),
	UAPI_CMD(FOE_FUNC_GET), UAPI_CMD(ENABLE_LRW), UAPI_CMD(RECV_MAILBOX), UAPI_CMD(MBX_STAT),
};
#undef UAPI_CMD

TEST_CASE("command table: every row is a command code of <linux/ecmxf.h>, under its name", "[cmds]")
{
	std::size_t n = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&n);
	REQUIRE(kUapi.size() == n); // no two macros share a code, none is missing from the table
	for (std::size_t i = 0; i < n; i++) {
		INFO("table row " << t[i].name << ", code " << static_cast<unsigned>(t[i].code));
		auto it = kUapi.find(t[i].code);
		REQUIRE(it != kUapi.end());
		CHECK(it->second == t[i].name);
	}
}

TEST_CASE("command table: async commands are exactly the digest's list", "[cmds]")
{
	for (unsigned code = 0; code < 256; code++) {
		INFO("code " << code);
		if (code == ECMXF_CMD_RECV_MAILBOX) {
			CHECK(ecmxf_cmd_is_async(code, 0));
			CHECK_FALSE(ecmxf_cmd_is_async(code, 1));
			continue;
		}
		CHECK(ecmxf_cmd_is_async(code, 0) == (kAsync.count(code) == 1));
	}
}

TEST_CASE("command table: *_REQ commands name their *_GET partner", "[cmds]")
{
	for (const auto &[req, get] : kFetch)
		CHECK(ecmxf_cmd_lookup(req)->partner == static_cast<int>(get));
	std::size_t n = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&n);
	for (std::size_t i = 0; i < n; i++) {
		if (t[i].partner < 0)
			continue;
		const ecmxf_cmd_info *p = ecmxf_cmd_lookup(static_cast<unsigned>(t[i].partner));
		INFO(t[i].name);
		REQUIRE(p != nullptr);
		CHECK_FALSE(p->flags & ECMXF_CMDF_ASYNC); // results are fetched immediately
	}
}

TEST_CASE("command table: ver. 050 additions are not claimed for ver. 038", "[cmds]")
{
	for (unsigned code : { 69u, 70u, 71u, 73u, 74u, 75u, 81u, 82u, 83u, 127u, 130u, 137u, 138u,
			       139u, 140u, 142u, 143u, 144u }) {
		INFO("code " << code);
		CHECK((ecmxf_cmd_lookup(code)->flags & ECMXF_CMDF_V038) == 0);
		CHECK((ecmxf_cmd_lookup(code)->flags & ECMXF_CMDF_V050) != 0);
	}
	CHECK((ecmxf_cmd_lookup(72)->flags & ECMXF_CMDF_OBSOLETE) != 0);
}

TEST_CASE("command table: the C++ view matches the C table", "[cmds]")
{
	REQUIRE(ecmxf::commandCount() == kDigest.size());
	auto sdo = ecmxf::commandInfo(ECMXF_CMD_ECAT_SDO_REQ);
	REQUIRE(sdo);
	CHECK(sdo->name == "ECAT_SDO_REQ");
	CHECK(sdo->async);
	CHECK(sdo->partner == std::optional<std::uint8_t>{ 11 });
	CHECK_FALSE(ecmxf::commandInfo(14));
	CHECK(ecmxf::commandAt(0).code == 0);
	CHECK(ecmxf::commandAt(ecmxf::commandCount() - 1).code == 144);
	CHECK(ecmxf::crc32(std::span<const std::uint8_t>(
		      reinterpret_cast<const std::uint8_t *>("123456789"), 9)) == 0xCBF43926u);
	CHECK(ecmxf::packetSize(ecmxf::kDataMax) == 1440);
	CHECK(ecmxf::version() == ECMXF_TEST_VERSION);
}

// The reserved word at packet offset 0x08 (ECM-XF user manual ver. 050, the
// command header table): bit 15 = "GPIO output valid" for any command, bits
// 11 and 12 = "enable LRW" and "bus shift mode" of ECAT_INIT_OP (1); every
// other bit is reserved.  Vectors written by hand from that table.
TEST_CASE("reserved word: only the manual's bits, and 11/12 only with ECAT_INIT_OP", "[cmds]")
{
	CHECK(ecmxf_rsv_valid(0, 0));
	CHECK(ecmxf_rsv_valid(0, 0x8000));	// INFO_UPDATE_OP with GPIO outputs
	CHECK(ecmxf_rsv_valid(1, 0x0800));	// ECAT_INIT_OP, LRW
	CHECK(ecmxf_rsv_valid(1, 0x1000));	// ECAT_INIT_OP, bus shift
	CHECK(ecmxf_rsv_valid(1, 0x9800));	// all three
	CHECK_FALSE(ecmxf_rsv_valid(0, 0x0800));	// LRW on INFO_UPDATE_OP
	CHECK_FALSE(ecmxf_rsv_valid(6, 0x1000));	// bus shift on PDO_DATA_OP
	CHECK_FALSE(ecmxf_rsv_valid(2, 0x0800));	// RECONFIG_OP is not INIT_OP
	for (unsigned bit = 0; bit < 16; bit++) {
		if (bit == 11 || bit == 12 || bit == 15)
			continue;
		INFO("bit " << bit);
		CHECK_FALSE(ecmxf_rsv_valid(1, 1u << bit));
		CHECK_FALSE(ecmxf_rsv_valid(0, 1u << bit));
	}
	CHECK_FALSE(ecmxf_rsv_valid(1, 0x10000));	// wider than the word
}
