// SPDX-License-Identifier: MIT
// Internal: Device::command() over a transport that runs the protocol
// itself (the kernel module), lib/link/transport_command.cpp.
#pragma once

#include <ecmxf/device.hpp>
#include <ecmxf/link/transport.hpp>

namespace ecmxf::detail {

class TraceWriter;

/// Runs @p c on @p t (recording request and response in @p trace when
/// not null) and returns the answer; throws ecmxf::Error with the same
/// messages as the protocol core's outcomes over byte transports, or
/// naming the failed call for a failure of the transport itself.
Response runOnCommandTransport(CommandTransport &t, const Command &c, TraceWriter *trace);

/// Device::transact() over @p t: runs @p c with @p payload, the answer's
/// data into @p answer, its header into @p header. Allocates nothing and
/// throws nothing (a trace, when recording, writes to its file). Returns
/// 0 or a positive errno value, as Device::transact() documents.
int transactOnCommandTransport(CommandTransport &t, const RawCommand &c, std::span<const std::uint8_t> payload,
			       std::span<std::uint8_t> answer, ResponseHeader &header, TraceWriter *trace) noexcept;

} // namespace ecmxf::detail
