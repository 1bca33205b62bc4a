// SPDX-License-Identifier: MIT
// unix:PATH devices: UnixChannel against a real ecmxf-sim --socket server
// (the built binary, ECMXF_SIM_BINARY) and against fake peers played by a
// thread of the test; ecmxf-util (ECMXF_UTIL_PATH) run twice against one
// server to see the chip's state persist. Expected messages and errnos
// are the ones include/ecmxf/link/unix_channel.hpp documents.
//
// No fixed sleeps: a server is ready when a UnixChannel's hello succeeds
// (bounded retry, with the reason when it never does); every server is
// killed and every temporary directory removed when its test ends.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/unix_channel.hpp>
#include "../cli/cli_run.hpp"
#include "../common/sim_server.hpp"
#include "../common/thrown.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;
using ecmxf::UnixChannel;

namespace {

using ecmxftest::thrown;

using ecmxftest::TempDir;
using Server = ecmxftest::SimServer;

/// A listening socket at @p path whose one connection a thread hands to
/// @p script (a peer that is not, or not quite, ecmxf-sim).
class FakePeer
{
public:
	FakePeer(const std::string &path, std::function<void(int)> script)
	{
		fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
		REQUIRE(fd_ >= 0);
		sockaddr_un a{};
		a.sun_family = AF_UNIX;
		REQUIRE(path.size() < sizeof(a.sun_path));
		std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
		REQUIRE(bind(fd_, reinterpret_cast<sockaddr *>(&a), sizeof(a)) == 0);
		REQUIRE(listen(fd_, 1) == 0);
		thread_ = std::thread([this, script = std::move(script)] {
			const int c = accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
			if (c < 0)
				return;
			script(c);
			close(c);
		});
	}
	~FakePeer()
	{
		// wakes an accept() that never got its client
		shutdown(fd_, SHUT_RDWR);
		thread_.join();
		close(fd_);
	}
	FakePeer(const FakePeer &) = delete;
	FakePeer &operator=(const FakePeer &) = delete;

private:
	int fd_ = -1;
	std::thread thread_;
};

void sendBytes(int fd, const std::string &b)
{
	(void)send(fd, b.data(), b.size(), MSG_NOSIGNAL);
}

/// Reads @p n bytes (less at end of input).
std::string recvBytes(int fd, std::size_t n)
{
	std::string s(n, '\0');
	std::size_t got = 0;
	while (got < n) {
		const ssize_t r = recv(fd, s.data() + got, n - got, 0);
		if (r <= 0)
			break;
		got += static_cast<std::size_t>(r);
	}
	s.resize(got);
	return s;
}

/// A correct hello answer.
std::string helloReply(std::uint16_t version = UnixChannel::kProtocolVersion)
{
	std::string r = "H";
	r.append(UnixChannel::kHelloMagic);
	r.push_back(static_cast<char>(version & 0xFF));
	r.push_back(static_cast<char>(version >> 8));
	return r;
}

/// The hello, answered correctly.
void answerHello(int c)
{
	REQUIRE(recvBytes(c, 1) == "H");
	sendBytes(c, helloReply());
}

} // namespace

// ------------------------------------------------------------ the channel

TEST_CASE("unix: the channel runs on the server's virtual time", "[unix]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock);

	UnixChannel ch(sock);
	CHECK(ch.name() == "unix:" + sock);
	const auto t0 = ch.now();
	ch.sleepFor(std::chrono::milliseconds(3));
	CHECK(ch.now() - t0 == std::chrono::milliseconds(3));
	ch.sleepFor(std::chrono::nanoseconds(-5));
	CHECK(ch.now() - t0 == std::chrono::milliseconds(3));
	// an idle chip is ready at once, without time passing
	const auto t1 = ch.now();
	CHECK(ch.waitReady(std::chrono::milliseconds(1)));
	CHECK(ch.now() == t1);
}

TEST_CASE("unix: Device::open runs commands and the chip outlives the connection", "[unix]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock);
	const std::string uri = "unix:" + sock;

	{
		auto dev = ecmxf::Device::open(uri);
		auto sim = ecmxf::Device::open("sim:");
		// the same chip as the in-process simulator, over the socket
		const auto fw = dev->chip().firmwareVersion();
		const auto simFw = sim->chip().firmwareVersion();
		CHECK(fw.version == simFw.version);
		CHECK(fw.extendedVersion == simFw.extendedVersion);
		CHECK(dev->bus().slaveCount() == 0); // not scanned yet
		dev->bus().initNetwork();
		CHECK(dev->bus().slaveCount() == 3);
	}
	{
		// a new connection: the network scanned by the first is still there
		auto dev = ecmxf::Device::open(uri);
		CHECK(dev->bus().slaveCount() == 3);
	}
}

TEST_CASE("unix: ecmxf-util states PREOP persists to a later ecmxf-util slaves", "[unix][cli]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock);
	const std::string d = "-d unix:" + sock + " ";

	auto r = clitest::run(d + "slaves");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	CHECK_THAT(r.out, Contains("INIT"));
	CHECK_THAT(r.out, !Contains("PREOP"));

	r = clitest::run(d + "states PREOP");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0    PREOP  +\n1    PREOP  +\n2    PREOP  +\n");

	// a second program, a new connection: the slaves are still in PRE-OP
	r = clitest::run(d + "slaves");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	const auto lines = [](const std::string &s) {
		std::vector<std::string> v;
		std::istringstream in(s);
		for (std::string l; std::getline(in, l);)
			v.push_back(l);
		return v;
	}(r.out);
	REQUIRE(lines.size() == 3);
	for (const auto &l : lines)
		CHECK_THAT(l, Contains(" PREOP "));
}

TEST_CASE("unix: ecmxf-sim --chip selects the CRC coverage, check=crc32 switches the chip at open",
	  "[unix][cli][variants]")
{
	for (const std::string coverage : { "frame", "valid" }) {
		INFO("crc32-coverage=" << coverage);
		TempDir dir;
		const std::string sock = dir.path + "/s";
		Server server(sock, { "--chip", "crc32-coverage=" + coverage });
		const std::string d = "-d 'unix:" + sock + "?check=crc32' ";

		auto r = clitest::run(d + "upload -p 0 0x2001:0");
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains(" 50000\n"));
		// a second program: the chip speaks CRC-32 already
		r = clitest::run(d + "info");
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains("check type:        CRC-32\n"));
		CHECK_THAT(r.out, Contains("CRC coverage:      " + coverage + "\n"));
		// and back to the fixed word, from a chip in CRC-32
		r = clitest::run("-d 'unix:" + sock + "?check=fixed' upload -p 1 0x2001:0");
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains(" 50000\n"));
		r = clitest::run("-d unix:" + sock + " info");
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains("check type:        fixed\n"));
	}
}

TEST_CASE("unix: ecmxf-sim --chip refuses what is not a chip option, naming key and value",
	  "[unix][cli][variants]")
{
	TempDir dir;
	const auto sim = [&](const std::string &args) {
		clitest::Result r;
		const std::string cmd = std::string(ECMXF_SIM_BINARY) + " " + args + " --socket " + dir.path +
					"/s 2>&1";
		std::FILE *p = popen(cmd.c_str(), "r");
		REQUIRE(p != nullptr);
		char buf[1024];
		std::size_t n;
		while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0)
			r.out.append(buf, n);
		const int st = pclose(p);
		REQUIRE(WIFEXITED(st));
		r.status = WEXITSTATUS(st);
		return r;
	};
	auto r = sim("--chip crc32-coverage=maybe");
	CHECK(r.status == 1);
	CHECK(r.out == "ecmxf-sim: --chip: chip option crc32-coverage: bad value 'maybe' (expected frame or valid)\n");
	r = sim("-c crc-type-set-fixed=1");
	CHECK(r.status == 1);
	CHECK(r.out == "ecmxf-sim: --chip: chip option crc-type-set-fixed: bad value '1' (expected drop or accept)\n");
	r = sim("--chip speed=fast");
	CHECK(r.status == 1);
	CHECK_THAT(r.out, StartsWith("ecmxf-sim: --chip: unknown chip option 'speed' (known: crc32-coverage"));
	r = sim("--chip crc32-coverage");
	CHECK(r.status == 1);
	CHECK_THAT(r.out, StartsWith("ecmxf-sim: --chip 'crc32-coverage' is not KEY=VALUE"));
	r = sim("--chip =valid");
	CHECK(r.status == 1);
	CHECK_THAT(r.out, StartsWith("ecmxf-sim: --chip '=valid' is not KEY=VALUE"));
	CHECK_FALSE(std::filesystem::exists(dir.path + "/s"));
	// the last word without its value
	clitest::Result last;
	{
		const std::string cmd = std::string(ECMXF_SIM_BINARY) + " --chip 2>&1";
		std::FILE *p = popen(cmd.c_str(), "r");
		REQUIRE(p != nullptr);
		char buf[256];
		std::size_t n;
		while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0)
			last.out.append(buf, n);
		last.status = WEXITSTATUS(pclose(p));
	}
	CHECK(last.status == 1);
	CHECK(last.out == "ecmxf-sim: --chip needs a value\n");
}

TEST_CASE("unix: slaves -v shows the DC information codes 10..13 after states brought up DC",
	  "[unix][cli][variants]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock, { "--network", std::string(ECMXF_TEST_NETWORK_DIR) + "/servo-io.net" });
	const std::string d = "-d unix:" + sock + " ";
	auto r = clitest::run(d + "states SAFEOP");
	REQUIRE(r.status == 0);
	r = clitest::run(d + "slaves -v");
	REQUIRE(r.status == 0);
	const auto lines = clitest::lines(r.out);
	REQUIRE(lines.size() == 4);
	CHECK_THAT(lines[0], Contains("  DC     CYCLE NS    SHIFT NS  ACT  NAME"));
	// the servos take part in DC (SYNC0 1 ms, shift 0), the I/O has none
	CHECK_THAT(lines[1], Contains("  yes     1000000           0  yes  "));
	CHECK_THAT(lines[2], Contains("  yes     1000000           0  yes  "));
	CHECK_THAT(lines[3], Contains("  no            0           0  no   "));
	r = clitest::run(d + "--json slaves -p 0");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\"dc\": true, \"dc_cycle_ns\": 1000000, \"dc_shift_ns\": 0, \"dc_active\": true}"));
}

TEST_CASE("unix: ecmxf-util names a missing server", "[unix][cli]")
{
	TempDir dir;
	const std::string sock = dir.path + "/nope";
	const auto r = clitest::run("-d unix:" + sock + " slaves");
	CHECK(r.status != 0);
	CHECK_THAT(r.err, Contains("unix:" + sock + ": no ecmxf-sim listening there (start one with `ecmxf-sim --socket " +
				   sock + "`)"));
}

TEST_CASE("unix: a second client is refused while one is connected (EBUSY)", "[unix]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock);

	{
		UnixChannel first(sock);
		const auto e = thrown([&] { UnixChannel second(sock); });
		CHECK(e.errnoValue() == EBUSY);
		CHECK_THAT(e.what(), Equals("unix:" + sock +
					    ": ecmxf-sim refused the connection: busy: ecmxf-sim serves one client "
					    "at a time and another one is connected"));
		// the first is still served
		first.sleepFor(std::chrono::microseconds(1));
	}
	// the first has gone: the next one is served
	UnixChannel third(sock);
	CHECK(third.waitReady(std::chrono::milliseconds(1)));
}

TEST_CASE("unix: the server survives a client that disconnects mid-request", "[unix]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock);

	{
		const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
		REQUIRE(fd >= 0);
		sockaddr_un a{};
		a.sun_family = AF_UNIX;
		std::memcpy(a.sun_path, sock.c_str(), sock.size() + 1);
		REQUIRE(connect(fd, reinterpret_cast<sockaddr *>(&a), sizeof(a)) == 0);
		// an exchange of 112 + 12 bytes announced, 3 of them sent
		sendBytes(fd, std::string("X\x7c\x00\x01\x02\x03", 6));
		close(fd);
	}
	UnixChannel ch(sock);
	std::vector<std::uint8_t> mosi(124), miso(124);
	CHECK_NOTHROW(ch.exchange(mosi, miso));
	CHECK_NOTHROW(ch.sleepFor(std::chrono::microseconds(10)));
}

TEST_CASE("unix: SIGTERM ends the server and removes its socket", "[unix]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";
	Server server(sock);
	REQUIRE(std::filesystem::is_socket(sock));
	CHECK(server.terminate() == 0);
	CHECK_FALSE(std::filesystem::exists(sock));
	// what a client then hears
	CHECK(thrown([&] { UnixChannel ch(sock); }).errnoValue() == ENOENT);
}

// ----------------------------------------------------------------- errors

TEST_CASE("unix: a missing socket is named, with how to start a server (ENOENT)", "[unix][errors]")
{
	TempDir dir;
	const std::string sock = dir.path + "/nope";
	const auto e = thrown([&] { UnixChannel ch(sock); });
	CHECK(e.errnoValue() == ENOENT);
	CHECK_THAT(e.what(), Equals("unix:" + sock + ": no ecmxf-sim listening there (start one with `ecmxf-sim --socket " +
				    sock + "`): " + std::strerror(ENOENT)));
	// the same through Device::open
	const auto e2 = thrown([&] { (void)ecmxf::Device::open("unix:" + sock); });
	CHECK(e2.errnoValue() == ENOENT);
	CHECK_THAT(e2.what(), Equals(e.what()));
}

TEST_CASE("unix: a socket nobody listens on any more (ECONNREFUSED)", "[unix][errors]")
{
	TempDir dir;
	const std::string sock = dir.path + "/stale";
	// what a killed server leaves: a socket file, bound, not listening
	const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	REQUIRE(fd >= 0);
	sockaddr_un a{};
	a.sun_family = AF_UNIX;
	std::memcpy(a.sun_path, sock.c_str(), sock.size() + 1);
	REQUIRE(bind(fd, reinterpret_cast<sockaddr *>(&a), sizeof(a)) == 0);
	const auto e = thrown([&] { UnixChannel ch(sock); });
	close(fd);
	CHECK(e.errnoValue() == ECONNREFUSED);
	CHECK_THAT(e.what(), StartsWith("unix:" + sock + ": no ecmxf-sim listening there (start one with"));
}

TEST_CASE("unix: a path that is not a socket (ENOTSOCK)", "[unix][errors]")
{
	TempDir dir;
	const std::string file = dir.path + "/file";
	std::ofstream(file) << "not a socket\n";
	auto e = thrown([&] { UnixChannel ch(file); });
	CHECK(e.errnoValue() == ENOTSOCK);
	CHECK_THAT(e.what(), Equals("unix:" + file +
				    ": not a socket (not a Unix socket; unix:PATH names an ecmxf-sim --socket PATH server)"));
	e = thrown([&] { UnixChannel ch(dir.path); });
	CHECK(e.errnoValue() == ENOTSOCK);
	CHECK_THAT(e.what(), Equals("unix:" + dir.path +
				    ": not a socket (a directory; unix:PATH names an ecmxf-sim --socket PATH server)"));
}

TEST_CASE("unix: a path longer than a socket address holds (ENAMETOOLONG)", "[unix][errors]")
{
	const std::string path = "/tmp/" + std::string(sizeof(sockaddr_un::sun_path), 'x');
	const auto e = thrown([&] { UnixChannel ch(path); });
	CHECK(e.errnoValue() == ENAMETOOLONG);
	CHECK_THAT(e.what(), Equals("unix:" + path + ": socket path is " + std::to_string(path.size()) +
				    " bytes long; a Unix socket address holds at most " +
				    std::to_string(sizeof(sockaddr_un::sun_path) - 1)));
	// the longest that fits is tried (and is missing)
	const std::string fits = "/tmp/" + std::string(sizeof(sockaddr_un::sun_path) - 6, 'y');
	CHECK(thrown([&] { UnixChannel ch(fits); }).errnoValue() == ENOENT);
}

TEST_CASE("unix: a peer that is not ecmxf-sim is refused at the hello (EPROTO)", "[unix][errors]")
{
	TempDir dir;
	const std::string sock = dir.path + "/peer";

	SECTION("it answers something else")
	{
		FakePeer peer(sock, [](int c) {
			(void)recvBytes(c, 1);
			sendBytes(c, "HTTP/1.1 400 Bad Request\r\n");
			(void)recvBytes(c, 1); // until the client closes
		});
		const auto e = thrown([&] { UnixChannel ch(sock); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), StartsWith("unix:" + sock +
						": not an ecmxf-sim server: its answer to the hello was \"HTTP/1.1 40"));
	}
	SECTION("it answers with a type the protocol does not have")
	{
		FakePeer peer(sock, [](int c) {
			(void)recvBytes(c, 1);
			sendBytes(c, "SSH-2.0-OpenSSH_9.2\r\n");
			(void)recvBytes(c, 1);
		});
		const auto e = thrown([&] { UnixChannel ch(sock); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), StartsWith("unix:" + sock +
						": not an ecmxf-sim server: its answer to the hello was \"SSH-2.0"));
	}
	SECTION("it closes without a word")
	{
		FakePeer peer(sock, [](int) {});
		const auto e = thrown([&] { UnixChannel ch(sock); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("unix:" + sock +
					    ": the peer closed the connection without answering the hello: not an "
					    "ecmxf-sim server?"));
	}
	SECTION("it speaks another protocol version")
	{
		FakePeer peer(sock, [](int c) {
			(void)recvBytes(c, 1);
			sendBytes(c, helloReply(2));
			(void)recvBytes(c, 1);
		});
		const auto e = thrown([&] { UnixChannel ch(sock); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("unix:" + sock +
					    ": ecmxf-sim speaks wire protocol version 2, this library version 1"));
	}
	SECTION("it answers the hello with an error (an ecmxf-sim without 'H')")
	{
		FakePeer peer(sock, [](int c) {
			(void)recvBytes(c, 1);
			const std::string msg = "unknown request type 0x48";
			sendBytes(c, std::string("E") + static_cast<char>(msg.size()) + '\0' + msg);
		});
		const auto e = thrown([&] { UnixChannel ch(sock); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("unix:" + sock +
					    ": the peer answered the hello with an error (an ecmxf-sim of an older "
					    "wire protocol, without 'H'?): unknown request type 0x48"));
	}
}

TEST_CASE("unix: a peer that never answers the hello times out (ETIMEDOUT)", "[unix][errors][slow]")
{
	TempDir dir;
	const std::string sock = dir.path + "/mute";
	FakePeer peer(sock, [](int c) {
		(void)recvBytes(c, 1);
		(void)recvBytes(c, 1); // silent until the client gives up
	});
	const auto start = std::chrono::steady_clock::now();
	const auto e = thrown([&] { UnixChannel ch(sock); });
	CHECK(std::chrono::steady_clock::now() - start >= UnixChannel::kHelloTimeout - std::chrono::milliseconds(10));
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK_THAT(e.what(), Equals("unix:" + sock + ": no answer to the hello within 5 s: not an ecmxf-sim server?"));
}

TEST_CASE("unix: a server that closes mid-request (ECONNRESET)", "[unix][errors]")
{
	TempDir dir;
	const std::string sock = dir.path + "/peer";

	SECTION("before any reply byte")
	{
		FakePeer peer(sock, [](int c) {
			answerHello(c);
			(void)recvBytes(c, 1); // 'T', then gone
		});
		UnixChannel ch(sock);
		const auto e = thrown([&] { (void)ch.now(); });
		CHECK(e.errnoValue() == ECONNRESET);
		CHECK_THAT(e.what(),
			   Equals("unix:" + sock + ": ecmxf-sim closed the connection in the middle of the 'T' request"));
	}
	SECTION("in the middle of the reply")
	{
		FakePeer peer(sock, [](int c) {
			answerHello(c);
			(void)recvBytes(c, 3 + 124);
			sendBytes(c, std::string("X\x7c\x00\x11\x22", 5));
		});
		UnixChannel ch(sock);
		std::vector<std::uint8_t> mosi(124), miso(124);
		const auto e = thrown([&] { ch.exchange(mosi, miso); });
		CHECK(e.errnoValue() == ECONNRESET);
		CHECK_THAT(e.what(), Equals("unix:" + sock +
					    ": ecmxf-sim closed the connection in the middle of the 'X' request "
					    "(after 5 bytes of its reply)"));
	}
	SECTION("a real server killed while a client is connected")
	{
		auto server = std::make_unique<Server>(sock);
		UnixChannel ch(sock);
		(void)ch.now();
		server.reset();
		const auto e = thrown([&] { (void)ch.now(); });
		CHECK((e.errnoValue() == ECONNRESET || e.errnoValue() == EPIPE));
		CHECK_THAT(e.what(), StartsWith("unix:" + sock + ": "));
	}
	SECTION("a real server killed under a Device: the next command fails, nothing terminates")
	{
		// the engine reads the channel's clock before a batch: that read
		// failing was once outside the engine's catch (std::terminate)
		auto server = std::make_unique<Server>(sock);
		auto dev = ecmxf::Device::open("unix:" + sock);
		(void)dev->bus().slaveCount();
		server.reset();
		const auto e = thrown([&] { (void)dev->bus().slaveCount(); });
		CHECK((e.errnoValue() == ECONNRESET || e.errnoValue() == EPIPE || e.errnoValue() == EIO));
		CHECK_THAT(e.what(), Contains("unix:" + sock));
	}
}

TEST_CASE("unix: an 'E' reply is an error with the server's message (EPROTO)", "[unix][errors]")
{
	TempDir dir;
	const std::string sock = dir.path + "/s";

	SECTION("the real server refuses an exchange of a size no packet has")
	{
		Server server(sock);
		UnixChannel ch(sock);
		std::vector<std::uint8_t> mosi(10), miso(10);
		const auto e = thrown([&] { ch.exchange(mosi, miso); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("unix:" + sock +
					    ": ecmxf-sim refused the 'X' request: exchange of 10 bytes: packets are "
					    "56..1440 bytes"));
		// the connection stays usable after an 'E'
		CHECK(ch.waitReady(std::chrono::milliseconds(1)));
	}
	SECTION("any request")
	{
		FakePeer peer(sock, [](int c) {
			answerHello(c);
			(void)recvBytes(c, 1 + 8);
			sendBytes(c, std::string("E\x04\x00nope", 7));
			(void)recvBytes(c, 1);
		});
		UnixChannel ch(sock);
		const auto e = thrown([&] { ch.sleepFor(std::chrono::microseconds(5)); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("unix:" + sock + ": ecmxf-sim refused the 'A' request: nope"));
	}
	SECTION("a reply of the wrong type")
	{
		FakePeer peer(sock, [](int c) {
			answerHello(c);
			(void)recvBytes(c, 1);
			sendBytes(c, std::string("L\x04", 2));
			(void)recvBytes(c, 1);
		});
		UnixChannel ch(sock);
		const auto e = thrown([&] { (void)ch.now(); });
		CHECK(e.errnoValue() == EPROTO);
		CHECK_THAT(e.what(), Equals("unix:" + sock + ": ecmxf-sim answered the 'T' request with a 'L' reply"));
	}
}

// ---------------------------------------------------------------- the URI

TEST_CASE("unix: URIs: the socket path, check=, trace= and nothing else", "[unix][uri]")
{
	auto u = ecmxf::parseDeviceUri("unix:/tmp/s");
	CHECK(u.kind == ecmxf::DeviceUri::Kind::Unix);
	CHECK(u.path == "/tmp/s");
	CHECK(u.trace.empty());
	u = ecmxf::parseDeviceUri("unix:relative/s?trace=/tmp/t.trace");
	CHECK(u.kind == ecmxf::DeviceUri::Kind::Unix);
	CHECK(u.path == "relative/s");
	CHECK(u.trace == "/tmp/t.trace");
	CHECK_THAT(std::string(ecmxf::kDeviceUriForms), Contains("\"unix:<socket path>\""));

	const auto bad = [](const std::string &uri, const std::string &what) {
		INFO("URI " << uri);
		const auto e = thrown([&] { (void)ecmxf::parseDeviceUri(uri); });
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("cannot open \"" + uri + "\": " + what + "; accepted: " +
					    std::string(ecmxf::kDeviceUriForms)));
	};
	bad("unix:", "no socket path after \"unix:\" (e.g. unix:/tmp/ecmxf-sim.sock, served by "
		     "`ecmxf-sim --socket /tmp/ecmxf-sim.sock`)");
	bad("unix:?trace=/tmp/t", "no socket path after \"unix:\" (e.g. unix:/tmp/ecmxf-sim.sock, served by "
				  "`ecmxf-sim --socket /tmp/ecmxf-sim.sock`)");
	bad("unix:/tmp/s?speed=1",
	    "option \"speed\" applies to spidev: URIs only (unix: takes check=<type> and trace=<file>)");
	bad("unix:/tmp/s?check=crc-32",
	    "bad check value \"crc-32\": expected fixed, crc8, ccitt or crc32 (the check word to switch the chip to)");
	bad("unix:/tmp/s?foo=1", "unknown option \"foo\" (check=<type> and trace=<file> are accepted here)");
	bad("unix:/tmp/s?trace=", "option \"trace\" needs a file name (trace=<file>)");
}

// -------------------------------------------------------- the reply parser

TEST_CASE("unix: parseSimReply takes replies apart without reading past them", "[unix][parser]")
{
	using S = ecmxf::SimReply::Status;
	// the payload points into the parsed bytes: they stay in buf
	std::string buf;
	const auto parse = [&buf](const std::string &s) {
		buf = s;
		return ecmxf::parseSimReply(
			std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t *>(buf.data()), buf.size()));
	};
	auto r = parse("");
	CHECK(r.status == S::NeedMore);
	CHECK(r.size == 1);
	r = parse("T\x01\x02");
	CHECK(r.status == S::NeedMore);
	CHECK(r.size == 9);
	r = parse(std::string("T\x01\x02\x00\x00\x00\x00\x00\x00", 9));
	CHECK(r.status == S::Complete);
	CHECK(r.value == 0x0201);
	r = parse("X\x03");
	CHECK(r.status == S::NeedMore);
	CHECK(r.size == 3);
	r = parse(std::string("X\x03\x00\xaa\xbb", 5));
	CHECK(r.status == S::NeedMore);
	CHECK(r.size == 6);
	r = parse(std::string("X\x03\x00\xaa\xbb\xcc\xdd", 7));
	CHECK(r.status == S::Complete);
	CHECK(r.size == 6);
	REQUIRE(r.payload.size() == 3);
	CHECK(r.payload[2] == 0xcc);
	r = parse(helloReply(7));
	CHECK(r.status == S::Complete);
	CHECK(r.type == 'H');
	CHECK(r.value == 7);
	CHECK(std::string(r.payload.begin(), r.payload.end()) == UnixChannel::kHelloMagic);
	r = parse("Q");
	CHECK(r.status == S::Complete);
	CHECK(r.size == 1);
	r = parse("Z123");
	CHECK(r.status == S::Malformed);
	r = parse(std::string("\0", 1));
	CHECK(r.status == S::Malformed);
}
