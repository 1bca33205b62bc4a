// SPDX-License-Identifier: MIT
/**
 * @file slot_link.hpp
 * @brief The ECM-SK's link: the slot protocol over a ByteChannel.
 *
 * SlotLink runs the slot protocol core (lib/core/ecmsk-*.c) over a
 * ByteChannel: one whole frame per exchange, the answer one exchange
 * late, Busy before each transfer, the CRC-8, and what lasts between
 * exchanges (the long commands SET_STATE, SDO and GO_HOME, the cyclic
 * commands staged and in flight). It is to the ECM-SK what ecmxf::Link is
 * to the ECM-XF: sk::Board owns one, and the view classes
 * (<ecmxf/sk/board_views.hpp>) run their commands on it. Before the
 * shared vocabulary it was the private Board::Link.
 *
 * Thread safety: none; one thread uses a SlotLink at a time.
 */
#pragma once

#include <cstddef>
#include <memory>
#include <string_view>
#include <utility>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/sk/types_sk.hpp>

namespace ecmxf::sk {

class SimBoard;
class SimBoardChannel;

/// The slot protocol over one channel.
class ECMXF_EXPORT SlotLink
{
public:
	/// Runs over @p channel with @p options. Throws ecmxf::Error (EINVAL)
	/// for no channel, a bad slot size or extension bits.
	explicit SlotLink(std::unique_ptr<ByteChannel> channel, LinkOptions options = {});
	/// Runs over the in-process simulated board of @p channel, which
	/// simulator() then gives (no downcast of a channel: the link is told).
	explicit SlotLink(std::unique_ptr<SimBoardChannel> channel, LinkOptions options = {});
	~SlotLink();
	SlotLink(const SlotLink &) = delete;
	SlotLink &operator=(const SlotLink &) = delete;

	[[nodiscard]] ByteChannel &channel() noexcept { return *channel_; }
	/// The simulated board it was given with its channel, else null.
	[[nodiscard]] SimBoard *simulator() noexcept;
	/// 12 or 16.
	[[nodiscard]] unsigned slotSize() const noexcept;
	/// Slave slots of the frame: 40 or 30.
	[[nodiscard]] unsigned maxSlaves() const noexcept;
	/// 504 or 512.
	[[nodiscard]] std::size_t frameSize() const noexcept;
	/// The state of the last response (no exchange).
	[[nodiscard]] ecmxf::State state() const noexcept;

	/// Records every exchange from now on to @p path (created or
	/// truncated): each MOSI frame with the channel's clock just before
	/// the transfer, each MISO frame with the clock just after it; text
	/// ("format ecm-sk <slot size> <crc>", then ">"/"<" records) or, for a
	/// name ending in ".pcapng", pcapng (LINKTYPE_USER2), as
	/// Documentation/trace.rst describes. Replaces a trace already
	/// running. Throws ecmxf::Error with the path and the system's reason.
	/// Recording allocates nothing per exchange.
	void startTrace(std::string_view path);
	/// Closes the trace; throws ecmxf::Error ("writing the trace file
	/// \"<path>\" failed: <reason>") when any write failed. No-op without
	/// a trace. A link destroyed while tracing closes the file silently.
	void stopTrace();
	/// Is a trace being recorded?
	[[nodiscard]] bool tracing() const noexcept;

	/// The protocol state the view classes work on (lib/sk/slot_link.hpp;
	/// not for applications).
	struct Impl;
	[[nodiscard]] Impl &impl() noexcept { return *impl_; }
	[[nodiscard]] const Impl &impl() const noexcept { return *impl_; }

private:
	SlotLink(std::pair<std::unique_ptr<ByteChannel>, SimBoard *> channel, LinkOptions options);

	std::unique_ptr<ByteChannel> channel_;
	std::unique_ptr<Impl> impl_;
};

} // namespace ecmxf::sk
