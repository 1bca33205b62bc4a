// SPDX-License-Identifier: MIT
// A bare host for the simulated ECM-SK board: frames built with the slot
// protocol core, one exchange at a time, waiting for Busy to fall.
#pragma once

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/sk_board.hpp>

#include "ecmsk-proto.h"

namespace skt {

using Frame = std::vector<std::uint8_t>;
using namespace std::chrono_literals;

inline ecmxf::sim::Network net(const std::string &text)
{
	return ecmxf::sim::Network::fromText(text, "test");
}

struct Host {
	ecmxf::sk::SimBoard b;
	ecmsk_geom g{};
	Frame cmd;
	Frame last;

	explicit Host(const std::string &network = "slave servo\nslave EST-584\nslave dio\n",
		      ecmxf::sk::BoardConfig cfg = {})
		: b(net(network), cfg)
	{
		REQUIRE(ecmsk_geom_init(&g, cfg.slotSize) == 0);
		cmd.assign(g.frame_size, 0);
	}

	void waitReady()
	{
		for (int i = 0; i < 100000 && b.busy(); i++)
			b.advance(1us);
		REQUIRE_FALSE(b.busy());
	}

	// sends cmd (then clears it), returns the response of this exchange
	const Frame &xfer()
	{
		waitReady();
		if (b.extensionsInForce() & ECMSK_EX_CMD_CRC)
			ecmsk_frame_seal(cmd.data(), cmd.size());
		last.assign(g.frame_size, 0xEE);
		b.exchange(cmd, last);
		cmd.assign(g.frame_size, 0);
		return last;
	}
	// sends cmd, then a GET_STATUS frame: the answer to cmd
	const Frame &answer()
	{
		xfer();
		return xfer();
	}
	void ecm(std::uint16_t id, std::uint32_t d1 = 0, std::uint8_t param = 0, std::uint32_t d2 = 0)
	{
		ecmsk_ecm_cmd c{ id, param, d1, d2, 0 };
		REQUIRE(ecmsk_put_ecm(&g, cmd.data(), &c) == 0);
	}
	void slave(unsigned n, std::uint8_t id, std::uint8_t index = 0, std::uint32_t target = 0,
		   std::uint32_t value = 0)
	{
		ecmsk_slave_cmd c{ id, index, target, value, 0 };
		REQUIRE(ecmsk_put_slave(&g, cmd.data(), n, &c) == 0);
	}
	void sdo(std::uint8_t id, std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
		 std::uint8_t size = 0, std::uint32_t value = 0)
	{
		ecmsk_sdo c{ id, 0, slave, size, sub, index, value };
		REQUIRE(ecmsk_put_sdo(&g, cmd.data(), &c) == 0);
	}
	[[nodiscard]] ecmsk_ecm_rsp ecmRsp(const Frame &f) const
	{
		ecmsk_ecm_rsp r{};
		ecmsk_get_ecm(&g, f.data(), &r);
		return r;
	}
	[[nodiscard]] ecmsk_slave_rsp slaveRsp(const Frame &f, unsigned n) const
	{
		ecmsk_slave_rsp r{};
		REQUIRE(ecmsk_get_slave(&g, f.data(), n, &r) == 0);
		return r;
	}
	[[nodiscard]] ecmsk_sdo sdoRsp(const Frame &f) const
	{
		ecmsk_sdo r{};
		ecmsk_get_sdo(&g, f.data(), &r);
		return r;
	}
	// polls GET_STATUS until the state is reached (or gives up)
	bool reach(std::uint8_t st, std::chrono::milliseconds within = 500ms)
	{
		const auto end = b.now() + within;
		while (b.now() < end) {
			if (ecmRsp(xfer()).state == st)
				return true;
			b.advance(200us);
		}
		return false;
	}
	bool setState(std::uint8_t st)
	{
		ecm(ECMSK_CMD_SET_STATE, st);
		xfer();
		return reach(st);
	}
	// SDO through the SDO slot, polled with GET_STATUS until done
	ecmsk_sdo sdoRun(std::uint8_t id, std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
			 std::uint8_t size = 0, std::uint32_t value = 0)
	{
		sdo(id, slave, index, sub, size, value);
		xfer();
		for (int i = 0; i < 2000; i++) {
			auto r = sdoRsp(xfer());
			if (r.cmd == id && r.status != ECMSK_SDO_BUSY)
				return r;
			if (r.cmd != id)
				return r;
			b.advance(100us);
		}
		FAIL("SDO did not complete");
		return {};
	}
	// PRE-OP, SET_AXIS from the network, DRIVE_MODE as given, then OP
	void toOp(const std::vector<std::uint8_t> &types, std::uint32_t cycleUs = 1000)
	{
		REQUIRE(setState(ECMSK_STATE_PREOP));
		for (unsigned grp = 0; grp * 8 < types.size(); grp++) {
			std::uint32_t topo = 0;
			REQUIRE(ecmsk_axis_topology(types.data(), static_cast<unsigned>(types.size()), grp,
						    &topo) == 0);
			ecm(ECMSK_CMD_SET_AXIS, topo, static_cast<std::uint8_t>(grp));
			auto r = ecmRsp(answer());
			REQUIRE(r.cmd == ECMSK_CMD_SET_AXIS);
			REQUIRE(r.data2 == 0u);
		}
		ecm(ECMSK_CMD_SET_DC, cycleUs, 0, ECMSK_DC_FIX);
		answer();
		REQUIRE(b.cycleUs() == cycleUs);
		REQUIRE(setState(ECMSK_STATE_OP));
	}
};

} // namespace skt
