// SPDX-License-Identifier: MIT
// A SpidevBackend played by the simulated chip: the bytes come from
// sim::Chip::exchange(), INT0/INT1 levels from chip.int0()/int1(), time is
// the chip's virtual clock. Faults of the system calls can be injected.
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

	FakeSpidev(ecmxf::sim::Chip &chip, bool int0, bool int1, FakeSpidevFaults &faults)
		: chip_(chip), int0_(int0), int1_(int1), faults_(faults)
	{
	}

	int transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) noexcept override
	{
		transfers++;
		if (faults_.transferErrno)
			return -faults_.transferErrno;
		chip_.exchange(mosi, miso);
		return static_cast<int>(mosi.size()) - faults_.shortBy.value_or(0);
	}
	bool hasLine(ecmxf::IntLine l) const noexcept override { return l == ecmxf::IntLine::Int0 ? int0_ : int1_; }
	int lineValue(ecmxf::IntLine l) noexcept override
	{
		lineReads++;
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
	std::chrono::nanoseconds now() const noexcept override { return chip_.now(); }
	void sleepFor(std::chrono::nanoseconds d) noexcept override
	{
		sleeps++;
		if (d > std::chrono::nanoseconds::zero())
			chip_.advance(d);
	}

	unsigned transfers = 0, lineReads = 0, edgeWaits = 0, sleeps = 0;

private:
	bool level(ecmxf::IntLine l) const { return l == ecmxf::IntLine::Int0 ? chip_.int0() : chip_.int1(); }

	ecmxf::sim::Chip &chip_;
	bool int0_, int1_;
	FakeSpidevFaults &faults_;
};

/// A chip, and a Device over a SpidevChannel over a FakeSpidev of it.
struct SpidevRig {
	explicit SpidevRig(bool int0 = true, bool int1 = false, ecmxf::sim::ChipConfig cfg = defaultConfig(),
			   bool readyHigh = true)
		: chip(std::string(), cfg)
	{
		auto fake = std::make_unique<FakeSpidev>(chip, int0, int1, faults);
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
