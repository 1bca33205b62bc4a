// SPDX-License-Identifier: MIT
/*
 * fuzz_scope.cpp - the scope's signal texts (ecmxf::Recorder::add(),
 * include/ecmxf/scope/recorder.hpp) over a fixed process image of two
 * slaves, and a trigger on each signal that was accepted.
 *
 * Input: signal texts separated by '\n' (at most 16). Invariants: a text
 * is accepted or refused with ecmxf::Error EINVAL whose message starts
 * with 'scope signal "' and names the text (quoted); nothing else is
 * thrown; an accepted signal keeps its text as its name, a label naming
 * its slave ("slave N ") or a cycle figure, and is found again by a
 * trigger (arm() accepts numeric ones, refuses the others with EINVAL);
 * samples then read each signal, never more than the capacity.
 */
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

ecmxf::ProcessImage image()
{
	ecmxf::SlavePdos a;
	a.outputs = { { 0x1600, 0x6040, 0, 16, 0, "Controlword" }, { 0x1600, 0x607A, 0, 32, 16, "Target position" } };
	a.inputs = { { 0x1A00, 0x6041, 0, 16, 0, "Statusword" },
		     { 0x1A00, 0x6064, 0, 32, 16, "Position actual value" },
		     { 0x1A00, 0x0000, 0, 4, 48, "" },
		     { 0x1A00, 0x2000, 1, 12, 52, "" } };
	a.outputBytes = 6;
	a.inputBytes = 8;
	ecmxf::SlavePdos b;
	b.inputs = { { 0x1A00, 0x60FD, 0, 32, 0, "Digital inputs" }, { 0x1A00, 0x6000, 1, 1, 32, "Input 1" } };
	b.inputBytes = 5;
	return ecmxf::ProcessImage({ a, b });
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	ecmxf::ProcessImage img = image();
	for (std::size_t i = 0; i < img.inputs().size() && i < size; i++)
		img.inputs()[i] = data[i];
	ecmxf::Recorder rec(8);
	std::vector<std::string> accepted;
	std::string_view in(reinterpret_cast<const char *>(data), size);
	for (int n = 0; n < 16 && !in.empty(); n++) {
		const auto nl = in.find('\n');
		const std::string_view text = in.substr(0, nl);
		in = nl == std::string_view::npos ? std::string_view() : in.substr(nl + 1);
		try {
			const std::size_t k = rec.add(img, text);
			FUZZ_ASSERT(k == accepted.size());
			const ecmxf::RecordedSignal &s = rec.signals()[k];
			FUZZ_ASSERT(s.name == text);
			FUZZ_ASSERT(!s.label.empty());
			FUZZ_ASSERT(text.find(':') == std::string_view::npos || s.label.rfind("slave ", 0) == 0);
			accepted.emplace_back(text);
		} catch (const ecmxf::Error &e) {
			FUZZ_ASSERT(e.errnoValue() == EINVAL);
			FUZZ_ASSERT(std::string_view(e.what()).rfind("scope signal \"", 0) == 0);
		}
	}
	if (accepted.empty())
		return 0;
	for (const std::string &name : accepted) {
		ecmxf::RecorderTrigger t;
		t.edge = ecmxf::TriggerEdge::Rising;
		t.signal = name;
		t.level = 3;
		t.preSamples = 2;
		std::size_t k = 0;
		while (rec.signals()[k].name != name)
			k++;
		try {
			rec.arm(t);
			FUZZ_ASSERT(rec.signals()[k].numeric);
		} catch (const ecmxf::Error &e) {
			FUZZ_ASSERT(e.errnoValue() == EINVAL);
			FUZZ_ASSERT(!rec.signals()[k].numeric);
			continue;
		}
		ecmxf::CycleResult r;
		for (std::size_t i = 0; i < 20; i++) {
			r.wkc = static_cast<std::uint32_t>(i);
			img.inputs()[i % img.inputs().size()] ^= static_cast<std::uint8_t>(i);
			(void)rec.sample(std::chrono::milliseconds(static_cast<long>(i)), r);
			FUZZ_ASSERT(rec.size() <= rec.capacity());
		}
		FUZZ_ASSERT(rec.triggered() || rec.size() <= 2);
	}
	return 0;
}
