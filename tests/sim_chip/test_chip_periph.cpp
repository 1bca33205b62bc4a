// SPDX-License-Identifier: MIT
// The chip hands GPIO_CONFIG_SET, GPIO_FUNC_OP, QEI_FUNC_OP, DAC_FUNC_OP,
// ADC_FUNC_OP (31..35) and MDIO (81) to its peripherals, lets them see
// every command header and takes the response header's GPIO fields and
// the encoder interrupt flag from them. The peripherals are tested on
// their own (tests/sim_periph); here a second Peripherals object that sees
// the same headers and commands at the same times must answer exactly as
// the chip does.

#include <catch2/catch.hpp>

#include "host.hpp"
#include "periph.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

TEST_CASE("chip: peripheral commands and header fields come from the peripherals", "[chip][periph]")
{
	sim::Chip chip(sim::Network{});
	Host h(chip);
	sim::Peripherals ref;
	std::chrono::nanoseconds refNow{ 0 };
	auto catchUp = [&] {
		if (chip.now() > refNow) {
			ref.advance(chip.now() - refNow);
			refNow = chip.now();
		}
	};
	// every packet the chip takes in passes through applyHeader
	auto mirrorSend = [&](const Cmd &c) {
		const Rsp r = h.send(c);
		catchUp();
		ref.applyHeader(h.last.h);
		return r;
	};
	auto mirrorRepeat = [&] {
		const Rsp r = h.repeat();
		catchUp();
		ref.applyHeader(h.last.h);
		return r;
	};
	mirrorSend(Cmd(ECMXF_CMD_INFO_UPDATE_OP));

	struct Case {
		const char *what;
		Cmd cmd;
	};
	std::vector<Case> cases{
		{ "GPIO 0-3 output mode", Cmd(ECMXF_CMD_GPIO_CONFIG_SET, 0).d(0x0F, 0x00, 0x1, 0x0) },
		{ "GPIO 4-7 input, pull-up", Cmd(ECMXF_CMD_GPIO_CONFIG_SET, 0).d(0xF0, 0x00, 0x0, 0x1) },
		{ "GPIO set value", Cmd(ECMXF_CMD_GPIO_FUNC_OP, 0).d(0x05, 0x00) },
		{ "GPIO get value", Cmd(ECMXF_CMD_GPIO_FUNC_OP, 1) },
		{ "GPIO ext get value", Cmd(ECMXF_CMD_GPIO_FUNC_OP, 3) },
		{ "GPIO interrupt enable", Cmd(ECMXF_CMD_GPIO_CONFIG_SET, 1).d(4, 0x1) },
		{ "GPIO int flag", Cmd(ECMXF_CMD_GPIO_FUNC_OP, 5) },
		{ "GPIO ext int flag", Cmd(ECMXF_CMD_GPIO_FUNC_OP, 7) },
		{ "GPIO outputs in the header",
		  [] {
			  Cmd c(ECMXF_CMD_INFO_UPDATE_OP);
			  c.reserved(ECMXF_RSV_GPIO_OUT);
			  c.h.gpio_out[0] = 0x0A;
			  return c;
		  }() },
		{ "QEI open", Cmd(ECMXF_CMD_QEI_FUNC_OP, 4).payload({ 0x00, 0x00, 0x00, 0x00 }) },
		{ "QEI start", Cmd(ECMXF_CMD_QEI_FUNC_OP, 5) },
		{ "QEI count", Cmd(ECMXF_CMD_QEI_FUNC_OP, 21) },
		{ "DAC open", Cmd(ECMXF_CMD_DAC_FUNC_OP, 20).payload({ 0x00, 0x00, 0x00, 0x00 }) },
		{ "DAC data", Cmd(ECMXF_CMD_DAC_FUNC_OP, 11).payload({ 0x00, 0x08, 0x00, 0x00 }) },
		{ "ADC open", Cmd(ECMXF_CMD_ADC_FUNC_OP, 40).payload({ 0x00, 0x00, 0x00, 0x00 }) },
		{ "ADC start", Cmd(ECMXF_CMD_ADC_FUNC_OP, 12).payload({ 0x00, 0x10, 0x00, 0x00 }) },
		{ "ADC data", Cmd(ECMXF_CMD_ADC_FUNC_OP, 15).payload({ 12, 0x00, 0x00, 0x00 }) },
		{ "MDIO read PHY 1 reg 1", Cmd(ECMXF_CMD_MDIO, 1).d(1, 1, 0, 0) },
		{ "MDIO write PHY 1 reg 4", Cmd(ECMXF_CMD_MDIO, 0).d(4, 1, 0x01, 0xE1) },
		{ "not a GPIO operation", Cmd(ECMXF_CMD_GPIO_FUNC_OP, 99) },
		{ "not a QEI operation", Cmd(ECMXF_CMD_QEI_FUNC_OP, 77) },
	};
	for (Case &k : cases) {
		INFO(k.what);
		k.cmd.h.control = static_cast<std::uint8_t>(k.cmd.h.control | ECMXF_CTL_CLR_CMD_ERR);
		mirrorSend(k.cmd);
		// what the reference answers to the same command at the same time
		std::vector<std::uint8_t> in(ECMXF_DATA_DEFAULT, 0), out(ECMXF_DATA_DEFAULT, 0);
		std::copy(k.cmd.data.begin(), k.cmd.data.end(), in.begin());
		sim::Peripherals::Reply want{};
		ecmxf_rsp_hdr wantHdr{};
		const bool isPeriph = k.cmd.h.code != ECMXF_CMD_INFO_UPDATE_OP;
		if (isPeriph)
			want = ref.handle(h.last.h, in, out);
		ref.fillHeader(wantHdr);
		const std::uint32_t wantEnc = ref.intFlags() & ECMXF_INT_ENCODER;

		const Rsp got = mirrorRepeat();
		REQUIRE(got.ok());
		if (isPeriph) {
			CHECK(got.h.code == k.cmd.h.code);
			CHECK(got.h.ret == want.ret);
			CHECK(got.cmdError() == want.cmdError);
			if (!want.cmdError) {
				REQUIRE(got.h.len == want.len);
				CHECK(std::equal(got.data.begin(), got.data.end(), out.begin()));
			}
		}
		CHECK(got.h.gpio_in[0] == wantHdr.gpio_in[0]);
		CHECK(got.h.gpio_in[1] == wantHdr.gpio_in[1]);
		CHECK(got.h.gpio_int_flag[0] == wantHdr.gpio_int_flag[0]);
		CHECK(got.h.gpio_int_flag[1] == wantHdr.gpio_int_flag[1]);
		CHECK((got.h.int_flags & ECMXF_INT_ENCODER) == wantEnc);
	}
}
