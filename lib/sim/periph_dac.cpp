// SPDX-License-Identifier: MIT
//
// periph_dac.cpp - the 12-bit DAC: a data register, a trigger source and a
// settling delay after which the converted value appears on the output.

#include "periph_blocks.hpp"

namespace ecmxf::sim::periph {

void Dac::reset()
{
	open_ = false;
	trigger_ = DacTrigger::WriteData;
	delay_ = 0;
	data_ = 0;
	output_ = 0;
	pending_ = false;
	pendingValue_ = 0;
	pendingLeft_ = Nanos{ 0 };
}

bool Dac::levelActive() const
{
	return (trigger_ == DacTrigger::PinLow && !pin_) ||
	       (trigger_ == DacTrigger::PinHigh && pin_);
}

void Dac::open(DacTrigger trigger)
{
	open_ = true;
	trigger_ = trigger;
	pending_ = false;
	if (levelActive())
		this->trigger();
}

void Dac::close()
{
	open_ = false;
	pending_ = false;
	output_ = 0;
}

void Dac::trigger()
{
	if (!open_)
		return;
	// 1/96 us per tick, rounded up to whole nanoseconds
	const auto ns = (std::uint64_t{ delay_ } * 1000u + 95u) / 96u;
	if (ns == 0) {
		output_ = data_;
		pending_ = false;
		return;
	}
	pending_ = true;
	pendingValue_ = data_;
	pendingLeft_ = Nanos{ static_cast<Nanos::rep>(ns) };
}

void Dac::setData(std::uint16_t value)
{
	data_ = value;
	if (trigger_ == DacTrigger::WriteData || levelActive())
		trigger();
}

void Dac::startConversion()
{
	if (trigger_ == DacTrigger::Software)
		trigger();
}

void Dac::advance(Nanos dt)
{
	if (!pending_ || dt <= Nanos{ 0 })
		return;
	pendingLeft_ -= dt;
	if (pendingLeft_ <= Nanos{ 0 }) {
		output_ = pendingValue_;
		pending_ = false;
	}
}

void Dac::setTriggerPin(bool level)
{
	const bool was = pin_;
	pin_ = level;
	if (was == level)
		return;
	if ((trigger_ == DacTrigger::PinRising && level) ||
	    (trigger_ == DacTrigger::PinFalling && !level) || levelActive())
		trigger();
}

} // namespace ecmxf::sim::periph
