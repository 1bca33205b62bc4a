// SPDX-License-Identifier: MIT
// SpidevChannel: Linux spidev for the bytes, libgpiod (v1 API) for the
// chip's INT0 (ready) and INT1 (event) lines
// (include/ecmxf/link/spidev_channel.hpp, Documentation/library.rst).

#include <ecmxf/error.hpp>
#include <ecmxf/link/spidev_channel.hpp>

#include <fcntl.h>
#include <gpiod.h>
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

#include "device/lib_text.hpp"
#include "device/os.hpp"

namespace ecmxf {

SpidevBackend::~SpidevBackend() = default;

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

/// One requested GPIO line with edge events on both edges.
class GpioLine
{
public:
	GpioLine(IntLine which, const GpioLineSpec &spec)
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
		if (::gpiod_line_request_both_edges_events(line_, "ecmxf") < 0) {
			const int err = errno;
			throw Error("cannot request edge events on the " + what + ": " + std::strerror(err) +
					    (err == EBUSY ? " (another consumer holds the line)" : ""),
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
		const auto ns = std::max<std::int64_t>(timeout.count(), 0);
		timespec ts{};
		ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
		ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
		const int r = ::gpiod_line_event_wait(line_, &ts);
		if (r < 0)
			return -errno;
		if (r == 0)
			return 0;
		gpiod_line_event ev{};
		if (::gpiod_line_event_read(line_, &ev) < 0)
			return -errno;
		return 1;
	}

private:
	struct ChipCloser {
		void operator()(gpiod_chip *c) const noexcept { ::gpiod_chip_close(c); }
	};
	/// the chip owns the line: released first (the destructor), then closed
	std::unique_ptr<gpiod_chip, ChipCloser> chip_;
	gpiod_line *line_ = nullptr;
};

/// The real system calls.
class SystemBackend final : public SpidevBackend
{
public:
	explicit SystemBackend(const SpidevOptions &o) : speedHz_(o.speedHz)
	{
		// the lines first: a wrong line is reported before the SPI bus is
		// reconfigured
		if (o.int0)
			lines_[0].emplace(IntLine::Int0, *o.int0);
		if (o.int1)
			lines_[1].emplace(IntLine::Int1, *o.int1);

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
	nanoseconds now() const noexcept override
	{
		return std::chrono::duration_cast<nanoseconds>(std::chrono::steady_clock::now().time_since_epoch());
	}
	void sleepFor(nanoseconds d) noexcept override
	{
		if (d > nanoseconds::zero())
			std::this_thread::sleep_for(d);
	}

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
	lastExchangeEnd_ = backend_->now();
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

	const nanoseconds end = backend_->now() + timeout;
	for (;;) {
		if (lineActive(IntLine::Int0, options_.readyHigh)) {
			stats_.int0Ready++;
			return true;
		}
		const nanoseconds now = backend_->now();
		if (now >= end) {
			stats_.int0Timeouts++;
			return false;
		}
		const int r = backend_->waitEdge(IntLine::Int0, end - now);
		if (r < 0)
			throw Error("spidev " + options_.device + ": waiting for an edge on the INT0 (ready) line failed: " +
					    std::strerror(-r),
				    -r);
		if (r > 0)
			stats_.int0Edges++;
	}
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
	return backend_->now();
}

void SpidevChannel::sleepFor(std::chrono::nanoseconds duration)
{
	if (duration > nanoseconds::zero())
		backend_->sleepFor(duration);
}

} // namespace ecmxf
