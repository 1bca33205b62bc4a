// SPDX-License-Identifier: MIT
// Counts every heap allocation of the process: a test or benchmark binary
// that links tests/common/alloc_counter.cpp gets the global operator
// new/delete replaced by counting versions (one binary per use, since the
// replacement is process-wide).
#pragma once

#include <cstdint>

namespace ecmxf_test {

/// operator new calls (all forms) since the program started.
[[nodiscard]] std::uint64_t allocations() noexcept;

} // namespace ecmxf_test
