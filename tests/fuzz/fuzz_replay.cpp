// SPDX-License-Identifier: MIT
/*
 * fuzz_replay.cpp - run the fuzz targets as ordinary tests
 *
 * Without libFuzzer, LLVMFuzzerTestOneInput() is an ordinary function:
 * run it on every seed in tests/fuzz/corpus/, on mutations of the seeds
 * and on inputs from a fixed-seed PRNG, so `make check` (and
 * `make check-asan`) exercise the same invariants on every build.  A
 * violated invariant aborts with the input's name on stderr.
 */
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "fuzz.h"

#ifndef ECMXF_FUZZ_CORPUS
#error "ECMXF_FUZZ_CORPUS must name the seed corpus directory"
#endif

namespace {

namespace fs = std::filesystem;

struct Seed {
	std::string name;
	std::vector<uint8_t> bytes;
};

std::vector<Seed> load_corpus()
{
	std::vector<Seed> seeds;

	for (const auto &ent : fs::recursive_directory_iterator(ECMXF_FUZZ_CORPUS)) {
		if (!ent.is_regular_file())
			continue;
		std::ifstream f(ent.path(), std::ios::binary);
		Seed s{ ent.path().string(),
			std::vector<uint8_t>(std::istreambuf_iterator<char>(f),
					     std::istreambuf_iterator<char>()) };
		seeds.push_back(std::move(s));
	}
	std::sort(seeds.begin(), seeds.end(),
		  [](const Seed &a, const Seed &b) { return a.name < b.name; });
	return seeds;
}

/*
 * Run one input from an exactly-sized heap block, as libFuzzer does.
 * With ECMXF_FUZZ_SAVE=FILE in the environment, each input is written to
 * FILE first, so after an abort FILE is the reproducer (feed it to the
 * fuzz-* binary of a `make fuzz` build).
 */
void run_one(const std::string &name, const std::vector<uint8_t> &in)
{
	static const char *save = std::getenv("ECMXF_FUZZ_SAVE");
	std::vector<uint8_t> copy(in);

	if (save) {
		std::ofstream f(save, std::ios::binary | std::ios::trunc);

		f.write(reinterpret_cast<const char *>(in.data()),
			static_cast<std::streamsize>(in.size()));
	}

	ecmxf_fuzz_context = name.c_str();
	LLVMFuzzerTestOneInput(copy.empty() ? nullptr : copy.data(),
			       copy.size());
	ecmxf_fuzz_context = nullptr;
}

} // namespace

TEST_CASE("every seed of the corpus passes", "[fuzz]")
{
	std::vector<Seed> seeds = load_corpus();

	REQUIRE(seeds.size() >= 5);
	for (const Seed &s : seeds)
		run_one(s.name, s.bytes);
	run_one("<empty input>", {});
}

TEST_CASE("mutated seeds pass", "[fuzz]")
{
	std::vector<Seed> seeds = load_corpus();
	std::mt19937 rng(0xEC3F0001u);

	REQUIRE_FALSE(seeds.empty());
	for (int i = 0; i < 1500; i++) {
		const Seed &s = seeds[rng() % seeds.size()];
		std::vector<uint8_t> in = s.bytes;
		unsigned flips = 1 + rng() % 8;

		for (unsigned k = 0; k < flips && !in.empty(); k++) {
			switch (rng() % 4) {
			case 0: /* flip a bit */
				in[rng() % in.size()] ^=
					static_cast<uint8_t>(1u << (rng() % 8));
				break;
			case 1: /* overwrite a byte */
				in[rng() % in.size()] =
					static_cast<uint8_t>(rng());
				break;
			case 2: /* cut */
				in.resize(rng() % (in.size() + 1));
				break;
			default: /* grow */
				in.push_back(static_cast<uint8_t>(rng()));
				break;
			}
		}
		run_one(s.name + " mutation #" + std::to_string(i), in);
	}
}

TEST_CASE("pseudo-random inputs pass", "[fuzz]")
{
	std::mt19937 rng(0xEC3F0002u);

	for (int i = 0; i < 3000; i++) {
		/* mostly short inputs, some of several packets */
		size_t len = (i % 10 == 0) ? rng() % 4096 : rng() % 400;
		std::vector<uint8_t> in(len);

		for (auto &b : in)
			b = static_cast<uint8_t>(rng());
		run_one("pseudo-random input #" + std::to_string(i), in);
	}
}
