// SPDX-License-Identifier: MIT
/**
 * @file trace.hpp
 * @brief Packet traces: the text format Device::startTrace() writes and a
 *        decoder that turns one into a readable protocol log.
 *
 * A trace records every exchange of a device with its transport's clock:
 * for byte transports each MOSI and MISO packet, for the kernel transport
 * each command's request and response headers and data. The format is
 * line-based text, documented in Documentation/trace.rst:
 *
 *   ecmxf-trace 1
 *   format 112 fixed
 *   0.000150000 > a4a3a2a1 00000000 ...     (MOSI packet, hex)
 *   0.000153000 < a4a3a2a1 ...              (MISO packet)
 *   1.250000000 C <header bytes 0x04..0x17> <data>   (kernel: request)
 *   1.250400000 R <status> <header 0x04..0x17> <data> (kernel: response)
 *
 * An ECM-SK trace (sk::Board::startTrace()) has the format line
 * "format ecm-sk <12|16> <crc|nocrc|cmdcrc|rspcrc>" and then ">" / "<"
 * records of whole frames (504 or 512 bytes); decodeTrace() shows their
 * CRC-8, slot 0, the slave slots in use and the SDO slot.
 *
 * decodeTrace() prints each packet like a protocol analyzer: header fields
 * by name, data bytes, the check word verdict, and for each response the
 * command it answers (one exchange late), following CRC_TYPE_SET,
 * SPI_RECONFIG_OP and WARM_RESET.
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/protocol.hpp> // kTraceMagic

namespace ecmxf {

/// How decodeTrace() prints.
struct TraceDecodeOptions {
	/// One JSON array of packet objects instead of the text log.
	bool json = false;
	/// Data bytes per hex line in the text log.
	std::size_t bytesPerLine = 16;
};

/// What decodeTrace() saw.
struct TraceSummary {
	std::size_t packets = 0;    ///< MOSI + MISO packets and kernel records
	std::size_t commands = 0;   ///< MOSI packets and kernel requests
	std::size_t responses = 0;  ///< MISO packets and kernel responses
	std::size_t bad = 0;        ///< packets with a check/start/end/length fault (not-ready included)
	std::size_t notReady = 0;   ///< MISO packets with the "not ready" check word 0x87654321
	/// ECM-SK frames (counted in packets, commands or responses too; a
	/// CRC-8 in force that does not match counts as bad)
	std::size_t skFrames = 0;
};

/// Reads a trace from @p in and writes the decoded log to @p out. Throws
/// ecmxf::Error (EINVAL) naming the line for input that is not a trace
/// (missing magic line, bad time, unknown record, bad hex, a packet size
/// outside 64..1440 bytes).
ECMXF_EXPORT TraceSummary decodeTrace(std::istream &in, std::ostream &out, const TraceDecodeOptions &options = {});

/// Converts the text trace read from @p in to a pcapng file at @p path
/// (Documentation/trace.rst, "pcapng"): one Enhanced Packet Block per
/// record (MOSI and MISO packets on LINKTYPE_USER0, kernel records on
/// USER1), with its time and direction. The file appears only when the
/// whole trace converted: a regular file (or a new one) is written under
/// a temporary name beside it and renamed at the end; any other file
/// (/dev/stdout, a pipe) is written in place. Throws ecmxf::Error naming
/// the line for a bad trace (as decodeTrace()), or with the path and the
/// system's reason when the file cannot be written; then no file is left
/// under @p path's name that was not there before. Returns the counts
/// (packets, commands, responses; bad is not counted: the packets are
/// not verified).
ECMXF_EXPORT TraceSummary traceToPcapng(std::istream &in, std::string_view path);

} // namespace ecmxf
