// SPDX-License-Identifier: MIT
// Packet traces: the writer (lib/link/trace_writer.hpp), fed by the links'
// exchange hooks and started by Device::startTrace() (Documentation/trace.rst).

#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>

#include <cinttypes>
#include <cstdio>
#include <string>

#include "ecmsk-proto.h"
#include "ecmxf-proto.h"
#include "link/trace_writer.hpp"

namespace ecmxf {

namespace detail {

namespace {

constexpr char kHex[] = "0123456789abcdef";

} // namespace

const char *checkKeyword(unsigned check) noexcept
{
	switch (check) {
	case ECMXF_CHECK_FIXED:
		return "fixed";
	case ECMXF_CHECK_CRC8:
		return "crc8";
	case ECMXF_CHECK_CCITT:
		return "ccitt";
	default:
		return "crc32";
	}
}

const char *skCrcKeyword(std::uint32_t crcBits) noexcept
{
	switch (crcBits & (ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC)) {
	case ECMSK_EX_CMD_CRC:
		return "cmdcrc";
	case ECMSK_EX_RSP_CRC:
		return "rspcrc";
	case ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC:
		return "crc";
	default:
		return "nocrc";
	}
}

TraceWriter::TraceWriter(std::string_view path) : path_(path)
{
	if (path_.ends_with(".pcapng")) {
		pcap_ = std::make_unique<PcapngWriter>(path_);
		return;
	}
	text_.emplace(path_);
	const std::string head = std::string(kTraceMagic) + "\n# libecmxf " + std::string(version()) +
				 " packet trace (Documentation/trace.rst)\n";
	put(head.data(), head.size());
}

void TraceWriter::put(const char *s, std::size_t n) noexcept
{
	if (text_)
		text_->put(s, n);
}

void TraceWriter::format(unsigned dataSize, unsigned check) noexcept
{
	if (pcap_)
		return; // pcapng: each packet carries its own check word
	char buf[64];
	const int n = std::snprintf(buf, sizeof(buf), "format %u %s\n", dataSize, checkKeyword(check));
	if (n > 0)
		put(buf, static_cast<std::size_t>(n));
}

void TraceWriter::skFormat(unsigned slotSize, std::uint32_t crcBits) noexcept
{
	skCrc_ = crcBits & (ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC);
	if (pcap_)
		return;
	char buf[64];
	const int n = std::snprintf(buf, sizeof(buf), "format ecm-sk %u %s\n", slotSize, skCrcKeyword(skCrc_));
	if (n > 0)
		put(buf, static_cast<std::size_t>(n));
}

void TraceWriter::comment(std::string_view text) noexcept
{
	if (pcap_)
		return;
	put("# ", 2);
	put(text.data(), text.size());
	put("\n", 1);
}

void TraceWriter::line(std::uint64_t ns, const char *tag, std::span<const std::uint8_t> a,
		       std::span<const std::uint8_t> b) noexcept
{
	// the largest record: a 1440-byte packet, 2 hex digits a byte and a
	// space every 4 bytes
	char buf[64 + ECMXF_PKT_MAX * 2 + ECMXF_PKT_MAX / 4 + 8];
	int n = std::snprintf(buf, 64, "%" PRIu64 ".%09" PRIu64 " %s", ns / 1'000'000'000u, ns % 1'000'000'000u,
			      tag);
	if (n < 0)
		return;
	std::size_t pos = static_cast<std::size_t>(n);
	for (const auto &part : { a, b }) {
		for (std::size_t i = 0; i < part.size() && pos + 4 < sizeof(buf); i++) {
			if (i % 4 == 0)
				buf[pos++] = ' ';
			buf[pos++] = kHex[part[i] >> 4];
			buf[pos++] = kHex[part[i] & 15];
		}
	}
	buf[pos++] = '\n';
	put(buf, pos);
}

void TraceWriter::packet(std::uint64_t ns, char dir, std::span<const std::uint8_t> bytes) noexcept
{
	if (pcap_) {
		pcap_->packet(PcapngWriter::Link::Spi, ns, dir == '>' ? PcapngWriter::kOutbound : PcapngWriter::kInbound,
			      bytes);
		return;
	}
	line(ns, dir == '>' ? ">" : "<", bytes, {});
}

void TraceWriter::skFrame(std::uint64_t ns, char dir, std::span<const std::uint8_t> frame) noexcept
{
	const bool mosi = dir == '>';
	if (pcap_) {
		const bool crc = skCrc_ & (mosi ? ECMSK_EX_CMD_CRC : ECMSK_EX_RSP_CRC);
		pcap_->packet(PcapngWriter::Link::Sk, ns,
			      (mosi ? PcapngWriter::kOutbound : PcapngWriter::kInbound) |
				      (crc ? PcapngWriter::kFcsLen1 : 0u),
			      frame);
		return;
	}
	line(ns, mosi ? ">" : "<", frame, {});
}

void TraceWriter::request(std::uint64_t ns, const RawRequest &req) noexcept
{
	// command header bytes 0x04..0x17; the index (0x0B) is the kernel's
	std::array<std::uint8_t, 20> h{};
	std::copy(req.data.begin(), req.data.end(), h.begin());
	h[4] = static_cast<std::uint8_t>(req.reserved);
	h[5] = static_cast<std::uint8_t>(req.reserved >> 8);
	h[6] = req.control;
	h[7] = 0;
	h[8] = req.code;
	h[9] = req.param;
	h[10] = static_cast<std::uint8_t>(req.len);
	h[11] = static_cast<std::uint8_t>(req.len >> 8);
	for (unsigned i = 0; i < 4; i++)
		h[12 + i] = static_cast<std::uint8_t>(req.intClear >> (8 * i));
	h[16] = req.gpioIntClear[0];
	h[17] = req.gpioIntClear[1];
	h[18] = req.gpioOut[0];
	h[19] = req.gpioOut[1];
	kernelRecord(ns, h, 0, false, req.tx);
}

void TraceWriter::response(std::uint64_t ns, const RawResult &res, std::span<const std::uint8_t> rx) noexcept
{
	const ResponseHeader &r = res.header;
	std::array<std::uint8_t, 20> h{};
	h[0] = r.crcErrCnt;
	h[1] = r.wkcErrCnt;
	h[2] = r.txFifoCnt;
	h[3] = r.rxFifoCnt;
	h[4] = r.ecatState;
	h[5] = r.errStatus;
	h[6] = r.ecmStatus;
	h[7] = r.index;
	h[8] = r.code;
	h[9] = r.ret;
	h[10] = static_cast<std::uint8_t>(r.len);
	h[11] = static_cast<std::uint8_t>(r.len >> 8);
	for (unsigned i = 0; i < 4; i++)
		h[12 + i] = static_cast<std::uint8_t>(r.intFlags >> (8 * i));
	h[16] = r.gpioIntFlag[0];
	h[17] = r.gpioIntFlag[1];
	h[18] = r.gpioIn[0];
	h[19] = r.gpioIn[1];
	kernelRecord(ns, h, res.status, true, rx);
}

void TraceWriter::kernelRecord(std::uint64_t ns, const std::array<std::uint8_t, 20> &h, int status, bool response,
			       std::span<const std::uint8_t> data) noexcept
{
	if (pcap_) {
		// Documentation/trace.rst, "pcapng": the status as int32 LE first
		std::uint8_t st[4];
		const auto u = static_cast<std::uint32_t>(status);
		for (unsigned i = 0; i < 4; i++)
			st[i] = static_cast<std::uint8_t>(u >> (8 * i));
		pcap_->packet(PcapngWriter::Link::Kernel, ns,
			      response ? PcapngWriter::kInbound : PcapngWriter::kOutbound, st, h, data);
		return;
	}
	char tag[24];
	if (response)
		std::snprintf(tag, sizeof(tag), "R %d", status);
	else
		std::snprintf(tag, sizeof(tag), "C");
	line(ns, tag, h, data);
}

void TraceWriter::close()
{
	if (pcap_)
		pcap_->close();
	else
		text_->close();
}

} // namespace detail

} // namespace ecmxf
