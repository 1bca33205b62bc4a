// SPDX-License-Identifier: MIT
// The protocol core's engine over the simulated chip, for the simulator's
// tests (test_chip_engine.cpp, test_chip_variants.cpp).
#pragma once

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <vector>

#include <ecmxf/sim/chip.hpp>

#include "ecmxf-proto.h"

namespace simtest {

using namespace std::chrono_literals;

/// The engine's loop (Documentation/protocol-core.rst) over the simulator:
/// wait for INT0 "ready" and the engine's hold-off, exchange, feed the answer.
struct EngineLink {
	ecmxf::sim::Chip &chip;
	ecmxf_engine e{};
	unsigned exchanges = 0;

	explicit EngineLink(ecmxf::sim::Chip &c) : chip(c)
	{
		ecmxf_engine_init(&e, ECMXF_DATA_DEFAULT, ECMXF_CHECK_FIXED);
	}
	std::uint64_t now() const { return static_cast<std::uint64_t>(chip.now().count()); }

	void exchange()
	{
		while (!chip.ready() || now() < ecmxf_engine_not_before(&e))
			chip.advance(10us);
		const std::size_t n = ecmxf_engine_pkt_size(&e);
		std::vector<std::uint8_t> tx(n), rx(n);
		REQUIRE(ecmxf_engine_next(&e, now(), tx.data(), n) == 0);
		chip.exchange(tx, rx);
		ecmxf_engine_input(&e, now(), rx.data(), n);
		exchanges++;
	}

	/// Submit @p x and exchange until it is final; returns its status.
	int run(ecmxf_xfer &x)
	{
		REQUIRE(ecmxf_engine_submit(&e, &x, now()) == 0);
		for (int i = 0; i < 100000 && x.status == -EINPROGRESS; i++) {
			exchange();
			chip.advance(100us); // a host that polls every ~250 us
		}
		return x.status;
	}
};

/// A command of @p code / @p param (answer into @p rx), run to its end.
inline int runCommand(EngineLink &l, std::uint8_t code, std::uint8_t param = 0, std::vector<std::uint8_t> *rx = nullptr)
{
	ecmxf_xfer x{};
	x.hdr.code = code;
	x.hdr.param = param;
	if (rx) {
		x.rx_buf = rx->data();
		x.rx_size = static_cast<std::uint16_t>(rx->size());
	}
	return l.run(x);
}

} // namespace simtest
