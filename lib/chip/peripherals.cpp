// SPDX-License-Identifier: MIT
// Peripherals (include/ecmxf/chip/peripherals.hpp): GPIO, QEI, DAC, ADC and
// MDIO (Documentation/commands-chip.rst). Arguments are checked before
// anything is sent; the commands run through the one command runner
// (lib/device/runner.hpp).

#include <ecmxf/chip/peripherals.hpp>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>

#include <cerrno>
#include <string>

#include "device/runner.hpp"
#include "ecmxf-proto.h"

namespace ecmxf {

using namespace detail; // the command runner and its helpers

namespace {

constexpr unsigned kAdcPolls = 100;

/// A command whose data section is one little-endian u32 (QEI/DAC/ADC).
Command withWord(std::uint8_t code, std::uint8_t param, std::uint32_t v)
{
	Command c = detail::cmd(code, param);
	c.payload.assign(4, 0);
	detail::put32At(c.payload, 0, v);
	return c;
}

/// Runs @p c and returns the little-endian value of its first @p bytes
/// (2 or 4) data bytes; @p what names the call in the EPROTO message.
std::uint32_t readValue(Device &d, const Command &c, const char *what, std::size_t bytes)
{
	const Response r = immediate(d, c);
	needData(what, r, bytes);
	return bytes == 2 ? le16(r.data, 0) : le32(r.data, 0);
}

std::string gpioLineMaskError(std::uint32_t lines)
{
	return "line mask " + hex(lines, 8) + " names lines above GPIO 19 (the ECM-XF has GPIO 0..19)";
}

} // namespace

Peripherals Device::peripherals() noexcept
{
	return Peripherals(*this);
}

// ===========================================================================
// GPIO
// ===========================================================================

void Peripherals::gpioSetMode(std::uint32_t lines, GpioMode mode, GpioPull pull) const
{
	const std::string what = "GPIO_CONFIG_SET (GpioSetMode)";
	const auto m = static_cast<unsigned>(mode), p = static_cast<unsigned>(pull);
	if (lines == 0)
		invalid(what, "no GPIO line selected (line mask 0)");
	if (lines >> kGpioLines)
		invalid(what, gpioLineMaskError(lines));
	if (m > 3)
		invalid(what, "mode " + std::to_string(m) +
				      " is out of range (0 input, 1 output, 2 open-drain, 3 quasi-bidirectional)");
	if (p > 2)
		invalid(what, "pull " + std::to_string(p) + " is out of range (0 none, 1 up, 2 down)");
	const auto m8 = static_cast<std::uint8_t>(m), p8 = static_cast<std::uint8_t>(p);
	if (lines & 0xFFFFu)
		immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 0, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8), m8, p8));
	if (lines >> 16)
		immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 8, static_cast<std::uint8_t>(lines >> 16), 0, m8, p8));
}

void Peripherals::gpioSetDebounce(std::uint32_t lines, bool enable) const
{
	const std::string what = "GPIO_CONFIG_SET (GpioEnableDebounce)";
	if (lines == 0)
		invalid(what, "no GPIO line selected (line mask 0)");
	if (lines >> kGpioLines)
		invalid(what, gpioLineMaskError(lines));
	const std::uint8_t e = enable ? 1 : 0;
	if (lines & 0xFFFFu)
		immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 2, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8), e));
	if (lines >> 16)
		immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 9, static_cast<std::uint8_t>(lines >> 16), 0, e));
}

void Peripherals::gpioSetDebounceClock(unsigned cycle, DebounceClock clock) const
{
	const std::string what = "GPIO_CONFIG_SET (GpioSetDebounceClock)";
	const auto c = static_cast<unsigned>(clock);
	if (cycle > 15)
		invalid(what, "cycle " + std::to_string(cycle) + " is out of range (0..15: 2^cycle clock periods)");
	if (c > 1)
		invalid(what, "clock " + std::to_string(c) + " is out of range (0 192 MHz, 1 10 kHz)");
	immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 3, static_cast<std::uint8_t>(cycle | c << 4)));
}

void Peripherals::gpioSetInterrupt(unsigned line, GpioEdge edge) const
{
	const std::string what = "GPIO_CONFIG_SET (GpioIntEnable)";
	const auto e = static_cast<unsigned>(edge);
	if (line >= kGpioLines)
		invalid(what, "GPIO line " + std::to_string(line) + " is out of range (0..19)");
	if (e > 3)
		invalid(what, "interrupt type " + std::to_string(e) +
				      " is out of range (0 disabled, 1 both edges, 2 falling, 3 rising)");
	immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 1, static_cast<std::uint8_t>(line),
				  static_cast<std::uint8_t>(e)),
		  {}, "this firmware has interrupts on GPIO 0..15 only");
}

void Peripherals::gpioClearInterrupts(std::uint32_t lines) const
{
	const std::string what = "GPIO_CONFIG_SET (GpioIntClear)";
	if (lines == 0)
		invalid(what, "no GPIO line selected (line mask 0)");
	if (lines >> kGpioLines)
		invalid(what, gpioLineMaskError(lines));
	if (lines >> 16)
		immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 6, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8), static_cast<std::uint8_t>(lines >> 16)));
	else
		immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_CONFIG_SET, 4, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8)));
}

void Peripherals::gpioWrite(std::uint16_t values) const
{
	immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_FUNC_OP, 0, static_cast<std::uint8_t>(values),
				  static_cast<std::uint8_t>(values >> 8)));
}

void Peripherals::gpioWriteAll(std::uint32_t values) const
{
	if (values >> kGpioLines)
		invalid("GPIO_FUNC_OP (GpioExtSetValue)",
			"values " + hex(values, 8) + " name lines above GPIO 19 (the ECM-XF has GPIO 0..19)");
	immediate(*dev_, detail::cmdData(ECMXF_CMD_GPIO_FUNC_OP, 2, static_cast<std::uint8_t>(values),
				  static_cast<std::uint8_t>(values >> 8), static_cast<std::uint8_t>(values >> 16)));
}

std::uint16_t Peripherals::gpioRead() const
{
	return static_cast<std::uint16_t>(
		readValue(*dev_, detail::cmd(ECMXF_CMD_GPIO_FUNC_OP, 1), "GPIO_FUNC_OP (GpioGetValue)", 2));
}

std::uint32_t Peripherals::gpioReadAll() const
{
	return readValue(*dev_, detail::cmd(ECMXF_CMD_GPIO_FUNC_OP, 3), "GPIO_FUNC_OP (GpioExtGetValue)", 4);
}

std::uint16_t Peripherals::gpioInterruptFlags() const
{
	return static_cast<std::uint16_t>(
		readValue(*dev_, detail::cmd(ECMXF_CMD_GPIO_FUNC_OP, 5), "GPIO_FUNC_OP (GpioGetIntFlag)", 2));
}

std::uint32_t Peripherals::gpioInterruptFlagsAll() const
{
	return readValue(*dev_, detail::cmd(ECMXF_CMD_GPIO_FUNC_OP, 7), "GPIO_FUNC_OP (GpioExtGetIntFlag)", 4);
}

// ===========================================================================
// QEI, DAC, ADC
// ===========================================================================

void Peripherals::qeiOpen(QeiMode mode) const
{
	const auto m = static_cast<std::uint32_t>(mode);
	if (m & ~0x300u)
		invalid("QEI_FUNC_OP (EncOpen)", "mode " + hex(m, 3) +
							 " is out of range (0x000 X4 free, 0x100 X2 free, 0x200 X4 "
							 "compare, 0x300 X2 compare)");
	immediate(*dev_, withWord(ECMXF_CMD_QEI_FUNC_OP, 4, m));
}

void Peripherals::qeiStart() const
{
	immediate(*dev_, detail::cmd(ECMXF_CMD_QEI_FUNC_OP, 5));
}

void Peripherals::qeiStop() const
{
	immediate(*dev_, detail::cmd(ECMXF_CMD_QEI_FUNC_OP, 6));
}

std::uint32_t Peripherals::qeiCount() const
{
	return readValue(*dev_, detail::cmd(ECMXF_CMD_QEI_FUNC_OP, 21), "QEI_FUNC_OP (EncGetCount)", 4);
}

void Peripherals::dacOpen(DacTrigger trigger) const
{
	const auto t = static_cast<std::uint32_t>(trigger);
	switch (t) {
	case 0x0000:
	case 0x0010:
	case 0x0030:
	case 0x1030:
	case 0x2030:
	case 0x3030:
		break;
	default:
		invalid("DAC_FUNC_OP (DacOpen)", "trigger " + hex(t, 4) +
							 " is not one of 0x0000, 0x0010, 0x0030, 0x1030, 0x2030, 0x3030");
	}
	immediate(*dev_, withWord(ECMXF_CMD_DAC_FUNC_OP, 20, t));
}

void Peripherals::dacClose() const
{
	immediate(*dev_, detail::cmd(ECMXF_CMD_DAC_FUNC_OP, 21));
}

void Peripherals::dacSetDelay(std::uint16_t ticks) const
{
	if (ticks > 1023)
		invalid("DAC_FUNC_OP (DacSetDelayTime)",
			"delay " + std::to_string(ticks) + " is out of range (0..1023 in 1/96 us)");
	immediate(*dev_, withWord(ECMXF_CMD_DAC_FUNC_OP, 22, ticks));
}

void Peripherals::dacWrite(std::uint16_t value) const
{
	if (value > 4095)
		invalid("DAC_FUNC_OP (DacSetData)",
			"value " + std::to_string(value) + " is out of range (0..4095 = 0..3.3 V)");
	immediate(*dev_, withWord(ECMXF_CMD_DAC_FUNC_OP, 11, value));
}

void Peripherals::dacStartConversion() const
{
	immediate(*dev_, detail::cmd(ECMXF_CMD_DAC_FUNC_OP, 0));
}

void Peripherals::adcOpen(AdcInputMode mode) const
{
	const auto m = static_cast<std::uint32_t>(mode);
	if (m != 0x000 && m != 0x100)
		invalid("ADC_FUNC_OP (AdcOpen)",
			"input mode " + hex(m, 3) + " is out of range (0x000 single-ended, 0x100 differential)");
	immediate(*dev_, withWord(ECMXF_CMD_ADC_FUNC_OP, 40, m));
}

void Peripherals::adcClose() const
{
	immediate(*dev_, detail::cmd(ECMXF_CMD_ADC_FUNC_OP, 41));
}

void Peripherals::adcConfigureModule(unsigned module, unsigned channel) const
{
	const std::string what = "ADC_FUNC_OP (AdcConfigSampleModule)";
	if (module > 15)
		invalid(what, "sample module " + std::to_string(module) + " is out of range (0..15)");
	if (channel > 15)
		invalid(what, "channel " + std::to_string(channel) + " is out of range (0..15)");
	Command c = detail::cmd(ECMXF_CMD_ADC_FUNC_OP, 42);
	c.payload.assign(12, 0);
	detail::put32At(c.payload, 0, module);
	detail::put32At(c.payload, 4, 0); // trigger source 0: software
	detail::put32At(c.payload, 8, channel);
	immediate(*dev_, c);
}

void Peripherals::adcStart(std::uint16_t moduleMask) const
{
	if (moduleMask == 0)
		invalid("ADC_FUNC_OP (AdcStartConv)", "no sample module selected (module mask 0)");
	immediate(*dev_, withWord(ECMXF_CMD_ADC_FUNC_OP, 12, moduleMask));
}

std::uint16_t Peripherals::adcValidFlags(std::uint16_t moduleMask) const
{
	const Response r = immediate(*dev_, withWord(ECMXF_CMD_ADC_FUNC_OP, 17, moduleMask));
	needData("ADC_FUNC_OP (AdcGetDataValidFlag)", r, 4);
	return static_cast<std::uint16_t>(le32(r.data, 0));
}

std::uint16_t Peripherals::adcRead(unsigned module) const
{
	const std::string what = "ADC_FUNC_OP (AdcGetConvData)";
	if (module > 15)
		invalid(what, "sample module " + std::to_string(module) + " is out of range (0..15)");
	const Response r = immediate(*dev_, withWord(ECMXF_CMD_ADC_FUNC_OP, 15, module));
	needData(what, r, 4);
	return static_cast<std::uint16_t>(le32(r.data, 0));
}

std::uint16_t Peripherals::adcConvert(unsigned module) const
{
	if (module > 15)
		invalid("ADC_FUNC_OP (AdcStartConv)", "sample module " + std::to_string(module) + " is out of range (0..15)");
	const auto mask = static_cast<std::uint16_t>(1u << module);
	adcStart(mask);
	for (unsigned i = 0; i < kAdcPolls; i++)
		if (adcValidFlags(mask) & mask)
			return adcRead(module);
	throw Error("ADC_FUNC_OP (AdcGetDataValidFlag): sample module " + std::to_string(module) +
			    " had no valid result after " + std::to_string(kAdcPolls) +
			    " polls (is the ADC open and the module configured?)",
		    ETIMEDOUT);
}

// ===========================================================================
// MDIO
// ===========================================================================

std::uint16_t Peripherals::mdioRead(unsigned phy, unsigned reg) const
{
	const std::string what = "MDIO (read)";
	if (phy > 31)
		invalid(what, "PHY address " + std::to_string(phy) + " is out of range (0..31)");
	if (reg > 31)
		invalid(what, "PHY register " + std::to_string(reg) + " is out of range (0..31)");
	const Response r = immediate(*dev_, detail::cmdData(ECMXF_CMD_MDIO, 1, static_cast<std::uint8_t>(reg),
						     static_cast<std::uint8_t>(phy)));
	needData(what, r, 2);
	return le16(r.data, 0);
}

void Peripherals::mdioWrite(unsigned phy, unsigned reg, std::uint16_t value) const
{
	const std::string what = "MDIO (write)";
	if (phy > 31)
		invalid(what, "PHY address " + std::to_string(phy) + " is out of range (0..31)");
	if (reg > 31)
		invalid(what, "PHY register " + std::to_string(reg) + " is out of range (0..31)");
	immediate(*dev_, detail::cmdData(ECMXF_CMD_MDIO, 0, static_cast<std::uint8_t>(reg), static_cast<std::uint8_t>(phy),
				  static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8)));
}

} // namespace ecmxf
