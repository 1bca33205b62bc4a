// SPDX-License-Identifier: MIT
/**
 * @file sim_channel.hpp
 * @brief The in-process simulated ECM-SK as a ByteChannel ("sk-sim:").
 *
 * Owns one SimBoard and answers each exchange with it in the calling
 * thread; waiting for Busy to fall and sleeping advance the board's
 * virtual time.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/sim/sk_board.hpp>

namespace ecmxf::sk {

/// Byte channel to an in-process simulated ECM-SK.
class ECMXF_EXPORT SimBoardChannel : public ByteChannel
{
public:
	/// A board with the network in @p networkFile (empty: Drive (servo) +
	/// STEP (EST-584) + IO) and @p config. Throws std::runtime_error /
	/// std::invalid_argument for a bad file or setting.
	explicit SimBoardChannel(const std::string &networkFile = {}, BoardConfig config = {});
	~SimBoardChannel() override;

	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override;
	/// Advances virtual time in steps of 1 us until Busy is low, for at
	/// most @p timeout.
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) override;
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	void sleepFor(std::chrono::nanoseconds duration) override;
	/// "sk-sim:" or "sk-sim:<network file>".
	[[nodiscard]] std::string name() const override;

	[[nodiscard]] SimBoard &board() noexcept { return *board_; }

private:
	std::string network_;
	std::unique_ptr<SimBoard> board_;
};

/// The network of "sk-sim:" without a file: a servo (Drive), an EST-584
/// (STEP) and a digital I/O terminal (IO).
[[nodiscard]] ECMXF_EXPORT const char *defaultSkNetwork() noexcept;

} // namespace ecmxf::sk
