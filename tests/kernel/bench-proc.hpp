// SPDX-License-Identifier: MIT
// What the guest benchmarks (guest-bench.cpp, guest-cyclic-bench.cpp) read
// from /proc about CPU time: their own, and the ecmxf0 link worker's.
#pragma once

#include <dirent.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/time.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <string>

namespace ecmxf::ktest {

/// CPU time of this process (user + system) in microseconds.
inline double cpuUs()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	const auto us = [](const timeval &t) {
		return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_usec);
	};
	return us(ru.ru_utime) + us(ru.ru_stime);
}

/// The pid of the first task whose /proc/PID/comm is @p comm, or 0.
inline long pidOf(const std::string &comm)
{
	DIR *d = ::opendir("/proc");
	if (!d)
		return 0;
	long found = 0;
	while (dirent *e = ::readdir(d)) {
		const long pid = std::strtol(e->d_name, nullptr, 10);
		if (pid <= 0)
			continue;
		std::ifstream f("/proc/" + std::string(e->d_name) + "/comm");
		std::string name;
		if (std::getline(f, name) && name == comm) {
			found = pid;
			break;
		}
	}
	::closedir(d);
	return found;
}

/// The pid of the kernel thread "ecmxf0" (the link worker), or 0.
inline long workerPid()
{
	return pidOf("ecmxf0");
}

/// Runs @p pid (0: this thread) on CPU @p cpu only; 0 or the errno.
inline int pinToCpu(long pid, unsigned cpu)
{
	cpu_set_t set;
	CPU_ZERO(&set);
	CPU_SET(cpu, &set);
	return ::sched_setaffinity(static_cast<pid_t>(pid), sizeof(set), &set) ? errno : 0;
}

/// CPU time of @p pid in microseconds (schedstat: ns on the CPU), or 0.
inline double taskCpuUs(long pid)
{
	if (!pid)
		return 0;
	std::ifstream f("/proc/" + std::to_string(pid) + "/schedstat");
	unsigned long long ns = 0;
	f >> ns;
	return static_cast<double>(ns) / 1000.0;
}

} // namespace ecmxf::ktest
