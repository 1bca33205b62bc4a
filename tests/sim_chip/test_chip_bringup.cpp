// SPDX-License-Identifier: MIT
// The chip with the real slave models: the default network (2 x EST-584 +
// digital I/O) brought up to OP the way both manuals describe it, with
// process data flowing through the FIFOs and the working counter right.

#include <catch2/catch.hpp>

#include <memory>
#include <string>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

/// The AL status codes of every slave, for a failure message.
std::string alCodes(Host &h, unsigned n)
{
	std::string s;
	for (unsigned i = 0; i < n; i++) {
		const Rsp r = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, static_cast<std::uint8_t>(i)).d(7));
		s += " slave " + std::to_string(i) + ": 0x" +
		     (r.h.len == 2 ? std::to_string(r.u16()) : std::string("?"));
	}
	return s;
}

/// Bring @p chip's network to OP the way both manuals describe it, exchange
/// process data through the FIFOs for 200 ms and check the WKC.
void bringUp(sim::Chip &chip, std::uint32_t sync0, std::uint16_t dataSize)
{
	const auto n = static_cast<unsigned>(chip.network().size());
	Host h(chip);
	h.sync();

	// INIT_OP: DC with SYNC0 every @p sync0 ns
	Rsp r = h.async(initOp(sync0, 0x0300));
	REQUIRE_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_INIT);
	REQUIRE(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == n);
	for (unsigned i = 0; i < n; i++) {
		INFO("slave " << i);
		const auto pos = static_cast<std::uint8_t>(i);
		const sim::Identity &id = chip.network().at(i).identity();
		CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, pos).d(0)).u32() == id.vendorId);
		CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, pos).d(1)).u32() == id.productCode);
		CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, pos).d(4)).u16() == 0x1001 + i);
	}
	const Rsp name = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 0).d(3));
	CHECK(std::string(name.data.begin(), name.data.end()) == chip.network().at(0).identity().name);

	r = h.async(stateSet(0xFF, ECMXF_ECAT_PREOP));
	INFO("AL status codes:" << alCodes(h, n));
	REQUIRE_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_PREOP);

	// an SDO through the chip: the identity object of the first slave
	if (chip.network().at(0).hasCoE()) {
		REQUIRE_FALSE(h.async(sdoReq(1, 0, 0x1018, 1)).asyncError());
		CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET)).u32() ==
		      chip.network().at(0).identity().vendorId);
	}

	r = h.async(stateSet(0xFF, ECMXF_ECAT_SAFEOP));
	INFO("AL status codes:" << alCodes(h, n));
	REQUIRE_FALSE(r.asyncError());

	if (dataSize != ECMXF_DATA_DEFAULT) {
		h.send(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(dataSize));
		h.dataSize = dataSize;
		chip.advance(100ms);
		REQUIRE(h.repeat().ok());
	}
	const unsigned rxSize = h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16();
	const unsigned txSize = h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1)).u16();
	REQUIRE(rxSize > 0);
	REQUIRE(txSize > 0);
	REQUIRE(rxSize <= dataSize);
	REQUIRE(txSize <= dataSize);
	std::size_t rxSum = 0, txSum = 0;
	unsigned inSlavesWant = 0, outSlavesWant = 0;
	for (unsigned i = 0; i < n; i++) {
		rxSum += chip.network().at(i).outputBytes();
		txSum += chip.network().at(i).inputBytes();
		outSlavesWant += chip.network().at(i).outputBytes() > 0;
		inSlavesWant += chip.network().at(i).inputBytes() > 0;
	}
	CHECK(rxSize == rxSum);
	CHECK(txSize == txSum);

	// initial outputs, then OP
	REQUIRE(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x05).payload(std::vector<std::uint8_t>(rxSize, 0)))
			.h.ret &
		0x01);
	r = h.async(stateSet(0xFF, ECMXF_ECAT_OP));
	INFO("AL status codes:" << alCodes(h, n));
	REQUIRE_FALSE(r.asyncError());
	REQUIRE(r.h.ecat_state == ECMXF_ECAT_OP);

	const std::uint32_t inSlaves = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 1)).u32();
	const std::uint32_t outSlaves = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 2)).u32();
	CHECK(inSlaves == inSlavesWant);
	CHECK(outSlaves == outSlavesWant);

	// cyclic exchange through the FIFOs: one frame per ms in, all frames out
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	std::size_t frames = 0;
	const auto t0 = chip.now();
	for (int ms = 0; ms < 200; ms++) {
		Cmd c = Cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, 1).d(0x03).payload(std::vector<std::uint8_t>(rxSize, 0));
		const Rsp x = h.cmd(c);
		REQUIRE(x.ok());
		REQUIRE_FALSE(x.cmdError());
		CHECK(x.h.len % txSize == 0);
		frames += x.h.len / txSize;
		const auto next = t0 + std::chrono::milliseconds(ms + 1);
		if (chip.now() < next)
			chip.advance(next - chip.now());
	}
	// one frame per response at most when a frame fills the data section
	CHECK(frames >= (2 * txSize <= dataSize ? 195u : 180u));
	r = h.info();
	CHECK(r.h.ecat_state == ECMXF_ECAT_OP);
	CHECK(r.h.wkc_err_cnt == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 3)).u32() == inSlaves * 1 + outSlaves * 2);
	CHECK(h.async(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE)).h.ecat_state == ECMXF_ECAT_OP);
}

std::string networkFile(const char *name)
{
	return std::string(ECMXF_TEST_NETWORK_DIR) + "/" + name;
}

} // namespace

TEST_CASE("chip bring-up: the default network reaches OP with process data flowing and the WKC right",
	  "[chip][bringup]")
{
	sim::Chip chip; // empty path: the default network
	REQUIRE(chip.network().size() == 3);
	bringUp(chip, 1'000'000, ECMXF_DATA_DEFAULT);
}

TEST_CASE("chip bring-up: est584x2-io.net is the default network and reaches OP", "[chip][bringup]")
{
	sim::Chip chip(networkFile("est584x2-io.net"));
	REQUIRE(chip.network().size() == 3);
	CHECK(chip.network().at(0).typeName() == "EST-584");
	CHECK(chip.network().at(2).typeName() == "dio");
	bringUp(chip, 1'000'000, ECMXF_DATA_DEFAULT);
}

TEST_CASE("chip bring-up: servo-io.net reaches OP with DC SYNC0 and process data flowing",
	  "[chip][bringup]")
{
	sim::Chip chip(networkFile("servo-io.net"));
	REQUIRE(chip.network().size() == 3);
	bringUp(chip, 1'000'000, ECMXF_DATA_MAX);
}

TEST_CASE("chip bring-up: slaves128.net (128 slaves) reaches OP at 8 kHz with the WKC right",
	  "[chip][bringup]")
{
	sim::Chip chip(networkFile("slaves128.net"));
	REQUIRE(chip.network().size() == 128);
	bringUp(chip, 125'000, ECMXF_DATA_MAX);
}

TEST_CASE("chip bring-up: a slave that drops out in OP falls to SAFE-OP+E with 0x001B (SM watchdog) "
	  "and the master shows ERROR while it is gone",
	  "[chip][bringup][faults]")
{
	sim::Chip chip; // 2 x EST-584 + digital I/O
	Host h(chip);
	h.sync();
	REQUIRE_FALSE(h.async(initOp(1'000'000, 0x0300)).asyncError());
	REQUIRE_FALSE(h.async(stateSet(0xFF, ECMXF_ECAT_PREOP)).asyncError());
	REQUIRE_FALSE(h.async(stateSet(0xFF, ECMXF_ECAT_SAFEOP)).asyncError());
	const unsigned rxSize = h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16();
	h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x05).payload(std::vector<std::uint8_t>(rxSize, 0)));
	REQUIRE(h.async(stateSet(0xFF, ECMXF_ECAT_OP)).h.ecat_state == ECMXF_ECAT_OP);
	chip.advance(50ms);
	CHECK(h.info().h.wkc_err_cnt == 0);

	// slave 1 stops receiving frames for longer than its 100 ms watchdog
	chip.faults().slaveDropped = 1;
	chip.advance(300ms);
	const Rsp during = h.info();
	CHECK(during.h.ecat_state == ECMXF_ECAT_ERROR);
	CHECK(during.h.wkc_err_cnt > 0);
	chip.faults().slaveDropped = -1;
	chip.advance(10ms);

	// back on the bus: it fell to SAFE-OP with the error bit and 0x001B
	const sim::Slave &s = chip.network().at(1);
	CHECK(s.alStatus() == (0x04 | 0x10));
	CHECK(s.alStatusCode() == 0x001B);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 1).d(7)).u16() == 0x001B);
	// the other slaves stayed in OP
	CHECK(chip.network().at(0).alStatus() == 0x08);
	CHECK(chip.network().at(2).alStatus() == 0x08);
}
