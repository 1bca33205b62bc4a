// SPDX-License-Identifier: MIT
//
// est584.cpp - the EST-584 EtherCAT hybrid stepper drive (ECON Technology),
// after its manual (004_...): CiA 402 modes PP, PV, HM, CSP; the object
// dictionary of "4.3 Parameters list" with its defaults, access rights and
// ranges; the default PDO maps of 5.4.1; 1C12/1C13 of 5.4.2; parameter
// save/restore through 0x1010:04; the SDO abort codes of 5.3.3 (an out of
// range value is set to the limit AND answered with 0x06090031/32).

#include <stdexcept>

#include "slaves/drive.hpp"
#include "slaves/factory.hpp"
#include "slaves/options.hpp"

namespace ecmxf::sim {

namespace slaves {
namespace {

using namespace std::chrono_literals;

constexpr std::uint32_t kSave = 0x65766173; // "save"
constexpr std::uint32_t kLoad = 0x64616F6C; // "load"
constexpr std::uint32_t kDefaultMaxSpeed = 2'500'000; // 50 rev/s at 50000 pulses/rev

class Est584 final : public DriveBase, public Est584Model
{
public:
	Est584(unsigned position, const SlaveOptions &opts);

	void setHomeSwitch(std::optional<std::int32_t> position) override
	{
		homeSwitch_ = position ? std::optional<double>(*position) : std::nullopt;
		composeOutputs();
	}
	[[nodiscard]] bool homeSwitchActive() const override { return homeSwitchAt(pos_); }

protected:
	void onPowerOn() override
	{
		followingWindow_ = window2030_;
		DriveBase::onPowerOn();
	}
	// 3.3: 0x2151 = 1 takes the alias from 0x2150, else from the EEPROM.
	std::uint16_t powerOnAlias(std::uint16_t eepromAlias) override
	{
		return aliasSource_ == 1 ? slaveId_ : eepromAlias;
	}

private:
	void buildDictionary(std::uint32_t maxSpeed, std::uint16_t window);
	std::uint32_t storeCommand(std::uint64_t raw);

	std::uint32_t deviceType_ = 0x00030192; // CiA 402, stepper
	std::string name_, hwVersion_ = "1.0", swVersion_ = "1.0";
	std::uint16_t window2030_ = 1000; // 0x2030, shared with 0x6065
	std::uint16_t autoTune_ = 1;      // 0x2013
	std::uint16_t slaveId_ = 1;       // 0x2150
	std::uint16_t aliasSource_ = 0;   // 0x2151
};

Est584::Est584(unsigned position, const SlaveOptions &opts)
	: DriveBase(BaseConfig{}, DriveConfig{})
{
	OptionReader o("EST-584", opts);
	identify(o, position, model::kEst584Product, model::kEst584Revision, "EST-584");
	readMailboxLatency(o, 1000);
	cfg_.coe = true;
	cfg_.clampOnRange = true;
	cfg_.maxEntriesPerPdo = 8;
	cfg_.maxPdoBytes = 32; // 5.4.1: "the max length is 32 bytes"
	cfg_.maxOutBytes = 64; // 5.4.3: PDO "the max is 64 bytes"
	cfg_.maxInBytes = 64;
	cfg_.siiGroup = "Drive";
	cfg_.siiOrder = "EST-584";
	cfg_.coeDetails = 0x2D; // SDO, PDO assign, PDO config, complete access
	cfg_.ds402Channels = 1;
	name_ = cfg_.identity.name;

	drv_.supportedModes = mode::bit(mode::PP) | mode::bit(mode::PV) | mode::bit(mode::HM) |
			      mode::bit(mode::CSP);
	drv_.est584 = true;
	drv_.homingTravelLimit = 20 * 50000.0; // 20 revolutions
	drv_.dcCyclesNs = { 250'000, 500'000, 750'000, 1'000'000, 2'000'000, 4'000'000 };
	drv_.dcRequired = false; // free run is fine for PP/HM (5.2.1)

	const auto maxSpeed = static_cast<std::uint32_t>(
		o.integer("max_speed", 1, 0x7FFFFFFF).value_or(kDefaultMaxSpeed));
	const auto window =
		static_cast<std::uint16_t>(o.integer("following_window", 1, 60000).value_or(1000));
	if (auto hs = o.integer("home_switch", INT32_MIN, INT32_MAX))
		homeSwitch_ = static_cast<double>(*hs);
	o.finish();

	buildDictionary(maxSpeed, window);
	finishSetup();
}

std::uint32_t Est584::storeCommand(std::uint64_t raw)
{
	if (raw == kSave) {
		saveParameters();
		return 0;
	}
	if (raw == kLoad) { // 4.2: "all parameter will be reset to default value"
		restoreDefaults(true);
		followingWindow_ = window2030_;
		return 0;
	}
	return abort::CannotTransfer;
}

void Est584::buildDictionary(std::uint32_t maxSpeed, std::uint16_t window)
{
	using DT = DataType;
	using A = Access;
	auto &od = od_;

	// ---- communication area (CiA 301) ----
	addDeviceObjects(deviceType_, name_, &hwVersion_, &swVersion_);
	for (std::uint8_t s = 1; s <= 4; s++) // 4.1/4.2: "save"/"load" at 0x1010:04
		od.sub(0x1010, s, "Store parameters", DT::U32, A::RW)
			.def(1)
			.asCommand()
			.onCheck([this](std::uint64_t v) { return storeCommand(v); });
	addIdentityObjects();

	// ---- PDO mapping, 5.4.1 (sub-indices renumbered 1..n, see the doc) ----
	addPdoMapping(0x1600, true, { 0x60400010, 0x607A0020, 0x60B00020, 0x60B80010 });
	addPdoMapping(0x1601, true,
		      { 0x60400010, 0x607A0020, 0x60810020, 0x60830020, 0x60840020, 0x60600008 });
	addPdoMapping(0x1602, true,
		      { 0x60400010, 0x60FF0020, 0x60830020, 0x60840020, 0x60600008 });
	addPdoMapping(0x1603, true,
		      { 0x60400010, 0x60980008, 0x60990120, 0x60990220, 0x609A0020, 0x607C0020,
			0x60600008 });
	addPdoMapping(0x1A00, false,
		      { 0x60410010, 0x60610008, 0x60640020, 0x60B90010, 0x60BA0020, 0x60FD0020 });
	addPdoMapping(0x1A01, false, {});
	addPdoAssignment(true, { 0x1600 });
	addPdoAssignment(false, { 0x1A00 });

	// ---- manufacturer parameters, 4.3.1 (R/W/S = storable) ----
	auto rws = [&](std::uint16_t idx, std::uint8_t sub, const char *name, std::int64_t def,
		       std::int64_t lo, std::int64_t hi, void *bound = nullptr) -> Entry & {
		Entry &e = sub ? od.sub(idx, sub, name, DT::U16, A::RW, bound)
			       : od.var(idx, name, DT::U16, A::RW, bound);
		return e.def(def).range(lo, hi).store();
	};
	rws(0x2000, 0, "Peak current (mA)", 3200, 1, 8400);
	rws(0x2001, 0, "Pulses per revolution", 50000, 200, 51200);
	rws(0x2002, 0, "Stand-by time (ms)", 500, 100, 10000);
	rws(0x2005, 1, "Output 1 function", 1, 1, 4);
	rws(0x2005, 2, "Output 2 function", 1, 1, 4);
	rws(0x2008, 0, "Output level", 0, 0, 3);
	rws(0x2009, 0, "Pulse filter enable", 0, 0, 1);
	rws(0x2010, 2, "Filter time (us)", 1000, 50, 25600);
	rws(0x2013, 0, "Current loop auto tuning", 1, 0, 1, &autoTune_);
	// "When 0x2013 is 1 (enable), this parameter is read only."
	auto lockedByAutoTune = [this](std::uint64_t) -> std::uint32_t {
		return autoTune_ == 1 ? abort::ReadOnly : 0;
	};
	rws(0x2015, 0, "Current Kp", 1000, 200, 32767).onCheck(lockedByAutoTune);
	rws(0x2016, 0, "Current Ki", 200, 0, 32767).onCheck(lockedByAutoTune);
	od.var(0x2017, "Current Kc", DT::U16, A::RO).def(100).range(80, 300);
	rws(0x2020, 0, "Motor resistance (mOhm)", 1000, 1, 20000);
	rws(0x2021, 0, "Motor inductance (uH)", 1, 1, 6000);
	rws(0x2024, 0, "Open/closed loop", 2, 0, 2);
	rws(0x2025, 0, "Control mode", 5, 0, 10);
	rws(0x2026, 0, "Shaft locking current (%)", 50, 0, 100);
	rws(0x2029, 0, "Encoder resolution", 1000, 200, 60000);
	rws(0x2030, 0, "Position following error", window, 1, 60000, &window2030_)
		.onAfter([this] { followingWindow_ = window2030_; });
	od.var(0x2039, "Pulse amount H", DT::U16, A::RO).def(0);
	auto clearCounter = [](std::uint64_t v) -> std::uint32_t {
		return v == 1 ? 0 : abort::ValueRange; // "write 1 to clear counter"
	};
	od.var(0x2040, "Pulse amount L", DT::U16, A::RW).def(0).asCommand().onCheck(clearCounter);
	od.var(0x2041, "Encoder feedback amount H", DT::U16, A::RO).def(0);
	od.var(0x2042, "Encoder feedback amount L", DT::U16, A::RW)
		.def(0)
		.asCommand()
		.onCheck(clearCounter);
	rws(0x2051, 0, "Motor rotation direction", 0, 0, 1);
	rws(0x2053, 0, "Pend output", 0, 0, 1);
	rws(0x2056, 0, "Fault detecting selection", 0xC3, 0, 0xFFFF);
	rws(0x2057, 0, "Fault clear enable", 0, 0, 1);
	rws(0x2058, 0, "Current soft-start time", 1, 0, 10000);
	rws(0x2083, 0, "Shaft wiggle at power up", 0, 0, 1);
	od.var(0x2093, "Record for fault clear", DT::U16, A::RW).def(0);
	rws(0x2137, 0, "Position loop Kp", 120, 0, 150);
	rws(0x2138, 0, "Position loop Ki", 50, 0, 150);
	rws(0x2139, 0, "Position loop Kvff", 70, 0, 150);
	rws(0x2140, 0, "Speed loop Kp", 60, 0, 150);
	rws(0x2150, 0, "Slave ID", 1, 1, 65535, &slaveId_);
	rws(0x2151, 0, "Slave ID source", 0, 0, 2, &aliasSource_);
	const std::int64_t inputDefaults[] = { 1, 2, 4, 8, 0 };
	for (std::uint8_t s = 1; s <= 5; s++)
		rws(0x2152, s, "Input function", inputDefaults[s - 1], 0, 32768);
	for (std::uint8_t s = 1; s <= 5; s++)
		rws(0x2153, s, "Input filter time (50 us)", 20, 1, 60000);
	rws(0x2154, 0, "Input logic", 0, 0, 31);
	od.var(0x2155, "Input level", DT::U16, A::RO).def(0);

	// ---- CiA 402, 4.3.2 and the mode sections ----
	addCia402Objects();
	od.var(0x605A, "Quick stop option code", DT::I16, A::RW, &quickStopOption_).def(5);
	od.var(0x6062, "Position demand value", DT::I32, A::RO, &positionDemand_).map(TxPdo);
	od.var(0x6065, "Following error window", DT::U32, A::RW, &followingWindow_)
		.def(window)
		.range(1, 60000)
		.onAfter([this] { window2030_ = static_cast<std::uint16_t>(followingWindow_); });
	od.var(0x606B, "Velocity demand value", DT::I32, A::RO, &velocityDemand_).map(TxPdo);
	od.var(0x607C, "Home offset", DT::I32, A::RW, &homeOffset_).map(RxPdo);
	od.var(0x607F, "Max profile velocity", DT::U32, A::RW, &maxProfileVelocity_)
		.def(maxSpeed)
		.map(RxPdo);
	od.var(0x6081, "Profile velocity", DT::U32, A::RW, &profileVelocity_).def(50000).map(RxPdo);
	od.var(0x6082, "Start/stop velocity", DT::U32, A::RW, &startStopVelocity_).def(0).map(RxPdo);
	od.var(0x6083, "Profile acceleration", DT::U32, A::RW, &profileAcceleration_)
		.def(500000)
		.map(RxPdo);
	od.var(0x6084, "Profile deceleration", DT::U32, A::RW, &profileDeceleration_)
		.def(500000)
		.map(RxPdo);
	od.var(0x6085, "Quick stop deceleration", DT::U32, A::RW, &quickStopDeceleration_)
		.def(2'000'000)
		.map(RxPdo);
	od.var(0x6098, "Homing method", DT::I8, A::RW, &homingMethod_)
		.def(19)
		.map(RxPdo)
		.onCheck([](std::uint64_t v) -> std::uint32_t {
			const auto m = static_cast<std::int8_t>(v);
			return m == 19 || m == 20 || m == 35 || m == 37 ? 0 : abort::ValueRange;
		});
	od.sub(0x6099, 1, "Homing speed (switch search)", DT::U32, A::RW, &homingSpeedFast_)
		.def(20000)
		.map(RxPdo);
	od.sub(0x6099, 2, "Homing speed (zero search)", DT::U32, A::RW, &homingSpeedSlow_)
		.def(2000)
		.map(RxPdo);
	od.var(0x609A, "Homing acceleration", DT::U32, A::RW, &homingAcceleration_)
		.def(200000)
		.map(RxPdo);
	od.var(0x60B0, "Position offset", DT::I32, A::RW, &positionOffset_).map(RxPdo);
	od.var(0x60B8, "Touch probe function", DT::U16, A::RW, &probeFunction_).map(RxPdo);
	od.var(0x60B9, "Touch probe status", DT::U16, A::RO, &probeStatus_).map(TxPdo);
	od.var(0x60BA, "Touch probe 1 positive edge", DT::I32, A::RO, &probePosition_).map(TxPdo);
	od.var(0x60F4, "Following error actual value", DT::I32, A::RO, &followingError_)
		.map(TxPdo);
	od.var(0x60FD, "Digital inputs", DT::U32, A::RO, &digitalInputs_).map(TxPdo);
}

} // namespace
} // namespace slaves

std::unique_ptr<Slave> makeEst584(unsigned position, const SlaveOptions &opts)
{
	return std::make_unique<slaves::Est584>(position, opts);
}

} // namespace ecmxf::sim
