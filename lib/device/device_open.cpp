// SPDX-License-Identifier: MIT
// Device URIs (include/ecmxf/device_uri.hpp): parseDeviceUri(). Opening the
// link each one names is Device::open() (lib/open/device_open.cpp).

#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/model/status.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/spidev_channel.hpp>

#include <cerrno>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/text.hpp"

namespace ecmxf {

namespace {

using detail::quoted;

/// Error(EINVAL): cannot open "<uri>": <what>; accepted: <forms> (the
/// ECM-SK's for an "sk-" URI).
[[noreturn]] void bad(std::string_view uri, const std::string &what)
{
	std::string m = "cannot open ";
	m.append(quoted(uri)).append(": ").append(what).append("; accepted: ");
	m.append(uri.starts_with("sk-") ? kSkUriForms : kDeviceUriForms);
	throw Error(m, EINVAL);
}

/// Decimal digits only, at most 10 of them; nullopt otherwise.
std::optional<std::uint64_t> number(std::string_view s)
{
	if (s.empty() || s.size() > 10)
		return std::nullopt;
	std::uint64_t v = 0;
	for (const char c : s) {
		if (c < '0' || c > '9')
			return std::nullopt;
		v = v * 10 + static_cast<std::uint64_t>(c - '0');
	}
	return v;
}

GpioLineSpec gpioLine(std::string_view uri, std::string_view key, std::string_view value)
{
	const auto colon = value.rfind(':');
	const std::string_view chip = colon == std::string_view::npos ? std::string_view{} : value.substr(0, colon);
	const auto line = colon == std::string_view::npos ? std::nullopt : number(value.substr(colon + 1));
	if (chip.empty() || !line || *line > 0xFFFF) {
		std::string m = "bad ";
		m.append(key).append(" value ").append(quoted(value)).append(": expected <chip>:<line>, e.g. ");
		m.append(key).append("=gpiochip0:17");
		bad(uri, m);
	}
	return GpioLineSpec{ std::string(chip), static_cast<unsigned>(*line) };
}

/// slot= and ex= of sk-unix: and sk-spidev:; false for another key.
bool skHostOption(std::string_view uri, DeviceUri &u, std::string_view key, std::string_view value)
{
	if (key == "slot") {
		const auto v = number(value);
		if (!v || (*v != 12 && *v != 16))
			bad(uri, "bad slot value " + quoted(value) + ": slot=" + std::string(value) +
					 ": the slot size is 12 or 16 (the board's CONFIG2)");
		u.skSlotSize = static_cast<unsigned>(*v);
	} else if (key == "ex") {
		const auto v = number(value);
		if (!v || *v > 3)
			bad(uri, "bad ex value " + quoted(value) +
					 ": expected 0..3 (the SET_EX setting in force: bit 0 command CRC, bit 1 response CRC)");
		u.skExtensions = static_cast<std::uint32_t>(*v);
	} else {
		return false;
	}
	return true;
}

/// An option of an ECM-SK URI.
void skOption(std::string_view uri, DeviceUri &u, std::string_view key, std::string_view value)
{
	switch (u.kind) {
	case DeviceUri::Kind::SkSim:
		try {
			u.skBoard.set(std::string(key), std::string(value));
		} catch (const std::invalid_argument &e) {
			bad(uri, e.what());
		}
		u.skSlotSize = u.skBoard.slotSize;
		u.skExtensions = u.skBoard.extensions;
		return;
	case DeviceUri::Kind::SkSpidev:
		if (key == "busy") {
			u.spidev.int0 = gpioLine(uri, key, value);
			return;
		}
		if (key == "speed") {
			const auto v = number(value);
			if (!v || *v < 1 || *v > kSkMaxSpeedHz)
				bad(uri, "bad speed value " + quoted(value) +
						 ": expected 1..24000000 (Hz; the ECM-SK's maximum is 24 MHz)");
			u.spidev.speedHz = static_cast<std::uint32_t>(*v);
			return;
		}
		if (key == "mode") {
			const auto v = number(value);
			if (!v || *v > 3)
				bad(uri, "bad mode value " + quoted(value) + ": expected 0..3 (the ECM-SK uses mode 0)");
			u.spidev.mode = static_cast<std::uint8_t>(*v);
			return;
		}
		if (!skHostOption(uri, u, key, value))
			bad(uri, "unknown option " + quoted(key) + " (sk-spidev: takes busy, slot, speed, mode, ex, trace)");
		return;
	case DeviceUri::Kind::SkUsb:
		if (key == "path") {
			// a USB device's sysfs name: bus, then ports ("1-1.2")
			const bool ok = !value.empty() && value.size() <= 32 &&
					value.find_first_not_of("0123456789-.") == std::string_view::npos &&
					value.find('-') != std::string_view::npos;
			if (!ok)
				bad(uri, "bad path value " + quoted(value) +
						 ": expected a USB path such as 1-1.2 (bus, then ports; `lsusb -t`)");
			if (!u.path.empty())
				bad(uri, "give the hidraw node or path=, not both");
			u.skUsbPath = std::string(value);
			return;
		}
		if (!skHostOption(uri, u, key, value))
			bad(uri, "unknown option " + quoted(key) + " (sk-usb: takes path, slot, ex and trace)");
		return;
	default:
		if (!skHostOption(uri, u, key, value))
			bad(uri, "unknown option " + quoted(key) + " (sk-unix: takes slot, ex and trace)");
		return;
	}
}

} // namespace

DeviceUri parseDeviceUri(std::string_view uri)
{
	using K = DeviceUri::Kind;
	// the schemes, and what an empty path after one means
	struct Scheme {
		std::string_view prefix;
		K kind;
		const char *noPath; // nullptr: an empty path is allowed
	};
	static constexpr Scheme kSchemes[] = {
		{ "sim:", K::Sim, nullptr },
		{ "spidev:", K::Spidev, "no spidev node after \"spidev:\" (e.g. spidev:/dev/spidev0.0)" },
		{ "unix:", K::Unix,
		  "no socket path after \"unix:\" (e.g. unix:/tmp/ecmxf-sim.sock, served by "
		  "`ecmxf-sim --socket /tmp/ecmxf-sim.sock`)" },
		{ "sk-sim:", K::SkSim, nullptr },
		{ "sk-unix:", K::SkUnix,
		  "no socket path after \"sk-unix:\" (e.g. sk-unix:/tmp/sk.sock, served by "
		  "`ecmxf-sim --board ecm-sk --socket /tmp/sk.sock`)" },
		{ "sk-spidev:", K::SkSpidev, "the spidev node must be an absolute path (sk-spidev:/dev/spidevB.C)" },
		{ "sk-usb:", K::SkUsb, nullptr },
	};

	if (uri.empty())
		bad(uri, "empty device URI");
	const auto q = uri.find('?');
	const std::string_view base = uri.substr(0, q);
	const std::string_view query = q == std::string_view::npos ? std::string_view{} : uri.substr(q + 1);

	DeviceUri u;
	const Scheme *scheme = nullptr;
	for (const Scheme &sc : kSchemes)
		if (base.starts_with(sc.prefix))
			scheme = &sc;
	if (scheme) {
		u.kind = scheme->kind;
		u.path = std::string(base.substr(scheme->prefix.size()));
		if (scheme->noPath && (u.path.empty() || (u.kind == K::SkSpidev && u.path[0] != '/')))
			bad(uri, scheme->noPath);
		if (u.kind == K::SkUsb && !u.path.empty() && u.path[0] != '/')
			bad(uri, "the hidraw node must be an absolute path (sk-usb:/dev/hidrawN), or none: sk-usb: "
				 "finds the board");
	} else if (base.starts_with("/")) {
		u.kind = K::Kernel;
		u.path = std::string(base);
	} else {
		bad(uri, base.starts_with("sk-") ? "unknown ECM-SK device URI" : "unknown device URI");
	}
	if (u.kind == K::Spidev || u.kind == K::SkSpidev)
		u.spidev.device = u.path;
	if (u.kind == K::SkSpidev) {
		u.spidev.speedHz = kSkMaxSpeedHz;
		u.spidev.mode = 0;
		u.spidev.readyHigh = false; // Busy: low = ready
	}

	if (q == std::string_view::npos) {
		if (u.kind == DeviceUri::Kind::SkSpidev)
			bad(uri, "busy=<chip>:<line> is required: the host may start an exchange only while Busy is low");
		return u;
	}
	const bool sk = u.isSk();
	const bool spidev = u.kind == DeviceUri::Kind::Spidev;
	const bool kernel = u.kind == DeviceUri::Kind::Kernel;
	std::vector<std::string_view> seen;
	std::size_t pos = 0;
	for (;;) {
		const auto amp = query.find('&', pos);
		const std::string_view opt = query.substr(pos, amp == std::string_view::npos ? amp : amp - pos);
		const auto eq = opt.find('=');
		if (opt.empty() && sk && amp != std::string_view::npos) {
			pos = amp + 1; // the ECM-SK's forms skip empty options, as they always did
			continue;
		}
		if (opt.empty() && sk)
			break;
		if (opt.empty())
			bad(uri, "empty option (options are key=value, separated by '&')");
		if (eq == std::string_view::npos || eq == 0)
			bad(uri, "option " + quoted(opt) + " is not key=value");
		const std::string_view key = opt.substr(0, eq);
		const std::string_view value = opt.substr(eq + 1);
		for (const std::string_view k : seen)
			if (k == key)
				bad(uri, "option " + quoted(key) + " given twice");
		seen.push_back(key);

		const bool spidevKey = key == "int0" || key == "int1" || key == "speed" || key == "mode" ||
				       key == "ready" || key == "size" || (key == "check" && kernel);
		if (key == "trace") {
			if (value.empty())
				bad(uri, "option \"trace\" needs a file name (trace=<file>)");
			u.trace = std::string(value);
		} else if (sk) {
			skOption(uri, u, key, value);
		} else if (spidevKey && !spidev) {
			bad(uri, "option " + quoted(key) + " applies to spidev: URIs only (" +
					 (u.kind == DeviceUri::Kind::Sim    ? "sim: takes check=<type> and trace=<file>"
					  : u.kind == DeviceUri::Kind::Unix ? "unix: takes check=<type> and trace=<file>"
									    : "the kernel device takes only trace=<file>") +
					 ")");
		} else if (key == "int0") {
			u.spidev.int0 = gpioLine(uri, key, value);
		} else if (key == "int1") {
			u.spidev.int1 = gpioLine(uri, key, value);
		} else if (key == "speed") {
			const auto v = number(value);
			if (!v || *v < 1 || *v > SpidevOptions::kMaxSpeedHz)
				bad(uri, "bad speed value " + quoted(value) +
						 ": expected 1..96000000 (Hz; the chip's maximum is 96 MHz)");
			u.spidev.speedHz = static_cast<std::uint32_t>(*v);
		} else if (key == "mode") {
			const auto v = number(value);
			if (!v || *v > 3)
				bad(uri, "bad mode value " + quoted(value) + ": expected 0..3 (the chip uses mode 0)");
			u.spidev.mode = static_cast<std::uint8_t>(*v);
		} else if (key == "ready") {
			if (value != "high" && value != "low")
				bad(uri, "bad ready value " + quoted(value) +
						 ": expected high or low (the INT0 level that means ready; high by default)");
			u.spidev.readyHigh = value == "high";
		} else if (key == "size") {
			const auto v = number(value);
			if (!v || *v < 32 || *v > 1408)
				bad(uri, "bad size value " + quoted(value) +
						 ": expected 32..1408 (the data section the chip uses now, in bytes)");
			u.dataSize = static_cast<std::uint16_t>(*v);
		} else if (key == "check") {
			if (value == "fixed")
				u.checkType = CheckType::Fixed;
			else if (value == "crc8")
				u.checkType = CheckType::Crc8;
			else if (value == "ccitt")
				u.checkType = CheckType::Ccitt;
			else if (value == "crc32")
				u.checkType = CheckType::Crc32;
			else
				bad(uri, "bad check value " + quoted(value) + ": expected fixed, crc8, ccitt or crc32 (" +
						 (spidev ? "the check word the chip uses now"
							 : "the check word to switch the chip to") +
						 ")");
		} else {
			bad(uri, "unknown option " + quoted(key) +
					 (spidev	    ? " (spidev: takes int0, int1, speed, mode, ready, size, check, trace)"
					  : kernel ? " (only trace=<file> is accepted here)"
						   : " (check=<type> and trace=<file> are accepted here)"));
		}
		if (amp == std::string_view::npos)
			break;
		pos = amp + 1;
	}
	if (u.kind == DeviceUri::Kind::SkSpidev && !u.spidev.int0)
		bad(uri, "busy=<chip>:<line> is required: the host may start an exchange only while Busy is low");
	return u;
}

} // namespace ecmxf
