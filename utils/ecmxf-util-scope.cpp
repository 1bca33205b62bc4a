// SPDX-License-Identifier: MIT
/*
 * ecmxf-util scope - record process data and cycle figures while the bus
 * runs in OP (ecmxf::Recorder), then write them as CSV and an SVG plot
 * (ecmxf::writeCsv, ecmxf::writeSvg); on the ECM-XF (sim:, unix:, spidev,
 * /dev/ecmxfN) and on the ECM-SK (its feedback slots), with a live view
 * in the terminal while it records (ecmxf::terminalText, LiveView). Also
 * the plot files of `cia402 move --plot` (takePlotFiles, writePlotFiles).
 */
#include "ecmxf-util-scope.hpp"

#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/scope/plot.hpp>
#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/scope/terminal.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/board_views.hpp>

#include "ecmxf-util-sk.hpp"

namespace ecmxf_util {

const char *const kScopeHelp =
	"Usage: ecmxf-util [global options] scope SIGNAL... [--cycles N | --time MS]\n"
	"                  [--trigger 'SIGNAL>LEVEL' | --trigger 'SIGNAL<LEVEL'] [--pre N]\n"
	"                  [--timeout MS] [--buffer N] [--csv FILE] [--svg FILE]\n"
	"                  [--title TEXT] [--live | --no-live] [--json]\n"
	"\n"
	"Record SIGNALs every cycle (1 ms) while the bus runs in OP, then write\n"
	"them as CSV (time in us, one column per signal, its unit in the header)\n"
	"and as an SVG plot (a time axis, one y-axis per unit, legend, grid, the\n"
	"minimum and maximum of each signal), and print each signal's minimum,\n"
	"maximum and last value. A fresh bus is brought to OP first (ECM-XF: the\n"
	"Master, SYNC0 1 ms, the EST-584s with the motion PDOs; ECM-SK: types\n"
	"found, CSP); a bus that is up is used as it is (its mapping read).\n"
	"\n"
	"SIGNAL (Documentation/scope.rst):\n"
	"  N:NAME        process-data entry NAME of slave N (case, spaces, '_' and\n"
	"                '-' ignored: 0:position_actual_value)\n"
	"  N:INDEX:SUB   the entry mapped as INDEX:SUB (hex: 0:6064:0, 0:0x607A:0)\n"
	"  wkc, wkc_expected, wkc_errors, rx_fifo, tx_fifo, pushed, popped, error\n"
	"                the ECM-XF's cycle figures\n"
	"  ECM-SK: N:position, N:statusword, N:torque, N:error_code (slave N's\n"
	"                feedback slot); fifo_remaining, fifo_full, dropped, staged\n"
	"\n"
	"Options:\n"
	"  --cycles N        stop after N samples from the trigger on (default\n"
	"                    1000 when --time is not given)\n"
	"  --time MS         stop MS ms (bus time) after the trigger\n"
	"  --trigger S>L     start when signal S rises to L or above (S<L: falls\n"
	"                    to L or below); S is recorded too; a word of bits or\n"
	"                    a code (statusword) is refused. Default: at once\n"
	"  --pre N           keep N samples from before the trigger (default 0)\n"
	"  --timeout MS      give up when the trigger has not come in MS ms (bus\n"
	"                    time; default 10000): exit 1, no file written\n"
	"  --buffer N        samples held (default: what the stop needs)\n"
	"  --csv FILE        write the samples as CSV\n"
	"  --svg FILE        write the SVG plot\n"
	"  --title TEXT      the plot's title (default: the device and signals)\n"
	"  --live            draw the signals in the terminal while recording\n"
	"                    (braille dots, 10 times a second; q or Ctrl-C stops\n"
	"                    the recording, the files are written, exit 0).\n"
	"                    Default: on when stdout is a terminal, without --json\n"
	"                    and -q\n"
	"  --no-live         no live view\n"
	"  --json            the summary as a JSON object\n"
	"  -h, --help        show this help\n"
	"\n"
	"The files are written whole or not at all (a temporary file renamed over\n"
	"FILE): an error names the file and the reason, exit 1. SIGINT (Ctrl-C),\n"
	"SIGTERM or SIGHUP end the recording early: what was recorded is written,\n"
	"exit 0.\n";

namespace {

using namespace std::chrono_literals;

struct ScopeOptions {
	std::vector<std::string> signals;
	std::optional<std::uint64_t> cycles;
	std::optional<std::uint64_t> timeMs;
	ecmxf::RecorderTrigger trigger;
	std::uint64_t timeoutMs = 10000;
	std::optional<std::uint64_t> buffer;
	PlotFiles files;
	std::optional<std::string> title;
	bool live = false;
};

ScopeOptions parseScope(const Args &args, Globals &g, bool &help)
{
	std::optional<std::string> cycles, timeMs, trigger, pre, timeout, buffer, csv, svg, title;
	bool live = false, noLive = false;
	const auto pos = parseArgs("scope", args, g, kScopeHelp,
				   { { "", "--cycles", nullptr, &cycles },
				     { "", "--time", nullptr, &timeMs },
				     { "", "--trigger", nullptr, &trigger },
				     { "", "--pre", nullptr, &pre },
				     { "", "--timeout", nullptr, &timeout },
				     { "", "--buffer", nullptr, &buffer },
				     { "", "--csv", nullptr, &csv },
				     { "", "--svg", nullptr, &svg },
				     { "", "--title", nullptr, &title },
				     { "", "--live", &live, nullptr },
				     { "", "--no-live", &noLive, nullptr } });
	ScopeOptions o;
	if (!pos) {
		help = true;
		return o;
	}
	o.signals = *pos;
	if (o.signals.empty())
		throw UsageError("scope: which signals? (N:NAME, N:INDEX:SUB or a cycle figure; try --help)");
	if (cycles && timeMs)
		throw UsageError("scope: --cycles or --time, not both");
	if (cycles)
		o.cycles = parseUnsigned("scope", "--cycles", *cycles, 10'000'000, 1);
	if (timeMs)
		o.timeMs = parseUnsigned("scope", "--time", *timeMs, 3'600'000, 1);
	if (!cycles && !timeMs)
		o.cycles = 1000;
	if (trigger) {
		const auto at = trigger->find_first_of("<>");
		if (at == std::string::npos || at == 0 || at + 1 >= trigger->size())
			throw UsageError("scope: --trigger '" + *trigger + "': SIGNAL>LEVEL (rising) or SIGNAL<LEVEL (falling)");
		o.trigger.edge = (*trigger)[at] == '>' ? ecmxf::TriggerEdge::Rising : ecmxf::TriggerEdge::Falling;
		o.trigger.signal = trigger->substr(0, at);
		o.trigger.level = parseReal("scope", "--trigger level", std::string_view(*trigger).substr(at + 1));
		if (std::find(o.signals.begin(), o.signals.end(), o.trigger.signal) == o.signals.end())
			o.signals.push_back(o.trigger.signal);
	}
	if (pre)
		o.trigger.preSamples = parseUnsigned("scope", "--pre", *pre, 10'000'000);
	if (pre && !trigger)
		throw UsageError("scope: --pre is for --trigger");
	if (timeout)
		o.timeoutMs = parseUnsigned("scope", "--timeout", *timeout, 3'600'000, 1);
	if (buffer)
		o.buffer = parseUnsigned("scope", "--buffer", *buffer, 10'000'000, 1);
	if (csv)
		o.files.csv = *csv;
	if (svg)
		o.files.svg = *svg;
	o.title = title;
	if (live && noLive)
		throw UsageError("scope: --live or --no-live, not both");
	if (live && g.json)
		throw UsageError("scope: --live draws on stdout, where --json writes: not both");
	o.live = live || (!noLive && !g.json && !g.quiet && ::isatty(STDOUT_FILENO) == 1);
	return o;
}

/// The live view (--live): the recorder's signals drawn on stdout about
/// 10 times a second (ecmxf::terminalText), between cycles, never inside
/// cycle() and sample(); 'q' read from stdin when it is a terminal. The
/// terminal is put in non-canonical mode without echo (a key counts at
/// once; ISIG kept, so Ctrl-C is still SIGINT, which StopSignals turns
/// into the end of the recording) and the cursor hidden; the destructor
/// restores both, on every way out of record(): a return, an exception,
/// a stop signal.
class LiveView
{
public:
	explicit LiveView(std::string title) : title_(std::move(title))
	{
		if (::isatty(STDIN_FILENO) == 1 && ::tcgetattr(STDIN_FILENO, &saved_) == 0) {
			termios raw = saved_;
			raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
			raw.c_cc[VMIN] = 0;
			raw.c_cc[VTIME] = 0;
			keys_ = ::tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0;
		}
		std::fputs("\x1b[?25l\x1b[2J", stdout); // cursor hidden, screen cleared
		std::fflush(stdout);
	}
	~LiveView()
	{
		if (keys_)
			(void)::tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
		std::fputs("\x1b[?25h\n", stdout);
		std::fflush(stdout);
	}
	LiveView(const LiveView &) = delete;
	LiveView &operator=(const LiveView &) = delete;

	/// A new frame when 100 ms have passed since the last one; true when
	/// 'q' was pressed.
	bool tick(const ecmxf::Recorder &rec)
	{
		const auto now = std::chrono::steady_clock::now();
		if (now < next_)
			return false;
		next_ = now + std::chrono::milliseconds(100);
		draw(rec);
		char key[16];
		const ssize_t n = keys_ ? ::read(STDIN_FILENO, key, sizeof key) : 0;
		return n > 0 && std::find_if(key, key + n, [](char c) { return c == 'q' || c == 'Q'; }) != key + n;
	}

	/// The last frame, whatever the time (the recording ended).
	void draw(const ecmxf::Recorder &rec)
	{
		winsize ws{};
		const bool sized = ::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 && ws.ws_row > 0;
		const unsigned cols = sized ? unsigned{ ws.ws_col } : 80u, rows = sized ? unsigned{ ws.ws_row } : 24u;
		const auto &sig = rec.signals();
		// a header line, then per signal a label line and its rows
		const unsigned each = sig.empty() ? 1 : std::max(2u, (rows - 2) / static_cast<unsigned>(sig.size()));
		const unsigned height = std::clamp(each - 1, 1u, 8u);
		const unsigned width = std::clamp(cols > 1 ? cols - 1 : 1u, 1u, 1000u);
		const char *state = rec.done() ? "done" : rec.triggered() ? "recording" : "waiting for the trigger";
		// the title cut to leave the rest of the header on one line
		const std::size_t room = cols > 70 ? cols - 70 : 10;
		std::string out = "\x1b[H" + (title_.size() > room ? title_.substr(0, room) + "..." : title_) + ": " +
				  std::to_string(rec.size()) + " samples, " + state +
				  "; q or Ctrl-C stops and writes\x1b[K\n";
		for (std::size_t k = 0; k < sig.size() && 1 + (k + 1) * (height + 1) < rows; k++) {
			ecmxf::TerminalRange r;
			const auto text = ecmxf::terminalText(rec, k, width, height, &r);
			const double last = rec.size() ? rec.value(rec.size() - 1, k) : NAN;
			out += sig[k].label + (sig[k].unit.empty() ? "" : " [" + sig[k].unit + "]") + "  min " +
			       shortNumber(r.min) + "  max " + shortNumber(r.max) + "  last " + shortNumber(last) +
			       "\x1b[K\n";
			for (const std::string &line : text)
				out += line + "\x1b[K\n";
		}
		out += "\x1b[J";
		std::fputs(out.c_str(), stdout);
		std::fflush(stdout);
	}

private:
	std::string title_;
	termios saved_{};
	bool keys_ = false;
	std::chrono::steady_clock::time_point next_{};
};

/// The samples the stop needs, the pre-trigger ones added (1 ms cycles).
std::size_t bufferFor(const ScopeOptions &o)
{
	if (o.buffer)
		return static_cast<std::size_t>(*o.buffer);
	// --time: a sample per 1 ms boundary, and the first ones closer
	const std::uint64_t n = (o.cycles ? *o.cycles : *o.timeMs + 16) + o.trigger.preSamples;
	return static_cast<std::size_t>(std::min<std::uint64_t>(n, 10'000'000));
}

ecmxf::RecorderStop stopOf(const ScopeOptions &o)
{
	ecmxf::RecorderStop s;
	s.cycles = o.cycles.value_or(0);
	s.time = std::chrono::milliseconds(o.timeMs.value_or(0));
	return s;
}

std::string defaultTitle(const Globals &g, const ScopeOptions &o)
{
	std::string t = "ecmxf-util scope on " + g.device + ":";
	for (const auto &s : o.signals)
		t += " " + s;
	return t;
}

/// Runs @p cycle (one exchange and its sample) until the recorder is done,
/// a stop signal or the live view's 'q' comes (the recording ends there),
/// or the trigger has not come within the timeout (bus time on @p now).
template <class Cycle, class Now>
void record(ecmxf::Recorder &rec, const ScopeOptions &o, const std::string &title, Cycle &&cycle, Now &&now)
{
	const StopSignals signals;
	std::optional<LiveView> live;
	if (o.live)
		live.emplace(title);
	const auto t0 = now();
	while (!rec.done()) {
		if (StopSignals::pending() || (live && live->tick(rec))) {
			rec.finish();
			break;
		}
		cycle();
		if (!rec.triggered() && now() - t0 >= std::chrono::milliseconds(o.timeoutMs))
			throw ecmxf::Error("the trigger " + o.trigger.signal +
						   (o.trigger.edge == ecmxf::TriggerEdge::Rising ? ">" : "<") +
						   shortNumber(o.trigger.level) + " did not come within " +
						   std::to_string(o.timeoutMs) + " ms (--timeout): nothing written",
					   ETIMEDOUT);
	}
	if (live)
		live->draw(rec); // the last frame: "done"
}

/// Signal @p k's minimum, maximum and last value (NaN: none sampled).
struct Range {
	double lo = NAN, hi = NAN, last = NAN;
};
Range rangeOf(const ecmxf::Recorder &rec, std::size_t k)
{
	Range r;
	for (std::size_t i = 0; i < rec.size(); i++) {
		const double v = rec.value(i, k);
		if (std::isnan(v))
			continue;
		r.lo = std::isnan(r.lo) ? v : std::min(r.lo, v);
		r.hi = std::isnan(r.hi) ? v : std::max(r.hi, v);
		r.last = v;
	}
	return r;
}

int summary(const Globals &g, const ecmxf::Recorder &rec)
{
	const auto &sig = rec.signals();
	if (g.json) {
		std::printf("{\"samples\": %zu, \"triggered\": %s, \"signals\": [", rec.size(),
			    rec.triggered() ? "true" : "false");
		for (std::size_t k = 0; k < sig.size(); k++) {
			const auto [lo, hi, last] = rangeOf(rec, k);
			const auto num = [](double v) { return std::isnan(v) ? std::string("null") : shortNumber(v); };
			std::printf("%s{\"signal\": %s, \"label\": %s, \"unit\": %s, \"min\": %s, \"max\": %s, \"last\": %s}",
				    k ? ", " : "", jsonString(sig[k].name).c_str(), jsonString(sig[k].label).c_str(),
				    jsonString(sig[k].unit).c_str(), num(lo).c_str(), num(hi).c_str(), num(last).c_str());
		}
		std::printf("]}\n");
		return 0;
	}
	if (g.quiet)
		return 0;
	std::printf("%zu samples%s\n", rec.size(), rec.triggered() ? "" : " (not triggered)");
	std::printf("%-36s %-10s %14s %14s %14s\n", "SIGNAL", "UNIT", "MIN", "MAX", "LAST");
	for (std::size_t k = 0; k < sig.size(); k++) {
		const auto [lo, hi, last] = rangeOf(rec, k);
		std::printf("%-36s %-10s %14s %14s %14s\n", sig[k].label.c_str(), sig[k].unit.empty() ? "-" : sig[k].unit.c_str(),
			    shortNumber(lo).c_str(), shortNumber(hi).c_str(), shortNumber(last).c_str());
	}
	return 0;
}

int scopeXf(Globals &g, const ScopeOptions &o)
{
	ProcessDataBus bus = openProcessDataBus(g, true);
	ecmxf::ProcessImage image(bus.pdos);
	ecmxf::Recorder rec(bufferFor(o));
	for (const auto &s : o.signals)
		rec.add(image, s);
	rec.arm(o.trigger, stopOf(o));
	ecmxf::Cyclic cyc(*bus.dev, image, ecmxf::CyclicConfig::motion(1ms));
	cyc.start();
	ecmxf::Link &link = bus.dev->link();
	const std::string title = o.title.value_or(defaultTitle(g, o));
	record(
		rec, o, title,
		[&] {
			const ecmxf::CycleResult &r = cyc.cycle();
			(void)rec.sample(link.now(), r);
			if (cyc.waitNextCycle() != 0)
				throw ecmxf::Error("the transport failed between cycles", EIO);
		},
		[&] { return link.now(); });
	cyc.stop();
	writePlotFiles(rec, o.files, title);
	return summary(g, rec);
}

int scopeSk(Globals &g, const ScopeOptions &o)
{
	const auto board = ecmxf::sk::Board::open(g.device); // the main program added --trace to it
	ecmxf::sk::Board &b = *board;
	if (b.states().status().state == ecmxf::State::Init)
		b.states().set(ecmxf::State::PreOp);
	const unsigned slaves = b.state() == ecmxf::State::PreOp ? b.setup().slaveCount() : b.maxSlaves();
	ecmxf::sk::bringUpToOp(b);
	ecmxf::Recorder rec(bufferFor(o));
	for (const auto &s : o.signals)
		rec.add(b, slaves, s);
	rec.arm(o.trigger, stopOf(o));
	const std::string title = o.title.value_or(defaultTitle(g, o));
	record(
		rec, o, title,
		[&] {
			const auto r = b.cyclic().cycle();
			if (r.status == ecmxf::sk::CycleStatus::Link)
				throw ecmxf::Error(b.cyclic().lastError(), EIO);
			(void)rec.sample(b.channel().now(), r);
			b.channel().sleepFor(1ms);
		},
		[&] { return b.channel().now(); });
	writePlotFiles(rec, o.files, title);
	return summary(g, rec);
}

} // namespace

std::string shortNumber(double v)
{
	char buf[40];
	std::snprintf(buf, sizeof(buf), "%.6g", v);
	return buf;
}

int cmdScope(Globals &g, const Args &args)
{
	bool help = false;
	const ScopeOptions o = parseScope(args, g, help);
	if (help)
		return 0;
	return skDevice(g) ? scopeSk(g, o) : scopeXf(g, o);
}

ProcessDataBus openProcessDataBus(const Globals &g, bool motionPdos)
{
	ProcessDataBus b;
	b.dev = openDevice(g);
	b.master = std::make_unique<ecmxf::Master>(*b.dev);
	ecmxf::Master &m = *b.master;
	if (ecmxf_util::busDown(*b.dev)) {
		if (motionPdos) {
			bringUpMotion(m);
		} else {
			ecmxf::MasterConfig mc;
			mc.init.dc.sync0Ns = 1'000'000;
			m.bringUp(mc);
		}
	} else {
		m.rescan();
	}
	const auto count = static_cast<unsigned>(m.slaves().size());
	b.pdos.resize(count);
	for (unsigned p = 0; p < count; p++)
		b.pdos[p] = m.pdos().size() > p ? m.pdos()[p] : m.readSlavePdos(static_cast<std::uint8_t>(p));
	return b;
}

} // namespace ecmxf_util
