// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/chip/peripherals.hpp
 * @brief The chip's peripherals: GPIO, QEI, DAC, ADC and MDIO.
 *
 * Peripheral calls: dev.peripherals().gpioRead(), gpioWrite(), qeiCount(),
 * dacWrite(), adcConvert(), mdioRead()... (each keeps its peripheral's
 * name: the class holds five of them).
 *
 * Typed calls for GPIO_CONFIG_SET, GPIO_FUNC_OP, QEI_FUNC_OP, DAC_FUNC_OP,
 * ADC_FUNC_OP and MDIO (Documentation/commands-chip.rst). Arguments out of
 * range throw Error(EINVAL) naming the argument and its range; a command
 * the chip refuses (error status bit 7) throws Error(EINVAL).
 *
 * A Peripherals is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::peripherals() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <cstdint>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_chip.hpp>

namespace ecmxf {

class Device;

/// The chip's peripherals: GPIO, QEI, DAC, ADC and MDIO.
class ECMXF_EXPORT Peripherals
{
public:
	/// The view of @p device's peripherals.
	explicit Peripherals(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	// ---- GPIO (31, 32): masks name GPIO n with bit n, n = 0..19 ----

	/// GpioSetMode (31/0 for GPIO 0..15, 31/8 for GPIO 16..19).
	void gpioSetMode(std::uint32_t lines, GpioMode mode, GpioPull pull = GpioPull::None) const;
	/// GpioEnableDebounce (31/2, 31/9) for the @p lines.
	void gpioSetDebounce(std::uint32_t lines, bool enable) const;
	/// GpioSetDebounceClock (31/3): sampling period 2^@p cycle (0..15)
	/// periods of @p clock.
	void gpioSetDebounceClock(unsigned cycle, DebounceClock clock) const;
	/// GpioIntEnable (31/1): interrupt type of one @p line (0..19).
	void gpioSetInterrupt(unsigned line, GpioEdge edge) const;
	/// GpioIntClear (31/4, or 31/6 when @p lines names GPIO 16..19).
	void gpioClearInterrupts(std::uint32_t lines) const;
	/// GpioSetValue (32/0): the output latches of GPIO 0..15.
	void gpioWrite(std::uint16_t values) const;
	/// GpioExtSetValue (32/2): the output latches of GPIO 0..19.
	void gpioWriteAll(std::uint32_t values) const;
	/// GpioGetValue (32/1): GPIO 0..15.
	[[nodiscard]] std::uint16_t gpioRead() const;
	/// GpioExtGetValue (32/3): GPIO 0..19.
	[[nodiscard]] std::uint32_t gpioReadAll() const;
	/// GpioGetIntFlag (32/5): interrupt flags of GPIO 0..15.
	[[nodiscard]] std::uint16_t gpioInterruptFlags() const;
	/// GpioExtGetIntFlag (32/7): interrupt flags of GPIO 0..19.
	[[nodiscard]] std::uint32_t gpioInterruptFlagsAll() const;

	// ---- QEI (33), DAC (34), ADC (35) ----

	/// EncOpen (33/4): counting mode; stops and clears the counter.
	void qeiOpen(QeiMode mode) const;
	/// EncStart (33/5), EncStop (33/6).
	void qeiStart() const;
	void qeiStop() const;
	/// EncGetCount (33/21): the 32-bit counter.
	[[nodiscard]] std::uint32_t qeiCount() const;
	/// DacOpen (34/20), DacClose (34/21).
	void dacOpen(DacTrigger trigger) const;
	void dacClose() const;
	/// DacSetDelayTime (34/22): 0..1023 in 1/96 us.
	void dacSetDelay(std::uint16_t ticks) const;
	/// DacSetData (34/11): 0..4095 = 0..3.3 V.
	void dacWrite(std::uint16_t value) const;
	/// DacStartConv (34/0).
	void dacStartConversion() const;
	/// AdcOpen (35/40), AdcClose (35/41).
	void adcOpen(AdcInputMode mode) const;
	void adcClose() const;
	/// AdcConfigSampleModule (35/42): sample @p module (0..15) converts
	/// @p channel (0..15), software trigger. The manuals' own call is
	/// (0, 0) ("reserved, set 0").
	void adcConfigureModule(unsigned module, unsigned channel) const;
	/// AdcStartConv (35/12): start the modules of @p moduleMask (bits 0..15).
	void adcStart(std::uint16_t moduleMask) const;
	/// AdcGetDataValidFlag (35/17): the modules of @p moduleMask whose
	/// result is valid.
	[[nodiscard]] std::uint16_t adcValidFlags(std::uint16_t moduleMask) const;
	/// AdcGetConvData (35/15): the result of @p module (0..4095).
	[[nodiscard]] std::uint16_t adcRead(unsigned module) const;
	/// adcStart, adcValidFlags until valid (at most 100 polls), adcRead.
	[[nodiscard]] std::uint16_t adcConvert(unsigned module = kAdcDefaultModule) const;

	// ---- MDIO (81, ver. 050) ----

	/// Reads register @p reg (0..31) of the PHY at @p phy (0..31).
	[[nodiscard]] std::uint16_t mdioRead(unsigned phy, unsigned reg) const;
	void mdioWrite(unsigned phy, unsigned reg, std::uint16_t value) const;

private:
	Device *dev_;
};

} // namespace ecmxf
