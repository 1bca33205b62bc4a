// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - helpers shared by the command units.
 */
#include "ecmxf-util.hpp"
#include <ecmxf/bus/bus.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <ecmxf/error.hpp>
#include <ecmxf/verbs.hpp>

#include <unistd.h>

namespace ecmxf_util {

bool parseFlags(std::string_view cmd, const Args &args, Globals &g, const char *help,
		const std::vector<Flag> &flags)
{
	for (const std::string_view a : args) {
		if (a == "-h" || a == "--help") {
			std::fputs(help, stdout);
			return true;
		}
		if (a == "--json") {
			g.json = true;
			continue;
		}
		bool known = false;
		for (const Flag &f : flags) {
			if ((!f.shortName.empty() && a == f.shortName) || a == f.longName) {
				*f.value = true;
				known = true;
			}
		}
		if (!known)
			throw UsageError(std::string(cmd) + ": unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util " + std::string(cmd) + " --help')");
	}
	return false;
}

std::string jsonString(std::string_view s)
{
	std::string out = "\"";
	for (const char ch : s) {
		const auto c = static_cast<unsigned char>(ch);
		if (c == '"' || c == '\\') {
			out += '\\';
			out += ch;
		} else if (c < 0x20 || c == 0x7F) {
			char buf[8];
			std::snprintf(buf, sizeof(buf), "\\u%04x", c);
			out += buf;
		} else {
			out += ch;
		}
	}
	return out + "\"";
}

ecmxf::Command simpleCommand(std::uint8_t code, std::uint8_t param)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

std::uint16_t le16(const ecmxf::Response &r, std::string_view what)
{
	if (r.data.size() < 2)
		throw std::runtime_error(std::string(what) + ": answer of " + std::to_string(r.data.size()) +
					 " bytes, expected 2");
	return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
}

std::uint32_t le32(const ecmxf::Response &r, std::string_view what)
{
	if (r.data.size() < 4)
		throw std::runtime_error(std::string(what) + ": answer of " + std::to_string(r.data.size()) +
					 " bytes, expected 4");
	return static_cast<std::uint32_t>(r.data[0]) | static_cast<std::uint32_t>(r.data[1]) << 8 |
	       static_cast<std::uint32_t>(r.data[2]) << 16 | static_cast<std::uint32_t>(r.data[3]) << 24;
}

std::string stateName(std::uint8_t state)
{
	// the library's names (ecmxf::stateName()) in the spelling the
	// command line takes: "PREOP", "SAFEOP"
	if (state == 0x10)
		return "ERROR";
	std::string name = ecmxf::stateName(static_cast<ecmxf::State>(state));
	if (name.rfind("0x", 0) == 0) {
		char buf[8];
		std::snprintf(buf, sizeof(buf), "0x%02x", state);
		return buf;
	}
	std::erase(name, '-');
	return name;
}

// ---------------------------------------------------------------------------
// arguments
// ---------------------------------------------------------------------------

namespace {

/// -a ALIAS of this run (parseArgs()), and whether selectSlave() took it.
std::optional<std::uint16_t> gAlias;
bool gAliasTaken = false;

std::string tryHelp(std::string_view cmd)
{
	return std::string(" (try 'ecmxf-util ").append(cmd).append(" --help')");
}

bool looksNegativeNumber(std::string_view a)
{
	return a.size() >= 2 && a[0] == '-' && ((a[1] >= '0' && a[1] <= '9') || a[1] == '.');
}

} // namespace

std::optional<std::vector<std::string>> parseArgs(std::string_view cmd, const Args &args, Globals &g,
						  const char *help, const std::vector<Option> &opts)
{
	std::vector<std::string> pos;
	bool onlyPositional = false;
	for (std::size_t i = 0; i < args.size(); i++) {
		const std::string_view a = args[i];
		if (onlyPositional || a.empty() || a[0] != '-' || a == "-" || looksNegativeNumber(a)) {
			pos.emplace_back(a);
			continue;
		}
		if (a == "--") {
			onlyPositional = true;
			continue;
		}
		if (a == "-h" || a == "--help") {
			std::fputs(help, stdout);
			return std::nullopt;
		}
		if (a == "--json") {
			g.json = true;
			continue;
		}
		if (a == "-q" || a == "--quiet") {
			g.quiet = true;
			continue;
		}
		std::string_view name = a;
		std::optional<std::string_view> inlineValue;
		if (a.starts_with("--")) {
			if (const auto eq = a.find('='); eq != std::string_view::npos) {
				name = a.substr(0, eq);
				inlineValue = a.substr(eq + 1);
			}
		} else if (a.size() > 2) {
			// -p0, -tfloat: a short option glued to its value (getopt's
			// form, as IgH's ethercat takes it)
			for (const Option &o : opts)
				if (o.value && !o.shortName.empty() && a.starts_with(o.shortName)) {
					name = o.shortName;
					inlineValue = a.substr(o.shortName.size());
				}
		}
		const Option *found = nullptr;
		for (const Option &o : opts)
			if ((!o.shortName.empty() && name == o.shortName) || name == o.longName)
				found = &o;
		if (!found && (name == "-a" || name == "--alias" || (a.starts_with("-a") && !a.starts_with("--")))) {
			// IgH's -a ALIAS [-p N]: the N-th slave after the first
			// one with that station alias (selectSlave())
			const bool selects = std::any_of(opts.begin(), opts.end(), [](const Option &o) {
				return o.shortName == "-p" && o.value;
			});
			if (!selects)
				throw UsageError(std::string(cmd).append(": -a/--alias: this command selects no "
									 "slave"));
			std::string_view v;
			if (inlineValue)
				v = *inlineValue;
			else if (name != "-a" && name != "--alias")
				v = a.substr(2); // -a5
			else if (i + 1 < args.size())
				v = args[++i];
			else
				throw UsageError(std::string(cmd).append(": option '").append(name).append(
					"' needs a value"));
			gAlias = static_cast<std::uint16_t>(parseUnsigned(cmd, "-a", v, 0xFFFF));
			continue;
		}
		if (!found)
			throw UsageError(std::string(cmd).append(": unknown argument '").append(a).append("'").append(
				tryHelp(cmd)));
		if (found->flag) {
			if (inlineValue)
				throw UsageError(std::string(cmd).append(": option '").append(name).append(
					"' takes no value"));
			*found->flag = true;
			continue;
		}
		if (inlineValue) {
			*found->value = std::string(*inlineValue);
		} else {
			if (i + 1 >= args.size())
				throw UsageError(std::string(cmd).append(": option '").append(name).append(
					"' needs a value"));
			*found->value = std::string(args[++i]);
		}
	}
	// -a without -p: the aliased slave itself (IgH's -p defaults to 0)
	if (gAlias)
		for (const Option &o : opts)
			if (o.shortName == "-p" && o.value && !*o.value)
				*o.value = "0";
	return pos;
}

std::uint64_t parseUnsigned(std::string_view cmd, std::string_view what, std::string_view text,
			    std::uint64_t max, std::uint64_t min)
{
	std::string_view digits = text;
	int base = 10;
	if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
		digits.remove_prefix(2);
		base = 16;
	}
	std::uint64_t v = 0;
	const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, base);
	const auto outOfRange = [&] {
		return UsageError(std::string(cmd).append(": ").append(what).append(": ").append(text).append(
			" is out of range ").append(std::to_string(min)).append("..").append(std::to_string(max)));
	};
	// a negative number is a number, out of an unsigned range
	if (text.size() > 1 && text[0] == '-' && text[1] >= '0' && text[1] <= '9') {
		std::uint64_t m = 0;
		const auto [e2, ec2] = std::from_chars(text.data() + 1, text.data() + text.size(), m, 10);
		if (e2 == text.data() + text.size() && ec2 != std::errc::invalid_argument && (m != 0 || min > 0))
			throw outOfRange();
		if (e2 == text.data() + text.size() && ec2 != std::errc::invalid_argument)
			return 0; // -0
	}
	if (digits.empty() || end != digits.data() + digits.size() || ec == std::errc::invalid_argument)
		throw UsageError(std::string(cmd).append(": ").append(what).append(": '").append(text).append(
			"' is not a number (decimal or 0x hex)"));
	if (ec == std::errc::result_out_of_range || v > max || v < min)
		throw outOfRange();
	return v;
}

std::int64_t parseSigned(std::string_view cmd, std::string_view what, std::string_view text, std::int64_t min,
			 std::int64_t max)
{
	const bool neg = !text.empty() && text[0] == '-';
	const std::string_view mag = neg ? text.substr(1) : text;
	std::uint64_t m = 0;
	try {
		m = parseUnsigned(cmd, what, mag, UINT64_MAX);
	} catch (const UsageError &) {
		throw UsageError(std::string(cmd).append(": ").append(what).append(": '").append(text).append(
			"' is not a number (decimal or 0x hex)"));
	}
	const auto outOfRange = [&] {
		return UsageError(std::string(cmd).append(": ").append(what).append(": ").append(text).append(
			" is out of range ").append(std::to_string(min)).append("..").append(std::to_string(max)));
	};
	if (neg) {
		if (m > static_cast<std::uint64_t>(INT64_MAX) + 1)
			throw outOfRange();
		const std::int64_t v = m == static_cast<std::uint64_t>(INT64_MAX) + 1 ? INT64_MIN
										     : -static_cast<std::int64_t>(m);
		if (v < min)
			throw outOfRange();
		return v;
	}
	if (m > static_cast<std::uint64_t>(max))
		throw outOfRange();
	return static_cast<std::int64_t>(m);
}

double parseReal(std::string_view cmd, std::string_view what, std::string_view text)
{
	const std::string s(text);
	char *end = nullptr;
	errno = 0;
	const double v = std::strtod(s.c_str(), &end);
	if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v))
		throw UsageError(std::string(cmd).append(": ").append(what).append(": '").append(text).append(
			"' is not a real number"));
	return v;
}

ObjectAddress parseObjectAddress(std::string_view cmd, std::string_view text)
{
	ObjectAddress a;
	const auto colon = text.find(':');
	const std::string_view idx = text.substr(0, colon);
	a.index = static_cast<std::uint16_t>(parseUnsigned(cmd, "INDEX", idx, 0xFFFF));
	if (colon != std::string_view::npos)
		a.sub = static_cast<std::uint8_t>(parseUnsigned(cmd, "SUB", text.substr(colon + 1), 0xFF));
	return a;
}

ObjectAddress parseObjectAddress(std::string_view cmd, std::string_view index, std::string_view sub)
{
	if (index.find(':') != std::string_view::npos)
		throw UsageError(std::string(cmd).append(": INDEX:SUB '").append(index).append(
			"' and a SUB argument: give the subindex once"));
	ObjectAddress a;
	a.index = static_cast<std::uint16_t>(parseUnsigned(cmd, "INDEX", index, 0xFFFF));
	a.sub = static_cast<std::uint8_t>(parseUnsigned(cmd, "SUB", sub, 0xFF));
	return a;
}

std::string hexString(std::uint64_t v, int digits)
{
	char buf[24];
	std::snprintf(buf, sizeof(buf), "0x%0*llx", digits, static_cast<unsigned long long>(v));
	return buf;
}

std::string objectName(ObjectAddress a)
{
	// the form parseObjectAddress() reads back: subindexes 0..9 read the
	// same in decimal and hex, larger ones get their 0x ("0x6064:10"
	// would be subindex 10, not 0x10)
	char buf[20];
	std::snprintf(buf, sizeof(buf), a.sub < 10 ? "0x%04x:%02x" : "0x%04x:0x%02x", a.index, a.sub);
	return buf;
}

std::string hexBytes(const std::vector<std::uint8_t> &b, const char *sep)
{
	std::string out;
	char buf[4];
	for (std::size_t i = 0; i < b.size(); i++) {
		if (i)
			out += sep;
		std::snprintf(buf, sizeof(buf), "%02x", b[i]);
		out += buf;
	}
	return out;
}

std::uint8_t parsePosition(std::string_view cmd, const std::optional<std::string> &text)
{
	if (!text)
		throw UsageError(std::string(cmd).append(": which slave? -p/--position N is required").append(
			tryHelp(cmd)));
	return static_cast<std::uint8_t>(parseUnsigned(cmd, "-p", *text, ecmxf::kMaxSlavePosition));
}

// ---------------------------------------------------------------------------
// the device and the bring-up rule
// ---------------------------------------------------------------------------

bool busDown(ecmxf::Device &dev)
{
	return ecmxf::busDown(dev);
}

unsigned ensureBus(ecmxf::Device &dev, BusNeed need, bool verbose)
{
	if (verbose && ecmxf::busDown(dev))
		std::fprintf(stderr, "ecmxf-util: no network initialised yet, running ECAT_INIT_OP%s\n",
			     need == BusNeed::PreOp ? " and PRE-OP" : "");
	return ecmxf::ensureBusUp(dev, need == BusNeed::PreOp);
}

std::uint8_t selectSlave(ecmxf::Device &dev, std::uint8_t position, unsigned count)
{
	if (!gAlias) {
		checkPosition(position, count);
		return position;
	}
	gAliasTaken = true;
	for (unsigned p = 0; p < count; p++) {
		if (dev.bus().slaveInfo(static_cast<std::uint8_t>(p)).alias != *gAlias)
			continue;
		const unsigned target = p + position;
		if (target >= count)
			throw ecmxf::Error("alias " + std::to_string(*gAlias) + " is slave " + std::to_string(p) +
						   ": -p " + std::to_string(position) + " after it is beyond the bus (" +
						   std::to_string(count) + (count == 1 ? " slave)" : " slaves)"),
					   ENODEV);
		return static_cast<std::uint8_t>(target);
	}
	throw ecmxf::Error("no slave has the alias " + std::to_string(*gAlias) +
				   " ('ecmxf-util slaves -v' shows each slave's alias)",
			   ENODEV);
}

bool Positions::has(unsigned p) const
{
	return std::binary_search(list.begin(), list.end(), p);
}

Positions parsePositions(std::string_view cmd, std::string_view text)
{
	Positions r;
	const std::string what = "-p " + std::string(text);
	if (text.empty())
		throw UsageError(std::string(cmd).append(": -p: no position given").append(tryHelp(cmd)));
	std::string_view rest = text;
	for (;;) {
		const auto comma = rest.find(',');
		const std::string_view item = rest.substr(0, comma);
		if (item.empty())
			throw UsageError(std::string(cmd) + ": " + what + ": an empty item in the list" + tryHelp(cmd));
		// a range low-high; a leading '-' is a (refused) negative number
		const auto dash = item.find('-', 1);
		const auto number = [&](std::string_view t) {
			return static_cast<unsigned>(parseUnsigned(cmd, "-p", t, ecmxf::kMaxSlavePosition));
		};
		if (dash != std::string_view::npos) {
			const unsigned lo = number(item.substr(0, dash)), hi = number(item.substr(dash + 1));
			if (lo > hi)
				throw UsageError(std::string(cmd) + ": " + what + ": range " + std::string(item) +
						 " runs backwards" + tryHelp(cmd));
			for (unsigned p = lo; p <= hi; p++)
				r.list.push_back(p);
		} else {
			r.list.push_back(number(item));
		}
		if (comma == std::string_view::npos)
			break;
		rest = rest.substr(comma + 1);
	}
	std::sort(r.list.begin(), r.list.end());
	r.list.erase(std::unique(r.list.begin(), r.list.end()), r.list.end());
	return r;
}

void checkPositions(const Positions &p, unsigned count)
{
	if (!p.list.empty())
		checkPosition(p.list.back(), count);
}

void checkPosition(unsigned position, unsigned count)
{
	if (gAlias && !gAliasTaken)
		throw UsageError("-a/--alias is not taken by this command: select the slave with -p N");
	if (position < count)
		return;
	std::string msg = "slave position " + std::to_string(position) + " out of range: the bus has " +
			  std::to_string(count) + (count == 1 ? " slave" : " slaves");
	if (count > 0)
		msg.append(" (0..").append(std::to_string(count - 1)).append(")");
	throw ecmxf::Error(msg, ENODEV);
}

// ---------------------------------------------------------------------------
// progress
// ---------------------------------------------------------------------------

Progress::Progress(const Globals &g, std::string what, std::string unit)
	: what_(std::move(what)), unit_(std::move(unit)), t0_(std::chrono::steady_clock::now()), last_(t0_)
{
	tty_ = isatty(STDOUT_FILENO) && isatty(STDERR_FILENO);
	on_ = g.progress || (tty_ && !g.quiet && !g.json);
}

void Progress::operator()(std::size_t done, std::size_t total)
{
	if (!on_ || ended_)
		return;
	const auto now = std::chrono::steady_clock::now();
	const bool end = done >= total;
	if (!end && now - last_ < (tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(1000)))
		return;
	last_ = now;
	const double s = std::chrono::duration<double>(now - t0_).count();
	const double rate = s > 0 ? static_cast<double>(done) / s : 0;
	char line[200];
	int n = std::snprintf(line, sizeof line, "%s: %zu/%zu %s (%zu%%)", what_.c_str(), done, total, unit_.c_str(),
			      total ? done * 100 / total : 100);
	if (rate > 0 && n > 0 && static_cast<std::size_t>(n) < sizeof line)
		n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ", %.1f %s/s", rate, unit_.c_str());
	if (!end && rate > 0 && n > 0 && static_cast<std::size_t>(n) < sizeof line)
		std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ", %.0f s left",
			      static_cast<double>(total - done) / rate);
	// on a terminal the line is redrawn in place (clear to its end)
	std::fprintf(stderr, tty_ ? "\r%s\x1b[K%s" : "%s%s", line, end || !tty_ ? "\n" : "");
	std::fflush(stderr);
	ended_ = end;
}

} // namespace ecmxf_util
