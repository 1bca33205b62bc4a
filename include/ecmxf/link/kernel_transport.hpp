// SPDX-License-Identifier: MIT
/**
 * @file kernel_transport.hpp
 * @brief The kernel module's character device /dev/ecmxfN as a Transport.
 *
 * The kernel runs the protocol itself (its own copy of the protocol core),
 * so this is a CommandTransport: each command goes down whole with
 * ECMXF_IOC_CMD and comes back with the answering header, the data and
 * the command's status. The ABI is <linux/ecmxf.h>
 * (include/uapi/linux/ecmxf.h, Documentation/uapi.rst); this header does
 * not include it, it mirrors what a user needs in C++ types.
 */
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include <ecmxf/export.hpp>
#include <ecmxf/link/transport.hpp>

namespace ecmxf {

/// The ABI version this library was built against (ECMXF_UAPI_VERSION).
inline constexpr std::uint32_t kKernelUapiVersion = 2;

/// Throws ecmxf::Error (EPROTO) naming @p path and both versions when the
/// running module's ABI version @p running differs from
/// kKernelUapiVersion; returns otherwise. KernelTransport calls it at open.
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

/// struct ecmxf_counters (ECMXF_IOC_COUNTERS), counts since probe.
struct KernelCounters {
	std::uint64_t exchanges = 0, badNotReady = 0, badStart = 0, badEnd = 0, badCheck = 0,
		      badLength = 0, retries = 0, polls = 0, exhausted = 0, timeouts = 0,
		      asyncErrors = 0, busyRejects = 0, lostAnswers = 0, chipResets = 0,
		      wkcErrors = 0, outRingUnderruns = 0, inRingOverruns = 0, rxFifoUnderruns = 0,
		      rxFifoOverruns = 0, txFifoOverruns = 0, int0Irqs = 0, int1Irqs = 0;
};

/// The fields of @p k with their names in struct ecmxf_counters, in its
/// order (for printing them).
inline std::array<std::pair<const char *, std::uint64_t>, 22> counterFields(const KernelCounters &k)
{
	return { {
		{ "exchanges", k.exchanges },
		{ "bad_not_ready", k.badNotReady },
		{ "bad_start", k.badStart },
		{ "bad_end", k.badEnd },
		{ "bad_check", k.badCheck },
		{ "bad_length", k.badLength },
		{ "retries", k.retries },
		{ "polls", k.polls },
		{ "exhausted", k.exhausted },
		{ "timeouts", k.timeouts },
		{ "async_errors", k.asyncErrors },
		{ "busy_rejects", k.busyRejects },
		{ "lost_answers", k.lostAnswers },
		{ "chip_resets", k.chipResets },
		{ "wkc_errors", k.wkcErrors },
		{ "out_ring_underruns", k.outRingUnderruns },
		{ "in_ring_overruns", k.inRingOverruns },
		{ "rx_fifo_underruns", k.rxFifoUnderruns },
		{ "rx_fifo_overruns", k.rxFifoOverruns },
		{ "tx_fifo_overruns", k.txFifoOverruns },
		{ "int0_irqs", k.int0Irqs },
		{ "int1_irqs", k.int1Irqs },
	} };
}

/// What ECMXF_IOC_RESET does.
enum class KernelReset : std::uint8_t {
	AsyncCmd, ///< ASYNCCMD_RESET with a parameter (bits 0..2)
	Warm,     ///< WARM_RESET: the chip restarts
	Link,     ///< forget the link state and resynchronise
};

/// Transport over /dev/ecmxfN.
class ECMXF_EXPORT KernelTransport : public CommandTransport
{
public:
	/// Opens @p path (O_RDWR), asks the ABI version
	/// (ECMXF_IOC_GET_VERSION, checkKernelUapiVersion()) and the device
	/// info. Throws ecmxf::Error with the path and the system's reason.
	explicit KernelTransport(const std::string &path);
	~KernelTransport() override;

	/// ECMXF_IOC_DEVINFO now (the value read at open: openInfo()); also
	/// refreshes the packet format dataSize() and checkTypeNow() keep.
	[[nodiscard]] KernelDevInfo devInfo() const;
	[[nodiscard]] const KernelDevInfo &openInfo() const noexcept { return info_; }
	/// The driver's data section size. Kept without a system call: read
	/// at open and read again (ECMXF_IOC_DEVINFO) on the first call after
	/// a command through this transport that can change the format
	/// (SPI_RECONFIG_OP, CRC_TYPE_SET), after reset(), and after any
	/// command that failed (the chip may have reset). A change made
	/// through another open file of the device is seen after such an
	/// event or devInfo(). If the ioctl fails, the last value known.
	[[nodiscard]] std::uint16_t dataSize() const noexcept override;
	/// The driver's check word type, kept as dataSize(); nullopt when it
	/// had to be read again and ECMXF_IOC_DEVINFO failed.
	[[nodiscard]] std::optional<std::uint8_t> checkTypeNow() const noexcept override;
	/// ECMXF_IOC_COUNTERS.
	[[nodiscard]] KernelCounters counters() const;
	/// ECMXF_IOC_RESET; @p param only for KernelReset::AsyncCmd;
	/// @p timeoutUs 0: the default.
	void reset(KernelReset kind, std::uint32_t param = 0, std::uint32_t timeoutUs = 0);

	/// The open file descriptor (for poll()).
	[[nodiscard]] int fd() const noexcept { return fd_; }

protected:
	[[nodiscard]] int doCommand(const RawRequest &req, RawResult &res, const char *&failedCall) noexcept override;

private:
	/// Reads ECMXF_IOC_DEVINFO into the kept format if it is stale;
	/// false when that ioctl fails.
	bool refreshFormat() const noexcept;

	int fd_ = -1;
	KernelDevInfo info_;
	// the packet format in force as last read (dataSize(), checkTypeNow())
	mutable std::uint16_t dataSize_ = 0;
	mutable std::uint8_t checkType_ = 0;
	mutable bool formatStale_ = false;
};

} // namespace ecmxf
