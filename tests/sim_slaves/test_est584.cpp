// SPDX-License-Identifier: MIT
// The EST-584 model against its manual (004_...): object dictionary
// defaults, ranges and access, SDO abort codes, parameter save/restore,
// PP/PV/HM/CSP, CSP cycle times, emergencies.

#include "helpers.hpp"

#include <cmath>

using namespace th;
using ecmxf::sim::AlState;
using ecmxf::sim::Cia402Model;
using ecmxf::sim::Est584Model;

namespace {

constexpr std::uint32_t kSave = 0x65766173; // "save", manual 4.1
constexpr std::uint32_t kLoad = 0x64616F6C; // "load", manual 4.2

struct Value {
	std::uint16_t index;
	std::uint8_t sub;
	std::size_t size;
	std::uint64_t value;
};

// Manual 5.4.1 (default PDO mapping) and 5.4.2 (assignment).
const Value kPdoDefaults[] = {
	{ 0x1C12, 0, 1, 1 },          { 0x1C12, 1, 2, 0x1600 },     { 0x1C13, 0, 1, 1 },
	{ 0x1C13, 1, 2, 0x1A00 },     { 0x1600, 0, 1, 4 },          { 0x1600, 1, 4, 0x60400010 },
	{ 0x1600, 2, 4, 0x607A0020 }, { 0x1600, 3, 4, 0x60B00020 }, { 0x1600, 4, 4, 0x60B80010 },
	{ 0x1601, 0, 1, 6 },          { 0x1601, 1, 4, 0x60400010 }, { 0x1601, 2, 4, 0x607A0020 },
	{ 0x1601, 3, 4, 0x60810020 }, { 0x1601, 4, 4, 0x60830020 }, { 0x1601, 5, 4, 0x60840020 },
	{ 0x1601, 6, 4, 0x60600008 }, { 0x1602, 0, 1, 5 },          { 0x1602, 1, 4, 0x60400010 },
	{ 0x1602, 2, 4, 0x60FF0020 }, { 0x1602, 3, 4, 0x60830020 }, { 0x1602, 4, 4, 0x60840020 },
	{ 0x1602, 5, 4, 0x60600008 }, { 0x1603, 0, 1, 7 },          { 0x1603, 1, 4, 0x60400010 },
	{ 0x1603, 2, 4, 0x60980008 }, { 0x1603, 3, 4, 0x60990120 }, { 0x1603, 4, 4, 0x60990220 },
	{ 0x1603, 5, 4, 0x609A0020 }, { 0x1603, 6, 4, 0x607C0020 }, { 0x1603, 7, 4, 0x60600008 },
	{ 0x1A00, 0, 1, 6 },          { 0x1A00, 1, 4, 0x60410010 }, { 0x1A00, 2, 4, 0x60610008 },
	{ 0x1A00, 3, 4, 0x60640020 }, { 0x1A00, 4, 4, 0x60B90010 }, { 0x1A00, 5, 4, 0x60BA0020 },
	{ 0x1A00, 6, 4, 0x60FD0020 }, { 0x1A01, 0, 1, 0 },
};

// Manual 4.3.1 / 3.x: default values.
const Value kParamDefaults[] = {
	{ 0x2000, 0, 2, 3200 }, { 0x2001, 0, 2, 50000 }, { 0x2002, 0, 2, 500 },
	{ 0x2005, 1, 2, 1 },    { 0x2005, 2, 2, 1 },     { 0x2008, 0, 2, 0 },
	{ 0x2009, 0, 2, 0 },    { 0x2010, 2, 2, 1000 },  { 0x2013, 0, 2, 1 },
	{ 0x2015, 0, 2, 1000 }, { 0x2016, 0, 2, 200 },   { 0x2017, 0, 2, 100 },
	{ 0x2020, 0, 2, 1000 }, { 0x2021, 0, 2, 1 },     { 0x2024, 0, 2, 2 },
	{ 0x2025, 0, 2, 5 },    { 0x2026, 0, 2, 50 },    { 0x2029, 0, 2, 1000 },
	{ 0x2030, 0, 2, 1000 }, { 0x2039, 0, 2, 0 },     { 0x2040, 0, 2, 0 },
	{ 0x2051, 0, 2, 0 },    { 0x2053, 0, 2, 0 },     { 0x2056, 0, 2, 0xC3 },
	{ 0x2057, 0, 2, 0 },    { 0x2058, 0, 2, 1 },     { 0x2083, 0, 2, 0 },
	{ 0x2137, 0, 2, 120 },  { 0x2138, 0, 2, 50 },    { 0x2139, 0, 2, 70 },
	{ 0x2140, 0, 2, 60 },   { 0x2150, 0, 2, 1 },     { 0x2151, 0, 2, 0 },
	{ 0x2152, 1, 2, 1 },    { 0x2152, 2, 2, 2 },     { 0x2152, 3, 2, 4 },
	{ 0x2152, 4, 2, 8 },    { 0x2152, 5, 2, 0 },     { 0x2153, 1, 2, 20 },
	{ 0x2153, 2, 2, 20 },   { 0x2153, 3, 2, 20 },    { 0x2153, 4, 2, 20 },
	{ 0x2153, 5, 2, 20 },   { 0x2154, 0, 2, 0 },     { 0x2155, 0, 2, 0 },
	{ 0x1018, 1, 4, ecmxf::sim::model::kVendorId },
	{ 0x1018, 2, 4, ecmxf::sim::model::kEst584Product },
	{ 0x1018, 3, 4, ecmxf::sim::model::kEst584Revision },
	{ 0x1018, 4, 4, 1 }, // serial: position + 1
	{ 0x6502, 0, 4, 0xA5 }, // PP, PV, HM, CSP
};

// Manual 4.3.1: ranges of R/W/S parameters.
struct Range {
	std::uint16_t index;
	std::uint8_t sub;
	std::int64_t min, max;
};
const Range kRanges[] = {
	{ 0x2000, 0, 1, 8400 },    { 0x2001, 0, 200, 51200 }, { 0x2002, 0, 100, 10000 },
	{ 0x2005, 1, 1, 4 },       { 0x2005, 2, 1, 4 },       { 0x2010, 2, 50, 25600 },
	{ 0x2020, 0, 1, 20000 },   { 0x2021, 0, 1, 6000 },    { 0x2024, 0, 0, 2 },
	{ 0x2025, 0, 0, 10 },      { 0x2026, 0, 0, 100 },     { 0x2029, 0, 200, 60000 },
	{ 0x2030, 0, 1, 60000 },   { 0x2058, 0, 0, 10000 },   { 0x2137, 0, 0, 150 },
	{ 0x2138, 0, 0, 150 },     { 0x2139, 0, 0, 150 },     { 0x2140, 0, 0, 150 },
	{ 0x2150, 0, 1, 65535 },   { 0x2151, 0, 0, 2 },       { 0x2152, 1, 0, 32768 },
	{ 0x2153, 3, 1, 60000 },   { 0x2009, 0, 0, 1 },       { 0x2051, 0, 0, 1 },
};

std::uint64_t readN(Slave &s, std::uint16_t idx, std::uint8_t sub, std::size_t n)
{
	std::vector<std::uint8_t> out;
	const std::uint32_t ab = s.sdoUpload(idx, sub, false, out);
	INFO("0x" << std::hex << idx << ":" << unsigned(sub) << " abort 0x" << ab);
	REQUIRE(ab == 0);
	REQUIRE(out.size() == n);
	std::uint64_t v = 0;
	for (std::size_t i = 0; i < n; i++)
		v |= std::uint64_t{ out[i] } << (8 * i);
	return v;
}

std::unique_ptr<Slave> preop(const std::map<std::string, std::string> &opts = {})
{
	auto s = make("EST-584", opts);
	reach(*s, AlState::PreOp);
	return s;
}

} // namespace

TEST_CASE("EST-584: default PDO mapping and assignment are the manual's (5.4.1, 5.4.2)")
{
	auto s = preop();
	for (const Value &v : kPdoDefaults) {
		INFO("0x" << std::hex << v.index << ":" << unsigned(v.sub));
		CHECK(readN(*s, v.index, v.sub, v.size) == v.value);
	}
	CHECK(s->outputBytes() == 12); // 16 + 32 + 32 + 16 bits
	CHECK(s->inputBytes() == 17);  // 16 + 8 + 32 + 16 + 32 + 32 bits
	const auto rx = s->rxPdos();
	REQUIRE(rx.size() == 1);
	CHECK(rx[0].index == 0x1600);
	REQUIRE(rx[0].entries.size() == 4);
	CHECK(rx[0].entries[1].index == 0x607A);
	CHECK(rx[0].entries[1].bits == 32);
}

TEST_CASE("EST-584: parameter defaults and identity (manual 4.3.1)")
{
	auto s = preop();
	for (const Value &v : kParamDefaults) {
		INFO("0x" << std::hex << v.index << ":" << unsigned(v.sub));
		CHECK(readN(*s, v.index, v.sub, v.size) == v.value);
	}
	std::vector<std::uint8_t> name;
	REQUIRE(s->sdoUpload(0x1008, 0, false, name) == 0);
	CHECK(std::string(name.begin(), name.end()) == "EST-584");
	CHECK(read<std::int8_t>(*s, 0x6060, 0) == 8);
	CHECK(read<std::int8_t>(*s, 0x6061, 0) == 8);
}

TEST_CASE("EST-584: out-of-range values are set to the limit and answered 0x06090031/32 (5.3.3)")
{
	auto s = preop();
	for (const Range &r : kRanges) {
		INFO("0x" << std::hex << r.index << ":" << unsigned(r.sub));
		CHECK(write<std::uint16_t>(*s, r.index, r.sub, static_cast<std::uint16_t>(r.max)) == 0);
		CHECK(readN(*s, r.index, r.sub, 2) == static_cast<std::uint64_t>(r.max));
		CHECK(write<std::uint16_t>(*s, r.index, r.sub, static_cast<std::uint16_t>(r.min)) == 0);
		CHECK(readN(*s, r.index, r.sub, 2) == static_cast<std::uint64_t>(r.min));
		if (r.max < 65535) {
			CHECK(write<std::uint16_t>(*s, r.index, r.sub,
						   static_cast<std::uint16_t>(r.max + 1)) == 0x06090031);
			CHECK(readN(*s, r.index, r.sub, 2) == static_cast<std::uint64_t>(r.max));
		}
		if (r.min > 0) {
			CHECK(write<std::uint16_t>(*s, r.index, r.sub,
						   static_cast<std::uint16_t>(r.min - 1)) == 0x06090032);
			CHECK(readN(*s, r.index, r.sub, 2) == static_cast<std::uint64_t>(r.min));
		}
	}
}

TEST_CASE("EST-584: SDO abort codes for access, existence, length and value")
{
	auto s = preop();
	CHECK(write<std::uint16_t>(*s, 0x6041, 0, 0) == 0x06010002);  // statusword RO
	CHECK(write<std::uint16_t>(*s, 0x2155, 0, 1) == 0x06010002);  // input level R
	CHECK(write<std::uint16_t>(*s, 0x2039, 0, 1) == 0x06010002);  // pulse amount H R
	CHECK(write<std::uint32_t>(*s, 0x1018, 1, 1) == 0x06010002);  // identity
	CHECK(write<std::uint32_t>(*s, 0x1234, 0, 1) == 0x06020000);  // no object
	CHECK(readAbort(*s, 0x5FFF, 0) == 0x06020000);
	CHECK(write<std::uint16_t>(*s, 0x2152, 6, 1) == 0x06090011);  // no sub-index
	CHECK(readAbort(*s, 0x6040, 1) == 0x06090011);
	CHECK(write<std::uint16_t>(*s, 0x607A, 0, 1) == 0x06070010);  // 2 bytes to an I32
	CHECK(write<std::uint32_t>(*s, 0x6040, 0, 1) == 0x06070010);  // 4 bytes to a U16
	CHECK(write<std::int8_t>(*s, 0x6060, 0, 2) == 0x06090030);    // no mode 2
	CHECK(write<std::int8_t>(*s, 0x6060, 0, 7) == 0x06090030);
	for (std::int8_t m : std::initializer_list<std::int8_t>{ 1, 3, 6, 8 })
		CHECK(write<std::int8_t>(*s, 0x6060, 0, m) == 0);
	CHECK(write<std::int8_t>(*s, 0x6098, 0, 1) == 0x06090030);    // unsupported homing method
	CHECK(write<std::uint16_t>(*s, 0x2040, 0, 2) == 0x06090030);  // "write 1 to clear"
	CHECK(write<std::uint16_t>(*s, 0x2040, 0, 1) == 0);
	std::vector<std::uint8_t> out;
	CHECK(s->sdoUpload(0x6040, 0, true, out) == 0x06010004);       // complete access on a VAR
	// "When 0x2013 is 1 (enable), this parameter is read only"
	CHECK(write<std::uint16_t>(*s, 0x2015, 0, 500) == 0x06010002);
	CHECK(write<std::uint16_t>(*s, 0x2016, 0, 100) == 0x06010002);
	CHECK(write<std::uint16_t>(*s, 0x2013, 0, 0) == 0);
	CHECK(write<std::uint16_t>(*s, 0x2015, 0, 500) == 0);
	CHECK(read<std::uint16_t>(*s, 0x2015, 0) == 500);
	// no mailbox in INIT
	s->alControl(0x01);
	CHECK(readAbort(*s, 0x6041, 0) == 0x08000022);
}

TEST_CASE("EST-584: 0x1010:04 'save' keeps parameters over power-off, 'load' restores defaults")
{
	auto s = preop();
	REQUIRE(write<std::uint16_t>(*s, 0x2001, 0, 1000) == 0);
	s->reset(); // not saved: lost
	REQUIRE(s->alStatus() == 0x01);
	s->alControl(0x02);
	CHECK(read<std::uint16_t>(*s, 0x2001, 0) == 50000);

	REQUIRE(write<std::uint16_t>(*s, 0x2001, 0, 1000) == 0);
	REQUIRE(write<std::uint16_t>(*s, 0x2030, 0, 300) == 0);
	CHECK(write<std::uint32_t>(*s, 0x1010, 4, kSave) == 0);
	CHECK(read<std::uint32_t>(*s, 0x1010, 4) == 1); // reads what the device can do
	s->reset();
	s->alControl(0x02);
	CHECK(read<std::uint16_t>(*s, 0x2001, 0) == 1000);
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 300); // shares 0x2030

	CHECK(write<std::uint32_t>(*s, 0x1010, 4, kLoad) == 0);
	CHECK(read<std::uint16_t>(*s, 0x2001, 0) == 50000); // at once
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 1000);
	s->reset();
	s->alControl(0x02);
	CHECK(read<std::uint16_t>(*s, 0x2001, 0) == 50000);

	CHECK(write<std::uint32_t>(*s, 0x1010, 4, 0x12345678) == 0x08000020);
}

TEST_CASE("EST-584: 0x6065 and 0x2030 are one following error window")
{
	auto s = preop({ { "following_window", "2000" } });
	CHECK(read<std::uint16_t>(*s, 0x2030, 0) == 2000);
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 2000);
	REQUIRE(write<std::uint32_t>(*s, 0x6065, 0, 500) == 0);
	CHECK(read<std::uint16_t>(*s, 0x2030, 0) == 500);
	REQUIRE(write<std::uint16_t>(*s, 0x2030, 0, 700) == 0);
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 700);
}

TEST_CASE("EST-584: station alias from 0x2150 when 0x2151 = 1 (manual 3.3.3)")
{
	auto s = preop({ { "alias", "5" } });
	CHECK(s->escRead8(0x0012) == 5);
	REQUIRE(write<std::uint16_t>(*s, 0x2150, 0, 0x0133) == 0);
	REQUIRE(write<std::uint16_t>(*s, 0x2151, 0, 1) == 0);
	CHECK(s->escRead8(0x0012) == 5); // "after the power supply restarted"
	REQUIRE(write<std::uint32_t>(*s, 0x1010, 4, kSave) == 0);
	s->reset();
	CHECK(s->escRead8(0x0012) == 0x33);
	CHECK(s->escRead8(0x0013) == 0x01);
}

namespace {

// An EST-584 in OP with RxPDO 0x1601 (PP parameters) and the default TxPDO.
// 0x1601: controlword 0, target 2, profile velocity 6, acceleration 10,
// deceleration 14, mode 18. 0x1A00: statusword 0, mode display 2,
// position 3, probe status 7, probe position 9, digital inputs 13.
struct PpRig {
	std::unique_ptr<Slave> s = make("EST-584");
	Cia402Model *d = dynamic_cast<Cia402Model *>(s.get());
	Image out{ 19 }, in{ 17 };

	PpRig()
	{
		reach(*s, AlState::PreOp);
		assign(*s, true, { 0x1601 });
		REQUIRE(s->outputBytes() == 19);
		s->alControl(0x04);
		REQUIRE(s->alStatus() == 0x04);
		tick();
		s->alControl(0x08);
		REQUIRE(s->alStatus() == 0x08);
		out.put(18, 1, 1); // PP
		out.put(6, 100000, 4);
		out.put(10, 1000000, 4);
		out.put(14, 1000000, 4);
		for (std::uint16_t cw : kEnable) {
			out.put(0, cw, 2);
			tick();
		}
		REQUIRE((sw() & 0x6F) == 0x27);
		REQUIRE(in.get(2, 1) == 1);
	}
	unsigned tick() { return cycle(*s, out.b, &in.b); }
	[[nodiscard]] std::uint16_t sw() const { return in.u16(0); }
	[[nodiscard]] std::int32_t pos() const { return in.i32(3); }
	void cw(std::uint16_t v) { out.put(0, v, 2); }
	void target(std::int32_t t) { out.put(2, t, 4); }
	// Run until target reached; returns the cycles taken.
	int runToTarget(int limit = 20000)
	{
		for (int n = 1; n <= limit; n++) {
			tick();
			if (sw() & 0x0400)
				return n;
		}
		FAIL("target not reached");
		return -1;
	}
};

} // namespace

TEST_CASE("EST-584 PP: set-point handshake, trapezoidal move, target reached")
{
	PpRig r;
	CHECK((r.sw() & 0x0400) != 0);    // bit 10: target reached (nothing to do)
	CHECK((r.sw() & 0x1000) == 0);    // bit 12: no set-point pending
	CHECK((r.sw() & 0x8000) != 0);    // bit 15: can take a new one (EST-584)
	CHECK(r.tick() == 3);             // WKC in OP: outputs + inputs

	r.target(20000);
	r.cw(0x1F); // new set-point
	r.tick();
	CHECK((r.sw() & 0x1000) != 0); // acknowledged
	CHECK((r.sw() & 0x8000) == 0); // bit 15 is the inverse of bit 12
	CHECK((r.sw() & 0x0400) == 0);
	r.cw(0x0F);
	r.tick();
	CHECK((r.sw() & 0x1000) == 0); // handshake completes
	// 20000 at 100000/s with 1e6/s^2 ramps: 0.1 s up, 0.1 s at speed,
	// 0.1 s down = 300 ms (already 2 ms in)
	const int n = r.runToTarget();
	CHECK(n >= 290);
	CHECK(n <= 305);
	CHECK(r.pos() == 20000);
	CHECK(r.d->velocityActual() == 0);

	// relative (bit 6): +5000 from the last target
	r.target(5000);
	r.cw(0x5F);
	r.tick();
	CHECK((r.sw() & 0x1000) != 0);
	r.cw(0x4F);
	r.runToTarget();
	CHECK(r.pos() == 25000);
}

TEST_CASE("EST-584 PP: bit 5 = 0 queues the next set-point, bit 5 = 1 changes at once")
{
	PpRig r;
	r.target(50000);
	r.cw(0x1F);
	r.tick();
	r.cw(0x0F);
	for (int i = 0; i < 50; i++)
		r.tick();
	// second set-point while moving, bit 5 = 0: buffered, ack stays set
	r.target(0);
	r.cw(0x1F);
	r.tick();
	CHECK((r.sw() & 0x1000) != 0);
	r.cw(0x0F);
	r.tick();
	CHECK((r.sw() & 0x1000) != 0); // buffer full: bit 12 stays until it starts
	std::int32_t maxPos = 0;
	int n = 0;
	while (!(r.sw() & 0x0400) && n++ < 5000) {
		r.tick();
		maxPos = std::max(maxPos, r.pos());
	}
	CHECK(maxPos == 50000); // the first move was completed
	CHECK(r.pos() == 0);

	// bit 5 = 1: the new target replaces the running move
	r.target(100000);
	r.cw(0x1F);
	r.tick();
	r.cw(0x0F);
	for (int i = 0; i < 300; i++)
		r.tick();
	REQUIRE(r.pos() > 10000);
	REQUIRE(r.pos() < 60000);
	r.target(60000);
	r.cw(0x3F);
	r.tick();
	CHECK((r.sw() & 0x1000) != 0);
	r.cw(0x2F); // manual: bit 12 clears with 0x2F
	r.tick();
	CHECK((r.sw() & 0x1000) == 0);
	maxPos = 0;
	n = 0;
	while (!(r.sw() & 0x0400) && n++ < 5000) {
		r.tick();
		maxPos = std::max(maxPos, r.pos());
	}
	CHECK(maxPos == 60000);
	CHECK(r.pos() == 60000);
}

TEST_CASE("EST-584 PP: a zero profile parameter sets bit 14 and refuses set-points, halt stops")
{
	PpRig r;
	r.out.put(6, 0, 4); // profile velocity 0
	r.target(1000);
	r.cw(0x1F);
	r.tick();
	CHECK((r.sw() & 0x4000) != 0);
	CHECK((r.sw() & 0x1000) == 0);
	r.cw(0x0F);
	r.tick();
	r.out.put(6, 100000, 4);
	r.tick();
	CHECK((r.sw() & 0x4000) == 0);

	r.target(100000);
	r.cw(0x1F);
	r.tick();
	r.cw(0x0F);
	for (int i = 0; i < 100; i++)
		r.tick();
	r.cw(0x10F); // halt (bit 8)
	for (int i = 0; i < 200; i++)
		r.tick();
	const auto stopped = r.pos();
	CHECK(r.d->velocityActual() == 0);
	CHECK((r.sw() & 0x0400) != 0); // halted: target reached = 1
	CHECK((r.sw() & 0x0100) != 0); // EST-584 bit 8: abnormal stop
	r.tick();
	CHECK(r.pos() == stopped);
	r.cw(0x0F); // continue
	r.runToTarget();
	CHECK(r.pos() == 100000);
}

TEST_CASE("EST-584 PV: ramps to the target velocity and reports velocity reached")
{
	auto s = make("EST-584");
	auto *d = dynamic_cast<Cia402Model *>(s.get());
	reach(*s, AlState::PreOp);
	assign(*s, true, { 0x1602 }); // controlword, target velocity, acc, dec, mode
	REQUIRE(s->outputBytes() == 15);
	s->alControl(0x04);
	Image out(15), in(17);
	cycle(*s, out.b, &in.b);
	s->alControl(0x08);
	REQUIRE(s->alStatus() == 0x08);
	out.put(14, 3, 1); // PV
	out.put(6, 1000000, 4);
	out.put(10, 2000000, 4);
	for (std::uint16_t cw : kEnable) {
		out.put(0, cw, 2);
		cycle(*s, out.b, &in.b);
	}
	REQUIRE(in.get(2, 1) == 3);
	CHECK((in.u16(0) & 0x1000) != 0); // speed 0
	out.put(2, 200000, 4);
	for (int i = 0; i < 100; i++)
		cycle(*s, out.b, &in.b);
	CHECK(d->velocityActual() == 100000); // 1e6/s^2 for 100 ms
	CHECK((in.u16(0) & 0x0400) == 0);
	CHECK((in.u16(0) & 0x1000) == 0);
	for (int i = 0; i < 100; i++)
		cycle(*s, out.b, &in.b);
	CHECK(d->velocityActual() == 200000);
	CHECK(read<std::int32_t>(*s, 0x606C, 0) == 200000);
	CHECK((in.u16(0) & 0x0400) != 0); // velocity reached
	// position integrates: 0.5 * 1e6 * 0.2^2 = 20000 so far
	CHECK(std::abs(in.i32(3) - 20000) <= 200);
	out.put(2, 0, 4);
	for (int i = 0; i < 100; i++)
		cycle(*s, out.b, &in.b);
	CHECK(d->velocityActual() == 0); // 2e6/s^2 down: 100 ms
	CHECK((in.u16(0) & 0x1000) != 0);
}

namespace {

struct HomingRig {
	std::unique_ptr<Slave> s;
	Cia402Model *d;
	Est584Model *e;

	explicit HomingRig(std::map<std::string, std::string> opts = { { "home_switch", "25000" } })
		: s(make("EST-584", opts))
	{
		d = dynamic_cast<Cia402Model *>(s.get());
		e = dynamic_cast<Est584Model *>(s.get());
		REQUIRE(e);
		reach(*s, AlState::PreOp);
		REQUIRE(write<std::int8_t>(*s, 0x6060, 0, 6) == 0);
		REQUIRE(write<std::uint32_t>(*s, 0x6099, 1, 50000) == 0);
		REQUIRE(write<std::uint32_t>(*s, 0x6099, 2, 5000) == 0);
		REQUIRE(write<std::uint32_t>(*s, 0x609A, 0, 500000) == 0);
		REQUIRE(write<std::int32_t>(*s, 0x607C, 0, 100) == 0);
		s->idle(1ms); // transition 1: not ready -> switch on disabled
	}
	void cw(std::uint16_t v) { REQUIRE(write<std::uint16_t>(*s, 0x6040, 0, v) == 0); }
	void enable()
	{
		for (std::uint16_t v : kEnable) {
			cw(v);
			s->idle(1ms);
		}
		REQUIRE((d->statusword() & 0x6F) == 0x27);
		REQUIRE(d->modeDisplay() == 6);
	}
	// Start homing and run until bit 10 (settled); returns the time taken.
	std::chrono::milliseconds home(int limitMs = 60000)
	{
		cw(0x1F);
		s->idle(1ms);
		CHECK((d->statusword() & 0x1400) == 0); // in progress: 10 = 0, 12 = 0
		for (int t = 2; t <= limitMs; t++) {
			s->idle(1ms);
			if (d->statusword() & 0x0400)
				return std::chrono::milliseconds(t);
		}
		FAIL("homing did not settle");
		return {};
	}
};

} // namespace

TEST_CASE("EST-584 HM: method 19 finds the home switch and sets the home offset there")
{
	HomingRig r;
	CHECK(!r.e->homeSwitchActive());
	r.enable();
	CHECK((r.d->statusword() & 0x3400) == 0x0400); // not started: 13/12/10 = 0/0/1
	const auto t = r.home();
	CHECK(t < 2000ms);
	const auto sw = r.d->statusword();
	CHECK((sw & 0x3400) == 0x1400); // attained, reached, no error
	// the edge (shaft 25000) is now position 100; the slow approach overshoots
	// by v^2 / 2a = 5000^2 / 1e6 = 25 at most
	CHECK(r.d->positionActual() >= 100);
	CHECK(r.d->positionActual() <= 130);
	CHECK(r.e->homeSwitchActive());
	CHECK((read<std::uint32_t>(*r.s, 0x60FD, 0) & 0x04) != 0); // home switch input
}

TEST_CASE("EST-584 HM: starting on the switch, method 20, no switch, interruption, method 35")
{
	SECTION("method 19 from above the switch")
	{
		HomingRig r;
		r.d->setPositionActual(40000);
		CHECK(r.e->homeSwitchActive());
		r.enable();
		r.home();
		CHECK((r.d->statusword() & 0x3400) == 0x1400);
		CHECK(r.d->positionActual() >= 100);
		CHECK(r.d->positionActual() <= 130);
	}
	SECTION("method 20 approaches from the switch side")
	{
		HomingRig r;
		REQUIRE(write<std::int8_t>(*r.s, 0x6098, 0, 20) == 0);
		r.enable();
		r.home();
		CHECK((r.d->statusword() & 0x3400) == 0x1400);
		CHECK(r.d->positionActual() <= 100);
		CHECK(r.d->positionActual() >= 70);
	}
	SECTION("without a switch: homing error after 20 revolutions")
	{
		HomingRig r(std::map<std::string, std::string>{});
		r.enable();
		r.home();
		CHECK((r.d->statusword() & 0x3400) == 0x2400); // error, stopped
		CHECK(r.d->positionActual() > 1'000'000);
	}
	SECTION("bit 4 dropped: interrupted")
	{
		HomingRig r;
		r.enable();
		r.cw(0x1F);
		for (int i = 0; i < 100; i++)
			r.s->idle(1ms);
		r.cw(0x0F);
		for (int i = 0; i < 300; i++)
			r.s->idle(1ms);
		CHECK((r.d->statusword() & 0x3400) == 0x0400); // interrupted: 0/0/1
		CHECK(r.d->velocityActual() == 0);
	}
	SECTION("method 35: the current position is home")
	{
		HomingRig r;
		REQUIRE(write<std::int8_t>(*r.s, 0x6098, 0, 35) == 0);
		r.d->setPositionActual(1234);
		r.enable();
		r.cw(0x1F);
		r.s->idle(1ms);
		CHECK((r.d->statusword() & 0x3400) == 0x1400);
		CHECK(r.d->positionActual() == 100);
	}
	SECTION("an unsupported method written through a PDO: homing error")
	{
		HomingRig r;
		// 0x6098 via SDO refuses 1; emulate a PDO write through 0x1603
		REQUIRE(write<std::int8_t>(*r.s, 0x6098, 0, 1) == 0x06090030);
		r.s->alControl(0x04);
		REQUIRE(r.s->alStatus() == 0x04);
		r.s->alControl(0x02);
		assign(*r.s, true, { 0x1603 });
		r.s->alControl(0x04);
		Image out(r.s->outputBytes());
		out.put(0, 0x06, 2);
		out.put(2, 1, 1); // homing method 1
		out.put(3, 50000, 4);
		out.put(7, 5000, 4);
		out.put(11, 500000, 4);
		out.put(19, 6, 1);
		cycle(*r.s, out.b);
		r.s->alControl(0x08);
		REQUIRE(r.s->alStatus() == 0x08);
		for (std::uint16_t v : std::initializer_list<std::uint16_t>{ 0x06, 0x07, 0x0F, 0x1F, 0x1F }) {
			out.put(0, v, 2);
			cycle(*r.s, out.b);
		}
		CHECK((r.d->statusword() & 0x3400) == 0x2400);
	}
}

namespace {

// EST-584 in OP with the default PDOs (0x1600: controlword 0, target 2,
// position offset 6, probe function 10; 0x1A00: statusword 0, mode 2,
// position 3, ...), SYNC0 at 1 ms, CSP enabled at position 0.
struct CspRig {
	std::unique_ptr<Slave> s = make("EST-584");
	Cia402Model *d = dynamic_cast<Cia402Model *>(s.get());
	Image out{ 12 }, in{ 17 };
	CspRig()
	{
		reach(*s, AlState::Init);
		dc(*s, 1'000'000);
		s->alControl(0x02);
		s->alControl(0x04);
		tick();
		s->alControl(0x08);
		REQUIRE(s->alStatus() == 0x08);
		for (std::uint16_t cw : kEnable) {
			out.put(0, cw, 2);
			tick();
		}
		REQUIRE((in.u16(0) & 0x6F) == 0x27);
		REQUIRE(in.get(2, 1) == 8);
	}
	void tick() { cycle(*s, out.b, &in.b, 1ms); }
};

} // namespace

TEST_CASE("EST-584 CSP: follows the target every cycle, position offset added")
{
	CspRig r;
	for (int i = 1; i <= 100; i++) {
		r.out.put(2, i * 2000, 4);
		r.tick();
		REQUIRE(r.in.i32(3) == i * 2000);
	}
	CHECK(r.d->velocityActual() == 2'000'000);
	CHECK((r.in.u16(0) & 0x1000) != 0); // follows the command value
	CHECK((r.in.u16(0) & 0x0800) == 0); // no internal limit
	r.out.put(6, 50, 4);                 // 0x60B0 position offset
	r.tick();
	CHECK(r.in.i32(3) == 200050);
}

TEST_CASE("EST-584 CSP: a following error beyond the window faults with 0x8611 in 0x603F")
{
	// max speed 2,500,000/s: 2500 per 1 ms cycle; window 1000 (0x2030)
	{
		CspRig r;
		r.out.put(2, 3500, 4); // error after the cycle: exactly 1000 = window
		r.tick();
		CHECK(r.in.i32(3) == 2500);
		CHECK((r.in.u16(0) & 0x6F) == 0x27);
		CHECK((r.in.u16(0) & 0x0800) != 0); // bit 11: speed limited
	}
	CspRig r;
	while (r.s->popEmergency()) {
	}
	r.out.put(2, 3501, 4);
	r.tick();
	CHECK((r.in.u16(0) & 0x6F) == 0x0F); // fault reaction active
	CHECK((r.in.u16(0) & 0x2000) != 0);  // bit 13: following error
	int n = 0;
	while ((r.in.u16(0) & 0x6F) != 0x08 && n++ < 5000)
		r.tick();
	CHECK((r.in.u16(0) & 0x6F) == 0x08); // Fault
	CHECK(r.d->errorCode() == 0x8611);
	CHECK(read<std::uint16_t>(*r.s, 0x603F, 0) == 0x8611);
	const auto e = r.s->popEmergency();
	REQUIRE(e);
	CHECK(e->errorCode == 0x8611);
	CHECK(e->errorRegister == 0x21); // generic + device profile specific
	// fault reset (edge), target = actual, enable again
	r.out.put(0, 0x80, 2);
	r.tick();
	CHECK((r.in.u16(0) & 0x6F) == 0x40);
	r.out.put(2, r.in.i32(3), 4);
	for (std::uint16_t cw : kEnable) {
		r.out.put(0, cw, 2);
		r.tick();
	}
	CHECK((r.in.u16(0) & 0x6F) == 0x27);
	CHECK(r.d->errorCode() == 0);
}

TEST_CASE("EST-584: SYNC0 cycles 250/500/750/1000/2000/4000 us are accepted, others refused with 0x0030")
{
	for (std::uint32_t us : { 250u, 500u, 750u, 1000u, 2000u, 4000u }) {
		INFO(us << " us");
		auto s = make("EST-584");
		dc(*s, us * 1000);
		s->alControl(0x02);
		s->alControl(0x04);
		REQUIRE(s->alStatus() == 0x04);
		cycle(*s);
		s->alControl(0x08);
		CHECK(s->alStatus() == 0x08);
	}
	for (std::uint32_t us : { 125u, 300u, 1500u, 8000u }) {
		INFO(us << " us");
		auto s = make("EST-584");
		s->alControl(0x02);
		s->alControl(0x04);
		cycle(*s);
		dc(*s, us * 1000); // configured after P->S
		s->alControl(0x08);
		CHECK(s->alStatus() == (0x04 | 0x10));
		CHECK(s->alStatusCode() == 0x0030);
		// configured before P->S: refused there, P+E
		s->alControl(0x12);
		s->alControl(0x04);
		CHECK(s->alStatus() == (0x02 | 0x10));
		CHECK(s->alStatusCode() == 0x0030);
	}
	// free run (no SYNC0) is fine for the EST-584
	auto s = make("EST-584");
	s->alControl(0x02);
	s->alControl(0x04);
	cycle(*s);
	s->alControl(0x08);
	CHECK(s->alStatus() == 0x08);
	// a bad cycle configured in OP: SAFE-OP+E 0x0030
	dc(*s, 300'000);
	CHECK(s->alStatus() == (0x04 | 0x10));
	CHECK(s->alStatusCode() == 0x0030);
}

TEST_CASE("EST-584: leaving OP switches the power stage off, a watchdog faults with 0x8130")
{
	{
		CspRig r;
		r.s->alControl(0x04);
		CHECK((r.d->statusword() & 0x6F) == 0x40); // switch on disabled
	}
	CspRig r;
	while (r.s->popEmergency()) {
	}
	idle(*r.s, 101ms);
	CHECK(r.s->alStatus() == (0x04 | 0x10));
	CHECK(r.s->alStatusCode() == 0x001B);
	CHECK((r.d->statusword() & 0x6F) == 0x08);
	CHECK(r.d->errorCode() == 0x8130);
	const auto e = r.s->popEmergency();
	REQUIRE(e);
	CHECK(e->errorCode == 0x8130);
}

TEST_CASE("EST-584: options are checked")
{
	CHECK_THROWS_WITH(make("EST-584", { { "colour", "red" } }),
			  Catch::Contains("unknown option 'colour'"));
	CHECK_THROWS_WITH(make("EST-584", { { "alias", "70000" } }),
			  Catch::Contains("option 'alias'"));
	CHECK_THROWS_WITH(make("EST-584", { { "following_window", "0" } }),
			  Catch::Contains("following_window"));
	CHECK_THROWS_WITH(make("EST-584", { { "home_switch", "abc" } }),
			  Catch::Contains("home_switch"));
	auto s = make("EST-584", { { "max_speed", "1000000" }, { "mailbox_latency_us", "2500" },
				   { "name", "axis X" } });
	CHECK(s->mailboxLatency() == 2500us);
	CHECK(s->identity().name == "axis X");
	reach(*s, AlState::PreOp);
	CHECK(read<std::uint32_t>(*s, 0x607F, 0) == 1'000'000);
}
