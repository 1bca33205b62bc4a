// SPDX-License-Identifier: MIT
// CspTrajectory: positions worked out by hand for the cosine and the
// trapezoid, exact end points, synchronized axes, argument checks.

#include <catch2/catch.hpp>

#include <array>
#include <cerrno>
#include <cstdint>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/error.hpp>

using namespace std::chrono_literals;
using Catch::Matchers::Equals;
using ecmxf::CspTrajectory;
using ecmxf::TrajectoryShape;

TEST_CASE("trajectory: cosine positions at 0, T/4, T/2, 3T/4, T", "[trajectory]")
{
	const std::array<std::int32_t, 2> from{ 0, 1000 };
	const std::array<std::int32_t, 2> to{ 100000, -9000 };
	const CspTrajectory t(from, to, 1s);
	// (1 - cos(pi u)) / 2: u = 1/4 -> 0.1464466; 1/2 -> 0.5; 3/4 -> 0.8535534
	CHECK(t.position(0, 0ms) == 0);
	CHECK(t.position(0, 250ms) == 14645);
	CHECK(t.position(0, 500ms) == 50000);
	CHECK(t.position(0, 750ms) == 85355);
	CHECK(t.position(0, 1s) == 100000);
	CHECK(t.position(0, 2s) == 100000);
	CHECK(t.position(0, -1ms) == 0);
	// axis 1: 1000 - 10000 x fraction
	CHECK(t.position(1, 250ms) == -464);
	CHECK(t.position(1, 500ms) == -4000);
	CHECK(t.position(1, 1s) == -9000);
	// pi/2 x 100000 / 1 s
	CHECK(t.peakVelocity(0) == Approx(157079.63).epsilon(1e-6));
	CHECK(t.finished(1s));
	CHECK_FALSE(t.finished(999ms));
}

TEST_CASE("trajectory: trapezoid with ramps of T/4", "[trajectory]")
{
	const std::array<std::int32_t, 1> from{ 0 };
	const std::array<std::int32_t, 1> to{ 120000 };
	const CspTrajectory t(from, to, 1s, TrajectoryShape::Trapezoid);
	// v = 4/3 x 120000 = 160000/s, a = v / 0.25 s = 640000/s^2
	// t = 0.125: a t^2 / 2 = 5000; t = 0.25: 20000; t = 0.5: 20000 + 160000 x 0.25 = 60000
	// t = 0.875: 120000 - 5000
	CHECK(t.position(0, 125ms) == 5000);
	CHECK(t.position(0, 250ms) == 20000);
	CHECK(t.position(0, 500ms) == 60000);
	CHECK(t.position(0, 750ms) == 100000);
	CHECK(t.position(0, 875ms) == 115000);
	CHECK(t.position(0, 1s) == 120000);
	CHECK(t.peakVelocity(0) == Approx(160000.0));
}

TEST_CASE("trajectory: minimum duration for a velocity limit, rounded up to the cycle", "[trajectory]")
{
	const std::array<std::int32_t, 2> from{ 0, 0 };
	const std::array<std::int32_t, 2> to{ 50000, -100000 };
	// cosine: pi/2 x 100000 / 100000 per s = 1.5707963 s -> 1571 cycles of 1 ms
	CHECK(CspTrajectory::minimumDuration(from, to, 100000.0, 1ms) == 1571ms);
	// trapezoid: 4/3 x 100000 / 200000 = 0.6667 s -> 667 ms
	CHECK(CspTrajectory::minimumDuration(from, to, 200000.0, 1ms, TrajectoryShape::Trapezoid) == 667ms);
}

TEST_CASE("trajectory: argument errors", "[trajectory]")
{
	const std::array<std::int32_t, 2> two{ 0, 0 };
	const std::array<std::int32_t, 1> one{ 0 };
	try {
		CspTrajectory t(two, one, 1s);
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("CspTrajectory: 2 start and 1 end positions (one of each per axis, at least "
					    "one axis)"));
	}
	try {
		CspTrajectory t(one, one, 0ms);
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("CspTrajectory: duration 0 ns is not positive"));
	}
}
