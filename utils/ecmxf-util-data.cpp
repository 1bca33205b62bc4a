// SPDX-License-Identifier: MIT
/*
 * ecmxf-util data - the process image decoded by entry (IgH's `ethercat
 * data`): the bus in SAFE-OP/OP, a ProcessImage of its mapping, a Cyclic
 * for a few cycles, then each slave's output and input entries with their
 * values; --set NAME=VALUE writes an output entry first.
 */
#include "ecmxf-util.hpp"
#include "ecmxf-util-scope.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/model/objects.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

namespace ecmxf_util {

const char *const kDataHelp =
	"Usage: ecmxf-util [global options] data [-p N] [--set NAME=VALUE]... [--json]\n"
	"                  [--watch [--interval MS] [--count N]]\n"
	"\n"
	"The process image (as IgH's 'ethercat data', decoded): for each slave,\n"
	"or slave N, its output entries (RxPDO, master to slave) and input\n"
	"entries (TxPDO) with index:subindex, name, bit length and value, read\n"
	"after a few cycles of the exchange (1 ms), and its unit:\n"
	"\n"
	"  slave 0: EST-584\n"
	"    out 0x6040:00  Controlword                   16 bit  0x0000 0\n"
	"    in  0x6064:00  Position actual value         32 bit  -1200 inc\n"
	"\n"
	"The CiA 402 objects the tools know have their type (INTEGER32...) and\n"
	"unit (CiA 402's without a factor group: inc, inc/s, inc/s^2, 0.1% rated\n"
	"torque): signed ones print as signed numbers; other entries print in hex\n"
	"and decimal, without a unit. A fresh bus is brought to OP first (the Master: SYNC0 1 ms);\n"
	"a bus that is already up must be in SAFE-OP or OP (process data runs\n"
	"there), else the command fails naming its state.\n"
	"\n"
	"Options:\n"
	"  -p, --position N   only the slave at bus position N (or a list: 0,2, a\n"
	"                     range: 0-3)\n"
	"  --set NAME=VALUE   before the image is read, write VALUE into output\n"
	"                     entry NAME of slave N (-p required): NAME is the\n"
	"                     entry's name (case, spaces and '_' ignored:\n"
	"                     TargetPosition) or INDEX:SUB; an input entry or an\n"
	"                     unknown one is refused with the reason. The chip\n"
	"                     keeps sending the last outputs after the command.\n"
	"  -w, --watch        live: the image again every --interval (the bus\n"
	"                     cycling between), redrawn in place on a terminal,\n"
	"                     one block (--json: one line) per refresh otherwise;\n"
	"                     until Ctrl-C (SIGINT, SIGTERM, SIGHUP: exit 0)\n"
	"  --interval MS      --watch: the refresh period (default 100; 1 = every\n"
	"                     bus cycle)\n"
	"  --count N          --watch: stop after N refreshes\n"
	"  --json             an array of {position, name, outputs: [{index, sub,\n"
	"                     name, bit_length, type, value, unit}], inputs: [...]}\n"
	"                     (type and unit null where not known)\n"
	"  -h, --help         show this help\n";

namespace {

using namespace std::chrono_literals;

/// The entry as a standard object (type, unit) when it is one mapped whole.
std::optional<ecmxf::StandardObject> objectOf(const ecmxf::PdoEntryInfo &e)
{
	const auto o = ecmxf::standardObject(e.index, e.sub);
	if (!o || ecmxf::objectTypeSize(o->type) * 8 != e.bitLength)
		return std::nullopt;
	return o;
}

std::optional<ecmxf::ObjectType> typeOf(const ecmxf::PdoEntryInfo &e)
{
	const auto o = objectOf(e);
	return o ? std::optional(o->type) : std::nullopt;
}

bool isSigned(const ecmxf::PdoEntryInfo &e)
{
	const auto t = typeOf(e);
	return t && ecmxf::objectTypeSigned(*t);
}

std::int64_t signedOf(std::uint64_t raw, unsigned bits)
{
	if (bits < 64 && ((raw >> (bits - 1)) & 1u))
		raw |= ~std::uint64_t{ 0 } << bits;
	return static_cast<std::int64_t>(raw);
}

std::string valueText(const ecmxf::PdoEntryInfo &e, std::uint64_t raw, bool json)
{
	if (isSigned(e))
		return std::to_string(signedOf(raw, e.bitLength));
	if (json || e.bitLength == 1)
		return std::to_string(raw);
	return hexString(raw, static_cast<int>((e.bitLength + 3) / 4)) + " " + std::to_string(raw);
}

struct Set {
	std::string name, value;
};

/// The output entry of @p s named @p name; refused with the reason.
const ecmxf::PdoEntryInfo &findOutput(const ecmxf::SlavePdos &s, unsigned pos, const std::string &name)
{
	const auto match = [&](const ecmxf::PdoEntryInfo &e) {
		if (e.index == 0)
			return false;
		if (ecmxf::entryNameMatches(e.name, name))
			return true;
		try {
			const ObjectAddress a = parseObjectAddress("data", name);
			return a.index == e.index && a.sub == e.sub;
		} catch (const UsageError &) {
			return false;
		}
	};
	for (const auto &e : s.outputs)
		if (match(e))
			return e;
	for (const auto &e : s.inputs)
		if (match(e))
			throw UsageError("data: --set " + name + ": slave " + std::to_string(pos) + " " +
					 objectName({ e.index, e.sub }) + (e.name.empty() ? "" : " (" + e.name + ")") +
					 " is an input (TxPDO): the slave writes it");
	std::string outs;
	for (const auto &e : s.outputs)
		if (e.index)
			outs += (outs.empty() ? "" : ", ") + objectName({ e.index, e.sub }) +
				(e.name.empty() ? "" : " " + e.name);
	throw UsageError("data: --set " + name + ": slave " + std::to_string(pos) + " maps no such output entry" +
			 (outs.empty() ? " (it has no outputs)" : " (its outputs: " + outs + ")"));
}

} // namespace

int cmdData(Globals &g, const Args &args)
{
	std::optional<std::string> posText;
	std::vector<Set> sets;
	// --set may be given more than once: take them out before parseArgs()
	Args rest;
	for (std::size_t i = 0; i < args.size(); i++) {
		std::string_view a = args[i];
		std::string_view v;
		if (a == "--set") {
			if (i + 1 >= args.size())
				throw UsageError("data: option '--set' needs NAME=VALUE");
			v = args[++i];
		} else if (a.starts_with("--set=")) {
			v = a.substr(6);
		} else {
			rest.push_back(a);
			continue;
		}
		const auto eq = v.find('=');
		if (eq == std::string_view::npos || eq == 0 || eq + 1 == v.size())
			throw UsageError("data: --set '" + std::string(v) + "': NAME=VALUE expected");
		sets.push_back({ std::string(v.substr(0, eq)), std::string(v.substr(eq + 1)) });
	}
	bool watch = false;
	std::optional<std::string> intervalText, countText;
	const auto pos = parseArgs("data", rest, g, kDataHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "-w", "--watch", &watch, nullptr },
				     { "", "--interval", nullptr, &intervalText },
				     { "", "--count", nullptr, &countText } });
	if (!pos)
		return 0;
	if ((intervalText || countText) && !watch)
		throw UsageError("data: --interval and --count are for --watch");
	const long intervalMs =
		intervalText ? static_cast<long>(parseUnsigned("data", "--interval", *intervalText, 3'600'000, 1)) : 100;
	std::optional<std::uint64_t> count_;
	if (countText)
		count_ = parseUnsigned("data", "--count", *countText, UINT32_MAX, 1);
	const bool tty = isatty(STDOUT_FILENO) != 0;
	if (!pos->empty())
		throw UsageError("data: unexpected argument '" + pos->front() + "' (try 'ecmxf-util data --help')");
	// none: every slave; -p 1, -p 0,2, -p 0-3
	const std::optional<Positions> sel = posText ? std::optional(parsePositions("data", *posText)) : std::nullopt;
	if (!sets.empty() && !sel)
		throw UsageError("data: --set needs the slave (-p N)");
	if (!sets.empty() && sel->list.size() != 1)
		throw UsageError("data: --set writes the entry of one slave: -p N, not " + *posText);

	ProcessDataBus bus = openProcessDataBus(g, false);
	const DevicePtr &dev = bus.dev;
	const auto count = static_cast<unsigned>(bus.pdos.size());
	if (sel)
		checkPositions(*sel, count);
	const std::vector<ecmxf::SlavePdos> &pdos = bus.pdos;

	ecmxf::ProcessImage image(pdos);
	std::unique_ptr<ecmxf::Cyclic> cyc;
	try {
		cyc = std::make_unique<ecmxf::Cyclic>(*dev, image, ecmxf::CyclicConfig::motion(1ms));
	} catch (const ecmxf::Error &e) {
		if (e.errnoValue() == ENETDOWN)
			throw ecmxf::Error(std::string("data: process data runs in SAFE-OP and OP: ") + e.what(),
					   ENETDOWN);
		throw;
	}
	// the outputs as they are on the bus: the chip's last ones are not
	// readable, so the image starts from zero; --set writes its entries
	for (const Set &s : sets) {
		const unsigned p = sel->list.front();
		const ecmxf::PdoEntryInfo &e = findOutput(pdos[p], p, s.name);
		const std::string what = "--set " + s.name;
		std::uint64_t raw = 0;
		if (isSigned(e)) {
			const std::int64_t max = e.bitLength >= 64 ? INT64_MAX : (std::int64_t{ 1 } << (e.bitLength - 1)) - 1;
			raw = static_cast<std::uint64_t>(parseSigned("data", what, s.value, -max - 1, max));
		} else {
			const std::uint64_t max = e.bitLength >= 64 ? UINT64_MAX : (std::uint64_t{ 1 } << e.bitLength) - 1;
			raw = parseUnsigned("data", what, s.value, max);
		}
		image.output<std::uint64_t>(p, e.index, e.sub).set(raw);
	}
	cyc->start();
	// runs @p n cycles (at least 20 the first time: the outputs reach the
	// slaves and their inputs come back, the FIFO's pipeline is about 7)
	const auto runCycles = [&](long n) {
		for (long i = 0; i < n; i++) {
			const auto &r = cyc->cycle();
			if (r.error)
				throw ecmxf::Error(std::string("data: the cyclic exchange failed: ") + r.message,
						   r.error);
			(void)cyc->waitNextCycle();
		}
	};
	runCycles(20);

	// the values through the image's handles (unsigned, as wide as can be)
	const auto entries = [&](unsigned p, bool out) {
		const std::vector<ecmxf::PdoEntryInfo> &v = out ? pdos[p].outputs : pdos[p].inputs;
		const char *dir = out ? "out" : "in";
		std::string s;
		bool first = true;
		for (const auto &e : v) {
			if (e.index == 0)
				continue; // padding
			const std::uint64_t raw = out ? image.output<std::uint64_t>(p, e.index, e.sub).get()
						      : image.input<std::uint64_t>(p, e.index, e.sub).get();
			const auto o = objectOf(e);
			const auto t = typeOf(e);
			const std::string_view unit = o ? o->unit : std::string_view();
			if (g.json) {
				s += std::string(first ? "" : ", ") + "{\"index\": " + std::to_string(e.index) +
				     ", \"sub\": " + std::to_string(e.sub) + ", \"name\": " + jsonString(e.name) +
				     ", \"bit_length\": " + std::to_string(e.bitLength) + ", \"type\": " +
				     (t ? jsonString(ecmxf::objectTypeName(*t)) : std::string("null")) +
				     ", \"value\": " + valueText(e, raw, true) + ", \"unit\": " +
				     (unit.empty() ? std::string("null") : jsonString(unit)) + "}";
			} else {
				char line[200];
				std::snprintf(line, sizeof line, "    %-3s %s  %-30s %2u bit  %s%s%.*s\n", dir,
					      objectName({ e.index, e.sub }).c_str(), e.name.c_str(), e.bitLength,
					      valueText(e, raw, false).c_str(), unit.empty() ? "" : " ",
					      static_cast<int>(unit.size()), unit.data());
				s += line;
			}
			first = false;
		}
		return s;
	};
	const auto printImage = [&] {
		std::string text = g.json ? "[" : "";
		bool first = true;
		for (unsigned p = 0; p < count; p++) {
			if (sel && !sel->has(p))
				continue;
			const std::string name = bus.master->slaves()[p].name;
			if (g.json)
				text += std::string(first ? "" : ",") + (watch ? " " : "\n  ") + "{\"position\": " +
					std::to_string(p) + ", \"name\": " + jsonString(name) + ", \"outputs\": [" +
					entries(p, true) + "], \"inputs\": [" + entries(p, false) + "]}";
			else
				text += "slave " + std::to_string(p) + (name.empty() ? "" : ": ") + name + "\n" +
					entries(p, true) + entries(p, false);
			first = false;
		}
		if (g.json)
			text += watch ? "]\n" : "\n]\n";
		// live on a terminal: redrawn in place (cursor home, clear)
		if (watch && tty && !g.json)
			std::fputs("\x1b[H\x1b[2J", stdout);
		std::fputs(text.c_str(), stdout);
		std::fflush(stdout);
	};
	if (!watch) {
		cyc->stop();
		printImage();
		return 0;
	}
	// --watch: a refresh per --interval (cycles of the bus between them,
	// paced to the wall clock as monitor is), until --count refreshes or a
	// signal (exit 0); --json: one array per line (JSON Lines)
	const StopSignals signals;
	for (std::uint64_t n = 0; !StopSignals::pending();) {
		printImage();
		if (count_ && ++n >= *count_)
			break;
		const auto w0 = std::chrono::steady_clock::now();
		runCycles(intervalMs);
		const auto left = std::chrono::milliseconds(intervalMs) - (std::chrono::steady_clock::now() - w0);
		if (left.count() > 0 && !StopSignals::pending())
			std::this_thread::sleep_for(left);
	}
	cyc->stop();
	return 0;
}

} // namespace ecmxf_util
