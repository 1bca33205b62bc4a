// SPDX-License-Identifier: MIT
// What a motion user expects of Cyclic (issue 15): the named fill presets,
// a Cyclic refused on a bus not in SAFE-OP/OP (ENETDOWN, naming the state)
// and a second Cyclic on one Device refused (EBUSY), while one after the
// other works. Errnos as cyclic.hpp documents them.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "bus.hpp"
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxftest::thrown;
using pdotest::Bus;

TEST_CASE("Cyclic presets: motion fills 2 frames, buffered (the default) depth - 2", "[lib][pdo][cyclic]")
{
	CHECK(ecmxf::kRxFillMotion == 2);
	const ecmxf::CyclicConfig m = ecmxf::CyclicConfig::motion(2ms);
	CHECK(m.period == 2ms);
	CHECK(m.rxFill == ecmxf::kRxFillMotion);
	CHECK(ecmxf::CyclicConfig::buffered().rxFill == ecmxf::kRxFillDeep);
	CHECK(ecmxf::CyclicConfig{}.rxFill == ecmxf::kRxFillDeep);

	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	{
		ecmxf::Cyclic cyc(*bus.dev, image, ecmxf::CyclicConfig::motion());
		CHECK(cyc.rxFill() == 2);
	}
	ecmxf::Cyclic deep(*bus.dev, image, ecmxf::CyclicConfig::buffered());
	CHECK(deep.rxFill() == deep.rxDepth() - 2);
}

TEST_CASE("Cyclic: refused on a bus below SAFE-OP, with the state named", "[lib][pdo][cyclic][errors]")
{
	Bus bus;
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	// no network initialised
	ecmxf::Error e = thrown([&] { ecmxf::Cyclic c(*bus.dev, image, ecmxf::CyclicConfig::motion()); });
	CHECK(e.errnoValue() == ENETDOWN);
	CHECK_THAT(e.what(), Equals("Cyclic: the bus is in no network initialised (ECAT state 0x00): process data "
				    "needs SAFE-OP or OP; bring the bus up first (Master::bringUp(), or "
				    "Bus::stateSet() to SAFE-OP/OP)"));
	bus.init();
	e = thrown([&] { ecmxf::Cyclic c(*bus.dev, image, ecmxf::CyclicConfig::motion()); });
	CHECK(e.errnoValue() == ENETDOWN);
	CHECK_THAT(e.what(), Contains("the bus is in INIT (ECAT state 0x01)"));
	bus.state(pdotest::kPreOp);
	e = thrown([&] { ecmxf::Cyclic c(*bus.dev, image, ecmxf::CyclicConfig::motion()); });
	CHECK(e.errnoValue() == ENETDOWN);
	CHECK_THAT(e.what(), Contains("the bus is in PRE-OP (ECAT state 0x02)"));
	// SAFE-OP is enough (inputs flow), and OP
	bus.state(pdotest::kSafeOp);
	{
		ecmxf::Cyclic c(*bus.dev, image, ecmxf::CyclicConfig::motion());
		CHECK(c.rxFill() == 2);
	}
	bus.state(pdotest::kOp);
	ecmxf::Cyclic c(*bus.dev, image, ecmxf::CyclicConfig::motion());
	c.start();
	CHECK(c.cycle().error == 0);
}

TEST_CASE("Cyclic: a second one on the same Device is refused, one after the other works",
	  "[lib][pdo][cyclic][errors]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::ProcessImage image2(pdotest::defaultPdos());
	{
		ecmxf::Cyclic first(*bus.dev, image, ecmxf::CyclicConfig::motion());
		const ecmxf::Error e =
			thrown([&] { ecmxf::Cyclic second(*bus.dev, image2, ecmxf::CyclicConfig::motion()); });
		CHECK(e.errnoValue() == EBUSY);
		CHECK_THAT(e.what(), Contains("this Device already has a Cyclic"));
		// the first one is untouched
		first.start();
		CHECK(first.cycle().error == 0);
	}
	// the first is gone: a new one may come
	ecmxf::Cyclic again(*bus.dev, image2, ecmxf::CyclicConfig::motion());
	again.start();
	CHECK(again.cycle().error == 0);
	// another Device is another chip: its own Cyclic
	Bus other;
	other.toOp();
	ecmxf::Cyclic onOther(*other.dev, image, ecmxf::CyclicConfig::motion());
	CHECK(onOther.rxFill() == 2);
	// a Cyclic refused for the bus state leaves no claim behind
	Bus down;
	CHECK(thrown([&] { ecmxf::Cyclic c(*down.dev, image, {}); }).errnoValue() == ENETDOWN);
	down.toOp();
	ecmxf::Cyclic ok(*down.dev, image, {});
	CHECK(ok.rxFill() == 62);
}
