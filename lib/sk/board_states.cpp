// SPDX-License-Identifier: MIT
// BoardStates: GET_STATUS, SET_STATE, SW_RESET (include/ecmxf/sk/board_views.hpp).

#include <ecmxf/sk/board_views.hpp>

#include <cerrno>

#include <ecmxf/error.hpp>
#include <ecmxf/sim/sk_board.hpp>

#include "slot_link.hpp"

namespace ecmxf::sk {

using namespace std::chrono_literals;

BoardStatus BoardStates::status()
{
	auto &k = link_->impl();
	k.xfer();
	BoardStatus s;
	const auto &e = k.res.ecm;
	s.state = static_cast<ecmxf::State>(e.state);
	s.crcErrors = e.crc_errors;
	s.fifoRemaining = e.fifo_remaining;
	s.fifoFull = e.fifo_full;
	return s;
}

void BoardStates::set(ecmxf::State s, std::chrono::milliseconds timeout)
{
	auto &k = link_->impl();
	k.knowState();
	ecmsk_ecm_cmd c{ ECMSK_CMD_SET_STATE, 0, static_cast<std::uint32_t>(s), 0, 0 };
	ecmsk_put_ecm(&k.l.g, k.mosi.data(), &c);
	k.stateDone = false;
	const auto start = k.ch.now();
	k.xfer();
	if (!k.waitDone(k.stateDone, start, timeout, 250us)) {
		std::string msg = "SET_STATE " + stateName(s) + ": the ECM-SK stayed in " + stateName(k.state()) +
				  " for " + std::to_string(timeout.count()) + " ms";
		if (auto *sim = k.simulator(); sim && !sim->lastError().empty())
			msg += " (simulator: " + sim->lastError() + ")";
		k.l.ecm.active = false;
		throw Error(msg, ETIMEDOUT);
	}
	if (k.stateErr)
		throw Error("SET_STATE " + stateName(s) + ": the board refused the frame (CRC)", -k.stateErr);
}

void BoardStates::reset()
{
	auto &k = link_->impl();
	ecmsk_ecm_cmd c{ ECMSK_CMD_SW_RESET, 0, 0, 0, 0 };
	ecmsk_put_ecm(&k.l.g, k.mosi.data(), &c);
	k.xfer();
	if (!k.ch.waitReady(1s))
		throw Error(k.ch.name() + ": Busy stayed high for 1 s after SW_RESET", ETIMEDOUT);
	ecmsk_link_reset(&k.l);
	status();
}

} // namespace ecmxf::sk
