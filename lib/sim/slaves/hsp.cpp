// SPDX-License-Identifier: MIT
//
// hsp.cpp - a minimal NEXTW HSP (high speed pulse output) slave, the fourth
// slave kind of the ECM-SK (quick start 2.1.3): pulse channel 1 driven as a
// CiA-402 axis in CSP or CSV (and homing to the current position, methods
// 35/37), its digital inputs in 0x60FD. With channels=2 a second channel
// at index + 0x800 (quick start 2.1.18, hint 3): 0x6840/0x6841 control-
// and statusword, 0x6860/0x6861 mode (CSP, CSV), 0x6864 position, 0x687A
// and 0x68FF targets, 0x68FD inputs; a pulse output follows its command
// exactly (no following error), and has no homing. The simulator's own
// identity numbers; not a model of NEXTW's HSP manual, which the seeds do
// not contain (Documentation/ecm-sk.rst, "The simulator").

#include <stdexcept>

#include "slaves/drive.hpp"
#include "slaves/factory.hpp"
#include "slaves/options.hpp"

namespace ecmxf::sim {

namespace slaves {
namespace {

constexpr std::uint32_t kHspProduct = 0x00000D5B;
constexpr std::uint32_t kHspRevision = 0x00010000;

class Hsp final : public DriveBase
{
public:
	Hsp(unsigned position, const SlaveOptions &opts);

protected:
	void step(std::chrono::nanoseconds dt, bool outputsApplied) override;
	void onAlChange(AlState from, AlState to, bool error) override;

private:
	void buildDictionary();
	void buildChannel2();

	std::uint32_t deviceType_ = 0x00020192; // CiA 402
	std::string name_;
	unsigned channels_ = 1;
	// channel 2 (index + 0x800)
	Cia402State st2_ = Cia402State::SwitchOnDisabled;
	std::uint16_t cw2_ = 0, sw2_ = 0x40;
	std::int8_t mode2_ = mode::CSP, modeDisp2_ = mode::CSP;
	std::int32_t pos2_ = 0, target2_ = 0, vel2_ = 0;
	std::uint32_t din2_ = 0;
	double pos2f_ = 0;
};

Hsp::Hsp(unsigned position, const SlaveOptions &opts) : DriveBase(BaseConfig{}, DriveConfig{})
{
	OptionReader o("hsp", opts);
	identify(o, position, kHspProduct, kHspRevision, "HSP");
	channels_ = static_cast<unsigned>(o.integer("channels", 1, 2).value_or(1));
	readMailboxLatency(o, 500);
	cfg_.coe = true;
	cfg_.siiGroup = "Pulse";
	cfg_.siiOrder = "HSP";
	cfg_.coeDetails = 0x2D;
	cfg_.ds402Channels = static_cast<std::uint8_t>(channels_);
	name_ = cfg_.identity.name;
	drv_.supportedModes = mode::bit(mode::HM) | mode::bit(mode::CSP) | mode::bit(mode::CSV);
	drv_.dcCyclesNs = { 250'000, 500'000, 1'000'000, 2'000'000, 4'000'000 };
	drv_.dcRequired = false;
	o.finish();
	buildDictionary();
	finishSetup();
}

void Hsp::buildDictionary()
{
	using DT = DataType;
	using A = Access;
	auto &od = od_;
	addDeviceObjects(deviceType_, name_);
	addIdentityObjects();
	if (channels_ == 2)
		buildChannel2();
	addPdoMapping(0x1600, true, { 0x60400010, 0x607A0020, 0x60FF0020, 0x60600008 });
	addPdoMapping(0x1A00, false, { 0x60410010, 0x60640020, 0x60FD0020, 0x60610008 });
	if (channels_ == 2) {
		addPdoMapping(0x1601, true, { 0x68400010, 0x687A0020, 0x68FF0020, 0x68600008 });
		addPdoMapping(0x1A01, false, { 0x68410010, 0x68640020, 0x68FD0020, 0x68610008 });
		addPdoAssignment(true, { 0x1600, 0x1601 });
		addPdoAssignment(false, { 0x1A00, 0x1A01 });
	} else {
		addPdoAssignment(true, { 0x1600 });
		addPdoAssignment(false, { 0x1A00 });
	}
	addCia402Objects();
	od.var(0x6065, "Following error window", DT::U32, A::RW, &followingWindow_).def(100000);
	od.var(0x607C, "Home offset", DT::I32, A::RW, &homeOffset_).map(RxPdo);
	od.var(0x607F, "Max profile velocity", DT::U32, A::RW, &maxProfileVelocity_).def(4'000'000);
	od.var(0x6083, "Profile acceleration", DT::U32, A::RW, &profileAcceleration_).def(4'000'000);
	od.var(0x6084, "Profile deceleration", DT::U32, A::RW, &profileDeceleration_).def(4'000'000);
	od.var(0x6085, "Quick stop deceleration", DT::U32, A::RW, &quickStopDeceleration_).def(8'000'000);
	od.var(0x6098, "Homing method", DT::I8, A::RW, &homingMethod_)
		.def(37)
		.map(RxPdo)
		.onCheck([](std::uint64_t v) -> std::uint32_t {
			const auto m = static_cast<std::int8_t>(v);
			return m == 35 || m == 37 ? 0 : abort::ValueRange;
		});
	od.sub(0x6099, 1, "Homing speed (switch search)", DT::U32, A::RW, &homingSpeedFast_).def(10000);
	od.sub(0x6099, 2, "Homing speed (zero search)", DT::U32, A::RW, &homingSpeedSlow_).def(1000);
	od.var(0x609A, "Homing acceleration", DT::U32, A::RW, &homingAcceleration_).def(100000);
	od.var(0x60FD, "Digital inputs", DT::U32, A::RO, &digitalInputs_).map(TxPdo);
}

void Hsp::buildChannel2()
{
	using DT = DataType;
	using A = Access;
	auto &od = od_;
	od.var(0x6840, "Controlword (channel 2)", DT::U16, A::RW, &cw2_).map(RxPdo);
	od.var(0x6841, "Statusword (channel 2)", DT::U16, A::RO, &sw2_).map(TxPdo);
	od.var(0x6860, "Modes of operation (channel 2)", DT::I8, A::RW, &mode2_)
		.def(mode::CSP)
		.map(RxPdo)
		.onCheck([](std::uint64_t v) -> std::uint32_t {
			const auto m = static_cast<std::int8_t>(v);
			return m == mode::CSP || m == mode::CSV ? 0 : abort::ValueRange;
		});
	od.var(0x6861, "Modes of operation display (channel 2)", DT::I8, A::RO, &modeDisp2_).map(TxPdo);
	od.var(0x6864, "Position actual value (channel 2)", DT::I32, A::RO, &pos2_).map(TxPdo);
	od.var(0x687A, "Target position (channel 2)", DT::I32, A::RW, &target2_).map(RxPdo);
	od.var(0x68FD, "Digital inputs (channel 2)", DT::U32, A::RO, &din2_).map(TxPdo);
	od.var(0x68FF, "Target velocity (channel 2)", DT::I32, A::RW, &vel2_).map(RxPdo);
}

void Hsp::step(std::chrono::nanoseconds dt, bool outputsApplied)
{
	DriveBase::step(dt, outputsApplied);
	if (channels_ != 2)
		return;
	using S = Cia402State;
	using C = Cia402Command;
	const bool op = alState() == AlState::Op;
	const C cmd = decodeControlword(cw2_);
	S next = st2_;
	if (!op) {
		next = S::SwitchOnDisabled;
	} else {
		switch (cmd) {
		case C::DisableVoltage:
		case C::QuickStop:
			next = S::SwitchOnDisabled;
			break;
		case C::Shutdown:
			next = S::ReadyToSwitchOn;
			break;
		case C::SwitchOn:
			if (st2_ == S::ReadyToSwitchOn || st2_ == S::OperationEnabled)
				next = S::SwitchedOn;
			break;
		case C::EnableOperation:
			if (st2_ == S::ReadyToSwitchOn)
				next = S::SwitchedOn;
			else if (st2_ == S::SwitchedOn || st2_ == S::OperationEnabled)
				next = S::OperationEnabled;
			break;
		case C::None:
			break;
		}
	}
	st2_ = next;
	modeDisp2_ = mode2_;
	if (st2_ == S::OperationEnabled) {
		if (mode2_ == mode::CSP)
			pos2f_ = target2_;
		else
			pos2f_ += static_cast<double>(vel2_) * static_cast<double>(dt.count()) * 1e-9;
	}
	pos2_ = static_cast<std::int32_t>(pos2f_);
	sw2_ = static_cast<std::uint16_t>(cia402StateBits(st2_) | 0x0200 |
					  (st2_ == S::OperationEnabled && mode2_ == mode::CSP ? 0x1000 : 0));
}

void Hsp::onAlChange(AlState from, AlState to, bool error)
{
	DriveBase::onAlChange(from, to, error);
	if (to != AlState::Op)
		st2_ = Cia402State::SwitchOnDisabled;
}

} // namespace
} // namespace slaves

std::unique_ptr<Slave> makeHsp(unsigned position, const SlaveOptions &opts)
{
	return std::make_unique<slaves::Hsp>(position, opts);
}

} // namespace ecmxf::sim
