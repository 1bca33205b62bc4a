// SPDX-License-Identifier: MIT
//
// options.cpp - network file slave options.

#include "slaves/options.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace ecmxf::sim::slaves {

std::optional<std::int64_t> OptionReader::integer(const std::string &key, std::int64_t lo,
						  std::int64_t hi)
{
	known_.insert(key);
	auto it = opts_.find(key);
	if (it == opts_.end())
		return std::nullopt;
	const std::string &s = it->second;
	std::size_t used = 0;
	long long v = 0;
	bool ok = !s.empty();
	if (ok) {
		try {
			const bool hex = s.size() > 2 && (s.rfind("0x", 0) == 0 || s.rfind("0X", 0) == 0);
			v = std::stoll(s, &used, hex ? 16 : 10);
			ok = used == s.size();
		} catch (const std::exception &) {
			ok = false;
		}
	}
	if (!ok || v < lo || v > hi)
		throw std::invalid_argument(type_ + ": option '" + key + "': '" + s +
					    "' is not a number in " + std::to_string(lo) + ".." +
					    std::to_string(hi));
	return v;
}

std::optional<bool> OptionReader::boolean(const std::string &key)
{
	known_.insert(key);
	auto it = opts_.find(key);
	if (it == opts_.end())
		return std::nullopt;
	std::string s = it->second;
	std::transform(s.begin(), s.end(), s.begin(),
		       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
	if (s == "1" || s == "true" || s == "yes" || s == "on")
		return true;
	if (s == "0" || s == "false" || s == "no" || s == "off")
		return false;
	throw std::invalid_argument(type_ + ": option '" + key + "': '" + it->second +
				    "' is not a boolean (1/0, true/false, yes/no, on/off)");
}

std::optional<std::string> OptionReader::string(const std::string &key)
{
	known_.insert(key);
	auto it = opts_.find(key);
	if (it == opts_.end())
		return std::nullopt;
	return it->second;
}

void OptionReader::finish() const
{
	for (const auto &[key, value] : opts_) {
		if (known_.count(key))
			continue;
		std::string list;
		for (const auto &k : known_)
			list += (list.empty() ? "" : ", ") + k;
		throw std::invalid_argument(type_ + ": unknown option '" + key + "' (known: " + list +
					    ")");
	}
}

void OptionReader::common(unsigned position, Identity &identity, std::uint16_t &alias,
			  const std::string &defaultName)
{
	identity.serial =
		static_cast<std::uint32_t>(integer("serial", 0, 0xFFFFFFFF).value_or(position + 1));
	identity.name = string("name").value_or(defaultName);
	alias = static_cast<std::uint16_t>(integer("alias", 0, 0xFFFF).value_or(0));
}

} // namespace ecmxf::sim::slaves
