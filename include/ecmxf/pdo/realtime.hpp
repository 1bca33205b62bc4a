// SPDX-License-Identifier: MIT
/**
 * @file realtime.hpp
 * @brief What a real-time cyclic thread needs from the system: memory
 *        locked, a SCHED_FIFO priority, a CPU, a pre-faulted stack.
 *
 * CyclicConfig::realtime carries a RealtimeConfig: the Cyclic checks it
 * when it is made and applies it to the thread that calls start(). A
 * thread of the application's own (e.g. one that runs several Cyclics)
 * calls applyRealtime() itself. Documentation/process-data.rst, "Real
 * time", has the chrt / isolcpus recipe for a PREEMPT_RT board.
 *
 * @code
 *   ecmxf::CyclicConfig cc = ecmxf::CyclicConfig::motion(1ms);
 *   cc.realtime.lockMemory = true;    // mlockall(MCL_CURRENT | MCL_FUTURE)
 *   cc.realtime.priority = 80;        // SCHED_FIFO 80
 *   cc.realtime.cpu = 3;              // the CPU isolcpus=3 keeps free
 *   cc.realtime.prefaultStack = 256 * 1024;
 *   ecmxf::Cyclic cyc(dev, image, cc);
 *   cyc.start();                      // on the cyclic thread
 * @endcode
 */
#pragma once

#include <cstddef>

#include <ecmxf/export.hpp>

namespace ecmxf {

/// The real-time setup of the thread that runs the cycle. The default
/// changes nothing.
struct RealtimeConfig {
	/// The largest prefaultStack: a quarter of the smallest default
	/// thread stack of the usual C libraries (glibc's 8 MiB, musl's
	/// 128 KiB do not bound it; 1 MiB leaves the rest of an 8 MiB stack).
	static constexpr std::size_t kMaxPrefaultStack = 1024 * 1024;

	/// mlockall(MCL_CURRENT | MCL_FUTURE): every page of the process
	/// resident, now and later (no page fault in the cycle). Needs
	/// CAP_IPC_LOCK or an RLIMIT_MEMLOCK (ulimit -l) as large as the
	/// process.
	bool lockMemory = false;
	/// SCHED_FIFO at this priority for the thread (1..99 on Linux:
	/// sched_get_priority_min/max(SCHED_FIFO)); 0: its scheduling is left
	/// as it is (e.g. set from outside with chrt). Needs CAP_SYS_NICE or
	/// an RLIMIT_RTPRIO (ulimit -r) of at least this.
	int priority = 0;
	/// Runs the thread on this CPU only (sched_setaffinity); -1: its
	/// affinity is left as it is. A CPU kept free with isolcpus= is
	/// allowed (it is in no process's default affinity).
	int cpu = -1;
	/// Touches this many bytes of the thread's stack below the caller's
	/// frame, so that the cycle's deeper calls find their pages present
	/// (locked too with lockMemory); 0: none. At most kMaxPrefaultStack.
	std::size_t prefaultStack = 0;
};

/// Checks @p rt without applying it: throws ecmxf::Error (EINVAL) naming
/// the field and the allowed range (a priority outside
/// sched_get_priority_min..max(SCHED_FIFO), a CPU this system does not
/// have, a prefaultStack above kMaxPrefaultStack).
ECMXF_EXPORT void checkRealtime(const RealtimeConfig &rt);

/// Checks and applies @p rt to the calling thread, in the order CPU,
/// memory lock, stack, priority. Throws ecmxf::Error with the errno of the
/// call that failed (EPERM naming the capability or rlimit it needs);
/// what was applied before the failure stays applied. The default
/// RealtimeConfig makes no system call.
ECMXF_EXPORT void applyRealtime(const RealtimeConfig &rt);

} // namespace ecmxf
