// SPDX-License-Identifier: MIT
// Firmware variants of the simulated chip (Documentation/simulator.rst,
// "Chip options"): the CRC coverage of NEXTW's example host code, a chip
// that takes CRC_TYPE_SET with the fixed word, both against raw packets and
// against the host's engine; the chip options of network files; and the
// project's decisions on a data length beyond the data section, on SDO_GET
// and on the slave information codes 10..13 (DC).

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine_link.hpp"
#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

const ecmxf_check kValid32 = static_cast<ecmxf_check>(ECMXF_CHECK_CRC32 | ECMXF_CHECK_COVER_VALID);

sim::ChipConfig variant(bool valid, bool crcSetFixed)
{
	sim::ChipConfig c;
	c.crcCoverage = valid ? sim::ChipConfig::CrcCoverage::Valid : sim::ChipConfig::CrcCoverage::Frame;
	c.crcTypeSetFixed = crcSetFixed;
	return c;
}

using simtest::EngineLink;

/// CRC_TYPE_SET by hand: sent in the type in force, its repeat (which
/// fetches the answer) already in @p ck, the new type; returns the answer.
Rsp switchCheck(Host &h, ecmxf_check type, ecmxf_check ck)
{
	const ecmxf_check old = h.check;
	h.send(Cmd(ECMXF_CMD_CRC_TYPE_SET, static_cast<std::uint8_t>(type)));
	h.check = ck;
	return h.decode(h.xfer(h.encode(h.last)), old);
}

} // namespace

TEST_CASE("chip option crc32-coverage=valid: the CRC covers the header and the valid data length",
	  "[chip][variants]")
{
	Rig rig(1, {}, variant(true, false));
	Host &h = rig.host;
	REQUIRE(switchCheck(h, ECMXF_CHECK_CRC32, kValid32).ok()); // answered in fixed
	// a command with 5 data bytes under the example code's rule is taken
	Rsp r = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET).payload({ 1, 2, 3, 4, 5 }));
	REQUIRE(r.ok());
	CHECK(r.h.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK((r.h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC32);
	CHECK(rig.chip->stats().badPackets == 0);
	// its answers verify under that rule only
	const auto miso = h.xfer(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP))));
	CHECK(h.decode(miso, kValid32).ok());
	CHECK(h.decode(miso, ECMXF_CHECK_CRC32).fault == ECMXF_FAULT_CHECK);
	// a packet under the manual's rule is a CRC error
	h.xfer(h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET).payload({ 1, 2, 3, 4, 5 })), ECMXF_CHECK_CRC32,
			 h.dataSize));
	CHECK(rig.chip->stats().badPackets == 1);
	// a data length of the whole section: both rules cover the same bytes
	h.xfer(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP).len(ECMXF_DATA_DEFAULT)), ECMXF_CHECK_CRC32,
			 h.dataSize));
	CHECK(rig.chip->stats().badPackets == 1);
}

TEST_CASE("chip option crc32-coverage=frame (default): the CRC covers the whole data section",
	  "[chip][variants]")
{
	Rig rig(1);
	Host &h = rig.host;
	REQUIRE(switchCheck(h, ECMXF_CHECK_CRC32, ECMXF_CHECK_CRC32).ok());
	REQUIRE(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET).payload({ 1, 2, 3, 4, 5 })).ok());
	CHECK(rig.chip->stats().badPackets == 0);
	h.xfer(h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET).payload({ 1, 2, 3, 4, 5 })), kValid32,
			 h.dataSize));
	CHECK(rig.chip->stats().badPackets == 1);
}

TEST_CASE("chip option crc-type-set-fixed: CRC_TYPE_SET with the fixed word under CRC-32, taken or dropped",
	  "[chip][variants]")
{
	for (const bool accept : { false, true }) {
		INFO("crc-type-set-fixed=" << (accept ? "accept" : "drop"));
		Rig rig(1, {}, variant(false, accept));
		Host &h = rig.host;
		REQUIRE(switchCheck(h, ECMXF_CHECK_CRC32, ECMXF_CHECK_CRC32).ok());
		REQUIRE(h.info().ok());
		// as the example code sends it: CRC_TYPE_SET 0 with the fixed word
		const Cmd set = h.fresh(Cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_FIXED));
		h.xfer(h.encode(set, ECMXF_CHECK_FIXED, h.dataSize));
		const auto miso = h.xfer(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP)), ECMXF_CHECK_FIXED, h.dataSize));
		// the answer (to CRC_TYPE_SET, or a refresh) is still in CRC-32
		const Rsp r = h.decode(miso, ECMXF_CHECK_CRC32);
		REQUIRE(r.ok());
		if (accept) {
			CHECK(r.h.index == set.h.index);
			CHECK(r.h.code == ECMXF_CMD_CRC_TYPE_SET);
			CHECK(rig.chip->stats().badPackets == 0);
			CHECK(r.h.crc_err_cnt == 1); // counted, as for SPI_RECONFIG_OP
			h.check = ECMXF_CHECK_FIXED;
			CHECK((h.info().h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_FIXED);
		} else {
			CHECK(r.h.code == ECMXF_CMD_INFO_UPDATE_OP);
			CHECK(r.h.index != set.h.index);
			CHECK(rig.chip->stats().badPackets == 2); // and the INFO_UPDATE in fixed
			CHECK((r.h.err_status & ECMXF_ERR_SPI_CRC) != 0);
			CHECK((h.info().h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC32);
		}
	}
}

TEST_CASE("chip and engine: fixed -> CRC-32 -> fixed on every variant, with a lost CRC_TYPE_SET",
	  "[chip][engine][variants]")
{
	for (const bool valid : { false, true }) {
		for (const bool accept : { false, true }) {
			for (const bool lose : { false, true }) {
				INFO("coverage " << (valid ? "valid" : "frame") << ", crc-type-set-fixed="
						 << (accept ? "accept" : "drop") << (lose ? ", first send lost" : ""));
				Rig rig(1, {}, variant(valid, accept));
				EngineLink link(*rig.chip);
				std::vector<std::uint8_t> size(2);
				// the engine's own first exchanges, so that the lost packet
				// is CRC_TYPE_SET itself
				REQUIRE(simtest::runCommand(link, ECMXF_CMD_SPI_PACK_SIZE_GET, 0, &size) == 0);
				for (const auto type : { ECMXF_CHECK_CRC32, ECMXF_CHECK_FIXED, ECMXF_CHECK_CRC32 }) {
					if (lose)
						rig.chip->faults().mosiBitErrors = 1;
					INFO("to type " << type);
					REQUIRE(simtest::runCommand(link, ECMXF_CMD_CRC_TYPE_SET, type) == 0);
					REQUIRE(simtest::runCommand(link, ECMXF_CMD_SPI_PACK_SIZE_GET, 0, &size) == 0);
					CHECK((size[0] | size[1] << 8) == 112);
					CHECK(ecmxf_engine_check(&link.e) == type);
					CHECK((link.e.last.ecm_status & ECMXF_STS_CHECK_MASK) == type);
				}
				CHECK(ecmxf_engine_cover(&link.e) ==
				      (valid ? ECMXF_COVER_VALID : ECMXF_COVER_FRAME));
				if (!lose)
					CHECK(rig.chip->stats().badPackets == 0);
				CHECK(link.e.stats.faults[ECMXF_FAULT_CHECK] == 0);
			}
		}
	}
}

TEST_CASE("chip: a data length beyond the data section is a bad parameter, nothing runs",
	  "[chip][variants]")
{
	Rig rig(2);
	Host &h = rig.host;
	// immediate: FIFO_ENABLE 1 does not switch the FIFO on
	REQUIRE(h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 0)).ok());
	Rsp r = h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1).len(ECMXF_DATA_DEFAULT + 1));
	REQUIRE(r.ok());
	CHECK(r.cmdError());
	CHECK((r.h.ecm_status & ECMXF_STS_FIFO_EN) == 0);
	r = h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1).len(ECMXF_DATA_MAX + 1).control(ECMXF_CTL_CLR_CMD_ERR));
	CHECK(r.cmdError());
	CHECK((r.h.ecm_status & ECMXF_STS_FIFO_EN) == 0);
	// exactly the data section is fine
	r = h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1).len(ECMXF_DATA_DEFAULT).control(ECMXF_CTL_CLR_CMD_ERR));
	CHECK_FALSE(r.cmdError());
	CHECK((r.h.ecm_status & ECMXF_STS_FIFO_EN) != 0);
	// async: INIT_OP is not started (no busy phase)
	Cmd init = initOp();
	init.h.len = 0xFFFF;
	r = h.cmd(init);
	CHECK(r.cmdError());
	CHECK_FALSE(r.busy());
	CHECK_FALSE(h.info().busy());
	// SPI_RECONFIG_OP's length is its parameter, not a data length
	r = h.cmd(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(256).control(ECMXF_CTL_CLR_CMD_ERR));
	CHECK(rig.chip->dataSize() == 256);
}

TEST_CASE("chip: SDO_GET returns the last read's data, a write keeps it, a failed read clears it",
	  "[chip][variants]")
{
	Rig rig(1);
	rig.init();
	Host &h = rig.host;
	REQUIRE(h.async(stateSet(0, ECMXF_ECAT_PREOP)).ok());
	REQUIRE(h.async(sdoReq(0, 0, 0x2000, 1, le32v(0x11223344))).ok());
	REQUIRE(h.async(sdoReq(1, 0, 0x2000, 1, {}, 4)).ok());
	Rsp g = h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET));
	REQUIRE(g.data.size() == 4);
	CHECK(g.u32() == 0x11223344u);
	// a write between read and SDO_GET: the read's data stays
	REQUIRE(h.async(sdoReq(0, 0, 0x2000, 1, le32v(0x55667788))).ok());
	g = h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET));
	REQUIRE(g.data.size() == 4);
	CHECK(g.u32() == 0x11223344u);
	// a read that fails (no such object): nothing was read back
	h.send(sdoReq(1, 0, 0x7777, 0, {}, 4));
	h.repeat();
	const Rsp done = h.waitIdle();
	CHECK(done.asyncError());
	g = h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET).control(ECMXF_CTL_CLR_ASYNC_ERR));
	CHECK(g.data.empty());
}

TEST_CASE("chip: slave information codes 10..13 give each slave model's DC state", "[chip][variants]")
{
	sim::Chip chip(sim::Network::fromText("slave servo\nslave EST-584\nslave dio\n"));
	Host h(chip);
	h.sync();
	const Rsp init = h.async(initOp(500'000, 0x0300, 0, 125'000));
	REQUIRE_FALSE(init.asyncError());
	const auto info = [&](std::uint8_t slave, std::uint8_t code) {
		Rsp r = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, slave).d(code));
		REQUIRE(r.ok());
		REQUIRE_FALSE(r.cmdError());
		return r;
	};
	// the servo uses DC (AssignActivate 0x0300): SYNC0 every 500 us, shift 125 us
	CHECK(info(0, 10).data == std::vector<std::uint8_t>{ 1 });
	CHECK(info(0, 11).u32() == 500'000u);
	CHECK(info(0, 12).u32() == 125'000u);
	CHECK(info(0, 13).data == std::vector<std::uint8_t>{ 1 });
	// the EST-584's ESC has DC, the model does not activate it
	CHECK(info(1, 10).data == std::vector<std::uint8_t>{ 1 });
	CHECK(info(1, 11).u32() == 0u);
	CHECK(info(1, 12).u32() == 0u);
	CHECK(info(1, 13).data == std::vector<std::uint8_t>{ 0 });
	// digital I/O: no DC at all
	CHECK(info(2, 10).data == std::vector<std::uint8_t>{ 0 });
	CHECK(info(2, 13).data == std::vector<std::uint8_t>{ 0 });
	// a negative shift is sent back as the signed 32-bit value
	REQUIRE_FALSE(h.async(initOp(1'000'000, 0x0300, 0, -2000)).asyncError());
	CHECK(static_cast<std::int32_t>(info(0, 12).u32()) == -2000);
	CHECK(info(0, 11).u32() == 1'000'000u);
	// past the codes: a command error
	const Rsp bad = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 0).d(14));
	CHECK(bad.cmdError());
}

TEST_CASE("network files: chip KEY=VALUE lines set chip options, bad ones name line, key and value",
	  "[chip][variants]")
{
	const sim::Network n = sim::Network::fromText("slave dio\nchip crc32-coverage=valid crc-type-set-fixed=accept\n");
	REQUIRE(n.chipOptions().size() == 2);
	CHECK(n.chipOptions()[0] == std::pair<std::string, std::string>{ "crc32-coverage", "valid" });
	// the chip applies them over the ChipConfig it is given
	sim::Chip chip(sim::Network::fromText("slave dio\nchip crc32-coverage=valid\n"));
	Host h(chip);
	h.sync();
	REQUIRE(switchCheck(h, ECMXF_CHECK_CRC32, kValid32).ok());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET).payload({ 9 })).ok());
	CHECK(chip.stats().badPackets == 0);

	const auto error = [](const std::string &text) {
		try {
			(void)sim::Network::fromText(text, "net.txt");
		} catch (const std::invalid_argument &e) {
			return std::string(e.what());
		}
		return std::string("no error");
	};
	CHECK(error("slave dio\nchip crc32-coverage=both\n") ==
	      "net.txt:2: chip option crc32-coverage: bad value 'both' (expected frame or valid)");
	CHECK(error("chip crc-type-set-fixed=yes\n") ==
	      "net.txt:1: chip option crc-type-set-fixed: bad value 'yes' (expected drop or accept)");
	CHECK(error("chip crc32-coverage=\n") ==
	      "net.txt:1: chip option crc32-coverage: bad value '' (expected frame or valid)");
	CHECK(error("\n\nchip speed=fast\n").starts_with("net.txt:3: unknown chip option 'speed' (known: "));
	CHECK(error("chip crc32-coverage\n") == "net.txt:1: chip option 'crc32-coverage' is not KEY=VALUE");
	CHECK(error("chip =frame\n") == "net.txt:1: chip option '=frame' is not KEY=VALUE");
	CHECK(error("chip\n").starts_with("net.txt:1: 'chip' needs KEY=VALUE options"));
	CHECK(error("chip crc32-coverage=valid crc32-coverage=frame\n") ==
	      "net.txt:1: chip option 'crc32-coverage' given twice");
	CHECK(error("chip crc32-coverage=valid\nchip crc32-coverage=valid\n") ==
	      "net.txt:2: chip option 'crc32-coverage' given twice");

	// applyChipOption and Network::setChipOption directly
	sim::ChipConfig cfg;
	sim::applyChipOption(cfg, "crc32-coverage", "valid");
	CHECK(cfg.crcCoverage == sim::ChipConfig::CrcCoverage::Valid);
	sim::applyChipOption(cfg, "crc-type-set-fixed", "accept");
	CHECK(cfg.crcTypeSetFixed);
	CHECK_THROWS_AS(sim::applyChipOption(cfg, "CRC32-coverage", "valid"), std::invalid_argument);
	CHECK_THROWS_AS(sim::applyChipOption(cfg, "crc32-coverage", "Valid"), std::invalid_argument);
	sim::Network m;
	m.setChipOption("crc32-coverage", "valid");
	m.setChipOption("crc32-coverage", "frame"); // replaces
	REQUIRE(m.chipOptions().size() == 1);
	CHECK(m.chipOptions()[0].second == "frame");
	CHECK_THROWS_AS(m.setChipOption("crc32-coverage", "x"), std::invalid_argument);
	CHECK(m.chipOptions()[0].second == "frame");
}

TEST_CASE("chip option init-op: strict refuses INIT_OP byte 1 = 0, lenient takes it and leaves the FIFO on",
	  "[chip][variants]")
{
	for (const bool lenient : { false, true }) {
		INFO("init-op=" << (lenient ? "lenient" : "strict"));
		sim::ChipConfig cfg;
		sim::applyChipOption(cfg, "init-op", lenient ? "lenient" : "strict");
		CHECK(cfg.initOpLenient == lenient);
		Rig rig(1, {}, cfg);
		Cmd c = initOp();
		c.data[1] = 0x00; // as NEXTW's example host drivers send it
		const Rsp a = rig.host.cmd(c);
		if (!lenient) {
			CHECK(a.cmdError());
			CHECK_FALSE(a.busy());
			CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == 0);
			continue;
		}
		REQUIRE_FALSE(a.cmdError());
		const Rsp r = rig.host.waitIdle();
		CHECK_FALSE(r.asyncError());
		CHECK(r.h.ecat_state == ECMXF_ECAT_INIT);
		CHECK(r.h.ecm_status & ECMXF_STS_FIFO_EN); // on without FIFO_ENABLE (manual ver. 038)
		CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == 1);
		// 0x81 on the lenient firmware: as ver. 050 says, FIFO off
		const Rsp b = rig.host.cmd(initOp());
		REQUIRE_FALSE(b.cmdError());
		CHECK_FALSE(rig.host.waitIdle().h.ecm_status & ECMXF_STS_FIFO_EN);
		// any other byte 1 is still a command error
		Cmd bad = initOp();
		bad.data[1] = 0x01;
		CHECK(rig.host.cmd(bad).cmdError());
	}
	sim::ChipConfig cfg;
	CHECK_FALSE(cfg.initOpLenient); // strict by default
	try {
		sim::applyChipOption(cfg, "init-op", "loose");
		FAIL("init-op=loose taken");
	} catch (const std::invalid_argument &e) {
		CHECK(std::string(e.what()) == "chip option init-op: bad value 'loose' (expected strict or lenient)");
	}
	const sim::Network n = sim::Network::fromText("slave dio\nchip init-op=lenient\n");
	CHECK(n.chipOptions()[0] == std::pair<std::string, std::string>{ "init-op", "lenient" });
}
