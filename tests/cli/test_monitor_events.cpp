// SPDX-License-Identifier: MIT
// monitor's events as a unit: response headers through the polled
// detector (ecmxf::EventDetector, the protocol core's rules), and typed
// events - polled or from the kernel - into lines and JSON members. Bit
// names are those of the response header table in
// Documentation/simulator.rst (0x09 error status, 0x0A ECM status).

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <string>

#include <ecmxf/model/types_bus.hpp>

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

/// The events between two headers, described (a fresh detector each time).
std::vector<Event> diff(const ResponseHeader &a, const ResponseHeader &b, Thresholds th = {})
{
	Detector d(th);
	REQUIRE(d.update(a, 0ms).empty()); // baseline
	std::vector<Event> out;
	for (const ecmxf::Event &e : d.update(b, 1ms))
		out.push_back(describe(e));
	return out;
}

} // namespace

TEST_CASE("monitor events: identical headers give none", "[monitor]")
{
	CHECK(diff(opHeader(), opHeader()).empty());
	ResponseHeader h = opHeader();
	h.index = 7; // index, code, ret, len, flags are not events
	h.code = 16;
	h.ret = 3;
	h.intFlags = 0x80000000u;
	h.ecmStatus |= 0x80 | 0x01; // busy, check type
	CHECK(diff(opHeader(), h).empty());
}

TEST_CASE("monitor events: ECAT state change", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.ecatState = 0x10;
	const auto ev = diff(opHeader(), cur);
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
	const auto ev = diff(opHeader(), cur);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "error_status");
	CHECK(ev[0].text == "error status 0x03 -> 0x89: set async error, command error; cleared link at INIT_OP");
	CHECK(field(ev[0], "set") == R"(["async error", "command error"])");
	CHECK(field(ev[0], "cleared") == R"(["link at INIT_OP"])");
	CHECK(field(ev[0], "value") == "137");
}

TEST_CASE("monitor events: link down and up are link events, bit 0 is no error-status event",
	  "[monitor]")
{
	ResponseHeader down = opHeader();
	down.errStatus = 0x02; // link gone, link at INIT_OP kept
	auto ev = diff(opHeader(), down);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "link");
	CHECK(ev[0].text == "EtherCAT link down (error status 0x02)");
	CHECK(field(ev[0], "link_up") == "false");
	ev = diff(down, opHeader());
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "EtherCAT link up (error status 0x03)");

	// the simulator's link loss: state ERROR, both link bits cleared
	down.errStatus = 0x00;
	down.ecatState = 0x10;
	ev = diff(opHeader(), down);
	REQUIRE(ev.size() == 3);
	CHECK(ev[0].type == "state");
	CHECK(ev[1].type == "link");
	CHECK(ev[2].text == "error status 0x03 -> 0x00: cleared link at INIT_OP");
}

TEST_CASE("monitor events: ECM status bits DC stable / PDO configured / FIFO enabled", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.ecmStatus = 0x08 | 0x04 | 0x40; // PDO configured gone; DC stable, FIFO enabled
	const auto ev = diff(opHeader(), cur);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "ecm_status");
	CHECK(ev[0].text == "ECM status 0x18 -> 0x4c: set DC stable, FIFO enabled; cleared PDO configured");
}

TEST_CASE("monitor events: CRC and WKC counters going up, going down is no event", "[monitor]")
{
	ResponseHeader cur = opHeader();
	cur.crcErrCnt = 3;
	cur.wkcErrCnt = 12;
	auto ev = diff(opHeader(), cur);
	REQUIRE(ev.size() == 2);
	CHECK(ev[0].type == "crc_errors");
	CHECK(ev[0].text == "SPI CRC errors +3 (count 3)");
	CHECK(ev[1].type == "wkc_burst");
	CHECK(ev[1].text == "WKC error burst: +12 (count 12)");
	CHECK(field(ev[1], "increase") == "12");
	CHECK(diff(cur, opHeader()).empty()); // cleared (CRC_ERR_CNT_CLR, INIT_OP)
}

TEST_CASE("monitor events: FIFO counts crossing their marks, both ways", "[monitor]")
{
	const Thresholds th{ 10, 2 };
	ResponseHeader a = opHeader(), b = opHeader();
	a.txFifoCnt = 9;
	b.txFifoCnt = 10;
	auto ev = diff(a, b, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "TxFIFO reached its high mark 10 (count 10)");
	CHECK(field(ev[0], "crossing") == "\"above\"");
	ev = diff(b, a, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "TxFIFO fell below its high mark 10 (count 9)");
	b.txFifoCnt = 20; // above to further above: nothing
	a.txFifoCnt = 10;
	CHECK(diff(a, b, th).empty());

	ResponseHeader c = opHeader(), d = opHeader();
	c.rxFifoCnt = 3;
	d.rxFifoCnt = 2;
	ev = diff(c, d, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "RxFIFO fell to its low mark 2 (count 2)");
	CHECK(field(ev[0], "fifo") == "\"rx\"");
	ev = diff(d, c, th);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].text == "RxFIFO rose above its low mark 2 (count 3)");
}

TEST_CASE("monitor events: a chip reset is one event, whatever else changed", "[monitor]")
{
	ResponseHeader powerOn; // ECAT state 0, link, FIFO enabled
	powerOn.errStatus = 0x01;
	powerOn.ecmStatus = 0x40;
	auto ev = diff(opHeader(), powerOn);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "reset");
	CHECK(ev[0].text == "the chip reset (ECAT state NONE, ECM status 0x40)");
	CHECK(field(ev[0], "reason") == "null"); // a poller cannot tell why
	// the NOP bit alone
	ResponseHeader nop = opHeader();
	nop.ecmStatus |= 0x20;
	ev = diff(opHeader(), nop);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == "reset");
	// before INIT_OP (state 0, bit 3 clear) a quiet poll is no reset
	CHECK(diff(powerOn, powerOn).empty());
}

TEST_CASE("monitor Detector: baseline first, WKC increases close together are one burst", "[monitor]")
{
	Detector d({}, 10ms);
	ResponseHeader h = opHeader();
	CHECK(d.update(h, 0ms).empty()); // baseline
	h.wkcErrCnt = 5;
	auto ev = d.update(h, 10ms);
	REQUIRE(ev.size() == 1);
	CHECK(describe(ev[0]).text == "WKC error burst: +5 (count 5)");
	h.wkcErrCnt = 15;
	CHECK(d.update(h, 20ms).empty());
	h.wkcErrCnt = 18;
	CHECK(d.update(h, 30ms).empty());
	CHECK(d.update(h, 39ms).empty()); // quiet for 9 ms: not yet
	ev = d.update(h, 40ms);           // quiet for 10 ms: the burst is over
	REQUIRE(ev.size() == 1);
	const Event end = describe(ev[0]);
	CHECK(end.type == "wkc_burst_end");
	// first to last increase: 10 ms .. 30 ms
	CHECK(end.text == "WKC error burst over: 18 errors in 20 ms (count 18)");
	CHECK(field(end, "errors") == "18");
	CHECK(field(end, "duration_ms") == "20");
	CHECK(d.update(h, 50ms).empty());
	h.wkcErrCnt = 255;
	ev = d.update(h, 60ms);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].increase == 237);
	ev = d.update(h, 70ms);
	REQUIRE(ev.size() == 1);
	CHECK(describe(ev[0]).text == "WKC error burst over: 237 errors in 0 ms (count 255, saturated)");
	// a rebase ends a running burst instead of losing it
	h.wkcErrCnt = 0;
	CHECK(d.update(h, 80ms).empty());
	h.wkcErrCnt = 4;
	REQUIRE(d.update(h, 90ms).size() == 1);
	ev = d.rebase(91ms);
	REQUIRE(ev.size() == 1);
	CHECK(ev[0].type == ecmxf::EventType::WkcBurstEnd);
	CHECK(ev[0].errors == 4);
	h.ecatState = 0x10;
	CHECK(d.update(h, 100ms).empty()); // a baseline again
}

TEST_CASE("monitor: state events with the slaves' states and AL status codes", "[monitor]")
{
	ecmxf::Event e;
	e.type = ecmxf::EventType::State;
	e.oldValue = 0x08;
	e.newValue = 0x12; // PRE-OP + error
	CHECK(wantsSlaves(e));
	e.haveSlaves = true;
	e.slaveCount = 3;
	ecmxf::SlaveAlStatus s0;
	s0.position = 0;
	s0.state = 0x12;
	s0.alStatus = 0x001B;
	ecmxf::SlaveAlStatus s2;
	s2.position = 2;
	s2.state = 0x10; // not answering
	e.slaves = { s0, s2 };
	e.alStatus = 0x001B;
	e.alSlave = 0;
	const Event l = describe(e);
	CHECK(l.text == "ECAT state OP -> 0x12; slave 0: PREOP + error, AL status 0x001b (Sync manager "
			"watchdog); slave 2: not answering");
	CHECK(field(l, "slave_count") == "3");
	CHECK(field(l, "al_status_code") == "27");
	CHECK(field(l, "slaves") ==
	      R"([{"position": 0, "answering": true, "state": 2, "state_name": "PREOP", "error": true, )"
	      R"("al_status_code": 27, "al_status_text": "Sync manager watchdog"}, {"position": 2, )"
	      R"("answering": false, "state": 0, "state_name": "NONE", "error": true, "al_status_code": null, )"
	      R"("al_status_text": null}])");

	e.slavesIncomplete = true;
	CHECK_THAT(describe(e).text, Catch::EndsWith("; (not every slave could be read)"));

	// up is no reason to ask; down without error is
	ecmxf::Event up;
	up.type = ecmxf::EventType::State;
	up.oldValue = 0x04;
	up.newValue = 0x08;
	CHECK_FALSE(wantsSlaves(up));
	up.oldValue = 0x08;
	up.newValue = 0x04;
	CHECK(wantsSlaves(up));
}

TEST_CASE("monitor: the kernel's own events (device, async error, reset reasons, suppressed)",
	  "[monitor][netlink]")
{
	ecmxf::Event d;
	d.type = ecmxf::EventType::Device;
	d.device = "ecmxf0";
	d.seq = 0;
	d.action = ecmxf::DeviceAction::Added;
	d.newValue = 0x08;
	d.errStatus = 0x03;
	Event l = describe(d);
	CHECK(l.type == "device");
	CHECK(l.text == "device ecmxf0 added (ECAT state OP, link up)");
	CHECK(field(l, "device") == "\"ecmxf0\"");
	CHECK(field(l, "seq") == "0");

	ecmxf::Event a;
	a.type = ecmxf::EventType::AsyncError;
	a.device = "ecmxf1";
	a.seq = 7;
	a.suppressed = 3;
	a.cmdCode = 12;
	a.status = -EREMOTEIO;
	a.errStatus = 0x0B;
	l = describe(a);
	CHECK(l.text == "async command ECAT_STATE_SET (12) failed: EREMOTEIO (error status 0x0b) "
			"[3 suppressed before]");
	CHECK(field(l, "status") == std::to_string(-EREMOTEIO));
	CHECK(field(l, "suppressed") == "3");

	ecmxf::Event r;
	r.type = ecmxf::EventType::Reset;
	r.device = "ecmxf0";
	r.resetReason = ecmxf::ResetReason::Warm;
	r.ecmStatus = 0x20;
	l = describe(r);
	CHECK(l.text == "the chip reset (WARM_RESET) (ECAT state NONE, ECM status 0x20)");
	CHECK(field(l, "reason") == "\"warm\"");
	r.resetReason = ecmxf::ResetReason::Link;
	CHECK(describe(r).text == "the link was resynchronised (ECAT state NONE, ECM status 0x20)");

	ecmxf::Event p;
	p.type = ecmxf::EventType::PdoLoss;
	p.device = "ecmxf0";
	p.loss = ecmxf::LossKind::InRingOverrun;
	p.increase = 12;
	p.total = 40;
	l = describe(p);
	CHECK(l.type == "pdo_loss");
	CHECK(l.text == "cyclic path: in_ring_overrun +12 (total 40): input frames dropped: the input ring was full");
	CHECK(field(l, "loss") == "\"in_ring_overrun\"");
	CHECK(field(l, "increase") == "12");
	CHECK(field(l, "total") == "40");
	p.loss = ecmxf::LossKind::RxFifoUnderrun;
	p.increase = 1;
	CHECK(describe(p).text ==
	      "cyclic path: rx_fifo_underrun +1 (total 40): the chip's RxFIFO ran empty: the bus repeated outputs");

	ecmxf::Event u;
	u.type = static_cast<ecmxf::EventType>(99);
	u.device = "ecmxf0";
	CHECK(describe(u).text == "event 99 (unknown to this version)");
}

TEST_CASE("monitor: AL status code texts are the library's (AKD2G table, seed 003)", "[monitor]")
{
	// monitor has no table of its own: it prints ecmxf::alStatusText()
	CHECK(ecmxf::alStatusText(0x0000) == "No error");
	CHECK(ecmxf::alStatusText(0x0011) == "Invalid requested state change");
	CHECK(ecmxf::alStatusText(0x001B) == "Sync manager watchdog");
	CHECK(ecmxf::alStatusText(0x1234) == "unknown AL status code");
}
