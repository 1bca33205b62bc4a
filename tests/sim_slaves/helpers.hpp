// SPDX-License-Identifier: MIT
// Helpers for the slave model tests: creating models, walking the AL state
// machine, typed SDO access, running cycles.

#pragma once

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>

namespace th {

using namespace std::chrono_literals;
using ecmxf::sim::AlState;
using ecmxf::sim::Network;
using ecmxf::sim::Slave;

inline std::unique_ptr<Slave> make(const std::string &type,
				   const std::map<std::string, std::string> &opts = {})
{
	return Network::makeSlave(type, 0, opts);
}

/// Controlwords of transitions 2, 3, 4: shutdown, switch on, enable operation.
inline constexpr std::uint16_t kEnable[] = { 0x06, 0x07, 0x0F };

inline std::uint8_t st(AlState s)
{
	return static_cast<std::uint8_t>(s);
}

/// One bus cycle with @p out as outputs (zeros when empty); returns WKC.
inline unsigned cycle(Slave &s, std::vector<std::uint8_t> out = {},
		      std::vector<std::uint8_t> *in = nullptr,
		      std::chrono::nanoseconds dt = 1ms, bool valid = true)
{
	out.resize(s.outputBytes(), 0);
	std::vector<std::uint8_t> local(s.inputBytes(), 0);
	std::vector<std::uint8_t> &inputs = in ? *in : local;
	inputs.resize(s.inputBytes(), 0);
	return s.cycle(out, valid, inputs, dt, true);
}

/// Configure DC SYNC0 at @p cycleNs (what a servo needs for OP).
inline void dc(Slave &s, std::uint32_t cycleNs = 1'000'000)
{
	s.configureDc(0x0300, cycleNs, 0, 0);
}

/// From power-on to @p target along the legal path (I->P->S->O, I->B).
/// Slaves that need DC get SYNC0 at 1 ms first.
inline void reach(Slave &s, AlState target)
{
	s.reset();
	if (s.dcAssignActivate())
		dc(s);
	if (target == AlState::Init)
		return;
	if (target == AlState::Boot) {
		s.alControl(st(AlState::Boot));
		REQUIRE(s.alStatus() == st(AlState::Boot));
		return;
	}
	s.alControl(st(AlState::PreOp));
	REQUIRE(s.alStatus() == st(AlState::PreOp));
	if (target == AlState::PreOp)
		return;
	s.alControl(st(AlState::SafeOp));
	REQUIRE(s.alStatus() == st(AlState::SafeOp));
	if (target == AlState::SafeOp)
		return;
	cycle(s); // outputs are arriving
	s.alControl(st(AlState::Op));
	REQUIRE(s.alStatus() == st(AlState::Op));
}

inline std::vector<std::uint8_t> le(std::uint64_t v, std::size_t n)
{
	std::vector<std::uint8_t> b(n);
	for (std::size_t i = 0; i < n; i++)
		b[i] = static_cast<std::uint8_t>(v >> (8 * i));
	return b;
}

template <typename T> std::uint32_t write(Slave &s, std::uint16_t idx, std::uint8_t sub, T v)
{
	return s.sdoDownload(idx, sub, false, le(static_cast<std::uint64_t>(v), sizeof(T)));
}

/// SDO upload as T; REQUIREs success and the exact size.
template <typename T> T read(Slave &s, std::uint16_t idx, std::uint8_t sub)
{
	std::vector<std::uint8_t> out;
	const std::uint32_t ab = s.sdoUpload(idx, sub, false, out);
	INFO("upload 0x" << std::hex << idx << ":" << unsigned(sub) << " abort 0x" << ab);
	REQUIRE(ab == 0);
	REQUIRE(out.size() == sizeof(T));
	T v;
	std::memcpy(&v, out.data(), sizeof v);
	return v;
}

inline std::uint32_t readAbort(Slave &s, std::uint16_t idx, std::uint8_t sub)
{
	std::vector<std::uint8_t> out;
	return s.sdoUpload(idx, sub, false, out);
}

inline std::uint16_t le16(const std::vector<std::uint8_t> &b, std::size_t at)
{
	return static_cast<std::uint16_t>(b[at] | b[at + 1] << 8);
}

inline std::uint32_t le32(const std::vector<std::uint8_t> &b, std::size_t at)
{
	return static_cast<std::uint32_t>(le16(b, at)) |
	       static_cast<std::uint32_t>(le16(b, at + 2)) << 16;
}

/// Let time pass without bus cycles.
inline void idle(Slave &s, std::chrono::nanoseconds total, std::chrono::nanoseconds step = 1ms)
{
	for (auto t = 0ns; t < total; t += step)
		s.idle(step);
}

} // namespace th

namespace th {

/// A process image under construction / being read (little-endian).
struct Image {
	std::vector<std::uint8_t> b;
	explicit Image(std::size_t n = 0) : b(n, 0) {}
	void put(std::size_t at, std::int64_t v, std::size_t n)
	{
		for (std::size_t i = 0; i < n; i++)
			b.at(at + i) = static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i));
	}
	[[nodiscard]] std::uint64_t get(std::size_t at, std::size_t n) const
	{
		std::uint64_t v = 0;
		for (std::size_t i = 0; i < n; i++)
			v |= std::uint64_t{ b.at(at + i) } << (8 * i);
		return v;
	}
	[[nodiscard]] std::int32_t i32(std::size_t at) const
	{
		return static_cast<std::int32_t>(static_cast<std::uint32_t>(get(at, 4)));
	}
	[[nodiscard]] std::uint16_t u16(std::size_t at) const
	{
		return static_cast<std::uint16_t>(get(at, 2));
	}
};

/// Replace the RxPDO (@p rx) or TxPDO assignment by @p pdos (in PRE-OP).
inline void assign(Slave &s, bool rx, const std::vector<std::uint16_t> &pdos)
{
	const std::uint16_t idx = rx ? 0x1C12 : 0x1C13;
	REQUIRE(write<std::uint8_t>(s, idx, 0, 0) == 0);
	for (std::size_t i = 0; i < pdos.size(); i++)
		REQUIRE(write<std::uint16_t>(s, idx, static_cast<std::uint8_t>(i + 1), pdos[i]) == 0);
	REQUIRE(write<std::uint8_t>(s, idx, 0, static_cast<std::uint8_t>(pdos.size())) == 0);
}

/// Replace the entries of mapping object @p pdo (in PRE-OP).
inline void mapPdo(Slave &s, std::uint16_t pdo, const std::vector<std::uint32_t> &entries)
{
	REQUIRE(write<std::uint8_t>(s, pdo, 0, 0) == 0);
	for (std::size_t i = 0; i < entries.size(); i++)
		REQUIRE(write<std::uint32_t>(s, pdo, static_cast<std::uint8_t>(i + 1), entries[i]) == 0);
	REQUIRE(write<std::uint8_t>(s, pdo, 0, static_cast<std::uint8_t>(entries.size())) == 0);
}

} // namespace th
