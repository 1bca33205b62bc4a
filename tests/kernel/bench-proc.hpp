// SPDX-License-Identifier: MIT
// What the guest benchmarks (guest-bench.cpp, guest-cyclic-bench.cpp) read
// from /proc about CPU time (their own, and the ecmxf0 link worker's), CPU
// pinning, and the exact system-call count of a piece of code (ptrace).
#pragma once

#include <dirent.h>
#include <sched.h>
#include <signal.h>
#include <sys/ptrace.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <sys/user.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

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

inline const char *syscallName(std::size_t nr)
{
	switch (nr) {
	case SYS_read: return "read";
	case SYS_write: return "write";
#ifdef SYS_poll // x86-64; arm64 has only ppoll
	case SYS_poll: return "poll";
#endif
	case SYS_ioctl: return "ioctl";
	case SYS_brk: return "brk";
	case SYS_mmap: return "mmap";
	case SYS_munmap: return "munmap";
	case SYS_futex: return "futex";
	case SYS_clock_gettime: return "clock_gettime";
	case SYS_clock_nanosleep: return "clock_nanosleep";
	case SYS_nanosleep: return "nanosleep";
	case SYS_ppoll: return "ppoll";
	default: return nullptr;
	}
}

/// System calls made by @p body, run in a child process traced with
/// PTRACE_SYSCALL (between two getppid() markers); @p which gets them by
/// name, @p failed the number @p body returns (its failed commands). -1
/// where that cannot be counted (not x86-64).
inline long countSyscalls(const std::function<int()> &body, std::string &which, int &failed)
{
	failed = -1;
#if defined(__x86_64__)
	std::fflush(stdout);
	const pid_t pid = ::fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		::ptrace(PTRACE_TRACEME, 0, nullptr, nullptr);
		::raise(SIGSTOP);
		::syscall(SYS_getppid);
		const int f = body();
		::syscall(SYS_getppid);
		::_exit(std::min(f, 255));
	}
	int st = 0;
	::waitpid(pid, &st, 0);
	::ptrace(PTRACE_SETOPTIONS, pid, nullptr, reinterpret_cast<void *>(PTRACE_O_TRACESYSGOOD | PTRACE_O_EXITKILL));
	long count = 0;
	int markers = 0;
	std::vector<long> nrs; // syscall number -> count
	bool entry = true;
	long sig = 0;
	for (;;) {
		if (::ptrace(PTRACE_SYSCALL, pid, nullptr, reinterpret_cast<void *>(sig)) < 0)
			break;
		sig = 0;
		if (::waitpid(pid, &st, 0) < 0)
			break;
		if (WIFEXITED(st)) {
			failed = WEXITSTATUS(st);
			break;
		}
		if (WIFSIGNALED(st))
			break;
		if (!WIFSTOPPED(st))
			continue;
		if (WSTOPSIG(st) == (SIGTRAP | 0x80)) {
			if (entry) {
				user_regs_struct regs{};
				::ptrace(PTRACE_GETREGS, pid, nullptr, &regs);
				if (static_cast<long>(regs.orig_rax) == SYS_getppid)
					markers++;
				else if (markers == 1) {
					count++;
					const auto nr = static_cast<std::size_t>(regs.orig_rax);
					if (nr < 1024) {
						if (nrs.size() <= nr)
							nrs.resize(nr + 1, 0);
						nrs[nr]++;
					}
				}
			}
			entry = !entry;
		} else {
			sig = WSTOPSIG(st); // deliver it
		}
	}
	if (failed < 0 && ::waitpid(pid, &st, 0) == pid && WIFEXITED(st))
		failed = WEXITSTATUS(st);
	for (std::size_t nr = 0; nr < nrs.size(); nr++) {
		if (!nrs[nr])
			continue;
		const char *name = syscallName(nr);
		which += " ";
		which += name ? name : "nr" + std::to_string(nr);
		which += "=" + std::to_string(nrs[nr]);
	}
	return markers >= 2 ? count : -1;
#else
	(void)body;
	(void)which;
	(void)failed;
	return -1;
#endif
}

} // namespace ecmxf::ktest
