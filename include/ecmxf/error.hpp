// SPDX-License-Identifier: MIT
/**
 * @file error.hpp
 * @brief The one exception type of libecmxf.
 *
 * Every failure the library reports is an ecmxf::Error whose message says
 * what happened in the field's words: the command's manual name, what was
 * waited for or what the chip answered, and the chip's error-status bits
 * where they matter. The same failure is also available as an errno value
 * (the protocol core's vocabulary, e.g. ETIMEDOUT, EREMOTEIO) for callers
 * that branch on it.
 */
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>

namespace ecmxf {

/// A failure of a transport, of the protocol or of a command on the chip.
class ECMXF_EXPORT Error : public std::runtime_error
{
public:
	/// @p message is the complete text what() returns; @p errnoValue a
	/// positive errno value (0 when none fits); @p errorStatus the chip's
	/// error-status byte (response header 0x09) when the chip's answer is
	/// the reason for the failure.
	Error(const std::string &message, int errnoValue,
	      std::optional<std::uint8_t> errorStatus = std::nullopt);
	Error(const Error &) = default;
	Error &operator=(const Error &) = default;
	~Error() override;

	/// The failure as a positive errno value: ETIMEDOUT (no answer or no
	/// completion in time), EBADMSG / EPROTO / EIO (the link kept
	/// delivering bad packets, or an answer was lost), EBUSY (the chip
	/// refused an async command), EREMOTEIO (an async command failed on the
	/// chip), ECONNRESET (the chip reset), EMSGSIZE (a payload or answer
	/// too large), ECANCELED, EINVAL (a bad argument or an unknown URI),
	/// EOPNOTSUPP (a transport that is not implemented yet).
	[[nodiscard]] int errnoValue() const noexcept { return errno_; }

	/// The whole error-status byte of the response that reported the
	/// failure (bit 3 async error, bit 7 command error, bits 0/1 link
	/// presence...), for failures the chip reported; std::nullopt for
	/// timeouts, transport and caller errors.
	[[nodiscard]] std::optional<std::uint8_t> errorStatus() const noexcept { return errorStatus_; }

	/// Throws a copy of this error, of the same type with the same fields,
	/// whose message is @p prefix followed by this one's: how a caller
	/// adds its context ("SDO upload 0x6064:00 from slave 0: ...") without
	/// knowing which error it caught. Each derived error overrides it.
	[[noreturn]] virtual void rethrowWithPrefix(std::string_view prefix) const;

private:
	int errno_;
	std::optional<std::uint8_t> errorStatus_;
};

} // namespace ecmxf
