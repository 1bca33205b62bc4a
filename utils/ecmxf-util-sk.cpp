// SPDX-License-Identifier: MIT
/*
 * ecmxf-util with an ECM-SK device (-d sk-sim:, sk-unix:, sk-spidev:, sk-usb:):
 * the bodies on ecmxf::sk::Board of the commands the starter kit's slot
 * protocol can carry (info, slaves, states, upload, download, cia402, io,
 * lio, reset), their verbs through ecmxf::MasterVerbs. The command table,
 * and why the board cannot do the others, is utils/ecmxf-util.cpp's.
 * Documentation/ecm-sk.rst, "ecmxf-util".
 */
#include "ecmxf-util.hpp"
#include "ecmxf-util-sk.hpp"

#include "ecmxf-util-cia402-motion.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/verbs.hpp>
#include <ecmxf/device_uri.hpp>

namespace ecmxf_util {

namespace {

using ecmxf::sk::Board;
using ecmxf::sk::Mode;
using ecmxf::sk::SlaveType;
using ecmxf::State;

const char *const kSkHelp =
	"With an ECM-SK device (-d sk-sim:..., sk-unix:PATH, sk-spidev:..., sk-usb:...)\n"
	"ecmxf-util speaks the starter kit's slot protocol. Commands:\n"
	"\n"
	"  info                        frame, state, CRC errors, FIFO, slaves\n"
	"  slaves [-p N] [-v]          the slaves, their types (found by SET_AXIS) and\n"
	"                              identity (0x1018; -v: revision, serial number)\n"
	"  states STATE                INIT, PREOP, SAFEOP or OP (types found first)\n"
	"  upload -p N [-t TYPE] INDEX[:SUB]          SDO_RD through the SDO slot\n"
	"  download -p N [-t TYPE] INDEX[:SUB] VALUE  SDO_WR through the SDO slot\n"
	"  cia402 -p N status|enable|disable|fault-reset|move TARGET|home METHOD\n"
	"                              move TARGET [--plot FILE.svg [--csv FILE.csv]]:\n"
	"                              the move's target, position, following error\n"
	"                              and statusword plotted (Documentation/scope.rst)\n"
	"  scope SIGNAL... [options]   record feedback slots and FIFO figures in OP\n"
	"                              (ecmxf-util -d sk-sim: scope --help)\n"
	"  io -p N [VALUE]             IO_RD, or IO_WR VALUE (IO slaves, in OP)\n"
	"  lio [VALUE]                 LIO_RD, or LIO_WR VALUE: the ECM IC's I/O 0..5\n"
	"  reset                       SW_RESET\n"
	"\n"
	"Positions (-p) count from 0 as on the ECM-XF: -p 0 is the first slave\n"
	"(slot 1 of the frame). Types are 1, 2 or 4 bytes: the SDO slot carries at\n"
	"most 4. --json works with every command. A fresh board (sk-sim: starts in\n"
	"INIT at every run) is brought as far up as the command needs.\n";

using SkBody = std::function<int(Globals &, Board &, const std::vector<std::string> &,
				 const std::optional<std::string> &, const std::optional<std::string> &)>;

// the command line's spelling ("PREOP"), as for the ECM-XF
std::string stateText(State s)
{
	return stateName(static_cast<std::uint8_t>(s));
}

// INIT -> PRE-OP if needed
void preop(Board &b, bool quiet)
{
	// silently, as the ECM-XF's ensureBus() does
	(void)quiet;
	if (b.states().status().state == State::Init)
		b.states().set(State::PreOp);
}

// up to OP: types found, DRIVE_MODE CSP for drives
void toOp(Board &b, bool quiet)
{
	if (b.states().status().state == State::Op)
		return;
	preop(b, quiet);
	ecmxf::sk::bringUpToOp(b);
}

unsigned slot(Board &b, const std::optional<std::string> &posText, const char *cmd, unsigned count)
{
	const std::uint8_t p = parsePosition(cmd, posText);
	if (p >= count)
		throw ecmxf::Error("slave position " + std::to_string(p) + " out of range: the bus has " +
					   std::to_string(count) + " slaves (0.." + std::to_string(count ? count - 1 : 0) +
					   ")",
				   EINVAL);
	(void)b;
	return p + 1u;
}

int info(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &,
	 const std::optional<std::string> &)
{
	if (!args.empty())
		throw UsageError("info: no arguments");
	const auto s = b.states().status();
	unsigned slaves = 0;
	if (s.state == State::PreOp)
		slaves = b.setup().slaveCount();
	auto *sim = b.simulator();
	if (g.json) {
		std::printf("{\"device\": %s, \"board\": \"ECM-SK\", \"slot_size\": %u, \"frame_size\": %zu, "
			    "\"max_slaves\": %u, \"state\": %s, \"crc_errors\": %u, \"fifo_remaining\": %s, "
			    "\"fifo_full\": %s, \"slaves\": %s, \"simulated\": %s}\n",
			    jsonString(g.device).c_str(), b.slotSize(), b.frameSize(), b.maxSlaves(),
			    jsonString(stateText(s.state)).c_str(), s.crcErrors,
			    s.state == State::Op ? std::to_string(s.fifoRemaining).c_str() : "null",
			    s.state == State::Op ? std::to_string(s.fifoFull).c_str() : "null",
			    s.state == State::PreOp ? std::to_string(slaves).c_str() : "null",
			    sim ? "true" : "false");
		return 0;
	}
	std::printf("Device:        %s (NEXTW ECM-SK, slot protocol)\n", g.device.c_str());
	std::printf("Frame:         %zu bytes, %u slots of %u bytes, up to %u slaves\n", b.frameSize(),
		    b.maxSlaves() + 2, b.slotSize(), b.maxSlaves());
	std::printf("State:         %s\n", stateText(s.state).c_str());
	std::printf("CRC errors:    %u (frames the board refused)\n", s.crcErrors);
	if (s.state == State::Op)
		std::printf("FIFO:          %u free, %u dropped (full)\n", s.fifoRemaining, s.fifoFull);
	if (s.state == State::PreOp)
		std::printf("Slaves:        %u\n", slaves);
	if (sim)
		std::printf("Simulator:     cycle %u us, SET_EX in force 0x%X, saved 0x%X\n", sim->cycleUs(),
			    sim->extensionsInForce(), sim->extensionsSaved());
	return 0;
}

// slaves -v: 0x1018:03 and :04 by SDO_RD, nullopt where the slave has
// none (an I/O terminal without CoE)
std::optional<std::uint32_t> identityWord(ecmxf::MasterVerbs &v, unsigned position, std::uint8_t sub)
{
	try {
		const std::vector<std::uint8_t> d = v.upload(position, 0x1018, sub);
		if (d.size() != 4)
			return std::nullopt;
		return std::uint32_t{ d[0] } | std::uint32_t{ d[1] } << 8 | std::uint32_t{ d[2] } << 16 | std::uint32_t{ d[3] } << 24;
	} catch (const ecmxf::Error &) {
		return std::nullopt;
	}
}

int slaves(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &pos,
	   bool verbose)
{
	if (!args.empty())
		throw UsageError("slaves: no arguments");
	const std::optional<Positions> only = pos ? std::optional(parsePositions("slaves", *pos)) : std::nullopt;
	preop(b, g.quiet || g.json);
	if (b.state() != State::PreOp)
		throw ecmxf::Error("slaves: the types are found in PRE-OP; the ECM-SK is in " +
					   stateText(b.state()) + " (ecmxf-util states PREOP)",
				   EPERM);
	// the slave list of both masters (MasterVerbs): types by SET_AXIS,
	// identity by SDO 0x1018 where the slave answers
	const auto verbs = ecmxf::verbsOf(b);
	auto list = verbs->slaves();
	if (only) {
		checkPositions(*only, static_cast<unsigned>(list.size()));
		std::erase_if(list, [&](const ecmxf::SlaveSummary &s) { return !only->has(s.position); });
	}
	struct More {
		std::optional<std::uint32_t> revision, serial;
	};
	std::vector<More> more(list.size());
	if (verbose)
		for (std::size_t i = 0; i < list.size(); i++)
			more[i] = { identityWord(*verbs, list[i].position, 3), identityWord(*verbs, list[i].position, 4) };
	const auto num = [](const std::optional<std::uint32_t> &v) { return v ? std::to_string(*v) : "null"; };
	const auto hex = [](const std::optional<std::uint32_t> &v) { return v ? hexString(*v, 8) : std::string("-"); };
	if (g.json) {
		// the ECM-XF's field names (vendor_id, product_code, revision,
		// serial_number), null when unknown
		std::printf("[");
		for (std::size_t i = 0; i < list.size(); i++) {
			std::printf("%s\n  {\"position\": %u, \"state\": %s, \"type\": %s, \"vendor_id\": %s, "
				    "\"product_code\": %s",
				    i ? "," : "", list[i].position, jsonString(stateText(list[i].state)).c_str(),
				    jsonString(list[i].kind).c_str(), num(list[i].vendorId).c_str(),
				    num(list[i].productCode).c_str());
			if (verbose)
				std::printf(", \"revision\": %s, \"serial_number\": %s", num(more[i].revision).c_str(),
					    num(more[i].serial).c_str());
			std::printf("}");
		}
		std::printf("\n]\n");
		return 0;
	}
	if (verbose)
		std::printf("%-3s %-6s %-6s %-21s %-10s %s\n", "POS", "STATE", "TYPE", "VENDOR:PRODUCT", "REVISION",
			    "SERIAL");
	for (std::size_t i = 0; i < list.size(); i++) {
		const auto &sl = list[i];
		const std::string id = sl.vendorId && sl.productCode
					       ? hexString(*sl.vendorId, 8) + ":" + hexString(*sl.productCode, 8)
					       : "-";
		if (verbose)
			std::printf("%-3u %-6s %-6s %-21s %-10s %s\n", sl.position, stateText(sl.state).c_str(),
				    sl.kind.c_str(), id.c_str(), hex(more[i].revision).c_str(), hex(more[i].serial).c_str());
		else
			std::printf("%-3u %-6s %-6s %s\n", sl.position, stateText(sl.state).c_str(), sl.kind.c_str(),
				    id.c_str());
	}
	return 0;
}

int states(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &pos,
	   const std::optional<std::string> &)
{
	// -p N would move the whole board: refused, not done silently
	if (pos)
		ecmxf::throwNotOn(ecmxf::MasterKind::EcmSk,
				  "states -p N: the board has one state for the whole bus (SET_STATE); 'states STATE' "
				  "moves every slave");
	if (args.size() != 1)
		throw UsageError("states: which state? (INIT, PREOP, SAFEOP, OP)");
	std::string want = args[0];
	for (auto &c : want)
		c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
	State target;
	if (want == "INIT")
		target = State::Init;
	else if (want == "PREOP" || want == "PRE-OP")
		target = State::PreOp;
	else if (want == "SAFEOP" || want == "SAFE-OP")
		target = State::SafeOp;
	else if (want == "OP")
		target = State::Op;
	else
		throw UsageError("states: unknown state '" + args[0] + "' (INIT, PREOP, SAFEOP, OP)");
	if (target == State::Op) {
		toOp(b, g.quiet || g.json);
	} else if (target == State::SafeOp) {
		preop(b, true);
		if (b.state() == State::PreOp)
			(void)b.setup().detectAxes();
		b.states().set(target);
	} else {
		b.states().set(target);
	}
	if (g.json)
		std::printf("{\"state\": %s}\n", jsonString(stateText(b.state())).c_str());
	else if (!g.quiet)
		std::printf("%s\n", stateText(b.state()).c_str());
	return 0;
}

unsigned opSlot(Globals &g, Board &b, const std::optional<std::string> &pos, const char *cmd)
{
	if (b.states().status().state == State::Init)
		preop(b, g.quiet || g.json);
	unsigned count = b.maxSlaves();
	if (b.state() == State::PreOp)
		count = b.setup().slaveCount();
	const unsigned s = slot(b, pos, cmd, count);
	toOp(b, g.quiet || g.json);
	return s;
}

int cia402Op(Globals &g, Board &b, const std::vector<std::string> &args, unsigned s, const PlotFiles &plot);

int cia402(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &pos,
	   const PlotFiles &plot)
{
	if (args.empty())
		throw UsageError("cia402: status, enable, disable, fault-reset, move TARGET or home METHOD");
	const std::string &what = args[0];
	const unsigned s = opSlot(g, b, pos, "cia402");
	// enable, move, home: SIGINT, SIGTERM, SIGHUP halt the drive (SV_OFF:
	// the board owns the controlword and has no quick stop) and exit with
	// 128 + the signal
	std::optional<StopSignals> signals;
	if (what == "enable" || what == "move" || what == "home")
		signals.emplace();
	try {
		if (plot.any() && what != "move")
			throw UsageError("cia402: --plot and --csv are for move");
		return cia402Op(g, b, args, s, plot);
	} catch (const Interrupted &e) {
		std::string done;
		try {
			const auto a = b.drives().halt(s);
			const auto st = ecmxf::cia402StateFrom(a.statusword);
			done = "slave " + std::to_string(s - 1) + ": SV_OFF: " +
			       (st ? std::string(ecmxf::cia402StateName(*st)) : std::string("no CiA-402 state")) +
			       " (statusword " + hexString(a.statusword, 4) + "), position " + std::to_string(a.position);
		} catch (const std::exception &x) {
			done = std::string("NOT halted: ") + x.what();
		}
		std::fprintf(stderr, "ecmxf-util: cia402 %s: %s: %s\n", what.c_str(), e.what(), done.c_str());
		return StopSignals::exitCode(e.signal());
	}
}

int cia402Op(Globals &g, Board &b, const std::vector<std::string> &args, unsigned s, const PlotFiles &plot)
{
	const std::string &what = args[0];
	const auto verbs = ecmxf::verbsOf(b);
	if (what == "enable") {
		verbs->driveEnable(s - 1);
		StopSignals::check();
	} else if (what == "disable") {
		verbs->driveDisable(s - 1);
	} else if (what == "fault-reset") {
		verbs->driveAlarmClear(s - 1);
	} else if (what == "move") {
		if (args.size() != 2)
			throw UsageError("cia402 move TARGET");
		const auto target = static_cast<std::int32_t>(parseSigned("cia402", "TARGET", args[1], INT32_MIN, INT32_MAX));
		b.drives().servoOn(s);
		b.drives().waitEnabled(s);
		b.states().status();
		const std::int32_t from = b.drives().axis(s).position;
		// --plot: target, position, following error (target - position)
		// and statusword of every exchange of the move
		std::int64_t setPoint = from, followingError = 0;
		std::unique_ptr<ecmxf::Recorder> rec;
		if (plot.any()) {
			rec = std::make_unique<ecmxf::Recorder>(120'000);
			const std::string p = std::to_string(s - 1) + ":";
			(void)rec->addValue(p + "target", "inc", &setPoint);
			(void)rec->add(b, b.maxSlaves(), p + "position");
			(void)rec->addValue(p + "following_error", "inc", &followingError);
			(void)rec->add(b, b.maxSlaves(), p + "statusword");
			rec->arm();
		}
		const auto sample = [&](const ecmxf::sk::CycleResult &r) {
			if (!rec)
				return;
			followingError = setPoint - b.drives().axis(s).position;
			(void)rec->sample(b.channel().now(), r);
		};
		// a ramp of at most 1000 units per exchange (the board applies
		// one per cycle); the FIFO's back-pressure paces it
		const std::int64_t dist = static_cast<std::int64_t>(target) - from;
		const std::int64_t steps = std::max<std::int64_t>(1, (std::llabs(dist) + 999) / 1000);
		if (!g.quiet)
			std::fprintf(stderr,
				     "ecmxf-util: cia402 move: slave %u: CSP move from %d to %d (SIGINT, SIGTERM or SIGHUP "
				     "stops the drive)\n",
				     s - 1, from, target);
		for (std::int64_t i = 1; i <= steps;) {
			StopSignals::check();
			const auto next = static_cast<std::int32_t>(from + dist * i / steps);
			if (b.cyclic().stage(s, Mode::Csp, next)) {
				setPoint = next;
				i++;
			}
			const auto r = b.cyclic().cycle();
			if (r.status == ecmxf::sk::CycleStatus::Link)
				throw ecmxf::Error("cia402 move: " + b.cyclic().lastError(), EIO);
			if (r.status == ecmxf::sk::CycleStatus::FifoOverflow)
				throw ecmxf::Error("cia402 move: the ECM-SK dropped " + std::to_string(r.dropped) +
							   " targets (FIFO full, or abandoned after 100 cycles)",
						   ENOBUFS);
			sample(r);
		}
		for (int i = 0; i < 2000 && std::llabs(static_cast<std::int64_t>(b.drives().axis(s).position) - target) > 0; i++) {
			StopSignals::check();
			b.channel().sleepFor(std::chrono::milliseconds(1));
			sample(b.cyclic().cycle());
		}
		if (rec) {
			rec->finish();
			writePlotFiles(*rec, plot,
				       "cia402 move " + std::to_string(target) + ": slave " + std::to_string(s - 1) + " on " +
					       g.device);
		}
	} else if (what == "home") {
		if (args.size() != 2)
			throw UsageError("cia402 home METHOD");
		const auto method = static_cast<std::int8_t>(parseSigned("cia402", "METHOD", args[1], -128, 127));
		b.drives().servoOn(s);
		b.drives().waitEnabled(s);
		StopSignals::check();
		b.drives().home(s, method);
		StopSignals::check();
	} else if (what != "status") {
		throw UsageError("cia402: unknown action '" + what + "'");
	}
	b.states().status();
	const auto a = b.drives().axis(s);
	if (g.json) {
		// the ECM-XF's field names where the two show the same thing
		const auto st = ecmxf::cia402StateFrom(a.statusword);
		std::printf("{\"position\": %u, \"statusword\": %u, \"state\": %s, \"position_actual\": %d, "
			    "\"torque_actual\": %d, \"error_code\": %u}\n",
			    s - 1, a.statusword,
			    jsonString(st ? ecmxf::cia402StateName(*st) : std::string_view("no CiA-402 state")).c_str(),
			    a.position, a.torque, a.errorCode);
		return 0;
	}
	if (!g.quiet || what == "status")
		std::printf("slave %u: statusword %s, position %d, torque %d, error code %s\n", s - 1,
			    hexString(a.statusword, 4).c_str(), a.position, a.torque, hexString(a.errorCode, 4).c_str());
	return 0;
}

int io(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &pos,
       const std::optional<std::string> &)
{
	if (args.size() > 1)
		throw UsageError("io -p N [VALUE]");
	const unsigned s = opSlot(g, b, pos, "io");
	if (args.size() == 1) {
		const auto v = static_cast<std::uint32_t>(parseUnsigned("io", "VALUE", args[0], 0xFFFFFFFFu));
		ecmxf::verbsOf(b)->ioWrite(s - 1, v);
		if (g.json)
			std::printf("{\"position\": %u, \"outputs\": %u}\n", s - 1, v);
		return 0;
	}
	const std::uint32_t v = ecmxf::verbsOf(b)->ioRead(s - 1);
	if (g.json)
		std::printf("{\"position\": %u, \"inputs\": %u}\n", s - 1, v);
	else
		std::printf("%s\n", hexString(v, 8).c_str());
	return 0;
}

int lio(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &,
	const std::optional<std::string> &)
{
	if (args.size() > 1)
		throw UsageError("lio [VALUE]");
	if (args.size() == 1) {
		const auto v = static_cast<std::uint32_t>(parseUnsigned("lio", "VALUE", args[0], 0x3F));
		b.io().writeLocal(v);
		if (g.json)
			std::printf("{\"outputs\": %u}\n", v);
		return 0;
	}
	const std::uint32_t v = b.io().readLocal();
	if (g.json)
		std::printf("{\"inputs\": %u}\n", v);
	else
		std::printf("%s\n", hexString(v, 2).c_str());
	return 0;
}

int reset(Globals &g, Board &b, const std::vector<std::string> &args, const std::optional<std::string> &,
	  const std::optional<std::string> &)
{
	if (!args.empty())
		throw UsageError("reset: no arguments");
	ecmxf::verbsOf(b)->reset();
	if (g.json)
		std::printf("{\"state\": %s}\n", jsonString(stateText(b.state())).c_str());
	else if (!g.quiet)
		std::printf("ECM-SK reset: %s\n", stateText(b.state()).c_str());
	return 0;
}

// -p/-t (and -v where @p verbose is given), the board opened, and
// "<command>: " before a failure
int onBoard(Globals &g, const Args &rawArgs, const char *name, const SkBody &body, bool *verbose = nullptr)
{
	std::optional<std::string> posText, typeText;
	static const std::string help = std::string(kSkHelp);
	std::vector<Option> opts = { { "-p", "--position", nullptr, &posText }, { "-t", "--type", nullptr, &typeText } };
	if (verbose)
		opts.push_back({ "-v", "--verbose", verbose, nullptr });
	const auto args = parseArgs(name, rawArgs, g, help.c_str(), opts);
	if (!args)
		return 0;
	const auto board = openBoard(g); // the main program added --trace to it
	return body(g, *board, *args, posText, typeText);
}

} // namespace

bool skDevice(const Globals &g)
{
	return Board::isSkUri(g.device);
}

const char *skHelp() noexcept
{
	return kSkHelp;
}

std::unique_ptr<ecmxf::MasterVerbs> openMaster(const Globals &g)
{
	return ecmxf::MasterVerbs::open(g.device);
}

std::uint8_t sdoPosition(const Globals &g, ecmxf::MasterVerbs &m, std::uint8_t position)
{
	if (ecmxf::Device *dev = m.device())
		return selectSlave(*dev, position, ensureBus(*dev, BusNeed::PreOp));
	Board &b = *m.board();
	if (b.states().status().state == State::Init)
		preop(b, g.quiet || g.json);
	const unsigned slaves = b.setup().slaveCount();
	const unsigned count = slaves ? slaves : b.maxSlaves();
	if (position >= count)
		throw ecmxf::Error("slave position " + std::to_string(position) + " out of range: the bus has " +
					   std::to_string(count) + " slaves (0.." + std::to_string(count ? count - 1 : 0) +
					   ")",
				   EINVAL);
	return position;
}

void checkSdoType(const Globals &g, const char *cmd, const std::optional<DataType> &type)
{
	if (!skDevice(g) || !type)
		return;
	const auto n = typeSize(*type);
	if (n != 1 && n != 2 && n != 4)
		throw ecmxf::Error(std::string(cmd) + ": type " + std::string(typeName(*type)) +
					   ": the ECM-SK's SDO slot carries objects of 1, 2 or 4 bytes",
				   EOPNOTSUPP);
}

int cmdSkInfo(Globals &g, const Args &a) { return onBoard(g, a, "info", info); }
int cmdSkSlaves(Globals &g, const Args &a)
{
	bool verbose = false; // -v, set by onBoard()'s parse before the body runs
	return onBoard(
		g, a, "slaves",
		[&verbose](Globals &gg, Board &b, const std::vector<std::string> &args,
			   const std::optional<std::string> &pos,
			   const std::optional<std::string> &) { return slaves(gg, b, args, pos, verbose); },
		&verbose);
}
int cmdSkStates(Globals &g, const Args &a) { return onBoard(g, a, "states", states); }
int cmdSkCia402(Globals &g, const Args &a)
{
	Args rest = a;
	const PlotFiles plot = takePlotFiles("cia402", rest); // move --plot FILE.svg [--csv FILE.csv]
	return onBoard(g, rest, "cia402",
		       [&plot](Globals &gg, Board &b, const std::vector<std::string> &args,
			       const std::optional<std::string> &pos,
			       const std::optional<std::string> &) { return cia402(gg, b, args, pos, plot); });
}
int cmdSkIo(Globals &g, const Args &a) { return onBoard(g, a, "io", io); }
int cmdSkLio(Globals &g, const Args &a) { return onBoard(g, a, "lio", lio); }
int cmdSkReset(Globals &g, const Args &a) { return onBoard(g, a, "reset", reset); }

} // namespace ecmxf_util
