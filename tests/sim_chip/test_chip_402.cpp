// SPDX-License-Identifier: MIT
// The CiA-402 engine inside the simulated chip: 402_CONFIG_SET,
// 402_STATE_SET/GET, 402_CTL_SET/GET, 402_GET_STATUSWORD. With the engine
// on, the chip owns control word bits 0-3 and 7 and walks the drive to the
// requested state; the state codes are those of the manuals' table.

#include <catch2/catch.hpp>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

struct Drives : Rig {
	static SlaveList make(std::size_t n)
	{
		SlaveList l;
		for (std::size_t i = 0; i < n; i++)
			l.push_back(std::make_unique<TestDrive>());
		return l;
	}
	explicit Drives(std::size_t n = 2) : Rig(make(n)) { toOp(); }

	/// Host outputs (control words and the host's bytes) for every drive.
	void outputs(std::vector<std::uint8_t> bytes)
	{
		REQUIRE_FALSE(host.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x05).payload(bytes)).cmdError());
	}
	Rsp cfg(std::uint8_t motor, std::uint8_t cwOff, std::uint8_t swOff, std::uint8_t ctl,
		std::uint8_t slave)
	{
		return host.cmd(Cmd(ECMXF_CMD_402_CONFIG_SET, motor).d(cwOff, swOff, ctl, slave));
	}
	std::uint8_t state402(std::uint8_t motor)
	{
		const Rsp r = host.cmd(Cmd(ECMXF_CMD_402_STATE_GET, motor));
		REQUIRE_FALSE(r.cmdError());
		return r.h.ret;
	}
	void target(std::uint8_t motor, std::uint8_t st)
	{
		REQUIRE_FALSE(host.cmd(Cmd(ECMXF_CMD_402_STATE_SET, motor).d(st)).cmdError());
	}
};

} // namespace

TEST_CASE("chip: the 402 engine walks a drive to OPERATION ENABLED, owning control word bits 0-3 and 7",
	  "[chip][402]")
{
	Drives d(2);
	// the host's control word has bits 4-6 and 8-14 set, and the drive
	// also gets two bytes the engine must not touch
	d.outputs({ 0x70, 0x7F, 0x12, 0x34, 0x00, 0x00, 0x00, 0x00 });
	d.run(3ms);
	CHECK(d.drive(0).cia == 0x40);
	REQUIRE_FALSE(d.cfg(0, 0, 0, 0x10, 0).cmdError());
	CHECK(d.state402(0) == 0x40);
	d.target(0, 0x27);
	d.run(10ms);
	CHECK(d.drive(0).cia == 0x27);
	CHECK(d.state402(0) == 0x27);
	const Rsp sw = d.host.cmd(Cmd(ECMXF_CMD_402_GET_STATUSWORD, 0));
	REQUIRE(sw.h.len == 2);
	CHECK(sw.u16() == 0x0227);
	// shutdown, switch on, enable operation, with the host's bits kept
	std::vector<std::uint16_t> steps;
	for (std::uint16_t cw : d.drive(0).cwLog) {
		const auto step = static_cast<std::uint16_t>(cw & 0x8F);
		if (steps.empty() || steps.back() != step)
			steps.push_back(step);
	}
	CHECK(steps == std::vector<std::uint16_t>{ 0x00, 0x06, 0x07, 0x0F });
	CHECK(d.drive(0).lastCw == 0x7F7F);
	CHECK(d.drive(0).lastOutputs == std::vector<std::uint8_t>{ 0x7F, 0x7F, 0x12, 0x34 });
	// the other drive is not a configured motor: untouched
	CHECK(d.drive(1).cia == 0x40);
	CHECK(d.host.cmd(Cmd(ECMXF_CMD_402_STATE_GET, 1)).cmdError());
}

TEST_CASE("chip: 402_STATE_SET moves between the switchable states", "[chip][402]")
{
	Drives d(1);
	d.cfg(0, 0, 0, 0x10, 0);
	for (unsigned st : { 0x27u, 0x23u, 0x21u, 0x40u, 0x23u, 0x27u, 0x07u, 0x40u }) {
		INFO("target 0x" << std::hex << int(st));
		d.target(0, static_cast<std::uint8_t>(st));
		d.run(10ms);
		CHECK(d.state402(0) == st);
	}
}

TEST_CASE("chip: the 402 engine resets faults: automatically with bit 7, once with bit 3", "[chip][402]")
{
	Drives d(1);
	d.cfg(0, 0, 0, 0x90, 0); // enable + auto fault reset
	d.target(0, 0x27);
	d.run(10ms);
	REQUIRE(d.state402(0) == 0x27);
	d.drive(0).fault();
	d.run(1ms);
	d.run(10ms);
	CHECK(d.drive(0).faultResetSeen);
	CHECK(d.state402(0) == 0x27); // back to the requested state
	// every fault again
	d.drive(0).faultResetSeen = false;
	d.drive(0).fault();
	d.run(10ms);
	CHECK(d.drive(0).faultResetSeen);

	// single reset: once, then bit 3 reads 0
	REQUIRE_FALSE(d.host.cmd(Cmd(ECMXF_CMD_402_CTL_SET, 0).d(0x18, 0x5A, 1, 0)).cmdError());
	CHECK(d.host.cmd(Cmd(ECMXF_CMD_402_CTL_GET, 0)).h.ret == 0x18);
	d.drive(0).fault();
	d.drive(0).faultResetSeen = false;
	d.run(10ms);
	CHECK(d.drive(0).faultResetSeen);
	CHECK(d.state402(0) == 0x27);
	CHECK(d.host.cmd(Cmd(ECMXF_CMD_402_CTL_GET, 0)).h.ret == 0x10);
	d.drive(0).fault();
	d.drive(0).faultResetSeen = false;
	d.run(10ms);
	CHECK_FALSE(d.drive(0).faultResetSeen);
	CHECK(d.state402(0) == 0x08); // FAULT stays
}

TEST_CASE("chip: with the 402 engine off the host's control word passes unchanged", "[chip][402]")
{
	Drives d(1);
	d.cfg(0, 0, 0, 0x00, 0);
	d.target(0, 0x27);
	d.outputs({ 0x06, 0x00, 0xAA, 0xBB });
	d.run(5ms);
	CHECK(d.drive(0).lastOutputs == std::vector<std::uint8_t>{ 0x06, 0x00, 0xAA, 0xBB });
	CHECK(d.state402(0) == 0x21); // the host's "shutdown" did it
	// enabling the engine takes over
	REQUIRE_FALSE(d.host.cmd(Cmd(ECMXF_CMD_402_CTL_SET, 0).d(0x10, 0x5A, 1, 0)).cmdError());
	d.run(10ms);
	CHECK(d.state402(0) == 0x27);
}

TEST_CASE("chip: 402 commands check motor, offsets, state codes and the 0x5A key", "[chip][402]")
{
	Rig before(Drives::make(1));
	CHECK(before.host.cmd(Cmd(ECMXF_CMD_402_CONFIG_SET, 0).d(0, 0, 0x10, 0)).cmdError());

	Drives d(2);
	Host &h = d.host;
	auto clr = [](Cmd c) { return c.control(ECMXF_CTL_CLR_CMD_ERR); };
	// the slave has 4 output and 4 input bytes
	CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_CONFIG_SET, 0).d(3, 0, 0x10, 0))).cmdError());
	CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_CONFIG_SET, 0).d(0, 3, 0x10, 0))).cmdError());
	CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_CONFIG_SET, 0).d(0, 0, 0x10, 2))).cmdError());
	CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_CONFIG_SET, 200).d(0, 0, 0x10, 0))).cmdError());
	CHECK_FALSE(h.cmd(clr(Cmd(ECMXF_CMD_402_CONFIG_SET, 1).d(2, 2, 0x00, 1))).cmdError());
	// not configured
	// the codes are plain ints in <linux/ecmxf.h>
	for (std::uint8_t code : std::initializer_list<std::uint8_t>{
		     ECMXF_CMD_402_STATE_SET, ECMXF_CMD_402_STATE_GET, ECMXF_CMD_402_CTL_SET, ECMXF_CMD_402_CTL_GET,
		     ECMXF_CMD_402_GET_STATUSWORD }) {
		INFO("code " << int(code));
		CHECK(h.cmd(clr(Cmd(code, 5).d(0x27, 0x5A, 1, 0))).cmdError());
	}
	// not a state one can ask for
	for (unsigned bad : { 0x00u, 0x08u, 0x0Fu, 0x55u })
		CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_STATE_SET, 1).d(static_cast<std::uint8_t>(bad)))).cmdError());
	CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_CTL_SET, 1).d(0x10, 0x5B, 2, 1))).cmdError());
	CHECK(h.cmd(clr(Cmd(ECMXF_CMD_402_CTL_SET, 1).d(0x10, 0x5A, 2, 2))).cmdError());
	CHECK_FALSE(h.cmd(clr(Cmd(ECMXF_CMD_402_CTL_SET, 1).d(0x90, 0x5A, 2, 1))).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_402_CTL_GET, 1)).h.ret == 0x90);
	// motor 1 reads the status word at offset 2 of slave 1's inputs
	d.run(2ms);
	CHECK(h.cmd(Cmd(ECMXF_CMD_402_GET_STATUSWORD, 1)).u16() == 0xA55A);
}
