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

using namespace ecmxf::sk;

namespace {

struct TempDir {
	std::string path;
	TempDir()
	{
		char t[] = "/tmp/ecmxf-skunix-XXXXXX";
		REQUIRE(mkdtemp(t) != nullptr);
		path = t;
	}
	~TempDir()
	{
		std::error_code ec;
		std::filesystem::remove_all(path, ec);
	}
};

class Server
{
public:
	Server(const std::string &socket, const std::string &settings) : socket_(socket)
	{
		pid_ = fork();
		REQUIRE(pid_ >= 0);
		if (pid_ == 0) {
			execl(ECMXF_SIM_BINARY, ECMXF_SIM_BINARY, "--board", "ecm-sk", "--settings", settings.c_str(),
			      "--socket", socket.c_str(), static_cast<char *>(nullptr));
			_exit(127);
		}
		const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
		for (;;) {
			int st = 0;
			if (waitpid(pid_, &st, WNOHANG) == pid_) {
				pid_ = -1;
				FAIL("ecmxf-sim --board ecm-sk exited at start (status " << st << ")");
			}
			try {
				ecmxf::UnixChannel probe(socket_);
				return;
			} catch (const ecmxf::Error &e) {
				if (std::chrono::steady_clock::now() > deadline)
					FAIL("ecmxf-sim --board ecm-sk never served: " << e.what());
			}
			usleep(10000);
		}
	}
	~Server()
	{
		if (pid_ > 0) {
			kill(pid_, SIGKILL);
			waitpid(pid_, nullptr, 0);
		}
	}
	Server(const Server &) = delete;
	Server &operator=(const Server &) = delete;

private:
	std::string socket_;
	pid_t pid_ = -1;
};

} // namespace

TEST_CASE("sk unix: bring-up and a CSP move over the socket; the board outlives its clients")
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
			       Case{ "--board ecm-sk --paced", "--paced" },
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
