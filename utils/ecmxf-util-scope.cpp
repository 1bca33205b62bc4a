// SPDX-License-Identifier: MIT
/*
 * ecmxf-util scope - record process data and cycle figures while the bus
 * runs in OP (ecmxf::Recorder), then write them as CSV and an SVG plot
 * (ecmxf::writeCsv, ecmxf::writeSvg); on the ECM-XF (sim:, unix:, spidev,
 * /dev/ecmxfN) and on the ECM-SK (its feedback slots), with a live view
 * in the terminal while it records (LiveView: a drawing thread fed copies
 * of the latest samples, ecmxf::SnapshotExchange, ecmxf::terminalText). Also
 * the plot files of `cia402 move --plot` (takePlotFiles, writePlotFiles).
 */
#include "ecmxf-util-scope.hpp"

#include <poll.h>
#include <pthread.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <stop_token>
#include <string>
#include <string_view>
#include <thread>
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
#include <ecmxf/scope/snapshot.hpp>
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

/// The terminal held by the live view: put in non-canonical mode without
/// echo when stdin is one (a key counts at once; ISIG kept, so Ctrl-C is
/// still SIGINT, which StopSignals turns into the end of the recording),
/// the screen cleared and the cursor hidden; the destructor restores both.
class LiveTerminal
{
public:
	LiveTerminal()
	{
		if (::isatty(STDIN_FILENO) == 1 && ::tcgetattr(STDIN_FILENO, &saved_) == 0) {
			termios raw = saved_;
			raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
			raw.c_cc[VMIN] = 0;
			raw.c_cc[VTIME] = 0;
			keys_ = ::tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0;
		}
		std::fputs("\x1b[?25l\x1b[2J", stdout); // cursor hidden, screen cleared
		std::fflush(stdout); // before the drawing thread's write()s
	}
	~LiveTerminal()
	{
		if (keys_)
			(void)::tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
		std::fputs("\x1b[?25h\n", stdout);
		std::fflush(stdout);
	}
	LiveTerminal(const LiveTerminal &) = delete;
	LiveTerminal &operator=(const LiveTerminal &) = delete;

	/// stdin is a terminal in non-canonical mode: keys can be read.
	[[nodiscard]] bool keys() const noexcept { return keys_; }

private:
	termios saved_{};
	bool keys_ = false;
};

/// The live view (--live): the recorder's signals drawn on stdout about
/// 10 times a second by a drawing thread of its own, so that neither the
/// drawing (it allocates) nor the terminal (a write to a slow or stopped
/// terminal blocks: ssh, a paused tmux pane, Ctrl-S) delays a cycle.
///
/// The thread that runs the cycles calls tick() between them: about every
/// 100 ms (wall time) it copies what a frame needs (the state, the sample
/// count and, of each signal that fits the terminal, the latest 2 x width
/// samples; ecmxf::RecorderSnapshot) into the back buffer of a triple
/// buffer allocated here (ecmxf::SnapshotExchange) and publishes it: no
/// allocation, no lock, no system call. While the drawing thread has not
/// taken the frame before (it is busy, its terminal stalled), the copy is
/// skipped. The drawing thread takes the latest frame, draws it
/// (ecmxf::terminalText over the copied samples) and write()s it to stdout;
/// it reads the terminal's size (TIOCGWINSZ), published in atomics for the
/// next copy's width and signals, and 'q' from stdin when it is a terminal,
/// published as an atomic that tick() returns.
///
/// finish() publishes the last frame ("done"), whether or not the drawer is
/// busy. The destructor stops the drawing thread (it draws that last frame
/// first) and joins it, then restores the terminal: on every way out (a
/// return, an exception, a stop signal), and nothing is written to the
/// terminal after that restore.
class LiveView
{
public:
	/// The widest drawing (cells): a frame copies at most 2 x kMaxWidth
	/// samples a signal.
	static constexpr unsigned kMaxWidth = 1000;

	LiveView(std::string title, const ecmxf::Recorder &rec)
		: title_(std::move(title)), frames_(rec.signals().size(), 2 * std::size_t{ kMaxWidth })
	{
		for (const auto &sig : rec.signals())
			labels_.push_back(sig.label + (sig.unit.empty() ? "" : " [" + sig.unit + "]"));
		publish(layout()); // the first copy's width, before the drawing thread's first frame
		drawer_ = startDrawer();
	}
	LiveView(const LiveView &) = delete;
	LiveView &operator=(const LiveView &) = delete;

	/// The cycling thread's, between cycles: a frame copied and published
	/// when 100 ms have passed since the last one and the drawing thread
	/// has taken that one. True once 'q' was pressed. Allocates nothing,
	/// blocks on nothing.
	bool tick(const ecmxf::Recorder &rec) noexcept
	{
		const auto now = std::chrono::steady_clock::now();
		if (now >= next_) {
			next_ = now + std::chrono::milliseconds(100);
			if (!frames_.pending()) // else the drawer is still busy: this frame is skipped
				copy(rec);
		}
		return quit_.load(std::memory_order_relaxed);
	}

	/// The last frame (the recording ended), whatever the time and even
	/// while the drawer is busy: drawn once it is free, before the
	/// destructor returns.
	void finish(const ecmxf::Recorder &rec) noexcept { copy(rec); }

private:
	/// Where a frame goes on a terminal of cols x rows: @c width cells
	/// and @c height rows a signal, the first @c shown signals.
	struct Layout {
		unsigned cols = 80, rows = 24, width = 79, height = 8;
		std::size_t shown = 0;
	};

	void copy(const ecmxf::Recorder &rec) noexcept
	{
		frames_.back().take(rec, 2 * std::size_t{ width_.load(std::memory_order_relaxed) },
				    shown_.load(std::memory_order_relaxed));
		frames_.publish();
	}

	/// The terminal's size (80 x 24 when it has none: a pipe) and what
	/// fits: a header line, then per signal a label line and its rows.
	[[nodiscard]] Layout layout() const noexcept
	{
		winsize ws{};
		Layout l;
		if (::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 && ws.ws_row > 0) {
			l.cols = ws.ws_col;
			l.rows = ws.ws_row;
		}
		const auto n = static_cast<unsigned>(labels_.size());
		const unsigned each = n == 0 ? 1 : std::max(2u, (l.rows > 2 ? l.rows - 2 : 0) / n);
		l.height = std::clamp(each - 1, 1u, 8u);
		l.width = std::clamp(l.cols > 1 ? l.cols - 1 : 1u, 1u, kMaxWidth);
		while (l.shown < labels_.size() && 1 + (l.shown + 1) * (l.height + 1) < l.rows)
			l.shown++;
		return l;
	}

	void publish(const Layout &l) noexcept
	{
		width_.store(l.width, std::memory_order_relaxed);
		shown_.store(l.shown, std::memory_order_relaxed);
	}

	/// The drawing thread, started with the stop signals blocked: their
	/// handler runs in the cycling thread, and no write() of the drawer is
	/// interrupted by them.
	std::jthread startDrawer()
	{
		sigset_t stop, old;
		sigemptyset(&stop);
		for (const int sig : { SIGINT, SIGTERM, SIGHUP })
			sigaddset(&stop, sig);
		(void)::pthread_sigmask(SIG_BLOCK, &stop, &old);
		struct Restore {
			sigset_t *old;
			~Restore() { (void)::pthread_sigmask(SIG_SETMASK, old, nullptr); }
		} restore{ &old };
		return std::jthread([this](const std::stop_token &st) { run(st); });
	}

	/// Until the stop: 'q' looked for every 20 ms, the latest frame drawn
	/// when there is one; then the frame published last, if not drawn yet.
	void run(const std::stop_token &st) noexcept
	{
		while (!st.stop_requested()) {
			waitForKeys(20);
			if (const ecmxf::RecorderSnapshot *s = frames_.take())
				draw(*s);
		}
		if (const ecmxf::RecorderSnapshot *s = frames_.take())
			draw(*s);
	}

	/// Up to @p ms for a key on stdin (a terminal: else a sleep); 'q' or
	/// 'Q' sets the quit.
	void waitForKeys(int ms) noexcept
	{
		if (!term_.keys()) {
			std::this_thread::sleep_for(std::chrono::milliseconds(ms));
			return;
		}
		pollfd in{ STDIN_FILENO, POLLIN, 0 };
		if (::poll(&in, 1, ms) <= 0)
			return;
		char key[16];
		const ssize_t n = ::read(STDIN_FILENO, key, sizeof key);
		if (n > 0 && std::find_if(key, key + n, [](char c) { return c == 'q' || c == 'Q'; }) != key + n)
			quit_.store(true, std::memory_order_relaxed);
	}

	/// One frame of @p s, in the drawing thread (it allocates; a frame
	/// that cannot be made is dropped).
	void draw(const ecmxf::RecorderSnapshot &s) noexcept
	{
		if (broken_)
			return;
		try {
			const Layout l = layout();
			publish(l);
			const char *state = s.done() ? "done" : s.triggered() ? "recording" : "waiting for the trigger";
			// the title cut to leave the rest of the header on one line
			const std::size_t room = l.cols > 70 ? l.cols - 70 : 10;
			std::string out = "\x1b[H" + (title_.size() > room ? title_.substr(0, room) + "..." : title_) +
					  ": " + std::to_string(s.size()) + " samples, " + state +
					  "; q or Ctrl-C stops and writes\x1b[K\n";
			// the signals that fit, of those copied (fewer when the
			// terminal grew since the copy: the next frame has them)
			for (std::size_t k = 0; k < std::min(l.shown, s.signals()); k++) {
				const std::span<const double> values = s.values(k);
				ecmxf::TerminalRange r;
				const auto text = ecmxf::terminalText(values, l.width, l.height, &r);
				const double last = values.empty() ? NAN : values.back();
				out += labels_[k] + "  min " + shortNumber(r.min) + "  max " + shortNumber(r.max) +
				       "  last " + shortNumber(last) + "\x1b[K\n";
				for (const std::string &line : text)
					out += line + "\x1b[K\n";
			}
			out += "\x1b[J";
			broken_ = !writeAll(out);
		} catch (...) {
			// no memory for this frame: the next one may have it
		}
	}

	/// @p text on stdout, all of it (write(2): not stdio, whose lock the
	/// cycling thread could meet); false when the terminal fails (gone).
	static bool writeAll(std::string_view text) noexcept
	{
		while (!text.empty()) {
			const ssize_t n = ::write(STDOUT_FILENO, text.data(), text.size());
			if (n < 0 && errno == EINTR)
				continue;
			if (n <= 0)
				return false;
			text.remove_prefix(static_cast<std::size_t>(n));
		}
		return true;
	}

	LiveTerminal term_; // first: restored last, after the drawing thread is joined
	std::string title_;
	std::vector<std::string> labels_;     // each signal's label and unit
	ecmxf::SnapshotExchange frames_;      // cycling thread -> drawing thread
	std::atomic<unsigned> width_{ 1 };    // drawing thread -> cycling thread: cells
	std::atomic<std::size_t> shown_{ 0 }; // ... and the signals that fit
	std::atomic<bool> quit_{ false };     // ... and 'q'
	std::chrono::steady_clock::time_point next_{}; // the cycling thread's
	bool broken_ = false;                          // the drawing thread's: a write failed
	std::jthread drawer_; // last: joined first (its destructor), before the rest goes
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
/// The caller holds the StopSignals and the live view (@p live, nullptr:
/// none): the live view outlives the recording, so that the files are
/// written while the drawing thread may still be writing to a slow
/// terminal.
template <class Cycle, class Now>
void record(ecmxf::Recorder &rec, const ScopeOptions &o, LiveView *live, Cycle &&cycle, Now &&now)
{
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
		live->finish(rec); // the last frame: "done"
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
	const std::string title = o.title.value_or(defaultTitle(g, o));
	const StopSignals signals; // first: it outlives the live view
	std::optional<LiveView> live; // its thread started before the cycles
	if (o.live)
		live.emplace(title, rec);
	cyc.start();
	ecmxf::Link &link = bus.dev->link();
	record(
		rec, o, live ? &*live : nullptr,
		[&] {
			const ecmxf::CycleResult &r = cyc.cycle();
			(void)rec.sample(link.now(), r);
			if (cyc.waitNextCycle() != 0)
				throw ecmxf::Error("the transport failed between cycles", EIO);
		},
		[&] { return link.now(); });
	cyc.stop();
	writePlotFiles(rec, o.files, title);
	live.reset(); // the last frame drawn, the terminal restored: then the summary
	return summary(g, rec);
}

int scopeSk(Globals &g, const ScopeOptions &o)
{
	const auto board = openBoard(g); // the main program added --trace to it
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
	const StopSignals signals; // first: it outlives the live view
	std::optional<LiveView> live;
	if (o.live)
		live.emplace(title, rec);
	record(
		rec, o, live ? &*live : nullptr,
		[&] {
			const auto r = b.cyclic().cycle();
			if (r.status == ecmxf::sk::CycleStatus::Link)
				throw ecmxf::Error(b.cyclic().lastError(), EIO);
			(void)rec.sample(b.channel().now(), r);
			b.channel().sleepFor(1ms);
		},
		[&] { return b.channel().now(); });
	writePlotFiles(rec, o.files, title);
	live.reset(); // the last frame drawn, the terminal restored: then the summary
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
