// SPDX-License-Identifier: MIT
// The suites' one "this must throw ecmxf::Error" helper.
#pragma once

#include <catch2/catch.hpp>

#include <utility>

#include <ecmxf/error.hpp>

namespace ecmxftest {

/// Runs @p f, which must throw ecmxf::Error, and returns the error (the
/// test fails when nothing or something else is thrown).
template <typename F>
ecmxf::Error thrown(F &&f)
{
	try {
		std::forward<F>(f)();
	} catch (const ecmxf::Error &e) {
		return e;
	}
	FAIL("no ecmxf::Error was thrown");
	return ecmxf::Error("unreachable", 0);
}

} // namespace ecmxftest
