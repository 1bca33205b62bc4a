// SPDX-License-Identifier: MIT
//
// chip_402.cpp - the CiA-402 engine inside the simulated ECM-XF
// (402_CONFIG_SET, 402_STATE_SET/GET, 402_CTL_SET/GET, 402_GET_STATUSWORD).
//
// With the engine enabled (control byte bit 4) the chip owns control word
// bits 0-3 and 7 of the motor's outputs in every frame it sends: it reads
// the status word from the motor's inputs, and writes the CiA-402 command
// that moves the drive one step towards the requested state (fault reset
// edges when bit 3 "single reset" or bit 7 "auto reset" is set).

#include "chip_impl.hpp"

namespace ecmxf::sim {

namespace {

// CiA-402 state codes (status word bits 6,5,3,2,1,0), as the manuals list
constexpr std::uint8_t kNotReady = 0x00;
constexpr std::uint8_t kSwitchOnDisabled = 0x40;
constexpr std::uint8_t kReadyToSwitchOn = 0x21;
constexpr std::uint8_t kSwitchedOn = 0x23;
constexpr std::uint8_t kOperationEnabled = 0x27;
constexpr std::uint8_t kQuickStopActive = 0x07;
constexpr std::uint8_t kFaultReaction = 0x0F;
constexpr std::uint8_t kFault = 0x08;

// control word commands (bits 0..3, 7)
constexpr std::uint16_t kShutdown = 0x0006;
constexpr std::uint16_t kSwitchOn = 0x0007;
constexpr std::uint16_t kEnableOperation = 0x000F;
constexpr std::uint16_t kDisableVoltage = 0x0000;
constexpr std::uint16_t kQuickStop = 0x0002;
constexpr std::uint16_t kFaultReset = 0x0080;
constexpr std::uint16_t kOwnedBits = 0x008F;

constexpr std::uint8_t kCtlSingleReset = 0x08;
constexpr std::uint8_t kCtlEnable = 0x10;
constexpr std::uint8_t kCtlAutoReset = 0x80;

/// The command that moves a drive in state @p cur towards @p target.
std::uint16_t command(std::uint8_t cur, std::uint8_t target)
{
	switch (target) {
	case kOperationEnabled:
		switch (cur) {
		case kSwitchOnDisabled:
			return kShutdown;
		case kReadyToSwitchOn:
			return kSwitchOn;
		case kSwitchedOn:
		case kOperationEnabled:
			return kEnableOperation;
		default:
			return kDisableVoltage;
		}
	case kSwitchedOn:
		switch (cur) {
		case kSwitchOnDisabled:
			return kShutdown;
		case kReadyToSwitchOn:
		case kSwitchedOn:
		case kOperationEnabled:
			return kSwitchOn; // from OPERATION ENABLED: disable operation
		default:
			return kDisableVoltage;
		}
	case kReadyToSwitchOn:
		return cur == kQuickStopActive ? kDisableVoltage : kShutdown;
	case kQuickStopActive:
		return kQuickStop;
	case kSwitchOnDisabled:
	default:
		return kDisableVoltage;
	}
}

} // namespace

std::uint8_t Chip::Impl::state402(std::uint16_t sw)
{
	// statusword mask, its value in the state, the state (first match wins)
	static constexpr struct {
		std::uint16_t mask, bits;
		std::uint8_t state;
	} kStates[] = {
		{ 0x4F, 0x00, kNotReady },	   { 0x4F, 0x40, kSwitchOnDisabled },
		{ 0x6F, 0x21, kReadyToSwitchOn },  { 0x6F, 0x23, kSwitchedOn },
		{ 0x6F, 0x27, kOperationEnabled }, { 0x6F, 0x07, kQuickStopActive },
		{ 0x4F, 0x0F, kFaultReaction },	   { 0x4F, 0x08, kFault },
	};
	for (const auto &s : kStates)
		if ((sw & s.mask) == s.bits)
			return s.state;
	return static_cast<std::uint8_t>(sw & 0x6F); // not a CiA-402 state
}

std::uint16_t Chip::Impl::statusword(const Motor &m) const
{
	if (m.slave >= slaves_.size())
		return 0;
	const SlaveRec &r = slaves_[m.slave];
	if (static_cast<std::size_t>(m.swOff) + 2 > r.inLen)
		return 0;
	return le16(inImage_.data() + r.inOff + m.swOff);
}

void Chip::Impl::apply402()
{
	for (Motor &m : motors_) {
		if (!m.configured || !(m.ctl & kCtlEnable) || m.slave >= slaves_.size())
			continue;
		const SlaveRec &r = slaves_[m.slave];
		if (static_cast<std::size_t>(m.cwOff) + 2 > r.outLen)
			continue;
		const std::uint8_t cur = state402(statusword(m));
		std::uint16_t cw;
		if (cur == kFault) {
			m.wasFault = true;
			if (m.ctl & (kCtlSingleReset | kCtlAutoReset))
				cw = (m.lastCw & kFaultReset) ? 0 : kFaultReset; // a rising edge
			else
				cw = 0;
		} else {
			if (m.wasFault && cur != kFaultReaction) {
				m.wasFault = false;
				m.ctl = static_cast<std::uint8_t>(m.ctl & ~kCtlSingleReset); // done
			}
			cw = cur == kFaultReaction || cur == kNotReady ? 0 : command(cur, m.target);
		}
		m.lastCw = cw;
		std::uint8_t *p = outImage_.data() + r.outOff + m.cwOff;
		const std::uint16_t host = le16(p);
		put16(p, static_cast<std::uint16_t>((host & ~kOwnedBits) | (cw & kOwnedBits)));
	}
}

Chip::Impl::Result Chip::Impl::cmd402(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out)
{
	Result r;
	if (h.param >= motors_.size())
		return Result::error();
	Motor &m = motors_[h.param];
	switch (h.code) {
	case ECMXF_CMD_402_CONFIG_SET: {
		const std::size_t slave = h.data[3];
		if (!initialized_ || slave >= slaves_.size())
			return Result::error();
		const SlaveRec &s = slaves_[slave];
		if (static_cast<std::size_t>(h.data[0]) + 2 > s.outLen ||
		    static_cast<std::size_t>(h.data[1]) + 2 > s.inLen)
			return Result::error(); // offsets outside the slave's process data
		m.configured = true;
		m.slave = static_cast<std::uint8_t>(slave);
		m.cwOff = h.data[0];
		m.swOff = h.data[1];
		m.ctl = h.data[2];
		m.lastCw = 0;
		m.wasFault = false;
		return r;
	}
	case ECMXF_CMD_402_STATE_SET: {
		const std::uint8_t t = h.data[0];
		if (!m.configured || (t != kSwitchOnDisabled && t != kReadyToSwitchOn && t != kSwitchedOn &&
				      t != kOperationEnabled && t != kQuickStopActive))
			return Result::error();
		m.target = t;
		return r;
	}
	case ECMXF_CMD_402_STATE_GET:
		if (!m.configured)
			return Result::error();
		r.ret = state402(statusword(m));
		return r;
	case ECMXF_CMD_402_CTL_SET:
		if (!m.configured || h.data[1] != 0x5A || h.data[3] >= slaves_.size())
			return Result::error();
		m.ctl = h.data[0];
		m.slave = h.data[3];
		motorTotal_ = h.data[2];
		return r;
	case ECMXF_CMD_402_CTL_GET:
		if (!m.configured)
			return Result::error();
		r.ret = m.ctl;
		return r;
	case ECMXF_CMD_402_GET_STATUSWORD:
		if (!m.configured)
			return Result::error();
		put16(out.data(), statusword(m));
		r.len = 2;
		return r;
	default:
		return Result::error();
	}
}

} // namespace ecmxf::sim
