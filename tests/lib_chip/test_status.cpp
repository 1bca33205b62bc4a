// SPDX-License-Identifier: MIT
// The status decoders of include/ecmxf/model/status.hpp against the bit tables of
// manual ver. 050 (table 2, response header; ECM_CMD_ECAT_INT_SET_ENABLE).

#include <catch2/catch.hpp>

#include <ecmxf/model/status.hpp>

using namespace ecmxf;

TEST_CASE("describeErrorStatus names every error-status bit of the ver. 050 table", "[lib][chip][status]")
{
	CHECK(describeErrorStatus(0x00) == "none");
	CHECK(describeErrorStatus(0x01) == "link (bit 0)");
	CHECK(describeErrorStatus(0x89) == "link (bit 0), async command error (bit 3), command error (bit 7)");
	CHECK(describeErrorStatus(0xFF) ==
	      "link (bit 0), link at INIT_OP (bit 1), reserved (bit 2), async command error (bit 3), "
	      "SPI error (bit 4), FIFO error (bit 5), SPI CRC error (bit 6), command error (bit 7)");
	const auto bits = errorStatusBits(0x30);
	REQUIRE(bits.size() == 2);
	CHECK(bits[0] == StatusBit{ 4, "SPI error" });
	CHECK(bits[1] == StatusBit{ 5, "FIFO error" });
}

TEST_CASE("describeEcmStatus names bits 2..7 and leaves the check type to its own decoder",
	  "[lib][chip][status]")
{
	CHECK(describeEcmStatus(0x00) == "none");
	CHECK(describeEcmStatus(0x03) == "none");
	CHECK(describeEcmStatus(0x43) == "FIFO enabled (bit 6)");
	CHECK(describeEcmStatus(0xBC) == "DC stable (bit 2), Ethernet initialised (bit 3), PDO configured (bit 4), "
					 "NOP (bit 5), async command busy (bit 7)");
	CHECK(ecmStatusBits(0x80) == std::vector<StatusBit>{ { 7, "async command busy" } });
	CHECK(checkTypeOfEcmStatus(0x43) == CheckType::Crc32);
	CHECK(checkTypeOfEcmStatus(0x40) == CheckType::Fixed);
	CHECK(checkTypeOfEcmStatus(0x01) == CheckType::Crc8);
	CHECK(checkTypeOfEcmStatus(0x02) == CheckType::Ccitt);
	CHECK(checkTypeName(CheckType::Fixed) == "fixed");
	CHECK(checkTypeName(CheckType::Crc8) == "CRC-8");
	CHECK(checkTypeName(CheckType::Ccitt) == "CRC-CCITT");
	CHECK(checkTypeName(CheckType::Crc32) == "CRC-32");
}

TEST_CASE("describeInterruptFlags names the flag and enable bits, others as reserved", "[lib][chip][status]")
{
	CHECK(describeInterruptFlags(0) == "none");
	CHECK(describeInterruptFlags(0xA0000000u) == "EtherCAT packet (bit 31), encoder (bit 29)");
	CHECK(describeInterruptFlags(0x03C00000u) ==
	      "RxFIFO low mark (bit 25), TxFIFO high mark (bit 24), CRC error (bit 23), WKC error (bit 22)");
	CHECK(describeInterruptFlags(0x00000001u) == "reserved (bit 0)");
	CHECK(interruptFlagBits(irq::kWkcError) == std::vector<StatusBit>{ { 22, "WKC error" } });
	CHECK(irq::kEnableMask == 0x83C00000u);
}

TEST_CASE("ecatStateName gives the header's state names, +ERROR and unknown values", "[lib][chip][status]")
{
	CHECK(ecatStateName(0x00) == "NONE");
	CHECK(ecatStateName(0x01) == "INIT");
	CHECK(ecatStateName(0x02) == "PRE-OP");
	CHECK(ecatStateName(0x03) == "BOOT");
	CHECK(ecatStateName(0x04) == "SAFE-OP");
	CHECK(ecatStateName(0x08) == "OP");
	CHECK(ecatStateName(0x10) == "ERROR");
	CHECK(ecatStateName(0x12) == "PRE-OP+ERROR");
	CHECK(ecatStateName(0x14) == "SAFE-OP+ERROR");
	CHECK(ecatStateName(0x05) == "unknown (0x05)");
	CHECK(ecatStateName(0x20) == "unknown (0x20)");
}

TEST_CASE("masterSeriesName and foeErrorText", "[lib][chip][status]")
{
	CHECK(masterSeriesName(0) == "ECM-XF");
	CHECK(masterSeriesName(1) == "ECM-XFL");
	CHECK(masterSeriesName(2) == "ECM-XFU");
	CHECK(masterSeriesName(3) == "ECM-XM");
	CHECK(masterSeriesName(9) == "unknown (9)");
	CHECK(foeErrorText(0x8001) == "file not found");
	CHECK(foeErrorText(0x8002) == "access denied");
	CHECK(foeErrorText(0x8008) == "bootstrap only");
	CHECK(foeErrorText(0x05040000) == "timeout (the slave did not answer)");
	CHECK(foeErrorText(0x08000000) == "general error (e.g. the slave has no FoE)");
	CHECK(foeErrorText(0x12345678) == "unknown error code");
}
