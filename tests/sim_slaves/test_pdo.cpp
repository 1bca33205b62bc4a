// SPDX-License-Identifier: MIT
// PDO configuration through SDO (0x1C12/0x1C13, 0x16xx/0x1Axx): sizes,
// bit-exact packing, abort codes, limits checked at PRE-OP -> SAFE-OP,
// complete access.

#include "helpers.hpp"

using namespace th;
using ecmxf::sim::AlState;

TEST_CASE("PDO remapping via SDO changes outputBytes()/inputBytes() and the packing")
{
	auto s = make("EST-584");
	reach(*s, AlState::PreOp);
	assign(*s, true, { 0x1601 });
	CHECK(s->outputBytes() == 19);
	// 0x1601: controlword, target position, profile velocity, acc, dec, mode
	s->alControl(0x04);
	cycle(*s);
	s->alControl(0x08);
	REQUIRE(s->alStatus() == 0x08);
	Image out(19);
	out.put(0, 0x0006, 2);
	out.put(2, -123456, 4);
	out.put(6, 0x01020304, 4);
	out.put(10, 0x0A0B0C0D, 4);
	out.put(14, 777, 4);
	out.put(18, 3, 1);
	cycle(*s, out.b);
	CHECK(read<std::uint16_t>(*s, 0x6040, 0) == 0x0006);
	CHECK(read<std::int32_t>(*s, 0x607A, 0) == -123456);
	CHECK(read<std::uint32_t>(*s, 0x6081, 0) == 0x01020304);
	CHECK(read<std::uint32_t>(*s, 0x6083, 0) == 0x0A0B0C0D);
	CHECK(read<std::uint32_t>(*s, 0x6084, 0) == 777);
	CHECK(read<std::int8_t>(*s, 0x6060, 0) == 3);
}

TEST_CASE("PDO packing is bit-exact, with gaps, in mapping order, little-endian")
{
	auto s = make("EST-584");
	reach(*s, AlState::PreOp);
	// Rx: controlword 16, gap 4, mode 8, gap 4 = 32 bits
	mapPdo(*s, 0x1601, { 0x60400010, 0x00000004, 0x60600008, 0x00000004 });
	assign(*s, true, { 0x1601 });
	// Tx: statusword 16, gap 3, mode display 8, gap 5 = 32 bits, then 0x1A00
	mapPdo(*s, 0x1A01, { 0x60410010, 0x00000003, 0x60610008, 0x00000005 });
	assign(*s, false, { 0x1A01, 0x1A00 });
	CHECK(s->outputBytes() == 4);
	CHECK(s->inputBytes() == 4 + 17);
	const auto tx = s->txPdos();
	REQUIRE(tx.size() == 2);
	CHECK(tx[0].index == 0x1A01);
	CHECK(tx[1].index == 0x1A00);

	s->alControl(0x04);
	REQUIRE(s->alStatus() == 0x04);
	cycle(*s);
	s->alControl(0x08);
	REQUIRE(s->alStatus() == 0x08);
	// mode 3 at bits 20..27: byte 2 = 0x30; the gap bits are ignored
	std::vector<std::uint8_t> out{ 0x06, 0x00, 0x3F, 0xF0 };
	std::vector<std::uint8_t> in;
	cycle(*s, out, &in);
	CHECK(read<std::uint16_t>(*s, 0x6040, 0) == 0x0006);
	CHECK(read<std::int8_t>(*s, 0x6060, 0) == 3);
	REQUIRE(in.size() == 21);
	// statusword: switch on disabled after shutdown? One cycle: SOD -> RTSO
	const std::uint16_t sw = read<std::uint16_t>(*s, 0x6041, 0);
	CHECK(in[0] == (sw & 0xFF));
	CHECK(in[1] == (sw >> 8));
	// mode display 3 at bits 19..26: byte 2 bits 3..7 = 0b00011, byte 3 bits 0..2 = 0
	CHECK(in[2] == 0x18);
	CHECK(in[3] == 0x00);
	// then 0x1A00 from byte 4: statusword again, mode display, position ...
	CHECK(in[4] == in[0]);
	CHECK(in[6] == 3);
}

TEST_CASE("PDO configuration abort codes")
{
	auto s = make("EST-584");
	reach(*s, AlState::PreOp);
	CHECK(write<std::uint16_t>(*s, 0x1C12, 1, 0x1601) == 0x06010003); // sub 0 != 0
	CHECK(write<std::uint32_t>(*s, 0x1600, 1, 0x60400010) == 0x06010003);
	CHECK(write<std::uint8_t>(*s, 0x1C12, 0, 5) == 0x06090031);       // 4 RxPDOs at most
	CHECK(write<std::uint8_t>(*s, 0x1C13, 0, 3) == 0x06090031);       // 2 TxPDOs
	REQUIRE(write<std::uint8_t>(*s, 0x1C12, 0, 0) == 0);
	CHECK(write<std::uint16_t>(*s, 0x1C12, 1, 0x1A00) == 0x06090030); // a TxPDO
	CHECK(write<std::uint16_t>(*s, 0x1C12, 1, 0x1700) == 0x06090030); // no such PDO
	CHECK(write<std::uint16_t>(*s, 0x1C12, 5, 0x1600) == 0x06090011);
	REQUIRE(write<std::uint16_t>(*s, 0x1C12, 1, 0x1600) == 0);
	REQUIRE(write<std::uint16_t>(*s, 0x1C12, 2, 0x1600) == 0);
	CHECK(write<std::uint8_t>(*s, 0x1C12, 0, 2) == 0x06090030);       // twice the same
	REQUIRE(write<std::uint8_t>(*s, 0x1C12, 0, 1) == 0);
	CHECK(write<std::uint16_t>(*s, 0x1C12, 1, 0x1600) == 0x06010003);
	CHECK(write<std::uint32_t>(*s, 0x1C12, 1, 0x1600) == 0x06070010);

	REQUIRE(write<std::uint8_t>(*s, 0x1A01, 0, 0) == 0);
	CHECK(write<std::uint32_t>(*s, 0x1A01, 1, 0x60400010) == 0x06040041); // Rx-only object
	CHECK(write<std::uint32_t>(*s, 0x1A01, 1, 0x60410020) == 0x06040041); // wrong length
	CHECK(write<std::uint32_t>(*s, 0x1A01, 1, 0x12340010) == 0x06040041); // no object
	CHECK(write<std::uint32_t>(*s, 0x1A01, 1, 0x20010010) == 0x06040041); // not mappable
	CHECK(write<std::uint32_t>(*s, 0x1A01, 9, 0x60410010) == 0x06090011);
	CHECK(write<std::uint8_t>(*s, 0x1A01, 0, 9) == 0x06090031);
	CHECK(write<std::uint8_t>(*s, 0x1A01, 0, 1) == 0x06040041); // entry 1 is empty
	CHECK(write<std::uint16_t>(*s, 0x1A01, 0, 1) == 0x06070010);

	// only in PRE-OP
	s->alControl(0x04);
	REQUIRE(s->alStatus() == 0x04);
	CHECK(write<std::uint8_t>(*s, 0x1C12, 0, 0) == 0x08000022);
	CHECK(write<std::uint8_t>(*s, 0x1600, 0, 0) == 0x08000022);
	CHECK(read<std::uint8_t>(*s, 0x1C12, 0) == 1); // reading is fine
}

TEST_CASE("PDO limits are checked at PRE-OP -> SAFE-OP: 0x0025 outputs, 0x0024 inputs")
{
	{
		auto s = make("EST-584");
		reach(*s, AlState::PreOp);
		assign(*s, true, { 0x1600, 0x1601, 0x1602, 0x1603 }); // 12+19+15+20 = 66 > 64
		CHECK(s->outputBytes() == 66);
		s->alControl(0x04);
		CHECK(s->alStatus() == (0x02 | 0x10));
		CHECK(s->alStatusCode() == 0x0025);
		assign(*s, true, { 0x1601, 0x1602, 0x1603 }); // 54
		s->alControl(0x14);
		CHECK(s->alStatus() == 0x04);
	}
	{
		auto s = make("EST-584");
		reach(*s, AlState::PreOp);
		mapPdo(*s, 0x1A01, { 0x60410010, 0x00000004 }); // 20 bits: not whole bytes
		assign(*s, false, { 0x1A01 });
		s->alControl(0x04);
		CHECK(s->alStatus() == (0x02 | 0x10));
		CHECK(s->alStatusCode() == 0x0024);
	}
	{
		auto s = make("servo");
		reach(*s, AlState::PreOp);
		const std::vector<std::uint32_t> big(8, 0x60640020); // 32 bytes
		mapPdo(*s, 0x1A01, big);
		mapPdo(*s, 0x1A02, big);
		assign(*s, false, { 0x1A00, 0x1A01, 0x1A02 }); // 15 + 32 + 32 = 79 > 64
		s->alControl(0x04);
		CHECK(s->alStatus() == (0x02 | 0x10));
		CHECK(s->alStatusCode() == 0x0024);
	}
}

TEST_CASE("PDO objects by complete access: upload, download, all-or-nothing")
{
	auto s = make("EST-584");
	reach(*s, AlState::PreOp);
	std::vector<std::uint8_t> out;
	REQUIRE(s->sdoUpload(0x1C12, 0, true, out) == 0);
	CHECK(out == std::vector<std::uint8_t>{ 0x01, 0x00, 0x00, 0x16 });
	REQUIRE(s->sdoUpload(0x1600, 1, true, out) == 0);
	CHECK(out.size() == 16);
	CHECK(le32(out, 4) == 0x607A0020);
	REQUIRE(s->sdoUpload(0x1018, 0, true, out) == 0);
	REQUIRE(out.size() == 18);
	CHECK(le32(out, 2) == ecmxf::sim::model::kVendorId);
	CHECK(s->sdoUpload(0x1018, 2, true, out) == 0x06010000);

	const std::vector<std::uint8_t> two{ 0x02, 0x00, 0x01, 0x16, 0x02, 0x16 };
	CHECK(s->sdoDownload(0x1C12, 0, true, two) == 0);
	CHECK(s->outputBytes() == 19 + 15);
	CHECK(read<std::uint16_t>(*s, 0x1C12, 2) == 0x1602);

	const std::vector<std::uint8_t> shortData{ 0x02, 0x00, 0x01, 0x16 };
	CHECK(s->sdoDownload(0x1C12, 0, true, shortData) == 0x06070010);
	const std::vector<std::uint8_t> bad{ 0x02, 0x00, 0x00, 0x16, 0x00, 0x1A };
	CHECK(s->sdoDownload(0x1C12, 0, true, bad) == 0x06090030);
	// unchanged
	CHECK(read<std::uint8_t>(*s, 0x1C12, 0) == 2);
	CHECK(read<std::uint16_t>(*s, 0x1C12, 1) == 0x1601);
	CHECK(s->outputBytes() == 19 + 15);
}

TEST_CASE("WKC: +1 inputs in SAFE-OP and OP, +2 outputs in OP only")
{
	for (const char *type : { "EST-584", "servo", "dio" }) {
		INFO(type);
		auto s = make(type);
		reach(*s, AlState::PreOp);
		CHECK(cycle(*s) == 0);
		s->alControl(0x04);
		CHECK(cycle(*s) == 1);
		s->alControl(0x08);
		CHECK(cycle(*s) == 3);
		CHECK(cycle(*s, {}, nullptr, 1ms, false) == 1);
	}
}
