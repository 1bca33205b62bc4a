// SPDX-License-Identifier: MIT
//
// servo.cpp - an AKD2G-like servo drive: CiA 402 with CSP (8), CSV (9) and
// CST (10), DC SYNC0 required for OP (AssignActivate 0x0300), a bootstrap
// mailbox and FoE ("firmware.bin" writable in BOOT, "log.txt" readable).
// The object dictionary and default PDOs are the simulator's own choice,
// modelled on the AKD2G (Documentation/sim-slaves.rst).

#include <cstdio>
#include <deque>
#include <functional>
#include <stdexcept>

#include "base/text.hpp"
#include "slaves/drive.hpp"
#include "slaves/factory.hpp"
#include "slaves/options.hpp"

namespace ecmxf::sim {

namespace slaves {
namespace {

constexpr std::uint32_t kSave = 0x65766173; // "save"
constexpr std::uint32_t kLoad = 0x64616F6C; // "load"
constexpr double kCountsPerRev = 1 << 20;   // 20-bit encoder
constexpr std::size_t kMaxFirmware = 1 << 20;
constexpr std::size_t kLogLines = 64;

/// FoE error codes (ETG.1000.6, FoE error request).
namespace foe {
inline constexpr std::uint32_t NotFound = 0x8001;
inline constexpr std::uint32_t AccessDenied = 0x8002;
inline constexpr std::uint32_t DiskFull = 0x8003;
inline constexpr std::uint32_t BootstrapOnly = 0x8008;
} // namespace foe

/// The state names of the drive's log.
constexpr detail::CodeText<AlState> kStateNames[] = {
	{ AlState::Init, "INIT" },
	{ AlState::PreOp, "PREOP" },
	{ AlState::Boot, "BOOT" },
	{ AlState::SafeOp, "SAFEOP" },
	{ AlState::Op, "OP" },
};

std::string_view stateName(AlState s)
{
	return detail::textOf(kStateNames, s, "?");
}

class Servo final : public DriveBase, public ServoModel
{
public:
	Servo(unsigned position, const SlaveOptions &opts);

	[[nodiscard]] std::uint16_t dcAssignActivate() const override { return 0x0300; }
	[[nodiscard]] std::int16_t torqueActual() const override { return torqueActual_; }
	void setLoadTorque(std::int16_t permille) override { loadTorque_ = permille; }
	[[nodiscard]] std::vector<std::uint8_t> firmware() const override { return firmware_; }

	std::uint32_t foeRead(const std::string &name, std::vector<std::uint8_t> &out) override;
	std::uint32_t foeWrite(const std::string &name, std::span<const std::uint8_t> data) override;
	void injectFault(std::uint16_t code) override
	{
		log("fault " + hex4(code) + " injected");
		DriveBase::injectFault(code);
	}

protected:
	void onAlChange(AlState from, AlState to, bool error) override
	{
		DriveBase::onAlChange(from, to, error);
		log(std::string("AL ").append(stateName(from)).append(" -> ").append(stateName(to)) +
		    (error ? " error " + hex4(alStatusCode()) : ""));
	}
	void onPowerOn() override
	{
		DriveBase::onPowerOn();
		log("power on");
	}

private:
	void buildDictionary(std::uint32_t maxSpeed, std::uint32_t window);
	void log(const std::string &what)
	{
		char stamp[32];
		std::snprintf(stamp, sizeof stamp, "%10.6f ",
			      static_cast<double>(escTimeNs()) * 1e-9);
		log_.emplace_back(stamp + what);
		if (log_.size() > kLogLines)
			log_.pop_front();
	}
	static std::string hex4(unsigned v)
	{
		char b[8];
		std::snprintf(b, sizeof b, "0x%04X", v & 0xFFFFu);
		return b;
	}
	[[nodiscard]] std::uint64_t escTimeNs() const
	{
		std::uint64_t t = 0;
		for (unsigned i = 0; i < 8; i++)
			t |= std::uint64_t{ escRead8(static_cast<std::uint16_t>(esc::DcSystemTime + i)) }
			     << (8 * i);
		return t;
	}

	std::uint32_t deviceType_ = 0x00020192; // CiA 402, servo drive
	std::string name_, hwVersion_ = "B", swVersion_ = "02-00-00-000";
	std::vector<std::uint8_t> firmware_;
	std::deque<std::string> log_;
};

Servo::Servo(unsigned position, const SlaveOptions &opts) : DriveBase(BaseConfig{}, DriveConfig{})
{
	OptionReader o("servo", opts);
	identify(o, position, model::kServoProduct, model::kServoRevision, "AKD2G-like servo");
	readMailboxLatency(o, 500);
	cfg_.coe = true;
	cfg_.foe = true;
	cfg_.bootMailbox = true;
	cfg_.clampOnRange = false;
	cfg_.maxEntriesPerPdo = 8;
	cfg_.maxPdoBytes = 32;
	cfg_.maxOutBytes = 64;
	cfg_.maxInBytes = 64;
	cfg_.siiGroup = "Drive";
	cfg_.siiOrder = "SIM-SERVO";
	cfg_.coeDetails = 0x2D;
	cfg_.ds402Channels = 1;
	name_ = cfg_.identity.name;

	drv_.supportedModes =
		mode::bit(mode::CSP) | mode::bit(mode::CSV) | mode::bit(mode::CST);
	drv_.est584 = false;
	// 1000 permille accelerates by 200 rev/s^2; viscous friction limits the
	// free-running speed at 1000 permille to 50 rev/s.
	drv_.accelPerPermille = 200.0 * kCountsPerRev / 1000.0;
	drv_.viscous = 4.0;
	drv_.dcCyclesNs = { 125'000, 250'000, 500'000, 1'000'000, 2'000'000, 4'000'000 };
	drv_.dcRequired = true;

	const auto maxSpeed = static_cast<std::uint32_t>(
		o.integer("max_speed", 1, 0x7FFFFFFF).value_or(static_cast<std::int64_t>(50 * kCountsPerRev)));
	const auto window = static_cast<std::uint32_t>(
		o.integer("following_window", 1, 0xFFFFFFFF).value_or(100000));
	o.finish();

	buildDictionary(maxSpeed, window);
	finishSetup();
}

void Servo::buildDictionary(std::uint32_t maxSpeed, std::uint32_t window)
{
	using DT = DataType;
	using A = Access;
	auto &od = od_;

	addDeviceObjects(deviceType_, name_, &hwVersion_, &swVersion_);
	// CiA 301: "save" to 0x1010:01 stores, "load" to 0x1011:01 restores the
	// defaults at the next power-on.
	auto command = [&](std::uint16_t idx, const char *name, std::uint32_t word,
			   std::function<void()> action, const char *done) {
		od.sub(idx, 1, name, DT::U32, A::RW)
			.def(1)
			.asCommand()
			.onCheck([this, word, action, done](std::uint64_t v) -> std::uint32_t {
				if (v != word)
					return abort::CannotTransfer;
				action();
				log(done);
				return 0;
			});
	};
	command(0x1010, "Save all parameters", kSave, [this] { saveParameters(); },
		"parameters saved");
	command(0x1011, "Restore default parameters", kLoad, [this] { restoreDefaults(false); },
		"defaults restored (next power-on)");
	addIdentityObjects();

	// RxPDO 13 bytes, TxPDO 15 bytes by default; three more free PDOs each.
	addPdoMapping(0x1600, true,
		      { 0x60400010, 0x607A0020, 0x60FF0020, 0x60710010, 0x60600008 });
	addPdoMapping(0x1601, true, {});
	addPdoMapping(0x1602, true, {});
	addPdoMapping(0x1603, true, {});
	addPdoMapping(0x1A00, false,
		      { 0x60410010, 0x60640020, 0x606C0020, 0x60770010, 0x603F0010, 0x60610008 });
	addPdoMapping(0x1A01, false, {});
	addPdoMapping(0x1A02, false, {});
	addPdoMapping(0x1A03, false, {});
	addPdoAssignment(true, { 0x1600 });
	addPdoAssignment(false, { 0x1A00 });

	addCia402Objects();
	od.var(0x605A, "Quick stop option code", DT::I16, A::RW, &quickStopOption_).def(5).store();
	od.var(0x6062, "Position demand value", DT::I32, A::RO, &positionDemand_).map(TxPdo);
	od.var(0x6065, "Following error window", DT::U32, A::RW, &followingWindow_)
		.def(window)
		.range(1, 0xFFFFFFFF)
		.store();
	od.var(0x606B, "Velocity demand value", DT::I32, A::RO, &velocityDemand_).map(TxPdo);
	od.var(0x6071, "Target torque", DT::I16, A::RW, &targetTorque_).map(RxPdo);
	od.var(0x6072, "Max torque", DT::U16, A::RW, &maxTorque_)
		.def(3000)
		.range(0, 10000)
		.map(RxPdo)
		.store();
	od.var(0x6077, "Torque actual value", DT::I16, A::RO, &torqueActual_).map(TxPdo);
	od.var(0x607F, "Max profile velocity", DT::U32, A::RW, &maxProfileVelocity_)
		.def(maxSpeed)
		.map(RxPdo)
		.store();
	od.var(0x6085, "Quick stop deceleration", DT::U32, A::RW, &quickStopDeceleration_)
		.def(static_cast<std::int64_t>(100 * kCountsPerRev))
		.map(RxPdo)
		.store();
	od.var(0x60B0, "Position offset", DT::I32, A::RW, &positionOffset_).map(RxPdo);
	od.var(0x60F4, "Following error actual value", DT::I32, A::RO, &followingError_)
		.map(TxPdo);
}

std::uint32_t Servo::foeRead(const std::string &name, std::vector<std::uint8_t> &out)
{
	out.clear();
	if (alState() == AlState::Init)
		return abort::CannotTransferState;
	if (name == "log.txt") {
		for (const auto &l : log_) {
			out.insert(out.end(), l.begin(), l.end());
			out.push_back('\n');
		}
		return 0;
	}
	if (name == "firmware.bin")
		return foe::AccessDenied;
	return foe::NotFound;
}

std::uint32_t Servo::foeWrite(const std::string &name, std::span<const std::uint8_t> data)
{
	if (alState() == AlState::Init)
		return abort::CannotTransferState;
	if (name == "firmware.bin") {
		if (alState() != AlState::Boot)
			return foe::BootstrapOnly;
		if (data.size() > kMaxFirmware)
			return foe::DiskFull;
		firmware_.assign(data.begin(), data.end());
		log("firmware.bin written (" + std::to_string(data.size()) + " bytes)");
		return 0;
	}
	if (name == "log.txt")
		return foe::AccessDenied;
	return foe::NotFound;
}

} // namespace
} // namespace slaves

std::unique_ptr<Slave> makeServo(unsigned position, const SlaveOptions &opts)
{
	return std::make_unique<slaves::Servo>(position, opts);
}

} // namespace ecmxf::sim
