// SPDX-License-Identifier: MIT
// The host's protocol engine (lib/core, the code the kernel module and the
// spidev transport run) against the simulated chip: both sides' reading of
// the exchange rules must agree, through async commands, SDO transfers and
// aborts, format changes and a reset.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include "engine_link.hpp"
#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

ecmxf_xfer xfer(std::uint8_t code, std::uint8_t param = 0, const std::vector<std::uint8_t> *tx = nullptr,
		std::vector<std::uint8_t> *rx = nullptr)
{
	ecmxf_xfer x{};
	x.hdr.code = code;
	x.hdr.param = param;
	if (tx) {
		x.tx_data = tx->data();
		x.tx_len = static_cast<std::uint16_t>(tx->size());
		x.hdr.len = x.tx_len;
	}
	if (rx) {
		x.rx_buf = rx->data();
		x.rx_size = static_cast<std::uint16_t>(rx->size());
	}
	return x;
}

} // namespace

TEST_CASE("chip and engine: INIT_OP, STATE_SET PRE-OP and an SDO read agree end to end",
	  "[chip][engine]")
{
	Rig rig(2);
	EngineLink link(*rig.chip);

	const std::vector<std::uint8_t> init = initOp(1'000'000).data;
	ecmxf_xfer x = xfer(ECMXF_CMD_ECAT_INIT_OP, 0, &init);
	CHECK(link.run(x) == 0);
	CHECK(x.async);
	CHECK(link.e.last.ecat_state == ECMXF_ECAT_INIT);

	x = xfer(ECMXF_CMD_ECAT_STATE_SET, 0xFF);
	x.hdr.data[0] = ECMXF_ECAT_PREOP;
	CHECK(link.run(x) == 0);
	CHECK(link.e.last.ecat_state == ECMXF_ECAT_PREOP);
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP);
	CHECK(rig.s(1).state == ECMXF_ECAT_PREOP);

	x = xfer(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	CHECK(link.run(x) == 0);
	CHECK(x.rsp.ret == ECMXF_ECAT_PREOP);

	const std::vector<std::uint8_t> req = sdoReq(1, 1, 0x2000, 0).data;
	x = xfer(ECMXF_CMD_ECAT_SDO_REQ, 0, &req);
	CHECK(link.run(x) == 0);
	std::vector<std::uint8_t> buf(16);
	x = xfer(ECMXF_CMD_ECAT_SDO_GET, 0, nullptr, &buf);
	CHECK(link.run(x) == 0);
	REQUIRE(x.rx_len == 4);
	CHECK(buf[0] == 0x11);
	CHECK(buf[3] == 0x44);

	// an abort: the engine reports the async error, the chip the code
	const std::vector<std::uint8_t> bad = sdoReq(1, 0, 0x7777, 0).data;
	x = xfer(ECMXF_CMD_ECAT_SDO_REQ, 0, &bad);
	CHECK(link.run(x) == -EREMOTEIO);
	std::vector<std::uint8_t> code(4);
	x = xfer(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET, 0, nullptr, &code);
	CHECK(link.run(x) == 0);
	CHECK((code[0] | code[1] << 8 | code[2] << 16 | code[3] << 24) == 0x06020000);

	CHECK(link.e.stats.exhausted == 0);
	CHECK(link.e.stats.busy_rejects == 0);
	CHECK(link.e.stats.chip_resets == 0);
	CHECK(link.e.stats.lost_answers == 0);
	for (auto f : link.e.stats.faults)
		CHECK(f == 0);
}

TEST_CASE("chip and engine: a refused second async command is -EBUSY", "[chip][engine]")
{
	SlaveConfig slow;
	slow.transitionTime = 50ms;
	Rig rig(1, slow);
	EngineLink link(*rig.chip);
	const std::vector<std::uint8_t> init = initOp().data;
	ecmxf_xfer x = xfer(ECMXF_CMD_ECAT_INIT_OP, 0, &init);
	REQUIRE(link.run(x) == 0);
	// another host (the raw one) starts an async command behind the
	// engine; its indices are kept apart from the engine's
	rig.host.index = 200;
	const Rsp other = rig.host.cmd(stateSet(0xFF, ECMXF_ECAT_PREOP));
	REQUIRE(other.busy());
	x = xfer(ECMXF_CMD_ECAT_STATE_UPDATE);
	CHECK(link.run(x) == -EBUSY);
	CHECK(link.e.stats.busy_rejects == 1);
}

TEST_CASE("chip and engine: SPI_RECONFIG_OP, CRC_TYPE_SET and WARM_RESET change the format in step",
	  "[chip][engine]")
{
	Rig rig(1);
	EngineLink link(*rig.chip);
	ecmxf_xfer x = xfer(ECMXF_CMD_SPI_RECONFIG_OP);
	x.hdr.len = 512;
	CHECK(link.run(x) == 0);
	CHECK(rig.chip->dataSize() == 512);
	CHECK(ecmxf_engine_pkt_size(&link.e) == rig.chip->packetSize());

	x = xfer(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32);
	CHECK(link.run(x) == 0);
	std::vector<std::uint8_t> size(2);
	x = xfer(ECMXF_CMD_SPI_PACK_SIZE_GET, 0, nullptr, &size);
	CHECK(link.run(x) == 0);
	CHECK((size[0] | size[1] << 8) == 512);
	CHECK((link.e.last.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC32);

	x = xfer(ECMXF_CMD_WARM_RESET);
	CHECK(link.run(x) == 0);
	CHECK(rig.chip->dataSize() == 112);
	x = xfer(ECMXF_CMD_SPI_PACK_SIZE_GET, 0, nullptr, &size);
	CHECK(link.run(x) == 0);
	CHECK((size[0] | size[1] << 8) == 112);
	for (int i = ECMXF_FAULT_START; i < ECMXF_FAULT_COUNT; i++)
		CHECK(link.e.stats.faults[i] == 0);
}

TEST_CASE("chip and engine: transport faults are retried by the engine", "[chip][engine]")
{
	Rig rig(1);
	EngineLink link(*rig.chip);
	rig.chip->faults().misoBitErrors = 2;
	rig.chip->faults().mosiBitErrors = 1;
	rig.chip->faults().notReady = 1;
	std::vector<std::uint8_t> v(20);
	ecmxf_xfer x = xfer(ECMXF_CMD_FW_VERSION_GET, 0, nullptr, &v);
	CHECK(link.run(x) == 0);
	CHECK(x.rsp.ret == sim::ChipConfig{}.fwVersion);
	CHECK(link.e.stats.faults[ECMXF_FAULT_CHECK] == 2);
	CHECK(link.e.stats.faults[ECMXF_FAULT_NOT_READY] == 1);
}
