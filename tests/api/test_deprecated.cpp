// SPDX-License-Identifier: MIT
//
// The names before "one model for two masters" (Documentation/library.rst,
// "API changes before 0.1.0: one model for two masters")
// still compile and do what the new names do: each deprecated alias is
// called here next to its new name, against the simulator. Only this file
// silences the deprecation warning; everything else in the tree uses the
// new names (the build is -Werror).
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include <ecmxf/ecmxf.hpp>

#pragma GCC diagnostic ignored "-Wdeprecated-declarations"

namespace {

std::unique_ptr<ecmxf::Device> busInOp()
{
	auto dev = ecmxf::Device::open("sim:");
	ecmxf::Master(*dev).bringUp({});
	return dev;
}

} // namespace

TEST_CASE("deprecated Sdo names forward to read/write/upload/download", "[api][deprecated]")
{
	auto dev = busInOp();
	const ecmxf::Sdo sdo = dev->sdo();
	CHECK(sdo.sdoRead<std::uint32_t>(0, 0x1018, 1) == sdo.read<std::uint32_t>(0, 0x1018, 1));
	sdo.sdoWrite<std::uint16_t>(0, 0x2000, 0, 1234);
	CHECK(sdo.read<std::uint16_t>(0, 0x2000, 0) == 1234);
	CHECK(sdo.sdoUpload(0, 0x2000, 0) == sdo.upload(0, 0x2000, 0));
	const std::vector<std::uint8_t> b{ 0x10, 0x09 };
	sdo.sdoDownload(0, 0x2000, 0, b);
	CHECK(sdo.read<std::uint16_t>(0, 0x2000, 0) == 0x0910);
	CHECK(sdo.sdoReadString(0, 0x1008, 0) == sdo.readString(0, 0x1008, 0));
	CHECK_FALSE(sdo.readString(0, 0x1008, 0).empty());
	// the same abort through either name
	const auto code = [&](auto &&f) {
		try {
			f();
		} catch (const ecmxf::SdoError &e) {
			return e.abortCode();
		}
		return std::uint32_t{ 0 };
	};
	const std::uint32_t oldAbort = code([&] { sdo.sdoWriteString(0, 0x1008, 0, "x"); });
	CHECK(oldAbort != 0);
	CHECK(oldAbort == code([&] { sdo.writeString(0, 0x1008, 0, "x"); }));
}

TEST_CASE("deprecated ProcessData names forward to read/write/fifoExchange", "[api][deprecated]")
{
	auto dev = busInOp();
	const ecmxf::ProcessData pdo = dev->pdo();
	CHECK(pdo.pdoSlaveCounts().expectedWkc() == pdo.slaveCounts().expectedWkc());
	dev->link().sleepFor(std::chrono::milliseconds(3));
	CHECK(pdo.pdoWorkingCounter() == pdo.workingCounter());
	const std::vector<std::uint8_t> in = pdo.read();
	CHECK(pdo.pdoRead().size() == in.size());
	const std::vector<std::uint8_t> out(pdo.fifoPackSizes().rxPdoBytes, 0);
	pdo.pdoWrite(out);
	CHECK(pdo.pdoWriteRead(out).size() == in.size());
	const ecmxf::PdoFifoResult r = pdo.pdoFifoExchange(out, 1, true);
	CHECK(r.allWritten);
}

TEST_CASE("deprecated Chip402 names forward to configure/state/awaitState", "[api][deprecated]")
{
	using ecmxf::Cia402State;
	auto dev = busInOp();
	dev->link().sleepFor(std::chrono::milliseconds(5));
	const ecmxf::Chip402 c = dev->chip402();
	const ecmxf::Chip402Flags engine{ true, false, false };
	c.chip402Configure(0, ecmxf::Chip402Config{ 0, 0, 0, engine });
	CHECK(c.chip402Control(0) == c.control(0));
	CHECK(c.chip402State(0).state == c.state(0).state);
	c.chip402SetControl(0, ecmxf::Chip402Control{ engine, 1, 0 });
	c.chip402RequestState(0, Cia402State::OperationEnabled);
	CHECK(c.chip402AwaitState(0, Cia402State::OperationEnabled, std::chrono::milliseconds(100)) ==
	      Cia402State::OperationEnabled);
	CHECK(c.chip402Statusword(0) == c.statusword(0));
}
