// SPDX-License-Identifier: MIT
// RealtimeConfig: memory lock, SCHED_FIFO, CPU affinity and a pre-faulted
// stack for the cyclic thread (include/ecmxf/pdo/realtime.hpp,
// Documentation/process-data.rst "Real time").

#include <ecmxf/error.hpp>
#include <ecmxf/pdo/realtime.hpp>

#include <alloca.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/sysinfo.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace ecmxf {

namespace {

/// Touches @p bytes of stack below this frame, one write per page.
[[gnu::noinline]] void touchStack(std::size_t bytes) noexcept
{
	auto *p = static_cast<volatile unsigned char *>(alloca(bytes));
	for (std::size_t i = 0; i < bytes; i += 4096)
		p[i] = 0;
	if (bytes)
		p[bytes - 1] = 0;
}

/// @p hint is added to a refusal (EPERM; ENOMEM from mlockall: over
/// RLIMIT_MEMLOCK).
[[noreturn]] void failed(const std::string &what, int err, const char *hint, bool hintOnNomem = false)
{
	const bool refused = err == EPERM || (hintOnNomem && err == ENOMEM);
	throw Error("realtime: " + what + " failed: " + std::strerror(err) + (refused ? hint : ""), err);
}

} // namespace

void checkRealtime(const RealtimeConfig &rt)
{
	if (rt.priority != 0) {
		const int lo = ::sched_get_priority_min(SCHED_FIFO);
		const int hi = ::sched_get_priority_max(SCHED_FIFO);
		if (rt.priority < lo || rt.priority > hi)
			throw Error("realtime: priority " + std::to_string(rt.priority) + " outside " +
					    std::to_string(lo) + ".." + std::to_string(hi) +
					    " (SCHED_FIFO; 0 leaves the scheduling as it is)",
				    EINVAL);
	}
	if (rt.cpu != -1) {
		const int n = ::get_nprocs_conf();
		if (rt.cpu < 0 || rt.cpu >= n || rt.cpu >= CPU_SETSIZE)
			throw Error("realtime: CPU " + std::to_string(rt.cpu) + " is not present (this system has CPUs 0.." +
					    std::to_string(n - 1) + "; -1 leaves the affinity as it is)",
				    EINVAL);
	}
	if (rt.prefaultStack > RealtimeConfig::kMaxPrefaultStack)
		throw Error("realtime: prefaultStack " + std::to_string(rt.prefaultStack) + " bytes above the " +
				    std::to_string(RealtimeConfig::kMaxPrefaultStack) + " allowed",
			    EINVAL);
}

void applyRealtime(const RealtimeConfig &rt)
{
	checkRealtime(rt);
	if (rt.cpu != -1) {
		cpu_set_t set;
		CPU_ZERO(&set);
		CPU_SET(static_cast<std::size_t>(rt.cpu), &set);
		const int err = ::pthread_setaffinity_np(::pthread_self(), sizeof(set), &set);
		if (err)
			failed("running the thread on CPU " + std::to_string(rt.cpu) + " (sched_setaffinity)", err,
			       " (the CPU is outside this process's cpuset)");
	}
	if (rt.lockMemory && ::mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
		const int err = errno;
		failed("locking the memory (mlockall(MCL_CURRENT | MCL_FUTURE))", err,
		       " (needs CAP_IPC_LOCK, or an RLIMIT_MEMLOCK as large as the process: ulimit -l)", true);
	}
	touchStack(rt.prefaultStack);
	if (rt.priority != 0) {
		sched_param sp{};
		sp.sched_priority = rt.priority;
		const int err = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &sp);
		if (err)
			failed("SCHED_FIFO priority " + std::to_string(rt.priority) + " (pthread_setschedparam)", err,
			       " (needs CAP_SYS_NICE, or an RLIMIT_RTPRIO of at least the priority: ulimit -r, or run "
			       "under chrt)");
	}
}

} // namespace ecmxf
