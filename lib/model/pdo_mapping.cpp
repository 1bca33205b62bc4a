// SPDX-License-Identifier: MIT
// Entry names as users type them (include/ecmxf/model/pdo_mapping.hpp).

#include <ecmxf/model/pdo_mapping.hpp>

#include <cctype>

namespace ecmxf {

namespace {

std::string folded(std::string_view s)
{
	std::string r;
	for (const char c : s)
		if (c != ' ' && c != '_' && c != '-')
			r += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
	return r;
}

} // namespace

bool entryNameMatches(std::string_view name, std::string_view text)
{
	return !name.empty() && folded(name) == folded(text);
}

} // namespace ecmxf
