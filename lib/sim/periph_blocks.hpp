// SPDX-License-Identifier: MIT
//
// periph_blocks.hpp - the hardware models behind Peripherals: the GPIO
// port, the quadrature encoder interface, the DAC, the ADC and the MDIO
// bus with its PHYs.
//
// These classes know nothing about packets: periph.cpp decodes the
// commands (the layouts of the manuals) and calls them. Each models what a
// Cortex-M4 microcontroller peripheral of the kind the ECM-XF is built on
// does (192 MHz core clock, 10 kHz low-speed clock, 12-bit converters);
// where the manuals are silent the choices are written down in
// Documentation/sim-peripherals.rst.
//
// Every block keeps two kinds of state: the chip's own (registers, flags,
// modes), which reset() restores to power-on values, and the outside world
// (levels driven onto pins, analog voltages, the encoder shaft, the PHY),
// which a chip reset does not touch.

#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>

namespace ecmxf::sim::periph {

using Nanos = std::chrono::nanoseconds;

// ---------------------------------------------------------------- GPIO ---

/// GPIO_CONFIG_SET param 0/8, command data 2.
enum class GpioMode : std::uint8_t { Input = 0, Output = 1, OpenDrain = 2, Quasi = 3 };
/// GPIO_CONFIG_SET param 0/8, command data 3.
enum class GpioPull : std::uint8_t { None = 0, Up = 1, Down = 2 };
/// GPIO_CONFIG_SET param 1, command data 1.
enum class GpioIrq : std::uint8_t { Disabled = 0, BothEdges = 1, Falling = 2, Rising = 3 };

/// The 20 GPIO lines. Line masks are bit n = line n.
class Gpio
{
public:
	static constexpr unsigned kLines = 20;
	static constexpr std::uint32_t kAllLines = (1u << kLines) - 1u;

	Gpio() { reset(); }

	/// Power-on state: floating inputs, output latches high, no debounce,
	/// no interrupts, no flags. Levels driven from outside are kept.
	void reset();

	void setMode(std::uint32_t mask, GpioMode mode, GpioPull pull);
	void setDebounce(std::uint32_t mask, bool enable);
	/// @p cycle 0..15: sampling period 2^cycle clocks of 192 MHz, or of
	/// 10 kHz when @p lowSpeed.
	void setDebounceClock(unsigned cycle, bool lowSpeed);
	void setIrq(unsigned line, GpioIrq type);
	void clearFlags(std::uint32_t mask);
	/// Write the output latches of the lines in @p mask.
	void setOutputs(std::uint32_t mask, std::uint32_t values);

	/// Input buffer of every line (after debounce), bit n = line n.
	[[nodiscard]] std::uint32_t inputs() const;
	/// Interrupt flags, bit n = line n.
	[[nodiscard]] std::uint32_t flags() const { return flags_; }
	/// Time a level must stay stable on a debounced line to be accepted:
	/// two sampling periods.
	[[nodiscard]] Nanos debounceTime() const;

	void advance(Nanos dt);

	// outside world
	void drive(unsigned line, bool level);
	/// Electrical level of the pad.
	[[nodiscard]] bool pad(unsigned line) const;

private:
	struct Line {
		GpioMode mode = GpioMode::Input;
		GpioPull pull = GpioPull::None;
		GpioIrq irq = GpioIrq::Disabled;
		bool latch = true;      // output data register (resets to 1)
		bool debounce = false;
		bool seen = false;      // input buffer after debounce
		bool lastPad = false;   // pad level at the last settle()
		Nanos stable{ 0 };      // how long lastPad != seen has held
		bool driven = false;    // outside world drives the pin
		bool drivenLevel = false;
	};

	void settle(unsigned line);
	void accept(unsigned line, bool level);

	std::array<Line, kLines> lines_{};
	std::uint32_t flags_ = 0;
	unsigned dbCycle_ = 0;
	bool dbLowSpeed_ = false;
};

// ----------------------------------------------------------------- QEI ---

/// QEI_FUNC_OP param 4 data: 0x000, 0x100, 0x200, 0x300 >> 8.
enum class QeiMode : std::uint8_t { X4Free = 0, X2Free = 1, X4Compare = 2, X2Compare = 3 };

/// The quadrature encoder interface: a 32-bit up/down counter.
class Qei
{
public:
	static constexpr std::uint8_t kFlagIndex = 1u << 4;
	static constexpr std::uint8_t kFlagCompare = 1u << 5;
	static constexpr std::uint8_t kFlagOverflow = 1u << 6;

	Qei() { reset(); }

	/// Power-on state: X4 free-counting, stopped, counter 0, no flags.
	void reset();
	/// Select the mode; stops counting and clears the counter and flags.
	void open(QeiMode mode);
	void start() { running_ = true; }
	void stop() { running_ = false; }
	[[nodiscard]] std::uint32_t count() const { return count_; }
	[[nodiscard]] std::uint8_t flags() const { return flags_; }
	void clearFlags() { flags_ = 0; }

	// outside world
	/// The shaft moves by @p edges quadrature edges (X4 counts).
	void move(std::int64_t edges);
	void index();

private:
	QeiMode mode_ = QeiMode::X4Free;
	bool running_ = false;
	std::uint32_t count_ = 0;
	std::uint8_t flags_ = 0;
	std::int64_t shaft_ = 0; // outside world: edges from the start
};

// ----------------------------------------------------------------- DAC ---

/// DAC_FUNC_OP param 20 data.
enum class DacTrigger : std::uint16_t {
	WriteData = 0x0000,
	Software = 0x0010,
	PinLow = 0x0030,
	PinHigh = 0x1030,
	PinRising = 0x2030,
	PinFalling = 0x3030,
};

/// The 12-bit DAC (one channel).
class Dac
{
public:
	static constexpr unsigned kChannels = 1;
	static constexpr std::uint16_t kMaxData = 4095;
	static constexpr std::uint32_t kMaxDelay = 1023; // 1/96 us units

	Dac() { reset(); }

	/// Power-on state: closed, output 0, data 0, delay 0.
	void reset();
	void open(DacTrigger trigger);
	/// Disable: the output returns to 0, a pending conversion is dropped.
	void close();
	void setDelay(std::uint32_t ticks) { delay_ = ticks; }
	/// Load the data register; converts at once in WriteData mode.
	void setData(std::uint16_t value);
	/// Software trigger; converts in Software mode only.
	void startConversion();
	[[nodiscard]] std::uint16_t output() const { return output_; }
	void advance(Nanos dt);

	// outside world
	void setTriggerPin(bool level);

private:
	void trigger();
	[[nodiscard]] bool levelActive() const;

	bool open_ = false;
	DacTrigger trigger_ = DacTrigger::WriteData;
	std::uint32_t delay_ = 0;
	std::uint16_t data_ = 0;
	std::uint16_t output_ = 0;
	bool pending_ = false;
	std::uint16_t pendingValue_ = 0;
	Nanos pendingLeft_{ 0 };
	bool pin_ = false; // outside world: DAC_ST
};

// ----------------------------------------------------------------- ADC ---

/// The 12-bit ADC: 16 analog channels, 16 sample modules sharing one
/// converter.
class Adc
{
public:
	static constexpr unsigned kChannels = 16;
	static constexpr unsigned kModules = 16;
	static constexpr std::uint16_t kMaxData = 4095;
	/// One sample-and-convert of one module.
	static constexpr Nanos kConversionTime{ 1000 };

	Adc() { reset(); }

	/// Power-on state: closed, single-ended, module n = software trigger of
	/// channel n, nothing valid. Analog input levels are kept.
	void reset();
	void open(bool differential);
	void close();
	void configModule(unsigned module, unsigned channel);
	/// Queue a conversion of every module in @p mask (ignored when closed).
	void start(std::uint32_t mask);
	[[nodiscard]] std::uint32_t valid() const { return valid_; }
	/// The module's last result; reading clears its valid flag.
	std::uint16_t take(unsigned module);
	void advance(Nanos dt);

	// outside world
	void setInput(unsigned ch, std::uint16_t raw);

private:
	[[nodiscard]] std::uint16_t sample(unsigned channel) const;

	bool open_ = false;
	bool differential_ = false;
	std::array<std::uint8_t, kModules> channel_{};
	std::array<std::uint16_t, kModules> data_{};
	std::uint32_t valid_ = 0;
	std::deque<unsigned> queue_;
	Nanos left_{ 0 }; // time left for queue_.front()
	std::array<std::uint16_t, kChannels> input_{}; // outside world
};

// ---------------------------------------------------------------- MDIO ---

/// The MDIO bus: 32 PHY addresses of 32 registers (IEEE 802.3 clause 22).
/// The ECM-XF's own PHY answers at address 1; absent PHYs read 0xFFFF.
class Mdio
{
public:
	static constexpr unsigned kAddresses = 32;
	static constexpr unsigned kRegisters = 32;
	static constexpr unsigned kChipPhy = 1;
	static constexpr std::uint16_t kAbsent = 0xFFFF;

	Mdio();
	[[nodiscard]] std::uint16_t read(unsigned phy, unsigned reg) const;
	/// Writes to absent PHYs and to read-only registers (1, 2, 3) are
	/// lost; BMCR bit 15 restores the PHY's defaults and self-clears.
	void write(unsigned phy, unsigned reg, std::uint16_t value);
	/// Outside world: set any register, making the PHY present.
	void poke(unsigned phy, unsigned reg, std::uint16_t value);

private:
	struct Phy {
		bool present = false;
		std::array<std::uint16_t, kRegisters> regs{};
	};
	static Phy defaults();

	std::array<Phy, kAddresses> phys_{};
};

} // namespace ecmxf::sim::periph
