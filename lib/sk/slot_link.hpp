// SPDX-License-Identifier: MIT
// SlotLink::Impl: the slot protocol's state between exchanges and the
// steps every ECM-SK command is made of (one exchange, a command and its
// answer, the wait for a long command); the view classes
// (lib/sk/board_*.cpp) are written with them. Not installed.
#pragma once

#include <ecmxf/sk/slot_link.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ecmsk-proto.h"
#include "link/trace_writer.hpp"

namespace ecmxf::sk {

struct SlotLink::Impl {
	Impl(ByteChannel &channel, SimBoard *board) : ch(channel), sim(board) {}

	ByteChannel &ch;
	SimBoard *sim; ///< the simulated board behind ch, if the link was given one
	ecmsk_link l{};
	std::vector<std::uint8_t> mosi, miso;
	ecmsk_result res{};
	std::chrono::milliseconds busyTimeout{ 100 };
	std::uint8_t nextIndex = 0;
	// sticky completions, cleared by whoever starts the command
	bool stateDone = false, sdoDone = false, homeDone = false;
	int stateErr = 0, sdoErr = 0, homeErr = 0;
	ecmsk_sdo sdo{};
	// the cyclic path
	std::array<bool, ECMSK_SLAVES_MAX + 1> staged{};
	unsigned stagedCount = 0;
	unsigned inFlight = 0; // cyclic commands of the last frame: not in its response yet
	std::uint16_t lastFull = 0;
	std::uint16_t fifoDepth = 0; // the most FIFO remaining seen in OP: the depth (the FIFO empty)
	std::string lastError; // of the last CycleStatus::Link
	/// The packet trace being recorded (SlotLink::startTrace()), or null:
	/// xfer() records every frame to it.
	std::unique_ptr<detail::TraceWriter> trace;

	[[nodiscard]] ecmxf::State state() const noexcept { return static_cast<ecmxf::State>(l.state); }
	[[nodiscard]] SimBoard *simulator() noexcept { return sim; }

	/// One exchange of the frame in mosi; throws on a link failure.
	void xfer();
	/// The command in the frame, then GET_STATUS: the second response
	/// answers it.
	void transact();
	/// GET_STATUS once if nothing was exchanged yet (the state is known).
	void knowState();
	/// EPERM unless @p cmd is allowed in the state (table 1.3).
	void require(std::uint16_t cmd, const char *what) const;
	/// EINVAL for a slave outside 1..maxSlaves.
	void checkSlave(unsigned slave, const char *cmd) const;
	[[noreturn]] void refused(const std::string &cmd, const std::string &why) const;
	/// An ECM slot command (slot 0), then its answer.
	void ecmCommand(std::uint16_t cmd, std::uint8_t param, std::uint32_t data1, std::uint32_t data2 = 0);
	/// A slave slot command with its checks, then its answer (EPERM when
	/// the board did not carry it out).
	void slaveCommand(unsigned slave, std::uint8_t cmd, std::uint32_t target = 0, std::uint32_t value = 0);
	/// GET_STATUS every @p period until @p done is set, for at most
	/// @p timeout from @p start; false on the timeout. The one wait of
	/// the long commands (SET_STATE, SDO, GO_HOME).
	bool waitDone(const bool &done, std::chrono::nanoseconds start, std::chrono::nanoseconds timeout,
		      std::chrono::nanoseconds period);
	/// SDO_RD or SDO_WR @p c through the SDO slot and its wait; throws
	/// SdoError on an abort. @p what names it in errors.
	void sdoRun(const ecmsk_sdo &c, const std::string &what);
};

/// "0x" and @p digits hex digits.
std::string skHex(std::uint32_t v, int digits);
/// "slave P" for the slave in frame slot @p slot: its bus position P =
/// slot - 1, counted from 0 as on the ECM-XF; messages never show slots.
std::string skSlave(unsigned slot);

} // namespace ecmxf::sk
