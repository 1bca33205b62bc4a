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
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/*
 * Printed with a failed invariant, before abort(): the replay test sets it
 * to the name of the input being run.
 */
extern const char *ecmxf_fuzz_context;

/* A failed invariant: where, what and on which input; then abort(). */
[[noreturn]] inline void ecmxf_fuzz_fail(const char *file, int line,
					 const char *what)
{
	std::fprintf(stderr, "%s:%d: fuzz invariant violated: %s\n", file,
		     line, what);
	if (ecmxf_fuzz_context)
		std::fprintf(stderr, "  input: %s\n", ecmxf_fuzz_context);
	std::fflush(stderr);
	std::abort();
}

#define FUZZ_ASSERT(cond)                                               \
	do {                                                            \
		if (!(cond))                                            \
			ecmxf_fuzz_fail(__FILE__, __LINE__, #cond);     \
	} while (0)

#endif /* ECMXF_TESTS_FUZZ_H */
