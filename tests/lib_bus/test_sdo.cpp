// SPDX-License-Identifier: MIT
// SDO through Device: typed uploads and downloads against the EST-584
// model (values from its manual, seed 004) and the chip tests' TestSlave
// (64-bit, real, octet-string and long objects), and every failure a user
// can meet: real aborts from the slave model, a forced abort, a timeout,
// sizes beyond the chip's limit, complete access, bad arguments.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/model/types_bus.hpp>

#include "rig.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxf::Error;
using ecmxf::SdoError;
using ecmxf::SdoOptions;
using ecmxf::State;
using bustest::Rig;

TEST_CASE("sdo: abort texts are the ETG table of manual ver. 050", "[sdo]")
{
	CHECK(ecmxf::sdoAbortText(0x06020000) == "Object not existing");
	CHECK(ecmxf::sdoAbortText(0x06010002) == "Read only entry");
	CHECK(ecmxf::sdoAbortText(0x05040000) == "SDO timeout");
	CHECK(ecmxf::sdoAbortText(0x06090031) == "Value is too great");
	CHECK(ecmxf::sdoAbortText(0x08000023) == "Object is not in the object dictionary");
	CHECK(ecmxf::sdoAbortText(0x06010004) == "The object can not be accessed via complete access");
	CHECK(ecmxf::sdoAbortText(0x12345678) == "unknown abort code");
}

TEST_CASE("sdo: typed uploads from the EST-584 give its manual's values", "[sdo]")
{
	Rig r;
	r.preOp();
	auto &d = r.d();
	// sim-slaves.rst identities; 0x2001 default 50000 (manual 3.5)
	CHECK(d.sdo().read<std::uint32_t>(0, 0x1000, 0) == 0x00030192u);
	CHECK(d.sdo().read<std::uint32_t>(1, 0x1018, 1) == 0x00000E5Cu);
	CHECK(d.sdo().read<std::uint32_t>(1, 0x1018, 2) == 0x00000584u);
	CHECK(d.sdo().read<std::uint16_t>(0, 0x2001, 0) == 50000);
	CHECK(d.sdo().read<std::uint16_t>(0, 0x2030, 0) == 1000); // position following error (4.3.1)
	// 5.4.2: 0x1C12:00 / 0x1C13:00 one PDO each, 0x1600 / 0x1A00
	CHECK(d.sdo().read<std::uint8_t>(0, 0x1C12, 0) == 1);
	CHECK(d.sdo().read<std::uint16_t>(0, 0x1C12, 1) == 0x1600);
	CHECK(d.sdo().read<std::uint16_t>(0, 0x1C13, 1) == 0x1A00);
	// 5.4.1: RXPDO1 entry 2 = 0x607A0020
	CHECK(d.sdo().read<std::uint32_t>(0, 0x1600, 2) == 0x607A0020u);
	CHECK(d.sdo().readString(0, 0x1008, 0) == "EST-584");
	const std::vector<std::uint8_t> raw = d.sdo().upload(0, 0x1000, 0);
	CHECK(raw == std::vector<std::uint8_t>{ 0x92, 0x01, 0x03, 0x00 });
}

TEST_CASE("sdo: typed downloads to the EST-584 read back", "[sdo]")
{
	Rig r;
	r.preOp();
	auto &d = r.d();
	d.sdo().write<std::uint16_t>(1, 0x2001, 0, 10000);
	CHECK(d.sdo().read<std::uint16_t>(1, 0x2001, 0) == 10000);
	CHECK(d.sdo().read<std::uint16_t>(0, 0x2001, 0) == 50000); // the other drive untouched
	d.sdo().write<std::int8_t>(0, 0x6060, 0, 8);                // CSP
	CHECK(d.sdo().read<std::int8_t>(0, 0x6060, 0) == 8);
	d.sdo().write<std::int32_t>(0, 0x607A, 0, -123456);
	CHECK(d.sdo().read<std::int32_t>(0, 0x607A, 0) == -123456);
	CHECK(d.sdo().read<std::uint32_t>(0, 0x607A, 0) == 0xFFFE1DC0u); // two's complement of 123456 = 0x1E240
	// a float is 4 bytes on the bus: 1.5f = 0x3FC00000 (IEEE 754)
	d.sdo().write<float>(0, 0x607A, 0, 1.5f);
	CHECK(d.sdo().read<std::uint32_t>(0, 0x607A, 0) == 0x3FC00000u);
	CHECK(d.sdo().read<float>(0, 0x607A, 0) == 1.5f);
	d.sdo().write<std::uint32_t>(0, 0x6081, 0, 200000);
	CHECK(d.sdo().read<std::int32_t>(0, 0x6081, 0) == 200000);
}

TEST_CASE("sdo: 64-bit, double, octet strings and 256-byte objects (TestSlave)", "[sdo]")
{
	Rig r(bustest::testSlaves(2));
	r.preOp();
	auto &d = r.d();
	auto &s = r.test(1);

	d.sdo().write<std::uint64_t>(1, 0x3000, 0, 0x0102030405060708ull);
	CHECK(s.od[{ 0x3000, 0 }] == std::vector<std::uint8_t>{ 8, 7, 6, 5, 4, 3, 2, 1 });
	CHECK(d.sdo().read<std::uint64_t>(1, 0x3000, 0) == 0x0102030405060708ull);
	d.sdo().write<std::int64_t>(1, 0x3001, 0, -2);
	// -2 is FE FF .. FF little-endian
	CHECK(s.od[{ 0x3001, 0 }] == std::vector<std::uint8_t>{ 0xFE, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF });
	CHECK(d.sdo().read<std::int64_t>(1, 0x3001, 0) == -2);
	// 1.0 = 0x3FF0000000000000
	d.sdo().write<double>(1, 0x3002, 0, 1.0);
	CHECK(s.od[{ 0x3002, 0 }] == std::vector<std::uint8_t>{ 0, 0, 0, 0, 0, 0, 0xF0, 0x3F });
	CHECK(d.sdo().read<double>(1, 0x3002, 0) == 1.0);
	d.sdo().write<std::int16_t>(1, 0x3003, 0, -300); // 0xFED4
	CHECK(s.od[{ 0x3003, 0 }] == std::vector<std::uint8_t>{ 0xD4, 0xFE });
	CHECK(d.sdo().read<std::int16_t>(1, 0x3003, 0) == -300);

	const std::vector<std::uint8_t> octets{ 0xDE, 0xAD, 0x00, 0xBE, 0xEF };
	d.sdo().download(1, 0x3004, 0, octets);
	CHECK(s.od[{ 0x3004, 0 }] == octets);
	CHECK(d.sdo().upload(1, 0x3004, 0) == octets);

	d.sdo().writeString(1, 0x3005, 0, "hello");
	CHECK(d.sdo().readString(1, 0x3005, 0) == "hello");
	s.od[{ 0x3006, 0 }] = { 'a', 'b', 0, 0 }; // NUL padded visible string
	CHECK(d.sdo().readString(1, 0x3006, 0) == "ab");

	// the TestSlave's 200-byte object 0x2001 does not fit the 112-byte
	// data section: a clear error, not 112 silent bytes
	try {
		(void)d.sdo().upload(1, 0x2001, 0);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EMSGSIZE);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 1: the answer fills the whole data section "
					    "(112 bytes), the object may be longer; enlarge the data section "
					    "(SPI_RECONFIG_OP) or pass SdoOptions::length"));
	}
	// a download of 101 bytes needs a 113-byte data section
	const std::vector<std::uint8_t> big(101, 0x5A);
	try {
		d.sdo().download(1, 0x3007, 0, big);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EMSGSIZE);
		CHECK_THAT(e.what(), Contains("SDO download 0x3007:00 to slave 1: ECAT_SDO_REQ: payload of 113 bytes "
					      "does not fit the data section (112 bytes)"));
	}
	// 100 bytes fit
	const std::vector<std::uint8_t> fits(100, 0xA5);
	d.sdo().download(1, 0x3007, 0, fits);
	CHECK(s.od[{ 0x3007, 0 }] == fits);
	SdoOptions o;
	o.length = 100;
	CHECK(d.sdo().upload(1, 0x3007, 0, o) == fits);
}

TEST_CASE("sdo: more than 256 bytes is refused naming the chip's limit", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	const std::vector<std::uint8_t> tooBig(257, 0);
	try {
		r.d().sdo().download(0, 0x2000, 0, tooBig);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EMSGSIZE);
		CHECK_THAT(e.what(), Equals("SDO download 0x2000:00 to slave 0: 257 bytes, the chip moves at most 256 "
					    "bytes per SDO request"));
	}
	SdoOptions o;
	o.length = 300;
	try {
		(void)r.d().sdo().upload(0, 0x2000, 0, o);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EMSGSIZE);
		CHECK_THAT(e.what(), Contains("300 bytes requested, the chip moves at most 256 bytes per SDO request"));
	}
}

TEST_CASE("sdo: a non-existent object aborts with 0x06020000 and its text", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	try {
		(void)r.d().sdo().read<std::uint32_t>(1, 0x5FFF, 0);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x06020000u);
		CHECK(e.errnoValue() == EREMOTEIO);
		CHECK_THAT(e.what(), Equals("SDO upload 0x5FFF:00 from slave 1 aborted: 0x06020000 Object not existing"));
	}
	// the chip keeps the code for ECAT_SDO_ABORTCODE_GET
	CHECK(r.d().bus().sdoAbortCode() == 0x06020000u);
	// and the next transfer works (the engine cleared the async error)
	CHECK(r.d().sdo().read<std::uint16_t>(1, 0x2001, 0) == 50000);
	CHECK(r.d().bus().sdoAbortCode() == 0u);
}

TEST_CASE("sdo: a write to a read-only object aborts with 0x06010002", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	try {
		r.d().sdo().write<std::uint32_t>(0, 0x1000, 0, 1);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x06010002u);
		CHECK_THAT(e.what(), Equals("SDO download 0x1000:00 to slave 0 aborted: 0x06010002 Read only entry"));
	}
	// a value above the range (0x2001: 200..51200): the EST-584 clamps and aborts (manual 5.3.3)
	try {
		r.d().sdo().write<std::uint16_t>(0, 0x2001, 0, 60000);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x06090031u);
		CHECK_THAT(e.what(), Equals("SDO download 0x2001:00 to slave 0 aborted: 0x06090031 Value is too great"));
	}
	CHECK(r.d().sdo().read<std::uint16_t>(0, 0x2001, 0) == 51200);
	// a wrong length: a 32-bit value to a 16-bit entry
	try {
		r.d().sdo().write<std::uint32_t>(0, 0x2001, 0, 1000);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x06070010u);
		CHECK_THAT(e.what(), Contains("aborted: 0x06070010 Parameter length error"));
	}
	// the reading side: a 16-bit object read as 32 bits
	try {
		(void)r.d().sdo().read<std::uint32_t>(0, 0x2001, 0);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 0: the object has 2 bytes, the value read "
					    "has 4"));
	}
}

TEST_CASE("sdo: in INIT the slave answers 0x08000022, the dio has no object dictionary", "[sdo][errors]")
{
	Rig r;
	r.d().bus().initNetwork();
	try {
		(void)r.d().sdo().read<std::uint32_t>(0, 0x1000, 0);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x08000022u);
		CHECK_THAT(e.what(), Contains("0x08000022 Data can not be read or written in the current state"));
	}
	r.d().bus().stateSet(ecmxf::kAllSlaves, State::PreOp);
	try {
		(void)r.d().sdo().read<std::uint32_t>(2, 0x1000, 0);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x08000023u);
		CHECK_THAT(e.what(), Equals("SDO upload 0x1000:00 from slave 2 aborted: 0x08000023 Object is not in the "
					    "object dictionary"));
	}
}

TEST_CASE("sdo: FaultPlan forcedSdoAbort reaches the user with its text", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	r.chip->faults().forcedSdoAbort = 0x06060000;
	try {
		(void)r.d().sdo().read<std::uint16_t>(0, 0x2001, 0);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x06060000u);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 0 aborted: 0x06060000 Hardware error"));
	}
	r.chip->faults().forcedSdoAbort = 0x0BADC0DE;
	try {
		r.d().sdo().write<std::uint16_t>(0, 0x2001, 0, 1000);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x0BADC0DEu);
		CHECK_THAT(e.what(), Equals("SDO download 0x2001:00 to slave 0 aborted: 0x0BADC0DE unknown abort code"));
	}
}

TEST_CASE("sdo: a slave slower than the SDO timeout gives 0x05040000", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	SdoOptions o;
	o.timeout = 500us; // the EST-584 answers after 1 ms
	try {
		(void)r.d().sdo().read<std::uint16_t>(0, 0x2001, 0, o);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x05040000u);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 0 aborted: 0x05040000 SDO timeout"));
	}
}

TEST_CASE("sdo: a chip that stays busy times out naming the wait", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	r.chip->faults().asyncStuckBusy = true;
	SdoOptions o;
	o.timeout = 100ms; // the library waits 100 ms + 1 s
	try {
		(void)r.d().sdo().read<std::uint16_t>(0, 0x2001, 0, o);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 0: ECAT_SDO_REQ: timed out after 1100 ms "
					    "waiting for the async command to complete"));
	}
}

TEST_CASE("sdo: complete access and bad arguments are refused before sending", "[sdo][errors]")
{
	Rig r;
	r.preOp();
	SdoOptions ca;
	ca.completeAccess = true;
	try {
		(void)r.d().sdo().upload(0, 0x1C12, 0, ca);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EOPNOTSUPP);
		CHECK_THAT(e.what(), Equals("SDO upload 0x1C12:00 from slave 0: complete access is not available: "
					    "ECAT_SDO_REQ has no complete-access field (byte 0x05 is reserved in manual "
					    "ver. 038 and 050); transfer the subindices one by one"));
	}
	try {
		(void)r.d().sdo().read<std::uint16_t>(128, 0x2001, 0);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 128: slave 128 out of range (0..127)"));
	}
	try {
		r.d().sdo().download(0, 0x2001, 0, std::span<const std::uint8_t>());
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("SDO download 0x2001:00 to slave 0: no data (1..256 bytes)"));
	}
	// a slave position the bus does not have: the chip refuses, the
	// library says why
	try {
		(void)r.d().sdo().read<std::uint16_t>(5, 0x2001, 0);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("SDO upload 0x2001:00 from slave 5: ECAT_SDO_REQ: the chip refused the command "
					    "(error status bit 7, command error: slave 5 is not on the bus (3 slaves "
					    "found by ECAT_INIT_OP))"));
	}
	// and the device works afterwards
	CHECK(r.d().sdo().read<std::uint16_t>(0, 0x2001, 0) == 50000);
}
