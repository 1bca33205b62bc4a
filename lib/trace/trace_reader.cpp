// SPDX-License-Identifier: MIT
// The text trace reader (lib/trace/trace_reader.hpp).

#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>

#include <array>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <istream>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "ecmsk-proto.h"
#include "ecmxf-proto.h"
#include "link/trace_writer.hpp"
#include "trace/trace_reader.hpp"

namespace ecmxf::detail {

namespace {

constexpr std::size_t kBlock = 1u << 16;

/// Per character: 0..15 a hex digit, kSep a separator, kBad anything else.
constexpr std::uint8_t kSep = 0x40, kBad = 0x80;
constexpr std::array<std::uint8_t, 256> kNibble = [] {
	std::array<std::uint8_t, 256> t{};
	for (auto &v : t)
		v = kBad;
	for (int c = '0'; c <= '9'; c++)
		t[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(c - '0');
	for (int c = 'a'; c <= 'f'; c++)
		t[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(c - 'a' + 10);
	for (int c = 'A'; c <= 'F'; c++)
		t[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(c - 'A' + 10);
	t[' '] = t['\t'] = t['\r'] = kSep;
	return t;
}();

/// Two characters (first in the high byte) to their byte, or 0x100 and
/// up when either is not a hex digit.
const std::array<std::uint16_t, 65536> &pairTable()
{
	static const auto t = [] {
		std::array<std::uint16_t, 65536> p{};
		for (std::size_t i = 0; i < p.size(); i++) {
			const std::uint8_t hi = kNibble[i >> 8], lo = kNibble[i & 0xFF];
			p[i] = (hi | lo) & (kSep | kBad) ? 0x100 : static_cast<std::uint16_t>(hi << 4 | lo);
		}
		return p;
	}();
	return t;
}

[[noreturn]] void badLine(std::size_t line, const std::string &what)
{
	throw Error("trace line " + std::to_string(line) + ": " + what, EINVAL);
}

std::uint64_t parseTime(std::size_t line, std::string_view t)
{
	const auto dot = t.find('.');
	const std::string_view sec = t.substr(0, dot);
	const std::string_view frac = dot == std::string_view::npos ? std::string_view() : t.substr(dot + 1);
	auto digits = [](std::string_view s) {
		if (s.empty())
			return false;
		for (const char c : s)
			if (c < '0' || c > '9')
				return false;
		return true;
	};
	if (!digits(sec) || sec.size() > 10 || (dot != std::string_view::npos && (!digits(frac) || frac.size() > 9)))
		badLine(line, "bad time \"" + std::string(t) +
				      "\" (expected seconds with up to 9 decimals, e.g. 0.000150000)");
	std::uint64_t s = 0;
	for (const char c : sec)
		s = s * 10 + static_cast<std::uint64_t>(c - '0');
	std::uint64_t f = 0;
	for (std::size_t i = 0; i < 9; i++)
		f = f * 10 + (i < frac.size() ? static_cast<std::uint64_t>(frac[i] - '0') : 0u);
	return s * 1'000'000'000u + f;
}

/// Eight hex digits at @p p to four bytes at @p o; false, nothing
/// written, when any of them is not a hex digit. Little-endian machines
/// take the eight characters at once in a 64-bit word (SIMD within a
/// register): a byte x below 0x80 is >= lo when x + (0x80 - lo) has bit 7
/// set and <= hi when x + (0x7F - hi) has it clear, and no byte carries
/// into the next. Others look the four pairs up in @p pairs.
bool hex8(const unsigned char *p, std::uint8_t *o, const std::array<std::uint16_t, 65536> &pairs) noexcept
{
	if constexpr (std::endian::native != std::endian::little) {
		const std::uint16_t v0 = pairs[static_cast<std::size_t>(p[0]) << 8 | p[1]];
		const std::uint16_t v1 = pairs[static_cast<std::size_t>(p[2]) << 8 | p[3]];
		const std::uint16_t v2 = pairs[static_cast<std::size_t>(p[4]) << 8 | p[5]];
		const std::uint16_t v3 = pairs[static_cast<std::size_t>(p[6]) << 8 | p[7]];
		if ((v0 | v1 | v2 | v3) >= 0x100)
			return false;
		o[0] = static_cast<std::uint8_t>(v0);
		o[1] = static_cast<std::uint8_t>(v1);
		o[2] = static_cast<std::uint8_t>(v2);
		o[3] = static_cast<std::uint8_t>(v3);
		return true;
	} else {
		(void)pairs;
		constexpr std::uint64_t k1 = 0x0101010101010101u, k80 = 0x80 * k1;
		std::uint64_t v;
		std::memcpy(&v, p, 8);
		if (v & k80)
			return false;
		const std::uint64_t lower = v | 0x20 * k1; // 'A'..'F' to 'a'..'f', digits as they are
		const std::uint64_t digit = (v + (0x80 - '0') * k1) & ~(v + (0x7F - '9') * k1);
		const std::uint64_t letter = (lower + (0x80 - 'a') * k1) & ~(lower + (0x7F - 'f') * k1);
		if (((digit | letter) & k80) != k80)
			return false;
		// each byte its digit's value: the low nibble, + 9 for a letter (bit 6)
		const std::uint64_t n = (lower & 0x0F * k1) + ((lower >> 6) & k1) * 9;
		// byte 2j: digit 2j in the high nibble, digit 2j+1 in the low one;
		// then bytes 0, 2, 4, 6 packed into 0..3
		std::uint64_t t = ((n << 4) | (n >> 8)) & 0x00FF00FF00FF00FFu;
		t = (t | (t >> 8)) & 0x0000FFFF0000FFFFu;
		t = (t | (t >> 16)) & 0xFFFFFFFFu;
		const auto w = static_cast<std::uint32_t>(t);
		std::memcpy(o, &w, 4);
		return true;
	}
}

/// Sixteen hex digits, eight at @p a and eight at @p b (the writer's two
/// groups around a space, or sixteen in a row), to eight bytes at @p o;
/// false when any is not a hex digit (bytes at @p o may then be written:
/// the caller's buffer has room, and does not count them). With SSE2 (every
/// x86-64) in one 128-bit register, else as two hex8().
bool hex16(const unsigned char *a, const unsigned char *b, std::uint8_t *o,
	   const std::array<std::uint16_t, 65536> &pairs) noexcept
{
#if defined(__SSE2__)
	(void)pairs;
	const __m128i v = _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i *>(a)),
					     _mm_loadl_epi64(reinterpret_cast<const __m128i *>(b)));
	const __m128i lower = _mm_or_si128(v, _mm_set1_epi8(0x20));
	// signed compares: a byte of 0x80 and up is negative, neither range
	const __m128i digit = _mm_and_si128(_mm_cmpgt_epi8(v, _mm_set1_epi8('0' - 1)),
					    _mm_cmplt_epi8(v, _mm_set1_epi8('9' + 1)));
	const __m128i letter = _mm_and_si128(_mm_cmpgt_epi8(lower, _mm_set1_epi8('a' - 1)),
					     _mm_cmplt_epi8(lower, _mm_set1_epi8('f' + 1)));
	if (_mm_movemask_epi8(_mm_or_si128(digit, letter)) != 0xFFFF)
		return false;
	const __m128i n = _mm_add_epi8(_mm_and_si128(lower, _mm_set1_epi8(0x0F)),
				       _mm_and_si128(letter, _mm_set1_epi8(9)));
	// per 16-bit lane (first digit low, second high): first << 4 | second
	const __m128i t = _mm_and_si128(_mm_or_si128(_mm_slli_epi16(n, 4), _mm_srli_epi16(n, 8)),
					_mm_set1_epi16(0x00FF));
	_mm_storel_epi64(reinterpret_cast<__m128i *>(o), _mm_packus_epi16(t, t));
	return true;
#else
	return hex8(a, o, pairs) && hex8(b, o + 4, pairs);
#endif
}

/// The hex of @p s into @p out: sixteen digits at once (hex16()), groups
/// of eight (hex8()), other digit pairs through the pair table, one nibble at a time where a
/// separator splits a pair.
void parseHex(std::size_t line, std::string_view s, std::vector<std::uint8_t> &out)
{
	const auto &pairs = pairTable();
	out.resize(s.size() / 2 + 1);
	std::uint8_t *o = out.data();
	const auto *p = reinterpret_cast<const unsigned char *>(s.data());
	const auto *e = p + s.size();
	int hi = -1;
	while (p < e) {
		// the writer's separator, then its groups: 8 digits, 4 bytes at once
		if (hi < 0 && *p == ' ') {
			p++;
			continue;
		}
		if (hi < 0 && e - p >= 17 && p[8] == ' ' && hex16(p, p + 9, o, pairs)) {
			o += 8;
			p += 17;
			continue;
		}
		if (hi < 0 && e - p >= 16 && hex16(p, p + 8, o, pairs)) {
			o += 8;
			p += 16;
			continue;
		}
		if (hi < 0 && e - p >= 8 && hex8(p, o, pairs)) {
			o += 4;
			p += 8;
			continue;
		}
		if (hi < 0 && e - p >= 2) {
			const std::uint16_t v = pairs[static_cast<std::size_t>(p[0]) << 8 | p[1]];
			if (v < 0x100) {
				*o++ = static_cast<std::uint8_t>(v);
				p += 2;
				continue;
			}
		}
		const std::uint8_t n = kNibble[*p];
		if (n == kSep) {
			p++;
			continue;
		}
		if (n == kBad)
			badLine(line, std::string("'") + static_cast<char>(*p) + "' is not a hex digit");
		if (hi < 0) {
			hi = n;
		} else {
			*o++ = static_cast<std::uint8_t>(hi << 4 | n);
			hi = -1;
		}
		p++;
	}
	if (hi >= 0)
		badLine(line, "odd number of hex digits");
	out.resize(static_cast<std::size_t>(o - out.data()));
}

} // namespace

TraceReader::TraceReader(std::istream &in) : in_(in), buf_(kBlock) {}

bool TraceReader::nextLine(std::string_view &line)
{
	for (;;) {
		const char *b = buf_.data();
		if (const void *nl = std::memchr(b + pos_, '\n', end_ - pos_)) {
			const std::size_t at = static_cast<std::size_t>(static_cast<const char *>(nl) - b);
			line = std::string_view(b + pos_, at - pos_);
			pos_ = at + 1;
			return true;
		}
		if (eof_) {
			if (pos_ == end_)
				return false;
			line = std::string_view(b + pos_, end_ - pos_); // the last line, without its newline
			pos_ = end_;
			return true;
		}
		// move the partial line to the front, grow for a long one, read on
		if (pos_ > 0) {
			std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
			end_ -= pos_;
			pos_ = 0;
		}
		if (end_ == buf_.size())
			buf_.resize(buf_.size() * 2);
		in_.read(buf_.data() + end_, static_cast<std::streamsize>(buf_.size() - end_));
		const std::streamsize got = in_.gcount();
		end_ += static_cast<std::size_t>(got);
		if (!in_)
			eof_ = true;
	}
}

bool TraceReader::next(TraceRecord &r)
{
	std::string_view s;
	while (nextLine(s)) {
		line_++;
		if (!s.empty() && s.back() == '\r')
			s.remove_suffix(1);
		if (s.empty() || s[0] == '#')
			continue;
		if (parse(s, r))
			return true;
	}
	if (!magic_)
		badLine(line_, "not an ecmxf trace (empty, or no \"" + std::string(kTraceMagic) + "\" line)");
	return false;
}

bool TraceReader::parse(std::string_view s, TraceRecord &r)
{
	if (!magic_) {
		if (s != kTraceMagic)
			badLine(line_, "not an ecmxf trace (the first line must be \"" + std::string(kTraceMagic) + "\")");
		magic_ = true;
		return false;
	}
	r.line = line_;
	r.status = 0;
	r.sk = false;
	r.slotSize = r.skCrc = 0;
	if (s.starts_with("format ecm-sk") && (s.size() == 13 || s[13] == ' ' || s[13] == '\t')) {
		// "format ecm-sk <12|16> <crc|nocrc|cmdcrc|rspcrc>"
		const std::string l(s);
		char crc[16] = {};
		unsigned slot = 0;
		char extra = 0;
		if (std::sscanf(l.c_str(), "format ecm-sk %u %15s %c", &slot, crc, &extra) != 2 ||
		    (slot != ECMSK_SLOT12 && slot != ECMSK_SLOT16))
			badLine(line_, "bad format line \"" + l +
					       "\" (expected format ecm-sk 12|16 crc|nocrc|cmdcrc|rspcrc: the slot size "
					       "and the CRC-8 in force)");
		const std::string c = crc;
		unsigned bits = 99u;
		for (const unsigned b : { 0u, ECMSK_EX_CMD_CRC, ECMSK_EX_RSP_CRC, ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC })
			if (c == skCrcKeyword(b))
				bits = b;
		if (bits == 99u)
			badLine(line_, "unknown ECM-SK CRC setting \"" + c +
					       "\" (crc: both directions, nocrc, cmdcrc: host to board only, rspcrc: board "
					       "to host only)");
		sk_.slot = slot;
		sk_.crc = bits;
		sk_.line = line_;
		r.kind = 'F';
		r.sk = true;
		r.slotSize = slot;
		r.skCrc = bits;
		r.bytes.clear();
		return true;
	}
	if (s.starts_with("format ")) {
		const std::string l(s);
		char check[16] = {};
		unsigned size = 0;
		char extra = 0;
		if (std::sscanf(l.c_str(), "format %u %15s %c", &size, check, &extra) != 2 || !ecmxf_data_size_valid(size))
			badLine(line_, "bad format line \"" + l +
					       "\" (expected format <32..1408> fixed|crc8|ccitt|crc32, or format ecm-sk 12|16 "
					       "crc|nocrc|cmdcrc|rspcrc)");
		const std::string c = check;
		unsigned type = 99u;
		for (const unsigned t : std::initializer_list<unsigned>{ ECMXF_CHECK_FIXED, ECMXF_CHECK_CRC8,
									  ECMXF_CHECK_CCITT, ECMXF_CHECK_CRC32 })
			if (c == checkKeyword(t))
				type = t;
		if (type == 99u)
			badLine(line_, "unknown check type \"" + c + "\" (fixed, crc8, ccitt, crc32)");
		r.kind = 'F';
		r.dataSize = size;
		r.check = type;
		r.bytes.clear();
		sk_.slot = 0; // the ECM-XF's packets again
		return true;
	}
	const auto sp = s.find(' ');
	if (sp == std::string_view::npos || sp + 2 > s.size() || (sp + 2 < s.size() && s[sp + 2] != ' '))
		badLine(line_, "expected <time> <record> ..., record one of > < C R");
	r.ns = parseTime(line_, s.substr(0, sp));
	r.kind = s[sp + 1];
	std::size_t from = sp + 2;
	if (r.kind == 'R') {
		const auto sp2 = s.find(' ', from + 1);
		const std::string st(s.substr(from, sp2 == std::string_view::npos ? std::string_view::npos : sp2 - from));
		char *end = nullptr;
		const long v = std::strtol(st.c_str(), &end, 10);
		if (st.find_first_not_of(' ') == std::string::npos || !end || *end || v < -4095 || v > 0)
			badLine(line_, "bad status in R record (expected 0 or a negative errno)");
		r.status = static_cast<int>(v);
		from = sp2 == std::string_view::npos ? s.size() : sp2;
	} else if (r.kind != '>' && r.kind != '<' && r.kind != 'C') {
		badLine(line_, std::string("unknown record '") + r.kind + "' (expected > < C R)");
	}
	if (sk_.slot && (r.kind == 'C' || r.kind == 'R'))
		badLine(line_, std::string("a kernel record '") + r.kind +
				       "' in ECM-SK frames (the format ecm-sk line " + std::to_string(sk_.line) +
				       " is in force; expected > or <)");
	parseHex(line_, s.substr(from), r.bytes);
	if (sk_.slot) {
		const std::size_t frame = sk_.slot == ECMSK_SLOT16 ? ECMSK_FRAME16 : ECMSK_FRAME12;
		if (r.bytes.size() != frame)
			badLine(line_, "an ECM-SK frame of " + std::to_string(r.bytes.size()) + " bytes (the format ecm-sk " +
					       std::to_string(sk_.slot) + " line " + std::to_string(sk_.line) + " takes " +
					       std::to_string(frame) + "-byte frames)");
		r.sk = true;
		r.slotSize = sk_.slot;
		r.skCrc = sk_.crc;
	} else if (r.kind == '>' || r.kind == '<') {
		if (r.bytes.size() < ECMXF_PKT_SIZE(ECMXF_DATA_MIN) || r.bytes.size() > ECMXF_PKT_MAX)
			badLine(line_, "a packet of " + std::to_string(r.bytes.size()) + " bytes (packets are 64..1440 bytes)");
	} else if (r.bytes.size() < 20) {
		badLine(line_, "a kernel record needs the 20 header bytes 0x04..0x17, found " +
				       std::to_string(r.bytes.size()));
	}
	return true;
}

} // namespace ecmxf::detail
