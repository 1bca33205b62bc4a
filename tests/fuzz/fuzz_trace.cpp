// SPDX-License-Identifier: MIT
/*
 * fuzz_trace.cpp - the trace decoder (ecmxf::decodeTrace(),
 * include/ecmxf/trace/trace.hpp; `ecmxf-util decode`).
 *
 * The input is a trace file (the seeds start with the magic line). Both
 * output forms are run. Invariants: the decoder returns a summary whose
 * counts add up (commands + responses <= packets, notReady <= bad <=
 * packets) or throws ecmxf::Error with EINVAL, nothing else. Inputs above
 * 64 KiB are cut.
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
	for (bool json : { false, true }) {
		std::istringstream in(text);
		std::ostringstream out;
		ecmxf::TraceDecodeOptions o;
		o.json = json;
		try {
			const ecmxf::TraceSummary s = ecmxf::decodeTrace(in, out, o);
			FUZZ_ASSERT(s.commands + s.responses <= s.packets);
			FUZZ_ASSERT(s.notReady <= s.bad && s.bad <= s.packets);
		} catch (const ecmxf::Error &e) {
			FUZZ_ASSERT(e.errnoValue() == EINVAL);
		}
	}
	return 0;
}
