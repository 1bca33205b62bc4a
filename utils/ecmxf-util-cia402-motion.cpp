// SPDX-License-Identifier: MIT
/*
 * ecmxf-util cia402 -p N move (--pp|--pv|--csp) TARGET ... / home: bring
 * the bus to OP with ecmxf::Master (the EST-584s with the motion PDOs of
 * est584MotionPdos()), run the cyclic exchange, and drive one axis with
 * ecmxf::Cia402Axis: mode, enable, move or home, final position, disable.
 */
#include "ecmxf-util-cia402-motion.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <climits>
#include <functional>
#include <span>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/scope/plot.hpp>
#include <ecmxf/scope/recorder.hpp>

namespace ecmxf_util {

const char *const kCia402MotionHelp =
	"Usage: ecmxf-util [global options] cia402 -p N move (--pp|--pv|--csp) TARGET\n"
	"                  [--velocity V] [--accel A] [--relative] [--time MS]\n"
	"                  [--plot FILE.svg [--csv FILE.csv]] [--json]\n"
	"       ecmxf-util [global options] cia402 -p N home [--method M] [--json]\n"
	"\n"
	"Bring the bus to OP (ecmxf::Master: SYNC0 1 ms; every EST-584 gets the\n"
	"motion PDOs: controlword, target position, target velocity, modes of\n"
	"operation / statusword, modes display, position and velocity actual,\n"
	"following error), start the cyclic exchange (1 ms), set the mode,\n"
	"enable the drive at position N, move or home it, print the final\n"
	"position, and disable it again.\n"
	"\n"
	"move:\n"
	"  --pp TARGET     profile position (mode 1): the set-point handshake,\n"
	"                  done at target reached; --velocity = 0x6081,\n"
	"                  --accel = 0x6083 and 0x6084; --time MS limits the move\n"
	"                  (default 60000)\n"
	"  --pv TARGET     profile velocity (mode 3): TARGET is the velocity\n"
	"                  (units/s); held for --time MS (default 1000; 0: until\n"
	"                  stopped by a signal) once reached, then ramped to 0;\n"
	"                  --accel = 0x6083/0x6084\n"
	"  --csp TARGET    cyclic synchronous position (mode 8): a cosine\n"
	"                  trajectory of --time MS (default: the shortest that\n"
	"                  keeps to --velocity, default 50000 units/s)\n"
	"  --relative      TARGET is relative to the position (PP: to the\n"
	"                  previous target, controlword bit 6)\n"
	"  --plot FILE.svg record target position, position actual value,\n"
	"                  following error and statusword every cycle of the\n"
	"                  move and plot them (Documentation/scope.rst)\n"
	"  --csv FILE.csv  with --plot: the samples as CSV too\n"
	"home:\n"
	"  --method M      homing method (0x6098; the EST-584: 19, 20, 35, 37)\n"
	"\n"
	"SIGINT (Ctrl-C), SIGTERM or SIGHUP stop the drive: quick stop to\n"
	"standstill, then disable, through the process data (in OP its\n"
	"controlword overrides SDO writes), each step at most 1 s; what was done\n"
	"goes to stderr and the exit code is 128 + the signal (130, 143, 129).\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the drive's bus position (required)\n"
	"  --json            the result as a JSON object\n"
	"  -h, --help        show this help\n";

namespace {

using namespace std::chrono_literals;
using std::chrono::nanoseconds;

template <class T>
T number(std::string_view opt, std::string_view text, T lo, T hi)
{
	long long v = 0;
	std::string_view t = text;
	bool neg = false;
	if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
		neg = t[0] == '-';
		t.remove_prefix(1);
	}
	int base = 10;
	if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
		base = 16;
		t.remove_prefix(2);
	}
	const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v, base);
	if (t.empty() || ec != std::errc() || p != t.data() + t.size())
		throw UsageError("cia402: " + std::string(opt) + ": '" + std::string(text) + "' is not a number");
	if (neg)
		v = -v;
	if (v < static_cast<long long>(lo) || v > static_cast<long long>(hi))
		throw UsageError("cia402: " + std::string(opt) + " " + std::string(text) + " out of range " +
				 std::to_string(lo) + ".." + std::to_string(hi));
	return static_cast<T>(v);
}

struct Options {
	std::optional<unsigned> position;
	std::string op;              // move, home
	std::string mode;            // pp, pv, csp
	std::optional<std::int32_t> target;
	std::optional<std::uint32_t> velocity, accel;
	bool relative = false;
	std::optional<std::uint32_t> timeMs;
	std::optional<std::int8_t> method;
	PlotFiles plot;
	bool help = false;
};

Options parse(const Args &given, Globals &g)
{
	Options o;
	Args args = given;
	o.plot = takePlotFiles("cia402", args);
	auto value = [&](std::size_t &i, std::string_view opt) -> std::string_view {
		if (i + 1 >= args.size())
			throw UsageError("cia402: option '" + std::string(opt) + "' needs a value");
		return args[++i];
	};
	for (std::size_t i = 0; i < args.size(); i++) {
		const std::string_view a = args[i];
		if (a == "cia402" && i == 0)
			continue;
		if (a == "-h" || a == "--help") {
			o.help = true;
		} else if (a == "--json") {
			g.json = true;
		} else if (a == "-p" || a == "--position") {
			o.position = number<unsigned>(a, value(i, a), 0, 127);
		} else if ((a == "move" || a == "home") && o.op.empty()) {
			o.op = a;
		} else if (a == "--pp" || a == "--pv" || a == "--csp") {
			if (!o.mode.empty())
				throw UsageError("cia402 move: one of --pp, --pv, --csp only");
			o.mode = a.substr(2);
			o.target = number<std::int32_t>(a, value(i, a), INT32_MIN, INT32_MAX);
		} else if (a == "--velocity") {
			o.velocity = number<std::uint32_t>(a, value(i, a), 1, UINT32_MAX);
		} else if (a == "--accel") {
			o.accel = number<std::uint32_t>(a, value(i, a), 1, UINT32_MAX);
		} else if (a == "--relative") {
			o.relative = true;
		} else if (a == "--time") {
			o.timeMs = number<std::uint32_t>(a, value(i, a), 0, 3'600'000);
		} else if (a == "--method") {
			o.method = number<std::int8_t>(a, value(i, a), -128, 127);
		} else {
			throw UsageError("cia402: unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util cia402 move --help')");
		}
	}
	if (o.help)
		return o;
	if (!o.position)
		throw UsageError("cia402 " + o.op + ": which drive? (-p N)");
	if (o.op == "move") {
		if (o.mode.empty())
			throw UsageError("cia402 move: which mode? (--pp, --pv or --csp TARGET)");
		if (o.method)
			throw UsageError("cia402 move: --method is for home");
		if (o.timeMs == 0u && o.mode != "pv")
			throw UsageError("cia402 move: --time 0 (until stopped) is for --pv only; --" + o.mode +
					 " needs 1..3600000 ms");
	} else {
		if (!o.mode.empty() || o.velocity || o.accel || o.relative || o.timeMs)
			throw UsageError("cia402 home: only --method M");
		if (o.plot.any())
			throw UsageError("cia402 home: --plot and --csv are for move");
	}
	return o;
}

/// Bus, image, cyclic exchange and the axis.
struct Rig {
	DevicePtr dev;
	std::unique_ptr<ecmxf::Master> master;
	std::unique_ptr<ecmxf::ProcessImage> image;
	std::unique_ptr<ecmxf::Cyclic> cyc;
	std::unique_ptr<ecmxf::Cia402Axis> axis;
	/// --plot: sampled every cycle while it records (armed)
	std::unique_ptr<ecmxf::Recorder> rec;

	nanoseconds now() const { return dev->link().now(); }
	/// Cycles until the axis is done; a stop signal throws Interrupted.
	void run(nanoseconds timeout, std::string_view what)
	{
		(void)runUntil([this] { return axis->done(); }, timeout, what);
	}
	/// Cycles until @p f; a stop signal (looked at every cycle) throws
	/// Interrupted.
	std::uint64_t runUntil(const std::function<bool()> &f, nanoseconds timeout, std::string_view what)
	{
		ecmxf::Cia402Axis *a = axis.get();
		return ecmxf::runUntil(
			*cyc, std::span<ecmxf::Cia402Axis *const>(&a, 1),
			[this, &f] {
				StopSignals::check();
				if (rec)
					(void)rec->sample(now(), cyc->lastResult());
				return f();
			},
			timeout, what);
	}
};

Rig bringUp(const Globals &g, unsigned position, std::int8_t mode)
{
	Rig r;
	r.dev = openDevice(g); // the main program added --trace to it
	r.master = std::make_unique<ecmxf::Master>(*r.dev);
	bringUpMotion(*r.master);
	const auto &slaves = r.master->slaves();
	if (position >= slaves.size())
		throw ecmxf::Error("slave position " + std::to_string(position) + " out of range: the bus has " +
					   std::to_string(slaves.size()) + " slaves (0.." + std::to_string(slaves.size() - 1) +
					   ")",
				   EINVAL);
	r.image = std::make_unique<ecmxf::ProcessImage>(r.master->pdos());
	ecmxf::CyclicConfig cc;
	cc.period = 1ms;
	cc.busCycle = 1ms;
	cc.rxFill = 2; // outputs reach the bus ~2 cycles later (motion.rst)
	r.cyc = std::make_unique<ecmxf::Cyclic>(*r.dev, *r.image, cc);
	ecmxf::Cia402AxisConfig ac;
	ac.modes = { mode };
	ac.homingTimeout = 120s;
	r.axis = std::make_unique<ecmxf::Cia402Axis>(*r.dev, *r.image, static_cast<std::uint8_t>(position), ac);
	r.cyc->start();
	return r;
}

const char *modeWord(std::int8_t m)
{
	switch (m) {
	case ecmxf::cia402::kModePp:
		return "pp";
	case ecmxf::cia402::kModePv:
		return "pv";
	case ecmxf::cia402::kModeHm:
		return "home";
	default:
		return "csp";
	}
}

} // namespace

int cia402Motion(Globals &g, const Args &args)
{
	return cia402Motion(g, args, std::cout);
}

namespace {

int motion(Globals &g, const Options &o, std::int8_t mode, Rig &r, std::ostream &out);

} // namespace

int cia402Motion(Globals &g, const Args &args, std::ostream &out)
{
	Options o = parse(args, g);
	if (o.help) {
		out << kCia402MotionHelp;
		return 0;
	}
	const std::int8_t mode = o.op == "home"  ? ecmxf::cia402::kModeHm
				 : o.mode == "pp" ? ecmxf::cia402::kModePp
				 : o.mode == "pv" ? ecmxf::cia402::kModePv
						  : ecmxf::cia402::kModeCsp;
	// SIGINT, SIGTERM, SIGHUP: the drive brought to a halt through the
	// process data (in OP its controlword overrides SDO writes), said on
	// stderr, exit 128 + the signal
	const StopSignals signals;
	Rig r = bringUp(g, *o.position, mode);
	try {
		return motion(g, o, mode, r, out);
	} catch (const Interrupted &e) {
		ecmxf::Cia402Axis *a = r.axis.get();
		const auto done = ecmxf::stopAxes(*r.cyc, std::span<ecmxf::Cia402Axis *const>(&a, 1), 1s);
		std::cerr << "ecmxf-util: cia402 " << o.op << ": " << e.what() << ": "
			  << (done.empty() ? std::string("the drive could not be reached") : done.front().text) << "\n";
		try {
			r.cyc->stop();
		} catch (const ecmxf::Error &) {
			// the chip keeps sending the last outputs: the halted drive's
		}
		return StopSignals::exitCode(e.signal());
	}
}

namespace {

int motion(Globals &g, const Options &o, std::int8_t mode, Rig &r, std::ostream &out)
{
	const unsigned pos = *o.position;
	ecmxf::Cia402Axis &axis = *r.axis;
	// says on stderr that the drive moves and how to stop it
	const auto moving = [&](const std::string &what) {
		if (!g.quiet)
			std::cerr << "ecmxf-util: cia402 " << o.op << ": slave " << pos << ": " << what
				  << " (SIGINT, SIGTERM or SIGHUP stops the drive)\n";
	};
	const nanoseconds t0 = r.now();

	// let the first inputs arrive, then the mode and the enable
	int warm = 0;
	(void)r.runUntil([&] { return ++warm >= 10; }, 1s, "the first inputs");
	axis.setMode(mode, r.now());
	r.run(1s, "the mode of operation");
	axis.enable(r.now());
	r.run(3s, "OPERATION ENABLED");
	const std::int32_t start = axis.position();
	if (o.plot.any()) {
		// the move's picture: 2 minutes of 1 ms cycles at most
		r.rec = std::make_unique<ecmxf::Recorder>(120'000);
		const std::string p = std::to_string(pos) + ":";
		for (const char *name : { "0x607A:0", "0x6064:0", "0x60F4:0", "0x6041:0" }) {
			try {
				(void)r.rec->add(*r.image, p + name);
			} catch (const ecmxf::Error &e) {
				// a drive without 0x60F4 mapped: plotted without it
				if (std::string_view(name) != "0x60F4:0")
					throw;
				if (!g.quiet)
					std::cerr << "ecmxf-util: cia402 move: --plot without the following error: " << e.what()
						  << "\n";
			}
		}
		r.rec->arm();
	}

	std::int32_t target = o.target.value_or(0);
	std::optional<std::int32_t> velocityReached;
	if (mode == ecmxf::cia402::kModePp) {
		ecmxf::PpMove m;
		m.relative = o.relative;
		m.velocity = o.velocity;
		m.acceleration = o.accel;
		m.deceleration = o.accel;
		axis.moveTo(target, m, r.now());
		if (o.relative)
			target = start + target; // from rest: the previous target is the position
		moving("PP move from " + std::to_string(start) + " to " + std::to_string(target));
		r.run(std::chrono::milliseconds(o.timeMs.value_or(60000)), "target reached (PP)");
	} else if (mode == ecmxf::cia402::kModePv) {
		axis.setVelocity(target, r.now(), o.accel, o.accel);
		r.run(60s, "velocity reached (PV)");
		velocityReached = axis.velocity();
		const nanoseconds hold = std::chrono::milliseconds(o.timeMs.value_or(1000));
		moving("velocity " + std::to_string(velocityReached.value_or(target)) + " reached, held " +
		       (hold.count() ? "for " + std::to_string(o.timeMs.value_or(1000)) + " ms" : std::string("until stopped")));
		const nanoseconds h0 = r.now();
		// --time 0: until a signal stops it (no timeout)
		(void)r.runUntil([&] { return hold.count() && r.now() - h0 >= hold; }, hold.count() ? hold + 1s : 0s,
				 "the hold time");
		axis.setVelocity(0, r.now(), o.accel, o.accel);
		r.run(60s, "standstill (PV)");
	} else if (mode == ecmxf::cia402::kModeCsp) {
		if (o.relative)
			target = start + target;
		const std::array<std::int32_t, 1> from{ start };
		const std::array<std::int32_t, 1> to{ target };
		const nanoseconds duration =
			o.timeMs ? nanoseconds(std::chrono::milliseconds(*o.timeMs))
				 : ecmxf::CspTrajectory::minimumDuration(from, to, o.velocity.value_or(50000), 1ms);
		const ecmxf::CspTrajectory traj(from, to, duration);
		axis.startCsp(r.now());
		moving("CSP move from " + std::to_string(start) + " to " + std::to_string(target));
		ecmxf::Cia402Axis *a = &axis;
		const nanoseconds c0 = r.now();
		(void)r.runUntil(
			[&] {
				traj.apply(std::span<ecmxf::Cia402Axis *const>(&a, 1), r.now() - c0 + 1ms);
				return traj.finished(r.now() - c0) && axis.position() == target;
			},
			duration + 1s, "the CSP trajectory's end");
	} else {
		ecmxf::HomingParams h;
		h.method = o.method;
		axis.home(h, r.now());
		moving("homing");
		r.run(120s, "homing attained");
	}
	const std::int32_t final = axis.position();
	const auto vel = axis.velocity();
	const std::uint16_t sw = axis.statusword();
	const double ms = std::chrono::duration<double, std::milli>(r.now() - t0).count();
	const std::uint64_t cycles = r.cyc->stats().cycles;
	if (r.rec) {
		r.rec->finish();
		if (r.rec->size() == r.rec->capacity() && !g.quiet)
			std::cerr << "ecmxf-util: cia402 move: the plot holds the move's first " << r.rec->capacity()
				  << " cycles\n";
	}

	axis.disable(r.now());
	r.run(3s, "SWITCH ON DISABLED");
	r.cyc->stop();
	if (r.rec)
		writePlotFiles(*r.rec, o.plot,
			       "cia402 move --" + o.mode + " " + std::to_string(o.target.value_or(0)) + ": slave " +
				       std::to_string(pos) + " on " + g.device);

	const bool home = mode == ecmxf::cia402::kModeHm;
	if (g.json) {
		out << "{\"slave\":" << pos << ",\"operation\":\"" << (home ? "home" : "move") << "\",\"mode\":\""
		    << modeWord(mode) << "\"";
		if (!home)
			out << ",\"target\":" << target;
		if (home && o.method)
			out << ",\"method\":" << int{ *o.method };
		out << ",\"start\":" << start << ",\"position\":" << final;
		if (velocityReached)
			out << ",\"velocity_reached\":" << *velocityReached;
		if (vel)
			out << ",\"velocity\":" << *vel;
		out << ",\"statusword\":" << sw << ",\"cycles\":" << cycles << ",\"time_ms\":" << static_cast<long>(ms)
		    << "}\n";
		return 0;
	}
	if (home) {
		out << "slave " << pos << ": homing attained";
		if (o.method)
			out << " (method " << int{ *o.method } << ")";
		out << ", position " << final << "\n";
	} else if (mode == ecmxf::cia402::kModePv) {
		out << "slave " << pos << ": velocity " << (velocityReached ? *velocityReached : 0)
		    << " reached, stopped at position " << final << "\n";
	} else {
		out << "slave " << pos << ": " << (mode == ecmxf::cia402::kModePp ? "PP" : "CSP") << " move from "
		    << start << " to " << target << ": position " << final << "\n";
	}
	out << "statusword " << ecmxf::cia402Hex16(sw) << ", " << cycles << " cycles, "
	    << static_cast<long>(ms) << " ms (bus time); drive disabled\n";
	return 0;
}

} // namespace

PlotFiles takePlotFiles(std::string_view cmd, Args &args)
{
	PlotFiles f;
	for (std::size_t i = 0; i < args.size();) {
		const std::string_view a = args[i];
		std::optional<std::string> *slot = a.starts_with("--plot") ? &f.svg : a.starts_with("--csv") ? &f.csv : nullptr;
		const std::string_view name = a.substr(0, a.find('='));
		if (!slot || (name != "--plot" && name != "--csv")) {
			i++;
			continue;
		}
		std::string value;
		std::size_t used = 1;
		if (name.size() < a.size()) {
			value = std::string(a.substr(name.size() + 1));
		} else {
			if (i + 1 >= args.size())
				throw UsageError(std::string(cmd) + ": option '" + std::string(name) + "' needs a value");
			value = std::string(args[i + 1]);
			used = 2;
		}
		if (value.empty())
			throw UsageError(std::string(cmd) + ": " + std::string(name) + ": an empty file name");
		if (slot->has_value())
			throw UsageError(std::string(cmd) + ": " + std::string(name) + " given twice");
		*slot = value;
		args.erase(args.begin() + static_cast<std::ptrdiff_t>(i), args.begin() + static_cast<std::ptrdiff_t>(i + used));
	}
	if (f.csv && !f.svg)
		throw UsageError(std::string(cmd) + ": --csv is written with --plot FILE.svg");
	return f;
}

void writePlotFiles(const ecmxf::Recorder &rec, const PlotFiles &files, const std::string &title)
{
	if (files.csv)
		ecmxf::writeCsv(rec, *files.csv);
	if (files.svg) {
		ecmxf::SvgOptions so;
		so.title = title;
		ecmxf::writeSvg(rec, *files.svg, so);
	}
}

void bringUpMotion(ecmxf::Master &m)
{
	constexpr std::uint32_t kEst584Vendor = 0x00000E5C;
	constexpr std::uint32_t kEst584Product = 0x00000584;
	// a first scan tells which slaves are EST-584s: they get the motion PDOs
	ecmxf::MasterConfig scan;
	scan.init.dc.sync0Ns = 1'000'000;
	scan.target = ecmxf::State::PreOp;
	scan.enableFifo = false;
	scan.readPdoMapping = false;
	m.bringUp(scan);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = 1'000'000;
	for (const ecmxf::SlaveInfo &s : m.slaves())
		if (s.vendorId == kEst584Vendor && s.productCode == kEst584Product)
			mc.pdoAssignments.push_back(ecmxf::est584MotionPdos(s.position));
	m.bringUp(mc);
}

} // namespace ecmxf_util
