// SPDX-License-Identifier: MIT
/**
 * @file device_uri.hpp
 * @brief The device URIs Device::open() accepts, parsed.
 *
 *  - "sim:" / "sim:<network file>": the in-process simulator;
 *    [?check=fixed|crc8|ccitt|crc32] switches the chip to that check
 *    word after opening (CRC_TYPE_SET), as a production setup does;
 *  - "/dev/ecmxfN" (any absolute path): the kernel module's device;
 *  - "unix:<socket path>": an `ecmxf-sim --socket <socket path>` server
 *    (UnixChannel, include/ecmxf/link/unix_channel.hpp); the simulated chip
 *    lives in the server, so its state persists between opens; check= as
 *    for sim:;
 *  - "spidev:/dev/spidevB.C[?int0=<chip>:<line>][&int1=<chip>:<line>]
 *    [&speed=<Hz>][&mode=0..3][&ready=high|low][&size=<bytes>]
 *    [&check=fixed|crc8|ccitt|crc32]": spidev + libgpiod; size= and check=
 *    give the packet format the chip speaks now (Device::assumeFormat()),
 *    e.g. after ecmxf.ko set CRC-32; default: the power-on format.
 *
 * Each may end in "?trace=<file>" (after the other options: "&trace=..."),
 * which records every exchange to <file> (Documentation/trace.rst).
 */
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/link/spidev_channel.hpp>

namespace ecmxf {

/// The accepted forms, as error messages list them.
inline constexpr std::string_view kDeviceUriForms =
	"\"sim:\", \"sim:<network file>\", \"/dev/ecmxfN\" (kernel module), "
	"\"unix:<socket path>\" (an ecmxf-sim --socket server), "
	"\"spidev:/dev/spidevB.C[?int0=<chip>:<line>][&int1=<chip>:<line>][&speed=<Hz>]"
	"[&mode=0..3][&ready=high|low][&size=<bytes>][&check=fixed|crc8|ccitt|crc32]\"; each may add \"trace=<file>\" as an option, "
	"sim: and unix: also \"check=fixed|crc8|ccitt|crc32\" (switch the chip to it)";

/// A parsed device URI.
struct DeviceUri {
	enum class Kind { Sim, Kernel, Spidev, Unix };
	Kind kind = Kind::Sim;
	/// Sim: the network file (empty: the default network); Kernel: the
	/// device node; Spidev: the spidev node (also in spidev.device);
	/// Unix: the socket path.
	std::string path;
	/// Spidev: the options (defaults from the chip manual otherwise).
	SpidevOptions spidev;
	/// Spidev: the format the chip speaks now (size=, check=); unset: the
	/// power-on format (112 bytes, fixed check word). Sim, Unix: check=
	/// is the check word Device::open() switches the chip to.
	std::optional<std::uint16_t> dataSize;
	std::optional<CheckType> checkType;
	/// The trace= option: where to record the exchanges; empty: none.
	std::string trace;
};

/// Parses @p uri. Throws ecmxf::Error (EINVAL) naming the bad part and
/// listing kDeviceUriForms.
[[nodiscard]] ECMXF_EXPORT DeviceUri parseDeviceUri(std::string_view uri);

} // namespace ecmxf
