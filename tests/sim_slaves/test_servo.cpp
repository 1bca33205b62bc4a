// SPDX-License-Identifier: MIT
// The AKD2G-like servo model: DC SYNC0 required for OP, default PDOs,
// CSP/CSV/CST, torque and fault hooks, FoE and BOOT, CiA 301 save/restore.

#include "helpers.hpp"

#include <cmath>
#include <string>

using namespace th;
using ecmxf::sim::AlState;
using ecmxf::sim::Cia402Model;
using ecmxf::sim::ServoModel;

namespace {

constexpr std::uint8_t E = 0x10;

// Default PDOs: 0x1600 controlword 0, target position 2, target velocity 6,
// target torque 10, mode 12; 0x1A00 statusword 0, position 2, velocity 6,
// torque 10, error code 12, mode display 14.
struct ServoRig {
	std::unique_ptr<Slave> s = make("servo");
	ServoModel *m = dynamic_cast<ServoModel *>(s.get());
	Cia402Model *d = dynamic_cast<Cia402Model *>(s.get());
	Image out{ 13 }, in{ 15 };

	explicit ServoRig(std::int8_t mode)
	{
		REQUIRE(m);
		REQUIRE(s->outputBytes() == 13);
		REQUIRE(s->inputBytes() == 15);
		reach(*s, AlState::Op);
		out.put(12, mode, 1);
		for (std::uint16_t cw : kEnable) {
			out.put(0, cw, 2);
			tick();
		}
		REQUIRE((in.u16(0) & 0x6F) == 0x27);
		REQUIRE(static_cast<std::int8_t>(in.get(14, 1)) == mode);
	}
	unsigned tick() { return cycle(*s, out.b, &in.b, 1ms); }
};

} // namespace

TEST_CASE("Servo: OP needs DC SYNC0 with an allowed cycle (0x0030 otherwise)")
{
	auto s = make("servo");
	CHECK(s->dcAssignActivate() == 0x0300);
	s->alControl(0x02);
	s->alControl(0x04); // no SYNC0 yet: P->S is fine
	REQUIRE(s->alStatus() == 0x04);
	cycle(*s);
	s->alControl(0x08);
	CHECK(s->alStatus() == (0x04 | E));
	CHECK(s->alStatusCode() == 0x0030);
	s->configureDc(0x0100, 1'000'000, 0, 0); // cyclic unit only, SYNC0 off
	s->alControl(0x18);
	CHECK(s->alStatus() == (0x04 | E));
	CHECK(s->alStatusCode() == 0x0030);
	dc(*s, 1'000'000);
	s->alControl(0x18);
	CHECK(s->alStatus() == 0x08);
	CHECK(s->escRead8(0x0981) == 0x03);
	CHECK(s->escRead8(0x09A0) == (1'000'000 & 0xFF));

	for (std::uint32_t us : { 125u, 250u, 500u, 1000u, 2000u, 4000u }) {
		INFO(us << " us");
		s->reset();
		dc(*s, us * 1000);
		s->alControl(0x02);
		s->alControl(0x04);
		cycle(*s);
		s->alControl(0x08);
		CHECK(s->alStatus() == 0x08);
	}
	for (std::uint32_t us : { 100u, 750u, 3000u }) {
		INFO(us << " us");
		s->reset();
		dc(*s, us * 1000);
		s->alControl(0x02);
		s->alControl(0x04); // a configured but invalid cycle: refused at P->S
		CHECK(s->alStatus() == (0x02 | E));
		CHECK(s->alStatusCode() == 0x0030);
	}
}

TEST_CASE("Servo: default PDO mapping")
{
	auto s = make("servo");
	reach(*s, AlState::PreOp);
	const std::uint32_t rx[] = { 0x60400010, 0x607A0020, 0x60FF0020, 0x60710010, 0x60600008 };
	const std::uint32_t tx[] = { 0x60410010, 0x60640020, 0x606C0020,
				     0x60770010, 0x603F0010, 0x60610008 };
	CHECK(read<std::uint8_t>(*s, 0x1600, 0) == 5);
	for (std::uint8_t i = 0; i < 5; i++)
		CHECK(read<std::uint32_t>(*s, 0x1600, static_cast<std::uint8_t>(i + 1)) == rx[i]);
	CHECK(read<std::uint8_t>(*s, 0x1A00, 0) == 6);
	for (std::uint8_t i = 0; i < 6; i++)
		CHECK(read<std::uint32_t>(*s, 0x1A00, static_cast<std::uint8_t>(i + 1)) == tx[i]);
	CHECK(read<std::uint32_t>(*s, 0x1000, 0) == 0x00020192);
	CHECK(read<std::uint32_t>(*s, 0x6502, 0) == 0x380); // CSP, CSV, CST
	CHECK(write<std::int8_t>(*s, 0x6060, 0, 1) == 0x06090030);
	CHECK(write<std::int8_t>(*s, 0x6060, 0, 10) == 0);
}

TEST_CASE("Servo CSP follows the target, WKC 3 in OP")
{
	ServoRig r(8);
	for (int i = 1; i <= 50; i++) {
		r.out.put(2, i * 10000, 4);
		CHECK(r.tick() == 3);
		REQUIRE(r.in.i32(2) == i * 10000);
	}
	CHECK(r.in.i32(6) == 10'000'000);
	r.out.put(2, 50 * 10000 + 200000, 4); // beyond the 100000 window
	r.tick();
	CHECK((r.in.u16(0) & 0x6F) == 0x0F);
	CHECK(r.in.u16(12) == 0x8611);
}

TEST_CASE("Servo CSV: velocity follows, position integrates, 0x607F limits")
{
	ServoRig r(9);
	r.out.put(6, 1'000'000, 4);
	for (int i = 0; i < 100; i++)
		r.tick();
	CHECK(r.in.i32(6) == 1'000'000);
	CHECK(r.in.i32(2) == 100'000);
	CHECK((r.in.u16(0) & 0x0800) == 0);
	r.out.put(6, 0x7FFFFFFF, 4);
	r.tick();
	CHECK(r.in.i32(6) == 50 * (1 << 20)); // max profile velocity 50 rev/s
	CHECK((r.in.u16(0) & 0x0800) != 0);   // internal limit active
}

TEST_CASE("Servo CST: torque accelerates the shaft against load and friction, 0x6072 limits")
{
	ServoRig r(10);
	r.out.put(10, 500, 2);
	r.tick();
	CHECK(static_cast<std::int16_t>(r.in.u16(10)) == 500);
	CHECK(r.m->torqueActual() == 500);
	for (int i = 0; i < 2000; i++)
		r.tick();
	// steady state: 500 permille * 200 rev/s^2 per 1000 permille / 4 per s
	const double vss = 500 * 200.0 * (1 << 20) / 1000 / 4;
	CHECK(std::abs(r.in.i32(6) - vss) < vss * 0.01);
	// a load torque equal to the drive torque: decelerates by friction only
	r.m->setLoadTorque(500);
	for (int i = 0; i < 3000; i++)
		r.tick();
	CHECK(std::abs(r.in.i32(6)) < vss * 0.001);
	r.out.put(10, 5000, 2);
	r.tick();
	CHECK(r.m->torqueActual() == 3000); // max torque default
}

TEST_CASE("Servo: injected fault reaches 0x603F, the TxPDO and an emergency")
{
	ServoRig r(8);
	while (r.s->popEmergency()) {
	}
	r.m->injectFault(0x2310);
	r.tick();
	CHECK((r.in.u16(0) & 0x6F) == 0x08);
	CHECK(r.in.u16(12) == 0x2310);
	const auto e = r.s->popEmergency();
	REQUIRE(e);
	CHECK(e->errorCode == 0x2310);
	CHECK(e->errorRegister == 0x03); // generic + current
	CHECK(!r.s->popEmergency());
}

TEST_CASE("Servo FoE: log.txt readable, firmware.bin writable in BOOT only")
{
	auto s = make("servo");
	auto *m = dynamic_cast<ServoModel *>(s.get());
	CHECK(s->hasFoE());
	std::vector<std::uint8_t> buf;
	s->reset();
	CHECK(s->foeRead("log.txt", buf) == 0x08000022); // no mailbox in INIT
	s->alControl(0x02);
	REQUIRE(s->foeRead("log.txt", buf) == 0);
	std::string log(buf.begin(), buf.end());
	CHECK(log.find("power on") != std::string::npos);
	CHECK(log.find("AL INIT -> PREOP") != std::string::npos);
	const std::vector<std::uint8_t> fw{ 1, 2, 3, 4, 5 };
	CHECK(s->foeWrite("firmware.bin", fw) == 0x8008); // bootstrap only
	CHECK(s->foeWrite("log.txt", fw) == 0x8002);
	CHECK(s->foeRead("firmware.bin", buf) == 0x8002);
	CHECK(s->foeRead("nothing.txt", buf) == 0x8001);
	s->alControl(0x01);
	s->alControl(0x03);
	REQUIRE(s->alStatus() == 0x03);
	CHECK(readAbort(*s, 0x1000, 0) == 0x08000022); // no CoE in BOOT
	CHECK(s->foeWrite("firmware.bin", fw) == 0);
	CHECK(m->firmware() == fw);
	REQUIRE(s->foeRead("log.txt", buf) == 0);
	log.assign(buf.begin(), buf.end());
	CHECK(log.find("firmware.bin written (5 bytes)") != std::string::npos);
}

TEST_CASE("Servo: CiA 301 save (0x1010:01) and restore defaults (0x1011:01, at next power-on)")
{
	auto s = make("servo");
	reach(*s, AlState::PreOp);
	REQUIRE(write<std::uint32_t>(*s, 0x6065, 0, 5000) == 0);
	CHECK(write<std::uint32_t>(*s, 0x1010, 1, 0x65766173) == 0);
	CHECK(write<std::uint32_t>(*s, 0x1010, 1, 1) == 0x08000020);
	reach(*s, AlState::PreOp);
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 5000);
	CHECK(write<std::uint32_t>(*s, 0x1011, 1, 0x64616F6C) == 0);
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 5000);
	reach(*s, AlState::PreOp);
	CHECK(read<std::uint32_t>(*s, 0x6065, 0) == 100000);
	// the servo does not clamp: out of range is refused and unchanged
	CHECK(write<std::uint16_t>(*s, 0x6072, 0, 20000) == 0x06090031);
	CHECK(read<std::uint16_t>(*s, 0x6072, 0) == 3000);
}
