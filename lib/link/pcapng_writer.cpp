// SPDX-License-Identifier: MIT
// The pcapng block writer (lib/link/pcapng_writer.hpp). Block layouts:
// the PCAP Next Generation Dump File Format (IETF draft
// draft-ietf-opsawg-pcapng-02), sections 4.1 (Section Header Block), 4.2
// (Interface Description Block, if_tsresol) and 4.3 (Enhanced Packet
// Block, epb_flags); link types 147..149: the tcpdump.org list of link
// types (LINKTYPE_USER0..2).

#include <ecmxf/protocol.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "base/bytes.hpp"
#include "link/pcapng_writer.hpp"

namespace ecmxf::detail {

namespace {

constexpr std::uint32_t kShb = 0x0A0D0D0A, kIdb = 1, kEpb = 6;
constexpr std::uint16_t kOptEnd = 0, kShbUserAppl = 4, kIfName = 2, kIfTsresol = 9, kEpbFlags = 2;

std::size_t pad4(std::size_t n) noexcept
{
	return (n + 3) & ~std::size_t(3);
}

/// An option at @p p: code, length, value padded to 4; returns its size.
std::size_t option(std::uint8_t *p, std::uint16_t code, const void *v, std::size_t n) noexcept
{
	put16(p, code);
	put16(p + 2, static_cast<std::uint32_t>(n));
	std::memset(p + 4, 0, pad4(n));
	if (n)
		std::memcpy(p + 4, v, n);
	return 4 + pad4(n);
}

const char *linkName(PcapngWriter::Link l) noexcept
{
	switch (l) {
	case PcapngWriter::Link::Spi:
		return "ecmxf SPI packets";
	case PcapngWriter::Link::Kernel:
		return "ecmxf kernel link records";
	default:
		return "ecmsk frames";
	}
}

} // namespace

PcapngWriter::PcapngWriter(std::string_view path, std::string_view shownAs, std::size_t bufferSize)
	: file_(path, shownAs, bufferSize)
{
	std::uint8_t *b = buf_.data();
	put32(b, kShb);
	put32(b + 8, 0x1A2B3C4D); // byte-order magic
	put16(b + 12, 1);         // version 1.0
	put16(b + 14, 0);
	put32(b + 16, 0xFFFFFFFF); // section length: not given
	put32(b + 20, 0xFFFFFFFF);
	std::size_t n = 24;
	char appl[64];
	const int an = std::snprintf(appl, sizeof(appl), "libecmxf %.*s", static_cast<int>(version().size()),
				     version().data());
	n += option(b + n, kShbUserAppl, appl, static_cast<std::size_t>(std::max(an, 0)));
	n += option(b + n, kOptEnd, nullptr, 0);
	put32(b + 4, static_cast<std::uint32_t>(n + 4));
	put32(b + n, static_cast<std::uint32_t>(n + 4));
	file_.put(b, n + 4);
}

std::uint32_t PcapngWriter::interface(Link link) noexcept
{
	const std::size_t k = static_cast<std::size_t>(link) - 147;
	if (ids_[k] >= 0)
		return static_cast<std::uint32_t>(ids_[k]);
	ids_[k] = nextId_++;
	std::uint8_t *b = buf_.data();
	put32(b, kIdb);
	put16(b + 8, static_cast<std::uint32_t>(link));
	put16(b + 10, 0);
	put32(b + 12, kSnapLen);
	std::size_t n = 16;
	const std::uint8_t tsresol = 6; // 10^-6 s
	n += option(b + n, kIfTsresol, &tsresol, 1);
	const char *name = linkName(link);
	n += option(b + n, kIfName, name, std::strlen(name));
	n += option(b + n, kOptEnd, nullptr, 0);
	put32(b + 4, static_cast<std::uint32_t>(n + 4));
	put32(b + n, static_cast<std::uint32_t>(n + 4));
	file_.put(b, n + 4);
	return static_cast<std::uint32_t>(ids_[k]);
}

void PcapngWriter::packet(Link link, std::uint64_t ns, std::uint32_t flags, std::span<const std::uint8_t> a,
			  std::span<const std::uint8_t> b, std::span<const std::uint8_t> c) noexcept
{
	const std::uint32_t id = interface(link);
	const std::size_t orig = a.size() + b.size() + c.size();
	const std::size_t cap = std::min(orig, kSnapLen);
	std::uint8_t *p = buf_.data();
	const std::uint64_t us = ns / 1000u;
	put32(p, kEpb);
	put32(p + 8, id);
	put32(p + 12, static_cast<std::uint32_t>(us >> 32));
	put32(p + 16, static_cast<std::uint32_t>(us));
	put32(p + 20, static_cast<std::uint32_t>(cap));
	put32(p + 24, static_cast<std::uint32_t>(orig));
	std::size_t n = 28;
	for (const auto &part : { a, b, c }) {
		const std::size_t k = std::min(part.size(), 28 + cap - n);
		if (k)
			std::memcpy(p + n, part.data(), k);
		n += k;
	}
	while (n & 3)
		p[n++] = 0;
	std::uint8_t fl[4];
	put32(fl, flags);
	n += option(p + n, kEpbFlags, fl, 4);
	n += option(p + n, kOptEnd, nullptr, 0);
	put32(p + 4, static_cast<std::uint32_t>(n + 4));
	put32(p + n, static_cast<std::uint32_t>(n + 4));
	file_.put(p, n + 4);
	packets_++;
}

void PcapngWriter::close()
{
	file_.close();
}

} // namespace ecmxf::detail
