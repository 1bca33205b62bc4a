// SPDX-License-Identifier: MIT
// The typed process-data and FIFO calls of Device against the simulator,
// with the values the manuals give for the default network (2 x EST-584 +
// digital I/O: 12 + 12 + 1 output, 17 + 17 + 1 input bytes).

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/slaves.hpp>

#include "bus.hpp"
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using pdotest::Bus;

namespace {

using ecmxftest::thrown;

/// @p n RxPDO frames of the default network (25 bytes), frame i filled
/// with i + 1 and its digital-output byte (offset 24) = 0x10 + i.
std::vector<std::uint8_t> frames(unsigned n)
{
	std::vector<std::uint8_t> f;
	for (unsigned i = 0; i < n; i++) {
		for (unsigned b = 0; b < 24; b++)
			f.push_back(static_cast<std::uint8_t>(i + 1));
		f.push_back(static_cast<std::uint8_t>(0x10 + i));
	}
	return f;
}

constexpr std::uint8_t kErrFifo = 0x20;
constexpr std::uint8_t kErrCmd = 0x80;
constexpr std::uint8_t kStsFifoEn = 0x40;

} // namespace

TEST_CASE("PDO_WC_GET: slave counts and the working counter of the default network", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	const ecmxf::PdoSlaveCounts c = bus.dev->pdo().slaveCounts();
	// all three slaves have inputs and outputs
	CHECK(c.inputSlaves == 3);
	CHECK(c.outputSlaves == 3);
	// 3 x 1 + 3 x 2
	CHECK(c.expectedWkc() == 9);
	bus.run(3ms);
	CHECK(bus.dev->pdo().workingCounter() == 9);
	// the I/O terminal stops answering: its 1 + 2 are missing
	bus.chip().faults().slaveDropped = 2;
	bus.run(3ms);
	CHECK(bus.dev->pdo().workingCounter() == 6);
}

TEST_CASE("FIFO_PACK_SIZE_GET: the RxPDO and TxPDO frame sizes", "[lib][pdo][cmd]")
{
	Bus bus;
	// no layout before ECAT_INIT_OP
	CHECK(bus.dev->pdo().fifoPackSizes().rxPdoBytes == 0);
	bus.init();
	const ecmxf::FifoPackSizes s = bus.dev->pdo().fifoPackSizes();
	CHECK(s.rxPdoBytes == 12 + 12 + 1);
	CHECK(s.txPdoBytes == 17 + 17 + 1);
}

TEST_CASE("FIFO_GET/SET_RX/TX_CNT: depths, the 0x4000-byte budget checked before sending", "[lib][pdo][cmd]")
{
	Bus bus(pdotest::network("big-dio.net"));
	bus.init();
	ecmxf::Device &d = *bus.dev;
	CHECK(d.pdo().fifoRxCount() == 64);
	CHECK(d.pdo().fifoTxCount() == 64);

	// 100 x 100 + 64 x 100 = 16400 > 16384
	ecmxf::Error e = thrown([&] { d.pdo().fifoSetRxCount(100); });
	CHECK_THAT(e.what(), Equals("FIFO_SET_RX_CNT: 100 x 100-byte RxPDO frames + 64 x 100-byte TxPDO frames = "
				    "16400 bytes exceed the FIFO memory of 16384 bytes (0x4000)"));
	CHECK(e.errnoValue() == EINVAL);
	// refused here: the chip never saw it (no command error on it)
	CHECK((bus.info().errStatus & kErrCmd) == 0);
	CHECK(d.pdo().fifoRxCount() == 64);

	// 99 x 100 + 64 x 100 = 16300
	d.pdo().fifoSetRxCount(99);
	CHECK(d.pdo().fifoRxCount() == 99);
	e = thrown([&] { d.pdo().fifoSetTxCount(65); });
	CHECK_THAT(e.what(), Equals("FIFO_SET_TX_CNT: 99 x 100-byte RxPDO frames + 65 x 100-byte TxPDO frames = "
				    "16400 bytes exceed the FIFO memory of 16384 bytes (0x4000)"));
	d.pdo().fifoSetTxCount(10);
	CHECK(d.pdo().fifoTxCount() == 10);

	e = thrown([&] { d.pdo().fifoSetTxCount(0); });
	CHECK_THAT(e.what(), Equals("FIFO_SET_TX_CNT: TxFIFO count 0 out of range (1..255 frames)"));
	CHECK(e.errnoValue() == EINVAL);
	e = thrown([&] { d.pdo().fifoSetRxCount(256); });
	CHECK_THAT(e.what(), Equals("FIFO_SET_RX_CNT: RxFIFO count 256 out of range (1..255 frames)"));

	// both at once: 20 x 100 + 140 x 100 = 16000 fits, but 140 TxPDO with
	// the present 99 RxPDO would not, so the RxFIFO has to shrink first
	d.pdo().fifoSetCounts(20, 140);
	CHECK(d.pdo().fifoRxCount() == 20);
	CHECK(d.pdo().fifoTxCount() == 140);
	// and the other way round
	d.pdo().fifoSetCounts(150, 10);
	CHECK(d.pdo().fifoRxCount() == 150);
	CHECK(d.pdo().fifoTxCount() == 10);
	e = thrown([&] { d.pdo().fifoSetCounts(100, 64); });
	CHECK_THAT(e.what(), Contains("100 x 100-byte RxPDO frames + 64 x 100-byte TxPDO frames = 16400 bytes "
				      "exceed the FIFO memory of 16384 bytes (0x4000)"));
}

TEST_CASE("PDO_DATA_FIFO_OP: frames into the RxFIFO, out of the TxFIFO", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	auto &dio = bus.model<ecmxf::sim::DioModel>(2);

	// ECAT_INIT_OP left the FIFO off: frames are stored, not sent
	const ecmxf::PdoFifoResult w = d.pdo().fifoExchange(frames(3), 3, false);
	CHECK(w.allWritten);
	CHECK(w.rxFifoCount == 3);
	CHECK(w.framesRead == 0);
	CHECK(w.inputs.empty());
	dio.setInputs(std::vector<std::uint8_t>{ 0xA7 });
	bus.run(5ms);
	CHECK(bus.info().rxFifoCnt == 3);
	CHECK(dio.outputs()[0] == 0);

	d.pdo().fifoEnable(true);
	CHECK(d.lastHeader().ecmStatus & kStsFifoEn);
	bus.run(10ms);
	// the three frames went out one per bus cycle; the last one stays
	CHECK(bus.info().rxFifoCnt == 0);
	CHECK(dio.outputs()[0] == 0x12);

	// ten cycles queued ten TxPDO frames; 112 data bytes hold 3 of 35
	const ecmxf::PdoFifoResult r = d.pdo().fifoExchange({}, 0, true);
	CHECK(r.framesRead == 3);
	REQUIRE(r.inputs.size() == 3 * 35);
	CHECK(r.inputs[34] == 0xA7);
	CHECK(r.inputs[69] == 0xA7);
	CHECK(r.inputs[104] == 0xA7);
	CHECK(r.allWritten == false); // no write asked for
}

TEST_CASE("PDO_DATA_FIFO_OP: a full RxFIFO refuses the newest frames", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	d.pdo().fifoSetRxCount(4);
	const ecmxf::PdoFifoResult r = d.pdo().fifoExchange(frames(4), 4, false);
	CHECK(r.allWritten);
	const auto refused0 = bus.chip().stats().rxRefused;
	const ecmxf::PdoFifoResult full = d.pdo().fifoExchange(frames(2), 2, false);
	CHECK_FALSE(full.allWritten);
	CHECK(full.rxFifoCount == 4);
	CHECK(full.errStatus & kErrFifo);
	CHECK(bus.chip().stats().rxRefused - refused0 == 2);
	// the FIFO error bit is cleared with the next write
	d.pdo().fifoClear(ecmxf::FifoSelect::RxFifo);
	const ecmxf::PdoFifoResult again = d.pdo().fifoExchange(frames(1), 1, false);
	CHECK(again.allWritten);
	CHECK((again.errStatus & kErrFifo) == 0);
}

TEST_CASE("PDO_DATA_FIFO_OP: bad frame counts and sizes are refused before sending", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	ecmxf::Error e = thrown([&] { (void)d.pdo().fifoExchange(frames(1), 256, false); });
	CHECK_THAT(e.what(), Equals("ECAT_PDO_DATA_FIFO_OP: 256 RxPDO frames out of range (0..255 per command)"));
	CHECK(e.errnoValue() == EINVAL);
	e = thrown([&] { (void)d.pdo().fifoExchange(frames(2), 3, false); });
	CHECK_THAT(e.what(), Equals("ECAT_PDO_DATA_FIFO_OP: 50 bytes do not divide into 3 RxPDO frames"));
	e = thrown([&] { (void)d.pdo().fifoExchange(std::vector<std::uint8_t>(24, 0), 1, false); });
	CHECK_THAT(e.what(), Equals("ECAT_PDO_DATA_FIFO_OP: RxPDO frames of 24 bytes given; the chip's RxPDO "
				    "frame is 25 bytes (FIFO_PACK_SIZE_GET 0)"));
	CHECK(e.errnoValue() == EINVAL);
	e = thrown([&] { (void)d.pdo().fifoExchange(frames(5), 5, false); });
	CHECK_THAT(e.what(), Equals("ECAT_PDO_DATA_FIFO_OP: 5 RxPDO frames of 25 bytes (125 bytes) do not fit "
				    "the data section (112 bytes)"));
	CHECK(e.errnoValue() == EMSGSIZE);
	CHECK(bus.info().rxFifoCnt == 0);
}

TEST_CASE("PDO_DATA_OP: read, write and both on the direct process image", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	auto &dio = bus.model<ecmxf::sim::DioModel>(2);
	auto &drive1 = bus.model<ecmxf::sim::Cia402Model>(1);
	dio.setInputs(std::vector<std::uint8_t>{ 0x5C });
	drive1.setPositionActual(-2);
	bus.run(3ms);

	const std::vector<std::uint8_t> in = d.pdo().read();
	REQUIRE(in.size() == 35);
	CHECK(in[34] == 0x5C);
	// slave 1's position actual: frame byte 17 + 3, little-endian -2
	CHECK(in[20] == 0xFE);
	CHECK(in[21] == 0xFF);
	CHECK(in[22] == 0xFF);
	CHECK(in[23] == 0xFF);

	std::vector<std::uint8_t> out(25, 0);
	out[24] = 0x3C;
	d.pdo().write(out);
	bus.run(3ms);
	CHECK(dio.outputs()[0] == 0x3C);

	out[24] = 0xC3;
	dio.setInputs(std::vector<std::uint8_t>{ 0x11 });
	bus.run(2ms);
	const std::vector<std::uint8_t> both = d.pdo().writeRead(out);
	REQUIRE(both.size() == 35);
	CHECK(both[34] == 0x11);
	bus.run(2ms);
	CHECK(dio.outputs()[0] == 0xC3);

	const ecmxf::Error e = thrown([&] { d.pdo().write({}); });
	CHECK_THAT(e.what(), Equals("ECAT_PDO_DATA_OP: no output bytes to write"));
	CHECK(e.errnoValue() == EINVAL);
}

TEST_CASE("process data commands before ECAT_INIT_OP: the chip's refusal names the command", "[lib][pdo][cmd]")
{
	Bus bus;
	ecmxf::Error e = thrown([&] { (void)bus.dev->pdo().read(); });
	CHECK_THAT(e.what(), Equals("ECAT_PDO_DATA_OP: the chip refused the command (error status bit 7, command "
				    "error: no process image yet (ECAT_INIT_OP first)?)"));
	CHECK(e.errnoValue() == EREMOTEIO);
	REQUIRE(e.errorStatus().has_value());
	CHECK(*e.errorStatus() & kErrCmd);
	// no layout: the chip's RxPDO frame is 0 bytes
	e = thrown([&] { (void)bus.dev->pdo().fifoExchange(std::vector<std::uint8_t>(4, 0), 1, false); });
	CHECK_THAT(e.what(), Contains("the chip's RxPDO frame is 0 bytes"));
	// a read alone reaches the chip, which refuses it
	e = thrown([&] { (void)bus.dev->pdo().fifoExchange({}, 0, true); });
	CHECK_THAT(e.what(), Contains("ECAT_PDO_DATA_FIFO_OP: the chip refused the command (error status bit 7"));
}

TEST_CASE("FIFO_CLR_OP and FIFO_INIT empty the FIFOs", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	auto fill = [&] {
		d.pdo().fifoEnable(true);
		bus.run(6ms);
		d.pdo().fifoEnable(false);
		(void)d.pdo().fifoExchange(frames(3), 3, false);
		const ecmxf::ResponseHeader h = bus.info();
		REQUIRE(h.txFifoCnt >= 5);
		REQUIRE(h.rxFifoCnt == 3);
	};
	fill();
	d.pdo().fifoClear(ecmxf::FifoSelect::TxFifo);
	CHECK(d.lastHeader().txFifoCnt == 0);
	CHECK(d.lastHeader().rxFifoCnt == 3);
	d.pdo().fifoClear(ecmxf::FifoSelect::RxFifo);
	CHECK(d.lastHeader().rxFifoCnt == 0);
	fill();
	d.pdo().fifoClear();
	CHECK(d.lastHeader().txFifoCnt == 0);
	CHECK(d.lastHeader().rxFifoCnt == 0);

	d.pdo().fifoSetRxCount(5);
	(void)d.pdo().fifoExchange(frames(2), 2, false);
	CHECK(bus.info().rxFifoCnt == 2);
	d.pdo().fifoInit();
	CHECK(d.lastHeader().rxFifoCnt == 0);
	CHECK(d.pdo().fifoRxCount() == 5);

	const ecmxf::Error e = thrown([&] { d.pdo().fifoClear(static_cast<ecmxf::FifoSelect>(3)); });
	CHECK_THAT(e.what(), Equals("FIFO_CLR_OP: FIFO selector 3 out of range (0 both, 1 TxFIFO, 2 RxFIFO)"));
}

TEST_CASE("FIFO_ENABLE switches the FIFO exchange and ECM status bit 6", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	CHECK((bus.info().ecmStatus & kStsFifoEn) == 0);
	d.pdo().fifoEnable(true);
	CHECK(bus.info().ecmStatus & kStsFifoEn);
	bus.run(4ms);
	CHECK(bus.info().txFifoCnt >= 4);
	d.pdo().fifoEnable(false);
	CHECK((bus.info().ecmStatus & kStsFifoEn) == 0);
	const auto queued = bus.info().txFifoCnt;
	bus.run(4ms);
	CHECK(bus.info().txFifoCnt == queued);
}

TEST_CASE("ECAT_SET_FIFO_TH: the TxFIFO high mark raises interrupt flag bit 24 and INT1", "[lib][pdo][cmd]")
{
	Bus bus;
	bus.toOp();
	ecmxf::Device &d = *bus.dev;
	// ECAT_INT_SET_ENABLE: INT0 active high (bit 1), INT1 active low;
	// u32CompIntEnable = bits 24 and 25
	ecmxf::Command en;
	en.code = pdotest::kIntSetEnable;
	en.param = 0x02;
	pdotest::put32(en.payload, (1u << 24) | (1u << 25));
	en.payload.push_back(0);
	en.payload.push_back(0);
	(void)d.command(en);

	ecmxf::FifoThresholds t;
	t.txHighEnabled = true;
	t.txHigh = 3;
	d.pdo().fifoSetThresholds(t);
	d.pdo().fifoEnable(true);
	bus.run(5ms);
	CHECK(bus.info().intFlags & (1u << 24));
	CHECK_FALSE(bus.chip().int1()); // active low: asserted
	CHECK((bus.info().intFlags & (1u << 25)) == 0);

	SECTION("the RxFIFO low mark: bit 25 when the count falls to it")
	{
		d.pdo().fifoEnable(false);
		ecmxf::FifoThresholds low;
		low.rxLowEnabled = true;
		low.rxLow = 1;
		d.pdo().fifoSetThresholds(low);
		(void)d.pdo().fifoExchange(frames(3), 3, false);
		CHECK((bus.info().intFlags & (1u << 25)) == 0);
		d.pdo().fifoEnable(true);
		bus.run(5ms);
		CHECK(bus.info().intFlags & (1u << 25));
	}
}
