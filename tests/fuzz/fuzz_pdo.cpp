// SPDX-License-Identifier: MIT
/*
 * fuzz_pdo.cpp - PDO mappings into a process image (ecmxf::ProcessImage,
 * include/ecmxf/pdo/process_image.hpp): the slaves' byte counts and
 * entries as Master::pdos() would fill them from whatever the slaves
 * report.
 *
 * Input: byte 0 = slaves (1..8), then per slave: output bytes, input
 * bytes, entry count (0..15) and per entry 8 bytes (direction bit, index,
 * sub, bit length, bit offset u16, T selector). Invariants: the
 * constructor accepts the mapping or throws ecmxf::Error (EINVAL); when it
 * accepts, the frames are the sums of the byte counts, each slave's
 * offset is the sum of the ones before it, and every entry is reachable
 * by a handle of a type that fits it (set() then get() gives the value
 * back, masked to the entry's width; a neighbour outside the entry is
 * untouched) or refused with EINVAL.
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/model/pdo_mapping.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

struct Reader {
	const std::uint8_t *d;
	std::size_t n, pos = 0;
	std::uint8_t u8() { return pos < n ? d[pos++] : 0; }
	std::uint16_t u16()
	{
		const unsigned lo = u8();
		return static_cast<std::uint16_t>(lo | static_cast<unsigned>(u8()) << 8);
	}
};

/// set() then get() through a handle of T on entry @p e (EINVAL when T does
/// not fit it); the frame outside the entry must not change.
template <class T>
void roundTrip(ecmxf::ProcessImage &img, std::size_t pos, const ecmxf::PdoEntryInfo &e, bool out, std::uint64_t v)
{
	try {
		const std::vector<std::uint8_t> before(img.outputs().begin(), img.outputs().end());
		if (out) {
			auto h = img.output<T>(pos, e.index, e.sub);
			h.set(static_cast<T>(v));
			const T got = h.get();
			if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
				// the entry the image resolved (the first mapped with
				// this index:sub: a mapping may name one twice)
				const unsigned bits = img.outputEntry(pos, e.index, e.sub).bitLength;
				const std::uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
				FUZZ_ASSERT((static_cast<std::uint64_t>(got) & mask) ==
					    (static_cast<std::uint64_t>(static_cast<T>(v)) & mask));
			}
			// bits outside the slave's bytes are untouched
			const std::size_t off = img.outputOffset(pos);
			const std::size_t len = img.slaveOutputs(pos).size();
			for (std::size_t i = 0; i < before.size(); i++)
				if (i < off || i >= off + len)
					FUZZ_ASSERT(img.outputs()[i] == before[i]);
		} else {
			(void)img.input<T>(pos, e.index, e.sub).get();
		}
	} catch (const ecmxf::Error &err) {
		FUZZ_ASSERT(err.errnoValue() == EINVAL);
	}
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	Reader in{ data, size };
	const unsigned n = in.u8() % 8 + 1;
	std::vector<ecmxf::SlavePdos> slaves(n);
	std::vector<std::uint8_t> sel;
	for (auto &s : slaves) {
		s.outputBytes = in.u8();
		s.inputBytes = in.u8();
		const unsigned entries = in.u8() % 16;
		for (unsigned i = 0; i < entries; i++) {
			ecmxf::PdoEntryInfo e;
			const std::uint8_t dir = in.u8();
			e.index = in.u16();
			e.sub = in.u8();
			e.bitLength = in.u8();
			e.bitOffset = in.u16();
			sel.push_back(in.u8());
			(dir & 1 ? s.outputs : s.inputs).push_back(e);
		}
	}
	std::size_t outSum = 0, inSum = 0;
	for (const auto &s : slaves) {
		outSum += s.outputBytes;
		inSum += s.inputBytes;
	}
	try {
		ecmxf::ProcessImage img(slaves);
		FUZZ_ASSERT(img.outputs().size() == outSum && img.inputs().size() == inSum);
		std::size_t o = 0, i = 0, k = 0;
		for (std::size_t p = 0; p < n; p++) {
			FUZZ_ASSERT(img.outputOffset(p) == o && img.inputOffset(p) == i);
			o += slaves[p].outputBytes;
			i += slaves[p].inputBytes;
			for (int dir = 0; dir < 2; dir++) {
				for (const auto &e : dir ? slaves[p].outputs : slaves[p].inputs) {
					const std::uint8_t t = k < sel.size() ? sel[k] : 0;
					k++;
					const std::uint64_t v = 0x8877665544332211ull * (t + 1u);
					switch (t % 6) {
					case 0: roundTrip<bool>(img, p, e, dir, v); break;
					case 1: roundTrip<std::uint8_t>(img, p, e, dir, v); break;
					case 2: roundTrip<std::int16_t>(img, p, e, dir, v); break;
					case 3: roundTrip<std::uint32_t>(img, p, e, dir, v); break;
					case 4: roundTrip<std::int64_t>(img, p, e, dir, v); break;
					default: roundTrip<double>(img, p, e, dir, v); break;
					}
				}
			}
		}
	} catch (const ecmxf::Error &err) {
		FUZZ_ASSERT(err.errnoValue() == EINVAL);
	}
	return 0;
}
