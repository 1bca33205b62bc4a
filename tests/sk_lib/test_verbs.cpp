// SPDX-License-Identifier: MIT
// MasterVerbs (include/ecmxf/verbs.hpp): the same verbs on the ECM-XF's
// simulator and the ECM-SK's, what each cannot do (ENOTSUP, with why), and
// bad positions and sizes.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/model/cia402.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/verbs.hpp>

using Catch::Matchers::Contains;
using ecmxf::MasterKind;
using ecmxf::MasterVerbs;

namespace {

ecmxf::Error errorOf(auto &&fn)
{
	try {
		fn();
	} catch (const ecmxf::Error &e) {
		return e;
	}
	return ecmxf::Error("no error", 0);
}

} // namespace

TEST_CASE("verbs: open() picks the master by the URI, a bad URI is EINVAL")
{
	auto xf = MasterVerbs::open("sim:");
	CHECK(xf->kind() == MasterKind::EcmXf);
	CHECK(xf->device() != nullptr);
	CHECK(xf->board() == nullptr);
	auto sk = MasterVerbs::open("sk-sim:");
	CHECK(sk->kind() == MasterKind::EcmSk);
	CHECK(sk->board() != nullptr);
	CHECK(sk->device() == nullptr);
	CHECK(ecmxf::masterKindName(MasterKind::EcmSk) == "ECM-SK");
	for (const char *bad : { "", "bogus:", "sk-can:", "sk-sim:?slot=14", "sim:?check=md5" }) {
		INFO(bad);
		CHECK(errorOf([&] { (void)MasterVerbs::open(bad); }).errnoValue() == EINVAL);
	}
}

TEST_CASE("verbs: the ECM-SK: states, slaves, SDO, drives, I/O and reset through the interface")
{
	auto m = MasterVerbs::open("sk-sim:");
	CHECK(m->state() == ecmxf::State::Init);
	m->requestState(ecmxf::State::PreOp);
	CHECK(m->state() == ecmxf::State::PreOp);
	CHECK(m->slaveCount() == 3u);
	const auto list = m->slaves();
	REQUIRE(list.size() == 3u);
	CHECK(list[0].kind == "Drive");
	CHECK(list[1].kind == "STEP");
	CHECK(list[2].kind == "IO");
	CHECK(list[0].vendorId.has_value());
	const auto dt = m->upload(0, 0x1000, 0);
	CHECK(dt.size() == 4u);
	const std::vector<std::uint8_t> acc{ 0x10, 0x27, 0, 0 };
	m->download(1, 0x607C, 0, acc);
	CHECK(m->upload(1, 0x607C, 0) == acc);
	// what the SDO slot cannot carry, positions outside the frame
	const auto e3 = errorOf([&] { m->download(0, 0x607C, 0, std::vector<std::uint8_t>{ 1, 2, 3 }); });
	CHECK(e3.errnoValue() == ENOTSUP);
	CHECK_THAT(e3.what(), Contains("not on the ECM-SK: "));
	CHECK(errorOf([&] { (void)m->upload(40, 0x1000, 0); }).errnoValue() == EINVAL);
	CHECK(errorOf([&] { (void)m->upload(0, 0x1000, 0); }).errnoValue() == 0);
	// OP with CSP for the drives, then the drive verbs
	auto &b = *m->board();
	b.setup().detectAxes();
	b.drives().setMode(1, ecmxf::sk::Mode::Csp);
	b.drives().setMode(2, ecmxf::sk::Mode::Csp);
	m->requestState(ecmxf::State::Op);
	const auto on = m->driveEnable(0);
	CHECK(ecmxf::cia402StateFrom(on) == ecmxf::Cia402State::OperationEnabled);
	(void)m->driveDisable(0);
	(void)m->driveAlarmClear(0);
	CHECK(errorOf([&] { (void)m->driveEnable(40); }).errnoValue() == EINVAL);
	m->ioWrite(2, 0x5);
	(void)m->ioRead(2);
	CHECK(errorOf([&] { m->ioWrite(0, 1); }).errnoValue() == EPERM); // a Drive is no IO slave
	m->reset();
	CHECK(m->state() == ecmxf::State::Init);
}

TEST_CASE("verbs: the ECM-XF: SDO and drives through the interface, I/O is not a verb of the chip")
{
	auto m = MasterVerbs::open("sim:");
	auto &dev = *m->device();
	dev.bus().initNetwork();
	CHECK(m->slaveCount() == 3u);
	m->requestState(ecmxf::State::PreOp);
	CHECK(m->state() == ecmxf::State::PreOp);
	CHECK(m->slaves().size() == 3u);
	CHECK(m->upload(0, 0x1000, 0).size() == 4u);
	const auto on = m->driveEnable(0);
	CHECK(ecmxf::cia402StateFrom(on) == ecmxf::Cia402State::OperationEnabled);
	CHECK(ecmxf::cia402StateFrom(m->driveDisable(0)) == ecmxf::Cia402State::SwitchOnDisabled);
	CHECK(ecmxf::cia402StateFrom(m->driveAlarmClear(0)) == ecmxf::Cia402State::SwitchOnDisabled);
	const auto io = errorOf([&] { (void)m->ioRead(2); });
	CHECK(io.errnoValue() == ENOTSUP);
	CHECK_THAT(io.what(), Contains("not on the ECM-XF: "));
	CHECK(errorOf([&] { m->ioWrite(2, 1); }).errnoValue() == ENOTSUP);
	CHECK(errorOf([&] { (void)m->upload(128, 0x1000, 0); }).errnoValue() == EINVAL);
	// the adapter of a Device the caller owns
	auto v = ecmxf::verbsOf(dev);
	CHECK(v->kind() == MasterKind::EcmXf);
	CHECK(v->upload(0, 0x1000, 0) == m->upload(0, 0x1000, 0));
}
