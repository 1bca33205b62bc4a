// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - command-line tool for the ECM-XF, in the manner of IgH's
 * `ethercat` tool:
 *
 *   ecmxf-util [-d URI] [--json] COMMAND [ARGS]
 *
 * Each command is its own unit (ecmxf-util-<command>.cpp) with its own
 * help text; unambiguous prefixes of command names are accepted. Errors
 * go to stderr as "ecmxf-util: <reason>": exit code 1 for failures, 2 for
 * bad usage.
 */
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/verbs.hpp>

#include "ecmxf-util.hpp"
#include "ecmxf-util-scope.hpp"
#include "ecmxf-util-sk.hpp"

using namespace ecmxf_util;

namespace {

const char *const kCommandsHelp =
	"Usage: ecmxf-util [global options] commands [--json]\n"
	"\n"
	"List the ECM-XF command codes of both manuals (ver. 038 and 050): code,\n"
	"name, immediate or async, the manuals that document it, the *_GET that\n"
	"fetches its result and the default timeout. Needs no device.\n"
	"\n"
	"Options:\n"
	"  --json      a JSON array instead of the table\n"
	"  -h, --help  show this help\n";

const char *const kVersionHelp = "Usage: ecmxf-util version [--json]\n"
				 "\n"
				 "Print the version of ecmxf-util and libecmxf (--json: {\"version\": ...}).\n";

std::string partnerName(const ecmxf::CommandInfo &ci)
{
	if (!ci.partner)
		return "-";
	auto p = ecmxf::commandInfo(*ci.partner);
	return p ? std::string(p->name) : std::to_string(*ci.partner);
}

int cmdCommands(Globals &g, const Args &args)
{
	if (parseFlags("commands", args, g, kCommandsHelp, {}))
		return 0;
	const std::size_t n = ecmxf::commandCount();

	if (g.json) {
		std::printf("[");
		for (std::size_t i = 0; i < n; i++) {
			const auto ci = ecmxf::commandAt(i);
			std::printf("%s\n  {\"code\": %u, \"name\": \"%.*s\", \"async\": %s, "
				    "\"v038\": %s, \"v050\": %s, \"partner\": %s, \"timeout_ms\": %u}",
				    i ? "," : "", ci.code, static_cast<int>(ci.name.size()),
				    ci.name.data(), ci.async ? "true" : "false",
				    ci.inV038 ? "true" : "false", ci.inV050 ? "true" : "false",
				    ci.partner ? std::to_string(*ci.partner).c_str() : "null",
				    ci.timeoutMs);
		}
		std::printf("\n]\n");
		return 0;
	}
	std::printf("%-4s  %-28s %-6s %-8s %-26s %s\n", "CODE", "NAME", "KIND", "MANUALS",
		    "RESULT / READ-BACK", "TIMEOUT");
	for (std::size_t i = 0; i < n; i++) {
		const auto ci = ecmxf::commandAt(i);
		std::string kind = ci.async ? (ci.asyncOnlyParam0 ? "async*" : "async") : "immed";
		std::string manuals = std::string(ci.inV038 ? "038" : "") +
				      (ci.inV038 && ci.inV050 ? "+" : "") + (ci.inV050 ? "050" : "");
		std::printf("%4u  %-28.*s %-6s %-8s %-26s %u ms\n", ci.code,
			    static_cast<int>(ci.name.size()), ci.name.data(), kind.c_str(),
			    manuals.c_str(), partnerName(ci).c_str(), ci.timeoutMs);
	}
	std::printf("\n%zu commands; async* = async only with command parameter 0\n", n);
	return 0;
}

void printVersion()
{
	std::printf("ecmxf-util %.*s\n", static_cast<int>(ecmxf::version().size()),
		    ecmxf::version().data());
}

int cmdVersion(Globals &g, const Args &args)
{
	if (parseFlags("version", args, g, kVersionHelp, {}))
		return 0;
	if (g.json)
		std::printf("{\"version\": %s}\n", jsonString(ecmxf::version()).c_str());
	else
		printVersion();
	return 0;
}

// The one command table, for both masters: each command says which it
// runs on (on), why not on the other (whyNot), and on the ECM-SK its body
// and summary there (utils/ecmxf-util-sk.cpp) where the two differ.
constexpr std::string_view kNoSii = "the slot protocol has no access to the slaves' SII EEPROM";
constexpr std::string_view kNoFoe = "the slot protocol has no FoE";
constexpr std::string_view kOwnMapping = "the ECM-SK maps the process data itself (by slave type)";

const CommandDesc kCommands[] = {
	{ "adc", "read the chip's analog inputs", kAdcHelp, cmdAdc, true, kOnXf,
	  "the ECM-SK has no analog inputs (its own I/O is 'lio')" },
	{ "cia402", "CiA-402 drive over SDO: status, enable, disable, fault-reset...", kCia402Help, cmdCia402, true,
	  kOnBoth, {}, cmdSkCia402, "SV_ON/SV_OFF/ALM_CLR, a CSP move, GO_HOME (-p N ...)" },
	{ "commands", "list the ECM-XF command codes (ver. 038 and 050)", kCommandsHelp, cmdCommands, false, kOnXf,
	  "lists ECM-XF command codes; the ECM-SK's are in Documentation/ecm-sk.rst" },
	{ "cstruct", "the PDO mapping as IgH's C structures (pdos --cstruct)", kCstructHelp, cmdCstruct, true, kOnXf,
	  kOwnMapping },
	{ "data", "the process image decoded by entry; --set writes an output entry", kDataHelp, cmdData, true,
	  kOnXf, "the board exchanges the process data itself; 'cia402' and 'io' show a slave's slot" },
	{ "dac", "set the chip's analog output", kDacHelp, cmdDac, true, kOnXf, "the ECM-SK has no analog output" },
	{ "decode", "decode a packet trace (--trace FILE) as a protocol log", kDecodeHelp, cmdDecode, false, kOnBoth },
	{ "download", "write an object by SDO download", kDownloadHelp, cmdDownload, true, kOnBoth, {}, nullptr,
	  "SDO_WR through the SDO slot (-p N -t TYPE INDEX[:SUB] VALUE)" },
	{ "eeprom", "read or write SII EEPROM words", kEepromHelp, cmdEeprom, true, kOnXf, kNoSii },
	{ "emergency", "the newest CoE emergencies the master read", kEmergencyHelp, cmdEmergency, true, kOnXf,
	  "the slot protocol does not pass CoE emergencies on" },
	{ "foe_read", "read a file from a slave by FoE", kFoeReadHelp, cmdFoeRead, true, kOnXf, kNoFoe },
	{ "foe_write", "write a file to a slave by FoE", kFoeWriteHelp, cmdFoeWrite, true, kOnXf, kNoFoe },
	{ "gpio", "the chip's GPIO lines: get, set, config", kGpioHelp, cmdGpio, true, kOnXf,
	  "the ECM-SK's I/O lines are 'lio' (LIO_RD/LIO_WR)" },
	{ "info", "firmware, packet format, status bits and counters of the chip", kInfoHelp, cmdInfo, true,
	  kOnBoth, {}, cmdSkInfo, "frame, state, CRC errors, FIFO, slaves" },
	{ "io", "an I/O slave's first 4 input/output bytes (IO_RD/IO_WR)", nullptr, nullptr, true, kOnSk,
	  "a slave's I/O is process data on the ECM-XF (ecmxf-util pdos)", cmdSkIo,
	  "IO_RD, or IO_WR VALUE (IO slaves, in OP; -p N [VALUE])" },
	{ "lio", "the master's own I/O 0..5 (LIO_RD/LIO_WR)", nullptr, nullptr, true, kOnSk,
	  "the chip's own I/O lines are 'gpio'", cmdSkLio, "LIO_RD, or LIO_WR VALUE: the ECM IC's I/O 0..5" },
	{ "master", "the master's phase, link and error counters (as IgH's ethercat master)", kMasterHelp, cmdMaster,
	  true, kOnXf, "the ECM-SK has no master counters; 'info' shows its state, CRC errors and FIFO" },
	{ "monitor", "live events: state changes, error bits, CRC/WKC errors, FIFO levels", kMonitorHelp, cmdMonitor,
	  false, kOnXf, "the ECM-SK reports no events; poll 'info' instead" },
	{ "pdos", "PDO assignment and mapping of each slave", kPdosHelp, cmdPdos, true, kOnXf, kOwnMapping },
	{ "qei", "the chip's quadrature encoder: open, start, stop, count", kQeiHelp, cmdQei, true, kOnXf,
	  "the ECM-SK has no encoder input" },
	{ "raw", "one raw command (or EtherCAT datagram): response header and data", kRawHelp, cmdRaw, false, kOnXf,
	  "ECM-XF command packets only" },
	{ "reg_read", "read an ESC register of a slave (one APRD datagram)", kRegReadHelp, cmdRegRead, true, kOnXf,
	  "the slot protocol has no datagrams to the slaves' ESC registers" },
	{ "reg_write", "write an ESC register of a slave (one APWR datagram)", kRegWriteHelp, cmdRegWrite, true,
	  kOnXf, "the slot protocol has no datagrams to the slaves' ESC registers" },
	{ "reset", "ASYNCCMD_RESET, or WARM_RESET with --warm --force", kResetHelp, cmdReset, true, kOnBoth, {},
	  cmdSkReset, "SW_RESET: the board restarts in INIT" },
	{ "scope", "record process data and cycle figures in OP: CSV and an SVG plot", kScopeHelp, cmdScope, true,
	  kOnBoth, {}, nullptr, "record feedback slots and FIFO figures in OP: CSV and an SVG plot" },
	{ "sii_read", "a slave's SII EEPROM: hex dump, binary or identity", kSiiReadHelp, cmdSiiRead, true, kOnXf,
	  kNoSii },
	{ "sii_write", "write an SII image file into a slave's EEPROM", kSiiWriteHelp, cmdSiiWrite, true, kOnXf,
	  kNoSii },
	{ "slaves", "list the slaves on the bus (scans a fresh simulator first)", kSlavesHelp, cmdSlaves, true,
	  kOnBoth, {}, cmdSkSlaves, "the slaves and their types (found by SET_AXIS), identity (SDO 0x1018)" },
	{ "states", "request an EtherCAT state for one or all slaves", kStatesHelp, cmdStates, true, kOnBoth, {},
	  cmdSkStates, "INIT, PREOP, SAFEOP or OP for the bus (types found first)" },
	{ "upload", "read an object by SDO upload", kUploadHelp, cmdUpload, true, kOnBoth, {}, nullptr,
	  "SDO_RD through the SDO slot (-p N [-t TYPE] INDEX[:SUB])" },
	{ "version", "print the version", kVersionHelp, cmdVersion, false, kOnBoth },
	{ "xml", "identity and PDO mapping as EtherCATInfo XML (pdos --xml)", kXmlHelp, cmdXml, true, kOnXf,
	  kOwnMapping },
};

/// Does @p c run on the master of the device given (@p sk: an ECM-SK)?
bool runsOn(const CommandDesc &c, bool sk)
{
	return (c.on & (sk ? kOnSk : kOnXf)) != 0;
}

/// The commands of the master the device names (@p sk: an ECM-SK).
void usage(std::FILE *out, bool sk)
{
	std::fprintf(out, "Usage: ecmxf-util [global options] COMMAND [ARGS]\n"
			  "\n"
			  "Commands%s (unambiguous prefixes are accepted):\n",
		     sk ? " on an ECM-SK" : "");
	for (const CommandDesc &c : kCommands) {
		if (!runsOn(c, sk))
			continue;
		const std::string_view summary = sk && !c.skSummary.empty() ? c.skSummary : c.summary;
		std::fprintf(out, "  %-10.*s %.*s\n", static_cast<int>(c.name.size()), c.name.data(),
			     static_cast<int>(summary.size()), summary.data());
	}
	if (sk)
		std::fprintf(out, "\n"
				  "Positions (-p) count from 0 as on the ECM-XF (slot 1 of the frame is -p 0);\n"
				  "the SDO slot carries 1, 2 or 4 bytes; a fresh board is brought as far up as\n"
				  "the command needs. Not on the ECM-SK (each says why): ");
	if (sk) {
		bool first = true;
		for (const CommandDesc &c : kCommands)
			if (!runsOn(c, sk)) {
				std::fprintf(out, "%s%.*s", first ? "" : ", ", static_cast<int>(c.name.size()),
					     c.name.data());
				first = false;
			}
		std::fprintf(out, ".\n");
	}
	std::fprintf(out,
		     "\n"
		     "Global options:\n"
		     "  -d, --device URI  the chip: \"sim:\" (default; the in-process simulator\n"
		     "                    with its default network), \"sim:<network file>\",\n"
		     "                    \"/dev/ecmxfN\" (kernel module), \"unix:<socket path>\"\n"
		     "                    (an ecmxf-sim --socket server; its chip keeps its state\n"
		     "                    between runs) or \"spidev:/dev/spidevB.C\n"
		     "                    [?int0=<chip>:<line>&int1=<chip>:<line>&speed=<Hz>&mode=0..3]\"\n"
		     "                    ECM-SK: \"sk-sim:\", \"sk-unix:PATH\", \"sk-spidev:/dev/spidevB.C\n"
		     "                    ?busy=<chip>:<line>\", \"sk-usb:[/dev/hidrawN][?path=<USB path>]\"\n"
		     "                    (ecmxf-util -d sk-sim: help)\n"
		     "  --trace FILE      record every exchange with the chip (or ECM-SK) to FILE\n"
		     "                    (ecmxf-util decode FILE shows it)\n"
		     "  --json            JSON output for scripts\n"
		     "  -q, --quiet       print nothing but errors and the data asked for\n"
		     "  --progress        progress of long transfers (foe_write, sii_write, pdos) on\n"
		     "                    stderr even when stdout is not a terminal\n"
		     "  -h, --help        show this help\n"
		     "  -V, --version     print the version\n"
		     "\n"
		     "'ecmxf-util COMMAND --help' describes one command.\n");
}

/// The command @p name, or the only one it is a prefix of among those
/// that run on the device's master (@p sk: an ECM-SK).
const CommandDesc &findCommand(std::string_view name, bool sk)
{
	std::vector<const CommandDesc *> matches;
	for (const CommandDesc &c : kCommands) {
		if (c.name == name)
			return c;
		if (c.name.starts_with(name) && runsOn(c, sk))
			matches.push_back(&c);
	}
	// IgH's commands that the ECM-XF cannot do: what to use instead
	if (const auto alt = ighAlternative(name))
		throw UsageError(*alt);
	if (matches.size() == 1)
		return *matches.front();
	if (matches.empty())
		throw UsageError("unknown command '" + std::string(name) + "'" + (sk ? " for an ECM-SK" : "") +
				 " (try --help)");
	std::string names;
	for (const CommandDesc *c : matches)
		names += (names.empty() ? "" : ", ") + std::string(c->name);
	throw UsageError("ambiguous command '" + std::string(name) + "': " + names);
}

int run(int argc, char **argv)
{
	Globals g;
	bool help = false;
	int i = 1;
	for (; i < argc; i++) {
		const std::string_view a = argv[i];
		if (a == "-h" || a == "--help") {
			help = true; // after -d, wherever it stands: the device's commands
			continue;
		}
		if (a == "-V" || a == "--version") {
			printVersion();
			return 0;
		}
		if (a == "--json") {
			g.json = true;
		} else if (a == "-q" || a == "--quiet") {
			g.quiet = true;
		} else if (a == "--progress") {
			g.progress = true;
		} else if (a == "-d" || a == "--device") {
			if (i + 1 >= argc)
				throw UsageError("option '" + std::string(a) + "' needs a device URI");
			g.device = argv[++i];
		} else if (a == "--trace") {
			if (i + 1 >= argc)
				throw UsageError("option '--trace' needs a file name");
			g.trace = argv[++i];
		} else if (a.starts_with("--trace=")) {
			g.trace = std::string(a.substr(std::strlen("--trace=")));
		} else if (a.starts_with("--device=")) {
			g.device = std::string(a.substr(std::strlen("--device=")));
		} else if (a.size() > 2 && a.starts_with("-d")) {
			g.device = std::string(a.substr(2));
		} else if (a.starts_with("-")) {
			if (help)
				break; // --help came first: it wins, as it always did
			throw UsageError("unknown option '" + std::string(a) + "' (try --help)");
		} else {
			break;
		}
	}
	const bool sk = skDevice(g); // an ECM-SK: the bodies of utils/ecmxf-util-sk.cpp
	if (help || (i < argc && std::string_view(argv[i]) == "help" && i + 1 >= argc)) {
		usage(stdout, sk);
		return 0;
	}
	if (i >= argc) {
		usage(stderr, sk);
		return 2;
	}
	if (std::string_view(argv[i]) == "help") {
		// help COMMAND = COMMAND --help
		const CommandDesc &c = findCommand(argv[i + 1], sk);
		std::fputs((sk && c.runSk) || !c.help ? skHelp() : c.help, stdout);
		return 0;
	}
	const CommandDesc &cmd = findCommand(argv[i], sk);
	const Args args(argv + i + 1, argv + argc);
	auto *const run = sk && cmd.runSk ? cmd.runSk : cmd.run;
	if (!g.trace.empty())
		g.device.append(g.device.find('?') == std::string::npos ? "?trace=" : "&trace=").append(g.trace);
	if (!cmd.prefixErrors && runsOn(cmd, sk))
		return run(g, args);
	try {
		if (!runsOn(cmd, sk))
			ecmxf::throwNotOn(sk ? ecmxf::MasterKind::EcmSk : ecmxf::MasterKind::EcmXf, cmd.whyNot);
		return run(g, args);
	} catch (const UsageError &) {
		throw;
	} catch (const std::exception &e) {
		// "ecmxf-util: <command>: <reason>"
		const std::string prefix = std::string(cmd.name) + ": ";
		const std::string_view what = e.what();
		if (what.starts_with(prefix))
			throw;
		throw std::runtime_error(std::string(prefix).append(what));
	}
}

} // namespace

namespace {

/// Output that did not reach standard output (a full disk, a closed pipe
/// reader, /dev/full) is a failure: said on stderr, exit code 1.
int checkStdout(int rc)
{
	errno = 0;
	if (std::fflush(stdout) == 0 && !std::ferror(stdout))
		return rc;
	const int err = errno;
	std::fprintf(stderr, "ecmxf-util: cannot write to standard output%s%s\n", err ? ": " : "",
		     err ? std::strerror(err) : "");
	return rc ? rc : 1;
}

/// A trace that could not be written (CloseTrace) fails the run.
int checkTrace(int rc)
{
	if (!*traceFailure())
		return rc;
	std::fprintf(stderr, "ecmxf-util: %s\n", traceFailure());
	return rc ? rc : 1;
}

} // namespace

int main(int argc, char **argv)
{
	try {
		return checkStdout(checkTrace(run(argc, argv)));
	} catch (const UsageError &e) {
		std::fprintf(stderr, "ecmxf-util: %s\n", e.what());
		return checkStdout(checkTrace(2));
	} catch (const std::exception &e) {
		std::fprintf(stderr, "ecmxf-util: %s\n", e.what());
		return checkStdout(checkTrace(1));
	}
}
