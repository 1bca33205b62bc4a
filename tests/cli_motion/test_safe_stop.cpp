// SPDX-License-Identifier: MIT
// The safe stop of ecmxf-util (issue 29): a signal sent to the program in
// the middle of a move brings the drive to a halt before it exits with
// 128 + the signal, on both masters: the in-process simulators (sim:,
// sk-sim:) and ecmxf-sim servers (unix:, sk-unix:), whose drives are asked
// for their state afterwards. The signal goes when the program has said
// that the drive moves (its stderr), never after a sleep.
//
// Neither move can end before the signal, by design, however slow the
// machine: on the ECM-XF a PV move with --time 0 runs until it is stopped;
// on the ECM-SK the board is paced (paced=1: its cycles follow the wall
// clock) and the CSP move of 2*10^9 units at most 1000 units a cycle lasts
// over half an hour, beyond the 5-minute guard of Child::waitFor().

#include <catch2/catch.hpp>

#include <cerrno>
#include <csignal>
#include <regex>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <ecmxf/model/cia402.hpp>

#include "cli/cli_run.hpp"
#include "common/sim_server.hpp"

using Catch::Matchers::Contains;

namespace {

/// ecmxf-util as a child process with stdout and stderr piped.
class Child
{
public:
	explicit Child(std::vector<std::string> args)
	{
		args.insert(args.begin(), ECMXF_UTIL_PATH);
		int out[2], err[2];
		REQUIRE(pipe2(out, O_CLOEXEC) == 0);
		REQUIRE(pipe2(err, O_CLOEXEC) == 0);
		pid_ = fork();
		REQUIRE(pid_ >= 0);
		if (pid_ == 0) {
			dup2(out[1], 1);
			dup2(err[1], 2);
			std::vector<char *> argv;
			for (std::string &a : args)
				argv.push_back(a.data());
			argv.push_back(nullptr);
			execv(ECMXF_UTIL_PATH, argv.data());
			_exit(127);
		}
		close(out[1]);
		close(err[1]);
		out_ = out[0];
		err_ = err[0];
	}
	~Child()
	{
		if (pid_ > 0) {
			kill(pid_, SIGKILL);
			waitpid(pid_, nullptr, 0);
		}
		close(out_);
		close(err_);
	}
	Child(const Child &) = delete;
	Child &operator=(const Child &) = delete;

	/// Reads until stderr holds @p text; fails when the program ends
	/// first (a guard of 5 minutes against a hang, no timing).
	void waitFor(const std::string &text)
	{
		while (errText.find(text) == std::string::npos)
			if (!readSome(300'000))
				FAIL("ecmxf-util ended before saying '" << text << "'; stderr: " << errText
									  << "; stdout: " << outText);
	}
	void signal(int sig) { REQUIRE(kill(pid_, sig) == 0); }
	/// Reads both pipes to their end, then the exit status.
	int wait()
	{
		while (readSome(300'000)) {
		}
		int st = 0;
		REQUIRE(waitpid(pid_, &st, 0) == pid_);
		pid_ = -1;
		INFO("stderr: " << errText);
		REQUIRE(WIFEXITED(st)); // not killed by the signal: it handled it
		return WEXITSTATUS(st);
	}

	std::string outText, errText;

private:
	/// false once both pipes are at their end
	bool readSome(int timeoutMs)
	{
		pollfd p[2] = { { outOpen_ ? out_ : -1, POLLIN, 0 }, { errOpen_ ? err_ : -1, POLLIN, 0 } };
		if (!outOpen_ && !errOpen_)
			return false;
		const int n = poll(p, 2, timeoutMs);
		if (n < 0 && errno == EINTR)
			return true;
		REQUIRE(n > 0); // else: hung for minutes
		char buf[4096];
		for (int i = 0; i < 2; i++) {
			if (!(p[i].revents & (POLLIN | POLLHUP | POLLERR)))
				continue;
			const ssize_t r = read(p[i].fd, buf, sizeof buf);
			if (r > 0)
				(i ? errText : outText).append(buf, static_cast<std::size_t>(r));
			else
				(i ? errOpen_ : outOpen_) = false;
		}
		return outOpen_ || errOpen_;
	}

	pid_t pid_ = -1;
	int out_ = -1, err_ = -1;
	bool outOpen_ = true, errOpen_ = true;
};

/// The number after "key": in a JSON object.
long long jsonNumber(const std::string &json, const std::string &key)
{
	std::smatch m;
	const std::regex re("\"" + key + "\": *(-?[0-9]+)");
	REQUIRE(std::regex_search(json, m, re));
	return std::stoll(m[1].str());
}

/// ecmxf-util ARGS run to its end (tests/cli/cli_run.hpp): stdout.
std::string runUtil(const std::string &args)
{
	const auto r = clitest::run(args);
	INFO("ecmxf-util stderr: " << r.err);
	REQUIRE(r.status == 0);
	return r.out;
}

const std::vector<std::string> kPvMove = { "cia402", "-p", "0", "move", "--pv", "20000", "--time", "0" };

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string> &more)
{
	a.insert(a.end(), more.begin(), more.end());
	return a;
}

} // namespace

TEST_CASE("safe stop: SIGINT during a PV move on sim: quick stop, disable, exit 130", "[safe-stop][xf]")
{
	Child c(with({ "-d", "sim:" }, kPvMove));
	c.waitFor("velocity 20000 reached");
	c.signal(SIGINT);
	CHECK(c.wait() == 130);
	CHECK_THAT(c.errText, Contains("cia402 move: interrupted by SIGINT: slave 0: quick stop, then disabled: "
				       "SWITCH ON DISABLED (statusword 0x"));
	CHECK_THAT(c.errText, Contains(", velocity 0\n"));
}

TEST_CASE("safe stop: SIGTERM during a PV move on unix: leaves the server's drive disabled at rest",
	  "[safe-stop][xf][unix]")
{
	ecmxftest::TempDir dir;
	const std::string sock = dir.path + "/sim.sock";
	ecmxftest::SimServer server(sock);
	const std::string dev = "unix:" + sock;
	{
		Child c(with({ "-d", dev }, kPvMove));
		c.waitFor("velocity 20000 reached");
		c.signal(SIGTERM);
		CHECK(c.wait() == 143);
		CHECK_THAT(c.errText, Contains("interrupted by SIGTERM: slave 0: quick stop, then disabled: SWITCH ON "
					       "DISABLED"));
	}
	// the drive as the server's chip has it now (before the fix: OPERATION
	// ENABLED at velocity 20000, the chip sending the last outputs)
	const std::string s1 = runUtil("-d " + dev + " cia402 -p 0 status --json");
	CHECK_THAT(s1, Contains("\"state\": \"SWITCH ON DISABLED\""));
	CHECK(jsonNumber(s1, "velocity_actual") == 0);
	const std::string s2 = runUtil("-d " + dev + " cia402 -p 0 status --json");
	CHECK(jsonNumber(s2, "position_actual") == jsonNumber(s1, "position_actual"));
}

TEST_CASE("safe stop: SIGHUP during a CSP move on sk-sim: SV_OFF, exit 129", "[safe-stop][sk]")
{
	Child c({ "-d", "sk-sim:?paced=1", "cia402", "-p", "0", "move", "2000000000" });
	c.waitFor("CSP move from");
	c.signal(SIGHUP);
	CHECK(c.wait() == 129);
	CHECK_THAT(c.errText, Contains("cia402 move: interrupted by SIGHUP: slave 0: SV_OFF: "));
	CHECK_THAT(c.errText, !Contains("NOT halted"));
	CHECK_THAT(c.errText, !Contains("OPERATION ENABLED"));
}

TEST_CASE("safe stop: SIGINT during a move on sk-unix: leaves the board's drive off and at rest",
	  "[safe-stop][sk][unix]")
{
	ecmxftest::TempDir dir;
	const std::string sock = dir.path + "/sk.sock";
	ecmxftest::SimServer server(sock, { "--board", "ecm-sk", "--paced" });
	const std::string dev = "sk-unix:" + sock;
	{
		Child c({ "-d", dev, "cia402", "-p", "0", "move", "2000000000" });
		c.waitFor("CSP move from");
		c.signal(SIGINT);
		CHECK(c.wait() == 130);
		CHECK_THAT(c.errText, Contains("interrupted by SIGINT: slave 0: SV_OFF: "));
	}
	const std::string s1 = runUtil("-d " + dev + " cia402 -p 0 status --json");
	const auto st = ecmxf::cia402StateFrom(static_cast<std::uint16_t>(jsonNumber(s1, "statusword")));
	CHECK(st != ecmxf::Cia402State::OperationEnabled);
	CHECK(st != ecmxf::Cia402State::SwitchedOn);
	const std::string s2 = runUtil("-d " + dev + " cia402 -p 0 status --json");
	CHECK(jsonNumber(s2, "position_actual") == jsonNumber(s1, "position_actual"));
}
