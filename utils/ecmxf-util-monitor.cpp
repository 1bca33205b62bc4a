// SPDX-License-Identifier: MIT
/*
 * ecmxf-util monitor - live events of the chip: it polls the chip with
 * INFO_UPDATE and reports what changed in the response header (ECAT state,
 * error and ECM status bits, CRC and WKC error counters, FIFO levels, a
 * chip reset), one line (or one JSON object) per event.
 *
 * Over /dev/ecmxfN the kernel module's generic-netlink events will replace
 * the polling (a later issue); the byte transports (sim:, spidev:) poll.
 */
#include "ecmxf-util-monitor.hpp"
#include "ecmxf-util.hpp"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim_transport.hpp>
#include <ecmxf/transport.hpp>

namespace ecmxf_util {

const char *const kMonitorHelp =
	"Usage: ecmxf-util [global options] monitor [--count N] [--duration MS]\n"
	"                                           [--interval MS] [--tx-high N]\n"
	"                                           [--rx-low N] [--json]\n"
	"\n"
	"Poll the chip with INFO_UPDATE every --interval and print one line per\n"
	"event, until --count events, --duration or Ctrl-C:\n"
	"  state          the ECAT state changed; when it leaves OP (or becomes\n"
	"                 ERROR), each slave not in OP with its state and AL\n"
	"                 status code + text (STATE_GET, SLV_INFO_GET 7)\n"
	"  reset          the chip reset (NOP answer, 'Ethernet initialised'\n"
	"                 cleared or the ECAT state back to NONE)\n"
	"  error_status   error-status bits set / cleared, by name\n"
	"  ecm_status     ECM status bits (DC stable, Ethernet initialised, PDO\n"
	"                 configured, FIFO enabled) set / cleared\n"
	"  crc_errors     the SPI CRC error counter went up\n"
	"  wkc_burst      the WKC error counter started going up; wkc_burst_end\n"
	"                 when a poll shows no more (errors of the burst, length)\n"
	"  fifo           the TxFIFO count crossed --tx-high, or the RxFIFO count\n"
	"                 crossed --rx-low\n"
	"A quiet bus prints nothing. Times are since the start, on the device's\n"
	"clock (virtual time on sim:, where the loop runs as fast as it can).\n"
	"Over /dev/ecmxfN the kernel's generic-netlink events will be used\n"
	"instead of polling (not implemented yet).\n"
	"\n"
	"Options:\n"
	"  --count N      stop after N events\n"
	"  --duration MS  stop after MS milliseconds\n"
	"  --interval MS  poll period, default 10\n"
	"  --tx-high N    TxFIFO high mark, default 10\n"
	"  --rx-low N     RxFIFO low mark, default 0 (the RxFIFO ran dry)\n"
	"  --json         one JSON object per event and line (JSON Lines)\n"
	"  -h, --help     show this help\n";

namespace monitor {

namespace {

struct BitName {
	unsigned bit;
	const char *name;
};

// response header 0x09 and 0x0A (Documentation/simulator.rst, "Response header")
constexpr BitName kErrBits[] = {
	{ 0, "link" },      { 1, "link at INIT_OP" }, { 3, "async error" },   { 4, "SPI error" },
	{ 5, "FIFO error" }, { 6, "SPI CRC error" },  { 7, "command error" },
};
constexpr BitName kEcmBits[] = {
	{ 2, "DC stable" },
	{ 3, "Ethernet initialised" },
	{ 4, "PDO configured" },
	{ 6, "FIFO enabled" },
};
constexpr std::uint8_t kEcmNop = 1u << 5;
constexpr std::uint8_t kEcmEthInit = 1u << 3;
constexpr std::uint8_t kEcmWatched = 0x5C; // bits 2, 3, 4, 6

template <std::size_t N>
std::vector<std::string> names(std::uint8_t v, const BitName (&table)[N])
{
	std::vector<std::string> out;
	for (const BitName &b : table)
		if (v & (1u << b.bit))
			out.emplace_back(b.name);
	return out;
}

std::string joined(const std::vector<std::string> &v, bool json)
{
	std::string s;
	for (const std::string &n : v) {
		if (!s.empty())
			s += ", ";
		s += json ? jsonString(n) : n;
	}
	return json ? "[" + s + "]" : s;
}

std::string hex2(unsigned v)
{
	char b[8];
	std::snprintf(b, sizeof(b), "0x%02x", v);
	return b;
}

Event bitsEvent(const char *type, const char *what, std::uint8_t prev, std::uint8_t cur,
		std::vector<std::string> (*namer)(std::uint8_t))
{
	const auto set = namer(static_cast<std::uint8_t>(cur & ~prev));
	const auto cleared = namer(static_cast<std::uint8_t>(prev & ~cur));
	Event e;
	e.type = type;
	e.text = std::string(what) + " " + hex2(prev) + " -> " + hex2(cur) + ":";
	if (!set.empty())
		e.text.append(" set ").append(joined(set, false));
	if (!set.empty() && !cleared.empty())
		e.text.append(";");
	if (!cleared.empty())
		e.text.append(" cleared ").append(joined(cleared, false));
	e.fields = { { "previous", std::to_string(prev) },
		     { "value", std::to_string(cur) },
		     { "set", joined(set, true) },
		     { "cleared", joined(cleared, true) } };
	return e;
}

} // namespace

std::vector<std::string> errorBitNames(std::uint8_t v)
{
	return names(v, kErrBits);
}

std::vector<std::string> ecmBitNames(std::uint8_t v)
{
	return names(v, kEcmBits);
}

std::vector<Event> diffHeaders(const ecmxf::ResponseHeader &prev, const ecmxf::ResponseHeader &cur,
			       const Thresholds &th)
{
	std::vector<Event> out;
	const bool reset = (cur.ecmStatus & kEcmNop) != 0 ||
			   ((prev.ecmStatus & kEcmEthInit) && !(cur.ecmStatus & kEcmEthInit)) ||
			   (prev.ecatState != 0 && cur.ecatState == 0);
	if (reset) {
		Event e;
		e.type = "reset";
		e.text = "the chip reset (ECAT state " + stateName(cur.ecatState) + ", ECM status " +
			 hex2(cur.ecmStatus) + ")";
		e.fields = { { "state", std::to_string(cur.ecatState) },
			     { "state_name", jsonString(stateName(cur.ecatState)) },
			     { "ecm_status", std::to_string(cur.ecmStatus) } };
		out.push_back(std::move(e));
		return out;
	}
	if (cur.ecatState != prev.ecatState) {
		Event e;
		e.type = "state";
		e.text = "ECAT state " + stateName(prev.ecatState) + " -> " + stateName(cur.ecatState);
		e.fields = { { "from", std::to_string(prev.ecatState) },
			     { "to", std::to_string(cur.ecatState) },
			     { "from_name", jsonString(stateName(prev.ecatState)) },
			     { "to_name", jsonString(stateName(cur.ecatState)) } };
		out.push_back(std::move(e));
	}
	if (cur.errStatus != prev.errStatus)
		out.push_back(bitsEvent("error_status", "error status", prev.errStatus, cur.errStatus,
					errorBitNames));
	if ((cur.ecmStatus & kEcmWatched) != (prev.ecmStatus & kEcmWatched))
		out.push_back(bitsEvent("ecm_status", "ECM status",
					static_cast<std::uint8_t>(prev.ecmStatus & kEcmWatched),
					static_cast<std::uint8_t>(cur.ecmStatus & kEcmWatched), ecmBitNames));
	if (cur.crcErrCnt > prev.crcErrCnt) {
		const unsigned d = cur.crcErrCnt - prev.crcErrCnt;
		Event e;
		e.type = "crc_errors";
		e.text = "SPI CRC errors +" + std::to_string(d) + " (count " +
			 std::to_string(cur.crcErrCnt) + ")";
		e.fields = { { "increase", std::to_string(d) }, { "count", std::to_string(cur.crcErrCnt) } };
		out.push_back(std::move(e));
	}
	if (cur.wkcErrCnt > prev.wkcErrCnt) {
		const unsigned d = cur.wkcErrCnt - prev.wkcErrCnt;
		Event e;
		e.type = "wkc";
		e.text = "WKC errors +" + std::to_string(d) + " (count " + std::to_string(cur.wkcErrCnt) + ")";
		e.fields = { { "increase", std::to_string(d) }, { "count", std::to_string(cur.wkcErrCnt) } };
		out.push_back(std::move(e));
	}
	auto fifo = [&](const char *name, const char *fifoKey, unsigned p, unsigned c, unsigned mark,
			bool high) {
		// high mark: at or above it is "high"; low mark: at or below it is "low"
		const bool was = high ? p >= mark : p <= mark;
		const bool is = high ? c >= mark : c <= mark;
		if (was == is)
			return;
		Event e;
		e.type = "fifo";
		const char *where = high ? (is ? "reached its high mark" : "fell below its high mark")
					 : (is ? "fell to its low mark" : "rose above its low mark");
		e.text = std::string(name) + " " + where + " " + std::to_string(mark) + " (count " +
			 std::to_string(c) + ")";
		e.fields = { { "fifo", jsonString(fifoKey) },
			     { "count", std::to_string(c) },
			     { "mark", std::to_string(mark) },
			     { "crossing", jsonString(high ? (is ? "above" : "below") : (is ? "below" : "above")) } };
		out.push_back(std::move(e));
	};
	fifo("TxFIFO", "tx", prev.txFifoCnt, cur.txFifoCnt, th.txHigh, true);
	fifo("RxFIFO", "rx", prev.rxFifoCnt, cur.rxFifoCnt, th.rxLow, false);
	return out;
}

std::vector<Event> Detector::update(const ecmxf::ResponseHeader &cur, std::chrono::nanoseconds now)
{
	if (!prev_) {
		prev_ = cur;
		return {};
	}
	std::vector<Event> raw = diffHeaders(*prev_, cur, th_);
	prev_ = cur;
	std::vector<Event> out;
	bool wkcUp = false;
	for (Event &e : raw) {
		if (e.type == "reset") {
			burst_ = false;
			out.push_back(std::move(e));
			return out;
		}
		if (e.type != "wkc") {
			out.push_back(std::move(e));
			continue;
		}
		wkcUp = true;
		const unsigned d = static_cast<unsigned>(std::stoul(e.fields[0].second));
		if (!burst_) {
			burst_ = true;
			burstErrors_ = d;
			burstStart_ = now;
			e.type = "wkc_burst";
			e.text = "WKC error burst: " + e.text.substr(std::string("WKC errors ").size());
			out.push_back(std::move(e));
		} else {
			burstErrors_ += d;
		}
	}
	if (burst_ && !wkcUp) {
		burst_ = false;
		const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - burstStart_).count();
		Event e;
		e.type = "wkc_burst_end";
		e.text = "WKC error burst over: " + std::to_string(burstErrors_) + " errors in " +
			 std::to_string(ms) + " ms (count " + std::to_string(cur.wkcErrCnt) +
			 (cur.wkcErrCnt == 255 ? ", saturated)" : ")");
		e.fields = { { "errors", std::to_string(burstErrors_) },
			     { "duration_ms", std::to_string(ms) },
			     { "count", std::to_string(cur.wkcErrCnt) } };
		out.push_back(std::move(e));
	}
	return out;
}

} // namespace monitor

namespace {

volatile std::sig_atomic_t gStop = 0;

extern "C" void onSigint(int)
{
	gStop = 1;
}

constexpr std::uint8_t kStateSet = 12;
constexpr std::uint8_t kWarmReset = 127;
constexpr std::uint8_t kStateOp = 0x08;
constexpr std::uint8_t kStateError = 0x10;

std::uint64_t number(std::string_view opt, std::string_view text, std::uint64_t min, std::uint64_t max)
{
	const std::string s(text);
	char *end = nullptr;
	errno = 0;
	const bool digit = !s.empty() && s[0] >= '0' && s[0] <= '9';
	const unsigned long long v = digit ? std::strtoull(s.c_str(), &end, 0) : 0;
	if (!digit || errno != 0 || end == nullptr || *end != '\0')
		throw UsageError("monitor: " + std::string(opt) + ": '" + s +
				 "' is not a number (decimal or 0x hex)");
	if (v < min || v > max)
		throw UsageError("monitor: " + std::string(opt) + ": " + s + " is out of range " +
				 std::to_string(min) + ".." + std::to_string(max));
	return v;
}

/// --sim-at MS:ACTION (hidden, for tests and demos on sim: devices).
struct SimAction {
	std::chrono::nanoseconds at;
	std::string action;
	long arg = 0;
};

SimAction parseSimAction(std::string_view text)
{
	const std::size_t colon = text.find(':');
	if (colon == std::string_view::npos)
		throw UsageError("monitor: --sim-at: '" + std::string(text) + "' is not MS:ACTION");
	SimAction a;
	a.at = std::chrono::milliseconds(number("--sim-at", text.substr(0, colon), 0, 86'400'000));
	std::string_view act = text.substr(colon + 1);
	const std::size_t eq = act.find('=');
	a.action = std::string(act.substr(0, eq));
	if (a.action == "drop" || a.action == "crc") {
		if (eq == std::string_view::npos)
			throw UsageError("monitor: --sim-at: " + a.action + " needs =N");
		a.arg = static_cast<long>(number("--sim-at", act.substr(eq + 1), 0, 1000));
	} else if (a.action != "op" && a.action != "return" && a.action != "link-down" &&
		   a.action != "link-up" && a.action != "reset") {
		throw UsageError("monitor: --sim-at: unknown action '" + std::string(act) +
				 "' (op, drop=N, return, link-down, link-up, crc=N, reset)");
	}
	return a;
}

/// ECAT_INIT_OP for all slaves (FIFO off, no DC, SYNC0 1 ms), then
/// STATE_SET PRE-OP, SAFE-OP, OP.
void bringUp(ecmxf::Device &dev)
{
	ecmxf::Command c = simpleCommand(kInitOp);
	c.payload = { 0xFF, 0x81, 0x00, 0x00, 0x40, 0x42, 0x0F, 0x00 }; // SYNC0 1'000'000 ns
	c.payload.resize(16, 0);
	c.len = 16;
	dev.command(c);
	for (const std::uint8_t st : { std::uint8_t{ 2 }, std::uint8_t{ 4 }, kStateOp }) {
		ecmxf::Command s = simpleCommand(kStateSet, 0xFF);
		s.data[0] = st;
		dev.command(s);
	}
}

void runSimAction(ecmxf::Device &dev, const SimAction &a)
{
	auto *sim = dynamic_cast<ecmxf::SimTransport *>(&dev.transport());
	if (!sim)
		throw UsageError("monitor: --sim-at needs a sim: device");
	ecmxf::sim::FaultPlan &f = sim->chip().faults();
	if (a.action == "op")
		bringUp(dev);
	else if (a.action == "drop")
		f.slaveDropped = static_cast<int>(a.arg);
	else if (a.action == "return")
		f.slaveDropped = -1;
	else if (a.action == "link-down")
		f.linkLost = true;
	else if (a.action == "link-up")
		f.linkLost = false;
	else if (a.action == "crc")
		f.mosiBitErrors += static_cast<unsigned>(a.arg);
	else if (a.action == "reset")
		dev.command(simpleCommand(kWarmReset));
}

/// Per-slave state and AL status code for a state event that leaves OP
/// or enters ERROR: the slaves not in OP or with the error bit.
void addSlaves(ecmxf::Device &dev, monitor::Event &e)
{
	const unsigned count = dev.command(simpleCommand(kSlvCntGet)).ret;
	std::string json = "[";
	for (unsigned pos = 0; pos < count; pos++) {
		const std::uint8_t st = dev.command(simpleCommand(kStateGet, static_cast<std::uint8_t>(pos))).ret;
		if (st == kStateOp)
			continue;
		const bool answering = st != kStateError;
		const auto state = static_cast<std::uint8_t>(st & 0x0F);
		// SLV_INFO_GET 7 of a slave that does not answer is a command
		// error (sticky): ask only the ones that answer
		std::optional<std::uint16_t> code;
		if (answering) {
			ecmxf::Command info = simpleCommand(kSlvInfoGet, static_cast<std::uint8_t>(pos));
			info.data[0] = 7;
			code = le16(dev.command(info), "SLV_INFO_GET AL status code");
		}
		e.text.append("; slave ").append(std::to_string(pos)).append(": ");
		if (!answering) {
			e.text.append("not answering");
		} else {
			char buf[16];
			std::snprintf(buf, sizeof(buf), "0x%04x", *code);
			e.text.append(stateName(state)).append(st & kStateError ? " + error" : "");
			e.text.append(", AL status ").append(buf).append(" (").append(std::string(ecmxf::alStatusText(*code))).append(")");
		}
		if (json.size() > 1)
			json += ", ";
		json.append("{\"position\": ")
			.append(std::to_string(pos))
			.append(", \"answering\": ")
			.append(answering ? "true" : "false")
			.append(", \"state\": ")
			.append(std::to_string(state))
			.append(", \"state_name\": ")
			.append(jsonString(answering ? stateName(state) : "NONE"))
			.append(", \"error\": ")
			.append(st & kStateError ? "true" : "false")
			.append(", \"al_status_code\": ")
			.append(code ? std::to_string(*code) : "null")
			.append(", \"al_status_text\": ")
			.append(code ? jsonString(std::string(ecmxf::alStatusText(*code))) : "null")
			.append("}");
	}
	json += "]";
	e.fields.emplace_back("slaves", json);
}

void print(const Globals &g, std::chrono::nanoseconds t, const monitor::Event &e)
{
	const double ms = static_cast<double>(t.count()) / 1e6;
	if (g.json) {
		std::string line = "{\"time_ms\": ";
		char b[32];
		std::snprintf(b, sizeof(b), "%.3f", ms);
		line.append(b).append(", \"type\": ").append(jsonString(e.type));
		for (const auto &[k, v] : e.fields)
			line.append(", ").append(jsonString(k)).append(": ").append(v);
		line.append(", \"text\": ").append(jsonString(e.text)).append("}");
		std::printf("%s\n", line.c_str());
	} else {
		std::printf("%10.3f ms  %s\n", ms, e.text.c_str());
	}
	std::fflush(stdout);
}

} // namespace

int cmdMonitor(Globals &g, const Args &args)
{
	std::optional<std::uint64_t> count, durationMs;
	std::uint64_t intervalMs = 10;
	monitor::Thresholds th;
	std::vector<SimAction> actions;
	for (std::size_t i = 0; i < args.size(); i++) {
		const std::string_view a = args[i];
		auto value = [&]() -> std::string_view {
			if (i + 1 >= args.size())
				throw UsageError("monitor: option '" + std::string(a) + "' needs a value");
			return args[++i];
		};
		if (a == "-h" || a == "--help") {
			std::fputs(kMonitorHelp, stdout);
			return 0;
		}
		if (a == "--json")
			g.json = true;
		else if (a == "--count")
			count = number("--count", value(), 1, UINT32_MAX);
		else if (a == "--duration")
			durationMs = number("--duration", value(), 0, 86'400'000ull * 365);
		else if (a == "--interval")
			intervalMs = number("--interval", value(), 1, 3'600'000);
		else if (a == "--tx-high")
			th.txHigh = static_cast<unsigned>(number("--tx-high", value(), 1, 255));
		else if (a == "--rx-low")
			th.rxLow = static_cast<unsigned>(number("--rx-low", value(), 0, 254));
		else if (a == "--sim-at")
			actions.push_back(parseSimAction(value()));
		else
			throw UsageError("monitor: unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util monitor --help')");
	}

	const std::unique_ptr<ecmxf::Device> dev = ecmxf::Device::open(g.device);
	if (!actions.empty() && !dynamic_cast<ecmxf::SimTransport *>(&dev->transport()))
		throw UsageError("monitor: --sim-at needs a sim: device");
	ecmxf::Transport &tr = dev->transport();

	gStop = 0;
	struct sigaction sa {};
	sa.sa_handler = onSigint;
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, nullptr);
	sigaction(SIGTERM, &sa, nullptr);

	const auto interval = std::chrono::milliseconds(intervalMs);
	const std::chrono::nanoseconds t0 = tr.now();
	monitor::Detector det(th);
	std::uint64_t events = 0;
	std::size_t nextAction = 0;
	std::stable_sort(actions.begin(), actions.end(),
			 [](const SimAction &x, const SimAction &y) { return x.at < y.at; });
	const ecmxf::Command poll = simpleCommand(0); // INFO_UPDATE_OP

	bool first = true;
	while (!gStop) {
		if (!first)
			tr.sleepFor(interval);
		const std::chrono::nanoseconds t = tr.now() - t0;
		if (durationMs && t > std::chrono::milliseconds(*durationMs))
			break;
		if (!first)
			while (nextAction < actions.size() && actions[nextAction].at <= t)
				runSimAction(*dev, actions[nextAction++]);
		first = false;
		std::vector<monitor::Event> evs;
		try {
			evs = det.update(dev->command(poll).header, tr.now());
		} catch (const ecmxf::Error &e) {
			if (e.errnoValue() != ECONNRESET)
				throw;
			monitor::Event r;
			r.type = "reset";
			r.text = "the chip reset (NOP answer)";
			evs.push_back(std::move(r));
			det.rebase();
		}
		for (monitor::Event &e : evs) {
			if (e.type == "state") {
				const bool leavesOp = e.fields[0].second == std::to_string(kStateOp);
				const bool error = e.fields[1].second == std::to_string(kStateError);
				if (leavesOp || error)
					addSlaves(*dev, e);
			}
			print(g, tr.now() - t0, e);
			if (count && ++events >= *count)
				return 0;
		}
	}
	return 0;
}

} // namespace ecmxf_util
