// SPDX-License-Identifier: MIT
//
// ecmxf-chrt: the part of util-linux chrt(1) that the kernel tests need,
// because busybox-static has no chrt applet. A machine builder tunes the
// link worker with the real `chrt -f -p PRIO PID` (Documentation/driver.rst
// "Locking and PREEMPT_RT"); this does the same system calls:
//
//   ecmxf-chrt -p PID             print "<policy> <priority>" of PID
//                                 (e.g. "SCHED_FIFO 50")
//   ecmxf-chrt -f -p PRIO PID     sched_setscheduler(PID, SCHED_FIFO, PRIO)
//   ecmxf-chrt -o -p 0 PID        sched_setscheduler(PID, SCHED_OTHER, 0)
//
// Exit status 0, or 1 with the errno's text on stderr (the kernel's answer:
// e.g. EINVAL for a SCHED_FIFO priority outside 1..99).
#include <sched.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

int usage()
{
	std::fprintf(stderr, "usage: ecmxf-chrt -p PID | ecmxf-chrt -f|-o -p PRIO PID\n");
	return 2;
}

bool parseInt(const char *s, long &out)
{
	char *end = nullptr;
	errno = 0;
	out = std::strtol(s, &end, 10);
	return errno == 0 && end != s && *end == '\0';
}

const char *policyName(int policy)
{
	switch (policy) {
	case SCHED_OTHER:
		return "SCHED_OTHER";
	case SCHED_FIFO:
		return "SCHED_FIFO";
	case SCHED_RR:
		return "SCHED_RR";
	case SCHED_BATCH:
		return "SCHED_BATCH";
	case SCHED_IDLE:
		return "SCHED_IDLE";
	default:
		return "SCHED_UNKNOWN";
	}
}

} // namespace

int main(int argc, char **argv)
{
	long pid = 0;
	long prio = 0;
	if (argc == 3 && std::string(argv[1]) == "-p") {
		if (!parseInt(argv[2], pid) || pid <= 0)
			return usage();
		const int policy = ::sched_getscheduler(static_cast<pid_t>(pid));
		sched_param sp{};
		if (policy < 0 || ::sched_getparam(static_cast<pid_t>(pid), &sp) != 0) {
			std::fprintf(stderr, "ecmxf-chrt: pid %ld: %s\n", pid, std::strerror(errno));
			return 1;
		}
		std::printf("%s %d\n", policyName(policy), sp.sched_priority);
		return 0;
	}
	if (argc != 5 || std::string(argv[2]) != "-p")
		return usage();
	int policy;
	if (std::string(argv[1]) == "-f")
		policy = SCHED_FIFO;
	else if (std::string(argv[1]) == "-o")
		policy = SCHED_OTHER;
	else
		return usage();
	if (!parseInt(argv[3], prio) || !parseInt(argv[4], pid) || pid <= 0)
		return usage();
	sched_param sp{};
	sp.sched_priority = static_cast<int>(prio);
	if (::sched_setscheduler(static_cast<pid_t>(pid), policy, &sp) != 0) {
		std::fprintf(stderr, "ecmxf-chrt: pid %ld: %s %ld: %s\n", pid, policyName(policy), prio,
			     std::strerror(errno));
		return 1;
	}
	return 0;
}
