// SPDX-License-Identifier: MIT
/*
 * fuzz_network.cpp - the simulator's network-file parser
 * (ecmxf::sim::Network::fromText(), Documentation/simulator.rst).
 *
 * The input is the text of a network file. Invariants: the parser either
 * returns a network of at most 128 slaves (the chip's limit), each with a
 * type name and process-data sizes it can state, or throws one of the
 * exceptions it documents (std::invalid_argument / std::runtime_error),
 * never anything else, and never crashes, hangs or reads out of bounds;
 * an error's message holds no control byte (the file's bytes escaped).
 * Inputs above 4 KiB are cut (a network of 128 slaves with options fits).
 */
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include <ecmxf/sim/network.hpp>

#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string text(reinterpret_cast<const char *>(data), size < 4096 ? size : 4096);
	try {
		ecmxf::sim::Network net = ecmxf::sim::Network::fromText(text, "fuzz");
		FUZZ_ASSERT(net.size() <= 128);
		for (std::size_t i = 0; i < net.size(); i++) {
			const ecmxf::sim::Slave &s = net.at(i);
			FUZZ_ASSERT(!s.typeName().empty());
			FUZZ_ASSERT(s.outputBytes() <= 1408 && s.inputBytes() <= 1408);
			FUZZ_ASSERT(s.sii().size() >= 64);
		}
	} catch (const std::invalid_argument &e) {
		// what the message quotes of the file is escaped: no control byte
		// reaches a terminal (issue 29)
		for (const char *p = e.what(); *p; p++)
			FUZZ_ASSERT(static_cast<unsigned char>(*p) >= 0x20 && *p != 0x7F);
	} catch (const std::runtime_error &) {
	}
	return 0;
}
