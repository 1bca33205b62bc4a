// SPDX-License-Identifier: MIT
// SimChannel: the in-process simulated chip as a ByteChannel
// (see include/ecmxf/link/sim_channel.hpp).

#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/sim/network.hpp>

#include <algorithm>
#include <utility>

namespace ecmxf {

SimChannel::SimChannel(const std::string &networkFile, sim::ChipConfig config)
	: network_(networkFile), chip_(std::make_unique<sim::Chip>(networkFile, std::move(config)))
{
}

SimChannel::SimChannel(sim::Network network, sim::ChipConfig config)
	: network_(network.name()), chip_(std::make_unique<sim::Chip>(std::move(network), std::move(config)))
{
}

std::string SimChannel::name() const
{
	return "sim:" + network_;
}

SimChannel::~SimChannel() = default;

void SimChannel::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	chip_->exchange(mosi, miso);
}

bool SimChannel::waitReady(std::chrono::nanoseconds timeout)
{
	const std::chrono::nanoseconds end = chip_->now() + std::max(timeout, std::chrono::nanoseconds::zero());

	while (!chip_->ready()) {
		const std::chrono::nanoseconds t = chip_->now();
		if (t >= end)
			return false;
		chip_->advance(std::min(readyStep(), end - t));
	}
	return true;
}

std::chrono::nanoseconds SimChannel::now() const
{
	return chip_->now();
}

void SimChannel::sleepFor(std::chrono::nanoseconds duration)
{
	if (duration > std::chrono::nanoseconds::zero())
		chip_->advance(duration);
}

} // namespace ecmxf
