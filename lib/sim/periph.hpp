// SPDX-License-Identifier: MIT
//
// periph.hpp - the ECM-XF's on-chip peripherals in the simulator: 20 GPIO
// lines (modes, pulls, debounce, interrupts, the GPIO fields of the packet
// header), the quadrature encoder (QEI), DAC, ADC and the MDIO bus.
//
// The chip model (chip.cpp) owns one Peripherals object, hands it the
// commands GPIO_CONFIG_SET (31), GPIO_FUNC_OP (32), QEI_FUNC_OP (33),
// DAC_FUNC_OP (34), ADC_FUNC_OP (35) and MDIO (81), lets it see every
// valid command header (GPIO outputs at 0x16/0x17 when 0x08 bit15 is set,
// GPIO interrupt clears at 0x14/0x15, encoder interrupt clear bit 29) and
// asks it for the response header's GPIO fields and interrupt flags.

#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "ecmxf-proto.h"

namespace ecmxf::sim {

class Peripherals
{
public:
	static constexpr unsigned kGpioLines = 20;

	/// Result of one command.
	struct Reply {
		std::uint8_t ret = 0;      ///< return value (header 0x0D)
		std::size_t len = 0;       ///< bytes written to the data section
		bool cmdError = false;     ///< bad parameter: error status bit 7
	};

	Peripherals();
	~Peripherals();
	Peripherals(const Peripherals &) = delete;
	Peripherals &operator=(const Peripherals &) = delete;

	/// Power-on state (also WARM_RESET).
	void reset();

	/// Execute one of the commands 31..35 or 81. @p data is the command's
	/// data section, @p out the response's (its size is the data size).
	Reply handle(const ecmxf_cmd_hdr &hdr, std::span<const std::uint8_t> data,
		     std::span<std::uint8_t> out);

	/// Every valid, executed command header passes through here first.
	void applyHeader(const ecmxf_cmd_hdr &hdr);

	/// GPIO fields of a response header (0x14..0x17).
	void fillHeader(ecmxf_rsp_hdr &rsp) const;

	/// Interrupt flags contributed to header 0x10 (bit 29 encoder).
	[[nodiscard]] std::uint32_t intFlags() const;
	/// GPIO interrupt flags, lines 0..15 (for INT1 with the GPIO enable).
	[[nodiscard]] std::uint16_t gpioIntFlags() const;
	/// The QEI's own interrupt flags, at the bit positions of
	/// ECAT_INT_SET_ENABLE's u8PeripIntEnable (ver. 050): bit 4 index,
	/// bit 5 compare, bit 6 counter over/underflow. Header bit 29 is their
	/// OR; clearing bit 29 clears them all.
	[[nodiscard]] std::uint8_t qeiIntFlags() const;

	/// Time passes (debounce, ADC conversions, encoder motion).
	void advance(std::chrono::nanoseconds dt);

	// ---- the outside world, for tests and the demo ----
	/// Drive an input pin from outside (input, open-drain, quasi modes).
	void setPin(unsigned line, bool level);
	/// Level seen on a pin (outputs: the driven value; inputs: the outside
	/// level or the pull).
	[[nodiscard]] bool pin(unsigned line) const;
	/// Move the encoder by @p counts quadrature counts (sign = direction).
	void encoderMove(std::int32_t counts);
	/// A pulse on the encoder's index input (sets the QEI index flag while
	/// the encoder is counting).
	void encoderIndex();
	/// Analog input of ADC channel @p ch (raw converter counts).
	void setAnalog(unsigned ch, std::uint16_t raw);
	/// Last value converted by DAC channel @p ch.
	[[nodiscard]] std::uint16_t dacOutput(unsigned ch) const;
	/// Level of the DAC_ST trigger pin (DAC modes 0x0030..0x3030).
	void setDacTriggerPin(bool level);
	/// An MDIO PHY register, for tests (PHY address, register).
	void setPhyRegister(unsigned phy, unsigned reg, std::uint16_t value);

private:
	struct State;
	std::unique_ptr<State> s_;
};

} // namespace ecmxf::sim
