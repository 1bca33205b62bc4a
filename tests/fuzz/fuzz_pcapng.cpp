// SPDX-License-Identifier: MIT
/*
 * fuzz_pcapng.cpp - text traces to pcapng (ecmxf::traceToPcapng(),
 * include/ecmxf/trace/trace.hpp; `ecmxf-util decode --pcapng`): the text
 * trace reader (lib/trace/trace_reader.cpp: block reads, the hex pair
 * table) and the pcapng block writer (lib/link/pcapng_writer.cpp).
 *
 * The input is a trace file (the seeds are fuzz-trace's). The pcapng goes
 * to /dev/null (written in place: not a regular file). Invariants: the
 * converter and the decoder accept the same inputs, with the same packet
 * count, and reject the others with ecmxf::Error (EINVAL) and the same
 * message. Inputs above 64 KiB are cut.
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include <ecmxf/error.hpp>
#include <ecmxf/trace/trace.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string text(reinterpret_cast<const char *>(data), size < 65536 ? size : 65536);
	std::string decodeError, convertError;
	std::size_t decoded = 0, converted = 0;
	try {
		std::istringstream in(text);
		std::ostringstream out;
		decoded = ecmxf::decodeTrace(in, out).packets;
	} catch (const ecmxf::Error &e) {
		FUZZ_ASSERT(e.errnoValue() == EINVAL);
		decodeError = e.what();
	}
	try {
		std::istringstream in(text);
		const ecmxf::TraceSummary s = ecmxf::traceToPcapng(in, "/dev/null");
		FUZZ_ASSERT(s.commands + s.responses == s.packets);
		converted = s.packets;
	} catch (const ecmxf::Error &e) {
		FUZZ_ASSERT(e.errnoValue() == EINVAL);
		convertError = e.what();
	}
	FUZZ_ASSERT(decodeError == convertError);
	FUZZ_ASSERT(decoded == converted);
	return 0;
}
