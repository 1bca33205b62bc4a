// SPDX-License-Identifier: MIT
// A command-level Link without the module: the ABI version check, and
// Device::command() over a Link (here a fake that plays the kernel's
// ECMXF_IOC_CMD): the request it gets, the answer it returns, every status
// mapped by the one outcome map (lib/link/outcome.cpp) to the Error an
// engine link gives, a failed system call, and the request/response trace
// records decoded.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/trace/trace.hpp>

#include "link/trace_writer.hpp"
#include "../common/thrown.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

using ecmxftest::thrown;

/// Plays the kernel: remembers the request, answers with @c answer,
/// records request and response in the trace as KernelLink does.
class FakeKernel final : public ecmxf::Link
{
public:
	int ioctlErrno = 0;
	ecmxf::RawResult answer;
	std::vector<std::uint8_t> answerData;
	// what the last request carried
	ecmxf::RawRequest got;
	std::vector<std::uint8_t> gotTx;
	std::size_t gotRxSize = 0;
	unsigned calls = 0;
	std::uint16_t driverDataSize = 1408;
	ecmxf::detail::TraceWriter *trace = nullptr;
	std::optional<ecmxf::ResponseHeader> last;

	void run(const ecmxf::RawRequest &req, ecmxf::RawResult &res) noexcept override
	{
		res = ecmxf::RawResult{};
		calls++;
		got = req;
		gotTx.assign(req.tx.begin(), req.tx.end());
		gotRxSize = req.rx.size();
		if (trace)
			trace->request(1000, req);
		if (ioctlErrno) {
			res.status = -ioctlErrno;
			res.linkFailure = failure.c_str();
			return;
		}
		res = answer;
		std::copy(answerData.begin(), answerData.end(), req.rx.begin());
		res.rxLen = answerData.size();
		if (res.status == 0)
			last = res.header;
		if (trace)
			trace->response(2000, res, std::span<const std::uint8_t>(req.rx.data(), res.rxLen));
	}
	[[nodiscard]] std::uint16_t dataSize() const noexcept override { return driverDataSize; }
	[[nodiscard]] ecmxf::CheckType checkType() const noexcept override { return ecmxf::CheckType::Crc32; }
	[[nodiscard]] std::optional<ecmxf::ResponseHeader> lastHeader() const noexcept override { return last; }
	[[nodiscard]] std::string name() const override { return "/dev/ecmxf-fake"; }
	[[nodiscard]] ecmxf::LinkCounters counters() const override { return {}; }
	void attachTrace(ecmxf::detail::TraceWriter *t) noexcept override { trace = t; }

	std::string failure = std::string("/dev/ecmxf-fake: ECMXF_IOC_CMD failed: ") + std::strerror(EINVAL);
};

struct Rig {
	Rig()
	{
		auto t = std::make_unique<FakeKernel>();
		k = t.get();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}
	FakeKernel *k;
	std::unique_ptr<ecmxf::Device> dev;
};

ecmxf::Command cmd(std::uint8_t code, std::uint8_t param = 0)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

} // namespace

TEST_CASE("the kernel ABI version check accepts version 4 only and names both versions otherwise",
	  "[transport][kernel]")
{
	CHECK(ecmxf::kKernelUapiVersion == 4);
	CHECK_NOTHROW(ecmxf::checkKernelUapiVersion("/dev/ecmxf0", 4));
	for (std::uint32_t other : { 1u, 2u, 3u, 5u }) {
		const ecmxf::Error e = thrown([other] { ecmxf::checkKernelUapiVersion("/dev/ecmxf0", other); });
		CHECK_THAT(e.what(), Equals("/dev/ecmxf0: the ecmxf kernel module speaks ABI version " +
					    std::to_string(other) +
					    ", this library ABI version 4 (<linux/ecmxf.h>); use a matching library and module"));
		CHECK(e.errnoValue() == EPROTO);
	}
}

TEST_CASE("Device::command over a Link hands the whole command down and returns the answer",
	  "[transport][kernel]")
{
	Rig r;
	r.k->driverDataSize = 1408;
	r.k->answer.header.code = 16;
	r.k->answer.header.index = 7;
	r.k->answer.header.ret = 3;
	r.k->answer.header.ecatState = 2;
	r.k->answer.header.len = 2;
	r.k->answerData = { 0x12, 0x34 };

	ecmxf::Command c = cmd(16, 0x05);
	c.data = { 1, 2, 3, 4 };
	c.reserved = 0x0800;
	c.control = 0x08;
	c.payload = { 0xAA, 0xBB, 0xCC };
	c.timeout = std::chrono::milliseconds(250);
	const ecmxf::Response rsp = r.dev->command(c);

	CHECK(r.k->got.code == 16);
	CHECK(r.k->got.param == 0x05);
	CHECK(r.k->got.data == std::array<std::uint8_t, 4>{ 1, 2, 3, 4 });
	CHECK(r.k->got.reserved == 0x0800);
	CHECK(r.k->got.control == 0x08);
	CHECK(r.k->got.len == 3); // unset: the payload size
	CHECK(r.k->gotTx == std::vector<std::uint8_t>{ 0xAA, 0xBB, 0xCC });
	CHECK(r.k->got.timeoutUs == 250'000u);
	CHECK(r.k->gotRxSize == 1408u); // room for the largest data section

	CHECK(rsp.ret == 3);
	CHECK(rsp.header.index == 7);
	CHECK(rsp.data == std::vector<std::uint8_t>{ 0x12, 0x34 });
	CHECK(r.dev->lastHeader().ecatState == 2);
	CHECK(r.dev->lastHeader().ret == 3);

	// a payload larger than the link's data section is refused before it
	r.k->driverDataSize = 112;
	ecmxf::Command big = cmd(16);
	big.payload.assign(113, 0);
	const ecmxf::Error e = thrown([&] { r.dev->command(big); });
	CHECK_THAT(e.what(), Equals("ECAT_SLV_CNT_GET: payload of 113 bytes does not fit the data section (112 bytes)"));
	CHECK(e.errnoValue() == EMSGSIZE);
	CHECK(r.k->calls == 1);
}

TEST_CASE("the command statuses of a Link become the same Errors as over a byte transport",
	  "[transport][kernel]")
{
	struct Case {
		int status;
		std::uint8_t code;
		std::string message;
		std::optional<std::uint8_t> errStatus;
	};
	const Case cases[] = {
		{ -ETIMEDOUT, 16, "ECAT_SLV_CNT_GET: timed out after 100 ms waiting for the chip's answer", {} },
		{ -ETIMEDOUT, 1,
		  "ECAT_INIT_OP: timed out after 10000 ms waiting for the answer and the async command's completion", {} },
		{ -EBUSY, 1, "ECAT_INIT_OP: chip refused: another async command is running (error status 0x80)", 0x81 },
		{ -EREMOTEIO, 10, "ECAT_SDO_REQ: the async command failed (error status bit 3)", 0x09 },
		{ -EBADMSG, 16,
		  "ECAT_SLV_CNT_GET: the link kept delivering bad packets (check word mismatch); /dev/ecmxf-fake's "
		  "counters tell more",
		  {} },
		{ -EIO, 16, "ECAT_SLV_CNT_GET: the chip kept answering not ready (check word 0x87654321)", {} },
		{ -ECONNRESET, 16, "ECAT_SLV_CNT_GET: the chip reset while the command was in flight", {} },
		{ -ECANCELED, 1, "ECAT_INIT_OP: the command was cancelled", {} },
		{ -EMSGSIZE, 16, "ECAT_SLV_CNT_GET: the answer (1500 bytes) is larger than the receive buffer (1408 bytes)",
		  {} },
		{ -EPERM, 16, std::string("ECAT_SLV_CNT_GET: failed: ") + std::strerror(EPERM), {} },
	};
	for (const Case &k : cases) {
		INFO("status " << k.status);
		Rig r;
		r.k->answer.status = k.status;
		r.k->answer.header.errStatus = k.errStatus.value_or(0);
		r.k->answer.header.len = 1500;
		const ecmxf::Error e = thrown([&] { r.dev->command(cmd(k.code)); });
		CHECK_THAT(e.what(), Equals(k.message));
		CHECK(e.errnoValue() == -k.status);
		CHECK(e.errorStatus() == k.errStatus);
	}
}

TEST_CASE("a failed ioctl names the command, the device, the call and the reason", "[transport][kernel]")
{
	Rig r;
	r.k->ioctlErrno = EINVAL;
	const ecmxf::Error e = thrown([&] { r.dev->command(cmd(75)); });
	CHECK_THAT(e.what(), Equals(std::string("ASYNCCMD_RESET: /dev/ecmxf-fake: ECMXF_IOC_CMD failed: ") +
				    std::strerror(EINVAL)));
	CHECK(e.errnoValue() == EINVAL);
	CHECK(r.dev->lastHeader().code == 0); // nothing answered

	// the same failure on the cyclic path: its errno, no throw
	ecmxf::RawCommand rc;
	rc.code = 16;
	ecmxf::ResponseHeader h;
	h.code = 99;
	CHECK(r.dev->transact(rc, {}, {}, h) == EINVAL);
	CHECK(h.code == 99); // untouched: nothing answered
}

TEST_CASE("a trace of a kernel-transport device records requests and responses and decodes them",
	  "[transport][kernel][trace]")
{
	const auto path = std::filesystem::temp_directory_path() /
			  ("ecmxf-test-kernel-" + std::to_string(getpid()) + ".trace");
	Rig r;
	r.dev->startTrace(path.string());
	r.k->answer.header.code = 56;
	r.k->answer.header.index = 0x21;
	r.k->answer.header.ret = 0x30;
	r.k->answer.header.len = 2;
	r.k->answerData = { 0xAB, 0xCD };
	ecmxf::Command c = cmd(56);
	c.payload = { 0x01, 0x02 };
	r.dev->command(c);
	r.dev->stopTrace();

	std::ifstream f(path);
	std::stringstream raw;
	raw << f.rdbuf();
	const std::string text = raw.str();
	// header bytes 0x04..0x17 (data, reserved, control, index 0, code 0x38,
	// param, len 2, int clear, GPIO) then the data
	CHECK_THAT(text, Contains(" C 00000000 00000000 38000200 00000000 00000000 0102\n"));
	CHECK_THAT(text, Contains(" R 0 00000000 00000021 38300200 00000000 00000000 abcd\n"));

	std::istringstream in(text);
	std::ostringstream out;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(in, out);
	CHECK(s.commands == 1);
	CHECK(s.responses == 1);
	CHECK_THAT(out.str(), Contains("request: FW_VERSION_GET (0x38)\n"));
	CHECK_THAT(out.str(), Contains("response: status 0 OK, answers #1 FW_VERSION_GET\n"));
	CHECK_THAT(out.str(), Contains("    index 0x21, code 0x38 FW_VERSION_GET, ret 0x30 (48), len 2\n"));
	std::filesystem::remove(path);
}

TEST_CASE("dataSize() and checkType() of a Device are its link's",
	  "[transport][kernel]")
{
	// the driver may run another size than the power-on 112 bytes (e.g.
	// its data_size module parameter)
	Rig r;
	CHECK(r.dev->checkType() == ecmxf::CheckType::Crc32);
	r.k->driverDataSize = 992;
	CHECK(r.dev->dataSize() == 992);
	CHECK(r.dev->pdoDataCapacity() == 992);
	r.k->driverDataSize = 1408;
	CHECK(r.dev->dataSize() == 1408);
}

TEST_CASE("assumeFormat() over a Link that tracks the format itself is refused",
	  "[transport][kernel]")
{
	Rig r;
	const ecmxf::Error e = thrown([&] { r.dev->assumeFormat(112, ecmxf::CheckType::Crc32); });
	CHECK(e.errnoValue() == EOPNOTSUPP);
	CHECK_THAT(e.what(), Equals("/dev/ecmxf-fake: this link tracks the chip's packet format itself"));
	CHECK(r.k->calls == 0);
	// an engine link takes it, and refuses what is out of range
	ecmxf::Device sim(std::make_unique<ecmxf::SimChannel>());
	sim.assumeFormat(1408, ecmxf::CheckType::Crc32);
	CHECK(sim.dataSize() == 1408);
	CHECK(sim.checkType() == ecmxf::CheckType::Crc32);
	const ecmxf::Error bad = thrown([&] { sim.assumeFormat(31, ecmxf::CheckType::Fixed); });
	CHECK(bad.errnoValue() == EINVAL);
	CHECK_THAT(bad.what(), Contains("31"));
}

TEST_CASE("where events come from: the kernel device's minor, none for an engine link", "[transport][kernel]")
{
	// /dev/null is the character device 1:3 (Documentation/admin-guide/devices.txt)
	CHECK(ecmxf::KernelLink::minorOf("/dev/null") == std::optional<std::uint32_t>(3u));
	// not a character device, or not there: no minor
	CHECK_FALSE(ecmxf::KernelLink::minorOf("/").has_value());
	CHECK_FALSE(ecmxf::KernelLink::minorOf("/nonexistent/ecmxf0").has_value());
	CHECK_FALSE(ecmxf::KernelLink::minorOf("").has_value());
	// an engine link's events are found by polling headers
	ecmxf::Device sim(std::make_unique<ecmxf::SimChannel>());
	CHECK_FALSE(ecmxf::KernelLink::minorOf(sim.link().name()).has_value());
	CHECK(sim.link().simulator() != nullptr);
	Rig r;
	CHECK(r.dev->link().simulator() == nullptr); // the Link default
}
