// SPDX-License-Identifier: MIT
/*
 * ecmxf-util raw - one raw ECM-XF command (Device::command), or one raw
 * EtherCAT datagram through RAW_ECAT_FUNC_REQ / RAW_ECAT_FUNC_GET.
 */
#include "ecmxf-util.hpp"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/protocol.hpp>

namespace ecmxf_util {

const char *const kRawHelp =
	"Usage: ecmxf-util [global options] raw CODE [--param P] [--data B0,B1,B2,B3]\n"
	"                                           [--payload HEX] [--len N] [--json]\n"
	"       ecmxf-util [global options] raw --datagram TYPE ADDR LEN [DATA] [--json]\n"
	"\n"
	"Send one command to the chip as it is and print the response header\n"
	"fields (crcErrCnt, wkcErrCnt, txFifoCnt, rxFifoCnt, ecatState, errStatus,\n"
	"ecmStatus, index, code, ret, len, intFlags, gpioIntFlag, gpioIn) and the\n"
	"data section as hex. CODE is a number (decimal or 0x hex) or a name of\n"
	"'ecmxf-util commands' (case-insensitive; ECM_CMD_ and ECAT_ may be left\n"
	"out, e.g. SLV_CNT_GET). An async command is waited for; its header is the\n"
	"one that reported completion. A command the chip refuses fails (exit 1).\n"
	"\n"
	"Options:\n"
	"  --param P            command parameter (header 0x0D), 0..255; default 0\n"
	"  --data B0,B1,B2,B3   parametric data bytes 0..3 (header 0x04..0x07)\n"
	"  --payload HEX        data section bytes, e.g. 0a0b0c or 0a:0b:0c\n"
	"  --len N              the data length field (0x0E); default: payload size\n"
	"  --datagram TYPE ADDR LEN [DATA]\n"
	"                       one EtherCAT datagram: TYPE one of APRD APWR APRW\n"
	"                       FPRD FPWR FPRW BRD BWR BRW LRD LWR LRW ARMW FRMW;\n"
	"                       ADDR is POSITION:REGISTER for AP* and ARMW,\n"
	"                       STATION:REGISTER for FP* and FRMW, REGISTER for B*,\n"
	"                       a 32-bit logical address for L*; LEN bytes (1..256);\n"
	"                       DATA the bytes to write as HEX (default zeros).\n"
	"                       Prints the working counter and the data read.\n"
	"  --json               one JSON object\n"
	"  -h, --help           show this help\n"
	"\n"
	"Example: ecmxf-util raw SLV_INFO_GET --param 0 --data 3\n"
	"         ecmxf-util raw --datagram FPRD 0x1001:0x0130 2\n";

namespace {

std::uint64_t number(std::string_view opt, std::string_view text, std::uint64_t max)
{
	const std::string s(text);
	char *end = nullptr;
	errno = 0;
	const bool ok = !s.empty() && std::isdigit(static_cast<unsigned char>(s[0]));
	const unsigned long long v = ok ? std::strtoull(s.c_str(), &end, 0) : 0;
	if (!ok || errno != 0 || end == nullptr || *end != '\0')
		throw UsageError("raw: " + std::string(opt) + ": '" + s +
				 "' is not a number (decimal or 0x hex)");
	if (v > max)
		throw UsageError("raw: " + std::string(opt) + ": " + s + " is out of range 0.." +
				 std::to_string(max));
	return v;
}

std::vector<std::uint8_t> hexBytes(std::string_view opt, std::string_view text)
{
	std::vector<std::uint8_t> out;
	int nibbles = 0;
	unsigned cur = 0;
	for (const char c : text) {
		if (c == ':' || c == ',' || c == ' ' || c == '-') {
			if (nibbles == 1)
				throw UsageError("raw: " + std::string(opt) + ": '" + std::string(text) +
						 "': odd number of hex digits in a byte");
			continue;
		}
		if (!std::isxdigit(static_cast<unsigned char>(c)))
			throw UsageError("raw: " + std::string(opt) + ": '" + std::string(text) +
					 "' is not hex bytes (e.g. 0a0b0c or 0a:0b:0c)");
		cur = cur << 4 | static_cast<unsigned>(std::isdigit(static_cast<unsigned char>(c))
							       ? c - '0'
							       : std::tolower(static_cast<unsigned char>(c)) - 'a' + 10);
		if (++nibbles == 2) {
			out.push_back(static_cast<std::uint8_t>(cur));
			cur = 0;
			nibbles = 0;
		}
	}
	if (nibbles != 0)
		throw UsageError("raw: " + std::string(opt) + ": '" + std::string(text) +
				 "': odd number of hex digits");
	return out;
}

std::string upper(std::string_view s)
{
	std::string u(s);
	for (char &c : u)
		c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
	return u;
}

std::uint8_t commandCode(std::string_view text)
{
	if (!text.empty() && std::isdigit(static_cast<unsigned char>(text[0])))
		return static_cast<std::uint8_t>(number("CODE", text, 255));
	std::string name = upper(text);
	if (name.starts_with("ECM_CMD_"))
		name.erase(0, 8);
	std::vector<ecmxf::CommandInfo> hits;
	for (std::size_t i = 0; i < ecmxf::commandCount(); i++) {
		const ecmxf::CommandInfo ci = ecmxf::commandAt(i);
		if (ci.name == name)
			return ci.code;
		std::string ecat = "ECAT_";
		ecat.append(name);
		if (ci.name == ecat)
			hits.push_back(ci);
	}
	if (hits.size() == 1)
		return hits.front().code;
	throw UsageError("raw: unknown command '" + std::string(text) +
			 "' (a code 0..255 or a name of 'ecmxf-util commands')");
}

std::string codeName(std::uint8_t code)
{
	const auto ci = ecmxf::commandInfo(code);
	return ci ? std::string(ci->name) : "?";
}

std::string hexString(const std::vector<std::uint8_t> &d)
{
	std::string s;
	char b[4];
	for (const std::uint8_t v : d) {
		std::snprintf(b, sizeof(b), "%02x", v);
		s += b;
	}
	return s;
}

void hexDump(const std::vector<std::uint8_t> &d)
{
	for (std::size_t off = 0; off < d.size(); off += 16) {
		std::printf("  %04zx ", off);
		for (std::size_t i = off; i < off + 16 && i < d.size(); i++)
			std::printf(" %02x", d[i]);
		std::printf("\n");
	}
}

void printHeader(const ecmxf::ResponseHeader &h)
{
	std::printf("crcErrCnt    %u\n", h.crcErrCnt);
	std::printf("wkcErrCnt    %u\n", h.wkcErrCnt);
	std::printf("txFifoCnt    %u\n", h.txFifoCnt);
	std::printf("rxFifoCnt    %u\n", h.rxFifoCnt);
	std::printf("ecatState    0x%02x (%s)\n", h.ecatState, stateName(h.ecatState).c_str());
	std::printf("errStatus    0x%02x\n", h.errStatus);
	std::printf("ecmStatus    0x%02x\n", h.ecmStatus);
	std::printf("index        %u\n", h.index);
	std::printf("code         %u (%s)\n", h.code, codeName(h.code).c_str());
	std::printf("ret          %u (0x%02x)\n", h.ret, h.ret);
	std::printf("len          %u\n", h.len);
	std::printf("intFlags     0x%08x\n", h.intFlags);
	std::printf("gpioIntFlag  0x%02x 0x%02x\n", h.gpioIntFlag[0], h.gpioIntFlag[1]);
	std::printf("gpioIn       0x%02x 0x%02x\n", h.gpioIn[0], h.gpioIn[1]);
}

std::string headerJson(const ecmxf::ResponseHeader &h)
{
	char b[512];
	std::snprintf(b, sizeof(b),
		      "{\"crcErrCnt\": %u, \"wkcErrCnt\": %u, \"txFifoCnt\": %u, \"rxFifoCnt\": %u, "
		      "\"ecatState\": %u, \"ecatStateName\": \"%s\", \"errStatus\": %u, "
		      "\"ecmStatus\": %u, \"index\": %u, \"code\": %u, \"name\": \"%s\", \"ret\": %u, "
		      "\"len\": %u, \"intFlags\": %u, \"gpioIntFlag\": [%u, %u], \"gpioIn\": [%u, %u]}",
		      h.crcErrCnt, h.wkcErrCnt, h.txFifoCnt, h.rxFifoCnt, h.ecatState,
		      stateName(h.ecatState).c_str(), h.errStatus, h.ecmStatus, h.index, h.code,
		      codeName(h.code).c_str(), h.ret, h.len, h.intFlags, h.gpioIntFlag[0],
		      h.gpioIntFlag[1], h.gpioIn[0], h.gpioIn[1]);
	return b;
}

// EtherCAT datagram command types (ETG.1000.4)
struct DatagramType {
	const char *name;
	std::uint8_t op;
};
constexpr DatagramType kDatagramTypes[] = {
	{ "APRD", 1 }, { "APWR", 2 },  { "APRW", 3 },  { "FPRD", 4 },  { "FPWR", 5 },
	{ "FPRW", 6 }, { "BRD", 7 },   { "BWR", 8 },   { "BRW", 9 },   { "LRD", 10 },
	{ "LWR", 11 }, { "LRW", 12 },  { "ARMW", 13 }, { "FRMW", 14 },
};

constexpr std::uint8_t kRawEcatFuncReq = ECMXF_CMD_RAW_ECAT_FUNC_REQ;
constexpr std::uint8_t kErrCmd = ECMXF_ERR_CMD; // error status bit 7
constexpr std::uint8_t kRawEcatFuncGet = ECMXF_CMD_RAW_ECAT_FUNC_GET;
constexpr std::uint32_t kDatagramTimeoutUs = 10'000;

void put16(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	d.push_back(static_cast<std::uint8_t>(v));
	d.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	put16(d, v);
	put16(d, v >> 16);
}

int runDatagram(Globals &g, const std::vector<std::string_view> &pos)
{
	if (pos.size() < 3 || pos.size() > 4)
		throw UsageError("raw: --datagram needs TYPE ADDR LEN [DATA] (try 'ecmxf-util raw --help')");
	const std::string type = upper(pos[0]);
	const DatagramType *dt = nullptr;
	for (const DatagramType &t : kDatagramTypes)
		if (type == t.name)
			dt = &t;
	if (!dt)
		throw UsageError("raw: --datagram: unknown type '" + std::string(pos[0]) +
				 "' (APRD APWR APRW FPRD FPWR FPRW BRD BWR BRW LRD LWR LRW ARMW FRMW)");
	const std::string_view addr = pos[1];
	std::uint16_t adp = 0, ado = 0;
	std::uint32_t logical = 0;
	const bool isLogical = type[0] == 'L';
	const bool isBroadcast = type[0] == 'B';
	const bool isPosition = type[0] == 'A';
	if (isLogical) {
		logical = static_cast<std::uint32_t>(number("ADDR", addr, 0xFFFFFFFF));
	} else if (isBroadcast && addr.find(':') == std::string_view::npos) {
		ado = static_cast<std::uint16_t>(number("ADDR", addr, 0xFFFF));
	} else {
		const std::size_t colon = addr.find(':');
		if (colon == std::string_view::npos)
			throw UsageError("raw: --datagram " + type + ": ADDR '" + std::string(addr) + "' must be " +
					 (isPosition ? "POSITION" : "STATION") + ":REGISTER");
		const auto a = number("ADDR", addr.substr(0, colon), isPosition ? 0x7FFF : 0xFFFF);
		ado = static_cast<std::uint16_t>(number("ADDR", addr.substr(colon + 1), 0xFFFF));
		adp = static_cast<std::uint16_t>(isPosition ? (0x10000 - a) & 0xFFFF : a);
	}
	const auto len = static_cast<std::uint16_t>(number("LEN", pos[2], 256));
	if (len == 0)
		throw UsageError("raw: --datagram: LEN 0 is out of range 1..256");
	std::vector<std::uint8_t> data(len, 0);
	if (pos.size() == 4) {
		const std::vector<std::uint8_t> w = hexBytes("DATA", pos[3]);
		if (w.size() != len)
			throw UsageError("raw: --datagram: DATA has " + std::to_string(w.size()) +
					 " bytes, LEN says " + std::to_string(len));
		data = w;
	}

	ecmxf::Command c = simpleCommand(kRawEcatFuncReq);
	c.payload = { dt->op, 0 };
	put16(c.payload, len);
	put16(c.payload, adp);
	put16(c.payload, ado);
	put32(c.payload, logical);
	put32(c.payload, kDatagramTimeoutUs);
	put32(c.payload, 0);
	c.payload.insert(c.payload.end(), data.begin(), data.end());

	const DevicePtr dev = openDevice(g);
	dev->command(c);
	const ecmxf::Response r = dev->command(simpleCommand(kRawEcatFuncGet));
	if (r.data.size() < 20)
		throw std::runtime_error("RAW_ECAT_FUNC_GET: answer of " + std::to_string(r.data.size()) +
					 " bytes, expected at least 20");
	const auto wkc = static_cast<unsigned>(r.data[16] | r.data[17] << 8);
	const std::vector<std::uint8_t> rd(r.data.begin() + 20, r.data.end());
	if (g.json) {
		std::printf("{\"type\": \"%s\", \"adp\": %u, \"ado\": %u, \"logical\": %u, \"length\": %u, "
			    "\"wkc\": %u, \"data\": \"%s\"}\n",
			    dt->name, adp, ado, logical, len, wkc, hexString(rd).c_str());
		return 0;
	}
	if (isLogical)
		std::printf("%s 0x%08x, %u bytes: working counter %u\n", dt->name, logical, len, wkc);
	else
		std::printf("%s ADP 0x%04x ADO 0x%04x, %u bytes: working counter %u\n", dt->name, adp, ado,
			    len, wkc);
	hexDump(rd);
	return 0;
}

} // namespace

int cmdRaw(Globals &g, const Args &args)
{
	std::vector<std::string_view> positional;
	std::optional<std::uint8_t> param;
	std::optional<std::vector<std::uint8_t>> data, payload;
	std::optional<std::uint16_t> len;
	bool datagram = false;
	for (std::size_t i = 0; i < args.size(); i++) {
		const std::string_view a = args[i];
		auto value = [&]() -> std::string_view {
			if (i + 1 >= args.size())
				throw UsageError("raw: option '" + std::string(a) + "' needs a value");
			return args[++i];
		};
		if (a == "-h" || a == "--help") {
			std::fputs(kRawHelp, stdout);
			return 0;
		}
		if (a == "--json") {
			g.json = true;
		} else if (a == "--param") {
			param = static_cast<std::uint8_t>(number("--param", value(), 255));
		} else if (a == "--data") {
			const std::string_view v = value();
			std::vector<std::uint8_t> d;
			std::size_t start = 0;
			while (true) {
				const std::size_t comma = v.find(',', start);
				d.push_back(static_cast<std::uint8_t>(
					number("--data", v.substr(start, comma - start), 255)));
				if (comma == std::string_view::npos)
					break;
				start = comma + 1;
			}
			if (d.size() > 4)
				throw UsageError("raw: --data: " + std::to_string(d.size()) +
						 " bytes, at most 4 (B0,B1,B2,B3)");
			data = d;
		} else if (a == "--payload") {
			payload = hexBytes("--payload", value());
		} else if (a == "--len") {
			len = static_cast<std::uint16_t>(number("--len", value(), 0xFFFF));
		} else if (a == "--datagram") {
			datagram = true;
		} else if (a.size() > 1 && a[0] == '-') {
			throw UsageError("raw: unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util raw --help')");
		} else {
			positional.push_back(a);
		}
	}
	if (datagram) {
		if (param || data || payload || len)
			throw UsageError("raw: --datagram takes no --param, --data, --payload or --len");
		return runDatagram(g, positional);
	}
	if (positional.size() != 1)
		throw UsageError(positional.empty() ? "raw: missing CODE (try 'ecmxf-util raw --help')"
						    : "raw: one CODE only, got '" + std::string(positional[1]) + "'");

	ecmxf::Command c = simpleCommand(commandCode(positional[0]), param.value_or(0));
	if (data)
		for (std::size_t i = 0; i < data->size(); i++)
			c.data[i] = (*data)[i];
	if (payload)
		c.payload = *payload;
	c.len = len;

	const DevicePtr dev = openDevice(g);
	// The command error bit is sticky: look at it before, so that only a
	// refusal of this command counts.
	const bool cmdErrBefore = c.code != 0 && (dev->command(simpleCommand(0)).header.errStatus & kErrCmd);
	const ecmxf::Response r = dev->command(c);
	if (g.json) {
		std::printf("{\"header\": %s, \"data\": \"%s\"}\n", headerJson(r.header).c_str(),
			    hexString(r.data).c_str());
	} else {
		printHeader(r.header);
		if (r.data.empty()) {
			std::printf("data         -\n");
		} else {
			std::printf("data         %zu bytes\n", r.data.size());
			hexDump(r.data);
		}
	}
	if (!cmdErrBefore && (r.header.errStatus & kErrCmd)) {
		std::fflush(stdout);
		throw std::runtime_error("raw: " + codeName(c.code) +
					 ": the chip refused the command (error status bit 7, command error)");
	}
	return 0;
}

} // namespace ecmxf_util
