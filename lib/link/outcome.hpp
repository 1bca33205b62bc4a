// SPDX-License-Identifier: MIT
// Internal: the one map from a command's outcome on a Link (RawResult) to
// ecmxf::Error, in the field's words, whatever the link
// (lib/link/outcome.cpp); the checks every link's reset() shares
// (lib/link/link.cpp).
#pragma once

#include <ecmxf/link/link.hpp>

namespace ecmxf::detail {

/// The linkFailure of a result fetch (RawRequest::fetchesPrevious) whose
/// async command failed, on every link.
inline constexpr const char *kFetchNotSent = "not sent: the async command it fetches the result of failed";

/// Throws the ecmxf::Error that says why @p req failed on @p link with
/// @p res (res.status != 0): "<COMMAND>: <what happened>", errno
/// -res.status, the chip's error status where it told one.
[[noreturn]] void throwOutcome(const Link &link, const RawRequest &req, const RawResult &res);

/// Throws ecmxf::Error (EINVAL) naming @p link when @p param does not suit
/// a reset of @p kind (ASYNCCMD_RESET: bits 0..2; the others: none).
void checkReset(const Link &link, LinkReset kind, std::uint32_t param);

} // namespace ecmxf::detail
