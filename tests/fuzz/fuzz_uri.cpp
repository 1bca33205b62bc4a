// SPDX-License-Identifier: MIT
/*
 * fuzz_uri.cpp - the device URI parser (ecmxf::parseDeviceUri(),
 * include/ecmxf/device_uri.hpp): the ECM-XF's forms and the ECM-SK's
 * (sk-sim:, sk-unix:, sk-spidev:, sk-usb:; seeds corpus/uri/sk-*).
 *
 * Invariants: a URI either parses or throws ecmxf::Error with EINVAL and a
 * message; parsing is deterministic (the same text twice gives the same
 * kind); a URI parses to an ECM-SK kind exactly when it starts with "sk-",
 * and an ECM-SK kind has a slot size of 12 or 16, extension bits 0..3 and,
 * for sk-spidev:, a Busy line; nothing else is thrown.
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
			FUZZ_ASSERT(u.isSk() == uri.starts_with("sk-"));
			if (u.isSk()) {
				FUZZ_ASSERT(u.skSlotSize == 12 || u.skSlotSize == 16);
				FUZZ_ASSERT(u.skExtensions <= 3);
				FUZZ_ASSERT(u.kind != ecmxf::DeviceUri::Kind::SkSpidev || u.spidev.int0.has_value());
			}
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
