// SPDX-License-Identifier: MIT
// ecmxf-sim: the byte-pipe server of the simulator, driven as another
// program would drive it (over its standard input/output and over a Unix
// socket), with packets built by the protocol core.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include "ecmxf-proto.h"

namespace {

struct Child {
	pid_t pid = -1;
	int to = -1;	// its stdin
	int from = -1;	// its stdout

	explicit Child(std::vector<std::string> args)
	{
		int in[2], out[2];
		REQUIRE(pipe2(in, O_CLOEXEC) == 0);
		REQUIRE(pipe2(out, O_CLOEXEC) == 0);
		pid = fork();
		REQUIRE(pid >= 0);
		if (pid == 0) {
			dup2(in[0], 0);
			dup2(out[1], 1);
			std::vector<char *> argv;
			argv.push_back(const_cast<char *>(ECMXF_SIM_BINARY));
			for (auto &a : args)
				argv.push_back(a.data());
			argv.push_back(nullptr);
			execv(ECMXF_SIM_BINARY, argv.data());
			_exit(127);
		}
		close(in[0]);
		close(out[1]);
		to = in[1];
		from = out[0];
	}
	~Child()
	{
		if (to >= 0)
			close(to);
		if (from >= 0)
			close(from);
		if (pid > 0) {
			kill(pid, SIGKILL);
			waitpid(pid, nullptr, 0);
		}
	}
	int wait()
	{
		close(to);
		to = -1;
		int st = 0;
		waitpid(pid, &st, 0);
		pid = -1;
		return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
	}
};

void writeAll(int fd, const std::vector<std::uint8_t> &b)
{
	std::size_t off = 0;
	while (off < b.size()) {
		const ssize_t r = write(fd, b.data() + off, b.size() - off);
		REQUIRE(r > 0);
		off += static_cast<std::size_t>(r);
	}
}

std::vector<std::uint8_t> readN(int fd, std::size_t n)
{
	std::vector<std::uint8_t> b(n);
	std::size_t off = 0;
	while (off < n) {
		const ssize_t r = read(fd, b.data() + off, n - off);
		REQUIRE(r > 0);
		off += static_cast<std::size_t>(r);
	}
	return b;
}

std::vector<std::uint8_t> exchangeMsg(const std::vector<std::uint8_t> &mosi)
{
	std::vector<std::uint8_t> m = { 'X', static_cast<std::uint8_t>(mosi.size()),
					static_cast<std::uint8_t>(mosi.size() >> 8) };
	m.insert(m.end(), mosi.begin(), mosi.end());
	return m;
}

std::vector<std::uint8_t> infoUpdate(std::uint8_t index)
{
	std::vector<std::uint8_t> p(ECMXF_PKT_SIZE(ECMXF_DATA_DEFAULT));
	ecmxf_cmd_hdr h{};
	h.index = index;
	h.code = ECMXF_CMD_INFO_UPDATE_OP;
	REQUIRE(ecmxf_encode_cmd(p.data(), p.size(), ECMXF_CHECK_FIXED, &h, nullptr, 0) == 0);
	return p;
}

std::vector<std::uint8_t> exchange(int to, int from, const std::vector<std::uint8_t> &mosi)
{
	writeAll(to, exchangeMsg(mosi));
	auto head = readN(from, 3);
	REQUIRE(head[0] == 'X');
	const auto n = static_cast<std::size_t>(head[1] | (head[2] << 8));
	REQUIRE(n == mosi.size());
	return readN(from, n);
}

std::uint64_t le64(const std::vector<std::uint8_t> &b, std::size_t off)
{
	std::uint64_t v = 0;
	for (int i = 7; i >= 0; i--)
		v = (v << 8) | b[off + static_cast<std::size_t>(i)];
	return v;
}

} // namespace

TEST_CASE("ecmxf-sim over stdin/stdout: NOP first, then answers one exchange late", "[sim-tool]")
{
	Child c({});
	auto r1 = exchange(c.to, c.from, infoUpdate(1));
	ecmxf_rsp_hdr h{};
	REQUIRE(ecmxf_decode_rsp(r1.data(), r1.size(), ECMXF_CHECK_FIXED, &h, nullptr) ==
		ECMXF_FAULT_NONE);
	CHECK((h.ecm_status & ECMXF_STS_NOP) != 0);

	auto r2 = exchange(c.to, c.from, infoUpdate(2));
	REQUIRE(ecmxf_decode_rsp(r2.data(), r2.size(), ECMXF_CHECK_FIXED, &h, nullptr) ==
		ECMXF_FAULT_NONE);
	CHECK((h.ecm_status & ECMXF_STS_NOP) == 0);
	CHECK(h.index == 1);

	writeAll(c.to, { 'Q' });
	CHECK(readN(c.from, 1)[0] == 'Q');
	CHECK(c.wait() == 0);
}

TEST_CASE("ecmxf-sim: INT lines, virtual time and fault requests", "[sim-tool]")
{
	Child c({});
	writeAll(c.to, { 'T' });
	auto t0 = readN(c.from, 9);
	REQUIRE(t0[0] == 'T');
	writeAll(c.to, { 'A', 0x40, 0x42, 0x0F, 0, 0, 0, 0, 0 }); // +1 ms
	auto t1 = readN(c.from, 9);
	REQUIRE(t1[0] == 'A');
	CHECK(le64(t1, 1) == le64(t0, 1) + 1'000'000);

	writeAll(c.to, { 'L' });
	auto l = readN(c.from, 2);
	REQUIRE(l[0] == 'L');
	CHECK((l[1] & 4) != 0); // ready after a millisecond of quiet
	CHECK((l[1] & 1) != 0); // INT0 is active high = ready by default
	CHECK((l[1] & 2) != 0); // INT1 idle high (active low)

	// "not ready" for the next exchange
	writeAll(c.to, { 'F', 3, 1, 0, 0, 0 });
	CHECK(readN(c.from, 2) == std::vector<std::uint8_t>{ 'F', 0 });
	auto r = exchange(c.to, c.from, infoUpdate(1));
	CHECK(ecmxf_decode_rsp(r.data(), r.size(), ECMXF_CHECK_FIXED, nullptr, nullptr) ==
	      ECMXF_FAULT_NOT_READY);
}

TEST_CASE("ecmxf-sim: malformed requests are answered with an error message", "[sim-tool]")
{
	Child c({});
	writeAll(c.to, { 'X', 10, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 });
	auto e = readN(c.from, 3);
	REQUIRE(e[0] == 'E');
	const auto n = static_cast<std::size_t>(e[1] | (e[2] << 8));
	auto msg = readN(c.from, n);
	CHECK(std::string(msg.begin(), msg.end()).find("56..1440") != std::string::npos);

	writeAll(c.to, { 'F', 99, 0, 0, 0, 0 });
	e = readN(c.from, 3);
	REQUIRE(e[0] == 'E');
	msg = readN(c.from, static_cast<std::size_t>(e[1] | (e[2] << 8)));
	CHECK(std::string(msg.begin(), msg.end()).find("unknown fault") != std::string::npos);
}

TEST_CASE("ecmxf-sim: a bad command line exits non-zero with the reason", "[sim-tool]")
{
	Child c({ "--bogus" });
	CHECK(c.wait() == 1);
	Child d({ "--network", "/nonexistent/network.net" });
	CHECK(d.wait() == 1);
}

TEST_CASE("ecmxf-sim over a Unix socket serves clients one after another", "[sim-tool]")
{
	char dir[] = "/tmp/ecmxf-sim-test-XXXXXX";
	REQUIRE(mkdtemp(dir) != nullptr);
	const std::string path = std::string(dir) + "/sock";
	Child c({ "--socket", path });

	auto connectTo = [&]() {
		const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
		REQUIRE(fd >= 0);
		sockaddr_un a{};
		a.sun_family = AF_UNIX;
		std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
		for (int i = 0; i < 200; i++) {
			if (connect(fd, reinterpret_cast<sockaddr *>(&a), sizeof(a)) == 0)
				return fd;
			usleep(10000);
		}
		FAIL("cannot connect to " << path);
		return -1;
	};

	int fd = connectTo();
	auto r1 = exchange(fd, fd, infoUpdate(7));
	ecmxf_rsp_hdr h{};
	REQUIRE(ecmxf_decode_rsp(r1.data(), r1.size(), ECMXF_CHECK_FIXED, &h, nullptr) ==
		ECMXF_FAULT_NONE);
	CHECK((h.ecm_status & ECMXF_STS_NOP) != 0);
	close(fd);

	// the second client sees the same chip: the answer to index 7 is waiting
	fd = connectTo();
	auto r2 = exchange(fd, fd, infoUpdate(8));
	REQUIRE(ecmxf_decode_rsp(r2.data(), r2.size(), ECMXF_CHECK_FIXED, &h, nullptr) ==
		ECMXF_FAULT_NONE);
	CHECK(h.index == 7);
	writeAll(fd, { 'Q' });
	CHECK(readN(fd, 1)[0] == 'Q');
	close(fd);
	CHECK(c.wait() == 0);
	rmdir(dir);
}
