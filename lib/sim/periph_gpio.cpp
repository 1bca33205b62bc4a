// SPDX-License-Identifier: MIT
//
// periph_gpio.cpp - the 20 GPIO lines: pad levels per mode and pull, the
// input buffer with its debounce filter, edge interrupts.

#include "periph_blocks.hpp"

namespace ecmxf::sim::periph {

namespace {

constexpr std::uint64_t kFastClockHz = 192'000'000; // debounce source 0
constexpr std::uint64_t kSlowClockHz = 10'000;      // debounce source 1

constexpr bool has(std::uint32_t mask, unsigned line) { return (mask >> line & 1u) != 0; }

} // namespace

void Gpio::reset()
{
	for (Line &l : lines_) {
		const bool driven = l.driven, level = l.drivenLevel;
		l = Line{};
		l.driven = driven;
		l.drivenLevel = level;
	}
	flags_ = 0;
	dbCycle_ = 0;
	dbLowSpeed_ = false;
	// The input buffers start at the pad level without an edge.
	for (unsigned i = 0; i < kLines; i++) {
		lines_[i].seen = lines_[i].lastPad = pad(i);
	}
}

bool Gpio::pad(unsigned line) const
{
	const Line &l = lines_[line];
	// What the pin floats to when nobody drives it: the pull, else low.
	const bool idle = l.pull == GpioPull::Up;
	const bool outside = l.driven ? l.drivenLevel : idle;
	switch (l.mode) {
	case GpioMode::Output:
		return l.latch;
	case GpioMode::OpenDrain:
		return l.latch ? outside : false;
	case GpioMode::Quasi:
		// latch 1 = weak internal pull-up that outside drivers override
		if (!l.latch)
			return false;
		return l.driven ? l.drivenLevel : true;
	case GpioMode::Input:
		break;
	}
	return outside;
}

void Gpio::accept(unsigned line, bool level)
{
	Line &l = lines_[line];
	const bool was = l.seen;
	l.seen = level;
	if (was == level)
		return;
	const bool rising = level;
	switch (l.irq) {
	case GpioIrq::BothEdges:
		flags_ |= 1u << line;
		break;
	case GpioIrq::Rising:
		if (rising)
			flags_ |= 1u << line;
		break;
	case GpioIrq::Falling:
		if (!rising)
			flags_ |= 1u << line;
		break;
	case GpioIrq::Disabled:
		break;
	}
}

// Something that may change the pad level happened.
void Gpio::settle(unsigned line)
{
	Line &l = lines_[line];
	const bool p = pad(line);
	if (p != l.lastPad) {
		l.lastPad = p;
		l.stable = Nanos{ 0 }; // a new level restarts the debounce count
	}
	if (!l.debounce || p == l.seen) {
		l.stable = Nanos{ 0 };
		accept(line, p);
	}
}

void Gpio::setMode(std::uint32_t mask, GpioMode mode, GpioPull pull)
{
	for (unsigned i = 0; i < kLines; i++) {
		if (!has(mask, i))
			continue;
		lines_[i].mode = mode;
		lines_[i].pull = pull;
		settle(i);
	}
}

void Gpio::setDebounce(std::uint32_t mask, bool enable)
{
	for (unsigned i = 0; i < kLines; i++) {
		if (!has(mask, i))
			continue;
		lines_[i].debounce = enable;
		settle(i);
	}
}

void Gpio::setDebounceClock(unsigned cycle, bool lowSpeed)
{
	dbCycle_ = cycle & 0x0Fu;
	dbLowSpeed_ = lowSpeed;
}

Nanos Gpio::debounceTime() const
{
	const std::uint64_t hz = dbLowSpeed_ ? kSlowClockHz : kFastClockHz;
	const std::uint64_t clocks = std::uint64_t{ 2 } << dbCycle_; // two samples
	const std::uint64_t ns = (clocks * 1'000'000'000u + hz - 1) / hz;
	return Nanos{ static_cast<Nanos::rep>(ns) };
}

void Gpio::setIrq(unsigned line, GpioIrq type)
{
	if (line < kLines)
		lines_[line].irq = type;
}

void Gpio::clearFlags(std::uint32_t mask) { flags_ &= ~mask; }

void Gpio::setOutputs(std::uint32_t mask, std::uint32_t values)
{
	for (unsigned i = 0; i < kLines; i++) {
		if (!has(mask, i))
			continue;
		lines_[i].latch = has(values, i);
		settle(i);
	}
}

std::uint32_t Gpio::inputs() const
{
	std::uint32_t v = 0;
	for (unsigned i = 0; i < kLines; i++) {
		if (lines_[i].seen)
			v |= 1u << i;
	}
	return v;
}

void Gpio::advance(Nanos dt)
{
	if (dt <= Nanos{ 0 })
		return;
	const Nanos need = debounceTime();
	for (unsigned i = 0; i < kLines; i++) {
		Line &l = lines_[i];
		if (!l.debounce || l.lastPad == l.seen)
			continue;
		l.stable += dt;
		if (l.stable >= need) {
			l.stable = Nanos{ 0 };
			accept(i, l.lastPad);
		}
	}
}

void Gpio::drive(unsigned line, bool level)
{
	Line &l = lines_[line];
	l.driven = true;
	l.drivenLevel = level;
	settle(line);
}

} // namespace ecmxf::sim::periph
