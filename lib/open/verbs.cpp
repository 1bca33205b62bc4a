// SPDX-License-Identifier: MIT
// MasterVerbs: the verbs both masters have, with the adapter of each
// (include/ecmxf/verbs.hpp). Here, in the top layer, because it sees both
// the ECM-XF's Device and the ECM-SK's Board.

#include <ecmxf/verbs.hpp>

#include <cerrno>
#include <chrono>
#include <string>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/model/cia402.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/sk/board.hpp>

namespace ecmxf {

std::string_view masterKindName(MasterKind k) noexcept
{
	return k == MasterKind::EcmSk ? "ECM-SK" : "ECM-XF";
}

void throwNotOn(MasterKind master, std::string_view why)
{
	std::string m = "not on the ";
	m.append(masterKindName(master)).append(": ").append(why);
	throw Error(m, ENOTSUP);
}

unsigned boardSlot(const sk::Board &board, unsigned position)
{
	if (position >= board.maxSlaves())
		throw Error("slave position " + std::to_string(position) + " is outside 0.." +
				    std::to_string(board.maxSlaves() - 1) + " (the frame's slave slots)",
			    EINVAL);
	return position + 1;
}

MasterVerbs::~MasterVerbs() = default;

bool busDown(Device &device)
{
	const unsigned count = device.bus().slaveCount();
	return count == 0 && device.lastHeader().ecatState == 0;
}

unsigned ensureBusUp(Device &device, bool preOp)
{
	if (busDown(device)) {
		device.bus().initNetwork();
		if (preOp && device.bus().slaveCount() > 0)
			device.bus().stateSet(kAllSlaves, State::PreOp);
	}
	return device.bus().slaveCount();
}

namespace {

std::optional<std::uint32_t> identity(MasterVerbs &m, unsigned position, std::uint8_t sub)
{
	try {
		const auto b = m.upload(position, 0x1018, sub);
		if (b.size() != 4)
			return std::nullopt;
		return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
		       static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
	} catch (const Error &) {
		return std::nullopt; // no CoE: no identity to show
	}
}

// ---------------------------------------------------------------- ECM-XF

class DeviceVerbs final : public MasterVerbs
{
public:
	DeviceVerbs(Device &dev, std::unique_ptr<Device> owned) : dev_(dev), owned_(std::move(owned)) {}

	MasterKind kind() const noexcept override { return MasterKind::EcmXf; }
	Device *device() noexcept override { return &dev_; }

	State state() override { return dev_.bus().stateGet(kAllSlaves).state(); }
	void requestState(State s) override { dev_.bus().stateSet(kAllSlaves, s); }
	unsigned slaveCount() override { return dev_.bus().slaveCount(); }
	std::vector<SlaveSummary> slaves() override
	{
		std::vector<SlaveSummary> out;
		const unsigned n = slaveCount();
		for (unsigned i = 0; i < n; i++) {
			SlaveSummary s;
			s.position = i;
			s.state = dev_.bus().stateGet(static_cast<std::uint8_t>(i)).state();
			s.vendorId = identity(*this, i, 1);
			s.productCode = identity(*this, i, 2);
			out.push_back(std::move(s));
		}
		return out;
	}

	std::vector<std::uint8_t> upload(unsigned position, std::uint16_t index, std::uint8_t sub) override
	{
		return dev_.sdo().upload(slave(position), index, sub);
	}
	void download(unsigned position, std::uint16_t index, std::uint8_t sub,
		      std::span<const std::uint8_t> data) override
	{
		dev_.sdo().download(slave(position), index, sub, data);
	}

	std::uint16_t driveEnable(unsigned position) override
	{
		return cia402WalkBySdo(dev_, slave(position), Cia402State::OperationEnabled);
	}
	std::uint16_t driveDisable(unsigned position) override
	{
		return cia402WalkBySdo(dev_, slave(position), Cia402State::SwitchOnDisabled);
	}
	std::uint16_t driveAlarmClear(unsigned position) override
	{
		return cia402WalkBySdo(dev_, slave(position), Cia402State::SwitchOnDisabled, true);
	}

	std::uint32_t ioRead(unsigned) override
	{
		throwNotOn(MasterKind::EcmXf, "a slave's inputs are process data on the ECM-XF (ecmxf-util pdos; "
					      "ProcessImage and Cyclic in the library)");
	}
	void ioWrite(unsigned, std::uint32_t) override
	{
		throwNotOn(MasterKind::EcmXf, "a slave's outputs are process data on the ECM-XF (ecmxf-util pdos; "
					      "ProcessImage and Cyclic in the library)");
	}

	void reset() override { dev_.chip().warmReset(); }

private:
	static std::uint8_t slave(unsigned position)
	{
		if (position > kMaxSlavePosition)
			throw Error("slave position " + std::to_string(position) + " is outside 0..127", EINVAL);
		return static_cast<std::uint8_t>(position);
	}

	Device &dev_;
	std::unique_ptr<Device> owned_;
};

// ---------------------------------------------------------------- ECM-SK

class BoardVerbs final : public MasterVerbs
{
public:
	BoardVerbs(sk::Board &b, std::unique_ptr<sk::Board> owned) : b_(b), owned_(std::move(owned)) {}

	MasterKind kind() const noexcept override { return MasterKind::EcmSk; }
	sk::Board *board() noexcept override { return &b_; }

	State state() override { return b_.states().status().state; }
	void requestState(State s) override { b_.states().set(s); }
	unsigned slaveCount() override { return b_.setup().slaveCount(); }
	std::vector<SlaveSummary> slaves() override
	{
		const auto types = b_.setup().detectAxes();
		std::vector<SlaveSummary> out;
		for (unsigned i = 0; i < types.size(); i++) {
			SlaveSummary s;
			s.position = i;
			s.state = b_.state();
			s.kind = std::string(sk::slaveTypeName(types[i]));
			s.vendorId = identity(*this, i, 1);
			s.productCode = s.vendorId ? identity(*this, i, 2) : std::nullopt;
			out.push_back(std::move(s));
		}
		return out;
	}

	std::vector<std::uint8_t> upload(unsigned position, std::uint16_t index, std::uint8_t sub) override
	{
		unsigned size = 0;
		const std::uint32_t v = b_.sdo().read(slot(position), index, sub, &size);
		std::vector<std::uint8_t> bytes(size);
		for (unsigned i = 0; i < size; i++)
			bytes[i] = static_cast<std::uint8_t>(v >> (8 * i));
		return bytes;
	}
	void download(unsigned position, std::uint16_t index, std::uint8_t sub,
		      std::span<const std::uint8_t> data) override
	{
		if (data.size() != 1 && data.size() != 2 && data.size() != 4)
			throwNotOn(MasterKind::EcmSk, "the SDO slot carries objects of 1, 2 or 4 bytes, not " +
							      std::to_string(data.size()));
		std::uint32_t v = 0;
		for (std::size_t i = 0; i < data.size(); i++)
			v |= static_cast<std::uint32_t>(data[i]) << (8 * i);
		b_.sdo().write(slot(position), index, sub, v, static_cast<unsigned>(data.size()));
	}

	std::uint16_t driveEnable(unsigned position) override
	{
		const unsigned s = slot(position);
		b_.drives().servoOn(s);
		b_.drives().waitEnabled(s);
		return statusword(s);
	}
	std::uint16_t driveDisable(unsigned position) override
	{
		const unsigned s = slot(position);
		b_.drives().servoOff(s);
		return statusword(s);
	}
	std::uint16_t driveAlarmClear(unsigned position) override
	{
		const unsigned s = slot(position);
		b_.drives().alarmClear(s);
		return statusword(s);
	}

	std::uint32_t ioRead(unsigned position) override { return b_.io().read(slot(position)); }
	void ioWrite(unsigned position, std::uint32_t outputs) override { b_.io().write(slot(position), outputs); }

	void reset() override { b_.states().reset(); }

private:
	unsigned slot(unsigned position) const { return boardSlot(b_, position); }
	std::uint16_t statusword(unsigned s)
	{
		(void)b_.states().status();
		return b_.drives().axis(s).statusword;
	}

	sk::Board &b_;
	std::unique_ptr<sk::Board> owned_;
};

} // namespace

std::uint16_t cia402WalkBySdo(Device &device, std::uint8_t position, Cia402State target, bool faultResetOnly)
{
	Sdo sdo = device.sdo();
	std::uint16_t sw = sdo.read<std::uint16_t>(position, 0x6041, 0);
	const auto initial = cia402StateFrom(sw);
	if (faultResetOnly && initial != Cia402State::Fault && initial != Cia402State::FaultReactionActive)
		return sw;
	Cia402Stepper stepper(position);
	Link &t = device.link();
	stepper.request(target, t.now());
	// the caller's bits (modes, halt): as the drive has them now
	const auto keep =
		static_cast<std::uint16_t>(sdo.read<std::uint16_t>(position, 0x6040, 0) & ~cia402::kCwStateBits);
	std::uint16_t lastCw = 0xFFFF;
	for (;;) {
		const Cia402Step st = stepper.step(sw, t.now(), keep);
		if (st.progress == Cia402Progress::Done)
			return sw;
		stepper.throwIfFailed();
		if (st.controlword != lastCw) {
			sdo.write<std::uint16_t>(position, 0x6040, 0, st.controlword);
			lastCw = st.controlword;
		}
		t.sleepFor(std::chrono::milliseconds(1));
		sw = sdo.read<std::uint16_t>(position, 0x6041, 0);
	}
}

std::unique_ptr<MasterVerbs> MasterVerbs::open(std::string_view uri)
{
	if (parseDeviceUri(uri).isSk()) {
		auto b = sk::Board::open(uri);
		sk::Board &ref = *b;
		return std::make_unique<BoardVerbs>(ref, std::move(b));
	}
	auto d = Device::open(uri);
	Device &ref = *d;
	return std::make_unique<DeviceVerbs>(ref, std::move(d));
}

std::unique_ptr<MasterVerbs> verbsOf(Device &device)
{
	return std::make_unique<DeviceVerbs>(device, nullptr);
}

std::unique_ptr<MasterVerbs> verbsOf(sk::Board &board)
{
	return std::make_unique<BoardVerbs>(board, nullptr);
}

} // namespace ecmxf
