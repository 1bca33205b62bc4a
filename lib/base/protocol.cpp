// SPDX-License-Identifier: MIT
// C++ view of the protocol core's static parts (see include/ecmxf/protocol.hpp).

#include <ecmxf/protocol.hpp>

#include "ecmxf-proto.h"

namespace ecmxf {

namespace {

CommandInfo toInfo(const ecmxf_cmd_info &ci) noexcept
{
	CommandInfo info{};
	info.code = ci.code;
	info.name = ci.name;
	info.async = (ci.flags & ECMXF_CMDF_ASYNC) != 0;
	info.asyncOnlyParam0 = (ci.flags & ECMXF_CMDF_ASYNC_PARAM0) != 0;
	info.inV038 = (ci.flags & ECMXF_CMDF_V038) != 0;
	info.inV050 = (ci.flags & ECMXF_CMDF_V050) != 0;
	info.idempotent = (ci.flags & ECMXF_CMDF_IDEMPOTENT) != 0;
	if (ci.partner >= 0)
		info.partner = static_cast<std::uint8_t>(ci.partner);
	info.timeoutMs = ci.timeout_ms;
	return info;
}

} // namespace

ECMXF_EXPORT std::string_view version() noexcept
{
	return ECMXF_VERSION_STRING;
}

ECMXF_EXPORT std::string_view crcCoverageName(CrcCoverage coverage) noexcept
{
	return ecmxf_cover_name(static_cast<ecmxf_cover>(coverage));
}

ECMXF_EXPORT std::uint8_t crc8(std::span<const std::uint8_t> bytes) noexcept
{
	return ecmxf_crc8(bytes.data(), bytes.size());
}

ECMXF_EXPORT std::uint16_t crcCcitt(std::span<const std::uint8_t> bytes) noexcept
{
	return ecmxf_crc_ccitt(bytes.data(), bytes.size());
}

ECMXF_EXPORT std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept
{
	return ecmxf_crc32(bytes.data(), bytes.size());
}

ECMXF_EXPORT std::optional<CommandInfo> commandInfo(std::uint8_t code) noexcept
{
	const ecmxf_cmd_info *ci = ecmxf_cmd_lookup(code);

	if (!ci)
		return std::nullopt;
	return toInfo(*ci);
}

ECMXF_EXPORT std::size_t commandCount() noexcept
{
	std::size_t n = 0;

	ecmxf_cmd_table(&n);
	return n;
}

ECMXF_EXPORT CommandInfo commandAt(std::size_t i) noexcept
{
	std::size_t n = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&n);

	return toInfo(t[i < n ? i : n - 1]);
}

} // namespace ecmxf
