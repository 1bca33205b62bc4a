// SPDX-License-Identifier: MIT
// sk-unix:PATH: the ECM-SK library against `ecmxf-sim --board ecm-sk
// --socket PATH` (the built binary): bring-up and a move over the socket,
// the board's state kept between clients, frame-size and option errors.
// No fixed sleeps: the server is ready when a hello succeeds.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <ecmxf/error.hpp>
#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/sk/board.hpp>

#include "../common/sim_server.hpp"

using namespace ecmxf::sk;

namespace {

using ecmxftest::TempDir;

/// ecmxf-sim --board ecm-sk --settings S --socket PATH
struct Server : ecmxftest::SimServer {
	Server(const std::string &socket, const std::string &settings)
		: SimServer(socket, { "--board", "ecm-sk", "--settings", settings })
	{
	}
};

} // namespace

TEST_CASE("sk unix: bring-up and a CSP move over the socket, the board outlives its clients")
{
	TempDir d;
	const std::string sock = d.path + "/sk.sock";
	Server s(sock, "slot=16");
	{
		auto b = Board::open("sk-unix:" + sock + "?slot=16");
		CHECK(b->frameSize() == 512u);
		CHECK(b->states().status().state == ecmxf::State::Init);
		b->states().set(ecmxf::State::PreOp);
		const std::vector<SlaveType> types = { SlaveType::Drive, SlaveType::Step, SlaveType::Io };
		CHECK(b->setup().setAxes(types) == 3u);
		b->states().set(ecmxf::State::Op);
		b->drives().servoOn(2);
		b->drives().waitEnabled(2);
		b->states().status();
		const auto p = b->drives().axis(2).position;
		for (int i = 1; i <= 50; i++) {
			REQUIRE(b->cyclic().stage(2, Mode::Csp, p + 10 * i));
			REQUIRE(b->cyclic().cycle().status == CycleStatus::Ok);
			b->channel().sleepFor(std::chrono::microseconds(800));
		}
		b->channel().sleepFor(std::chrono::milliseconds(20));
		b->states().status();
		CHECK(std::abs(b->drives().axis(2).position - (p + 500)) <= 5);
	}
	auto again = Board::open("sk-unix:" + sock + "?slot=16");
	CHECK(again->states().status().state == ecmxf::State::Op);
}

TEST_CASE("sk unix: a host told the wrong slot size gets the server's reason")
{
	TempDir d;
	const std::string sock = d.path + "/sk.sock";
	Server s(sock, "");
	auto b = Board::open("sk-unix:" + sock + "?slot=16");
	try {
		b->states().status();
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EPROTO);
		CHECK(std::string(e.what()).find("frame is 504 bytes") != std::string::npos);
	}
}

TEST_CASE("sk unix: no server, or bad options, are errors naming the reason")
{
	TempDir d;
	try {
		(void)Board::open("sk-unix:" + d.path + "/none.sock");
		FAIL("opened");
	} catch (const ecmxf::Error &e) {
		CHECK(std::string(e.what()).find("ecmxf-sim") != std::string::npos);
	}
	try {
		(void)Board::open("sk-unix:" + d.path + "/none.sock?slot=10");
		FAIL("opened");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
	}
}

TEST_CASE("sk unix: ecmxf-sim refuses bad board settings and unknown boards, with the reason")
{
	TempDir d;
	struct Case {
		const char *args;
		const char *says;
	};
	for (const Case &c : { Case{ "--board ecm-sk --settings slot=13", "slot=13" },
			       Case{ "--board ecm-sk --settings fifo=10", "fifo=10" },
			       Case{ "--board ecm-sk --settings colour=red", "colour" },
			       Case{ "--board ecm-sk --settings paced=2", "paced=2" },
			       Case{ "--board ecm-zz", "ecm-zz" }, Case{ "--board", "--board" } }) {
		INFO(c.args);
		const std::string out = d.path + "/err.txt";
		const std::string cmd = std::string(ECMXF_SIM_BINARY) + " " + c.args + " </dev/null >/dev/null 2>" + out;
		const int st = std::system(cmd.c_str());
		CHECK(WIFEXITED(st));
		CHECK(WEXITSTATUS(st) == 1);
		std::FILE *f = std::fopen(out.c_str(), "r");
		REQUIRE(f != nullptr);
		char buf[512] = {};
		const auto n = std::fread(buf, 1, sizeof(buf) - 1, f);
		std::fclose(f);
		CHECK(std::string(buf, n).find(c.says) != std::string::npos);
	}
}
