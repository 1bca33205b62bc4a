// SPDX-License-Identifier: MIT
/*
 * fuzz_uri.cpp - the device URI parser (ecmxf::parseDeviceUri(),
 * include/ecmxf/device_uri.hpp).
 *
 * Invariants: a URI either parses or throws ecmxf::Error with EINVAL and a
 * message; parsing is deterministic (the same text twice gives the same
 * kind); nothing else is thrown.
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string_view uri(reinterpret_cast<const char *>(data), size);
	int first = -1;
	for (int round = 0; round < 2; round++) {
		int kind;
		try {
			const ecmxf::DeviceUri u = ecmxf::parseDeviceUri(uri);
			kind = static_cast<int>(u.kind);
		} catch (const ecmxf::Error &e) {
			FUZZ_ASSERT(e.errnoValue() == EINVAL);
			FUZZ_ASSERT(e.what()[0] != '\0');
			kind = -2;
		}
		if (round == 0)
			first = kind;
		else
			FUZZ_ASSERT(kind == first);
	}
	return 0;
}
