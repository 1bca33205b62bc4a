// SPDX-License-Identifier: MIT
// monitor's event detection (utils/ecmxf-util-monitor.hpp) as a unit: from
// two response headers to events. Bit names are those of the response
// header table in Documentation/simulator.rst (0x09 error status, 0x0A ECM
// status).

#include <catch2/catch.hpp>

#include <chrono>
#include <string>

#include "ecmxf-util-monitor.hpp"

using ecmxf::ResponseHeader;
using namespace ecmxf_util::monitor;
using namespace std::chrono_literals;

namespace {

ResponseHeader opHeader()
{
	ResponseHeader h;
	h.ecatState = 0x08;
	h.errStatus = 0x03; // link, link at INIT_OP
	h.ecmStatus = 0x18; // Ethernet initialised, PDO configured
	return h;
}

std::string field(const Event &e, const std::string &k)
{
	for (const auto &[key, v] : e.fields)
		if (key == k)
			return v;
	FAIL("no field " << k << " in " << e.type);
	return {};
}

} // namespace

TEST_CASE("monitor events: identical headers give none", "[monitor]")
{
	CHECK(diffHeaders(opHeader(), opHeader(), {}).empty());
	ResponseHeader h = opHeader();
	h.index = 7; // index, code, ret, len, flags are not events
	h.code = 16;
	h.ret = 3;
	h.intFlags = 0x80000000u;
	h.ecmStatus |= 0x80 | 0x01; // busy, check type
	CHECK(diffHeaders(opHeader(), h, {}).empty());
}

TEST_CASE("monitor events: ECAT state change", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.ecatState = 0x10;
	const auto ev = diffHeaders(opHeader(), cur, {});
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "state");
	CHECK(ev[0].text == "ECAT state OP -> ERROR");
	CHECK(field(ev[0], "from") == "8");
	CHECK(field(ev[0], "to") == "16");
	CHECK(field(ev[0], "to_name") == "\"ERROR\"");
}

TEST_CASE("monitor events: error-status bits set and cleared by name", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.errStatus = 0x01 | 0x08 | 0x80; // link kept, link at INIT_OP gone, async + command error
	const auto ev = diffHeaders(opHeader(), cur, {});
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "error_status");
	CHECK(ev[0].text == "error status 0x03 -> 0x89: set async error, command error; cleared link at INIT_OP");
	CHECK(field(ev[0], "set") == R"(["async error", "command error"])");
	CHECK(field(ev[0], "cleared") == R"(["link at INIT_OP"])");
	CHECK(field(ev[0], "value") == "137");
}

TEST_CASE("monitor events: ECM status bits DC stable / PDO configured / FIFO enabled", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.ecmStatus = 0x08 | 0x04 | 0x40; // PDO configured gone; DC stable, FIFO enabled
	const auto ev = diffHeaders(opHeader(), cur, {});
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "ecm_status");
	CHECK(ev[0].text == "ECM status 0x18 -> 0x4c: set DC stable, FIFO enabled; cleared PDO configured");
}

TEST_CASE("monitor events: CRC and WKC counters going up; going down is no event", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.crcErrCnt = 3;
	cur.wkcErrCnt = 12;
	auto ev = diffHeaders(opHeader(), cur, {});
	REQUIRE(ev.size() == 2);
	CHECK(ev[0].type == "crc_errors");
	CHECK(ev[0].text == "SPI CRC errors +3 (count 3)");
	CHECK(ev[1].type == "wkc");
	CHECK(field(ev[1], "increase") == "12");
	CHECK(diffHeaders(cur, opHeader(), {}).empty()); // cleared (CRC_ERR_CNT_CLR, INIT_OP)
}

TEST_CASE("monitor events: FIFO counts crossing their marks, both ways", "[monitor]")
{
	const Thresholds th{ 10, 2 };
	ResponseHeader a = opHeader(), b = opHeader();
	a.txFifoCnt = 9;
	b.txFifoCnt = 10;
	auto ev = diffHeaders(a, b, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "TxFIFO reached its high mark 10 (count 10)");
	CHECK(field(ev[0], "crossing") == "\"above\"");
	ev = diffHeaders(b, a, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "TxFIFO fell below its high mark 10 (count 9)");
	b.txFifoCnt = 20; // above to further above: nothing
	a.txFifoCnt = 10;
	CHECK(diffHeaders(a, b, th).empty());

	ResponseHeader c = opHeader(), d = opHeader();
	c.rxFifoCnt = 3;
	d.rxFifoCnt = 2;
	ev = diffHeaders(c, d, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "RxFIFO fell to its low mark 2 (count 2)");
	CHECK(field(ev[0], "fifo") == "\"rx\"");
	ev = diffHeaders(d, c, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "RxFIFO rose above its low mark 2 (count 3)");
}

TEST_CASE("monitor events: a chip reset is one event, whatever else changed", "[monitor]")
{
	ResponseHeader powerOn; // ECAT state 0, link, FIFO enabled
	powerOn.errStatus = 0x01;
	powerOn.ecmStatus = 0x40;
	auto ev = diffHeaders(opHeader(), powerOn, {});
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "reset");
	CHECK(ev[0].text == "the chip reset (ECAT state NONE, ECM status 0x40)");
	// the NOP bit alone
	ResponseHeader nop = opHeader();
	nop.ecmStatus |= 0x20;
	ev = diffHeaders(opHeader(), nop, {});
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "reset");
	// before INIT_OP (state 0, bit 3 clear) a quiet poll is no reset
	CHECK(diffHeaders(powerOn, powerOn, {}).empty());
}

TEST_CASE("monitor Detector: baseline first, WKC increments in a row are one burst", "[monitor]")
{
	Detector d;
	ResponseHeader h = opHeader();
	CHECK(d.update(h, 0ms).empty()); // baseline
	h.wkcErrCnt = 5;
	auto ev = d.update(h, 10ms);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "wkc_burst");
	CHECK(ev[0].text == "WKC error burst: +5 (count 5)");
	h.wkcErrCnt = 15;
	CHECK(d.update(h, 20ms).empty());
	h.wkcErrCnt = 18;
	CHECK(d.update(h, 30ms).empty());
	ev = d.update(h, 40ms); // no increment: the burst is over
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "wkc_burst_end");
	CHECK(ev[0].text == "WKC error burst over: 18 errors in 30 ms (count 18)");
	CHECK(field(ev[0], "errors") == "18");
	CHECK(field(ev[0], "duration_ms") == "30");
	CHECK(d.update(h, 50ms).empty());
	h.wkcErrCnt = 255;
	ev = d.update(h, 60ms);
	REQUIRE(ev.size() == 1);
	CHECK(field(ev[0], "increase") == "237");
	ev = d.update(h, 70ms);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "WKC error burst over: 237 errors in 10 ms (count 255, saturated)");
	d.rebase();
	h.ecatState = 0x10;
	CHECK(d.update(h, 80ms).empty()); // a baseline again
}

TEST_CASE("monitor: AL status code texts are the library's (AKD2G table, seed 003)", "[monitor]")
{
	// monitor no longer has its own table: it prints ecmxf::alStatusText()
	CHECK(ecmxf::alStatusText(0x0000) == "No error");
	CHECK(ecmxf::alStatusText(0x0011) == "Invalid requested state change");
	CHECK(ecmxf::alStatusText(0x001B) == "Sync manager watchdog");
	CHECK(ecmxf::alStatusText(0x1234) == "unknown AL status code");
}
