// SPDX-License-Identifier: MIT
// Internal: the one reader of text traces (Documentation/trace.rst, "File
// format"), shared by decodeTrace() and traceToPcapng(). It reads its
// stream in blocks and decodes the hex sixteen or eight digits at once
// (Documentation/trace.rst, "Speed"; make bench: bench-trace).
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string_view>
#include <vector>

namespace ecmxf::detail {

/// One record of a trace file.
struct TraceRecord {
	std::size_t line = 0;
	std::uint64_t ns = 0;
	/// '>' (MOSI), '<' (MISO), 'C', 'R' (kernel), 'F' (a format line:
	/// dataSize and check, or for an ECM-SK one slotSize and skCrc)
	char kind = 0;
	int status = 0; ///< R: the command's status
	unsigned dataSize = 0, check = 0; ///< F
	/// F: a "format ecm-sk" line; '>', '<': an ECM-SK frame (one is in
	/// force), else an ECM-XF packet
	bool sk = false;
	/// sk: the slot size (12 or 16) and the CRC-8 in force (ECMSK_EX_*
	/// bits: bit 0 host-to-board frames, bit 1 board-to-host frames)
	unsigned slotSize = 0, skCrc = 0;
	std::vector<std::uint8_t> bytes;  ///< the packet / header and data

	/// An ECM-SK frame whose CRC-8 (byte 3) is in force in its direction.
	[[nodiscard]] bool skCrcChecked() const noexcept
	{
		return sk && (kind == '>' || kind == '<') && (skCrc & (kind == '>' ? 1u : 2u));
	}
};

/// Reads the records of a text trace; throws ecmxf::Error (EINVAL) naming
/// the line for input that is not a trace.
class TraceReader
{
public:
	explicit TraceReader(std::istream &in);
	/// The next record into @p r (its buffer reused); false at the end
	/// of the input (which throws when there was no magic line).
	bool next(TraceRecord &r);

private:
	bool nextLine(std::string_view &line);
	bool parse(std::string_view s, TraceRecord &r);

	std::istream &in_;
	std::vector<char> buf_;
	std::size_t pos_ = 0, end_ = 0;
	bool eof_ = false;
	std::size_t line_ = 0;
	bool magic_ = false;
	/// the "format ecm-sk" line in force (its slot size, CRC-8 bits and
	/// line), slot 0: the ECM-XF's packets
	struct { unsigned slot = 0, crc = 0; std::size_t line = 0; } sk_;
};

} // namespace ecmxf::detail
