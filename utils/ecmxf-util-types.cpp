// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - the SDO data types of -t: names, encoding of a VALUE and
 * formatting of an object's bytes.
 */
#include "ecmxf-util.hpp"

#include <bit>
#include <cctype>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <limits>

namespace ecmxf_util {

namespace {

struct TypeEntry {
	std::string_view name;
	DataType type;
};

constexpr TypeEntry kTypes[] = {
	{ "bool", DataType::Bool },      { "int8", DataType::Int8 },
	{ "int16", DataType::Int16 },    { "int32", DataType::Int32 },
	{ "int64", DataType::Int64 },    { "uint8", DataType::Uint8 },
	{ "uint16", DataType::Uint16 },  { "uint32", DataType::Uint32 },
	{ "uint64", DataType::Uint64 },  { "float", DataType::Float },
	{ "double", DataType::Double },  { "string", DataType::String },
	{ "octet_string", DataType::OctetString },
	// IgH's aliases
	{ "sint8", DataType::Int8 },     { "sint16", DataType::Int16 },
	{ "sint32", DataType::Int32 },   { "sint64", DataType::Int64 },
	{ "real32", DataType::Float },   { "real64", DataType::Double },
	// the rest of IgH's --type names: sign-and-magnitude integers,
	// unicode_string (its bytes, as IgH sends them) and raw (the bytes)
	{ "sm8", DataType::Sm8 },        { "sm16", DataType::Sm16 },
	{ "sm32", DataType::Sm32 },      { "sm64", DataType::Sm64 },
	{ "unicode_string", DataType::String },
	{ "raw", DataType::OctetString },
};

/// VALUE of a float or double: a finite number in the type's range, or
/// inf, -inf, nan spelled out; 1e99 as a float is refused, not sent as
/// +inf, and so is a non-zero number too small for it (it would be 0).
double parseRealValue(std::string_view cmd, std::string_view text, bool isFloat)
{
	std::string lower;
	for (const char c : text)
		lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
	if (lower == "inf" || lower == "+inf" || lower == "infinity" || lower == "+infinity")
		return std::numeric_limits<double>::infinity();
	if (lower == "-inf" || lower == "-infinity")
		return -std::numeric_limits<double>::infinity();
	if (lower == "nan")
		return std::numeric_limits<double>::quiet_NaN();
	const std::string s(text);
	char *end = nullptr;
	errno = 0;
	const double v = std::strtod(s.c_str(), &end);
	const char *const name = isFloat ? "float" : "double";
	const auto outOfRange = [&] {
		return UsageError(std::string(cmd).append(": VALUE: ").append(text).append(
			" is out of range for ").append(name).append(isFloat ? " (magnitude 1.17549435e-38 .. "
									     "3.40282347e+38, or 0)"
									   : " (magnitude 2.2250738585072014e-308 .. "
									     "1.7976931348623157e+308, or 0)").append(
			"; inf, -inf and nan are taken when spelled so"));
	};
	const bool ranged = errno == ERANGE;
	if (s.empty() || end != s.c_str() + s.size() || std::isnan(v) || (std::isinf(v) && !ranged))
		throw UsageError(std::string(cmd).append(": VALUE: '").append(text).append(
			"' is not a real number (inf, -inf and nan are taken when spelled so)"));
	if (ranged)
		throw outOfRange();
	if (isFloat) {
		const double mag = std::fabs(v);
		if (mag > static_cast<double>(std::numeric_limits<float>::max()) ||
		    (mag != 0.0 && mag < static_cast<double>(std::numeric_limits<float>::min())))
			throw outOfRange();
	}
	return v;
}

std::uint64_t le(const std::vector<std::uint8_t> &b)
{
	std::uint64_t v = 0;
	for (std::size_t i = 0; i < b.size() && i < 8; i++)
		v |= static_cast<std::uint64_t>(b[i]) << (8 * i);
	return v;
}

std::vector<std::uint8_t> leBytes(std::uint64_t v, std::size_t n)
{
	std::vector<std::uint8_t> b(n);
	for (std::size_t i = 0; i < n; i++)
		b[i] = static_cast<std::uint8_t>(v >> (8 * i));
	return b;
}

bool isSigned(DataType t)
{
	return t == DataType::Int8 || t == DataType::Int16 || t == DataType::Int32 || t == DataType::Int64;
}

std::int64_t signExtend(std::uint64_t v, std::size_t bytes)
{
	const unsigned shift = static_cast<unsigned>(64 - 8 * bytes);
	return static_cast<std::int64_t>(v << shift) >> shift;
}

std::string real(double v, int digits)
{
	char buf[40];
	std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
	return buf;
}

} // namespace

DataType parseType(std::string_view cmd, std::string_view text)
{
	for (const TypeEntry &e : kTypes)
		if (e.name == text)
			return e.type;
	throw UsageError(std::string(cmd).append(": unknown type '").append(text).append(
		"' (bool, int8, int16, int32, int64, uint8, uint16, uint32, uint64, float, double, string, "
		"octet_string; IgH's unicode_string, sm8, sm16, sm32, sm64, raw; sint8..sint64, real32, real64)"));
}

std::string_view typeName(DataType t)
{
	for (const TypeEntry &e : kTypes)
		if (e.type == t)
			return e.name;
	return "?";
}

std::size_t typeSize(DataType t)
{
	switch (t) {
	case DataType::Bool:
	case DataType::Int8:
	case DataType::Sm8:
	case DataType::Uint8: return 1;
	case DataType::Int16:
	case DataType::Sm16:
	case DataType::Uint16: return 2;
	case DataType::Int32:
	case DataType::Sm32:
	case DataType::Uint32:
	case DataType::Float: return 4;
	case DataType::Int64:
	case DataType::Sm64:
	case DataType::Uint64:
	case DataType::Double: return 8;
	case DataType::String:
	case DataType::OctetString: return 0;
	}
	return 0;
}

DataType dataTypeOf(ecmxf::ObjectType t) noexcept
{
	switch (t) {
	case ecmxf::ObjectType::Int8: return DataType::Int8;
	case ecmxf::ObjectType::Int16: return DataType::Int16;
	case ecmxf::ObjectType::Int32: return DataType::Int32;
	case ecmxf::ObjectType::Uint8: return DataType::Uint8;
	case ecmxf::ObjectType::Uint16: return DataType::Uint16;
	case ecmxf::ObjectType::Uint32: return DataType::Uint32;
	}
	return DataType::Uint32;
}

bool integerType(DataType t) noexcept
{
	return t != DataType::Float && t != DataType::Double && t != DataType::String && t != DataType::OctetString &&
	       t != DataType::Bool;
}

std::vector<std::uint8_t> encodeValue(std::string_view cmd, DataType t, std::string_view text)
{
	const std::size_t n = typeSize(t);
	switch (t) {
	case DataType::Bool:
		if (text == "true" || text == "1")
			return { 1 };
		if (text == "false" || text == "0")
			return { 0 };
		throw UsageError(std::string(cmd).append(": VALUE: '").append(text).append(
			"' is not a bool (0, 1, true, false)"));
	case DataType::Int8:
	case DataType::Int16:
	case DataType::Int32:
	case DataType::Int64: {
		const std::int64_t max = n == 8 ? std::numeric_limits<std::int64_t>::max()
						: (std::int64_t{ 1 } << (8 * n - 1)) - 1;
		const std::int64_t v = parseSigned(cmd, "VALUE", text, -max - 1, max);
		return leBytes(static_cast<std::uint64_t>(v), n);
	}
	case DataType::Uint8:
	case DataType::Uint16:
	case DataType::Uint32:
	case DataType::Uint64: {
		const std::uint64_t max = n == 8 ? std::numeric_limits<std::uint64_t>::max()
						 : (std::uint64_t{ 1 } << (8 * n)) - 1;
		return leBytes(parseUnsigned(cmd, "VALUE", text, max), n);
	}
	case DataType::Sm8:
	case DataType::Sm16:
	case DataType::Sm32:
	case DataType::Sm64: {
		// sign and magnitude: the top bit is the sign, the rest |VALUE|
		const std::uint64_t sign = std::uint64_t{ 1 } << (8 * n - 1);
		const std::int64_t max = static_cast<std::int64_t>(sign - 1);
		const std::int64_t v = parseSigned(cmd, "VALUE", text, -max, max);
		const std::uint64_t mag = v < 0 ? static_cast<std::uint64_t>(-v) : static_cast<std::uint64_t>(v);
		return leBytes(v < 0 ? (mag | sign) : mag, n);
	}
	case DataType::Float:
		return leBytes(std::bit_cast<std::uint32_t>(static_cast<float>(parseRealValue(cmd, text, true))), 4);
	case DataType::Double:
		return leBytes(std::bit_cast<std::uint64_t>(parseRealValue(cmd, text, false)), 8);
	case DataType::String:
		return std::vector<std::uint8_t>(text.begin(), text.end());
	case DataType::OctetString: {
		std::vector<std::uint8_t> b;
		std::string digits;
		for (const char c : text)
			if (c != ' ' && c != ':' && c != ',' && c != '-')
				digits += c;
		if (digits.empty() || digits.size() % 2 != 0)
			throw UsageError(std::string(cmd).append(": VALUE: '").append(text).append(
				"' is not hex bytes (e.g. 0a0b0c or 0a:0b:0c)"));
		for (std::size_t i = 0; i < digits.size(); i += 2) {
			unsigned v = 0;
			for (std::size_t k = i; k < i + 2; k++) {
				const char c = digits[k];
				unsigned d;
				if (c >= '0' && c <= '9')
					d = static_cast<unsigned>(c - '0');
				else if (c >= 'a' && c <= 'f')
					d = static_cast<unsigned>(c - 'a' + 10);
				else if (c >= 'A' && c <= 'F')
					d = static_cast<unsigned>(c - 'A' + 10);
				else
					throw UsageError(std::string(cmd).append(": VALUE: '").append(text).append(
						"' is not hex bytes (e.g. 0a0b0c or 0a:0b:0c)"));
				v = v * 16 + d;
			}
			b.push_back(static_cast<std::uint8_t>(v));
		}
		return b;
	}
	}
	return {};
}

std::string formatValue(std::optional<DataType> t, const std::vector<std::uint8_t> &b)
{
	if (!t) {
		const std::size_t n = b.size();
		if (n == 1 || n == 2 || n == 4 || n == 8) {
			const std::uint64_t v = le(b);
			return hexString(v, static_cast<int>(2 * n)) + " " + std::to_string(v);
		}
		return hexBytes(b);
	}
	switch (*t) {
	case DataType::Bool: return le(b) ? "true" : "false";
	case DataType::Float: return real(std::bit_cast<float>(static_cast<std::uint32_t>(le(b))), 9);
	case DataType::Double: return real(std::bit_cast<double>(le(b)), 17);
	case DataType::String: {
		std::string s(b.begin(), b.end());
		if (const auto nul = s.find('\0'); nul != std::string::npos)
			s.resize(nul);
		return s;
	}
	case DataType::OctetString: return hexBytes(b);
	case DataType::Sm8:
	case DataType::Sm16:
	case DataType::Sm32:
	case DataType::Sm64: {
		const std::uint64_t sign = std::uint64_t{ 1 } << (8 * b.size() - 1);
		const std::uint64_t v = le(b);
		const auto mag = static_cast<std::int64_t>(v & (sign - 1));
		return std::to_string(v & sign ? -mag : mag);
	}
	default:
		if (isSigned(*t))
			return std::to_string(signExtend(le(b), b.size()));
		return std::to_string(le(b));
	}
}

std::string jsonValue(std::optional<DataType> t, const std::vector<std::uint8_t> &b)
{
	if (!t) {
		const std::size_t n = b.size();
		if (n == 1 || n == 2 || n == 4 || n == 8)
			return std::to_string(le(b));
		return jsonString(hexBytes(b, ""));
	}
	switch (*t) {
	case DataType::String:
	case DataType::OctetString: return jsonString(formatValue(t, b));
	default: return formatValue(t, b);
	}
}

} // namespace ecmxf_util
