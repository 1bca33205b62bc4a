// SPDX-License-Identifier: MIT
// SimTransport: the in-process simulated chip as a Transport
// (see include/ecmxf/link/sim_transport.hpp).

#include <ecmxf/link/sim_transport.hpp>

#include <algorithm>
#include <utility>

namespace ecmxf {

SimTransport::SimTransport(const std::string &networkFile, sim::ChipConfig config)
	: chip_(std::make_unique<sim::Chip>(networkFile, std::move(config)))
{
}

SimTransport::~SimTransport() = default;

void SimTransport::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	chip_->exchange(mosi, miso);
}

bool SimTransport::waitReady(std::chrono::nanoseconds timeout)
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

std::chrono::nanoseconds SimTransport::now() const
{
	return chip_->now();
}

void SimTransport::sleepFor(std::chrono::nanoseconds duration)
{
	if (duration > std::chrono::nanoseconds::zero())
		chip_->advance(duration);
}

} // namespace ecmxf
