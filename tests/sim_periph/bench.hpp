// SPDX-License-Identifier: MIT
//
// bench.hpp - drives ecmxf::sim::Peripherals the way the chip model does,
// with command packets written byte by byte at the offsets of the manuals'
// command header (Pic. 4 / 圖四):
//
//   0x04..0x07 command data 0..3     0x08 reserved (bit 15: GPIO out valid)
//   0x0B index   0x0C command code   0x0D command parameter
//   0x0E data length                 0x10 interrupt clear
//   0x14/0x15 GPIO interrupt clear   0x16/0x17 GPIO output
//   0x18...    data section
//
// and reads the response header fields back from an encoded response
// packet at the offsets of Pic. 5 / 圖五 (0x10 interrupt flags, 0x14/0x15
// GPIO interrupt flags, 0x16/0x17 GPIO inputs).

#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "ecmxf-proto.h"
#include "periph.hpp"

namespace periph_test {

constexpr std::size_t kData = ECMXF_DATA_DEFAULT;
constexpr std::size_t kPkt = ECMXF_PKT_SIZE(kData);

/// A command packet under construction.
class Cmd
{
public:
	Cmd(std::uint8_t code, std::uint8_t param)
	{
		put32(0x00, ECMXF_START_WORD);
		pkt_[0x0B] = 0x42; // index
		pkt_[0x0C] = code;
		pkt_[0x0D] = param;
	}
	/// Command data 0..3 (header 0x04..0x07).
	Cmd &cmdData(std::uint8_t d0, std::uint8_t d1 = 0, std::uint8_t d2 = 0, std::uint8_t d3 = 0)
	{
		pkt_[0x04] = d0;
		pkt_[0x05] = d1;
		pkt_[0x06] = d2;
		pkt_[0x07] = d3;
		return *this;
	}
	/// Data length field (0x0E).
	Cmd &length(std::uint16_t n)
	{
		pkt_[0x0E] = static_cast<std::uint8_t>(n);
		pkt_[0x0F] = static_cast<std::uint8_t>(n >> 8);
		return *this;
	}
	/// A little-endian 32-bit word at @p off of the data section.
	Cmd &data32(std::size_t off, std::uint32_t v)
	{
		put32(ECMXF_HDR_SIZE + off, v);
		return *this;
	}
	/// Header 0x08..0x09 (the "reserved" word; bit 15 = GPIO out valid).
	Cmd &reserved(std::uint16_t v)
	{
		pkt_[0x08] = static_cast<std::uint8_t>(v);
		pkt_[0x09] = static_cast<std::uint8_t>(v >> 8);
		return *this;
	}
	Cmd &intClear(std::uint32_t v)
	{
		put32(0x10, v);
		return *this;
	}
	Cmd &gpioIntClear(std::uint8_t lo, std::uint8_t hi)
	{
		pkt_[0x14] = lo;
		pkt_[0x15] = hi;
		return *this;
	}
	Cmd &gpioOut(std::uint8_t lo, std::uint8_t hi)
	{
		pkt_[0x16] = lo;
		pkt_[0x17] = hi;
		return *this;
	}
	/// The finished packet (fixed check word, end word).
	std::array<std::uint8_t, kPkt> bytes() const
	{
		auto p = pkt_;
		put32(p, ECMXF_HDR_SIZE + kData, ECMXF_FIXED_CHECK);
		put32(p, ECMXF_HDR_SIZE + kData + 4, ECMXF_END_WORD);
		return p;
	}

private:
	static void put32(std::array<std::uint8_t, kPkt> &p, std::size_t off, std::uint32_t v)
	{
		for (unsigned i = 0; i < 4; i++)
			p[off + i] = static_cast<std::uint8_t>(v >> (8 * i));
	}
	void put32(std::size_t off, std::uint32_t v) { put32(pkt_, off, v); }

	std::array<std::uint8_t, kPkt> pkt_{};
};

/// What one command did.
struct Result {
	ecmxf::sim::Peripherals::Reply reply;
	std::vector<std::uint8_t> data; // the first reply.len bytes of the data section

	std::uint32_t le(std::size_t off, std::size_t n) const
	{
		std::uint32_t v = 0;
		for (std::size_t i = 0; i < n; i++)
			v |= static_cast<std::uint32_t>(data.at(off + i)) << (8 * i);
		return v;
	}
};

/// The response header fields that the peripherals fill, read back from
/// the encoded packet.
struct RspFields {
	std::uint32_t intFlags;          // 0x10..0x13
	std::uint8_t gpioIntFlag[2];     // 0x14, 0x15
	std::uint8_t gpioIn[2];          // 0x16, 0x17
};

class Bench
{
public:
	ecmxf::sim::Peripherals p;

	/// Decode @p c as the chip does, pass the header, run the command.
	Result run(const Cmd &c)
	{
		const auto pkt = c.bytes();
		ecmxf_cmd_hdr hdr{};
		const std::uint8_t *data = nullptr;
		if (ecmxf_decode_cmd(pkt.data(), pkt.size(), ECMXF_CHECK_FIXED, &hdr, &data) !=
		    ECMXF_FAULT_NONE)
			throw std::logic_error("test built an invalid command packet");
		p.applyHeader(hdr);
		std::array<std::uint8_t, kData> out{};
		Result r;
		r.reply = p.handle(hdr, std::span<const std::uint8_t>(data, kData), out);
		r.data.assign(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(r.reply.len));
		return r;
	}

	RspFields header() const
	{
		ecmxf_rsp_hdr rsp{};
		rsp.int_flags = p.intFlags();
		p.fillHeader(rsp);
		std::array<std::uint8_t, kPkt> pkt{};
		if (ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_FIXED, &rsp, nullptr, 0) != 0)
			throw std::logic_error("response encoding failed");
		RspFields f{};
		f.intFlags = static_cast<std::uint32_t>(pkt[0x10]) |
			     static_cast<std::uint32_t>(pkt[0x11]) << 8 |
			     static_cast<std::uint32_t>(pkt[0x12]) << 16 |
			     static_cast<std::uint32_t>(pkt[0x13]) << 24;
		f.gpioIntFlag[0] = pkt[0x14];
		f.gpioIntFlag[1] = pkt[0x15];
		f.gpioIn[0] = pkt[0x16];
		f.gpioIn[1] = pkt[0x17];
		return f;
	}
};

// Command codes, from the manuals' command tables (decimal).
constexpr std::uint8_t kGpioConfigSet = 31;
constexpr std::uint8_t kGpioFuncOp = 32;
constexpr std::uint8_t kQeiFuncOp = 33;
constexpr std::uint8_t kDacFuncOp = 34;
constexpr std::uint8_t kAdcFuncOp = 35;
constexpr std::uint8_t kMdio = 81;

} // namespace periph_test
