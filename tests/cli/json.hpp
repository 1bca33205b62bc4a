// SPDX-License-Identifier: MIT
/*
 * json.hpp - a small, strict JSON parser for the tests (header-only).
 *
 * Enough to read back what ecmxf-util prints with --json: objects, arrays,
 * strings with every RFC 8259 escape (\uXXXX, surrogate pairs included,
 * decoded to UTF-8), numbers, true, false and null. Anything that is not
 * JSON (trailing commas, single quotes, hex numbers, leading zeros,
 * duplicate keys, trailing garbage, raw control characters in strings)
 * throws std::runtime_error naming what was wrong and the byte offset.
 *
 *   const auto j = testjson::parse(out);
 *   CHECK(j["slaves"].num == 3);
 *   for (const auto &l : testjson::parseLines(out)) ...   // JSON Lines
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace testjson {

/// One JSON value.
struct Json {
	enum Kind { Null, Bool, Number, String, Array, Object } kind = Null;
	bool b = false;
	double num = 0;
	std::string str;
	std::vector<Json> arr;
	std::map<std::string, Json> obj;

	/// The member @p k of an object; throws when this is not an object or
	/// has no such member.
	const Json &operator[](const std::string &k) const
	{
		if (kind != Object)
			throw std::runtime_error("JSON: not an object (looking for key " + k + ")");
		auto it = obj.find(k);
		if (it == obj.end())
			throw std::runtime_error("JSON: no key " + k);
		return it->second;
	}
	const Json &operator[](const char *k) const { return (*this)[std::string(k)]; }
	/// Element @p i of an array; throws when this is not an array or @p i
	/// is out of range.
	const Json &operator[](std::size_t i) const
	{
		if (kind != Array)
			throw std::runtime_error("JSON: not an array");
		if (i >= arr.size())
			throw std::runtime_error("JSON: index " + std::to_string(i) + " out of range");
		return arr[i];
	}
	const Json &operator[](int i) const { return (*this)[static_cast<std::size_t>(i)]; }
	/// Has an object the member @p k.
	[[nodiscard]] bool contains(const std::string &k) const
	{
		return kind == Object && obj.count(k) != 0;
	}
	/// Elements of an array or members of an object, 0 otherwise.
	[[nodiscard]] std::size_t size() const
	{
		return kind == Array ? arr.size() : kind == Object ? obj.size() : 0;
	}
};

namespace detail {

class Parser
{
public:
	explicit Parser(const std::string &s) : s_(s) {}

	Json parse()
	{
		Json v = value(0);
		ws();
		if (i_ != s_.size())
			fail("trailing characters");
		return v;
	}

private:
	static constexpr int kMaxDepth = 256;

	[[noreturn]] void fail(const std::string &what) const
	{
		throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(i_));
	}
	void ws()
	{
		while (i_ < s_.size() &&
		       (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t' || s_[i_] == '\r'))
			i_++;
	}
	char peek()
	{
		ws();
		if (i_ >= s_.size())
			fail("unexpected end");
		return s_[i_];
	}
	void expect(char c)
	{
		if (peek() != c)
			fail(std::string("expected '") + c + "'");
		i_++;
	}
	bool literal(const char *w)
	{
		const std::string lit(w);
		if (s_.compare(i_, lit.size(), lit) != 0)
			return false;
		i_ += lit.size();
		return true;
	}
	unsigned hex4()
	{
		unsigned v = 0;
		for (int k = 0; k < 4; k++) {
			if (i_ >= s_.size())
				fail("bad \\u escape");
			const char c = s_[i_++];
			v <<= 4;
			if (c >= '0' && c <= '9')
				v |= static_cast<unsigned>(c - '0');
			else if (c >= 'a' && c <= 'f')
				v |= static_cast<unsigned>(c - 'a' + 10);
			else if (c >= 'A' && c <= 'F')
				v |= static_cast<unsigned>(c - 'A' + 10);
			else
				fail("bad \\u escape");
		}
		return v;
	}
	static void utf8(std::string &out, std::uint32_t cp)
	{
		auto byte = [&](std::uint32_t b) { out += static_cast<char>(static_cast<unsigned char>(b)); };
		if (cp < 0x80) {
			byte(cp);
		} else if (cp < 0x800) {
			byte(0xC0 | cp >> 6);
			byte(0x80 | (cp & 0x3F));
		} else if (cp < 0x10000) {
			byte(0xE0 | cp >> 12);
			byte(0x80 | (cp >> 6 & 0x3F));
			byte(0x80 | (cp & 0x3F));
		} else {
			byte(0xF0 | cp >> 18);
			byte(0x80 | (cp >> 12 & 0x3F));
			byte(0x80 | (cp >> 6 & 0x3F));
			byte(0x80 | (cp & 0x3F));
		}
	}
	std::string string()
	{
		expect('"');
		std::string out;
		while (true) {
			if (i_ >= s_.size())
				fail("unterminated string");
			const char c = s_[i_++];
			if (c == '"')
				return out;
			if (static_cast<unsigned char>(c) < 0x20)
				fail("control character in string");
			if (c != '\\') {
				out += c;
				continue;
			}
			if (i_ >= s_.size())
				fail("bad escape");
			const char e = s_[i_++];
			switch (e) {
			case '"': case '\\': case '/': out += e; break;
			case 'b': out += '\b'; break;
			case 'f': out += '\f'; break;
			case 'n': out += '\n'; break;
			case 'r': out += '\r'; break;
			case 't': out += '\t'; break;
			case 'u': {
				std::uint32_t cp = hex4();
				if (cp >= 0xDC00 && cp <= 0xDFFF)
					fail("lone low surrogate");
				if (cp >= 0xD800 && cp <= 0xDBFF) {
					if (!literal("\\u"))
						fail("high surrogate without low surrogate");
					const std::uint32_t lo = hex4();
					if (lo < 0xDC00 || lo > 0xDFFF)
						fail("high surrogate without low surrogate");
					cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
				}
				utf8(out, cp);
				break;
			}
			default: fail("bad escape");
			}
		}
	}
	Json value(int depth)
	{
		if (depth > kMaxDepth)
			fail("nested too deeply");
		Json v;
		const char c = peek();
		if (c == '{') {
			v.kind = Json::Object;
			i_++;
			if (peek() == '}') {
				i_++;
				return v;
			}
			while (true) {
				if (peek() != '"')
					fail("expected a string key");
				const std::string k = string();
				expect(':');
				if (!v.obj.emplace(k, value(depth + 1)).second)
					fail("duplicate key " + k);
				if (peek() == ',') {
					i_++;
					continue;
				}
				expect('}');
				return v;
			}
		}
		if (c == '[') {
			v.kind = Json::Array;
			i_++;
			if (peek() == ']') {
				i_++;
				return v;
			}
			while (true) {
				v.arr.push_back(value(depth + 1));
				if (peek() == ',') {
					i_++;
					continue;
				}
				expect(']');
				return v;
			}
		}
		if (c == '"') {
			v.kind = Json::String;
			v.str = string();
			return v;
		}
		if (literal("true")) {
			v.kind = Json::Bool;
			v.b = true;
			return v;
		}
		if (literal("false")) {
			v.kind = Json::Bool;
			return v;
		}
		if (literal("null"))
			return v;
		// number: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
		const std::size_t start = i_;
		if (s_[i_] == '-')
			i_++;
		auto isDigit = [&] { return i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9'; };
		auto digits = [&] {
			if (!isDigit())
				fail("digit expected");
			while (isDigit())
				i_++;
		};
		if (i_ < s_.size() && s_[i_] == '0')
			i_++;
		else
			digits();
		if (i_ < s_.size() && s_[i_] == '.') {
			i_++;
			digits();
		}
		if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
			i_++;
			if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-'))
				i_++;
			digits();
		}
		if (isDigit())
			fail("leading zero");
		v.kind = Json::Number;
		v.num = std::strtod(s_.substr(start, i_ - start).c_str(), nullptr);
		return v;
	}

	const std::string &s_;
	std::size_t i_ = 0;
};

} // namespace detail

/// Parses one JSON document (whitespace around it allowed).
inline Json parse(const std::string &s)
{
	return detail::Parser(s).parse();
}

/// Parses JSON Lines: one document per non-empty line.
inline std::vector<Json> parseLines(const std::string &s)
{
	std::vector<Json> out;
	std::size_t pos = 0;
	while (pos < s.size()) {
		std::size_t nl = s.find('\n', pos);
		if (nl == std::string::npos)
			nl = s.size();
		const std::string line = s.substr(pos, nl - pos);
		if (line.find_first_not_of(" \t\r") != std::string::npos)
			out.push_back(parse(line));
		pos = nl + 1;
	}
	return out;
}

} // namespace testjson
