// SPDX-License-Identifier: MIT
// SpidevChannel: Linux spidev for the bytes, libgpiod (v1 API) for the
// chip's INT0 (ready) and INT1 (event) lines
// (include/ecmxf/link/spidev_channel.hpp, Documentation/library.rst).

#include <ecmxf/error.hpp>
#include <ecmxf/link/spidev_channel.hpp>

#include <fcntl.h>
#include <gpiod.h>
#include <poll.h>
#include <linux/spi/spidev.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "base/text.hpp"
#include "base/os.hpp"

namespace ecmxf {

SpidevBackend::~SpidevBackend() = default;

int SpidevBackend::readEdges(IntLine line, std::chrono::nanoseconds timeout, Edges &edges) noexcept
{
	edges = Edges{};
	const int r = waitEdge(line, timeout);
	if (r <= 0)
		return r;
	const int v = lineValue(line);
	if (v < 0)
		return v;
	edges.count = 1;
	edges.high = v != 0;
	edges.time = now();
	return 1;
}

void SpidevBackend::sleepUntil(std::chrono::nanoseconds deadline) noexcept
{
	sleepFor(deadline - now());
}

namespace {

using std::chrono::nanoseconds;
using detail::quoted;

const char *lineName(IntLine l)
{
	return l == IntLine::Int0 ? "INT0 (ready)" : "INT1 (event)";
}

std::string lineText(const GpioLineSpec &s)
{
	std::string t = s.chip;
	t.append(":").append(std::to_string(s.line));
	return t;
}

/// Which edges a line's events report.
enum class Edge : std::uint8_t { Both, Rising, Falling };

/// One requested GPIO line with edge events.
class GpioLine
{
public:
	GpioLine(IntLine which, const GpioLineSpec &spec, Edge edge)
	{
		const std::string what = std::string(lineName(which)) + " line " + quoted(lineText(spec));
		chip_.reset(::gpiod_chip_open_lookup(spec.chip.c_str()));
		if (!chip_) {
			const int err = errno ? errno : ENODEV;
			throw Error("cannot open the GPIO chip " + quoted(spec.chip) + " of the " + what + ": " +
					    std::strerror(err),
				    err);
		}
		line_ = ::gpiod_chip_get_line(chip_.get(), spec.line);
		if (!line_) {
			const int err = errno ? errno : EINVAL;
			throw Error("the GPIO chip " + quoted(spec.chip) + " has no line " + std::to_string(spec.line) +
					    " (" + what + "): " + std::strerror(err),
				    err);
		}
		const int req = edge == Edge::Rising	? ::gpiod_line_request_rising_edge_events(line_, "ecmxf")
				: edge == Edge::Falling ? ::gpiod_line_request_falling_edge_events(line_, "ecmxf")
							: ::gpiod_line_request_both_edges_events(line_, "ecmxf");
		if (req < 0) {
			const int err = errno;
			throw Error("cannot request edge events on the " + what + ": " + std::strerror(err) +
					    (err == EBUSY ? " (another consumer holds the line)" : ""),
				    err);
		}
		// readEdges() reads what is queued without blocking
		fd_ = ::gpiod_line_event_get_fd(line_);
		const int fl = fd_ < 0 ? -1 : ::fcntl(fd_, F_GETFL);
		if (fl < 0 || ::fcntl(fd_, F_SETFL, fl | O_NONBLOCK) < 0) {
			const int err = errno ? errno : EBADF;
			::gpiod_line_release(line_);
			throw Error("cannot make the event fd of the " + what + " non-blocking: " + std::strerror(err),
				    err);
		}
	}
	~GpioLine() { ::gpiod_line_release(line_); }
	GpioLine(const GpioLine &) = delete;
	GpioLine &operator=(const GpioLine &) = delete;

	int value() noexcept
	{
		const int v = ::gpiod_line_get_value(line_);
		return v < 0 ? -errno : v;
	}

	int waitEdge(nanoseconds timeout) noexcept
	{
		SpidevBackend::Edges e;
		const int r = readEdges(timeout, e, 1);
		return r < 0 ? r : r > 0;
	}

	/// One ppoll() when @p timeout is positive, then one read() of up to
	/// @p max queued events (of the kernel's 16; more are read on).
	int readEdges(nanoseconds timeout, SpidevBackend::Edges &e, unsigned max = kBatch) noexcept
	{
		e = SpidevBackend::Edges{};
		if (timeout > nanoseconds::zero()) {
			const std::int64_t ns = timeout.count();
			timespec ts{};
			ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
			ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
			pollfd p{ fd_, POLLIN, 0 };
			const int r = ::ppoll(&p, 1, &ts, nullptr);
			if (r < 0)
				return -errno;
			if (r == 0)
				return 0;
		}
		std::array<gpiod_line_event, kBatch> ev{};
		const unsigned batch = std::clamp(max, 1u, kBatch);
		for (;;) {
			const int n = ::gpiod_line_event_read_fd_multiple(fd_, ev.data(), batch);
			if (n < 0)
				return errno == EAGAIN ? static_cast<int>(e.count) : -errno;
			if (n == 0)
				break;
			const gpiod_line_event &last = ev[static_cast<std::size_t>(n - 1)];
			e.count += static_cast<unsigned>(n);
			e.high = last.event_type == GPIOD_LINE_EVENT_RISING_EDGE;
			e.time = std::chrono::seconds(last.ts.tv_sec) + nanoseconds(last.ts.tv_nsec);
			// a full batch: there may be more (kept for the next wait
			// when one was asked for)
			if (static_cast<unsigned>(n) < batch || max == 1)
				break;
		}
		return static_cast<int>(e.count);
	}

private:
	struct ChipCloser {
		void operator()(gpiod_chip *c) const noexcept { ::gpiod_chip_close(c); }
	};
	/// the chip owns the line: released first (the destructor), then closed
	std::unique_ptr<gpiod_chip, ChipCloser> chip_;
	gpiod_line *line_ = nullptr;
	int fd_ = -1; ///< the line's event fd (the line owns it)
	/// events read at once (the kernel queues 16 per line)
	static constexpr unsigned kBatch = 16;
};

/// The real system calls.
class SystemBackend final : public SpidevBackend
{
public:
	explicit SystemBackend(const SpidevOptions &o) : speedHz_(o.speedHz)
	{
		// the lines first: a wrong line is reported before the SPI bus is
		// reconfigured
		// INT0: its ready edge only (a wait is one ppoll() and one read());
		// INT1: both edges
		if (o.int0)
			lines_[0].emplace(IntLine::Int0, *o.int0, o.readyHigh ? Edge::Rising : Edge::Falling);
		if (o.int1)
			lines_[1].emplace(IntLine::Int1, *o.int1, Edge::Both);

		fd_.reset(::open(o.device.c_str(), O_RDWR | O_CLOEXEC));
		if (!fd_.valid())
			detail::throwErrno("cannot open " + quoted(o.device), errno);
		std::uint8_t mode = o.mode;
		if (::ioctl(fd_.get(), SPI_IOC_WR_MODE, &mode) < 0)
			setupFailed(o.device, "SPI mode " + std::to_string(mode), "SPI_IOC_WR_MODE");
		std::uint8_t bits = 8;
		if (::ioctl(fd_.get(), SPI_IOC_WR_BITS_PER_WORD, &bits) < 0)
			setupFailed(o.device, "8 bits per word", "SPI_IOC_WR_BITS_PER_WORD");
		std::uint32_t speed = o.speedHz;
		if (::ioctl(fd_.get(), SPI_IOC_WR_MAX_SPEED_HZ, &speed) < 0)
			setupFailed(o.device, "the clock to " + std::to_string(speed) + " Hz", "SPI_IOC_WR_MAX_SPEED_HZ");
	}

	int transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) noexcept override
	{
		spi_ioc_transfer tr{};
		tr.tx_buf = reinterpret_cast<std::uintptr_t>(mosi.data());
		tr.rx_buf = reinterpret_cast<std::uintptr_t>(miso.data());
		tr.len = static_cast<__u32>(std::min(mosi.size(), miso.size()));
		tr.speed_hz = speedHz_;
		tr.bits_per_word = 8;
		const int r = ::ioctl(fd_.get(), SPI_IOC_MESSAGE(1), &tr);
		return r < 0 ? -errno : r;
	}
	bool hasLine(IntLine l) const noexcept override { return lines_[index(l)].has_value(); }
	int lineValue(IntLine l) noexcept override
	{
		auto &g = lines_[index(l)];
		return g ? g->value() : -ENODEV;
	}
	int waitEdge(IntLine l, nanoseconds timeout) noexcept override
	{
		auto &g = lines_[index(l)];
		return g ? g->waitEdge(timeout) : -ENODEV;
	}
	int readEdges(IntLine l, nanoseconds timeout, Edges &edges) noexcept override
	{
		auto &g = lines_[index(l)];
		return g ? g->readEdges(timeout, edges) : -ENODEV;
	}
	nanoseconds now() const noexcept override
	{
		return std::chrono::duration_cast<nanoseconds>(std::chrono::steady_clock::now().time_since_epoch());
	}
	void sleepFor(nanoseconds d) noexcept override
	{
		if (d > nanoseconds::zero())
			std::this_thread::sleep_for(d);
	}
	void sleepUntil(nanoseconds deadline) noexcept override { detail::sleepUntilMonotonic(deadline); }

private:
	static std::size_t index(IntLine l) noexcept { return l == IntLine::Int0 ? 0 : 1; }
	[[noreturn]] static void setupFailed(const std::string &dev, const std::string &what, const char *call)
	{
		const int err = errno;
		throw Error(dev + ": cannot set " + what + " (" + call + "): " + std::strerror(err) +
				    (err == ENOTTY ? " (not a spidev device?)" : ""),
			    err);
	}

	detail::FileDescriptor fd_;
	std::uint32_t speedHz_;
	std::array<std::optional<GpioLine>, 2> lines_;
};

void validate(const SpidevOptions &o)
{
	if (o.device.empty())
		throw Error("spidev: no spidev node given (e.g. /dev/spidev0.0)", EINVAL);
	if (o.mode > 3)
		throw Error("spidev " + o.device + ": SPI mode " + std::to_string(o.mode) + " outside 0..3", EINVAL);
	if (o.speedHz < 1 || o.speedHz > SpidevOptions::kMaxSpeedHz)
		throw Error("spidev " + o.device + ": SPI clock " + std::to_string(o.speedHz) +
				    " Hz outside 1..96000000 Hz (the chip's maximum is 96 MHz)",
			    EINVAL);
}

} // namespace

std::unique_ptr<SpidevBackend> openSpidevBackend(const SpidevOptions &options)
{
	validate(options);
	return std::make_unique<SystemBackend>(options);
}

SpidevChannel::SpidevChannel(const SpidevOptions &options) : SpidevChannel(openSpidevBackend(options), options)
{
}

SpidevChannel::SpidevChannel(std::unique_ptr<SpidevBackend> backend, SpidevOptions options)
	: backend_(std::move(backend)), options_(std::move(options))
{
	if (!backend_)
		throw Error("spidev " + options_.device + ": no backend given", EINVAL);
}

SpidevChannel::~SpidevChannel() = default;

std::string SpidevChannel::name() const
{
	return "spidev:" + options_.device;
}

void SpidevChannel::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	if (mosi.size() != miso.size())
		throw Error("spidev " + options_.device + ": MOSI and MISO buffers differ in size (" +
				    std::to_string(mosi.size()) + " and " + std::to_string(miso.size()) + " bytes)",
			    EINVAL);
	const int r = backend_->transfer(mosi, miso);
	if (r < 0)
		throw Error("spidev " + options_.device + ": SPI transfer of " + std::to_string(mosi.size()) +
				    " bytes failed (SPI_IOC_MESSAGE): " + std::strerror(-r),
			    -r);
	stats_.exchanges++;
	exchanged_ = true;
	sleptSinceExchange_ = false;
	if (backend_->hasLine(IntLine::Int0)) {
		// the chip is busy with the packet now: its ready edge follows
		if (int0_ != Int0State::Unknown)
			int0_ = Int0State::Busy;
	} else {
		lastExchangeEnd_ = now();
	}
	if (static_cast<std::size_t>(r) != mosi.size())
		throw Error("spidev " + options_.device + ": short SPI transfer: " + std::to_string(r) + " of " +
				    std::to_string(mosi.size()) + " bytes moved",
			    EIO);
}

bool SpidevChannel::lineActive(IntLine line, bool activeHigh)
{
	const int v = backend_->lineValue(line);
	if (v < 0)
		throw Error("spidev " + options_.device + ": cannot read the " + lineName(line) + " line: " +
				    std::strerror(-v),
			    -v);
	return (v != 0) == activeHigh;
}

bool SpidevChannel::waitReady(std::chrono::nanoseconds timeout)
{
	timeout = std::max(timeout, nanoseconds::zero());
	if (!backend_->hasLine(IntLine::Int0)) {
		// no INT0: the chip is given kFallbackWait after each exchange
		if (!exchanged_)
			return true;
		const nanoseconds now = backend_->now();
		const nanoseconds readyAt = lastExchangeEnd_ + SpidevOptions::kFallbackWait;
		if (now >= readyAt)
			return true;
		stats_.fallbackWaits++;
		const nanoseconds rest = readyAt - now;
		if (rest > timeout) {
			backend_->sleepFor(timeout);
			return false;
		}
		backend_->sleepFor(rest);
		return true;
	}

	if (int0_ == Int0State::Ready) {
		// its ready edge came after the last exchange: no system call
		stats_.int0Ready++;
		return true;
	}
	bool levelRead = false;
	if (int0_ == Int0State::Unknown) {
		// the first wait: what is queued is older than anything we
		// sent; the level says
		(void)readyEdge(nanoseconds::zero());
		stats_.int0LevelReads++;
		levelRead = true;
		if (lineActive(IntLine::Int0, options_.readyHigh)) {
			// an edge queued after the first look is no newer either
			(void)readyEdge(nanoseconds::zero());
			int0_ = Int0State::Ready;
			(void)now(); // the coarse clock from here
			stats_.int0Ready++;
			return true;
		}
		int0_ = Int0State::Busy;
	} else if (sleptSinceExchange_) {
		// slept since the exchange: the edge is most likely there
		if (readyEdge(nanoseconds::zero())) {
			stats_.int0Ready++;
			return true;
		}
		// and if not, the chip had its time: the level at once, no
		// kEdgeGrace for an edge that may never come (a chip that was
		// done before it could drop INT0)
		levelRead = true;
		if (levelReady())
			return true;
	}
	// wait for the ready edge; the level once, after kEdgeGrace without one
	nanoseconds left = timeout;
	while (left > nanoseconds::zero()) {
		const nanoseconds slice = levelRead ? left : std::min(left, SpidevOptions::kEdgeGrace);
		if (readyEdge(slice)) {
			stats_.int0Ready++;
			return true;
		}
		left -= slice;
		if (!levelRead) {
			levelRead = true;
			if (levelReady())
				return true;
		}
	}
	stats_.int0Timeouts++;
	(void)now(); // the time has moved on by at least @p timeout
	return false;
}

bool SpidevChannel::levelReady()
{
	stats_.int0LevelReads++;
	if (!lineActive(IntLine::Int0, options_.readyHigh))
		return false;
	// ready: an edge that came in the meantime is this one, late (left
	// queued, it would pass for the next)
	if (!readyEdge(nanoseconds::zero()))
		stats_.int0Unsignalled++;
	int0_ = Int0State::Ready;
	(void)now();
	stats_.int0Ready++;
	return true;
}

bool SpidevChannel::readyEdge(nanoseconds timeout)
{
	// at most a few edges to busy in a row (a backend that reports both
	// edges); then the time is counted as waited
	for (int i = 0; i < 8; i++) {
		SpidevBackend::Edges e;
		const int r = backend_->readEdges(IntLine::Int0, timeout, e);
		if (r < 0)
			throw Error("spidev " + options_.device + ": waiting for an edge on the INT0 (ready) line failed: " +
					    std::strerror(-r),
				    -r);
		if (r == 0)
			return false;
		stats_.int0Edges += e.count;
		if (e.high != options_.readyHigh)
			continue; // busy again: wait on
		// a timestamp on our clock, and not ahead of it by more than an
		// exchange could take (an older kernel stamps CLOCK_REALTIME)
		if (e.time > known_ && e.time - known_ < std::chrono::seconds(10))
			advanceClock(e.time);
		int0_ = Int0State::Ready;
		return true;
	}
	return false;
}

void SpidevChannel::advanceClock(nanoseconds t) const noexcept
{
	if (t > known_)
		known_ = t;
}

std::chrono::nanoseconds SpidevChannel::coarseNow() const
{
	return known_;
}

bool SpidevChannel::waitEvent(std::chrono::nanoseconds timeout)
{
	if (!backend_->hasLine(IntLine::Int1))
		throw Error("spidev " + options_.device +
				    ": no INT1 (event) line configured (add int1=<chip>:<line> to the device URI)",
			    EOPNOTSUPP);
	const nanoseconds end = backend_->now() + std::max(timeout, nanoseconds::zero());
	for (;;) {
		if (lineActive(IntLine::Int1, !options_.int1ActiveLow)) {
			stats_.int1Events++;
			return true;
		}
		const nanoseconds now = backend_->now();
		if (now >= end)
			return false;
		const int r = backend_->waitEdge(IntLine::Int1, end - now);
		if (r < 0)
			throw Error("spidev " + options_.device + ": waiting for an edge on the INT1 (event) line failed: " +
					    std::strerror(-r),
				    -r);
	}
}

std::chrono::nanoseconds SpidevChannel::now() const
{
	const nanoseconds t = backend_->now();
	advanceClock(t);
	return t;
}

void SpidevChannel::sleepFor(std::chrono::nanoseconds duration)
{
	if (duration > nanoseconds::zero()) {
		backend_->sleepFor(duration);
		// at least that much later than the last time known
		advanceClock(known_ + duration);
		sleptSinceExchange_ = true;
	}
}

void SpidevChannel::sleepUntil(std::chrono::nanoseconds deadline)
{
	backend_->sleepUntil(deadline);
	advanceClock(deadline);
	sleptSinceExchange_ = true;
}

} // namespace ecmxf
