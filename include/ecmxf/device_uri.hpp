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
 *
 * The ECM-SK's forms (ecmxf::sk::Board::open(), Documentation/ecm-sk.rst):
 *  - "sk-sim:[<network file>][?<board settings>]": the in-process
 *    simulated board; settings as sk::BoardConfig::parse() takes them
 *    (slot=12|16, test=0|1, abandon=0|1, ex=0..3, fifo=, busy_us=,
 *    spi_hz=, lio=, paced=);
 *  - "sk-unix:<socket path>[?slot=12|16][&ex=0..3]": an
 *    `ecmxf-sim --board ecm-sk --socket <path>` server;
 *  - "sk-spidev:/dev/spidevB.C?busy=<chip>:<line>[&slot=12|16]
 *    [&speed=<Hz>][&mode=0..3][&ex=0..3]": spidev, with the board's Busy
 *    output on a GPIO line read with libgpiod (low = ready);
 *  - "sk-usb:[/dev/hidrawN][?path=<USB path>][&slot=12|16][&ex=0..3]": the
 *    board on USB through hidraw (HidrawChannel,
 *    <ecmxf/link/hidraw_channel.hpp>); without a node, the one hidraw
 *    device of USB ID 16C0:05DF (at that USB path, e.g. 1-1.2).
 * slot= and ex= tell the host what the board's CONFIG2 pin and the SET_EX
 * setting in force are: the host cannot ask the board. Each may add
 * trace=<file> (sk-spidev: "&trace=<file>"), which records every frame
 * exchanged to <file> (sk::Board::startTrace(), Documentation/trace.rst).
 */
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/sim/sk_board.hpp>

namespace ecmxf {

/// The accepted forms, as error messages list them.
inline constexpr std::string_view kDeviceUriForms =
	"\"sim:\", \"sim:<network file>\", \"/dev/ecmxfN\" (kernel module), "
	"\"unix:<socket path>\" (an ecmxf-sim --socket server), "
	"\"spidev:/dev/spidevB.C[?int0=<chip>:<line>][&int1=<chip>:<line>][&speed=<Hz>]"
	"[&mode=0..3][&ready=high|low][&size=<bytes>][&check=fixed|crc8|ccitt|crc32]\"; each may add \"trace=<file>\" as an option, "
	"sim: and unix: also \"check=fixed|crc8|ccitt|crc32\" (switch the chip to it)";

/// The ECM-SK's forms, as the errors of an "sk-" URI list them.
inline constexpr std::string_view kSkUriForms =
	"\"sk-sim:[<network file>][?slot=12|16&test=0|1&abandon=0|1&ex=0..3&fifo=<n>&busy_us=<us>&spi_hz=<Hz>&lio=0..63&paced=0|1]\", "
	"\"sk-unix:<socket path>[?slot=12|16&ex=0..3]\", "
	"\"sk-spidev:/dev/spidevB.C?busy=<chip>:<line>[&slot=12|16][&speed=<Hz>][&mode=0..3][&ex=0..3]\", "
	"\"sk-usb:[/dev/hidrawN][?path=<USB path>][&slot=12|16][&ex=0..3]\"; "
	"each may add \"trace=<file>\" as an option";

/// Highest SCLK of the ECM-SK (quick start 1.6): 24 MHz, the default of
/// "sk-spidev:".
inline constexpr std::uint32_t kSkMaxSpeedHz = 24'000'000;

/// A parsed device URI.
struct DeviceUri {
	/// Sim, Kernel, Spidev, Unix: an ECM-XF (Device::open()); SkSim,
	/// SkUnix, SkSpidev, SkUsb: an ECM-SK (sk::Board::open()).
	enum class Kind { Sim, Kernel, Spidev, Unix, SkSim, SkUnix, SkSpidev, SkUsb };
	Kind kind = Kind::Sim;
	/// Sim, SkSim: the network file (empty: the default network);
	/// Kernel: the device node; Spidev, SkSpidev: the spidev node (also
	/// in spidev.device); Unix, SkUnix: the socket path; SkUsb: the
	/// hidraw node (empty: find the board).
	std::string path;
	/// SkUsb: path=, the USB path of the board to find (empty: any).
	std::string skUsbPath;
	/// Spidev: the options (defaults from the chip manual otherwise);
	/// SkSpidev: 24 MHz, mode 0 and busy= as the ready line, low = ready.
	SpidevOptions spidev;
	/// Spidev: the format the chip speaks now (size=, check=); unset: the
	/// power-on format (112 bytes, fixed check word). Sim, Unix: check=
	/// is the check word Device::open() switches the chip to.
	std::optional<std::uint16_t> dataSize;
	std::optional<CheckType> checkType;
	/// The trace= option (every kind, the ECM-SK's too): where to record
	/// the exchanges; empty: none.
	std::string trace;
	/// The ECM-SK kinds: what the host assumes of the board, which it
	/// cannot ask (slot=: CONFIG2, 12 or 16; ex=: the SET_EX setting in
	/// force, bit 0 command CRC, bit 1 response CRC). SkSim: taken from
	/// the board's settings.
	unsigned skSlotSize = 12;
	std::uint32_t skExtensions = 0;
	/// SkSim: the simulated board's settings.
	sk::BoardConfig skBoard;

	/// Is it one of the ECM-SK's kinds?
	[[nodiscard]] bool isSk() const noexcept
	{
		return kind == Kind::SkSim || kind == Kind::SkUnix || kind == Kind::SkSpidev || kind == Kind::SkUsb;
	}
};

/// Parses @p uri. Throws ecmxf::Error (EINVAL) naming the bad part and
/// listing kDeviceUriForms (kSkUriForms for an "sk-" URI).
[[nodiscard]] ECMXF_EXPORT DeviceUri parseDeviceUri(std::string_view uri);

} // namespace ecmxf
