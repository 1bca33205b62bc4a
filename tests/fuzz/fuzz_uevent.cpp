// SPDX-License-Identifier: MIT
/*
 * fuzz_uevent.cpp - the HID uevent parser that finds the ECM-SK on USB
 * (ecmxf::parseHidUevent(), include/ecmxf/link/hidraw_channel.hpp; seeds
 * corpus/uevent/).
 *
 * Invariants: parsing never throws and is deterministic; it succeeds
 * exactly when the text has a HID_ID line of the form BBBB:VVVVVVVV:PPPPPPPP
 * (hex) whose vendor and product fit 16 bits, and then the IDs are the
 * ones on that line (checked against a second reading here); a failure
 * leaves the output as it was.
 */
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include <ecmxf/link/hidraw_channel.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

/// The last HID_ID line's three fields, read another way (strtoul).
bool independentId(std::string_view text, unsigned long &bus, unsigned long &vendor, unsigned long &product)
{
	bool found = false, ok = false;
	std::size_t pos = 0;
	while (pos <= text.size()) {
		const auto nl = text.find('\n', pos);
		const std::string line(text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos));
		if (line.rfind("HID_ID=", 0) == 0) {
			found = true;
			const std::string v = line.substr(7);
			ok = v.size() == 22 && v[4] == ':' && v[13] == ':';
			for (std::size_t i = 0; ok && i < v.size(); i++)
				ok = (i == 4 || i == 13) ? true : std::isxdigit(static_cast<unsigned char>(v[i])) != 0;
			if (ok) {
				bus = std::strtoul(v.substr(0, 4).c_str(), nullptr, 16);
				vendor = std::strtoul(v.substr(5, 8).c_str(), nullptr, 16);
				product = std::strtoul(v.substr(14, 8).c_str(), nullptr, 16);
				ok = vendor <= 0xFFFF && product <= 0xFFFF;
			}
			if (!ok)
				return false; // the parser stops at a bad HID_ID line
		}
		if (nl == std::string_view::npos)
			break;
		pos = nl + 1;
	}
	return found && ok;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string_view text(reinterpret_cast<const char *>(data), size);
	ecmxf::HidrawDevice a, b;
	a.node = b.node = "untouched";
	a.vendor = b.vendor = 0x1234;
	const bool ra = ecmxf::parseHidUevent(text, a);
	const bool rb = ecmxf::parseHidUevent(text, b);
	FUZZ_ASSERT(ra == rb);
	FUZZ_ASSERT(a.vendor == b.vendor && a.product == b.product && a.bus == b.bus && a.name == b.name);
	FUZZ_ASSERT(a.node == "untouched");
	unsigned long bus = 0, vendor = 0, product = 0;
	const bool ri = independentId(text, bus, vendor, product);
	FUZZ_ASSERT(ra == ri);
	if (ra) {
		FUZZ_ASSERT(a.bus == bus && a.vendor == vendor && a.product == product);
	} else {
		FUZZ_ASSERT(a.vendor == 0x1234 && a.name.empty());
	}
	return 0;
}
