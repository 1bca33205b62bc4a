// SPDX-License-Identifier: MIT
// Runs ecmxf-util (ECMXF_UTIL_PATH), or another program, as a separate
// process and collects its exit code, stdout and stderr.
#pragma once

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace clitest {

struct Result {
	int status = -1; ///< exit code
	std::string out, err;
};

/// @p program with @p args (passed through /bin/sh: no metacharacters).
inline Result runProgram(const std::string &program, const std::string &args)
{
	static int serial = 0;
	const auto errFile = std::filesystem::temp_directory_path() /
			     ("ecmxf-test-cli-tools-" + std::to_string(getpid()) + "-" +
			      std::to_string(serial++) + ".err");
	const std::string cmd = program + " " + args + " 2>" + errFile.string();
	Result r;
	std::FILE *p = popen(cmd.c_str(), "r");
	REQUIRE(p != nullptr);
	char buf[4096];
	std::size_t n;
	while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0)
		r.out.append(buf, n);
	const int st = pclose(p);
	REQUIRE(WIFEXITED(st));
	r.status = WEXITSTATUS(st);
	std::ifstream f(errFile);
	std::stringstream ss;
	ss << f.rdbuf();
	r.err = ss.str();
	std::filesystem::remove(errFile);
	return r;
}

/// ecmxf-util with @p args (passed through /bin/sh: no metacharacters).
inline Result run(const std::string &args)
{
	return runProgram(ECMXF_UTIL_PATH, args);
}

inline std::vector<std::string> lines(const std::string &s)
{
	std::vector<std::string> v;
	std::istringstream in(s);
	for (std::string l; std::getline(in, l);)
		v.push_back(l);
	return v;
}

} // namespace clitest
