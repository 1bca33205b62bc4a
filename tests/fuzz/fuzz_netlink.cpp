// SPDX-License-Identifier: MIT
/*
 * fuzz_netlink.cpp - the library's decoders of the driver's generic
 * netlink messages (ecmxf::decodeEventMessage(),
 * ecmxf::decodeCountersMessage(), include/ecmxf/events/events.hpp).
 *
 * The input is one whole netlink message (nlmsghdr, genlmsghdr,
 * attributes), run through both decoders on an exactly-sized copy (ASan
 * sees a read past it). Invariants: each decoder returns or throws
 * ecmxf::Error with EPROTO (the documented error), nothing else.
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/events/events.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::vector<std::uint8_t> msg(data, data + size);
	const std::span<const std::uint8_t> m(msg.data(), msg.size());
	try {
		(void)ecmxf::decodeEventMessage(m);
	} catch (const ecmxf::Error &e) {
		FUZZ_ASSERT(e.errnoValue() == EPROTO);
	}
	try {
		(void)ecmxf::decodeCountersMessage(m);
	} catch (const ecmxf::Error &e) {
		FUZZ_ASSERT(e.errnoValue() == EPROTO);
	}
	return 0;
}
