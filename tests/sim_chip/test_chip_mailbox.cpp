// SPDX-License-Identifier: MIT
// The acyclic services of the simulated chip: SDO transfers and abort
// codes, PDO configuration through SDO, the slave EEPROM, raw datagrams,
// FoE, CoE emergencies and the receive mailbox.

#include <catch2/catch.hpp>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

/// A rig in PRE-OP with @p n slaves.
struct PreOp : Rig {
	explicit PreOp(std::size_t n = 2, SlaveConfig sc = {}) : Rig(n, sc)
	{
		init();
		state(ECMXF_ECAT_PREOP);
	}
	explicit PreOp(SlaveList l) : Rig(std::move(l))
	{
		init();
		state(ECMXF_ECAT_PREOP);
	}
	std::uint32_t abortCode() { return host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32(); }
	void clearErrors() { host.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(0xF8)); }
};

} // namespace

// ---------------------------------------------------------------------------
// SDO
// ---------------------------------------------------------------------------

TEST_CASE("chip: SDO_REQ read takes the slave's mailbox time, SDO_GET returns the data", "[chip][sdo]")
{
	SlaveConfig sc;
	sc.mbxLatency = 7ms;
	PreOp rig(2, sc);
	const auto t0 = rig.chip->now();
	const Rsp a = rig.host.cmd(sdoReq(1, 1, 0x2000, 0));
	CHECK(a.busy());
	const Rsp done = rig.host.waitIdle(200us);
	CHECK_FALSE(done.asyncError());
	const auto took = rig.chip->now() - t0;
	CHECK(took >= 7ms);
	CHECK(took < 8ms);
	const Rsp g = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET));
	CHECK(g.data == std::vector<std::uint8_t>{ 0x11, 0x22, 0x33, 0x44 });
	const Rsp ab = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET));
	REQUIRE(ab.h.len == 4);
	CHECK(ab.u32() == 0);
}

TEST_CASE("chip: SDO_REQ write sends the data at offset 0x0C to the slave", "[chip][sdo]")
{
	PreOp rig(2);
	const Rsp r = rig.host.async(sdoReq(0, 1, 0x6060, 0, { 0x08 }));
	CHECK_FALSE(r.asyncError());
	REQUIRE(rig.s(1).downloads.size() == 1);
	CHECK(std::get<0>(rig.s(1).downloads[0]) == 0x6060);
	CHECK(std::get<2>(rig.s(1).downloads[0]) == std::vector<std::uint8_t>{ 0x08 });
	CHECK(rig.s(0).downloads.empty());
	// 256 bytes at most, as long as they fit the data section
	rig.host.send(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(400));
	rig.host.dataSize = 400;
	rig.host.repeat();
	std::vector<std::uint8_t> big(256, 0xA5);
	CHECK_FALSE(rig.host.async(sdoReq(0, 0, 0x2002, 1, big)).asyncError());
	CHECK(rig.s(0).od[{ 0x2002, 1 }] == big);
}

TEST_CASE("chip: a failed SDO sets the async error, SDO_ABORTCODE_GET returns the slave's abort code",
	  "[chip][sdo]")
{
	PreOp rig(1);
	Rsp r = rig.host.async(sdoReq(1, 0, 0x7777, 3));
	CHECK(r.asyncError());
	CHECK(rig.abortCode() == sim::abort::NoObject);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET)).h.len == 0);
	rig.clearErrors();
	r = rig.host.async(sdoReq(0, 0, 0x1000, 0, { 1, 2, 3, 4 }));
	CHECK(r.asyncError());
	CHECK(rig.abortCode() == sim::abort::ReadOnly);
	rig.clearErrors();
	// a good one clears the abort code
	CHECK_FALSE(rig.host.async(sdoReq(1, 0, 0x1000, 0)).asyncError());
	CHECK(rig.abortCode() == 0);
}

TEST_CASE("chip: SDO to a slave without CoE or in INIT fails with the chip's abort code", "[chip][sdo]")
{
	SlaveConfig noCoe;
	noCoe.coe = false;
	SlaveList l;
	l.push_back(std::make_unique<TestSlave>());
	l.push_back(std::make_unique<TestSlave>(noCoe));
	Rig rig(std::move(l));
	rig.init();
	// INIT: no mailbox yet
	Rsp r = rig.host.async(sdoReq(1, 0, 0x2000, 0));
	CHECK(r.asyncError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == sim::abort::CannotTransferState);
	rig.state(ECMXF_ECAT_PREOP);
	rig.host.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_ASYNC_ERR));
	r = rig.host.async(sdoReq(1, 1, 0x2000, 0));
	CHECK(r.asyncError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == sim::abort::NoObjectDictionary);
}

TEST_CASE("chip: an SDO slower than its timeout fails with the SDO timeout abort code", "[chip][sdo]")
{
	SlaveConfig slow;
	slow.mbxLatency = 30ms;
	PreOp rig(1, slow);
	const auto t0 = rig.chip->now();
	const Rsp r = rig.host.async(sdoReq(1, 0, 0x2000, 0, {}, 0, 10'000));
	CHECK(r.asyncError());
	CHECK(rig.abortCode() == sim::abort::Timeout);
	CHECK(rig.chip->now() - t0 < 15ms);
	rig.clearErrors();
	CHECK_FALSE(rig.host.async(sdoReq(1, 0, 0x2000, 0, {}, 0, 50'000)).asyncError());
}

TEST_CASE("chip: SDO read data is limited by the length field and the data section", "[chip][sdo]")
{
	PreOp rig(1);
	CHECK_FALSE(rig.host.async(sdoReq(1, 0, 0x2001, 0)).asyncError());
	Rsp g = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET));
	REQUIRE(g.h.len == 112); // 200 bytes read, the data section holds 112
	CHECK(g.data[111] == 111);
	CHECK_FALSE(rig.host.async(sdoReq(1, 0, 0x2001, 0, {}, 10)).asyncError());
	g = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_GET));
	REQUIRE(g.h.len == 10);
	CHECK(g.data[9] == 9);
}

TEST_CASE("chip: SDO_REQ with bad parameters is a command error", "[chip][sdo]")
{
	PreOp rig(2);
	Host &h = rig.host;
	Cmd op2 = sdoReq(1, 0, 0x2000, 0);
	op2.data[0] = 2;
	CHECK(h.cmd(op2).cmdError());
	CHECK(h.cmd(sdoReq(1, 2, 0x2000, 0).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
	CHECK(h.cmd(sdoReq(1, 0, 0x2000, 0, {}, 300).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
	// more write data than the data section holds: 12 + 101 > 112
	Cmd big = sdoReq(0, 0, 0x2000, 0, std::vector<std::uint8_t>(100, 1));
	big.data[6] = 101;
	CHECK(h.cmd(big.control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// PDO configuration
// ---------------------------------------------------------------------------

namespace {

/// PDO_CONFIG_SET data: slave, count, assign index, 3 mappings, 3 object
/// counts, 3 x 8 objects (index << 16 | sub << 8 | bits).
Cmd pdoConfigSet(std::uint8_t slave, std::uint16_t assign,
		 std::vector<std::pair<std::uint16_t, std::vector<std::uint32_t>>> pdos)
{
	std::vector<std::uint8_t> d(112, 0);
	d[0] = slave;
	d[1] = static_cast<std::uint8_t>(pdos.size());
	d[2] = static_cast<std::uint8_t>(assign);
	d[3] = static_cast<std::uint8_t>(assign >> 8);
	for (std::size_t i = 0; i < pdos.size(); i++) {
		d[4 + 2 * i] = static_cast<std::uint8_t>(pdos[i].first);
		d[5 + 2 * i] = static_cast<std::uint8_t>(pdos[i].first >> 8);
		d[0x0A + 2 * i] = static_cast<std::uint8_t>(pdos[i].second.size());
		for (std::size_t j = 0; j < pdos[i].second.size(); j++) {
			const std::uint32_t e = pdos[i].second[j];
			for (std::size_t b = 0; b < 4; b++)
				d[0x10 + 0x20 * i + 4 * j + b] = static_cast<std::uint8_t>(e >> (8 * b));
		}
	}
	return Cmd(ECMXF_CMD_ECAT_PDO_CONFIG_SET).payload(d);
}

} // namespace

TEST_CASE("chip: PDO_CONFIG_SET writes assignment and mapping through SDO in the CoE order",
	  "[chip][sdo][pdo]")
{
	PreOp rig(2);
	const Rsp r = rig.host.async(pdoConfigSet(1, 0x1C12, { { 0x1600, { 0x60400010, 0x607A0020 } },
							     { 0x1601, { 0x60FF0020 } } }));
	CHECK_FALSE(r.asyncError());
	using W = std::tuple<std::uint16_t, std::uint8_t, std::vector<std::uint8_t>>;
	const std::vector<W> expected{
		{ 0x1C12, 0, { 0 } },
		{ 0x1600, 0, { 0 } },
		{ 0x1600, 1, { 0x10, 0x00, 0x40, 0x60 } },
		{ 0x1600, 2, { 0x20, 0x00, 0x7A, 0x60 } },
		{ 0x1600, 0, { 2 } },
		{ 0x1601, 0, { 0 } },
		{ 0x1601, 1, { 0x20, 0x00, 0xFF, 0x60 } },
		{ 0x1601, 0, { 1 } },
		{ 0x1C12, 1, { 0x00, 0x16 } },
		{ 0x1C12, 2, { 0x01, 0x16 } },
		{ 0x1C12, 0, { 2 } },
	};
	CHECK(rig.s(1).downloads == expected);
	// RECONFIG_OP makes the chip use the new size: 16 + 32 + 32 bits
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 4);
	rig.host.async(Cmd(ECMXF_CMD_ECAT_RECONFIG_OP));
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 2 + 10);
}

TEST_CASE("chip: PDO_CONFIG_REQ reads the configuration back for PDO_CONFIG_GET", "[chip][sdo][pdo]")
{
	PreOp rig(1);
	rig.host.async(pdoConfigSet(0, 0x1C13, { { 0x1A00, { 0x60410010, 0x60640020, 0x606C0020 } } }));
	const Rsp r = rig.host.async(Cmd(ECMXF_CMD_ECAT_PDO_CONFIG_REQ).payload({ 0, 0, 0x13, 0x1C }));
	CHECK_FALSE(r.asyncError());
	const Rsp g = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_PDO_CONFIG_GET));
	REQUIRE(g.h.len == 112);
	CHECK(g.data[0] == 0);
	CHECK(g.data[1] == 1);
	CHECK(g.u16(2) == 0x1C13);
	CHECK(g.u16(4) == 0x1A00);
	CHECK(g.u16(0x0A) == 3);
	CHECK(g.u32(0x10) == 0x60410010);
	CHECK(g.u32(0x14) == 0x60640020);
	CHECK(g.u32(0x18) == 0x606C0020);
	CHECK(g.u32(0x1C) == 0);
	// an assignment the slave does not have: abort
	rig.host.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_ASYNC_ERR));
	const Rsp bad = rig.host.async(Cmd(ECMXF_CMD_ECAT_PDO_CONFIG_REQ).payload({ 0, 0, 0x12, 0x1C }));
	CHECK(bad.asyncError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == sim::abort::NoObject);
}

TEST_CASE("chip: PDO_CONFIG_SET allows 3 PDOs of 8 objects at most", "[chip][sdo][pdo]")
{
	PreOp rig(1);
	CHECK(rig.host.cmd(pdoConfigSet(0, 0x1C12, { { 0x1600, {} }, { 0x1601, {} }, { 0x1602, {} },
						     { 0x1603, {} } }))
		      .cmdError());
	CHECK(rig.host.cmd(pdoConfigSet(0, 0x1C12, { { 0x1600, std::vector<std::uint32_t>(9, 0x60400010) } })
				   .control(ECMXF_CTL_CLR_CMD_ERR))
		      .cmdError());
	CHECK(rig.host.cmd(pdoConfigSet(1, 0x1C12, { { 0x1600, { 0x60400010 } } }).control(ECMXF_CTL_CLR_CMD_ERR))
		      .cmdError());
	const Rsp ok = rig.host.async(pdoConfigSet(0, 0x1C12, { { 0x1600, std::vector<std::uint32_t>(8, 0x60400010) } }));
	CHECK_FALSE(ok.asyncError());
}

// ---------------------------------------------------------------------------
// EEPROM
// ---------------------------------------------------------------------------

namespace {

Cmd eeprom(std::uint16_t op, std::uint16_t slave, std::uint16_t addr, std::uint16_t value = 0)
{
	std::vector<std::uint8_t> d;
	append16(d, op);
	append16(d, slave);
	append16(d, addr);
	append16(d, value);
	append32(d, 0);
	return Cmd(ECMXF_CMD_EEPROM_REQ).payload(d);
}

} // namespace

TEST_CASE("chip: EEPROM_REQ reads and writes SII words, EEPROM_GET returns the word and the error code",
	  "[chip][eeprom]")
{
	SlaveConfig sc;
	sc.vendor = 0x12345678;
	Rig rig(2, sc);
	// works before INIT_OP: the ESC's EEPROM interface needs no state
	Rsp r = rig.host.async(eeprom(0, 1, 0x0008));
	CHECK_FALSE(r.asyncError());
	Rsp g = rig.host.cmd(Cmd(ECMXF_CMD_EEPROM_GET));
	CHECK(g.h.ret == 0);
	REQUIRE(g.h.len == 2);
	CHECK(g.u16() == 0x5678);
	r = rig.host.async(eeprom(0, 1, 0x0009));
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_EEPROM_GET)).u16() == 0x1234);
	// write the alias word, read it back; INIT_OP sees it too
	r = rig.host.async(eeprom(1, 1, 0x0004, 0x0777));
	CHECK_FALSE(r.asyncError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_EEPROM_GET)).h.len == 0);
	rig.host.async(eeprom(0, 1, 0x0004));
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_EEPROM_GET)).u16() == 0x0777);
	rig.init();
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 1).d(5)).u16() == 0x0777);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 0).d(5)).u16() == 0);
	// beyond the EEPROM: async error, error code in the return value
	r = rig.host.async(eeprom(0, 0, 0x7000));
	CHECK(r.asyncError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_EEPROM_GET)).h.ret == 1);
	CHECK(rig.host.cmd(eeprom(2, 0, 0)).cmdError());
	CHECK(rig.host.cmd(eeprom(0, 2, 0).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// raw datagrams
// ---------------------------------------------------------------------------

namespace {

Cmd raw(std::uint8_t op, std::uint16_t adp, std::uint16_t ado, std::vector<std::uint8_t> data,
	std::uint16_t n = 0)
{
	std::vector<std::uint8_t> d{ op, 0 };
	append16(d, n ? n : static_cast<std::uint16_t>(data.size()));
	append16(d, adp);
	append16(d, ado);
	append32(d, 0);	     // logical address
	append32(d, 10'000); // timeout
	append32(d, 0);	     // reserved
	d.insert(d.end(), data.begin(), data.end());
	return Cmd(ECMXF_CMD_RAW_ECAT_FUNC_REQ).payload(d);
}

struct RawResult {
	std::uint16_t wkc;
	std::vector<std::uint8_t> data;
};

RawResult rawRun(Rig &rig, Cmd c)
{
	const Rsp r = rig.host.async(std::move(c));
	REQUIRE_FALSE(r.asyncError());
	const Rsp g = rig.host.cmd(Cmd(ECMXF_CMD_RAW_ECAT_FUNC_GET));
	REQUIRE(g.h.len >= 20);
	return { g.u16(16), std::vector<std::uint8_t>(g.data.begin() + 20, g.data.end()) };
}

} // namespace

TEST_CASE("chip: RAW_ECAT_FUNC_REQ runs datagrams against the slaves' registers, with a WKC",
	  "[chip][raw]")
{
	Rig rig(3);
	rig.init();
	rig.s(1).regs[0x0110] = 0x35; // DL status
	// APRD slave 1 (ADP = -1): DL status
	RawResult r = rawRun(rig, raw(1, 0xFFFF, 0x0110, { 0, 0 }));
	CHECK(r.wkc == 1);
	CHECK(r.data == std::vector<std::uint8_t>{ 0x35, 0x00 });
	// FPRD by station address: AL status of slave 2
	r = rawRun(rig, raw(4, 0x1003, 0x0130, { 0, 0 }));
	CHECK(r.wkc == 1);
	CHECK(r.data[0] == ECMXF_ECAT_INIT);
	// FPWR AL control PRE-OP to slave 0
	r = rawRun(rig, raw(5, 0x1001, 0x0120, { 0x02, 0x00 }));
	CHECK(r.wkc == 1);
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP);
	CHECK(rig.s(1).state == ECMXF_ECAT_INIT);
	// BRD: OR of all slaves' AL status, WKC = slave count
	r = rawRun(rig, raw(7, 0, 0x0130, { 0 }));
	CHECK(r.wkc == 3);
	CHECK(r.data[0] == (ECMXF_ECAT_INIT | ECMXF_ECAT_PREOP));
	// BWR a register to everyone
	r = rawRun(rig, raw(8, 0, 0x0F00, { 0xAA }));
	CHECK(r.wkc == 3);
	CHECK(rig.s(2).regs[0x0F00] == 0xAA);
	// APWR station address of slave 2, then FPRD at the new address
	r = rawRun(rig, raw(2, 0xFFFE, 0x0010, { 0x34, 0x12 }));
	CHECK(r.wkc == 1);
	r = rawRun(rig, raw(4, 0x1234, 0x0F00, { 0 }));
	CHECK(r.wkc == 1);
	CHECK(r.data[0] == 0xAA);
	// FRMW: read slave 0's register, write it to the others
	rig.s(0).regs[0x0910] = 0x42;
	r = rawRun(rig, raw(14, 0x1001, 0x0910, { 0 }));
	CHECK(r.wkc == 3);
	CHECK(rig.s(2).regs[0x0910] == 0x42);
	// nobody at that address / no FMMU for logical datagrams
	CHECK(rawRun(rig, raw(4, 0x5555, 0x0130, { 0 })).wkc == 0);
	CHECK(rawRun(rig, raw(10, 0, 0, { 0, 0 })).wkc == 0);
	// the GET answer echoes the request header
	const Rsp g = rig.host.cmd(Cmd(ECMXF_CMD_RAW_ECAT_FUNC_GET));
	CHECK(g.data[0] == 10);
	CHECK(g.u16(2) == 2);
	CHECK(g.u32(12) == 10'000);
	CHECK(g.h.len == 22);
}

TEST_CASE("chip: RAW_ECAT_FUNC_REQ with an unknown op or more than 256 bytes is a command error",
	  "[chip][raw]")
{
	Rig rig(1);
	CHECK(rig.host.cmd(raw(3, 0, 0, { 0 })).cmdError());
	CHECK(rig.host.cmd(raw(1, 0, 0, { 0 }, 300).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
	CHECK(rig.host.cmd(raw(1, 0, 0, { 0 }, 100).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// FoE
// ---------------------------------------------------------------------------

namespace {

Cmd foe(std::uint8_t slave, std::uint8_t op, std::uint32_t len, std::uint32_t addr,
	std::vector<std::uint8_t> tail)
{
	std::vector<std::uint8_t> d{ slave, 0, op, 0 };
	append32(d, 0); // password
	append32(d, len);
	append32(d, 0); // timeout
	append32(d, addr);
	d.insert(d.end(), tail.begin(), tail.end());
	return Cmd(ECMXF_CMD_FOE_FUNC_REQ).payload(d);
}

std::vector<std::uint8_t> bytesOf(const std::string &s)
{
	return std::vector<std::uint8_t>(s.begin(), s.end());
}

} // namespace

TEST_CASE("chip: FOE_FUNC_REQ moves files between the slave and the chip's flash", "[chip][foe]")
{
	SlaveConfig sc;
	sc.foe = true;
	PreOp rig(1, sc);
	Host &h = rig.host;
	// write 5 bytes into the flash at 0x100, read them back
	CHECK_FALSE(h.async(foe(0, 4, 5, 0x100, { 1, 2, 3, 4, 5 })).asyncError());
	CHECK_FALSE(h.async(foe(0, 3, 5, 0x100, {})).asyncError());
	const Rsp rd = h.cmd(Cmd(ECMXF_CMD_FOE_FUNC_GET));
	CHECK(rd.data == std::vector<std::uint8_t>{ 1, 2, 3, 4, 5 });
	// download flash[0x100..0x105) as "fw.bin"
	CHECK_FALSE(h.async(foe(0, 2, 5, 0x100, bytesOf("fw.bin"))).asyncError());
	CHECK(rig.s(0).files["fw.bin"] == std::vector<std::uint8_t>{ 1, 2, 3, 4, 5 });
	// upload "cfg" into the flash at 0x2000
	rig.s(0).files["cfg"] = { 9, 8, 7 };
	CHECK_FALSE(h.async(foe(0, 1, 0, 0x2000, bytesOf("cfg"))).asyncError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_FOE_FUNC_GET)).u32() == 3);
	h.async(foe(0, 3, 3, 0x2000, {}));
	CHECK(h.cmd(Cmd(ECMXF_CMD_FOE_FUNC_GET)).data == std::vector<std::uint8_t>{ 9, 8, 7 });
	// a file the slave does not have: the FoE error code
	const Rsp missing = h.async(foe(0, 1, 0, 0, bytesOf("nope")));
	CHECK(missing.asyncError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == 0x8001);
	// outside the 256 KiB flash, or an unknown op
	CHECK(h.cmd(foe(0, 3, 16, 0x40000, {})).cmdError());
	CHECK(h.cmd(foe(0, 5, 0, 0, {}).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

TEST_CASE("chip: FoE to a slave without FoE fails", "[chip][foe]")
{
	PreOp rig(1);
	const Rsp r = rig.host.async(foe(0, 2, 4, 0, bytesOf("x")));
	CHECK(r.asyncError());
}

// ---------------------------------------------------------------------------
// emergencies, receive mailbox
// ---------------------------------------------------------------------------

TEST_CASE("chip: COE_EMERGENCY lists the latest emergencies, newest first", "[chip][mbx]")
{
	PreOp rig(3);
	Host &h = rig.host;
	Rsp r = h.cmd(Cmd(ECMXF_CMD_COE_EMERGENCY, 2));
	REQUIRE(r.h.len == 24);
	CHECK(r.data[0] == 0xFF);
	CHECK(r.data[12] == 0xFF);
	sim::Emergency e1{ 0x8611, 0x81, { 1, 2, 3, 4, 5 } };
	sim::Emergency e2{ 0x3210, 0x05, { 9, 0, 0, 0, 7 } };
	rig.s(2).emergencies.push_back(e1);
	rig.run(3ms);
	rig.s(0).emergencies.push_back(e2);
	rig.run(3ms);
	r = h.cmd(Cmd(ECMXF_CMD_COE_EMERGENCY, 3));
	REQUIRE(r.h.len == 36);
	// entry 0: the newest (slave 0)
	CHECK(r.data[0] == 0);
	CHECK(r.data[1] == 0);
	CHECK(r.u16(2) == 2); // the second one since the chip started
	CHECK(r.u16(4) == 0x3210);
	CHECK(r.data[6] == 0x05);
	CHECK(r.data[7] == 9);
	CHECK(r.data[11] == 7);
	// entry 1: slave 2's
	CHECK(r.data[12] == 1);
	CHECK(r.data[13] == 2);
	CHECK(r.u16(14) == 1);
	CHECK(r.u16(16) == 0x8611);
	CHECK(r.data[18] == 0x81);
	CHECK(r.data[19] == 1);
	CHECK(r.data[23] == 5);
	CHECK(r.data[24] == 0xFF);
	CHECK(h.cmd(Cmd(ECMXF_CMD_COE_EMERGENCY, 0)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_COE_EMERGENCY, 9).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

TEST_CASE("chip: MBX_STAT and RECV_MAILBOX read a slave's mailbox the master does not poll", "[chip][mbx]")
{
	PreOp rig(10);
	Host &h = rig.host;
	// polling: on for every CoE slave by default
	Rsp p = h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 2));
	REQUIRE(p.h.len == 2);
	CHECK(p.data == std::vector<std::uint8_t>{ 0xFF, 0x03 });
	// switch polling off for slaves 1 and 9: from the next RECONFIG_OP on
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 1).payload({ 0xFD, 0x01 })).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 2)).data == std::vector<std::uint8_t>{ 0xFF, 0x03 });
	h.async(Cmd(ECMXF_CMD_ECAT_RECONFIG_OP));
	CHECK(h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 2)).data == std::vector<std::uint8_t>{ 0xFD, 0x01 });

	rig.s(9).emergencies.push_back(sim::Emergency{ 0xFF01, 0x80, { 0xA, 0xB, 0xC, 0xD, 0xE } });
	rig.run(3ms);
	Rsp st = h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 0));
	REQUIRE(st.h.len == 2);
	CHECK(st.data == std::vector<std::uint8_t>{ 0x00, 0x02 });
	// not polled: not in the emergency list yet
	CHECK(h.cmd(Cmd(ECMXF_CMD_COE_EMERGENCY, 1)).data[0] == 0xFF);
	// request the mailbox of slave 9, then read 16 bytes from offset 0
	const Rsp a = h.cmd(Cmd(ECMXF_CMD_RECV_MAILBOX, 0).d(9));
	CHECK(a.busy());
	CHECK_FALSE(h.waitIdle().asyncError());
	const Rsp m = h.cmd(Cmd(ECMXF_CMD_RECV_MAILBOX, 1).d(0, 0, 16, 0));
	REQUIRE(m.h.len == 16);
	CHECK(m.u16(0) == 10);	 // mailbox length
	CHECK(m.data[5] == 0x03); // CoE
	CHECK(m.u16(6) == 0x1000); // emergency service
	CHECK(m.u16(8) == 0xFF01);
	CHECK(m.data[10] == 0x80);
	CHECK(m.data[11] == 0xA);
	CHECK(m.data[15] == 0xE);
	// offset 8, 2 bytes: the error code
	const Rsp part = h.cmd(Cmd(ECMXF_CMD_RECV_MAILBOX, 1).d(8, 0, 2, 0));
	CHECK(part.data == std::vector<std::uint8_t>{ 0x01, 0xFF });
	// read out: the flag clears, and the master logged it
	CHECK(h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 0)).data == std::vector<std::uint8_t>{ 0, 0 });
	const Rsp e = h.cmd(Cmd(ECMXF_CMD_COE_EMERGENCY, 1));
	CHECK(e.data[1] == 9);
	CHECK(e.u16(4) == 0xFF01);
	CHECK(h.cmd(Cmd(ECMXF_CMD_RECV_MAILBOX, 2)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_MBX_STAT, 3).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}
