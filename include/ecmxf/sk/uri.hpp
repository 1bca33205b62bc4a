// SPDX-License-Identifier: MIT
/**
 * @file uri.hpp
 * @brief The ECM-SK device URIs, parsed.
 *
 *  - "sk-sim:[<network file>][?<board settings>]": the in-process
 *    simulated board; settings as BoardConfig::parse() takes them
 *    (slot=12|16, test=0|1, abandon=0|1, ex=0..3, fifo=, busy_us=,
 *    spi_hz=, lio=);
 *  - "sk-unix:<socket path>[?slot=12|16][&ex=0..3]": an
 *    `ecmxf-sim --board ecm-sk --socket <path>` server;
 *  - "sk-spidev:/dev/spidevB.C?busy=<chip>:<line>[&slot=12|16]
 *    [&speed=<Hz>][&mode=0..3][&ex=0..3]": spidev, with the board's Busy
 *    output on a GPIO line read with libgpiod (low = ready).
 *
 * slot= and ex= tell the host what the board's CONFIG2 pin and the SET_EX
 * setting in force are: the host cannot ask the board.
 */
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/sim/sk_board.hpp>

namespace ecmxf::sk {

/// The forms, as error messages list them.
inline constexpr std::string_view kSkUriForms =
	"\"sk-sim:[<network file>][?slot=12|16&test=0|1&abandon=0|1&ex=0..3&fifo=<n>&busy_us=<us>&spi_hz=<Hz>&lio=0..63]\", "
	"\"sk-unix:<socket path>[?slot=12|16&ex=0..3]\", "
	"\"sk-spidev:/dev/spidevB.C?busy=<chip>:<line>[&slot=12|16][&speed=<Hz>][&mode=0..3][&ex=0..3]\"";

/// Highest SCLK of the ECM-SK (quick start 1.6): 24 MHz.
inline constexpr std::uint32_t kSkMaxSpeedHz = 24'000'000;

struct SkUri {
	enum class Kind { Sim, Unix, Spidev };
	Kind kind = Kind::Sim;
	std::string path;	 ///< Sim: network file (empty: default); Unix: socket; Spidev: node
	BoardConfig board;	 ///< Sim: the board's settings
	unsigned slotSize = 12;	 ///< what the host assumes
	std::uint32_t extensions = 0;
	SpidevOptions spidev;	 ///< Spidev: node, speed, mode, Busy as INT0 (ready low)
};

/// Parses @p uri; throws ecmxf::Error (EINVAL) naming the bad part and
/// listing kSkUriForms.
[[nodiscard]] ECMXF_EXPORT SkUri parseSkUri(std::string_view uri);

} // namespace ecmxf::sk
