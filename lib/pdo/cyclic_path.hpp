// SPDX-License-Identifier: MIT
// The strategies behind Cyclic (lib/pdo/cyclic.cpp): how one cycle's frames
// travel between the process image and the bus. Internal to the library.
//
//  - FifoCommandPath (fifo_command_path.cpp): ECAT_PDO_DATA_FIFO_OP over
//    Device::transact(), planned and read by the protocol core's pump
//    (lib/core/ecmxf-pump.c), which the kernel's pump runs too;
//  - RingPath (cyclic.cpp): the kernel's mmap()ed PDO rings.
#ifndef ECMXF_LIB_PDO_CYCLIC_PATH_HPP
#define ECMXF_LIB_PDO_CYCLIC_PATH_HPP

#include <ecmxf/device.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include <chrono>
#include <memory>

namespace ecmxf::detail {

/// Marks @p r failed with a static text (cycle() may not build strings).
inline void cycleFail(CycleResult &r, int err, const char *text) noexcept
{
	r.error = err;
	r.message = text;
}

/// How one cycle's frames travel between the image and the bus.
class CyclicPath
{
public:
	CyclicPath() = default;
	CyclicPath(const CyclicPath &) = delete;
	CyclicPath &operator=(const CyclicPath &) = delete;
	virtual ~CyclicPath() = default;

	/// Prepares the exchange (may send commands; throws ecmxf::Error).
	virtual void start() = 0;
	/// Ends it (throws ecmxf::Error).
	virtual void stop() = 0;
	/// One cycle: outputs out, inputs in; fills @p r (its WKC fields hold
	/// the previous read). Allocates nothing, throws nothing.
	virtual void exchange(CycleResult &r, bool readWkc) noexcept = 0;
	/// The clock the cycle is paced on.
	virtual Link &clock() noexcept = 0;
	/// Cyclic::waitInputs() after its checks.
	virtual int waitInputs(std::chrono::nanoseconds timeout) noexcept = 0;
	/// The kernel's PDO rings carry the frames.
	[[nodiscard]] virtual bool kernelRings() const noexcept { return false; }

	/// Reads the frame sizes, slave counts and FIFO depths and checks the
	/// image and the configuration against them (throws ecmxf::Error).
	void readChip(Device &dev, const ProcessImage &image, const CyclicConfig &cfg);

	// what the path found out when it was set up
	FifoPackSizes sizes{};
	PdoSlaveCounts counts{};
	unsigned rxDepth = 0;
	unsigned txDepth = 0;
	unsigned rxFill = 0;
	unsigned perWrite = 0;
	unsigned perRead = 0;
	/// the data section the frames travel in (Device::pdoDataCapacity())
	std::size_t dataCapacity = 0;
};

/// The FIFO-command path for @p dev (throws ecmxf::Error).
std::unique_ptr<CyclicPath> makeFifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg);

} // namespace ecmxf::detail

#endif // ECMXF_LIB_PDO_CYCLIC_PATH_HPP
