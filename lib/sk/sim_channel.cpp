// SPDX-License-Identifier: MIT
// SimBoardChannel: the in-process simulated ECM-SK as a byte channel
// (include/ecmxf/sk/sim_channel.hpp).

#include <ecmxf/sk/sim_channel.hpp>

#include <ecmxf/sim/network.hpp>

namespace ecmxf::sk {

namespace {
constexpr std::chrono::nanoseconds kStep = std::chrono::microseconds(1);
} // namespace

const char *defaultSkNetwork() noexcept
{
	return "name ECM-SK: servo (Drive) + EST-584 (STEP) + digital I/O (IO)\n"
	       "slave servo\n"
	       "slave EST-584\n"
	       "slave dio\n";
}

SimBoardChannel::SimBoardChannel(const std::string &networkFile, BoardConfig config)
	: network_(networkFile),
	  board_(std::make_unique<SimBoard>(networkFile.empty()
						    ? sim::Network::fromText(defaultSkNetwork(), "sk-sim:")
						    : sim::Network::fromFile(networkFile),
					    config))
{
}

SimBoardChannel::~SimBoardChannel() = default;

void SimBoardChannel::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	board_->exchange(mosi, miso);
}

bool SimBoardChannel::waitReady(std::chrono::nanoseconds timeout)
{
	const auto end = board_->now() + timeout;
	while (board_->busy()) {
		if (board_->now() >= end)
			return false;
		board_->advance(std::min(kStep, end - board_->now()));
	}
	return true;
}

std::chrono::nanoseconds SimBoardChannel::now() const
{
	return board_->now();
}

void SimBoardChannel::sleepFor(std::chrono::nanoseconds duration)
{
	board_->advance(duration);
}

std::string SimBoardChannel::name() const
{
	return "sk-sim:" + network_;
}

} // namespace ecmxf::sk
