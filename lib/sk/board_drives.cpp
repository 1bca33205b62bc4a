// SPDX-License-Identifier: MIT
// BoardDrives: DRIVE_MODE, SV_ON/SV_OFF, ALM_CLR, homing and the drives'
// slots (include/ecmxf/sk/board_views.hpp).

#include <ecmxf/sk/board_views.hpp>

#include <cerrno>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/error.hpp>

#include "slot_link.hpp"

namespace ecmxf::sk {

using namespace std::chrono_literals;

void BoardDrives::setMode(unsigned slave, Mode mode, Sync sync)
{
	link_->impl().slaveCommand(slave, ECMSK_CMD_DRIVE_MODE, static_cast<std::uint32_t>(mode),
				   static_cast<std::uint32_t>(sync));
}

void BoardDrives::servoOn(unsigned slave) { link_->impl().slaveCommand(slave, ECMSK_CMD_SV_ON); }
void BoardDrives::servoOff(unsigned slave) { link_->impl().slaveCommand(slave, ECMSK_CMD_SV_OFF); }
void BoardDrives::alarmClear(unsigned slave) { link_->impl().slaveCommand(slave, ECMSK_CMD_ALM_CLR); }

void BoardDrives::waitEnabled(unsigned slave, std::chrono::milliseconds timeout)
{
	auto &k = link_->impl();
	k.checkSlave(slave, "SV_ON");
	const auto end = k.ch.now() + timeout;
	for (;;) {
		k.xfer();
		const auto a = axis(slave);
		if (cia402StateFrom(a.statusword) == Cia402State::OperationEnabled)
			return;
		if (k.ch.now() >= end)
			throw Error(skSlave(slave) + " did not reach Operation enabled within " +
					    std::to_string(timeout.count()) + " ms (statusword " +
					    skHex(a.statusword, 4) + ", error code " + skHex(a.errorCode, 4) + ")",
				    ETIMEDOUT);
		k.ch.sleepFor(500us);
	}
}

AxisStatus BoardDrives::halt(unsigned slave, std::chrono::milliseconds timeout)
{
	auto &k = link_->impl();
	k.checkSlave(slave, "SV_OFF");
	servoOff(slave);
	const auto end = k.ch.now() + timeout;
	for (;;) {
		k.xfer();
		const auto a = axis(slave);
		const auto s = cia402StateFrom(a.statusword);
		if (s != Cia402State::OperationEnabled && s != Cia402State::QuickStopActive &&
		    s != Cia402State::SwitchedOn)
			return a;
		if (k.ch.now() >= end)
			throw Error(skSlave(slave) + ": SV_OFF: the drive stays " +
					    std::string(cia402StateName(*s)) + " after " + std::to_string(timeout.count()) +
					    " ms (statusword " + skHex(a.statusword, 4) + ")",
				    ETIMEDOUT);
		k.ch.sleepFor(500us);
	}
}

void BoardDrives::home(unsigned slave, std::int8_t method, std::chrono::milliseconds timeout)
{
	auto &k = link_->impl();
	k.checkSlave(slave, "GO_HOME");
	BoardSdo sdo(*link_);
	sdo.write<std::int8_t>(slave, 0x6060, 0, cia402::kModeHm);
	sdo.write<std::int8_t>(slave, 0x6098, 0, method);
	k.homeDone = false;
	const auto start = k.ch.now();
	k.slaveCommand(slave, ECMSK_CMD_GO_HOME);
	if (!k.waitDone(k.homeDone, start, timeout, 1ms)) {
		k.l.home.active = false;
		throw Error("GO_HOME " + skSlave(slave) + ": not homed within " +
				    std::to_string(timeout.count()) + " ms (statusword " +
				    skHex(axis(slave).statusword, 4) + ")",
			    ETIMEDOUT);
	}
	if (k.homeErr == -EIO)
		throw Error("GO_HOME " + skSlave(slave) + ": homing error (statusword bit 13, " +
				    skHex(axis(slave).statusword, 4) + ")",
			    EIO);
	if (k.homeErr)
		throw Error("GO_HOME " + skSlave(slave) + ": failed", -k.homeErr);
}

void BoardDrives::abortHome(unsigned slave)
{
	link_->impl().slaveCommand(slave, ECMSK_CMD_ABORT_HOME);
}

AxisStatus BoardDrives::axis(unsigned slave) const
{
	const auto &k = link_->impl();
	k.checkSlave(slave, "axis");
	ecmsk_slave_rsp r{};
	ecmsk_get_slave(&k.l.g, k.miso.data(), slave, &r);
	AxisStatus a;
	a.cmd = r.cmd;
	a.index = r.index;
	a.statusword = r.statusword;
	a.position = static_cast<std::int32_t>(r.position);
	a.torque = static_cast<std::int16_t>(r.torque);
	a.errorCode = r.error_code;
	return a;
}

Hsp2Status BoardDrives::hsp2(unsigned slave) const
{
	const auto &k = link_->impl();
	k.checkSlave(slave, "hsp2");
	ecmsk_hsp2 r{};
	if (ecmsk_get_hsp2(&k.l.g, k.miso.data(), slave, &r))
		throw Error("a 2-channel HSP needs 16-byte slots (the board's CONFIG2 high, slot=16)", EINVAL);
	Hsp2Status h;
	h.cmd = r.cmd;
	h.index = r.index;
	h.statusword = r.statusword;
	h.position1 = static_cast<std::int32_t>(r.pos1);
	h.inputs1 = r.io1;
	h.position2 = static_cast<std::int32_t>(r.pos2);
	h.inputs2 = r.io2;
	return h;
}

} // namespace ecmxf::sk
