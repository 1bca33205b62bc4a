// SPDX-License-Identifier: MIT
/*
 * ecmxf-util monitor - live events of the chip, one line (or one JSON
 * object) per event.
 *
 * Over /dev/ecmxfN it subscribes to the kernel module's generic netlink
 * events (libmnl, through ecmxf::EventSubscriber) and needs no access to
 * the device node; the kernel detects them (its worker sees every
 * response header) and reads the slaves' AL status codes itself. On the
 * byte transports (sim:, unix:, spidev:) it polls the chip with INFO_UPDATE and
 * runs the same detector (ecmxf::EventDetector, lib/core/ecmxf-events.c)
 * over the headers; the detector, made with the device, asks the slaves
 * for their AL status codes as the kernel does (ecmxf::readSlaveStatus()).
 */
#include "ecmxf-util-monitor.hpp"
#include "ecmxf-util.hpp"


#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/events/events.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/sim/chip.hpp>

#include <thread>
#include <ecmxf/model/types_bus.hpp>

namespace ecmxf_util {

const char *const kMonitorHelp =
	"Usage: ecmxf-util [global options] monitor [--count N] [--duration MS]\n"
	"                                           [--interval MS] [--tx-high N]\n"
	"                                           [--rx-low N] [--json]\n"
	"       ecmxf-util -d /dev/ecmxfN monitor --counters [--json]\n"
	"\n"
	"Print one line per event of the chip, until --count events, --duration\n"
	"or Ctrl-C. With a kernel device (-d /dev/ecmxfN) the events come from the\n"
	"kernel module over generic netlink (family \"ecmxf\", group \"events\"; no\n"
	"access to the device node is needed); on sim:, unix: and spidev: devices\n"
	"the chip is polled with INFO_UPDATE every --interval and the same rules\n"
	"run over the response headers:\n"
	"  state          the ECAT state changed; when it went down or to ERROR,\n"
	"                 each slave not in OP with its state and AL status code\n"
	"                 + text (STATE_GET, SLV_INFO_GET 7)\n"
	"  link           the EtherCAT link went down or up (error status bit 0)\n"
	"  reset          the chip reset (NOP answer, 'Ethernet initialised'\n"
	"                 cleared or the ECAT state back to NONE); the kernel also\n"
	"                 says why (warm reset, link resynchronised)\n"
	"  error_status   error-status bits 1..7 set / cleared, by name\n"
	"  ecm_status     ECM status bits (DC stable, Ethernet initialised, PDO\n"
	"                 configured, FIFO enabled) set / cleared\n"
	"  crc_errors     the SPI CRC error counter went up\n"
	"  wkc_burst      the WKC error counter started going up; wkc_burst_end\n"
	"                 after 100 ms without new errors (errors of the burst,\n"
	"                 first to last increase)\n"
	"  fifo           the TxFIFO count crossed --tx-high, or the RxFIFO count\n"
	"                 crossed --rx-low\n"
	"  async_error    (kernel) an async command failed, timed out or was\n"
	"                 refused as busy\n"
	"  device         (kernel) the device was probed or is being removed\n"
	"A quiet bus prints nothing. Times are since the start: CLOCK_MONOTONIC\n"
	"for the kernel's events, the device's clock when polling (virtual time\n"
	"on sim:). On a simulator the polls are paced to the wall clock (one per\n"
	"--interval), with --count and --duration too, instead of spinning a core.\n"
	"\n"
	"Options:\n"
	"  --count N      stop after N events\n"
	"  --duration MS  stop after MS milliseconds\n"
	"  --interval MS  poll period, default 10 (polled devices only)\n"
	"  --tx-high N    TxFIFO high mark, default 10 (polled devices only; the\n"
	"                 kernel's is 10)\n"
	"  --rx-low N     RxFIFO low mark, default 0 (polled devices only; the\n"
	"                 kernel's is 0: the RxFIFO ran dry)\n"
	"  --counters     print the kernel's counters of the device (netlink\n"
	"                 ECMXF_NL_CMD_GET_COUNTERS) and exit\n"
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
constexpr std::uint8_t kErrLink = ECMXF_ERR_LINK_HW;
constexpr std::uint8_t kStateError = ECMXF_ECAT_ERROR;

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

std::string hex4(unsigned v)
{
	char b[8];
	std::snprintf(b, sizeof(b), "0x%04x", v);
	return b;
}

std::string u8s(unsigned v)
{
	return std::to_string(v);
}

/// Bits set and cleared between @p prev and @p cur (only @p mask).
Event bitsEvent(const char *type, const char *what, unsigned prev, unsigned cur, std::uint8_t mask,
		std::vector<std::string> (*namer)(std::uint8_t))
{
	const auto set = namer(static_cast<std::uint8_t>(cur & ~prev & mask));
	const auto cleared = namer(static_cast<std::uint8_t>(prev & ~cur & mask));
	Event e;
	e.type = type;
	e.text = std::string(what) + " " + hex2(prev) + " -> " + hex2(cur) + ":";
	if (!set.empty())
		e.text.append(" set ").append(joined(set, false));
	if (!set.empty() && !cleared.empty())
		e.text.append(";");
	if (!cleared.empty())
		e.text.append(" cleared ").append(joined(cleared, false));
	e.fields = { { "previous", u8s(prev) },
		     { "value", u8s(cur) },
		     { "set", joined(set, true) },
		     { "cleared", joined(cleared, true) } };
	return e;
}

/// "; slave 1: not answering" etc. and the JSON array of a state event.
void addSlaves(const ecmxf::Event &ev, Event &e)
{
	std::string json = "[";
	for (const ecmxf::SlaveAlStatus &s : ev.slaves) {
		const bool answering = s.state != kStateError;
		const auto state = static_cast<std::uint8_t>(s.state & 0x0F);
		const bool error = (s.state & kStateError) != 0;
		e.text.append("; slave ").append(std::to_string(s.position)).append(": ");
		if (!answering) {
			e.text.append("not answering");
		} else {
			e.text.append(stateName(state)).append(error ? " + error" : "");
			if (s.alStatus)
				e.text.append(", AL status ")
					.append(hex4(*s.alStatus))
					.append(" (")
					.append(std::string(ecmxf::alStatusText(*s.alStatus)))
					.append(")");
		}
		if (json.size() > 1)
			json += ", ";
		json.append("{\"position\": ")
			.append(std::to_string(s.position))
			.append(", \"answering\": ")
			.append(answering ? "true" : "false")
			.append(", \"state\": ")
			.append(std::to_string(state))
			.append(", \"state_name\": ")
			.append(jsonString(answering ? stateName(state) : "NONE"))
			.append(", \"error\": ")
			.append(error ? "true" : "false")
			.append(", \"al_status_code\": ")
			.append(s.alStatus ? std::to_string(*s.alStatus) : "null")
			.append(", \"al_status_text\": ")
			.append(s.alStatus ? jsonString(std::string(ecmxf::alStatusText(*s.alStatus))) : "null")
			.append("}");
	}
	json += "]";
	if (ev.slavesIncomplete)
		e.text.append("; (not every slave could be read)");
	e.fields.emplace_back("slave_count", std::to_string(ev.slaveCount));
	e.fields.emplace_back("slaves", json);
	e.fields.emplace_back("slaves_incomplete", ev.slavesIncomplete ? "true" : "false");
	e.fields.emplace_back("al_status_code", ev.alStatus ? std::to_string(*ev.alStatus) : "null");
}

std::string resetReasonName(ecmxf::ResetReason r)
{
	switch (r) {
	case ecmxf::ResetReason::Chip: return "chip";
	case ecmxf::ResetReason::Warm: return "warm";
	case ecmxf::ResetReason::Link: return "link";
	case ecmxf::ResetReason::Unknown: break;
	}
	return "";
}

std::string errnoName(int negErrno)
{
	switch (-negErrno) {
	case EREMOTEIO: return "EREMOTEIO";
	case EBUSY: return "EBUSY";
	case ETIMEDOUT: return "ETIMEDOUT";
	default: return std::to_string(negErrno);
	}
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

bool wantsSlaves(const ecmxf::Event &e)
{
	return ecmxf::stateWentDown(e);
}

Event describe(const ecmxf::Event &ev)
{
	using T = ecmxf::EventType;
	Event e;
	e.type = ecmxf::eventTypeName(ev.type);
	switch (ev.type) {
	case T::State: {
		const auto from = static_cast<std::uint8_t>(ev.oldValue);
		const auto to = static_cast<std::uint8_t>(ev.newValue);
		e.text = "ECAT state " + stateName(from) + " -> " + stateName(to);
		e.fields = { { "from", u8s(from) },
			     { "to", u8s(to) },
			     { "from_name", jsonString(stateName(from)) },
			     { "to_name", jsonString(stateName(to)) } };
		if (ev.haveSlaves)
			addSlaves(ev, e);
		break;
	}
	case T::Link:
		e.text = std::string("EtherCAT link ") + (ev.linkUp ? "up" : "down") + " (error status " +
			 hex2(ev.errStatus) + ")";
		e.fields = { { "link_up", ev.linkUp ? "true" : "false" }, { "err_status", u8s(ev.errStatus) } };
		break;
	case T::ErrorStatus:
		e = bitsEvent("error_status", "error status", ev.oldValue, ev.newValue,
			      static_cast<std::uint8_t>(~kErrLink), errorBitNames);
		break;
	case T::EcmStatus:
		e = bitsEvent("ecm_status", "ECM status", ev.oldValue, ev.newValue, 0xFF, ecmBitNames);
		break;
	case T::CrcErrors:
		e.text = "SPI CRC errors +" + std::to_string(ev.increase) + " (count " + std::to_string(ev.count) + ")";
		e.fields = { { "increase", std::to_string(ev.increase) }, { "count", std::to_string(ev.count) } };
		break;
	case T::WkcBurst:
		e.text = "WKC error burst: +" + std::to_string(ev.increase) + " (count " + std::to_string(ev.count) + ")";
		e.fields = { { "increase", std::to_string(ev.increase) }, { "count", std::to_string(ev.count) } };
		break;
	case T::WkcBurstEnd: {
		const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(ev.duration).count();
		e.text = "WKC error burst over: " + std::to_string(ev.errors) + " errors in " + std::to_string(ms) +
			 " ms (count " + std::to_string(ev.count) + (ev.count == 255 ? ", saturated)" : ")");
		e.fields = { { "errors", std::to_string(ev.errors) },
			     { "duration_ms", std::to_string(ms) },
			     { "count", std::to_string(ev.count) } };
		break;
	}
	case T::Fifo: {
		const bool tx = ev.fifo == ecmxf::FifoId::Tx;
		const char *where = tx ? (ev.above ? "reached its high mark" : "fell below its high mark")
				       : (ev.above ? "rose above its low mark" : "fell to its low mark");
		e.text = std::string(tx ? "TxFIFO " : "RxFIFO ") + where + " " + std::to_string(ev.mark) +
			 " (count " + std::to_string(ev.count) + ")";
		e.fields = { { "fifo", jsonString(tx ? "tx" : "rx") },
			     { "count", std::to_string(ev.count) },
			     { "mark", std::to_string(ev.mark) },
			     { "crossing", jsonString(ev.above ? "above" : "below") } };
		break;
	}
	case T::Reset: {
		const auto st = static_cast<std::uint8_t>(ev.newValue);
		const std::string what = ev.resetReason == ecmxf::ResetReason::Link ? "the link was resynchronised"
					 : ev.resetReason == ecmxf::ResetReason::Warm ? "the chip reset (WARM_RESET)"
										       : "the chip reset";
		e.text = what + " (ECAT state " + stateName(st) + ", ECM status " + hex2(ev.ecmStatus) + ")";
		const std::string reason = resetReasonName(ev.resetReason);
		e.fields = { { "state", u8s(st) },
			     { "state_name", jsonString(stateName(st)) },
			     { "ecm_status", u8s(ev.ecmStatus) },
			     { "reason", reason.empty() ? "null" : jsonString(reason) } };
		break;
	}
	case T::Device: {
		const bool added = ev.action == ecmxf::DeviceAction::Added;
		const auto st = static_cast<std::uint8_t>(ev.newValue);
		e.text = "device " + ev.device + (added ? " added" : " removed");
		if (added)
			e.text += " (ECAT state " + stateName(st) + ", link " +
				  ((ev.errStatus & kErrLink) ? "up" : "down") + ")";
		e.fields = { { "action", jsonString(added ? "added" : "removed") } };
		if (added) {
			e.fields.emplace_back("state", u8s(st));
			e.fields.emplace_back("link_up", (ev.errStatus & kErrLink) ? "true" : "false");
		}
		break;
	}
	case T::PdoLoss: {
		const std::string kind = ecmxf::lossKindName(ev.loss);
		static constexpr const char *kWhat[] = {
			"output ring empty when the chip wanted a frame",
			"input frames dropped: the input ring was full",
			"the chip's RxFIFO ran empty: the bus repeated outputs",
			"output frames refused: the chip's RxFIFO was full",
			"the chip's TxFIFO was full: it dropped input frames",
			"output frames skipped by the pump (it had fallen behind)",
			"pump commands failed: their frames are lost, never sent again",
		};
		const auto i = static_cast<std::size_t>(ev.loss);
		e.text = "cyclic path: " + kind + " +" + std::to_string(ev.increase) + " (total " +
			 std::to_string(ev.total) + ")" + (i < std::size(kWhat) ? std::string(": ") + kWhat[i] : "");
		e.fields = { { "loss", jsonString(kind) },
			     { "increase", std::to_string(ev.increase) },
			     { "total", std::to_string(ev.total) } };
		break;
	}
	case T::AsyncError: {
		const auto info = ecmxf::commandInfo(ev.cmdCode);
		const std::string name = info ? std::string(info->name) : "command";
		e.text = "async command " + name + " (" + std::to_string(ev.cmdCode) + ") failed: " +
			 errnoName(ev.status) + " (error status " + hex2(ev.errStatus) + ")";
		e.fields = { { "command", std::to_string(ev.cmdCode) },
			     { "command_name", jsonString(name) },
			     { "status", std::to_string(ev.status) },
			     { "error", jsonString(errnoName(ev.status)) },
			     { "err_status", u8s(ev.errStatus) } };
		break;
	}
	default:
		e.text = "event " + std::to_string(static_cast<std::uint32_t>(ev.type)) + " (unknown to this version)";
		e.fields = { { "type_number", std::to_string(static_cast<std::uint32_t>(ev.type)) } };
		break;
	}
	if (!ev.device.empty()) {
		e.fields.emplace_back("device", jsonString(ev.device));
		e.fields.emplace_back("seq", std::to_string(ev.seq));
		if (ev.suppressed) {
			e.fields.emplace_back("suppressed", std::to_string(ev.suppressed));
			e.text += " [" + std::to_string(ev.suppressed) + " suppressed before]";
		}
	}
	return e;
}

Detector::Detector(Thresholds th, std::chrono::nanoseconds wkcQuiet, ecmxf::Device *device)
	: det_([&] {
		  ecmxf::EventDetector::Config c;
		  c.txHigh = static_cast<std::uint8_t>(std::min(th.txHigh, 255u));
		  c.rxLow = static_cast<std::uint8_t>(std::min(th.rxLow, 255u));
		  c.wkcQuiet = wkcQuiet;
		  return device ? ecmxf::EventDetector(*device, c) : ecmxf::EventDetector(c);
	  }())
{
}

std::vector<ecmxf::Event> Detector::update(const ecmxf::ResponseHeader &cur, std::chrono::nanoseconds now)
{
	return det_.feed(cur, now);
}

std::vector<ecmxf::Event> Detector::rebase(std::chrono::nanoseconds now)
{
	return det_.rebase(now);
}

namespace {

std::string counterLines(const ecmxf::NetlinkCounters &c, bool json)
{
	const std::pair<const char *, std::uint64_t> events[] = {
		{ "events", c.events },
		{ "events_suppressed", c.eventsSuppressed },
		{ "events_failed", c.eventsFailed },
	};
	std::string s;
	if (json)
		s = "{\"device\": " + jsonString(c.device) + ", \"minor\": " + std::to_string(c.minor);
	const auto put = [&](const char *name, std::uint64_t value) {
		if (json)
			s.append(", ").append(jsonString(name)).append(": ").append(std::to_string(value));
		else
			s.append(name).append(" ").append(std::to_string(value)).append("\n");
	};
	for (const auto &[name, value] : ecmxf::counterFields(c.link))
		put(name, value);
	for (const auto &[name, value] : events)
		put(name, value);
	if (json)
		s += "}\n";
	return s;
}

} // namespace

std::string countersText(const ecmxf::NetlinkCounters &c)
{
	return counterLines(c, false);
}

std::string countersJson(const ecmxf::NetlinkCounters &c)
{
	return counterLines(c, true);
}

} // namespace monitor

namespace {

constexpr std::uint8_t kWarmReset = ECMXF_CMD_WARM_RESET;

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

/// ECAT_INIT_OP for all slaves (FIFO off, no DC on the slaves, SYNC0
/// 1 ms, LRD + LWR), then every slave to PRE-OP, SAFE-OP, OP.
void bringUp(ecmxf::Device &dev)
{
	ecmxf::InitConfig init;
	init.dc.assignActivate = 0;
	init.lrw = false;
	const ecmxf::Bus bus = dev.bus();
	bus.initNetwork(init);
	for (const ecmxf::State st : { ecmxf::State::PreOp, ecmxf::State::SafeOp, ecmxf::State::Op })
		bus.stateSet(ecmxf::kAllSlaves, st);
}

void runSimAction(ecmxf::Device &dev, const SimAction &a)
{
	ecmxf::sim::Chip *sim = dev.link().simulator();
	if (!sim)
		throw UsageError("monitor: --sim-at needs a sim: device");
	ecmxf::sim::FaultPlan &f = sim->faults();
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

std::chrono::nanoseconds monotonicNow()
{
	timespec ts{};
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

/// The kernel's events of /dev/ecmxf@p minor over generic netlink.
int monitorNetlink(const Globals &g, std::uint32_t minorNo, std::optional<std::uint64_t> count,
		   std::optional<std::uint64_t> durationMs)
{
	ecmxf::EventSubscriber sub;
	const StopSignals signals; // SIGINT, SIGTERM, SIGHUP end the monitor (exit 0)
	const std::chrono::nanoseconds t0 = monotonicNow();
	std::uint64_t events = 0;
	// say when the subscription stands (stderr: stdout is the events)
	if (!g.quiet)
		std::fprintf(stderr, "monitor: listening to the kernel's events of ecmxf%u\n", minorNo);
	while (!StopSignals::pending()) {
		auto wait = std::chrono::milliseconds(200);
		if (durationMs) {
			const auto left = std::chrono::milliseconds(*durationMs) -
					  std::chrono::duration_cast<std::chrono::milliseconds>(monotonicNow() - t0);
			if (left <= std::chrono::milliseconds(0))
				break;
			wait = std::min(wait, left);
		}
		const std::optional<ecmxf::Event> ev = sub.next(wait);
		if (!ev || ev->minor != minorNo)
			continue;
		print(g, ev->time - t0, monitor::describe(*ev));
		if (count && ++events >= *count)
			break;
	}
	if (sub.lost())
		std::fprintf(stderr, "monitor: the socket lost messages %llu times (receive buffer full)\n",
			     static_cast<unsigned long long>(sub.lost()));
	return 0;
}

} // namespace

int cmdMonitor(Globals &g, const Args &args)
{
	std::optional<std::uint64_t> count, durationMs, intervalMs;
	std::optional<unsigned> txHigh, rxLow;
	bool counters = false;
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
			txHigh = static_cast<unsigned>(number("--tx-high", value(), 1, 255));
		else if (a == "--rx-low")
			rxLow = static_cast<unsigned>(number("--rx-low", value(), 0, 254));
		else if (a == "--counters")
			counters = true;
		else if (a == "--sim-at")
			actions.push_back(parseSimAction(value()));
		else
			throw UsageError("monitor: unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util monitor --help')");
	}

	// the kernel's device reports its events over netlink (a listener needs
	// no access to the device itself); other links are polled and their
	// headers run through the detector
	const ecmxf::DeviceUri uri = ecmxf::parseDeviceUri(g.device);
	const std::optional<std::uint32_t> kminor =
		uri.kind == ecmxf::DeviceUri::Kind::Kernel ? ecmxf::KernelLink::minorOf(uri.path) : std::nullopt;
	if (kminor) {
		const char *polledOnly = intervalMs ? "--interval"
					 : txHigh   ? "--tx-high"
					 : rxLow    ? "--rx-low"
					 : !actions.empty() ? "--sim-at"
							    : nullptr;
		if (polledOnly)
			throw UsageError(std::string("monitor: ") + polledOnly +
					 " applies to polled devices (sim:, unix:, spidev:), not to the kernel's events");
		if (counters) {
			const ecmxf::NetlinkCounters c = ecmxf::readNetlinkCounters(*kminor);
			std::fputs((g.json ? monitor::countersJson(c) : monitor::countersText(c)).c_str(), stdout);
			return 0;
		}
		return monitorNetlink(g, *kminor, count, durationMs);
	}
	if (counters)
		throw UsageError("monitor: --counters needs a kernel device (-d /dev/ecmxfN)");

	monitor::Thresholds th;
	if (txHigh)
		th.txHigh = *txHigh;
	if (rxLow)
		th.rxLow = *rxLow;
	const auto interval = std::chrono::milliseconds(intervalMs.value_or(10));
	const DevicePtr dev = openDevice(g);
	if (!actions.empty() && !dev->link().simulator())
		throw UsageError("monitor: --sim-at needs a sim: device");
	ecmxf::Link &tr = dev->link();
	// A simulator runs in virtual time: unpaced, the loop would spin a
	// core polling as fast as it can (for ever with --count on a quiet
	// bus). The polls are paced to the wall clock always (below), as a
	// real chip's are.
	if (tr.simulator() && !durationMs && !g.quiet)
		std::fprintf(stderr, "monitor: a simulator: paced to the wall clock, one poll every %lld ms "
				     "(Ctrl-C stops)\n",
			     static_cast<long long>(interval.count()));
	const StopSignals signals; // SIGINT, SIGTERM, SIGHUP end the monitor (exit 0)

	const std::chrono::nanoseconds t0 = tr.now();
	// a burst ends after 100 ms without new errors, as in the kernel, but
	// never because a single poll saw none
	monitor::Detector det(th, std::max<std::chrono::nanoseconds>(std::chrono::milliseconds(100), 2 * interval),
			      dev.get());
	std::uint64_t events = 0;
	std::size_t nextAction = 0;
	std::stable_sort(actions.begin(), actions.end(),
			 [](const SimAction &x, const SimAction &y) { return x.at < y.at; });
	const ecmxf::Command poll = simpleCommand(0); // INFO_UPDATE_OP

	bool first = true;
	while (!StopSignals::pending()) {
		if (!first) {
			// one poll per --interval of the wall clock, whatever the
			// link's clock does (virtual on sim: and an unpaced unix:)
			const auto w0 = std::chrono::steady_clock::now();
			tr.sleepFor(interval);
			const auto left = interval - (std::chrono::steady_clock::now() - w0);
			if (left.count() > 0)
				std::this_thread::sleep_for(left);
		}
		const std::chrono::nanoseconds t = tr.now() - t0;
		if (durationMs && t > std::chrono::milliseconds(*durationMs))
			break;
		if (!first)
			while (nextAction < actions.size() && actions[nextAction].at <= t)
				runSimAction(*dev, actions[nextAction++]);
		first = false;
		std::vector<ecmxf::Event> evs;
		bool nopAnswer = false;
		try {
			evs = det.update(dev->command(poll).header, tr.now());
		} catch (const ecmxf::Error &e) {
			if (e.errnoValue() != ECONNRESET)
				throw;
			// the poll itself was answered by a NOP: no header to show
			evs = det.rebase(tr.now());
			ecmxf::Event r;
			r.type = ecmxf::EventType::Reset;
			r.time = tr.now();
			evs.push_back(r);
			nopAnswer = true;
		}
		for (std::size_t i = 0; i < evs.size(); i++) {
			const ecmxf::Event &e = evs[i];
			monitor::Event line = monitor::describe(e);
			if (nopAnswer && i + 1 == evs.size())
				line.text = "the chip reset (NOP answer)";
			print(g, tr.now() - t0, line);
			if (count && ++events >= *count)
				return 0;
		}
	}
	return 0;
}

} // namespace ecmxf_util
