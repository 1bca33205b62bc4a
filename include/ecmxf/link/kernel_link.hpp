// SPDX-License-Identifier: MIT
/**
 * @file kernel_link.hpp
 * @brief The kernel module's character device /dev/ecmxfN as a Link.
 *
 * The kernel runs the protocol itself (its own copy of the protocol core):
 * each command goes down whole with
 * ECMXF_IOC_CMD and comes back with the answering header, the data and
 * the command's status. The ABI is <linux/ecmxf.h>
 * (include/uapi/linux/ecmxf.h, Documentation/uapi.rst); this header does
 * not include it, it mirrors what a user needs in C++ types.
 */
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <memory>
#include <string>

#include <ecmxf/export.hpp>
#include <ecmxf/link/link.hpp>

namespace ecmxf {

/// The ABI version this library was built against (ECMXF_UAPI_VERSION).
inline constexpr std::uint32_t kKernelUapiVersion = 4;

/// Throws ecmxf::Error (EPROTO) naming @p path and both versions when the
/// running module's ABI version @p running differs from
/// kKernelUapiVersion; returns otherwise. KernelLink calls it at open.
ECMXF_EXPORT void checkKernelUapiVersion(const std::string &path, std::uint32_t running);

/// struct ecmxf_devinfo (ECMXF_IOC_DEVINFO).
struct KernelDevInfo {
	std::uint32_t uapiVersion = 0;
	std::uint32_t flags = 0;          ///< ECMXF_DEVINFO_F_* bits
	std::uint16_t dataSize = 0;       ///< packet data section size
	std::uint8_t checkType = 0;       ///< 0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32
	std::uint8_t fwVersion = 0;       ///< FW_VERSION_GET return value
	std::array<std::uint8_t, 20> fwInfo{}; ///< FW_VERSION_GET data
	std::uint32_t slaveCount = 0;
	std::uint32_t maxOpen = 0;
	std::uint32_t openCount = 0;
	std::uint32_t claimPid = 0;
	std::uint32_t queueDepth = 0;
	std::uint32_t spiSpeedHz = 0;
};

/// Link over /dev/ecmxfN.
class ECMXF_EXPORT KernelLink final : public Link
{
public:
	/// Opens @p path (O_RDWR), asks the ABI version
	/// (ECMXF_IOC_GET_VERSION, checkKernelUapiVersion()) and the device
	/// info. Throws ecmxf::Error with the path and the system's reason.
	explicit KernelLink(const std::string &path);
	~KernelLink() override;

	/// ECMXF_IOC_CMD: the one system call of a command.
	void run(const RawRequest &req, RawResult &res) noexcept override;
	/// The requests one by one with run(), but an async command and its
	/// result fetch (RawRequest::fetchesPrevious) in one ECMXF_IOC_CMD
	/// (ECMXF_CMD_F_FETCH): the kernel sends the fetch as the poll of the
	/// running command. Every result is in on return (@p leaveLast has
	/// nothing to leave).
	void runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res,
		      bool leaveLast = false) noexcept override;
	/// The driver's data section size. Kept without a system call: read
	/// at open and read again (ECMXF_IOC_DEVINFO) on the first call after
	/// a command through this link that can change the format
	/// (SPI_RECONFIG_OP, CRC_TYPE_SET), after reset(), and after any
	/// command that failed (the chip may have reset). A change made
	/// through another open file of the device is seen after such an
	/// event or devInfo(). If the ioctl fails, the last value known.
	[[nodiscard]] std::uint16_t dataSize() const noexcept override;
	/// The driver's check word type, kept as dataSize(); when it had to be
	/// read again and ECMXF_IOC_DEVINFO failed, the ECM status bits of the
	/// last answer (which lag one command behind CRC_TYPE_SET).
	[[nodiscard]] CheckType checkType() const noexcept override;
	[[nodiscard]] std::optional<ResponseHeader> lastHeader() const noexcept override;
	/// The driver's finding: /sys/class/ecmxf/ecmxfN/crc_coverage
	/// (Documentation/driver.rst); Unknown when it cannot be read.
	[[nodiscard]] CrcCoverage crcCoverage() const noexcept override;
	/// The path it opened.
	[[nodiscard]] std::string name() const override;
	/// One absolute clock_nanosleep() on the steady clock (CLOCK_MONOTONIC).
	void sleepUntil(std::chrono::nanoseconds deadline) override;
	/// ECMXF_IOC_RESET (the kernel sends ASYNCCMD_RESET and WARM_RESET only
	/// this way); @p param only for LinkReset::AsyncCmd; @p timeoutUs 0:
	/// the default.
	void reset(LinkReset kind, std::uint32_t param = 0, std::uint32_t timeoutUs = 0) override;
	/// EOPNOTSUPP: the kernel tracks the chip's format itself.
	void assumeFormat(std::uint16_t dataSize, CheckType check) override;
	/// ECMXF_IOC_COUNTERS.
	[[nodiscard]] LinkCounters counters() const override;
	/// The minor of the character device at @p path, without opening it
	/// (a netlink listener needs no access to the device itself); nullopt
	/// when @p path is not a character device. The minor of an open
	/// KernelLink is minorOf(link.name()).
	[[nodiscard]] static std::optional<std::uint32_t> minorOf(const std::string &path);
	/// ECMXF_IOC_CLAIM; the rings made by its setup (ECMXF_IOC_RING_SETUP,
	/// mmap) live as long as the returned object, which releases the claim.
	[[nodiscard]] std::unique_ptr<detail::PdoRings> openPdoRings() override;
	/// ECMXF_IOC_CLAIM_BREAK (EPERM without CAP_SYS_ADMIN or a writable
	/// file, named in the error).
	std::optional<std::uint32_t> breakClaim() override;
	void attachTrace(detail::TraceWriter *trace) noexcept override;

	/// ECMXF_IOC_DEVINFO now (the value read at open: openInfo()); also
	/// refreshes the packet format dataSize() and checkType() keep.
	[[nodiscard]] KernelDevInfo devInfo() const;
	[[nodiscard]] const KernelDevInfo &openInfo() const noexcept;

	/// The open file descriptor (for poll()).
	[[nodiscard]] int fd() const noexcept;

private:
	/// One ECMXF_IOC_CMD: @p req, with @p fetch (its result fetch) when
	/// not null, whose outcome goes to @p fetchRes.
	void command(const RawRequest &req, const RawRequest *fetch, RawResult &res, RawResult *fetchRes) noexcept;

	class State;
	std::unique_ptr<State> s_;
};

} // namespace ecmxf
