// SPDX-License-Identifier: MIT
/*
 * fuzz_sim_reply.cpp - the ecmxf-sim wire protocol's reply parser
 * (ecmxf::parseSimReply(), include/ecmxf/link/unix_channel.hpp), which
 * UnixChannel runs on whatever a peer of a unix: URI sends.
 *
 * The input is a byte stream as a peer would send it; it is parsed reply
 * by reply, each time on an exactly-sized copy of the rest (ASan sees any
 * read past it). Invariants:
 *  - NeedMore asks for more bytes than there are, Complete takes at most
 *    what there is (and at least the type byte), Malformed only for a
 *    type byte the protocol does not have;
 *  - a Complete reply's payload lies inside the input, and its length is
 *    the u16 of the variable-length replies ('X', 'E', 'B') or the 8-byte
 *    magic of 'H';
 *  - parsing a prefix of a Complete reply asks for more, never for less
 *    than the prefix.
 */
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string_view>
#include <vector>

#include <ecmxf/link/unix_channel.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

bool knownType(std::uint8_t t)
{
	return std::string_view("XLATFQHEB").find(static_cast<char>(t)) != std::string_view::npos;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	using S = ecmxf::SimReply::Status;
	std::size_t off = 0;

	while (off <= size) {
		const std::size_t rest = size - off;
		const std::vector<std::uint8_t> copy(data + off, data + size);
		const std::span<const std::uint8_t> in(copy.data(), copy.size());
		const ecmxf::SimReply r = ecmxf::parseSimReply(in);

		if (r.status == S::NeedMore) {
			FUZZ_ASSERT(r.size > rest);
			FUZZ_ASSERT(r.payload.empty());
			break;
		}
		if (r.status == S::Malformed) {
			FUZZ_ASSERT(rest > 0 && !knownType(copy[0]));
			break;
		}
		FUZZ_ASSERT(rest > 0 && knownType(copy[0]));
		FUZZ_ASSERT(r.type == static_cast<char>(copy[0]));
		FUZZ_ASSERT(r.size >= 1 && r.size <= rest);
		if (!r.payload.empty()) {
			FUZZ_ASSERT(r.payload.data() >= copy.data());
			FUZZ_ASSERT(r.payload.data() + r.payload.size() <= copy.data() + r.size);
		}
		if (r.type == 'X' || r.type == 'E' || r.type == 'B')
			FUZZ_ASSERT(r.payload.size() == static_cast<std::size_t>(copy[1] | (copy[2] << 8)) &&
				    r.size == 3 + r.payload.size());
		if (r.type == 'H')
			FUZZ_ASSERT(r.payload.size() == ecmxf::UnixChannel::kHelloMagic.size());

		// every proper prefix of the reply needs more
		const std::size_t cut = r.size - 1 - (r.size > 1 ? copy[r.size - 1] % (r.size - 1) : 0);
		const ecmxf::SimReply p = ecmxf::parseSimReply(in.first(cut));
		FUZZ_ASSERT(p.status == S::NeedMore && p.size > cut && p.size <= r.size);

		off += r.size;
	}
	return 0;
}
