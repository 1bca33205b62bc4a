// SPDX-License-Identifier: MIT
//
// periph_adc.cpp - the 12-bit ADC: sample modules bound to channels, one
// converter that works through the started modules in order, a valid flag
// per module.

#include "periph_blocks.hpp"

#include <algorithm>

namespace ecmxf::sim::periph {

void Adc::reset()
{
	open_ = false;
	differential_ = false;
	for (unsigned m = 0; m < kModules; m++)
		channel_[m] = static_cast<std::uint8_t>(m);
	data_.fill(0);
	valid_ = 0;
	queue_.clear();
	left_ = Nanos{ 0 };
}

void Adc::open(bool differential)
{
	open_ = true;
	differential_ = differential;
}

void Adc::close()
{
	open_ = false;
	valid_ = 0;
	queue_.clear();
	left_ = Nanos{ 0 };
}

void Adc::configModule(unsigned module, unsigned channel)
{
	channel_[module] = static_cast<std::uint8_t>(channel);
}

void Adc::start(std::uint32_t mask)
{
	if (!open_)
		return;
	for (unsigned m = 0; m < kModules; m++) {
		if ((mask >> m & 1u) == 0)
			continue;
		valid_ &= ~(1u << m); // the flag now belongs to this conversion
		if (std::find(queue_.begin(), queue_.end(), m) != queue_.end())
			continue;
		if (queue_.empty())
			left_ = kConversionTime;
		queue_.push_back(m);
	}
}

std::uint16_t Adc::take(unsigned module)
{
	valid_ &= ~(1u << module);
	return data_[module];
}

std::uint16_t Adc::sample(unsigned channel) const
{
	if (!differential_)
		return input_[channel];
	// Pairs (0,1), (2,3)...: -Vref..+Vref maps to 0..4095, 0 V to 2048.
	const unsigned pos = channel & ~1u;
	const int diff = int{ input_[pos] } - int{ input_[pos + 1] };
	return static_cast<std::uint16_t>(std::clamp((diff + 4096) / 2, 0, int{ kMaxData }));
}

void Adc::advance(Nanos dt)
{
	while (dt > Nanos{ 0 } && !queue_.empty()) {
		const Nanos used = std::min(dt, left_);
		left_ -= used;
		dt -= used;
		if (left_ > Nanos{ 0 })
			break;
		const unsigned m = queue_.front();
		queue_.pop_front();
		data_[m] = sample(channel_[m]);
		valid_ |= 1u << m;
		left_ = kConversionTime;
	}
}

void Adc::setInput(unsigned ch, std::uint16_t raw) { input_[ch] = std::min(raw, kMaxData); }

} // namespace ecmxf::sim::periph
