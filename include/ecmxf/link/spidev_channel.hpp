// SPDX-License-Identifier: MIT
/**
 * @file spidev_channel.hpp
 * @brief The userspace SPI channel: Linux spidev for the bytes, libgpiod
 *        for the chip's INT0 (ready) and INT1 (event) lines.
 *
 * URI: "spidev:/dev/spidevB.C[?int0=<chip>:<line>][&int1=<chip>:<line>]
 * [&speed=<Hz>][&mode=0..3][&ready=high|low]" (see device_uri.hpp and
 * Documentation/library.rst). A byte channel: the engine link runs the
 * protocol core on top of it.
 *
 * The channel makes its system calls through a SpidevBackend, so that
 * its logic (INT0 waits, the 150 us fallback, short transfers, error
 * texts) can be tested with a fake backend; openSpidevBackend() gives the
 * real one (open/ioctl on the spidev node, libgpiod v1 for the lines).
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>

namespace ecmxf {

/// A GPIO line: the chip as libgpiod's gpiod_chip_open_lookup() accepts it
/// (a name like "gpiochip0", a path, a label or a number) and the line
/// offset on that chip.
struct GpioLineSpec {
	std::string chip;
	unsigned line = 0;
};

/// Everything a spidev channel needs to know.
struct SpidevOptions {
	/// Highest SPI clock of the chip (manual: 96 Mbit/s).
	static constexpr std::uint32_t kMaxSpeedHz = 96'000'000;
	/// Default clock: half the maximum, which common SPI controllers can
	/// divide down to and which leaves margin on board wiring.
	static constexpr std::uint32_t kDefaultSpeedHz = 48'000'000;
	/// Without an INT0 line: the time the chip may need to process a
	/// packet (manual: typically < 150 us), waited after each exchange.
	static constexpr std::chrono::nanoseconds kFallbackWait = std::chrono::microseconds(150);

	std::string device;                  ///< the spidev node, e.g. /dev/spidev0.0
	std::uint32_t speedHz = kDefaultSpeedHz; ///< 1..kMaxSpeedHz
	std::uint8_t mode = 0;               ///< SPI mode 0..3; the chip uses mode 0 (CPOL=0, CPHA=0)
	std::optional<GpioLineSpec> int0;    ///< the ready line; none: wait kFallbackWait
	std::optional<GpioLineSpec> int1;    ///< the event line
	/// INT0 level that means "ready": high by default (manual ver. 050;
	/// ECAT_INT_SET_ENABLE parameter bit 1 inverts it).
	bool readyHigh = true;
	/// INT1 level that means "event pending": low by default.
	bool int1ActiveLow = true;
};

/// Which interrupt line.
enum class IntLine : std::uint8_t { Int0, Int1 };

/// The system calls of a spidev channel. Every call reports failure as
/// a negative errno and never throws, so that SpidevChannel can name
/// what failed; the real implementation is openSpidevBackend().
class ECMXF_EXPORT SpidevBackend
{
public:
	SpidevBackend() = default;
	SpidevBackend(const SpidevBackend &) = delete;
	SpidevBackend &operator=(const SpidevBackend &) = delete;
	virtual ~SpidevBackend();

	/// One full-duplex transfer (SPI_IOC_MESSAGE(1)) of mosi.size() bytes.
	/// Returns the number of bytes transferred or a negative errno.
	virtual int transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) noexcept = 0;
	/// Is @p line wired (configured)?
	[[nodiscard]] virtual bool hasLine(IntLine line) const noexcept = 0;
	/// The level of @p line: 1 high, 0 low, or a negative errno.
	virtual int lineValue(IntLine line) noexcept = 0;
	/// Waits for one edge (either direction) on @p line for at most
	/// @p timeout and consumes it: 1 an edge came, 0 timeout, or a
	/// negative errno.
	virtual int waitEdge(IntLine line, std::chrono::nanoseconds timeout) noexcept = 0;
	/// The backend's monotonic clock.
	[[nodiscard]] virtual std::chrono::nanoseconds now() const noexcept = 0;
	/// Lets @p duration pass on that clock.
	virtual void sleepFor(std::chrono::nanoseconds duration) noexcept = 0;
};

/// The real backend: opens the INT0/INT1 lines (libgpiod, edge events on
/// both edges, consumer "ecmxf") and then the spidev node (O_RDWR), and
/// sets mode, 8 bits per word and the clock. Throws ecmxf::Error naming
/// the node or line and the system's reason (errno kept).
[[nodiscard]] ECMXF_EXPORT std::unique_ptr<SpidevBackend> openSpidevBackend(const SpidevOptions &options);

/// Counters of a spidev channel.
struct SpidevStats {
	std::uint64_t exchanges = 0;      ///< transfers made
	std::uint64_t int0Ready = 0;      ///< waitReady() calls that found or saw INT0 ready
	std::uint64_t int0Edges = 0;      ///< INT0 edges consumed
	std::uint64_t int0Timeouts = 0;   ///< waitReady() calls that ended without INT0 ready
	std::uint64_t fallbackWaits = 0;  ///< waits of the 150 us fallback (no INT0)
	std::uint64_t int1Events = 0;     ///< waitEvent() calls that found INT1 asserted
};

/// Byte channel over spidev and libgpiod.
class ECMXF_EXPORT SpidevChannel : public ByteChannel
{
public:
	/// Opens the real backend for @p options (openSpidevBackend()).
	explicit SpidevChannel(const SpidevOptions &options);
	/// Runs over @p backend (e.g. a fake in tests); @p options gives the
	/// node name for messages, the INT0/INT1 polarity and the fallback.
	SpidevChannel(std::unique_ptr<SpidevBackend> backend, SpidevOptions options);
	~SpidevChannel() override;

	/// One transfer; throws ecmxf::Error (the errno of the ioctl, or EIO
	/// for a short transfer) naming the node.
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override;
	/// With INT0: checks the level, then waits for edges until the level
	/// says ready or @p timeout has passed. Without INT0: ready once
	/// kFallbackWait has passed since the end of the last exchange (waits
	/// for the rest of it, or for @p timeout if shorter). Throws
	/// ecmxf::Error when the line cannot be read.
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) override;
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	void sleepFor(std::chrono::nanoseconds duration) override;
	/// "spidev:<node>".
	[[nodiscard]] std::string name() const override;

	/// Waits until INT1 says an event is pending (the chip's IntFlag &
	/// IntEnable is non-zero), for at most @p timeout; true when it is.
	/// Throws ecmxf::Error (EOPNOTSUPP) when no INT1 line is configured.
	[[nodiscard]] bool waitEvent(std::chrono::nanoseconds timeout);

	[[nodiscard]] const SpidevOptions &options() const noexcept { return options_; }
	[[nodiscard]] const SpidevStats &stats() const noexcept { return stats_; }

private:
	bool lineActive(IntLine line, bool activeHigh);

	std::unique_ptr<SpidevBackend> backend_;
	SpidevOptions options_;
	SpidevStats stats_;
	std::chrono::nanoseconds lastExchangeEnd_{ 0 };
	bool exchanged_ = false;
};

} // namespace ecmxf
