// SPDX-License-Identifier: MIT
// The ecmxf-sim server as a test runs it (ECMXF_SIM_BINARY, either board)
// and a temporary directory for its socket: shared by the ECM-XF's and the
// ECM-SK's suites (tests/unix, tests/sk_cli).
#pragma once

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <ecmxf/error.hpp>
#include <ecmxf/link/unix_channel.hpp>

namespace ecmxftest {

/// A fresh directory under /tmp, removed with its contents at the end.
struct TempDir {
	std::string path;
	TempDir()
	{
		char t[] = "/tmp/ecmxf-test-XXXXXX";
		REQUIRE(mkdtemp(t) != nullptr);
		path = t;
	}
	~TempDir()
	{
		std::error_code ec;
		std::filesystem::remove_all(path, ec);
	}
	TempDir(const TempDir &) = delete;
	TempDir &operator=(const TempDir &) = delete;
};

/// An ecmxf-sim --socket server (ECMXF_SIM_BINARY), killed at the end.
class SimServer
{
public:
	/// @p extra: more ecmxf-sim options (e.g. --board ecm-sk, --chip
	/// KEY=VALUE). Returns once the server answers a hello.
	explicit SimServer(const std::string &socket, const std::vector<std::string> &extra = {}) : socket_(socket)
	{
		std::vector<std::string> args{ ECMXF_SIM_BINARY, "--socket", socket };
		args.insert(args.end(), extra.begin(), extra.end());
		std::vector<char *> argv;
		for (std::string &a : args)
			argv.push_back(a.data());
		argv.push_back(nullptr);
		pid_ = fork();
		REQUIRE(pid_ >= 0);
		if (pid_ == 0) {
			execv(ECMXF_SIM_BINARY, argv.data());
			_exit(127);
		}
		waitUntilServing();
	}
	~SimServer()
	{
		if (pid_ > 0) {
			kill(pid_, SIGKILL);
			waitpid(pid_, nullptr, 0);
		}
	}
	SimServer(const SimServer &) = delete;
	SimServer &operator=(const SimServer &) = delete;

	/// SIGTERM, then its exit status (-1: it did not exit normally).
	int terminate()
	{
		REQUIRE(pid_ > 0);
		kill(pid_, SIGTERM);
		int st = 0;
		REQUIRE(waitpid(pid_, &st, 0) == pid_);
		pid_ = -1;
		return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
	}

private:
	/// Retries a hello until the server answers it: at most 30 s (the
	/// first connect of a loaded machine), failing with the last reason.
	void waitUntilServing()
	{
		const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
		std::string last = "never tried";
		for (;;) {
			int st = 0;
			if (waitpid(pid_, &st, WNOHANG) == pid_) {
				pid_ = -1;
				FAIL("ecmxf-sim --socket " << socket_ << " exited at start (status " << st << ")");
			}
			try {
				ecmxf::UnixChannel probe(socket_);
				return;
			} catch (const ecmxf::Error &e) {
				// only "not there yet" is worth waiting for
				if (e.errnoValue() != ENOENT && e.errnoValue() != ECONNREFUSED)
					FAIL("ecmxf-sim at " << socket_ << ": " << e.what());
				last = e.what();
			}
			if (std::chrono::steady_clock::now() > deadline)
				FAIL("ecmxf-sim at " << socket_ << " not serving after 30 s: " << last);
			// poll() on nothing: a 5 ms pause between attempts
			poll(nullptr, 0, 5);
		}
	}

	std::string socket_;
	pid_t pid_ = -1;
};

} // namespace ecmxftest
