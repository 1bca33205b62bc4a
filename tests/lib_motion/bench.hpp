// SPDX-License-Identifier: MIT
//
// A simulated bus in OP with a ProcessImage and a Cyclic for the motion
// tests: SYNC0 1 ms, the EST-584s remapped with est584MotionPdos() unless
// asked otherwise, a 1 ms application cycle with a small RxFIFO fill.

#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/link.hpp>

namespace motiontest {

using namespace std::chrono_literals;

struct Bench {
	ecmxf::SimChannel *sim = nullptr;
	std::unique_ptr<ecmxf::Device> dev;
	std::unique_ptr<ecmxf::Master> master;
	std::unique_ptr<ecmxf::ProcessImage> image;
	std::unique_ptr<ecmxf::Cyclic> cyc;

	explicit Bench(const std::string &network = "est584x2-io.net", bool motionPdos = true)
	{
		auto t = std::make_unique<ecmxf::SimChannel>(std::string(ECMXF_TEST_NETWORK_DIR) + "/" + network);
		sim = t.get();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
		master = std::make_unique<ecmxf::Master>(*dev);
		ecmxf::MasterConfig mc;
		mc.init.dc.sync0Ns = 1'000'000;
		if (motionPdos && network == "est584x2-io.net")
			mc.pdoAssignments = { ecmxf::est584MotionPdos(0), ecmxf::est584MotionPdos(1) };
		master->bringUp(mc);
		image = std::make_unique<ecmxf::ProcessImage>(master->pdos());
		ecmxf::CyclicConfig cc;
		cc.period = 1ms;
		cc.busCycle = 1ms;
		cc.rxFill = 2;
		cyc = std::make_unique<ecmxf::Cyclic>(*dev, *image, cc);
		cyc->start();
	}

	[[nodiscard]] std::chrono::nanoseconds now() const { return sim->now(); }
	ecmxf::sim::Cia402Model &drive(std::size_t pos)
	{
		return dynamic_cast<ecmxf::sim::Cia402Model &>(sim->chip().network().at(pos));
	}
	ecmxf::sim::Est584Model &est(std::size_t pos)
	{
		return dynamic_cast<ecmxf::sim::Est584Model &>(sim->chip().network().at(pos));
	}
};

} // namespace motiontest
