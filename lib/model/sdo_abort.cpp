// SPDX-License-Identifier: MIT
// SDO abort codes in words (sdoAbortText()) and SdoError: the shared
// vocabulary of both masters (include/ecmxf/model/types_bus.hpp); the
// ECM-XF's SDO transfers are lib/bus/sdo.cpp.

#include <ecmxf/model/types_bus.hpp>

#include <string>

#include "base/text.hpp"

namespace ecmxf {

namespace {

/// The ETG table of manual ver. 050 (ECM_CMD_ECAT_SDO_ABORTCODE_GET), its
/// wording.
constexpr detail::CodeText<std::uint32_t> kSdoAbortTexts[] = {
	{ 0x00000000, "No SDO error" },
	{ 0x05030000, "Toggle bit not changed" },
	{ 0x05040000, "SDO timeout" },
	{ 0x05040001, "Command specifier unknown" },
	{ 0x05040005, "Out of memory" },
	{ 0x06010000, "Unsupported Access" },
	{ 0x06010001, "Write only entry" },
	{ 0x06010002, "Read only entry" },
	{ 0x06010003, "Entry can not be written because Subindex0 is not 0" },
	{ 0x06010004, "The object can not be accessed via complete access" },
	{ 0x06020000, "Object not existing" },
	{ 0x06040041, "Object can not be mapped to PDO" },
	{ 0x06040042, "Mapped Object exceeds PDO" },
	{ 0x06040043, "Parameter is incompatible" },
	{ 0x06040047, "Device incompatibility" },
	{ 0x06060000, "Hardware error" },
	{ 0x06070010, "Parameter length error" },
	{ 0x06070012, "Parameter is too long" },
	{ 0x06070013, "Parameter is too short" },
	{ 0x06090011, "Subindex (Entry) not exists" },
	{ 0x06090030, "Value exceeds" },
	{ 0x06090031, "Value is too great" },
	{ 0x06090032, "Value is too small" },
	{ 0x06090033, "Detected Module Ident List (0xF030) and Configured Module Ident list (0xF050) does not match" },
	{ 0x06090036, "Value is less than minimum value" },
	{ 0x08000000, "General error" },
	{ 0x08000020, "Data can not be read or written" },
	{ 0x08000021, "Data can not be accessed because of local control" },
	{ 0x08000022, "Data can not be read or written in the current state" },
	{ 0x08000023, "Object is not in the object dictionary" },
};

} // namespace

std::string_view sdoAbortText(std::uint32_t code) noexcept
{
	return detail::textOf(kSdoAbortTexts, code, "unknown abort code");
}

SdoError::SdoError(const std::string &message, int errnoValue, std::uint32_t abortCode,
		   std::optional<std::uint8_t> errorStatus)
	: Error(message, errnoValue, errorStatus), abortCode_(abortCode)
{
}

SdoError::~SdoError() = default;

void SdoError::rethrowWithPrefix(std::string_view prefix) const
{
	throw SdoError(std::string(prefix).append(what()), errnoValue(), abortCode(), errorStatus());
}

} // namespace ecmxf
