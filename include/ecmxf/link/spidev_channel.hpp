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
	/// With INT0: how long a wait for INT0's ready edge lasts before the
	/// level is read once (a missed edge; a chip that did not go busy).
	static constexpr std::chrono::nanoseconds kEdgeGrace = std::chrono::microseconds(300);
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
	/// Waits for one edge on @p line for at most @p timeout and consumes
	/// it: 1 an edge came, 0 timeout, or a negative errno. (INT1: either
	/// direction; INT0: the real backend asks for the ready edge only.)
	virtual int waitEdge(IntLine line, std::chrono::nanoseconds timeout) noexcept = 0;
	/// What readEdges() saw.
	struct Edges {
		unsigned count = 0;  ///< edge events read
		bool high = false;   ///< the line's level after the last of them
		/// when the last happened, on now()'s clock; zero: not known
		std::chrono::nanoseconds time{ 0 };
	};
	/// Reads every edge event queued on @p line, first waiting up to
	/// @p timeout for one to come (zero: no wait, only what is queued).
	/// Returns the number read (0: none came in time) or a negative
	/// errno; @p edges tells the last. The real backend: one read() of
	/// the line's event fd (non-blocking), after one ppoll() when
	/// @p timeout is positive. The default builds it from waitEdge() and
	/// lineValue() (backends that predate it).
	virtual int readEdges(IntLine line, std::chrono::nanoseconds timeout, Edges &edges) noexcept;
	/// The backend's monotonic clock.
	[[nodiscard]] virtual std::chrono::nanoseconds now() const noexcept = 0;
	/// Lets @p duration pass on that clock.
	virtual void sleepFor(std::chrono::nanoseconds duration) noexcept = 0;
	/// Sleeps until now() reads @p deadline. The real backend: one
	/// absolute clock_nanosleep(); the default sleeps deadline - now().
	virtual void sleepUntil(std::chrono::nanoseconds deadline) noexcept;
};

/// The real backend: opens the INT0/INT1 lines (libgpiod, consumer
/// "ecmxf"; INT0 with events on its ready edge only, rising for ready=high,
/// falling for ready=low, its event fd non-blocking; INT1 with events on
/// both edges) and then the spidev node (O_RDWR), and
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
	/// reads of INT0's level: the first wait, waits in which no ready edge
	/// came within kEdgeGrace, and waits after a sleep that found no edge
	/// queued (a steady exchange reads none)
	std::uint64_t int0LevelReads = 0;
	/// of those after kEdgeGrace or a sleep, the ones that found INT0 ready
	/// with no edge queued (an edge missed, or a chip that did not go busy)
	std::uint64_t int0Unsignalled = 0;
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
	/// With INT0, event-driven: INT0 is ready when its ready edge came
	/// after the last exchange (the chip drops INT0 while it processes a
	/// packet and raises it when done). Ready with no system call when
	/// that edge was seen already; else one read() of the queued events
	/// when the channel slept since the exchange (none there: the level,
	/// once, at once), then one ppoll() + one read() per wait. The level
	/// is read only for the first wait, after a sleep that found no edge,
	/// and when no edge came within kEdgeGrace of waiting (a missed edge).
	/// Without INT0: ready once kFallbackWait has passed since the end of
	/// the last exchange (waits for the rest of it, or for @p timeout if
	/// shorter). Throws ecmxf::Error when the line cannot be read.
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) override;
	/// Reads the clock (and keeps what it read for coarseNow()).
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	void sleepFor(std::chrono::nanoseconds duration) override;
	/// One absolute sleep (SpidevBackend::sleepUntil()).
	void sleepUntil(std::chrono::nanoseconds deadline) override;
	/// The latest of: the last clock read, the last sleep's end, the time
	/// of INT0's last ready edge (when its events carry a timestamp on
	/// now()'s clock). No system call.
	[[nodiscard]] std::chrono::nanoseconds coarseNow() const override;
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
	/// Reads INT0's queued events (waiting up to @p timeout): true when
	/// the last says ready. Throws ecmxf::Error when that fails.
	bool readyEdge(std::chrono::nanoseconds timeout);
	/// One read of INT0's level with no edge seen: true (and INT0 known
	/// ready) when it says ready; counts it in stats().
	bool levelReady();
	/// Moves coarseNow() on to @p t (never back).
	void advanceClock(std::chrono::nanoseconds t) const noexcept;

	/// What the channel knows of INT0 without reading it.
	enum class Int0State : std::uint8_t {
		Unknown, ///< nothing yet: the level is read
		Ready,   ///< its ready edge came after the last exchange
		Busy,    ///< an exchange since its last ready edge
	};

	std::unique_ptr<SpidevBackend> backend_;
	SpidevOptions options_;
	SpidevStats stats_;
	std::chrono::nanoseconds lastExchangeEnd_{ 0 };
	bool exchanged_ = false;
	Int0State int0_ = Int0State::Unknown;
	/// the channel slept since the last exchange: the ready edge has
	/// probably come, so the events are read before any wait
	bool sleptSinceExchange_ = false;
	/// coarseNow()
	mutable std::chrono::nanoseconds known_{ 0 };
};

} // namespace ecmxf
