// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - what the command units share: the global options, usage
 * errors, JSON strings, little-endian fields and state names.
 */
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/device.hpp>

namespace ecmxf_util {

/// Options given before the command (and --json also after it).
struct Globals {
	std::string device = "sim:"; ///< -d/--device URI
	bool json = false;           ///< --json
	std::string trace;           ///< --trace FILE (added to the URI as trace=FILE)
};

/// Bad command-line usage: reported as "ecmxf-util: <reason>", exit code 2.
class UsageError : public std::runtime_error
{
public:
	using std::runtime_error::runtime_error;
};

using Args = std::vector<std::string_view>;

/// One command: its name, a one-line summary, its help text and its body.
struct CommandDesc {
	std::string_view name;
	std::string_view summary;
	const char *help;
	int (*run)(Globals &g, const Args &args);
};

/// Parses a command's arguments that take no value: -h/--help prints
/// @p help and returns true; --json sets g.json; each name in @p flags
/// sets the bool next to it; anything else throws UsageError.
struct Flag {
	std::string_view shortName;
	std::string_view longName;
	bool *value;
};
bool parseFlags(std::string_view cmd, const Args &args, Globals &g, const char *help,
		const std::vector<Flag> &flags);

/// @p s as a JSON string literal, quotes included.
std::string jsonString(std::string_view s);

/// A command with no data section.
ecmxf::Command simpleCommand(std::uint8_t code, std::uint8_t param = 0);

/// Little-endian fields of an answer; throw std::runtime_error naming
/// @p what when the answer is too short.
std::uint16_t le16(const ecmxf::Response &r, std::string_view what);
std::uint32_t le32(const ecmxf::Response &r, std::string_view what);

/// EtherCAT state names as `ethercat slaves` prints them: INIT, PREOP,
/// BOOT, SAFEOP, OP; 0 is NONE (no network), 0x10 ERROR; others in hex.
std::string stateName(std::uint8_t state);

// command codes (manual ver. 050)
inline constexpr std::uint8_t kInitOp = 1;
inline constexpr std::uint8_t kStateGet = 13;
inline constexpr std::uint8_t kSlvInfoGet = 15;
inline constexpr std::uint8_t kSlvCntGet = 16;
inline constexpr std::uint8_t kSpiPackSizeGet = 20;
inline constexpr std::uint8_t kFwVersionGet = 56;

int cmdInfo(Globals &g, const Args &args);
int cmdSlaves(Globals &g, const Args &args);
int cmdDecode(Globals &g, const Args &args);
extern const char *const kInfoHelp;
extern const char *const kSlavesHelp;
extern const char *const kDecodeHelp;

// raw (ecmxf-util-raw.cpp), monitor (ecmxf-util-monitor.cpp)
int cmdRaw(Globals &g, const Args &args);
int cmdMonitor(Globals &g, const Args &args);
extern const char *const kRawHelp;
extern const char *const kMonitorHelp;

} // namespace ecmxf_util
