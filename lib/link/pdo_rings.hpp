// SPDX-License-Identifier: MIT
// Internal: the kernel module's PDO rings as one object (Link::openPdoRings(),
// made by KernelLink): the claim on the cyclic path, the rings' setup and
// their two mappings, and the wait for input frames. Everything the cyclic
// path needs from the kernel goes through here: no ioctl or mmap outside
// lib/link/kernel_link.cpp.
#pragma once

#include <chrono>
#include <string>

#include "base/os.hpp"
#include "link/pdo_ring.hpp"
#include "uapi/linux/ecmxf.h"

namespace ecmxf::detail {

class PdoRings
{
public:
	/// Holds the claim (ECMXF_IOC_CLAIM, taken by KernelLink) on @p fd,
	/// which outlives this object; @p name names the device in messages.
	PdoRings(int fd, std::string name) noexcept : fd_(fd), name_(std::move(name)) {}
	~PdoRings();
	PdoRings(const PdoRings &) = delete;
	PdoRings &operator=(const PdoRings &) = delete;

	/// ECMXF_IOC_RING_SETUP with @p rs (the kernel fills in the layouts)
	/// and both rings mapped; rings set up before are unmapped first.
	/// Throws ecmxf::Error naming the call that failed.
	void setup(ecmxf_ring_setup &rs);
	/// The output ring (frames to the chip) and the input ring (frames from
	/// it); invalid views before setup().
	[[nodiscard]] PdoRingView &out() noexcept { return out_; }
	[[nodiscard]] PdoRingView &in() noexcept { return in_; }
	/// Waits up to @p timeout for the input ring to hold frames or the pump
	/// to stop (ppoll for POLLRDBAND: the rings were set up with
	/// ECMXF_RING_F_POLL_IN). Returns 0 when woken or timed out (look at
	/// the rings), 1 when the device reports an error or hang-up, or a
	/// negative errno.
	[[nodiscard]] int wait(std::chrono::nanoseconds timeout) noexcept;

private:
	void unmap() noexcept;

	int fd_;
	std::string name_;
	Mapping outMap_, inMap_;
	PdoRingView out_, in_;
};

} // namespace ecmxf::detail
