// SPDX-License-Identifier: MIT
// Device::open(): the link each device URI names (include/ecmxf/device_uri.hpp,
// parsed by parseDeviceUri() in lib/device/device_open.cpp), and the chip
// set up as the URI asks (check=). The one place above every link and view
// (Documentation/architecture.rst, "open").

#include <ecmxf/chip/chip.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/model/status.hpp>

#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "base/text.hpp"

namespace ecmxf {

namespace {

using detail::quoted;

/// check= of sim: and unix: URIs: CRC_TYPE_SET, as a production setup
/// switches the chip after power-on. A unix: server's chip keeps its state:
/// when it does not answer in the power-on format, it may speak another
/// check type (an earlier client set it): CRC_TYPE_SET is then sent in
/// each other type in turn.
void switchCheck(Device &dev, CheckType want, std::string_view uri, bool unix)
{
	std::string m = "cannot open ";
	m.append(quoted(uri)).append(": switching the chip to the ").append(checkTypeName(want));
	m.append(" check word: ");
	try {
		dev.chip().setCheckType(want);
		return;
	} catch (const Error &e) {
		if (!unix)
			throw Error(m + e.what(), e.errnoValue());
		for (const CheckType t : { want, CheckType::Crc32, CheckType::Crc8, CheckType::Ccitt }) {
			if (t == CheckType::Fixed)
				continue; // tried first
			try {
				dev.assumeFormat(dev.dataSize(), t);
				dev.chip().setCheckType(want);
				return;
			} catch (const Error &) {
				// not this one either
			}
		}
		dev.assumeFormat(dev.dataSize(), CheckType::Fixed);
		throw Error(m + e.what(), e.errnoValue());
	}
}

} // namespace

std::unique_ptr<Device> Device::open(std::string_view uri)
{
	const DeviceUri u = parseDeviceUri(uri);
	std::unique_ptr<Link> link;
	switch (u.kind) {
	case DeviceUri::Kind::Sim:
		try {
			link = std::make_unique<EngineLink>(std::make_unique<SimChannel>(u.path));
		} catch (const Error &) {
			throw;
		} catch (const std::exception &ex) {
			std::string m = "cannot open ";
			m.append(quoted(uri)).append(": ").append(ex.what());
			throw Error(m, EINVAL);
		}
		break;
	case DeviceUri::Kind::Kernel:
		link = std::make_unique<KernelLink>(u.path);
		break;
	case DeviceUri::Kind::Spidev:
		link = std::make_unique<EngineLink>(std::make_unique<SpidevChannel>(u.spidev));
		break;
	case DeviceUri::Kind::Unix:
		link = std::make_unique<EngineLink>(std::make_unique<UnixChannel>(u.path));
		break;
	case DeviceUri::Kind::SkSim:
	case DeviceUri::Kind::SkUnix:
	case DeviceUri::Kind::SkSpidev:
	case DeviceUri::Kind::SkUsb: {
		std::string m = "cannot open ";
		m.append(quoted(uri)).append(": an ECM-SK, which ecmxf::sk::Board::open() opens (<ecmxf/sk/board.hpp>)");
		throw Error(m, EINVAL);
	}
	}
	auto dev = std::make_unique<Device>(std::move(link));
	if (u.kind == DeviceUri::Kind::Spidev && (u.dataSize || u.checkType))
		dev->assumeFormat(u.dataSize.value_or(static_cast<std::uint16_t>(kDataDefault)),
				  u.checkType.value_or(CheckType::Fixed));
	if (!u.trace.empty())
		dev->startTrace(u.trace);
	if (u.kind != DeviceUri::Kind::Spidev && u.checkType)
		switchCheck(*dev, *u.checkType, uri, u.kind == DeviceUri::Kind::Unix);
	return dev;
}

} // namespace ecmxf
