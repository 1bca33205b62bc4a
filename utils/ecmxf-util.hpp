// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - what the command units share: the global options, usage
 * errors, JSON strings, little-endian fields and state names.
 */
#pragma once

#include <chrono>
#include <cstdio>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/model/objects.hpp>

#include <signal.h>

#include <uapi/linux/ecmxf.h> // the chip's command codes and header bits

namespace ecmxf_util {

/// Options given before the command (and --json also after it).
struct Globals {
	std::string device = "sim:"; ///< -d/--device URI
	bool json = false;           ///< --json
	std::string trace;           ///< --trace FILE (added to the URI as trace=FILE)
	bool quiet = false;          ///< -q/--quiet: nothing but errors and the data asked for
	bool progress = false;       ///< --progress: progress lines on stderr even off a terminal
};

/// Progress of a long transfer on stderr: "foe_write: 51200/204800 bytes
/// (25%), 7.8 kB/s, 20 s left". Shown when stdout and stderr are
/// terminals (not with -q or --json: redrawn in place, at most 10 times a
/// second), or with --progress (then a line at most once a second off a
/// terminal); silent otherwise. The last update ends the line.
class Progress
{
public:
	Progress(const Globals &g, std::string what, std::string unit);
	/// @p done of @p total units.
	void operator()(std::size_t done, std::size_t total);
	[[nodiscard]] bool shown() const noexcept { return on_; }

private:
	std::string what_, unit_;
	bool on_ = false, tty_ = false, ended_ = false;
	std::chrono::steady_clock::time_point t0_, last_;
};

/// Bad command-line usage: reported as "ecmxf-util: <reason>", exit code 2.
class UsageError : public std::runtime_error
{
public:
	using std::runtime_error::runtime_error;
};

using Args = std::vector<std::string_view>;

/// The masters a command runs on (CommandDesc::on).
enum Masters : unsigned { kOnXf = 1, kOnSk = 2, kOnBoth = kOnXf | kOnSk };

/// One command of the one table (utils/ecmxf-util.cpp): its name, a
/// one-line summary, its help text and its body, and what it needs of the
/// device: the masters it runs on; on another, "not on the <master>:
/// <why>" (exit 1).
struct CommandDesc {
	std::string_view name;
	std::string_view summary;
	const char *help;
	int (*run)(Globals &g, const Args &args);
	/// Failures (not usage errors) are reported as "<name>: <reason>".
	bool prefixErrors = false;
	/// The masters it runs on.
	unsigned on = kOnXf;
	/// Why it does not run on the master it lacks.
	std::string_view whyNot = {};
	/// On an ECM-SK: its body there (null: run serves both) and its
	/// summary there (empty: summary).
	int (*runSk)(Globals &g, const Args &args) = nullptr;
	std::string_view skSummary = {};
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

// command codes (<linux/ecmxf.h>)
inline constexpr std::uint8_t kInitOp = ECMXF_CMD_ECAT_INIT_OP;
inline constexpr std::uint8_t kStateGet = ECMXF_CMD_ECAT_STATE_GET;
inline constexpr std::uint8_t kSlvInfoGet = ECMXF_CMD_ECAT_SLV_INFO_GET;
inline constexpr std::uint8_t kSlvCntGet = ECMXF_CMD_ECAT_SLV_CNT_GET;
inline constexpr std::uint8_t kSpiPackSizeGet = ECMXF_CMD_SPI_PACK_SIZE_GET;
inline constexpr std::uint8_t kFwVersionGet = ECMXF_CMD_FW_VERSION_GET;

// ---- arguments with values, numbers, object addresses (ecmxf-util-common.cpp)

/// An option of a command: a flag (@c flag set) or one that takes a value
/// (@c value set; "--name VALUE" or "--name=VALUE").
struct Option {
	std::string_view shortName;
	std::string_view longName;
	bool *flag = nullptr;
	std::optional<std::string> *value = nullptr;
};

/// Parses a command's arguments: -h/--help prints @p help and returns
/// std::nullopt; --json sets g.json, -q/--quiet g.quiet; the options of
/// @p opts; the rest (including negative numbers such as -5) are returned
/// in order. An unknown option or a missing value throws UsageError.
std::optional<std::vector<std::string>> parseArgs(std::string_view cmd, const Args &args, Globals &g,
						  const char *help, const std::vector<Option> &opts);

/// A number (decimal, 0x hex) in @p min..@p max; UsageError
/// "<cmd>: <what>: ..." otherwise.
std::uint64_t parseUnsigned(std::string_view cmd, std::string_view what, std::string_view text,
			    std::uint64_t max, std::uint64_t min = 0);
std::int64_t parseSigned(std::string_view cmd, std::string_view what, std::string_view text, std::int64_t min,
			 std::int64_t max);
double parseReal(std::string_view cmd, std::string_view what, std::string_view text);

/// INDEX[:SUB], e.g. 0x6064:00 or 0x6064 (sub 0). Each part is a number
/// of its own: decimal, or hex with 0x (0x1A00:0x0A; 0x6064:10 is sub 10).
struct ObjectAddress {
	std::uint16_t index = 0;
	std::uint8_t sub = 0;
};
ObjectAddress parseObjectAddress(std::string_view cmd, std::string_view text);
/// IgH's INDEX SUB as two arguments (INDEX without ':').
ObjectAddress parseObjectAddress(std::string_view cmd, std::string_view index, std::string_view sub);
/// "0x6064:00", "0x1A00:0x0a": parseObjectAddress() reads it back.
std::string objectName(ObjectAddress a);

/// "0x%0*x"
std::string hexString(std::uint64_t v, int digits);
/// Bytes as "92 01 03 00" (@p sep between them).
std::string hexBytes(const std::vector<std::uint8_t> &b, const char *sep = " ");

/// -p/--position N: 0..127 (UsageError otherwise).
std::uint8_t parsePosition(std::string_view cmd, const std::optional<std::string> &text);

/// The slaves of a -p that takes several: positions in ascending order,
/// each once.
struct Positions {
	std::vector<unsigned> list;
	[[nodiscard]] bool has(unsigned p) const;
};
/// -p N, a list "0,2", a range "0-3", or both ("0,2-4"): each position
/// 0..127, a range low-high with low <= high; UsageError naming the item
/// that is wrong otherwise.
Positions parsePositions(std::string_view cmd, std::string_view text);
/// checkPosition() for the highest of @p p.
void checkPositions(const Positions &p, unsigned count);

/// The first trace failure of the run ("writing the trace file ...
/// failed: ..."), "" when none: a buffer, so that a failing run need not
/// allocate on its way out (the text is cut to fit).
inline char *traceFailure() noexcept
{
	static char text[512];
	return text;
}

/// The trace a device or board records (--trace, trace= in the URI) is
/// stopped when the tool lets the device go, and a write that failed (a
/// full disk, /dev/full) is kept in traceFailure() for the end of the run:
/// main() says it and exits with 1. The library's destructors close a
/// trace without a word; these deleters do not let that happen.
struct CloseTrace {
	template <class T>
	void operator()(T *t) const noexcept
	{
		try {
			if (t->tracing())
				t->stopTrace();
		} catch (const std::exception &e) {
			if (!*traceFailure())
				std::snprintf(traceFailure(), 512, "%s", e.what());
		}
		delete t;
	}
};
using DevicePtr = std::unique_ptr<ecmxf::Device, CloseTrace>;
using BoardPtr = std::unique_ptr<ecmxf::sk::Board, CloseTrace>;

/// Opens g.device (an ECM-XF).
inline DevicePtr openDevice(const Globals &g)
{
	return DevicePtr(ecmxf::Device::open(g.device).release());
}
/// Opens g.device (an ECM-SK).
inline BoardPtr openBoard(const Globals &g)
{
	return BoardPtr(ecmxf::sk::Board::open(g.device).release());
}

/// How far a command needs the bus.
enum class BusNeed {
	Scan,   ///< the slaves known (ECAT_INIT_OP): EEPROM, slave lists
	PreOp,  ///< mailboxes up (ECAT_STATE_SET PRE-OP): SDO, FoE, CiA-402 over SDO
};

/**
 * THE bring-up rule of ecmxf-util: when the chip reports no initialised
 * network (ECAT state 0 after ECAT_SLV_CNT_GET, as a fresh "sim:" does),
 * bring the bus up as far as @p need: ECAT_INIT_OP (all slaves, the
 * library's DC defaults) and for PreOp ECAT_STATE_SET PRE-OP for all
 * slaves. A bus that is already up (a real device someone configured) is
 * left as it is. With @p verbose, says on stderr what it does. Returns
 * the slave count.
 */
unsigned ensureBus(ecmxf::Device &dev, BusNeed need, bool verbose = false);
/// True when the chip reports no initialised network (ECAT state 0).
bool busDown(ecmxf::Device &dev);

/// Throws "slave position N out of range: the bus has C slaves (0..C-1)"
/// when @p position >= @p count (a usage error when -a was given to a
/// command that does not take it).
void checkPosition(unsigned position, unsigned count);
/// The slave a command addresses: -p N as it is (checked against @p
/// count), or with IgH's -a ALIAS the N-th slave after the first one whose
/// station alias is ALIAS (ENODEV when none has it or that is beyond the
/// bus).
std::uint8_t selectSlave(ecmxf::Device &dev, std::uint8_t position, unsigned count);

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

// the bus and slave commands (ecmxf-util-<name>.cpp)
#define ECMXF_UTIL_COMMAND(fn, helpVar) \
	int fn(Globals &g, const Args &args); \
	extern const char *const helpVar;
ECMXF_UTIL_COMMAND(cmdStates, kStatesHelp)
ECMXF_UTIL_COMMAND(cmdUpload, kUploadHelp)
ECMXF_UTIL_COMMAND(cmdDownload, kDownloadHelp)
ECMXF_UTIL_COMMAND(cmdPdos, kPdosHelp)
ECMXF_UTIL_COMMAND(cmdData, kDataHelp)
ECMXF_UTIL_COMMAND(cmdCstruct, kCstructHelp)
ECMXF_UTIL_COMMAND(cmdXml, kXmlHelp)
ECMXF_UTIL_COMMAND(cmdSiiRead, kSiiReadHelp)
ECMXF_UTIL_COMMAND(cmdEeprom, kEepromHelp)
ECMXF_UTIL_COMMAND(cmdFoeRead, kFoeReadHelp)
ECMXF_UTIL_COMMAND(cmdFoeWrite, kFoeWriteHelp)
ECMXF_UTIL_COMMAND(cmdGpio, kGpioHelp)
ECMXF_UTIL_COMMAND(cmdQei, kQeiHelp)
ECMXF_UTIL_COMMAND(cmdAdc, kAdcHelp)
ECMXF_UTIL_COMMAND(cmdDac, kDacHelp)
ECMXF_UTIL_COMMAND(cmdEmergency, kEmergencyHelp)
ECMXF_UTIL_COMMAND(cmdReset, kResetHelp)
ECMXF_UTIL_COMMAND(cmdCia402, kCia402Help)
// IgH's ethercat commands (ecmxf-util-igh.cpp)
ECMXF_UTIL_COMMAND(cmdRegRead, kRegReadHelp)
ECMXF_UTIL_COMMAND(cmdRegWrite, kRegWriteHelp)
ECMXF_UTIL_COMMAND(cmdSiiWrite, kSiiWriteHelp)
ECMXF_UTIL_COMMAND(cmdMaster, kMasterHelp)
#undef ECMXF_UTIL_COMMAND
/// For an IgH ethercat command that ecmxf-util does not have: the message
/// saying what to use instead; std::nullopt for any other name.
std::optional<std::string> ighAlternative(std::string_view name);

// ---- SDO data types (-t; ecmxf-util-types.cpp)

enum class DataType {
	Bool, Int8, Int16, Int32, Int64, Uint8, Uint16, Uint32, Uint64, Float, Double, String, OctetString,
	Sm8, Sm16, Sm32, Sm64, ///< IgH's sign-and-magnitude integers
};
/// -t TYPE: the contract's names and IgH's (unicode_string, sm8..sm64,
/// raw) and aliases (sint8.., real32/64).
DataType parseType(std::string_view cmd, std::string_view text);
std::string_view typeName(DataType t);
/// Bytes of a fixed-size type; 0 for string and octet_string.
std::size_t typeSize(DataType t);
/// The -t type of a standard object's type (<ecmxf/model/objects.hpp>).
DataType dataTypeOf(ecmxf::ObjectType t) noexcept;
/// int8..uint64 and sm8..sm64.
bool integerType(DataType t) noexcept;
/// VALUE as the little-endian bytes of @p t (octet_string: hex bytes).
std::vector<std::uint8_t> encodeValue(std::string_view cmd, DataType t, std::string_view text);
/// Bytes of an object as text / as a JSON value. Without a type: the
/// unsigned little-endian value as hex and decimal for 1, 2, 4 or 8
/// bytes ("0x00030192 197010"), else the bytes in hex.
std::string formatValue(std::optional<DataType> t, const std::vector<std::uint8_t> &b);
std::string jsonValue(std::optional<DataType> t, const std::vector<std::uint8_t> &b);

// ---- the safe stop (ecmxf-util-signals.cpp)

/// SIGINT, SIGTERM and SIGHUP handled while it lives (the previous
/// handlers back after): the handler only records the first signal; a
/// command that enables or moves a drive looks at it every cycle, brings
/// the drive to a halt and exits with 128 + the signal (exitCode()).
class StopSignals
{
public:
	StopSignals();
	~StopSignals();
	StopSignals(const StopSignals &) = delete;
	StopSignals &operator=(const StopSignals &) = delete;
	/// The signal received (0: none yet).
	[[nodiscard]] static int pending() noexcept;
	/// Throws Interrupted when a signal came.
	static void check();
	/// 130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP.
	[[nodiscard]] static int exitCode(int sig) noexcept { return 128 + sig; }

private:
	struct sigaction old_[3];
};

/// What StopSignals::check() throws: "interrupted by SIGINT".
class Interrupted : public std::runtime_error
{
public:
	explicit Interrupted(int sig);
	[[nodiscard]] int signal() const noexcept { return sig_; }

private:
	int sig_;
};

/// "SIGINT", "SIGTERM", "SIGHUP".
std::string_view signalName(int sig) noexcept;

/// cia402 move / home (ecmxf-util-cia402-motion.cpp): @p args are all of
/// cia402's arguments. The dispatch point for the motion commands.
int cia402Motion(Globals &g, const Args &args);

/// The text of a CiA 301 emergency error code (its class, e.g. 0x8130
/// "monitoring: life guard / heartbeat error").
std::string emergencyCodeText(std::uint16_t code);

} // namespace ecmxf_util
