// SPDX-License-Identifier: MIT
// RealtimeConfig (include/ecmxf/pdo/realtime.hpp): bad values are refused
// naming the field and the range, before anything is applied (also by the
// Cyclic constructor); the default applies nothing; applied in a child
// process (the test runner keeps its scheduling and memory), it sets
// SCHED_FIFO, the CPU and the memory lock, or, without the privilege,
// fails with EPERM naming what it needs.

#include <catch2/catch.hpp>

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/sysinfo.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <string>

#include <ecmxf/error.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/pdo/realtime.hpp>

#include "bus.hpp"
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxftest::thrown;

namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAsan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAsan = true;
#else
constexpr bool kAsan = false;
#endif
#else
constexpr bool kAsan = false;
#endif

/// Runs @p body in a child process; its exit status (0..255), or -1.
template <typename F>
int inChild(F &&body)
{
	const pid_t pid = ::fork();
	if (pid == 0)
		::_exit(body());
	int st = 0;
	if (pid < 0 || ::waitpid(pid, &st, 0) != pid || !WIFEXITED(st))
		return -1;
	return WEXITSTATUS(st);
}

/// VmLck of this process in kB (/proc/self/status), or -1.
long lockedKb()
{
	std::ifstream f("/proc/self/status");
	for (std::string line; std::getline(f, line);)
		if (line.rfind("VmLck:", 0) == 0)
			return std::stol(line.substr(6));
	return -1;
}

} // namespace

TEST_CASE("realtime: bad values are refused naming the field and the range", "[lib][pdo][realtime]")
{
	CHECK_NOTHROW(ecmxf::checkRealtime(ecmxf::RealtimeConfig{}));
	const int hi = ::sched_get_priority_max(SCHED_FIFO);
	const int lo = ::sched_get_priority_min(SCHED_FIFO);
	const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
	for (const int p : { hi + 1, -1, 1000 }) {
		ecmxf::RealtimeConfig rt;
		rt.priority = p;
		const ecmxf::Error e = thrown([&] { ecmxf::checkRealtime(rt); });
		CHECK_THAT(e.what(), Equals("realtime: priority " + std::to_string(p) + " outside " + range +
					    " (SCHED_FIFO; 0 leaves the scheduling as it is)"));
		CHECK(e.errnoValue() == EINVAL);
		// applyRealtime() checks first: nothing is applied
		CHECK(thrown([&] { ecmxf::applyRealtime(rt); }).errnoValue() == EINVAL);
	}
	const int n = ::get_nprocs_conf();
	for (const int cpu : { -2, n, 100000 }) {
		ecmxf::RealtimeConfig rt;
		rt.cpu = cpu;
		const ecmxf::Error e = thrown([&] { ecmxf::checkRealtime(rt); });
		CHECK_THAT(e.what(), Equals("realtime: CPU " + std::to_string(cpu) +
					    " is not present (this system has CPUs 0.." + std::to_string(n - 1) +
					    "; -1 leaves the affinity as it is)"));
		CHECK(e.errnoValue() == EINVAL);
	}
	ecmxf::RealtimeConfig rt;
	rt.prefaultStack = ecmxf::RealtimeConfig::kMaxPrefaultStack + 1;
	const ecmxf::Error e = thrown([&] { ecmxf::checkRealtime(rt); });
	CHECK_THAT(e.what(), Equals("realtime: prefaultStack 1048577 bytes above the 1048576 allowed"));
	CHECK(e.errnoValue() == EINVAL);
}

TEST_CASE("realtime: a Cyclic with a bad realtime setup is refused when it is made", "[lib][pdo][realtime]")
{
	pdotest::Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::CyclicConfig cc;
	cc.realtime.priority = 1000;
	const ecmxf::Error e = thrown([&] { ecmxf::Cyclic cyc(*bus.dev, image, cc); });
	CHECK_THAT(e.what(), Contains("realtime: priority 1000 outside"));
	CHECK(e.errnoValue() == EINVAL);
	cc.realtime = ecmxf::RealtimeConfig{};
	cc.realtime.cpu = -7;
	CHECK_THAT(thrown([&] { ecmxf::Cyclic cyc(*bus.dev, image, cc); }).what(),
		   Contains("realtime: CPU -7 is not present"));
	// the refused ones left no claim behind: a good one is made
	cc.realtime = ecmxf::RealtimeConfig{};
	ecmxf::Cyclic cyc(*bus.dev, image, cc);
	cyc.start();
	CHECK(cyc.cycle().error == 0);
	cyc.stop();
}

TEST_CASE("realtime: the default applies nothing", "[lib][pdo][realtime]")
{
	int policy = -1;
	sched_param before{};
	REQUIRE(::pthread_getschedparam(::pthread_self(), &policy, &before) == 0);
	cpu_set_t setBefore;
	REQUIRE(::sched_getaffinity(0, sizeof(setBefore), &setBefore) == 0);
	const long locked = lockedKb();

	ecmxf::applyRealtime(ecmxf::RealtimeConfig{});

	int policyAfter = -1;
	sched_param after{};
	REQUIRE(::pthread_getschedparam(::pthread_self(), &policyAfter, &after) == 0);
	CHECK(policyAfter == policy);
	CHECK(after.sched_priority == before.sched_priority);
	cpu_set_t setAfter;
	REQUIRE(::sched_getaffinity(0, sizeof(setAfter), &setAfter) == 0);
	CHECK(CPU_EQUAL(&setBefore, &setAfter));
	CHECK(lockedKb() == locked);
}

TEST_CASE("realtime: applied where permitted (SCHED_FIFO, CPU 0, memory locked), refused with EPERM and what "
	  "it needs where not",
	  "[lib][pdo][realtime]")
{
	// 1: applied; 2: not applied as asked; 3: EPERM (no privilege here);
	// 4: another error
	const int applied = inChild([] {
		ecmxf::RealtimeConfig rt;
		rt.priority = 1;
		rt.cpu = 0;
		// ASan's shadow memory is not to be locked
		rt.lockMemory = !kAsan;
		rt.prefaultStack = 256 * 1024;
		try {
			ecmxf::applyRealtime(rt);
		} catch (const ecmxf::Error &e) {
			return e.errnoValue() == EPERM && std::strstr(e.what(), "needs") ? 3 : 4;
		}
		int policy = -1;
		sched_param sp{};
		cpu_set_t set;
		if (::pthread_getschedparam(::pthread_self(), &policy, &sp) != 0 ||
		    ::sched_getaffinity(0, sizeof(set), &set) != 0)
			return 4;
		const bool locked = kAsan || lockedKb() > 0;
		return policy == SCHED_FIFO && sp.sched_priority == 1 && CPU_COUNT(&set) == 1 && CPU_ISSET(0, &set) &&
				       locked
			       ? 1
			       : 2;
	});
	INFO("child: " << applied);
	CHECK((applied == 1 || applied == 3));

	// without the privilege: no RT priority and no locked memory allowed,
	// and as root also another user (root's capabilities go with it)
	const int refused = inChild([] {
		const rlimit none{ 0, 0 };
		if (::setrlimit(RLIMIT_RTPRIO, &none) != 0 || ::setrlimit(RLIMIT_MEMLOCK, &none) != 0)
			return 10;
		if (::getuid() == 0 && (::setresgid(65534, 65534, 65534) != 0 || ::setresuid(65534, 65534, 65534) != 0))
			return 11;
		int bits = 0;
		ecmxf::RealtimeConfig prio;
		prio.priority = 1;
		try {
			ecmxf::applyRealtime(prio);
		} catch (const ecmxf::Error &e) {
			if (e.errnoValue() == EPERM && std::strstr(e.what(), "SCHED_FIFO priority 1 (pthread_setschedparam) "
									  "failed: ") &&
			    std::strstr(e.what(), "needs CAP_SYS_NICE"))
				bits |= 1;
		}
		ecmxf::RealtimeConfig mem;
		mem.lockMemory = true;
		try {
			ecmxf::applyRealtime(mem);
		} catch (const ecmxf::Error &e) {
			if ((e.errnoValue() == EPERM || e.errnoValue() == ENOMEM) &&
			    std::strstr(e.what(), "needs CAP_IPC_LOCK"))
				bits |= 2;
		}
		return bits;
	});
	// AddressSanitizer intercepts mlockall() and makes it a no-op that
	// succeeds, so there only the priority can be refused
	CHECK(refused == (kAsan ? 1 : 3));
}
