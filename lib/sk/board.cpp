// SPDX-License-Identifier: MIT
// Board: a SlotLink opened from an ECM-SK URI, and the views over it
// (include/ecmxf/sk/board.hpp, Documentation/ecm-sk.rst); the commands
// are in lib/sk/board_*.cpp, the slot protocol in lib/sk/slot_link.cpp.

#include <ecmxf/sk/board.hpp>

#include <cerrno>
#include <exception>

#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/hidraw_channel.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/sk/sim_channel.hpp>

namespace ecmxf::sk {

std::string_view slaveTypeName(SlaveType t) noexcept
{
	switch (t) {
	case SlaveType::Drive: return "Drive";
	case SlaveType::Io: return "IO";
	case SlaveType::Hsp: return "HSP";
	case SlaveType::Step: return "STEP";
	case SlaveType::None: return "none";
	}
	return "?";
}

Board::Board(std::unique_ptr<ByteChannel> channel, LinkOptions options) : link_(std::move(channel), options)
{
}

Board::Board(std::unique_ptr<SimBoardChannel> channel, LinkOptions options) : link_(std::move(channel), options)
{
}

Board::~Board() = default;

bool Board::isSkUri(std::string_view uri) noexcept
{
	return uri.rfind("sk-", 0) == 0;
}

namespace {

/// The board of the parsed @p u (of @p uri), before its trace.
std::unique_ptr<Board> openBoard(std::string_view uri, const DeviceUri &u)
{
	LinkOptions o;
	o.slotSize = u.skSlotSize;
	o.extensions = u.skExtensions;
	std::unique_ptr<ByteChannel> ch;
	switch (u.kind) {
	case DeviceUri::Kind::SkSim:
		try {
			return std::make_unique<Board>(std::make_unique<SimBoardChannel>(u.path, u.skBoard), o);
		} catch (const Error &) {
			throw;
		} catch (const std::exception &e) {
			throw Error(std::string(uri) + ": " + e.what(), EINVAL);
		}
	case DeviceUri::Kind::SkUnix:
		ch = std::make_unique<UnixChannel>(u.path);
		break;
	case DeviceUri::Kind::SkSpidev:
		ch = std::make_unique<SpidevChannel>(u.spidev);
		break;
	case DeviceUri::Kind::SkUsb:
		ch = std::make_unique<HidrawChannel>(u.path.empty() ? findSkUsb(listHidraw(), u.skUsbPath).node
								     : u.path);
		break;
	default:
		throw Error("cannot open \"" + std::string(uri) +
				    "\": an ECM-XF, which ecmxf::Device::open() opens; the ECM-SK's forms are " +
				    std::string(kSkUriForms),
			    EINVAL);
	}
	return std::make_unique<Board>(std::move(ch), o);
}

} // namespace

std::unique_ptr<Board> Board::open(std::string_view uri)
{
	const DeviceUri u = parseDeviceUri(uri);
	auto board = openBoard(uri, u);
	if (!u.trace.empty())
		board->startTrace(u.trace);
	return board;
}

void bringUpToOp(Board &b)
{
	if (b.states().status().state == ecmxf::State::Op)
		return;
	if (b.state() == ecmxf::State::Init)
		b.states().set(ecmxf::State::PreOp);
	if (b.state() == ecmxf::State::PreOp) {
		const auto types = b.setup().detectAxes();
		for (std::size_t i = 0; i < types.size(); i++)
			if (types[i] != SlaveType::Io)
				b.drives().setMode(static_cast<unsigned>(i + 1), Mode::Csp);
	}
	b.states().set(ecmxf::State::Op);
}

} // namespace ecmxf::sk
