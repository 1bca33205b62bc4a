// SPDX-License-Identifier: MIT
//
// hsp.cpp - a minimal NEXTW HSP (high speed pulse output) slave, the fourth
// slave kind of the ECM-SK (quick start 2.1.3): one pulse channel driven
// as a CiA-402 axis in CSP or CSV (and homing to the current position,
// methods 35/37), its digital inputs in 0x60FD. The simulator's own
// identity numbers; not a model of NEXTW's HSP manual, which the seeds do
// not contain (Documentation/ecm-sk.rst, "Slave models"). Only one
// channel: a 2-channel HSP (second axis at index + 0x800) is not modelled.

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

private:
	void buildDictionary();

	std::uint32_t deviceType_ = 0x00020192; // CiA 402
	std::string name_;
};

Hsp::Hsp(unsigned position, const SlaveOptions &opts) : DriveBase(BaseConfig{}, DriveConfig{})
{
	OptionReader o("hsp", opts);
	cfg_.typeName = "hsp";
	cfg_.identity.vendorId = model::kVendorId;
	cfg_.identity.productCode = kHspProduct;
	cfg_.identity.revision = kHspRevision;
	o.common(position, cfg_.identity, cfg_.alias, "HSP");
	if (auto ch = o.integer("channels", 1, 2); ch && *ch != 1)
		throw std::invalid_argument("hsp: channels=2: a 2-channel HSP is not modelled "
					    "(Documentation/ecm-sk.rst)");
	cfg_.mailboxLatency = std::chrono::microseconds(
		o.integer("mailbox_latency_us", 0, 10'000'000).value_or(500));
	cfg_.coe = true;
	cfg_.siiGroup = "Pulse";
	cfg_.siiOrder = "HSP";
	cfg_.coeDetails = 0x2D;
	cfg_.ds402Channels = 1;
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
	od.var(0x1000, "Device type", DT::U32, A::RO, &deviceType_).def(0x00020192);
	od.var(0x1001, "Error register", DT::U8, A::RO, &errorRegister_).map(TxPdo);
	od.string(0x1008, "Device name", &name_);
	addIdentityObjects();
	addPdoMapping(0x1600, true, { 0x60400010, 0x607A0020, 0x60FF0020, 0x60600008 });
	addPdoMapping(0x1A00, false, { 0x60410010, 0x60640020, 0x60FD0020, 0x60610008 });
	addPdoAssignment(true, { 0x1600 });
	addPdoAssignment(false, { 0x1A00 });
	od.var(0x603F, "Error code", DT::U16, A::RO, &errorCode_).map(TxPdo);
	od.var(0x6040, "Controlword", DT::U16, A::RW, &controlword_).map(RxPdo);
	od.var(0x6041, "Statusword", DT::U16, A::RO, &statusword_).map(TxPdo);
	od.var(0x6060, "Modes of operation", DT::I8, A::RW, &modeOfOperation_)
		.def(mode::CSP)
		.map(RxPdo)
		.onCheck([this](std::uint64_t v) { return checkMode(v); });
	od.var(0x6061, "Modes of operation display", DT::I8, A::RO, &modeDisplay_).map(TxPdo);
	od.var(0x6064, "Position actual value", DT::I32, A::RO, &positionActual_).map(TxPdo);
	od.var(0x6065, "Following error window", DT::U32, A::RW, &followingWindow_).def(100000);
	od.var(0x606C, "Velocity actual value", DT::I32, A::RO, &velocityActual_).map(TxPdo);
	od.var(0x607A, "Target position", DT::I32, A::RW, &targetPosition_).map(RxPdo);
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
	od.var(0x60FF, "Target velocity", DT::I32, A::RW, &targetVelocity_).map(RxPdo);
	od.var(0x6502, "Supported drive modes", DT::U32, A::RO, &supportedModes_).def(drv_.supportedModes);
}

} // namespace
} // namespace slaves

std::unique_ptr<Slave> makeHsp(unsigned position, const SlaveOptions &opts)
{
	return std::make_unique<slaves::Hsp>(position, opts);
}

} // namespace ecmxf::sim
