// SPDX-License-Identifier: MIT
/**
 * @file transport.hpp
 * @brief The byte-level link between the library and one ECM-XF chip.
 *
 * A Transport moves SPI packets and reports the chip's INT0 "ready" line;
 * it knows nothing about the protocol. The Device runs the protocol core
 * (framing, check words, the one-exchange-late answers, retries, async
 * tracking) on top of it. Implementations: the in-process simulator
 * (SimTransport, include/ecmxf/sim_transport.hpp); spidev and the kernel
 * module's /dev/ecmxfN are planned.
 *
 * Thread safety: a Transport is not thread-safe; its one owner (a Device)
 * calls it from one thread at a time.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <span>

#include <ecmxf/export.hpp>

namespace ecmxf {

/// Abstract byte-level link to one chip.
class ECMXF_EXPORT Transport
{
public:
	Transport() = default;
	Transport(const Transport &) = delete;
	Transport &operator=(const Transport &) = delete;
	virtual ~Transport();

	/// One full-duplex SPI transfer: clocks out @p mosi and fills @p miso
	/// with the bytes clocked in. Both spans have the same size (the
	/// current packet size) and belong to the caller; the transport keeps
	/// no reference to them after returning. Blocks for the duration of the
	/// transfer. Throws ecmxf::Error when the transfer cannot be made at
	/// all (a corrupted transfer is not an error here: the protocol core
	/// detects it from the check word).
	virtual void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) = 0;

	/// Waits until the chip signals "ready" on INT0 (it has processed the
	/// previous packet), for at most @p timeout on the transport's clock.
	/// Returns true at once when the chip is ready, false when @p timeout
	/// passed without it (then now() has moved on by at least @p timeout).
	/// Blocks (real transports) or advances virtual time (simulator).
	[[nodiscard]] virtual bool waitReady(std::chrono::nanoseconds timeout) = 0;

	/// The transport's clock, monotonic, any origin: virtual time for the
	/// simulator, std::chrono::steady_clock otherwise. The protocol core's
	/// deadlines are measured on it.
	[[nodiscard]] virtual std::chrono::nanoseconds now() const = 0;

	/// Lets @p duration pass on the transport's clock: sleeps (real
	/// transports; the default implementation sleeps on the steady clock)
	/// or advances virtual time (simulator). Non-positive durations return
	/// at once.
	virtual void sleepFor(std::chrono::nanoseconds duration);
};

} // namespace ecmxf
