// SPDX-License-Identifier: MIT
/*
 * fuzz.h - what the fuzz targets share with their replay test
 *
 * Every fuzz target defines the libFuzzer entry point.  Built with
 * -fsanitize=fuzzer it is a libFuzzer binary; built normally it is linked
 * into test-fuzz-replay, which calls it on the seed corpus and on inputs
 * from a fixed-seed PRNG.
 */
#ifndef ECMXF_TESTS_FUZZ_H
#define ECMXF_TESTS_FUZZ_H

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/*
 * Printed with a failed invariant, before abort(): the replay test sets it
 * to the name of the input being run.
 */
extern const char *ecmxf_fuzz_context;

#endif /* ECMXF_TESTS_FUZZ_H */
