// SPDX-License-Identifier: MIT
/**
 * @file byte_channel.hpp
 * @brief A byte channel: SPI packets to one ECM-XF chip and its INT0
 *        "ready" line, with no knowledge of the protocol.
 *
 * The engine link (engine_link.hpp) runs the shared protocol core over a
 * ByteChannel: framing, check words, the one-exchange-late answers,
 * retries and async tracking are all the engine's. A channel only moves
 * bytes and reports readiness; it knows nothing of what is behind it (the
 * in-process simulator's chip is SimChannel::chip(), and through a Link,
 * Link::simulator()). Implementations:
 *  - SimChannel (sim_channel.hpp): the in-process simulated chip, virtual time;
 *  - UnixChannel (unix_channel.hpp): an `ecmxf-sim --socket` server;
 *  - SpidevChannel (spidev_channel.hpp): /dev/spidevB.C + libgpiod INT0/INT1;
 *  - HidrawChannel (hidraw_channel.hpp): the ECM-SK on USB, one HID report
 *    each way per frame.
 * Documentation/architecture.rst, "How to add a channel".
 *
 * Thread safety: a channel is not thread-safe; its one owner (an
 * EngineLink) calls it from one thread at a time.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>

#include <ecmxf/export.hpp>

namespace ecmxf {

/// Abstract byte channel to one chip.
class ECMXF_EXPORT ByteChannel
{
public:
	ByteChannel() = default;
	ByteChannel(const ByteChannel &) = delete;
	ByteChannel &operator=(const ByteChannel &) = delete;
	virtual ~ByteChannel();

	/// One full-duplex SPI transfer: clocks out @p mosi and fills @p miso
	/// with the bytes clocked in. Both spans have the same size (the
	/// current packet size) and belong to the caller; the channel keeps no
	/// reference to them after returning. Blocks for the duration of the
	/// transfer. Throws ecmxf::Error when the transfer cannot be made at
	/// all (a corrupted transfer is not an error here: the protocol core
	/// detects it from the check word).
	virtual void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) = 0;

	/// Waits until the chip signals "ready" on INT0 (it has processed the
	/// previous packet), for at most @p timeout on the channel's clock.
	/// Returns true at once when the chip is ready, false when @p timeout
	/// passed without it (then now() has moved on by at least @p timeout).
	/// Blocks (real channels) or advances virtual time (simulator). Throws
	/// ecmxf::Error when the line cannot be read at all.
	[[nodiscard]] virtual bool waitReady(std::chrono::nanoseconds timeout) = 0;

	/// The channel's clock, monotonic, any origin: virtual time for the
	/// simulator, std::chrono::steady_clock otherwise. The protocol core's
	/// deadlines are measured on it.
	[[nodiscard]] virtual std::chrono::nanoseconds now() const = 0;

	/// Lets @p duration pass on the channel's clock: sleeps (real
	/// channels; the default implementation sleeps on the steady clock)
	/// or advances virtual time (simulator). Non-positive durations return
	/// at once.
	virtual void sleepFor(std::chrono::nanoseconds duration);
	/// Sleeps until now() reads @p deadline (an absolute time on the
	/// channel's clock); returns at once when it has passed. The default
	/// sleeps for deadline - now(); a real channel overrides it with one
	/// absolute sleep (clock_nanosleep(TIMER_ABSTIME)), the cyclic loop's
	/// one system call per cycle.
	virtual void sleepUntil(std::chrono::nanoseconds deadline);
	/// A time not later than now(), and not older than the channel's
	/// last exchange, ready wait or sleep: what the channel learned
	/// without reading the clock (the time of INT0's ready edge, the
	/// deadline of a sleep), for the protocol core's bookkeeping between
	/// exchanges. Must not be used to start a timeout (it may lag by as
	/// much as the caller spent since). The default is now().
	[[nodiscard]] virtual std::chrono::nanoseconds coarseNow() const { return now(); }

	/// How messages name the channel, e.g. "sim:", "unix:/tmp/s",
	/// "/dev/spidev0.0".
	[[nodiscard]] virtual std::string name() const = 0;
};

} // namespace ecmxf
