// SPDX-License-Identifier: MIT
//
// A Device over a simulated chip for the bus tests: either a bundled
// network file (SimTransport) or a network of the chip tests' TestSlaves
// (a small Transport over a sim::Chip built from that network).

#pragma once

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/link/sim_transport.hpp>
#include <ecmxf/link/transport.hpp>

#include "test_slave.hpp"

namespace bustest {

/// Transport over a sim::Chip it owns (like SimTransport, but for a
/// Network built in the test).
class ChipTransport : public ecmxf::Transport
{
public:
	explicit ChipTransport(ecmxf::sim::Network net) : chip_(std::make_unique<ecmxf::sim::Chip>(std::move(net))) {}
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		chip_->exchange(mosi, miso);
	}
	bool waitReady(std::chrono::nanoseconds timeout) override
	{
		const auto end = chip_->now() + timeout;
		while (!chip_->ready()) {
			if (chip_->now() >= end)
				return false;
			chip_->advance(std::min<std::chrono::nanoseconds>(std::chrono::microseconds(10), end - chip_->now()));
		}
		return true;
	}
	std::chrono::nanoseconds now() const override { return chip_->now(); }
	void sleepFor(std::chrono::nanoseconds d) override
	{
		if (d.count() > 0)
			chip_->advance(d);
	}
	ecmxf::sim::Chip &chip() { return *chip_; }

private:
	std::unique_ptr<ecmxf::sim::Chip> chip_;
};

inline std::string networkFile(const char *name)
{
	return std::string(ECMXF_TEST_NETWORK_DIR) + "/" + name;
}

using SlaveList = std::vector<std::unique_ptr<simtest::TestSlave>>;

/// A Device and its simulated chip.
struct Rig {
	ecmxf::sim::Chip *chip = nullptr;
	std::unique_ptr<ecmxf::Device> dev;

	/// A bundled network (lib/sim/networks/@p net).
	explicit Rig(const char *net = "est584x2-io.net")
	{
		auto t = std::make_unique<ecmxf::SimTransport>(networkFile(net));
		chip = &t->chip();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}
	/// @p n TestSlaves.
	explicit Rig(SlaveList slaves)
	{
		ecmxf::sim::Network net;
		net.setName("bus test network");
		for (auto &s : slaves)
			net.add(std::move(s));
		auto t = std::make_unique<ChipTransport>(std::move(net));
		chip = &t->chip();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}

	ecmxf::Device &d() { return *dev; }
	simtest::TestSlave &test(std::size_t i) { return dynamic_cast<simtest::TestSlave &>(chip->network().at(i)); }

	/// INIT_OP and every slave to PRE-OP (mailbox running).
	void preOp(ecmxf::InitConfig cfg = {})
	{
		dev->initNetwork(cfg);
		dev->stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);
	}
};

inline SlaveList testSlaves(std::size_t n, simtest::SlaveConfig sc = {})
{
	SlaveList l;
	for (std::size_t i = 0; i < n; i++)
		l.push_back(std::make_unique<simtest::TestSlave>(sc));
	return l;
}

} // namespace bustest
