// SPDX-License-Identifier: MIT
// Internal: the writer of packet traces (Documentation/trace.rst), fed by
// the links; a Device owns the one it records to (Device::startTrace()),
// an ECM-SK SlotLink its own (SlotLink::startTrace(), lib/sk/slot_link.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <ecmxf/link/link.hpp>

#include "link/pcapng_writer.hpp"

namespace ecmxf {

namespace detail {

/// The keyword of a "format" line for a check type (ECMXF_CHECK_*):
/// "fixed", "crc8", "ccitt" or "crc32". The trace reader reads the
/// keywords back through it.
const char *checkKeyword(unsigned check) noexcept;

/// The keyword of a "format ecm-sk" line for the CRC-8 bits in force
/// (ECMSK_EX_*): "nocrc", "cmdcrc", "rspcrc" or "crc" (both). The trace
/// reader reads the keywords back through it.
const char *skCrcKeyword(std::uint32_t crcBits) noexcept;

/// Writes one trace file. Every record call is noexcept and allocates
/// nothing (the exchange loop calls them); a failed write is remembered
/// and reported by close().
class TraceWriter
{
public:
	/// Creates or truncates @p path and writes the magic line, or, for a
	/// name ending in ".pcapng", a pcapng file (PcapngWriter: the packets
	/// and kernel records, no format or comment lines). Throws
	/// ecmxf::Error with the path and the system's reason.
	explicit TraceWriter(std::string_view path);
	TraceWriter(const TraceWriter &) = delete;
	TraceWriter &operator=(const TraceWriter &) = delete;

	/// "format <data size> <check>": the packet format in force.
	void format(unsigned dataSize, unsigned check) noexcept;
	/// "format ecm-sk <slot size> <crc>": from here on the records are
	/// ECM-SK frames of @p slotSize-byte slots; @p crcBits the CRC-8 in
	/// force (ECMSK_EX_CMD_CRC: host-to-board frames, ECMSK_EX_RSP_CRC:
	/// board-to-host frames). For pcapng it is remembered: each frame's
	/// epb_flags FCS length is 1 when its CRC-8 is in force.
	void skFormat(unsigned slotSize, std::uint32_t crcBits) noexcept;
	/// "# <text>".
	void comment(std::string_view text) noexcept;
	/// One packet: @p dir '>' (MOSI, host to chip) or '<' (MISO).
	void packet(std::uint64_t ns, char dir, std::span<const std::uint8_t> bytes) noexcept;
	/// One ECM-SK frame (after skFormat()): @p dir '>' (MOSI, host to
	/// board) or '<' (MISO); LINKTYPE_USER2 in pcapng.
	void skFrame(std::uint64_t ns, char dir, std::span<const std::uint8_t> frame) noexcept;
	/// A kernel request: header bytes 0x04..0x17 (index 0) and tx data.
	void request(std::uint64_t ns, const RawRequest &req) noexcept;
	/// A kernel response: status, header bytes 0x04..0x17 and rx data.
	void response(std::uint64_t ns, const RawResult &res, std::span<const std::uint8_t> rx) noexcept;

	/// Flushes and closes; throws ecmxf::Error when any write failed.
	void close();
	[[nodiscard]] const std::string &path() const noexcept { return path_; }

private:
	void line(std::uint64_t ns, const char *tag, std::span<const std::uint8_t> a,
		  std::span<const std::uint8_t> b) noexcept;
	void put(const char *s, std::size_t n) noexcept;
	void kernelRecord(std::uint64_t ns, const std::array<std::uint8_t, 20> &h, int status, bool response,
			  std::span<const std::uint8_t> data) noexcept;

	std::string path_;
	/// the pcapng writer (a .pcapng trace), or null (text)
	std::unique_ptr<PcapngWriter> pcap_;
	/// the text trace file, or none (a .pcapng trace)
	std::optional<TraceFile> text_;
	/// the ECM-SK CRC-8 in force (skFormat())
	std::uint32_t skCrc_ = 0;
};

} // namespace detail

} // namespace ecmxf
