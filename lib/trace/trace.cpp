// SPDX-License-Identifier: MIT
// Packet traces: the decoder decodeTrace() (include/ecmxf/trace/trace.hpp,
// Documentation/trace.rst). The writer is lib/link/trace_writer.cpp.

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/model/status.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/trace/trace.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cinttypes>
#include <cstdarg>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <istream>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "ecmsk-proto.h"
#include "ecmxf-proto.h"
#include "link/trace_writer.hpp"
#include "trace/trace_reader.hpp"

namespace ecmxf {

// ===========================================================================
// Decoder
// ===========================================================================

namespace {

std::string fmt(const char *f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char *f, ...)
{
	char buf[256];
	va_list ap;
	va_start(ap, f);
	const int n = std::vsnprintf(buf, sizeof(buf), f, ap);
	va_end(ap);
	return n < 0 ? std::string() : std::string(buf, std::min<std::size_t>(static_cast<std::size_t>(n), sizeof(buf) - 1));
}

/// "a, b, bit 9" for the set bits of @p v (the core's names of @p field,
/// lib/core/ecmxf-bits.c; bits without one by number).
std::string bitNames(std::uint32_t v, ecmxf_bits_field field, std::uint32_t ignore = 0)
{
	std::size_t count = 0;
	const ecmxf_bit_name *table = ecmxf_bit_names(field, &count);
	std::string out;
	for (unsigned b = 0; b < 32; b++) {
		if (!(v & (1u << b)) || (ignore & (1u << b)))
			continue;
		if (!out.empty())
			out += ", ";
		const char *name = nullptr;
		for (std::size_t i = 0; i < count; i++)
			if (table[i].bit == b)
				name = table[i].name;
		out += name ? std::string(name) : "bit " + std::to_string(b);
	}
	return out;
}

/// " (names)" or "" when no bit is set.
std::string withBits(std::uint32_t v, ecmxf_bits_field field)
{
	const std::string n = bitNames(v, field);
	return n.empty() ? std::string() : " (" + n + ")";
}

std::string cmdName(unsigned code)
{
	const auto info = commandInfo(static_cast<std::uint8_t>(code));
	return info ? std::string(info->name) : std::string("unknown command");
}

const char *checkName(unsigned check)
{
	switch (check) {
	case ECMXF_CHECK_FIXED:
		return "fixed";
	case ECMXF_CHECK_CRC8:
		return "CRC-8";
	case ECMXF_CHECK_CCITT:
		return "CRC-CCITT";
	default:
		return "CRC-32";
	}
}

/// The header's ECAT state: ecatStateName()'s words (the one table of
/// state names) and the byte.
std::string stateName(std::uint8_t s)
{
	const std::string name = ecatStateName(s);
	if (name.rfind("unknown", 0) == 0)
		return name;
	return fmt("%s (0x%02X)", name.c_str(), s);
}

const char *statusName(int status)
{
	switch (-status) {
	case 0:
		return "OK";
	case ETIMEDOUT:
		return "ETIMEDOUT (no answer or no completion in time)";
	case EBUSY:
		return "EBUSY (the chip refused: async command running)";
	case EREMOTEIO:
		return "EREMOTEIO (async command failed)";
	case EBADMSG:
		return "EBADMSG (retries exhausted: check word)";
	case EPROTO:
		return "EPROTO (retries exhausted: framing)";
	case EIO:
		return "EIO (retries exhausted: not ready)";
	case ECONNRESET:
		return "ECONNRESET (the chip reset)";
	case EMSGSIZE:
		return "EMSGSIZE (answer larger than the buffer)";
	case ECANCELED:
		return "ECANCELED (cancelled by a reset)";
	default:
		return "error";
	}
}

std::uint16_t le16(const std::uint8_t *p)
{
	return static_cast<std::uint16_t>(p[0] | p[1] << 8);
}

std::uint32_t le32(const std::uint8_t *p)
{
	return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
	       static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

std::string timeText(std::uint64_t ns)
{
	return fmt("%" PRIu64 ".%09" PRIu64, ns / 1'000'000'000u, ns % 1'000'000'000u);
}

std::string hexBytes(const std::uint8_t *p, std::size_t n)
{
	std::string s;
	for (std::size_t i = 0; i < n; i++)
		s += fmt(i ? " %02X" : "%02X", p[i]);
	return s;
}

std::string jsonHex(const std::uint8_t *p, std::size_t n)
{
	std::string s = "\"";
	for (std::size_t i = 0; i < n; i++)
		s += fmt("%02x", p[i]);
	return s + "\"";
}

using Record = detail::TraceRecord;

/// The decoder's view of the link, followed across the format commands.
class Decoder
{
public:
	Decoder(std::ostream &out, const TraceDecodeOptions &o) : out_(out), o_(o) {}

	void format(unsigned dataSize, unsigned check)
	{
		dataSize_ = dataSize;
		check_ = prevCheck_ = check;
	}
	void record(const Record &r);
	void finish()
	{
		if (o_.json)
			out_ << (first_ ? "[]\n" : "\n]\n");
	}
	TraceSummary summary;

private:
	struct Verdict {
		bool ok = false;
		bool notReady = false;
		std::string text;       ///< "check word 0x...: OK (fixed)"
		std::string json;       ///< "ok", "bad_check", ...
		unsigned checkUsed = 0; ///< the type that matched (ok)
	};
	Verdict verify(const std::vector<std::uint8_t> &p, bool command);
	void mosi(const Record &r);
	void miso(const Record &r);
	void skFrame(const Record &r);
	void kernel(const Record &r);
	void header(const Record &r, const std::string &title);
	void dataLines(const std::uint8_t *p, std::size_t n, std::size_t total);
	void cmdFields(const std::uint8_t *h, const std::uint8_t *data, std::size_t n, bool kernel);
	void rspFields(const std::uint8_t *h, const std::uint8_t *data, std::size_t n, std::size_t dataSize);
	void jsonBegin(const Record &r, const char *dir);
	void jsonField(const std::string &key, const std::string &value) { json_ += ", \"" + key + "\": " + value; }
	/// A field whose value is a JSON string (no character in it needs
	/// escaping: command names, check word names).
	void jsonText(const std::string &key, std::string_view text)
	{
		json_.append(", \"").append(key).append("\": \"").append(text).append("\"");
	}
	void jsonEnd();

	std::ostream &out_;
	TraceDecodeOptions o_;
	std::optional<unsigned> dataSize_;
	std::optional<unsigned> pendingSize_; ///< SPI_RECONFIG_OP / WARM_RESET: size from the next exchange
	unsigned check_ = ECMXF_CHECK_FIXED;
	unsigned prevCheck_ = ECMXF_CHECK_FIXED;
	std::size_t exchange_ = 0;
	bool lastWasMosi = false;
	std::optional<std::pair<std::uint8_t, std::uint8_t>> lastSent_; ///< (index, code) of the last MOSI
	std::map<std::pair<std::uint8_t, std::uint8_t>, std::size_t> sent_; ///< (index, code) -> exchange
	/// index -> (exchange, code) of the latest re-send with that index
	std::map<std::uint8_t, std::pair<std::size_t, std::uint8_t>> resent_;
	std::size_t kernelReq_ = 0;
	std::string kernelReqName_;
	bool first_ = true;
	std::string json_;
};

void Decoder::header(const Record &r, const std::string &title)
{
	out_ << '#' << exchange_ << ' ' << timeText(r.ns) << ' ' << title << '\n';
}

void Decoder::dataLines(const std::uint8_t *p, std::size_t n, std::size_t total)
{
	if (o_.json) {
		jsonField("data", jsonHex(p, n));
		return;
	}
	if (n == 0)
		return;
	out_ << "    data (" << n << " of " << total << " bytes):\n";
	const std::size_t per = std::max<std::size_t>(o_.bytesPerLine, 1);
	for (std::size_t i = 0; i < n; i += per)
		out_ << fmt("      %04zx: ", i) << hexBytes(p + i, std::min(per, n - i)) << '\n';
}

void Decoder::jsonBegin(const Record &r, const char *dir)
{
	json_ = fmt("{\"n\": %zu, \"line\": %zu, \"time\": \"%s\", \"time_ns\": %" PRIu64 ", \"dir\": \"%s\"",
		    exchange_, r.line, timeText(r.ns).c_str(), r.ns, dir);
}

void Decoder::jsonEnd()
{
	out_ << (first_ ? "[\n  " : ",\n  ") << json_ << '}';
	first_ = false;
}

Decoder::Verdict Decoder::verify(const std::vector<std::uint8_t> &p, bool command)
{
	Verdict v;
	const std::size_t n = p.size() - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	const std::uint32_t word = le32(p.data() + ECMXF_HDR_SIZE + n);
	const std::uint32_t start = le32(p.data());
	const std::uint32_t end = le32(p.data() + ECMXF_HDR_SIZE + n + 4);
	if (!command && word == ECMXF_NOT_READY_WORD) {
		v.notReady = true;
		v.json = "not_ready";
		v.text = "check word 0x87654321: NOT READY (the chip had not processed the previous packet)";
		return v;
	}
	if (start != ECMXF_START_WORD) {
		v.json = "bad_start";
		v.text = fmt("start word 0x%08X: BAD (expected 0xA1A2A3A4)", start);
		return v;
	}
	if (end != ECMXF_END_WORD) {
		v.json = "bad_end";
		v.text = fmt("end word 0x%08X: BAD (expected 0x56575859)", end);
		return v;
	}
	// the type in force, then the ones that may still be legitimately
	// in use: the type before a CRC_TYPE_SET, fixed for SPI_RECONFIG_OP
	const unsigned expected = check_;
	std::vector<std::pair<unsigned, const char *>> tries = { { expected, "" } };
	if (command && p[0x0C] == ECMXF_CMD_SPI_RECONFIG_OP && expected != ECMXF_CHECK_FIXED)
		tries.insert(tries.begin(), { ECMXF_CHECK_FIXED, ", as SPI_RECONFIG_OP is sent" });
	if (prevCheck_ != expected)
		tries.emplace_back(prevCheck_, ", the type before CRC_TYPE_SET");
	for (const auto &[type, why] : tries) {
		if (word == ecmxf_check_word(static_cast<ecmxf_check>(type), p.data(), ECMXF_HDR_SIZE + n)) {
			v.ok = true;
			v.checkUsed = type;
			v.json = "ok";
			v.text = fmt("check word 0x%08X: OK (%s%s)", word, checkName(type), why);
			break;
		}
	}
	if (!v.ok) {
		const std::uint32_t want = ecmxf_check_word(static_cast<ecmxf_check>(expected), p.data(), ECMXF_HDR_SIZE + n);
		v.json = "bad_check";
		v.text = fmt("check word 0x%08X: BAD (%s expected 0x%08X, got 0x%08X)", word, checkName(expected), want,
			     word);
		return v;
	}
	if (!command && le16(p.data() + 0x0E) > n) {
		v.ok = false;
		v.json = "bad_length";
		v.text = fmt("len %u: BAD (longer than the %zu-byte data section)", le16(p.data() + 0x0E), n);
	}
	return v;
}

void Decoder::cmdFields(const std::uint8_t *h, const std::uint8_t *data, std::size_t n, bool kernel)
{
	// h points at packet byte 0x04 (the header fields)
	const unsigned code = h[8], param = h[9], control = h[6];
	const unsigned reserved = le16(h + 4), len = le16(h + 10);
	const std::uint32_t intClear = le32(h + 12);
	// data shown: the length field's worth, and any non-zero byte after it
	std::size_t shown = len <= n ? len : 0;
	for (std::size_t i = n; i > shown; i--)
		if (data[i - 1]) {
			shown = i;
			break;
		}
	if (o_.json) {
		jsonField("code", std::to_string(code));
		jsonText("name", cmdName(code));
		if (!kernel)
			jsonField("index", std::to_string(h[7]));
		jsonField("param", std::to_string(param));
		jsonField("len", std::to_string(len));
		jsonField("cmd_data", fmt("[%u, %u, %u, %u]", h[0], h[1], h[2], h[3]));
		jsonField("reserved", std::to_string(reserved));
		jsonField("control", std::to_string(control));
		jsonField("int_clear", std::to_string(intClear));
		jsonField("gpio_int_clear", fmt("[%u, %u]", h[16], h[17]));
		jsonField("gpio_out", fmt("[%u, %u]", h[18], h[19]));
		dataLines(data, shown, n);
		return;
	}
	out_ << fmt("    param 0x%02X, len %u, data %02X %02X %02X %02X, reserved 0x%04X", param, len, h[0], h[1],
		    h[2], h[3], reserved)
	     << withBits(reserved, ECMXF_BITS_RESERVED) << '\n';
	out_ << fmt("    control 0x%02X", control) << withBits(control, ECMXF_BITS_CONTROL)
	     << fmt(", int clear 0x%08X", intClear) << withBits(intClear, ECMXF_BITS_INT)
	     << fmt(", GPIO int clear 0x%02X 0x%02X, GPIO out 0x%02X 0x%02X", h[16], h[17], h[18], h[19]) << '\n';
	dataLines(data, shown, n);
}

void Decoder::rspFields(const std::uint8_t *h, const std::uint8_t *data, std::size_t n, std::size_t dataSize)
{
	const unsigned ecm = h[6], err = h[5], len = le16(h + 10);
	const std::uint32_t intFlags = le32(h + 12);
	const std::size_t shown = std::min<std::size_t>(len, n);
	if (o_.json) {
		jsonField("index", std::to_string(h[7]));
		jsonField("code", std::to_string(h[8]));
		jsonText("name", cmdName(h[8]));
		jsonField("ret", std::to_string(h[9]));
		jsonField("len", std::to_string(len));
		jsonField("crc_err_cnt", std::to_string(h[0]));
		jsonField("wkc_err_cnt", std::to_string(h[1]));
		jsonField("tx_fifo_cnt", std::to_string(h[2]));
		jsonField("rx_fifo_cnt", std::to_string(h[3]));
		jsonField("ecat_state", std::to_string(h[4]));
		jsonField("err_status", std::to_string(err));
		jsonField("ecm_status", std::to_string(ecm));
		jsonField("int_flags", std::to_string(intFlags));
		jsonField("gpio_int_flag", fmt("[%u, %u]", h[16], h[17]));
		jsonField("gpio_in", fmt("[%u, %u]", h[18], h[19]));
		dataLines(data, shown, dataSize);
		return;
	}
	const std::string ecmBits = bitNames(ecm, ECMXF_BITS_ECM_STATUS, ECMXF_STS_CHECK_MASK);
	out_ << "    ECAT state " << stateName(h[4]) << fmt(", error status 0x%02X", err)
	     << withBits(err, ECMXF_BITS_ERR_STATUS)
	     << fmt(", ECM status 0x%02X (check %s", ecm, checkName(ecm & ECMXF_STS_CHECK_MASK))
	     << (ecmBits.empty() ? "" : ", " + ecmBits) << ")\n";
	out_ << fmt("    CRC errors %u, WKC errors %u, TxFIFO %u, RxFIFO %u\n", h[0], h[1], h[2], h[3]);
	out_ << fmt("    index 0x%02X, code 0x%02X %s, ret 0x%02X (%u), len %u\n", h[7], h[8], cmdName(h[8]).c_str(),
		    h[9], h[9], len);
	out_ << fmt("    int flags 0x%08X", intFlags) << withBits(intFlags, ECMXF_BITS_INT)
	     << fmt(", GPIO int flags 0x%02X 0x%02X, GPIO in 0x%02X 0x%02X\n", h[16], h[17], h[18], h[19]);
	dataLines(data, shown, dataSize);
}

void Decoder::mosi(const Record &r)
{
	const std::vector<std::uint8_t> &p = r.bytes;
	const std::size_t n = p.size() - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	exchange_++;
	summary.commands++;
	std::string sizeNote;
	if (dataSize_ && *dataSize_ != n)
		sizeNote = fmt(" (expected %zu: data section %u)", static_cast<std::size_t>(ECMXF_PKT_SIZE(*dataSize_)),
			       *dataSize_);
	dataSize_ = static_cast<unsigned>(n);

	const Verdict v = verify(p, true);
	if (!v.ok)
		summary.bad++;
	const std::uint8_t index = p[0x0B], code = p[0x0C];
	const std::pair<std::uint8_t, std::uint8_t> key{ index, code };
	const bool resend = lastSent_ && *lastSent_ == key;
	std::string title = fmt("host>chip %zu bytes%s: %s (0x%02X), index 0x%02X", p.size(), sizeNote.c_str(),
				cmdName(code).c_str(), code, index);
	if (resend)
		title += fmt(" (re-send of #%zu: the chip answers it as INFO_UPDATE_OP)", sent_[key]);
	if (!v.ok)
		title += " [BAD]";
	if (o_.json) {
		jsonBegin(r, "mosi");
		jsonField("size", std::to_string(p.size()));
		jsonText("check", v.json);
		jsonField("resend", resend ? "true" : "false");
		cmdFields(p.data() + 4, p.data() + ECMXF_HDR_SIZE, n, false);
		jsonEnd();
	} else {
		header(r, title);
		cmdFields(p.data() + 4, p.data() + ECMXF_HDR_SIZE, n, false);
		out_ << "    " << v.text << '\n';
	}
	if (!v.ok)
		return; // the chip drops a bad command
	lastSent_ = key;
	if (resend) {
		resent_[index] = { exchange_, code };
		return;
	}
	sent_[key] = exchange_;
	resent_.erase(index);
	// the format changes the chip makes after taking the command in
	switch (code) {
	case ECMXF_CMD_CRC_TYPE_SET:
		if (p[0x0D] <= ECMXF_CHECK_CRC32) {
			prevCheck_ = check_;
			check_ = p[0x0D];
		}
		break;
	case ECMXF_CMD_SPI_RECONFIG_OP:
		if (ecmxf_data_size_valid(le16(p.data() + 0x0E)))
			pendingSize_ = le16(p.data() + 0x0E);
		break;
	case ECMXF_CMD_WARM_RESET:
		pendingSize_ = ECMXF_DATA_DEFAULT;
		prevCheck_ = check_;
		check_ = ECMXF_CHECK_FIXED;
		break;
	default:
		break;
	}
}

void Decoder::miso(const Record &r)
{
	const std::vector<std::uint8_t> &p = r.bytes;
	const std::size_t n = p.size() - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	summary.responses++;
	if (!lastWasMosi)
		exchange_++; // a MISO packet without its MOSI
	const Verdict v = verify(p, false);
	if (!v.ok)
		summary.bad++;
	if (v.notReady)
		summary.notReady++;
	if (v.ok && v.checkUsed == check_)
		prevCheck_ = check_; // the chip speaks the new type

	std::string what;
	std::string answers = "null";
	const std::uint8_t ecm = p[0x0A], index = p[0x0B], code = p[0x0C];
	if (v.notReady) {
		what = "not ready";
	} else if (ecm & ECMXF_STS_NOP) {
		what = "answers nothing (NOP: the chip's first answer after power-on or reset)";
	} else {
		const auto it = sent_.find({ index, code });
		const auto re = resent_.find(index);
		if (code == ECMXF_CMD_INFO_UPDATE_OP && re != resent_.end()) {
			what = fmt("answers #%zu, the re-send of %s (0x%02X) with index 0x%02X, run as INFO_UPDATE_OP",
				   re->second.first, cmdName(re->second.second).c_str(), re->second.second, index);
			answers = std::to_string(re->second.first);
		} else if (it != sent_.end()) {
			what = fmt("answers #%zu %s (0x%02X), index 0x%02X", it->second, cmdName(code).c_str(), code, index);
			answers = std::to_string(it->second);
		} else {
			what = fmt("answers %s (0x%02X), index 0x%02X (not sent in this trace)", cmdName(code).c_str(), code,
				   index);
		}
		if (ecm & ECMXF_STS_BUSY)
			what += "; async command running";
	}
	if (!v.ok && !v.notReady)
		what += " [BAD]";
	if (o_.json) {
		jsonBegin(r, "miso");
		jsonField("size", std::to_string(p.size()));
		jsonText("check", v.json);
		jsonField("answers", answers);
		jsonField("nop", (ecm & ECMXF_STS_NOP) && !v.notReady ? "true" : "false");
		if (!v.notReady)
			rspFields(p.data() + 4, p.data() + ECMXF_HDR_SIZE, n, n);
		jsonEnd();
	} else {
		header(r, fmt("chip>host %zu bytes: ", p.size()) + what);
		if (!v.notReady)
			rspFields(p.data() + 4, p.data() + ECMXF_HDR_SIZE, n, n);
		out_ << "    " << v.text << '\n';
	}
	// the packet size the command of this exchange switched to
	if (pendingSize_) {
		dataSize_ = *pendingSize_;
		pendingSize_.reset();
		if (!o_.json)
			out_ << "    (from the next exchange on: data section " << *dataSize_ << " bytes, packets of "
			     << ECMXF_PKT_SIZE(*dataSize_) << " bytes)\n";
	}
}

void Decoder::kernel(const Record &r)
{
	const std::vector<std::uint8_t> &b = r.bytes;
	const std::size_t n = b.size() - 20;
	if (r.kind == 'C') {
		exchange_++;
		kernelReq_ = exchange_;
		summary.commands++;
		kernelReqName_ = cmdName(b[8]);
		if (o_.json) {
			jsonBegin(r, "request");
			cmdFields(b.data(), b.data() + 20, n, true);
			jsonEnd();
		} else {
			header(r, fmt("request: %s (0x%02X)", kernelReqName_.c_str(), b[8]));
			cmdFields(b.data(), b.data() + 20, n, true);
		}
		return;
	}
	summary.responses++;
	if (o_.json) {
		jsonBegin(r, "response");
		jsonField("status", std::to_string(r.status));
		jsonField("answers", kernelReq_ ? std::to_string(kernelReq_) : "null");
		rspFields(b.data(), b.data() + 20, n, n);
		jsonEnd();
		return;
	}
	std::string title = fmt("response: status %d %s", r.status, statusName(r.status));
	if (kernelReq_)
		title += fmt(", answers #%zu %s", kernelReq_, kernelReqName_.c_str());
	header(r, title);
	rspFields(b.data(), b.data() + 20, n, n);
}

/// The name of slot 0's or a slave slot's command byte: the core's
/// (ecmsk_cmd_name(), "?" for an unknown one); in a response's slot 0
/// ECMSK_RSP_OP is "OP" (the board's byte 0 in OP).
std::string skCmdName(unsigned cmd, bool answer)
{
	if (answer && cmd == ECMSK_RSP_OP)
		return "OP";
	return ecmsk_cmd_name(static_cast<std::uint16_t>(cmd));
}

void Decoder::skFrame(const Record &r)
{
	const std::vector<std::uint8_t> &f = r.bytes;
	const bool cmd = r.kind == '>';
	if (cmd || !lastWasMosi)
		exchange_++;
	(cmd ? summary.commands : summary.responses)++;
	summary.skFrames++;
	ecmsk_geom g{};
	ecmsk_geom_init(&g, r.slotSize);
	const std::uint8_t crcByte = f[ECMSK_CRC_OFFSET];
	const std::uint8_t crcWant = ecmsk_crc8(f.data(), f.size());
	const bool checked = r.skCrcChecked();
	const bool bad = checked && crcByte != crcWant;
	if (bad)
		summary.bad++;
	const char *crcJson = !checked ? "none" : bad ? "bad" : "ok";
	std::string crcText = fmt("CRC-8 (byte 3) 0x%02X: ", crcByte);
	if (!checked)
		crcText += fmt("not checked (%s)", detail::skCrcKeyword(r.skCrc));
	else if (bad)
		crcText += fmt("BAD (expected 0x%02X, got 0x%02X)", crcWant, crcByte);
	else
		crcText += "OK";

	// slot 0: a command's Cmd ID is bytes 0-1; an answer's byte 0, then the
	// CRC error counter and the state
	const unsigned code = cmd ? le16(f.data()) : f[0];
	const std::string name = skCmdName(code, !cmd);
	const std::uint32_t d1 = le32(f.data() + 4), d2 = le32(f.data() + 8);
	const bool wide = g.slot_size == ECMSK_SLOT16;
	const std::uint32_t d3 = wide ? le32(f.data() + 12) : 0;
	const std::uint8_t *sdo = f.data() + static_cast<std::size_t>(g.sdo_slot) * g.slot_size;

	if (o_.json) {
		jsonBegin(r, cmd ? "mosi" : "miso");
		jsonField("sk", "true");
		jsonField("size", std::to_string(f.size()));
		jsonField("slot_size", std::to_string(g.slot_size));
		jsonText("crc", crcJson);
		jsonField("crc_byte", std::to_string(crcByte));
		jsonField("crc_expected", std::to_string(crcWant));
		jsonField("cmd", std::to_string(code));
		jsonText("name", name);
		if (cmd) {
			jsonField("param", std::to_string(f[2]));
		} else {
			jsonField("crc_errors", std::to_string(f[1]));
			jsonField("state", std::to_string(f[2]));
		}
		jsonField("data1", std::to_string(d1));
		jsonField("data2", std::to_string(d2));
		if (wide)
			jsonField("data3", std::to_string(d3));
	} else {
		std::string title = fmt("%s %zu bytes (%u-byte slots): ", cmd ? "host>board" : "board>host", f.size(),
					g.slot_size);
		title += cmd ? fmt("%s (0x%04X)", name.c_str(), code)
			     : fmt("%s (0x%02X), state %s", name.c_str(), code, stateName(f[2]).c_str());
		if (bad)
			title += " [BAD]";
		header(r, title);
		out_ << "    " << crcText << '\n';
		out_ << "    slot 0 (ECM): "
		     << (cmd ? fmt("%s (0x%04X), param 0x%02X", name.c_str(), code, f[2])
			     : fmt("%s (0x%02X), CRC errors %u, state %s", name.c_str(), code, f[1],
				   stateName(f[2]).c_str()))
		     << fmt(", data1 0x%08X, data2 0x%08X", d1, d2) << (wide ? fmt(", data3 0x%08X", d3) : "") << '\n';
	}
	// the slave slots that are not all zero
	std::string slaves;
	for (unsigned slot = 1; slot <= g.max_slaves; slot++) {
		const std::uint8_t *p = f.data() + static_cast<std::size_t>(slot) * g.slot_size;
		if (std::all_of(p, p + g.slot_size, [](std::uint8_t b) { return b == 0; }))
			continue;
		const std::string sname = ecmsk_cmd_name(p[0]);
		const std::uint32_t target = le32(p + 4), value = le32(p + 8);
		if (o_.json) {
			slaves += fmt("%s{\"slot\": %u, \"slave\": %u, \"cmd\": %u, \"name\": \"%s\", \"index\": %u, "
				      "\"target\": %u, \"value\": %u",
				      slaves.empty() ? "" : ", ", slot, slot - 1, p[0], sname.c_str(), p[1], target, value);
			if (!cmd)
				slaves += fmt(", \"statusword\": %u", le16(p + 2));
			slaves += "}";
		} else if (cmd) {
			out_ << fmt("    slot %u (slave %u): %s (0x%02X), index 0x%02X, target 0x%08X, value 0x%08X\n", slot,
				    slot - 1, sname.c_str(), p[0], p[1], target, value);
		} else {
			out_ << fmt("    slot %u (slave %u): %s (0x%02X), index 0x%02X, statusword 0x%04X, position "
				    "0x%08X, torque 0x%04X, error code 0x%04X\n",
				    slot, slot - 1, sname.c_str(), p[0], p[1], le16(p + 2), target, le16(p + 8),
				    le16(p + 10));
		}
	}
	if (o_.json) {
		jsonField("slaves", "[" + slaves + "]");
		jsonField("sdo", jsonHex(sdo, g.slot_size));
		jsonEnd();
		return;
	}
	out_ << fmt("    slot %u (SDO): ", g.sdo_slot) << hexBytes(sdo, g.slot_size) << '\n';
}

void Decoder::record(const Record &r)
{
	summary.packets++;
	if (r.sk) {
		skFrame(r);
		lastWasMosi = r.kind == '>';
		return;
	}
	switch (r.kind) {
	case '>':
		mosi(r);
		lastWasMosi = true;
		return;
	case '<':
		miso(r);
		break;
	default:
		kernel(r);
		break;
	}
	lastWasMosi = false;
}

} // namespace

TraceSummary decodeTrace(std::istream &in, std::ostream &out, const TraceDecodeOptions &options)
{
	Decoder d(out, options);
	detail::TraceReader reader(in);
	Record r;
	while (reader.next(r)) {
		if (r.kind == 'F' && r.sk)
			continue; // the reader gives each ECM-SK frame its format
		if (r.kind == 'F')
			d.format(r.dataSize, r.check);
		else
			d.record(r);
	}
	d.finish();
	return d.summary;
}

} // namespace ecmxf
