// SPDX-License-Identifier: MIT
//
// periph.cpp - the peripheral commands of the ECM-XF as the manuals lay
// them out, and the GPIO/encoder fields of the packet headers.
//
// Page references: "038" = the English manual ver. 038, "050" = the Chinese
// manual ver. 050 (which wins where they differ), section = the command's
// page (ECM_GPIO_CONFIG_SET(ECM_GpioSetMode) and so on). The hardware
// behind the commands is in periph_blocks.hpp; the choices the manuals
// leave open are in Documentation/sim-peripherals.rst.

#include "periph.hpp"

#include <optional>
#include <stdexcept>
#include <string>

#include "le.hpp"
#include "periph_blocks.hpp"

namespace ecmxf::sim {

using periph::Adc;
using periph::Dac;
using periph::DacTrigger;
using periph::Gpio;
using periph::GpioIrq;
using periph::GpioMode;
using periph::GpioPull;
using periph::Mdio;
using periph::Qei;
using periph::QeiMode;

namespace {

// GPIO_CONFIG_SET (31) sub-operations, command parameter
enum : std::uint8_t {
	kCfgSetMode = 0,
	kCfgIntEnable = 1,
	kCfgDebounce = 2,
	kCfgDebounceClock = 3,
	kCfgIntClear = 4,
	kCfgIntClearExt = 6,
	kCfgSetModeExt = 8,
	kCfgDebounceExt = 9,
};

// GPIO_FUNC_OP (32)
enum : std::uint8_t {
	kFnSetValue = 0,
	kFnGetValue = 1,
	kFnSetValueExt = 2,
	kFnGetValueExt = 3,
	kFnGetIntFlag = 5,
	kFnGetIntFlagExt = 7,
};

// QEI_FUNC_OP (33)
enum : std::uint8_t { kEncOpen = 4, kEncStart = 5, kEncStop = 6, kEncGetCount = 21 };

// DAC_FUNC_OP (34)
enum : std::uint8_t {
	kDacStartConv = 0,
	kDacSetData = 11,
	kDacOpen = 20,
	kDacClose = 21,
	kDacSetDelay = 22,
};

// ADC_FUNC_OP (35)
enum : std::uint8_t {
	kAdcStartConv = 12,
	kAdcGetConvData = 15,
	kAdcGetValidFlag = 17,
	kAdcOpen = 40,
	kAdcClose = 41,
	kAdcConfigModule = 42,
};

// MDIO (81)
enum : std::uint8_t { kMdioWrite = 0, kMdioRead = 1 };

using Reply = Peripherals::Reply;

constexpr Reply kOk{};
constexpr Reply kBad{ 0, 0, true };

// Reply with @p n (2 or 4) little-endian bytes of @p v in the data section.
Reply put(std::span<std::uint8_t> out, std::uint32_t v, std::size_t n)
{
	if (out.size() < n)
		return kBad;
	if (n == 2)
		put16(out.data(), static_cast<std::uint16_t>(v));
	else
		put32(out.data(), v);
	return Reply{ 0, n, false };
}

// Lines 0..15 from command data 0 and 1.
std::uint32_t mask16(const ecmxf_cmd_hdr &h)
{
	return le16(h.data);
}

// The lines a GPIO_CONFIG_SET command names: data0/1 lines 0..15, or in an
// "Ext" one (@p ext) data0 bits 0..3 lines 16..19; nothing where that names
// lines 20..23, which do not exist.
std::optional<std::uint32_t> configLines(const ecmxf_cmd_hdr &h, bool ext)
{
	if (!ext)
		return mask16(h);
	if ((h.data[0] & 0xF0u) != 0)
		return std::nullopt;
	return std::uint32_t{ h.data[0] } << 16;
}

void checkLine(unsigned line, const char *what)
{
	if (line >= Gpio::kLines)
		throw std::out_of_range(std::string(what) + ": GPIO line " + std::to_string(line) +
					" does not exist (0.." + std::to_string(Gpio::kLines - 1) + ")");
}

} // namespace

struct Peripherals::State {
	Gpio gpio;
	Qei qei;
	Dac dac;
	Adc adc;
	Mdio mdio; // outside world: survives reset()

	Reply gpioConfig(const ecmxf_cmd_hdr &h);
	Reply gpioFunc(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out);
	Reply qeiFunc(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data,
		      std::span<std::uint8_t> out);
	Reply dacFunc(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data);
	Reply adcFunc(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data,
		      std::span<std::uint8_t> out);
	Reply mdioOp(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out);
};

// ECM_GPIO_CONFIG_SET (038 p. 35-39, 050 same section). Everything is in
// the command data bytes (header 0x04..0x07); the data length is 0.
Reply Peripherals::State::gpioConfig(const ecmxf_cmd_hdr &h)
{
	switch (h.param) {
	case kCfgSetMode:    // data0/1 = lines 0..15, data2 = mode, data3 = pull
	case kCfgSetModeExt: // data0 bits 0..3 = lines 16..19, data1 reserved
	{
		if (h.data[2] > 3 || h.data[3] > 2)
			return kBad;
		const auto mask = configLines(h, h.param == kCfgSetModeExt);
		if (!mask)
			return kBad;
		gpio.setMode(*mask, static_cast<GpioMode>(h.data[2]),
			     static_cast<GpioPull>(h.data[3]));
		return kOk;
	}
	case kCfgDebounce:    // data0/1 = lines 0..15, data2 = 0 disable / 1 enable
	case kCfgDebounceExt: // data0 bits 0..3 = lines 16..19
	{
		if (h.data[2] > 1)
			return kBad;
		const auto mask = configLines(h, h.param == kCfgDebounceExt);
		if (!mask)
			return kBad;
		gpio.setDebounce(*mask, h.data[2] != 0);
		return kOk;
	}
	case kCfgDebounceClock: // data0 bits 0..3 cycle, bit 4 clock 0 = 192M, 1 = 10K
		if ((h.data[0] & 0xE0u) != 0)
			return kBad;
		gpio.setDebounceClock(h.data[0] & 0x0Fu, (h.data[0] & 0x10u) != 0);
		return kOk;
	case kCfgIntEnable: // data0 = line 0..19, data1 = type 0..3
		if (h.data[0] >= Gpio::kLines || h.data[1] > 3)
			return kBad;
		gpio.setIrq(h.data[0], static_cast<GpioIrq>(h.data[1]));
		return kOk;
	case kCfgIntClear:    // data0/1 = lines 0..15
	case kCfgIntClearExt: // + data2 bits 0..3 = lines 16..19
	{
		std::uint32_t mask = mask16(h);
		if (h.param == kCfgIntClearExt)
			mask |= std::uint32_t{ h.data[2] & 0x0Fu } << 16;
		gpio.clearFlags(mask);
		return kOk;
	}
	default:
		return kBad;
	}
}

// ECM_GPIO_FUNC_OP (038 p. 39-42, 050 same section).
Reply Peripherals::State::gpioFunc(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out)
{
	switch (h.param) {
	case kFnSetValue: // data0/1 = output latches of lines 0..15
		gpio.setOutputs(0xFFFFu, mask16(h));
		return kOk;
	case kFnSetValueExt: // + data2 bits 0..3 = lines 16..19
		gpio.setOutputs(Gpio::kAllLines,
				mask16(h) | std::uint32_t{ h.data[2] & 0x0Fu } << 16);
		return kOk;
	case kFnGetValue: // 2 data bytes, lines 0..15
		return put(out, gpio.inputs() & 0xFFFFu, 2);
	case kFnGetValueExt: // 4 data bytes, lines 0..19
		return put(out, gpio.inputs(), 4);
	case kFnGetIntFlag: // 2 data bytes
		return put(out, gpio.flags() & 0xFFFFu, 2);
	case kFnGetIntFlagExt: // 4 data bytes
		return put(out, gpio.flags(), 4);
	default:
		return kBad;
	}
}

// ECM_QEI_FUNC_OP (038 p. 42-43, 050 same section).
Reply Peripherals::State::qeiFunc(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data,
				  std::span<std::uint8_t> out)
{
	switch (h.param) {
	case kEncOpen: { // data section: u32 mode 0x000/0x100/0x200/0x300
		if (data.size() < 4)
			return kBad;
		const std::uint32_t mode = le32(&data[0]);
		if ((mode & ~0x300u) != 0)
			return kBad;
		qei.open(static_cast<QeiMode>(mode >> 8));
		return kOk;
	}
	case kEncStart:
		qei.start();
		return kOk;
	case kEncStop:
		qei.stop();
		return kOk;
	case kEncGetCount: // 4 data bytes: the 32-bit counter
		return put(out, qei.count(), 4);
	default:
		return kBad;
	}
}

// ECM_DAC_FUNC_OP (038 p. 44-46, 050 same section).
Reply Peripherals::State::dacFunc(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data)
{
	switch (h.param) {
	case kDacOpen: { // data section: u32 trigger mode
		if (data.size() < 4)
			return kBad;
		const std::uint32_t m = le32(&data[0]);
		switch (m) {
		case 0x0000:
		case 0x0010:
		case 0x0030:
		case 0x1030:
		case 0x2030:
		case 0x3030:
			dac.open(static_cast<DacTrigger>(m));
			return kOk;
		default:
			return kBad;
		}
	}
	case kDacClose:
		dac.close();
		return kOk;
	case kDacSetDelay: { // data section: u32 0..1023, unit 1/96 us
		if (data.size() < 4)
			return kBad;
		const std::uint32_t t = le32(&data[0]);
		if (t > Dac::kMaxDelay)
			return kBad;
		dac.setDelay(t);
		return kOk;
	}
	case kDacSetData: { // data section: u32 0..4095 = 0..3.3 V
		if (data.size() < 4)
			return kBad;
		const std::uint32_t v = le32(&data[0]);
		if (v > Dac::kMaxData)
			return kBad;
		dac.setData(static_cast<std::uint16_t>(v));
		return kOk;
	}
	case kDacStartConv:
		dac.startConversion();
		return kOk;
	default:
		return kBad;
	}
}

// ECM_ADC_FUNC_OP (038 p. 46-48, 050 same section).
Reply Peripherals::State::adcFunc(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data,
				  std::span<std::uint8_t> out)
{
	constexpr std::uint32_t kModuleMask = (1u << Adc::kModules) - 1u;
	const std::size_t need = h.param == kAdcConfigModule ? 12 : h.param == kAdcClose ? 0 : 4;
	if (data.size() < need)
		return kBad;
	switch (h.param) {
	case kAdcOpen: { // u32 0x000 single-ended, 0x100 differential
		const std::uint32_t m = le32(&data[0]);
		if (m != 0x000 && m != 0x100)
			return kBad;
		adc.open(m == 0x100);
		return kOk;
	}
	case kAdcClose:
		adc.close();
		return kOk;
	case kAdcConfigModule: { // 0x0 module ("reserved, 0"), 0x4 trigger (0 = software), 0x8 channel ("reserved, 0")
		const std::uint32_t module = le32(&data[0]), trig = le32(&data[4]), ch = le32(&data[8]);
		if (module >= Adc::kModules || trig != 0 || ch >= Adc::kChannels)
			return kBad;
		adc.configModule(module, ch);
		return kOk;
	}
	case kAdcGetValidFlag: { // u32 module mask (manual: 0x1000); reply u32 flags
		const std::uint32_t mask = le32(&data[0]);
		if ((mask & ~kModuleMask) != 0)
			return kBad;
		return put(out, adc.valid() & mask, 4);
	}
	case kAdcStartConv: { // u32 module mask (manual: 0x1000)
		const std::uint32_t mask = le32(&data[0]);
		if ((mask & ~kModuleMask) != 0)
			return kBad;
		adc.start(mask);
		return kOk;
	}
	case kAdcGetConvData: { // u32 module number (manual: 12); reply u32 0..4095
		const std::uint32_t module = le32(&data[0]);
		if (module >= Adc::kModules)
			return kBad;
		if (out.size() < 4)
			return kBad;
		return put(out, adc.take(module), 4);
	}
	default:
		return kBad;
	}
}

// ECM_CMD_MDIO (050 only). Command data: byte 0 PHY register, byte 1 PHY
// address, bytes 2-3 the value to write (little-endian). A read answers
// 2 data bytes.
Reply Peripherals::State::mdioOp(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out)
{
	const unsigned reg = h.data[0], phy = h.data[1];
	if (reg >= Mdio::kRegisters || phy >= Mdio::kAddresses)
		return kBad;
	switch (h.param) {
	case kMdioWrite:
		mdio.write(phy, reg,
			   le16(&h.data[2]));
		return kOk;
	case kMdioRead:
		return put(out, mdio.read(phy, reg), 2);
	default:
		return kBad;
	}
}

Peripherals::Peripherals() : s_(std::make_unique<State>()) {}
Peripherals::~Peripherals() = default;

void Peripherals::reset()
{
	s_->gpio.reset();
	s_->qei.reset();
	s_->dac.reset();
	s_->adc.reset();
}

Peripherals::Reply Peripherals::handle(const ecmxf_cmd_hdr &hdr, std::span<const std::uint8_t> data,
				       std::span<std::uint8_t> out)
{
	switch (hdr.code) {
	case ECMXF_CMD_GPIO_CONFIG_SET:
		return s_->gpioConfig(hdr);
	case ECMXF_CMD_GPIO_FUNC_OP:
		return s_->gpioFunc(hdr, out);
	case ECMXF_CMD_QEI_FUNC_OP:
		return s_->qeiFunc(hdr, data, out);
	case ECMXF_CMD_DAC_FUNC_OP:
		return s_->dacFunc(hdr, data);
	case ECMXF_CMD_ADC_FUNC_OP:
		return s_->adcFunc(hdr, data, out);
	case ECMXF_CMD_MDIO:
		return s_->mdioOp(hdr, out);
	default:
		return kBad;
	}
}

// Command header 0x08 bit 15: 0x16 = GPIO 0..7, 0x17 = GPIO 8..15, where
// (firmware 0x1E and later) 0x17 bit 4 drives GPIO 13 and bit 5 GPIO 12.
// 0x14/0x15 clear GPIO interrupt flags 0..15, 0x10 bit 29 the encoder's.
void Peripherals::applyHeader(const ecmxf_cmd_hdr &hdr)
{
	if ((hdr.reserved & ECMXF_RSV_GPIO_OUT) != 0) {
		const std::uint32_t lo = hdr.gpio_out[0], hi = hdr.gpio_out[1];
		std::uint32_t v = lo | (hi & 0x0Fu) << 8 | (hi & 0xC0u) << 8;
		v |= (hi >> 4 & 1u) << 13; // bit 12 of the field -> GPIO 13
		v |= (hi >> 5 & 1u) << 12; // bit 13 of the field -> GPIO 12
		s_->gpio.setOutputs(0xFFFFu, v);
	}
	s_->gpio.clearFlags(std::uint32_t{ hdr.gpio_int_clear[0] } |
			    std::uint32_t{ hdr.gpio_int_clear[1] } << 8);
	if ((hdr.int_clear & ECMXF_INT_ENCODER) != 0)
		s_->qei.clearFlags();
}

void Peripherals::fillHeader(ecmxf_rsp_hdr &rsp) const
{
	const std::uint32_t flags = s_->gpio.flags(), in = s_->gpio.inputs();
	rsp.gpio_int_flag[0] = static_cast<std::uint8_t>(flags);
	rsp.gpio_int_flag[1] = static_cast<std::uint8_t>(flags >> 8);
	rsp.gpio_in[0] = static_cast<std::uint8_t>(in);
	rsp.gpio_in[1] = static_cast<std::uint8_t>(in >> 8);
}

std::uint32_t Peripherals::intFlags() const
{
	return s_->qei.flags() != 0 ? ECMXF_INT_ENCODER : 0u;
}

std::uint16_t Peripherals::gpioIntFlags() const
{
	return static_cast<std::uint16_t>(s_->gpio.flags());
}

std::uint8_t Peripherals::qeiIntFlags() const { return s_->qei.flags(); }

void Peripherals::advance(std::chrono::nanoseconds dt)
{
	s_->gpio.advance(dt);
	s_->dac.advance(dt);
	s_->adc.advance(dt);
}

void Peripherals::setPin(unsigned line, bool level)
{
	checkLine(line, "Peripherals::setPin");
	s_->gpio.drive(line, level);
}

bool Peripherals::pin(unsigned line) const
{
	checkLine(line, "Peripherals::pin");
	return s_->gpio.pad(line);
}

void Peripherals::encoderMove(std::int32_t counts) { s_->qei.move(counts); }

void Peripherals::encoderIndex() { s_->qei.index(); }

void Peripherals::setAnalog(unsigned ch, std::uint16_t raw)
{
	if (ch >= Adc::kChannels)
		throw std::out_of_range("Peripherals::setAnalog: ADC channel " + std::to_string(ch) +
					" does not exist (0.." + std::to_string(Adc::kChannels - 1) +
					")");
	s_->adc.setInput(ch, raw);
}

std::uint16_t Peripherals::dacOutput(unsigned ch) const
{
	if (ch >= Dac::kChannels)
		throw std::out_of_range("Peripherals::dacOutput: DAC channel " + std::to_string(ch) +
					" does not exist (the ECM-XF has one DAC output, channel 0)");
	return s_->dac.output();
}

void Peripherals::setDacTriggerPin(bool level) { s_->dac.setTriggerPin(level); }

void Peripherals::setPhyRegister(unsigned phy, unsigned reg, std::uint16_t value)
{
	if (phy >= Mdio::kAddresses || reg >= Mdio::kRegisters)
		throw std::out_of_range("Peripherals::setPhyRegister: PHY " + std::to_string(phy) +
					" register " + std::to_string(reg) +
					" is outside the MDIO space (PHY 0..31, register 0..31)");
	s_->mdio.poke(phy, reg, value);
}

} // namespace ecmxf::sim
