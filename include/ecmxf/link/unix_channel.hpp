// SPDX-License-Identifier: MIT
/**
 * @file unix_channel.hpp
 * @brief An `ecmxf-sim --socket PATH` server as a ByteChannel ("unix:PATH"
 *        URIs).
 *
 * UnixChannel connects to the Unix stream socket of an ecmxf-sim server
 * and speaks its wire protocol (Documentation/sim-wire-protocol.rst):
 * exchange() is an 'X' request, waitReady() polls 'L' and advances time
 * with 'A', now() is 'T', sleepFor() is 'A'. The chip lives in the server,
 * so its state (slave states, mailboxes, counters) survives between
 * connections, like a real device between program runs.
 *
 * Time: the channel's clock is the server chip's clock. Without
 * `--paced` that is virtual time, moved only by exchanges and by this
 * channel's 'A' requests: timeouts and the protocol core's deadlines
 * behave exactly as over the in-process SimChannel (deterministic, as
 * fast as the CPU allows). With `--paced` the server's time follows the
 * wall clock and waiting polls until it has passed.
 *
 * At connect the channel sends the hello request 'H' and requires the
 * answer 'H' + kHelloMagic + u16 kProtocolVersion; anything else (another
 * program on the socket, a server of another protocol version) is refused
 * with ecmxf::Error (EPROTO) naming the path and what came back. A server
 * that serves another client answers 'B' (busy) and the channel throws
 * EBUSY.
 */
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>

namespace ecmxf {

/// Byte channel to an ecmxf-sim server over its Unix socket.
class ECMXF_EXPORT UnixChannel : public ByteChannel
{
public:
	/// The 8 bytes after 'H' in the hello reply.
	static constexpr std::string_view kHelloMagic = "ECMXFSIM";
	/// The wire protocol version the channel speaks (u16 after the magic).
	static constexpr std::uint16_t kProtocolVersion = 1;
	/// How long the hello may take (wall clock) before the peer is taken
	/// for something else than ecmxf-sim. Later requests have no time
	/// limit: the server answers each at once.
	static constexpr std::chrono::seconds kHelloTimeout{ 5 };

	/// Connects to the ecmxf-sim server listening at @p path and checks
	/// its hello. Throws ecmxf::Error: ENAMETOOLONG for a path longer than
	/// a socket address holds, the connect errno (ENOENT, ECONNREFUSED,
	/// ENOTSOCK...) when no server listens there, EBUSY when the server
	/// serves another client, EPROTO when the peer is not ecmxf-sim,
	/// ETIMEDOUT when it does not answer the hello in kHelloTimeout. Every
	/// message starts with "unix:<path>: ".
	explicit UnixChannel(const std::string &path);
	~UnixChannel() override;

	/// 'X': the server's chip answers @p mosi in @p miso.
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override;
	/// 'L' until ready; while not ready, 'A' in steps of readyStep() until
	/// @p timeout has passed on the server's clock.
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) override;
	/// 'T': the server chip's time.
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	/// 'A': advances the server chip's time by @p duration.
	void sleepFor(std::chrono::nanoseconds duration) override;
	/// "unix:<path>".
	[[nodiscard]] std::string name() const override;

	/// The granularity of waitReady() (10 us, as SimChannel's).
	static constexpr std::chrono::nanoseconds readyStep() noexcept
	{
		return std::chrono::microseconds(10);
	}

private:
	class Impl;
	std::unique_ptr<Impl> impl_;
};

/// What a reply from an ecmxf-sim server holds (parseSimReply()).
struct SimReply {
	enum class Status {
		Complete,   ///< a whole reply: type, value, payload are set
		NeedMore,   ///< the bytes so far are the start of a reply
		Malformed,  ///< not a reply this protocol knows
	};
	Status status = Status::NeedMore;
	/// The bytes the reply takes (Complete), or at least how many are
	/// needed to go on (NeedMore).
	std::size_t size = 1;
	/// 'X', 'L', 'A', 'T', 'F', 'Q', 'H', 'E' or 'B'.
	char type = 0;
	/// 'L': the line byte; 'A'/'T': the time in ns; 'F': the status byte;
	/// 'H': the protocol version.
	std::uint64_t value = 0;
	/// 'X': the MISO bytes; 'E'/'B': the message; 'H': the magic.
	std::span<const std::uint8_t> payload;
};

/// Parses the start of @p bytes as one reply of the ecmxf-sim wire
/// protocol (no I/O; the channel's reader, and a fuzz target). Never reads
/// outside @p bytes; payload points into it.
[[nodiscard]] ECMXF_EXPORT SimReply parseSimReply(std::span<const std::uint8_t> bytes) noexcept;

} // namespace ecmxf
