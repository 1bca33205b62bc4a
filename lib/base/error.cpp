// SPDX-License-Identifier: MIT
// ecmxf::Error's out-of-line parts (include/ecmxf/error.hpp).

#include <ecmxf/error.hpp>

#include <string>

namespace ecmxf {

Error::Error(const std::string &message, int errnoValue, std::optional<std::uint8_t> errorStatus)
	: std::runtime_error(message), errno_(errnoValue), errorStatus_(errorStatus)
{
}

Error::~Error() = default;

void Error::rethrowWithPrefix(std::string_view prefix) const
{
	throw Error(std::string(prefix).append(what()), errnoValue(), errorStatus());
}

} // namespace ecmxf
