// SPDX-License-Identifier: MIT
// The raw paths (Device::command(), Device::transact()), a packet trace,
// and the transport's own evidence that INT0 drove the exchanges, on the
// device of ECMXF_TEST_URI.
//
// Expected values: FW_VERSION_GET (56) answers the version 0x30 as its
// return value and 20 data bytes, bytes 4.. the build id (050); ECAT_SLV_
// CNT_GET (16) returns the slave count; GPIO_FUNC_OP (32) with an undefined
// sub-operation is a command error (error status bit 7, sim-peripherals.rst).

#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/trace/trace.hpp>
#include <ecmxf/chip/chip.hpp>

#include "integration.hpp"

using Catch::Matchers::Contains;
using integ::Rig;

TEST_CASE("raw: command() and transact() of FW_VERSION_GET, SLV_CNT_GET and a refused command", "[raw]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	ecmxf::Command c;
	c.code = 56; // FW_VERSION_GET
	const ecmxf::Response fw = d.command(c);
	CHECK(fw.ret == 0x30);
	CHECK(fw.header.code == 56);
	REQUIRE(fw.data.size() == 20);
	CHECK(std::string(fw.data.begin() + 4, fw.data.begin() + 19) == "ecmxf-simulator");

	integ::initBus(d);
	c = ecmxf::Command{};
	c.code = 16; // ECAT_SLV_CNT_GET
	CHECK(d.command(c).ret == 3);

	ecmxf::RawCommand rc;
	rc.code = 56;
	std::array<std::uint8_t, 1408> rx{};
	ecmxf::ResponseHeader h;
	CHECK(d.transact(rc, {}, rx, h) == 0);
	CHECK(h.ret == 0x30);
	CHECK(h.len == 20);
	CHECK(rx[4] == 'e');
	CHECK(d.pdoDataCapacity() == 112);

	// GPIO_FUNC_OP sub-operation 4 does not exist: a command error, which
	// transact() reports in the header, not as a failure
	rc = ecmxf::RawCommand{};
	rc.code = 32;
	rc.param = 4;
	rc.control = 0x80; // clear an older command error first
	CHECK(d.transact(rc, {}, rx, h) == 0);
	CHECK((h.errStatus & 0x80) == 0x80);
	// and the next command is clean again
	rc = ecmxf::RawCommand{};
	rc.code = 56;
	rc.control = 0x80;
	CHECK(d.transact(rc, {}, rx, h) == 0);
	CHECK((h.errStatus & 0x80) == 0);
}

TEST_CASE("trace: the exchanges of a few commands are recorded and decode", "[raw][trace]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	const std::filesystem::path path =
		std::filesystem::temp_directory_path() / ("ecmxf-integ-trace-" + std::to_string(::getpid()) + ".txt");
	d.startTrace(path.string());
	CHECK(d.tracing());
	CHECK(d.chip().firmwareVersion().version == 0x30);
	CHECK(d.chip().queryDataSize() == 112);
	d.stopTrace();
	CHECK_FALSE(d.tracing());

	std::ifstream in(path);
	REQUIRE(in);
	std::ostringstream out;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(in, out);
	std::filesystem::remove(path);
	// two commands went out and were answered; nothing bad on the link
	CHECK(s.commands >= 2);
	CHECK(s.responses >= 2);
	CHECK(s.bad == 0);
	CHECK_THAT(out.str(), Contains("FW_VERSION_GET"));
	CHECK_THAT(out.str(), Contains("SPI_PACK_SIZE_GET"));
}

TEST_CASE("transport: INT0 drove the exchanges (the transport's own counters)", "[transport]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	ecmxf::Link &link = d.link();
	auto *k = dynamic_cast<ecmxf::KernelLink *>(&link);
	auto *engine = dynamic_cast<ecmxf::EngineLink *>(&link);
	auto *sp = engine ? dynamic_cast<ecmxf::SpidevChannel *>(&engine->channel()) : nullptr;
	const ecmxf::LinkCounters before = link.counters();
	integ::initBus(d); // an async command: the chip is busy for a while
	for (int i = 0; i < 10; i++)
		CHECK(d.chip().firmwareVersion().version == 0x30);
	if (sp) {
		// libgpiod edge events on INT0 ended the waits, none timed out
		const ecmxf::SpidevStats &st = sp->stats();
		INFO("exchanges " << st.exchanges << ", ready " << st.int0Ready << ", edges " << st.int0Edges
				  << ", timeouts " << st.int0Timeouts);
		CHECK(st.exchanges > 10);
		// whether a wait needed an edge or found the line ready depends
		// on how fast the bridge answered (an rt-amd64 run saw 194 of
		// 194 ready at the first look): the edges are reported, not
		// required. So are waits that ended without INT0 (the engine's
		// 10 ms slice): a guest on a loaded host can stall the bridge
		// that long (an rt-amd64 run beside a fuzzer saw 2 of 227), and
		// the engine then just waits again. What INT0 guarantees is
		// checked: every exchange went out on a ready line, none on the
		// no-INT0 fallback.
		WARN("INT0 edges waited for: " << st.int0Edges << " of " << st.exchanges << " exchanges, "
					       << st.int0Timeouts << " waits of 10 ms ended without INT0");
		CHECK(st.fallbackWaits == 0);
		CHECK(st.int0Ready >= st.exchanges);
	} else if (k) {
		// the driver's INT0 interrupt fired and no packet went bad
		const ecmxf::LinkCounters c = link.counters();
		INFO("exchanges " << c.exchanges - before.exchanges << ", INT0 IRQs " << c.int0Irqs - before.int0Irqs);
		CHECK(c.exchanges - before.exchanges > 10);
		// as over spidev: whether INT0 dropped at all (an edge, an
		// interrupt) depends on how fast the bridge's chip was ready
		// again; a debug-kernel guest on a loaded host saw 0 of 187.
		// Reported, not required; no command may have timed out (below)
		WARN("INT0 interrupts: " << c.int0Irqs - before.int0Irqs << " in " << c.exchanges - before.exchanges
					 << " exchanges");
		CHECK(c.badCheck == before.badCheck);
		CHECK(c.badStart == before.badStart);
		CHECK(c.exhausted == before.exhausted);
		CHECK(c.timeouts == before.timeouts);
		const ecmxf::KernelDevInfo info = k->devInfo();
		CHECK(info.dataSize == 112);
		CHECK(info.checkType == 3);
		CHECK(info.fwVersion == 0x30);
	} else {
		// the simulator: no exchange started while the chip said busy
		ecmxf::sim::Chip *sim = link.simulator();
		REQUIRE(sim);
		CHECK(sim->stats().exchanges > 10);
		CHECK(sim->stats().busyExchanges == 0);
		CHECK(sim->stats().badPackets == 0);
		// the engine's own counts: every exchange, none bad
		const ecmxf::LinkCounters c = link.counters();
		CHECK(c.exchanges - before.exchanges == sim->stats().exchanges);
		CHECK(c.badCheck == 0);
		CHECK(c.exhausted == 0);
	}
}
