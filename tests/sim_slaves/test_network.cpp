// SPDX-License-Identifier: MIT
// The bundled network files, network file errors, and the 128-slave
// network (sizes, OP, cost of a cycle).

#include "helpers.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include <ctime>
#include <unistd.h>

using namespace th;
using ecmxf::sim::AlState;

namespace {

const std::string kDir = ECMXF_TEST_NETWORK_DIR;

std::vector<std::string> types(Network &n)
{
	std::vector<std::string> t;
	for (std::size_t i = 0; i < n.size(); i++)
		t.push_back(n.at(i).typeName());
	return t;
}

struct TempFile {
	std::string path;
	explicit TempFile(const std::string &text)
	{
		char name[] = "/tmp/ecmxf-net-XXXXXX";
		const int fd = mkstemp(name);
		REQUIRE(fd >= 0);
		close(fd);
		path = name;
		std::ofstream(path) << text;
	}
	~TempFile() { std::remove(path.c_str()); }
};

} // namespace

TEST_CASE("Network files: est584x2-io.net is the default network")
{
	Network n = Network::fromFile(kDir + "/est584x2-io.net");
	CHECK(n.name() == "2x EST-584 + digital I/O");
	CHECK(types(n) == std::vector<std::string>{ "EST-584", "EST-584", "dio" });
	Network d = Network::defaultNetwork();
	REQUIRE(d.size() == n.size());
	for (std::size_t i = 0; i < n.size(); i++) {
		CHECK(d.at(i).typeName() == n.at(i).typeName());
		CHECK(d.at(i).outputBytes() == n.at(i).outputBytes());
		CHECK(d.at(i).inputBytes() == n.at(i).inputBytes());
		CHECK(d.at(i).identity().serial == n.at(i).identity().serial);
	}
	// serial numbers follow the bus position
	CHECK(n.at(0).identity().serial == 1);
	CHECK(n.at(2).identity().serial == 3);
}

TEST_CASE("Network files: servo-io.net")
{
	Network n = Network::fromFile(kDir + "/servo-io.net");
	CHECK(types(n) == std::vector<std::string>{ "servo", "servo", "dio" });
}

TEST_CASE("Network files: slaves128.net loads 128 slaves whose process data fits one FIFO entry")
{
	Network n = Network::fromFile(kDir + "/slaves128.net");
	REQUIRE(n.size() == 128);
	std::size_t out = 0, in = 0, est = 0, dio = 0;
	for (std::size_t i = 0; i < n.size(); i++) {
		out += n.at(i).outputBytes();
		in += n.at(i).inputBytes();
		est += n.at(i).typeName() == "EST-584";
		dio += n.at(i).typeName() == "dio";
	}
	CHECK(est == 64);
	CHECK(dio == 64);
	CHECK(out == 832);
	CHECK(in == 1152);
	CHECK(out <= 1408);
	CHECK(in <= 1408);
}

TEST_CASE("Network files: options reach the models, errors name file and line")
{
	TempFile good("# test\nname my bus\nslave EST-584 alias=7 name=\"Axis X\" home_switch=-100\n"
		      "slave dio outputs=2 inputs=3 count=2\n");
	Network n = Network::fromFile(good.path);
	REQUIRE(n.size() == 3);
	CHECK(n.name() == "my bus");
	CHECK(n.at(0).identity().name == "Axis X");
	CHECK(n.at(0).sii()[0x04] == 7);
	CHECK(n.at(0).escRead8(0x0012) == 7);
	CHECK(n.at(2).outputBytes() == 2);
	CHECK(n.at(2).inputBytes() == 3);
	auto *e = dynamic_cast<ecmxf::sim::Est584Model *>(&n.at(0));
	REQUIRE(e);
	CHECK(e->homeSwitchActive()); // position 0 is above -100

	TempFile bad("name x\nslave EST-584\n\nslave EST-584 colour=red\n");
	CHECK_THROWS_WITH(Network::fromFile(bad.path),
			  Catch::Contains(bad.path + ":4") && Catch::Contains("colour"));
	TempFile badValue("slave dio outputs=lots\n");
	CHECK_THROWS_WITH(Network::fromFile(badValue.path),
			  Catch::Contains(badValue.path + ":1") && Catch::Contains("outputs"));
	TempFile badType("slave stepper\n");
	CHECK_THROWS_WITH(Network::fromFile(badType.path), Catch::Contains(badType.path + ":1"));
	CHECK_THROWS(Network::fromFile("/nonexistent/x.net"));
}

TEST_CASE("128 slaves in OP at 8 kHz: all contribute to the WKC, and a cycle is cheap")
{
	Network n = Network::fromFile(kDir + "/slaves128.net");
	std::vector<std::vector<std::uint8_t>> outs, ins;
	std::vector<Slave *> slaves;
	std::vector<bool> drive;
	for (std::size_t i = 0; i < n.size(); i++) {
		Slave &s = n.at(i);
		slaves.push_back(&s);
		drive.push_back(s.typeName() == "EST-584");
		s.configureDc(s.dcAssignActivate(), 125'000, 0, 0);
		s.alControl(0x02);
		s.alControl(0x04);
		REQUIRE(s.alStatus() == 0x04);
		outs.emplace_back(s.outputBytes(), 0);
		ins.emplace_back(s.inputBytes(), 0);
		s.cycle(outs.back(), true, ins.back(), 125us, true);
		s.alControl(0x08);
		REQUIRE(s.alStatus() == 0x08);
		// drives: enabled in CSP at their position
		if (s.typeName() == "EST-584")
			outs.back()[0] = 0x06;
	}
	constexpr int kCycles = 8000; // one second at 8 kHz
	unsigned wkc = 0;
	for (int c = 0; c < kCycles; c++) {
		wkc = 0;
		for (std::size_t i = 0; i < slaves.size(); i++) {
			if (drive[i]) {
				if (c < 3) {
					outs[i][0] = c == 1 ? 0x07 : c == 2 ? 0x0F : 0x06;
				} else {
					const std::int32_t target = c * 100; // 800 units/ms: 0.8 M/s
					for (std::size_t b = 0; b < 4; b++)
						outs[i][2 + b] = static_cast<std::uint8_t>(target >> (8 * b));
				}
			}
			wkc += slaves[i]->cycle(outs[i], true, ins[i], 125us, true);
		}
	}
	CHECK(wkc == 128 * 3);
	// the drives followed: statusword operation enabled, position = target
	CHECK((ins[0][0] & 0x6F) == 0x27);
	CHECK(ins[0][3] == static_cast<std::uint8_t>((kCycles - 1) * 100));
	// the speed of this loop is measured by `make bench` (bench-sim), not here
}

TEST_CASE("Network files: a bare name is looked for in ECMXF_NETWORK_PATH, with or without .net")
{
	char dir[] = "/tmp/ecmxf-netpath-XXXXXX";
	REQUIRE(mkdtemp(dir) != nullptr);
	const std::string d = dir;
	std::ofstream(d + "/mine.net") << "name mine\nslave dio\nslave dio\n";
	const char *old = std::getenv("ECMXF_NETWORK_PATH");
	const std::string saved = old ? old : "";
	REQUIRE(setenv("ECMXF_NETWORK_PATH", ("/nonexistent:" + d).c_str(), 1) == 0);
	CHECK(Network::findFile("mine.net") == d + "/mine.net");
	CHECK(Network::findFile("mine") == d + "/mine.net");
	CHECK(Network::fromFile("mine").name() == "mine");
	CHECK(Network::fromFile("mine.net").size() == 2);
	// a path with '/' is taken as it is
	CHECK(Network::findFile("./mine.net") == "./mine.net");
	try {
		(void)Network::fromFile("nosuch.net");
		FAIL("nosuch.net found");
	} catch (const std::runtime_error &e) {
		INFO(e.what());
		CHECK(std::string(e.what()).starts_with("cannot open network file 'nosuch.net': not in the working "
							"directory, nor in /nonexistent, " + d + ", "));
		CHECK(std::string(e.what()).find("ECMXF_NETWORK_PATH adds directories") != std::string::npos);
	}
	if (old)
		setenv("ECMXF_NETWORK_PATH", saved.c_str(), 1);
	else
		unsetenv("ECMXF_NETWORK_PATH");
	std::remove((d + "/mine.net").c_str());
	rmdir(dir);
}

TEST_CASE("Network files: bytes of a bad file are escaped in the message, never echoed raw")
{
	const auto error = [](const std::string &text) {
		try {
			(void)Network::fromText(text, "bad.net");
		} catch (const std::invalid_argument &e) {
			return std::string(e.what());
		}
		return std::string("no error");
	};
	// a terminal escape (clear screen), a lone 0xFF, a backslash, and UTF-8
	const std::string m = error("slave \x1b[2Jx\xff\\\xc2\xb5\n");
	INFO(m);
	CHECK(m.find('\x1b') == std::string::npos);
	CHECK(m.find('\xff') == std::string::npos);
	CHECK(m.find("\\x1b[2Jx\\xff\\\\\xc2\xb5") != std::string::npos); // µ kept
	CHECK(m.starts_with("bad.net:1: "));
	const std::string k = error("chip \x07\x7f=1\n");
	CHECK(k.find("\\x07\\x7f") != std::string::npos);
	CHECK(k.find('\x07') == std::string::npos);
}
