// SPDX-License-Identifier: MIT
// Internal: the one pcapng block writer of the library (Documentation/
// trace.rst, "pcapng"). The live trace (TraceWriter, a trace file name
// ending in .pcapng) and the converter of text traces (traceToPcapng(),
// lib/trace/pcapng.cpp) both write through it. It stands in the link layer
// because the live trace's writer does (the trace layer is above link).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ecmxf-proto.h"
#include "link/trace_file.hpp"

namespace ecmxf::detail {

/// Writes one pcapng file (one Section Header Block, an Interface
/// Description Block per link type at its first packet, one Enhanced
/// Packet Block per packet). packet() is noexcept and allocates nothing:
/// blocks are built in a buffer allocated with the writer; a failed write
/// is remembered and reported by close().
class PcapngWriter
{
public:
	/// The link types (LINKTYPE_USER0..2, DLT 147..149).
	enum class Link : std::uint16_t {
		Spi = 147,    ///< one ECM-XF SPI packet, start word to end word
		Kernel = 148, ///< a kernel link record: int32 LE status, header 0x04..0x17, data
		Sk = 149,     ///< one ECM-SK frame
	};
	/// epb_flags bits 0-1 (the direction).
	static constexpr std::uint32_t kInbound = 1;  ///< chip to host (MISO, response)
	static constexpr std::uint32_t kOutbound = 2; ///< host to chip (MOSI, request)
	/// epb_flags bits 5-8 (FCS length) = 1: an ECM-SK frame whose CRC-8
	/// (byte 3) is in force; 0: not checked (Documentation/trace.rst).
	static constexpr std::uint32_t kFcsLen1 = 1u << 5;
	/// The largest packet kept whole; longer ones are cut (captured
	/// length < original length).
	static constexpr std::size_t kSnapLen = 4096;

	/// Creates or truncates @p path and writes the Section Header Block.
	/// Throws ecmxf::Error with the path (or @p shownAs, when given: the
	/// name a temporary file stands for) and the system's reason.
	/// @p bufferSize as TraceFile's.
	explicit PcapngWriter(std::string_view path, std::string_view shownAs = {}, std::size_t bufferSize = 0);
	PcapngWriter(const PcapngWriter &) = delete;
	PcapngWriter &operator=(const PcapngWriter &) = delete;

	/// One Enhanced Packet Block on @p link at @p ns (written in µs,
	/// if_tsresol 6), direction @p flags; the packet is @p a, @p b and
	/// @p c one after the other.
	void packet(Link link, std::uint64_t ns, std::uint32_t flags, std::span<const std::uint8_t> a,
		    std::span<const std::uint8_t> b = {}, std::span<const std::uint8_t> c = {}) noexcept;

	/// Flushes and closes; throws ecmxf::Error when any write failed.
	void close();
	[[nodiscard]] const std::string &path() const noexcept { return file_.path(); }
	[[nodiscard]] std::uint64_t packets() const noexcept { return packets_; }

private:
	std::uint32_t interface(Link link) noexcept;

	TraceFile file_;
	std::uint64_t packets_ = 0;
	/// interface id of each link type (index: type - 147), -1: none yet
	std::array<int, 3> ids_{ -1, -1, -1 };
	int nextId_ = 0;
	/// one block: header 28, the packet, options 12, trailer 4
	std::array<std::uint8_t, 28 + kSnapLen + 12 + 4> buf_{};
};

} // namespace ecmxf::detail
