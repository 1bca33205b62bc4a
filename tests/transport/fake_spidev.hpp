// SPDX-License-Identifier: MIT
// A SpidevBackend played by the simulated chip: the bytes come from
// sim::Chip::exchange(), INT0/INT1 levels from chip.int0()/int1(), time is
// the chip's virtual clock. Faults of the system calls can be injected.
// INT0's events are those the real backend asks for: the ready edge only,
// queued as the kernel queues them. Each call counts as the system calls
// the real backend makes for it (FakeSpidev::Syscalls).
#pragma once

#include <cerrno>
#include <chrono>
#include <memory>
#include <optional>
#include <span>

#include <ecmxf/sim/chip.hpp>
#include <ecmxf/link/spidev_channel.hpp>

namespace test {

struct FakeSpidevFaults {
	int transferErrno = 0;      ///< every transfer fails with this errno
	std::optional<int> shortBy; ///< transfers move this many bytes fewer
	int lineErrno = 0;          ///< reading a line fails with this errno
	int edgeErrno = 0;          ///< waiting for an edge fails with this errno
};

class FakeSpidev final : public ecmxf::SpidevBackend
{
public:
	/// Resolution of the simulated edge wait.
	static constexpr std::chrono::nanoseconds kStep = std::chrono::microseconds(1);

	/// The real backend's system calls, by kind.
	struct Syscalls {
		unsigned ioctlTransfer = 0; ///< SPI_IOC_MESSAGE
		unsigned ioctlLine = 0;     ///< GPIOHANDLE_GET_LINE_VALUES (a level read)
		unsigned ppoll = 0;         ///< the wait on the line's event fd
		unsigned read = 0;          ///< the read of its events
		unsigned clock = 0;         ///< clock_gettime (no vDSO, as in the QEMU guest)
		unsigned sleep = 0;         ///< clock_nanosleep
		[[nodiscard]] unsigned total() const { return ioctlTransfer + ioctlLine + ppoll + read + clock + sleep; }
	};

	FakeSpidev(ecmxf::sim::Chip &chip, bool int0, bool int1, FakeSpidevFaults &faults, bool readyHigh = true)
		: chip_(chip), int0_(int0), int1_(int1), readyHigh_(readyHigh), faults_(faults)
	{
		lastInt0_ = chip_.int0();
	}

	int transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) noexcept override
	{
		transfers++;
		calls.ioctlTransfer++;
		if (faults_.transferErrno)
			return -faults_.transferErrno;
		observe();
		chip_.exchange(mosi, miso);
		observe();
		return static_cast<int>(mosi.size()) - faults_.shortBy.value_or(0);
	}
	bool hasLine(ecmxf::IntLine l) const noexcept override { return l == ecmxf::IntLine::Int0 ? int0_ : int1_; }
	int lineValue(ecmxf::IntLine l) noexcept override
	{
		lineReads++;
		calls.ioctlLine++;
		if (faults_.lineErrno)
			return -faults_.lineErrno;
		return level(l) ? 1 : 0;
	}
	int waitEdge(ecmxf::IntLine l, std::chrono::nanoseconds timeout) noexcept override
	{
		edgeWaits++;
		if (faults_.edgeErrno)
			return -faults_.edgeErrno;
		const bool start = level(l);
		const auto end = chip_.now() + timeout;
		while (chip_.now() < end) {
			chip_.advance(std::min(kStep, end - chip_.now()));
			if (level(l) != start)
				return 1;
		}
		return 0;
	}
	/// INT0: the queued ready edges (after waiting up to @p timeout for
	/// one: a ppoll(), then a read()); INT1: the default (waitEdge()).
	int readEdges(ecmxf::IntLine l, std::chrono::nanoseconds timeout, Edges &e) noexcept override
	{
		if (l != ecmxf::IntLine::Int0)
			return SpidevBackend::readEdges(l, timeout, e);
		e = Edges{};
		edgeReads++;
		if (timeout > std::chrono::nanoseconds::zero()) {
			calls.ppoll++;
			if (faults_.edgeErrno)
				return -faults_.edgeErrno;
			observe();
			const auto end = chip_.now() + timeout;
			while (queued_ == 0 && chip_.now() < end) {
				chip_.advance(std::min(kStep, end - chip_.now()));
				observe();
			}
			if (queued_ == 0)
				return 0; // ppoll timed out: no read
		}
		calls.read++;
		if (faults_.edgeErrno)
			return -faults_.edgeErrno;
		observe();
		if (queued_ == 0)
			return 0; // EAGAIN
		e.count = queued_;
		e.high = readyHigh_;
		e.time = edgeTime_;
		queued_ = 0;
		return static_cast<int>(e.count);
	}
	std::chrono::nanoseconds now() const noexcept override
	{
		calls.clock++;
		return chip_.now();
	}
	void sleepFor(std::chrono::nanoseconds d) noexcept override
	{
		sleeps++;
		calls.sleep++;
		if (d > std::chrono::nanoseconds::zero())
			chip_.advance(d);
		observe();
	}
	void sleepUntil(std::chrono::nanoseconds deadline) noexcept override
	{
		sleeps++;
		calls.sleep++;
		if (deadline > chip_.now())
			chip_.advance(deadline - chip_.now());
		observe();
	}

	unsigned transfers = 0, lineReads = 0, edgeWaits = 0, edgeReads = 0, sleeps = 0;
	mutable Syscalls calls;

private:
	bool level(ecmxf::IntLine l) const { return l == ecmxf::IntLine::Int0 ? chip_.int0() : chip_.int1(); }
	/// A change of INT0 to its ready level queues an edge (the kernel's
	/// event FIFO, 16 deep).
	void observe() noexcept
	{
		const bool l = chip_.int0();
		if (l != lastInt0_ && l == readyHigh_ && queued_ < 16) {
			queued_++;
			edgeTime_ = chip_.now();
		}
		lastInt0_ = l;
	}

	ecmxf::sim::Chip &chip_;
	bool int0_, int1_;
	bool readyHigh_;
	FakeSpidevFaults &faults_;
	bool lastInt0_ = true;
	unsigned queued_ = 0;
	std::chrono::nanoseconds edgeTime_{ 0 };
};

/// A chip, and a Device over a SpidevChannel over a FakeSpidev of it.
struct SpidevRig {
	explicit SpidevRig(bool int0 = true, bool int1 = false, ecmxf::sim::ChipConfig cfg = defaultConfig(),
			   bool readyHigh = true)
		: chip(std::string(), cfg)
	{
		auto fake = std::make_unique<FakeSpidev>(chip, int0, int1, faults, readyHigh);
		backend = fake.get();
		ecmxf::SpidevOptions o;
		o.device = "/dev/spidev-fake";
		o.readyHigh = readyHigh;
		auto t = std::make_unique<ecmxf::SpidevChannel>(std::move(fake), o);
		transport = t.get();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}
	/// A chip that answers "not ready" to an exchange started while it is
	/// busy, as the real one does: a host that ignores INT0 is caught.
	static ecmxf::sim::ChipConfig defaultConfig()
	{
		ecmxf::sim::ChipConfig c;
		c.notReadyWhileBusy = true;
		return c;
	}

	ecmxf::sim::Chip chip;
	FakeSpidevFaults faults;
	FakeSpidev *backend = nullptr;
	ecmxf::SpidevChannel *transport = nullptr;
	std::unique_ptr<ecmxf::Device> dev;
};

} // namespace test
