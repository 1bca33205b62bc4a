// SPDX-License-Identifier: MIT
/**
 * @file sim_channel.hpp
 * @brief The in-process simulator as a ByteChannel ("sim:" URIs).
 *
 * SimChannel owns one simulated chip (ecmxf::sim::Chip) and answers
 * exchanges with it in the calling thread. Time is the chip's virtual
 * time: waiting and sleeping advance it, so a test runs as fast as the CPU
 * allows and is deterministic. The chip is chip() here, and
 * Link::simulator() of the EngineLink that runs over this channel (a
 * Device opened with "sim:").
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <ecmxf/export.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/link/byte_channel.hpp>

namespace ecmxf {

/// Byte channel to an in-process simulated chip.
class ECMXF_EXPORT SimChannel : public ByteChannel
{
public:
	/// A new chip with the network in @p networkFile (empty: the default
	/// network, 2 x EST-584 + 1 x digital I/O) and @p config. Throws when
	/// the network file cannot be read or parsed.
	explicit SimChannel(const std::string &networkFile = {}, sim::ChipConfig config = {});
	/// A new chip with @p network (built in code, e.g. by a test) and
	/// @p config; name() says "sim:<network name>".
	explicit SimChannel(sim::Network network, sim::ChipConfig config = {});
	~SimChannel() override;

	/// Hands @p mosi to the chip, which answers in @p miso at once (the
	/// chip's virtual time moves by the time the transfer takes on the
	/// wire).
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override;
	/// Advances virtual time in steps of readyStep() until the chip is
	/// ready or @p timeout has passed.
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) override;
	/// The chip's virtual time since power-on.
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	/// Advances the chip's virtual time by @p duration.
	void sleepFor(std::chrono::nanoseconds duration) override;

	/// The granularity of waitReady() (10 us).
	static constexpr std::chrono::nanoseconds readyStep() noexcept
	{
		return std::chrono::microseconds(10);
	}

	/// "sim:", or "sim:<network file>".
	[[nodiscard]] std::string name() const override;
	/// The simulated chip, owned by this channel (tests inject faults
	/// and inspect the network through it).
	[[nodiscard]] sim::Chip &chip() noexcept { return *chip_; }

private:
	std::string network_;
	std::unique_ptr<sim::Chip> chip_;
};

} // namespace ecmxf
