// SPDX-License-Identifier: MIT
// Shared helpers of test-lib-chip: a Device over the simulator with its
// chip at hand, the raw bring-up commands the other typed-call groups own
// (INIT_OP, STATE_SET, RECONFIG_OP, SLV_INFO_GET), and error capture.
#pragma once

#include <catch2/catch.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include "../common/thrown.hpp"

namespace chiptest {

inline ecmxf::Command raw(std::uint8_t code, std::uint8_t param = 0)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

inline void put16(std::vector<std::uint8_t> &d, std::uint16_t v)
{
	d.push_back(static_cast<std::uint8_t>(v));
	d.push_back(static_cast<std::uint8_t>(v >> 8));
}

inline void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	for (unsigned i = 0; i < 4; i++)
		d.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// A Device over a SimChannel whose chip the test can reach.
struct SimDevice {
	explicit SimDevice(const std::string &network = {}, ecmxf::sim::ChipConfig cfg = {})
	{
		auto t = std::make_unique<ecmxf::SimChannel>(
			network.empty() ? std::string() : std::string(ECMXF_TEST_NETWORK_DIR) + "/" + network, cfg);
		transport = t.get();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}

	ecmxf::sim::Chip &chip() { return transport->chip(); }

	/// ECAT_INIT_OP (1) for all slaves, free run: slaves in INIT.
	void initOp()
	{
		ecmxf::Command c = raw(1);
		c.payload = { 0xFF, 0x81 };
		put16(c.payload, 0);
		put32(c.payload, 1'000'000);
		put32(c.payload, 0);
		put32(c.payload, 0);
		c.len = 16;
		dev->command(c);
	}

	/// ECAT_STATE_SET (12) for all slaves.
	void stateSet(std::uint8_t state)
	{
		ecmxf::Command c = raw(12, 0xFF);
		c.data[0] = state;
		dev->command(c);
	}

	/// INIT_OP, then PRE-OP (mailboxes running).
	void toPreOp()
	{
		initOp();
		stateSet(0x02);
		REQUIRE(dev->lastHeader().ecatState == 0x02);
	}

	/// ECAT_RECONFIG_OP (2).
	void reconfig() { dev->command(raw(2)); }

	/// ECAT_SLV_INFO_GET (15) item @p item of @p slave as a u16.
	std::uint16_t slaveInfo16(std::uint8_t slave, std::uint8_t item)
	{
		ecmxf::Command c = raw(15, slave);
		c.data[0] = item;
		const ecmxf::Response r = dev->command(c);
		REQUIRE(r.data.size() == 2);
		return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
	}

	ecmxf::SimChannel *transport = nullptr;
	std::unique_ptr<ecmxf::Device> dev;
};

using ecmxftest::thrown;

} // namespace chiptest
