// SPDX-License-Identifier: MIT
//
// A Device over a simulated chip for the bus tests: either a bundled
// network file (SimChannel) or a network of the chip tests' TestSlaves
// (a SimChannel over a sim::Chip built from that network).

#pragma once

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/link.hpp>

#include "test_slave.hpp"

namespace bustest {

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
		auto t = std::make_unique<ecmxf::SimChannel>(networkFile(net));
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
		auto t = std::make_unique<ecmxf::SimChannel>(std::move(net));
		chip = &t->chip();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}

	ecmxf::Device &d() { return *dev; }
	simtest::TestSlave &test(std::size_t i) { return dynamic_cast<simtest::TestSlave &>(chip->network().at(i)); }

	/// INIT_OP and every slave to PRE-OP (mailbox running).
	void preOp(ecmxf::InitConfig cfg = {})
	{
		dev->bus().initNetwork(cfg);
		dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);
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
