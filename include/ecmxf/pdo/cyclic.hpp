// SPDX-License-Identifier: MIT
/**
 * @file cyclic.hpp
 * @brief The cyclic process-data exchange: once per application cycle,
 *        outputs out and inputs in, allocation-free and exception-free.
 *
 * A Cyclic runs over a Device (bus in OP) and a ProcessImage. Each call
 * of cycle() pushes the image's output frame into the chip's RxFIFO
 * (ECAT_PDO_DATA_FIFO_OP), pops every TxPDO frame the chip has queued (the
 * newest becomes the image's inputs), keeps the RxFIFO filled to its
 * target level, and reports what happened in a CycleResult. cycle() and
 * waitNextCycle() allocate nothing and throw nothing; their errors are
 * errno values with a static description.
 *
 * @code
 *   ecmxf::ProcessImage image(master.pdos());
 *   auto cw = image.output<std::uint16_t>(0, 0x6040, 0);
 *   ecmxf::Cyclic cyc(dev, image, ecmxf::CyclicConfig::motion(1ms));
 *   cyc.start();
 *   for (;;) {
 *       cw.set(...);
 *       const ecmxf::CycleResult &r = cyc.cycle();
 *       if (r.error) ... r.message ...
 *       cyc.waitNextCycle();
 *   }
 * @endcode
 *
 * Over the simulator or spidev, the chip's FIFO commands go over the
 * Device's raw command path (Device::transact()); over /dev/ecmxfN (a
 * KernelLink) the frames go through the kernel's mmap()ed PDO rings
 * and cycle() makes no system call. The API and its semantics are the
 * same; Documentation/process-data.rst describes both paths.
 *
 * Thread safety: none; the thread that calls cycle() owns the Device and
 * the image while the Cyclic exists.
 */
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include <ecmxf/export.hpp>
#include <ecmxf/pdo/realtime.hpp>
#include <ecmxf/model/types_pdo.hpp>

namespace ecmxf {

class Device;
class ProcessImage;

/// CyclicConfig::rxFill for closed-loop motion (CSP/CSV, a position or
/// velocity loop closed over the bus): two frames in the RxFIFO cover one
/// late application cycle, and the outputs of a cycle() reach the bus two
/// bus cycles later (a CSP target shows in the position actual ~7 cycles
/// later on the simulator, Documentation/motion.rst "Latency").
inline constexpr unsigned kRxFillMotion = 2;
/// CyclicConfig::rxFill that fills the RxFIFO to its depth minus 2 (~62
/// frames): rides out a late or jittery host, for I/O and logging, but the
/// outputs lag ~62 bus cycles behind: never for motion.
inline constexpr unsigned kRxFillDeep = 0;

/// How a Cyclic runs. For motion start from CyclicConfig::motion(); the
/// default rxFill (kRxFillDeep) buffers ~62 bus cycles of outputs.
struct CyclicConfig {
	/// The preset for closed-loop motion: @p period, rxFill kRxFillMotion.
	[[nodiscard]] static CyclicConfig motion(std::chrono::nanoseconds period = std::chrono::milliseconds(1))
	{
		CyclicConfig c;
		c.period = period;
		c.rxFill = kRxFillMotion;
		return c;
	}
	/// The preset for buffered I/O: @p period, rxFill kRxFillDeep (the
	/// default).
	[[nodiscard]] static CyclicConfig buffered(std::chrono::nanoseconds period = std::chrono::milliseconds(1))
	{
		CyclicConfig c;
		c.period = period;
		c.rxFill = kRxFillDeep;
		return c;
	}

	/// The application cycle; waitNextCycle() waits for its next boundary
	/// on the transport's clock (virtual time in the simulator).
	std::chrono::nanoseconds period{ std::chrono::milliseconds(1) };
	/// RxFIFO level (frames) that cycle() tops up to; 0 (kRxFillDeep): the
	/// FIFO depth minus the margin of two. At most depth - 2. The outputs
	/// of a cycle reach the bus after about this many bus cycles: for
	/// motion use kRxFillMotion (CyclicConfig::motion()).
	unsigned rxFill = kRxFillDeep;
	/// Read the working counter (ECAT_PDO_WC_GET 3) every this many
	/// cycles (one more command each time); 0: never.
	unsigned wkcEvery = 1;
	/// The working counter read rides in the exchange that fetches the
	/// cycle's FIFO command answer (pipelining), and its own answer is
	/// fetched within the cycle: 3 SPI exchanges per cycle with a read, 2
	/// without. true: its answer is left to the next cycle's first
	/// exchange, so a cycle with a read costs 2 exchanges, and
	/// CycleResult::wkc / wkcOk report the read of the cycle before (the
	/// first cycle reports none). Over the kernel module's PDO rings it
	/// sets ECMXF_RING_F_WKC_NEXT: the pump's read is answered by the
	/// pump's next FIFO command (2 exchanges per pump cycle with a read,
	/// not 3), and the read shows in the status block about one period
	/// later. With fifoAnswerNextCycle the read is answered within the
	/// cycle anyway (this then changes nothing).
	bool wkcAnswerNextCycle = false;
	/// The cycle's ECAT_PDO_DATA_FIFO_OP goes out in the cycle's first
	/// exchange and its answer is left in flight: the next exchange on the
	/// link (the next cycle's first, which sends the next FIFO command)
	/// fetches it, and the next cycle() takes it. One SPI exchange per
	/// cycle instead of two (for spidev under PREEMPT_RT: one round trip
	/// less per cycle). A cycle with a working counter read sends the read
	/// first, in the exchange that fetches the previous answer, then the
	/// FIFO command in the exchange that fetches the read's answer: 2
	/// exchanges, the read's answer within the cycle (wkcAnswerNextCycle
	/// then changes nothing). The price, in the CycleResult of cycle N:
	/// error / message (of the FIFO command), framesPushed, framesPopped,
	/// inputsUpdated (the image's inputs), rxRefused, txOverflow,
	/// txDroppedEstimate and the response header fields are those of the
	/// FIFO command of cycle N - 1 (cycle N's outputs went out, their
	/// fate is told by cycle N + 1); commands and the working counter
	/// fields are cycle N's. The first cycle after start() reports no
	/// frames (its header fields: the latest header the chip sent). Only
	/// one FIFO command goes out per cycle (the extra writes and reads of
	/// the synchronous cycle need its answer): a TxFIFO backlog, or an
	/// RxFIFO below its fill level, is worked off by the next cycles at up
	/// to framesPerRead() / framesPerWrite() frames each. stop() and the
	/// destructor fetch the last answer and drop it (its input frames
	/// reach neither the image nor onInputFrame). Over a link that does not
	/// pipeline (it runs a command to its end) the answer is taken within
	/// the cycle. Over the kernel module's link (its PDO rings) cycle()
	/// sends no command: this sets ECMXF_RING_F_FIFO_NEXT, and the pump's
	/// FIFO command is answered by its next one (one exchange per pump
	/// cycle, not two). The input frames then reach the input ring, and
	/// the image, one pump period later, and output frames the chip
	/// refuses with a command error are dropped (counted in the ring's
	/// dropped count), not sent again.
	bool fifoAnswerNextCycle = false;
	/// The bus cycle (ECAT_INIT_OP's SYNC0 cycle, or 1 ms free run): with
	/// it, TxPDO frames lost to a TxFIFO overflow are estimated; zero: not
	/// estimated (overflows are still detected and counted).
	std::chrono::nanoseconds busCycle{ 0 };
	/// Called for every TxPDO frame popped, oldest first, inside cycle()
	/// (e.g. to log inputs at bus rate when the application cycle is
	/// slower); the span is valid during the call only.
	void (*onInputFrame)(void *context, std::span<const std::uint8_t> frame) noexcept = nullptr;
	void *context = nullptr;
	/// Time allowed for each command of cycle() (ECAT_PDO_DATA_FIFO_OP,
	/// ECAT_PDO_WC_GET) until its answer; zero: the command table's 100 ms.
	/// Raise it where the host can stall that long (e.g. under emulation).
	/// Over the kernel's PDO rings cycle() sends no command (the kernel's
	/// pump allows each of its commands 500 ms) and this is not used.
	std::chrono::microseconds commandTimeout{ 0 };
	/// The real-time setup of the cyclic thread (memory lock, SCHED_FIFO
	/// priority, CPU, pre-faulted stack): checked when the Cyclic is made
	/// (ecmxf::Error EINVAL naming the field), applied by start() to the
	/// thread that calls it (ecmxf::Error with the errno, e.g. EPERM).
	/// The default changes nothing. realtime.hpp, Documentation/
	/// process-data.rst "Real time".
	RealtimeConfig realtime{};
};

/// What one cycle() did.
struct CycleResult {
	/// 0, or a positive errno value (ETIMEDOUT, EIO, EREMOTEIO...).
	int error = 0;
	/// A static description of the failure ("" when error is 0); never
	/// freed, safe to keep.
	const char *message = "";

	/// Commands sent (ECAT_PDO_DATA_FIFO_OP, ECAT_PDO_WC_GET); over the
	/// kernel's PDO rings, those of the kernel's pump answered since the
	/// previous cycle (the status block's pump_ops and wkc_reads).
	unsigned commands = 0;
	/// RxPDO frames sent to the RxFIFO (copies of the output frame).
	unsigned framesPushed = 0;
	/// TxPDO frames received.
	unsigned framesPopped = 0;
	/// A new input frame went into the image.
	bool inputsUpdated = false;

	/// The chip refused RxPDO frames: the RxFIFO was full (return value
	/// bit 0 clear).
	bool rxRefused = false;
	/// The TxFIFO was found full: the chip has dropped its oldest frames
	/// since the last cycle.
	bool txOverflow = false;
	/// Estimated TxPDO frames lost to that overflow (needs
	/// CyclicConfig::busCycle; 0 otherwise).
	std::uint32_t txDroppedEstimate = 0;
	/// Over the kernel's PDO rings: output frames of earlier cycles that
	/// the kernel's pump dropped since the last cycle, the oldest of a
	/// backlog it could not send in time (the status block's out_skipped;
	/// the same count as /sys/class/ecmxf/ecmxfN/ring_skipped). Always 0
	/// over the FIFO commands (the image is the only output frame there).
	std::uint32_t outputsSkipped = 0;

	/// The working counter was read this cycle (CyclicConfig::wkcEvery).
	bool wkcRead = false;
	/// The working counter as last read (ECAT_PDO_WC_GET 3).
	std::uint32_t wkc = 0;
	/// inputs x 1 + outputs x 2 slaves (ECAT_PDO_WC_GET 1 and 2).
	std::uint32_t expectedWkc = 0;
	/// wkc == expectedWkc (as last read).
	bool wkcOk = false;

	/// Response header fields of the cycle's last answer:
	std::uint8_t rxFifoCount = 0;   ///< 0x07 RxPDO frames waiting to go out
	std::uint8_t txFifoCount = 0;   ///< 0x06 TxPDO frames not yet read
	std::uint8_t wkcErrorCount = 0; ///< 0x05 bus cycles with a wrong WKC (saturating)
	std::uint8_t ecatState = 0;     ///< 0x08 1 INIT, 2 PRE-OP, 4 SAFE-OP, 8 OP, 0x10 ERROR
	std::uint8_t errStatus = 0;     ///< 0x09 error status
	std::uint8_t ecmStatus = 0;     ///< 0x0A ECM status (bit 4 PDO configured, bit 6 FIFO on)
	std::uint32_t intFlags = 0;     ///< 0x10 interrupt flags
};

/// Totals since start().
struct CyclicStats {
	std::uint64_t cycles = 0;        ///< cycle() calls
	std::uint64_t failedCycles = 0;  ///< ... with an error
	std::uint64_t commands = 0;
	std::uint64_t framesPushed = 0;
	std::uint64_t framesPopped = 0;
	std::uint64_t rxRefusals = 0;    ///< cycles with refused RxPDO frames
	std::uint64_t txOverflows = 0;   ///< cycles that found the TxFIFO full
	std::uint64_t txDroppedEstimate = 0;
	std::uint64_t outputsSkipped = 0; ///< CycleResult::outputsSkipped summed
	std::uint64_t wkcReads = 0;
	std::uint64_t wkcMismatches = 0; ///< reads with wkc != expected
	std::uint64_t lateCycles = 0;    ///< waitNextCycle() found a boundary already past
};

/// The cyclic exchange over one Device and one ProcessImage.
class ECMXF_EXPORT Cyclic
{
public:
	/// Checks that the bus is in SAFE-OP or OP (ENETDOWN naming the state
	/// otherwise) and that @p device has no other Cyclic (EBUSY: one per
	/// Device); reads the frame sizes (FIFO_PACK_SIZE_GET), the FIFO depths
	/// (FIFO_GET_RX/TX_CNT) and the slave counts (ECAT_PDO_WC_GET); checks
	/// that the image's frames have the chip's sizes (EINVAL) and that one
	/// frame each way fits the data section (EMSGSIZE: raise it with
	/// SPI_RECONFIG_OP). Both objects must outlive the Cyclic. Throws
	/// ecmxf::Error.
	Cyclic(Device &device, ProcessImage &image, CyclicConfig config = {});
	~Cyclic();
	Cyclic(const Cyclic &) = delete;
	Cyclic &operator=(const Cyclic &) = delete;

	/// Pre-loads the image's outputs (ECAT_PDO_DATA_OP), empties both
	/// FIFOs (FIFO_CLR_OP), enables the FIFO (FIFO_ENABLE 1), zeroes the
	/// statistics and starts the cycle clock. Throws ecmxf::Error.
	void start();
	/// FIFO_ENABLE 0: the chip keeps sending the last outputs. Throws.
	void stop();
	/// Between start() and stop().
	[[nodiscard]] bool running() const noexcept;

	/// Something to do with this Cyclic before it goes away (what
	/// Cia402Axis::stopOnExit() registers: the drive brought to a halt
	/// while the exchange still runs). The destructor calls each hook still
	/// registered, newest first, then forgets it; @p owner removes its own
	/// with removeExitHook() (in its destructor, if it goes first).
	using ExitHook = void (*)(void *owner, Cyclic &cyclic) noexcept;
	void addExitHook(void *owner, ExitHook hook);
	void removeExitHook(void *owner) noexcept;

	/// One exchange: see the file comment and process-data.rst.
	/// Allocates nothing, throws nothing.
	const CycleResult &cycle() noexcept;

	/// Waits on the transport's clock until the next cycle boundary
	/// (start() + n x period). When that is already past, it skips to
	/// the next one still ahead and counts a late cycle. Returns 0, or EIO
	/// when the transport failed. Allocates nothing, throws nothing.
	int waitNextCycle() noexcept;

	/// The cycle boundary the last waitNextCycle() waited for (after
	/// start(): the start, the first cycle's boundary), on the transport's
	/// clock (Link::now()): how late this cycle began is now() minus it. 0
	/// before the first start().
	[[nodiscard]] std::chrono::nanoseconds boundary() const noexcept;

	/// Waits until at least one TxPDO frame that cycle() has not taken yet
	/// is there (then cycle() returns it), at most @p timeout on the
	/// transport's clock: for an application clocked by its inputs (one
	/// cycle() per bus cycle, woken when the bus cycle's inputs arrive).
	/// Over the kernel's PDO rings it poll()s the device for POLLIN (no
	/// system call when frames are already there); over the FIFO commands
	/// it asks the chip for its TxFIFO count (an ECAT_PDO_DATA_FIFO_OP
	/// that moves no frame) once per bus cycle (CyclicConfig::busCycle, or
	/// the period when that is zero) until one is queued. With
	/// CyclicConfig::fifoAnswerNextCycle it fetches the answer in flight
	/// first and returns 0 at once when that holds frames (the next
	/// cycle() reports them); frames it finds queued are popped by the
	/// next cycle() and reported by the one after: an application clocked
	/// by its inputs should not use that option.
	/// Returns 0 (inputs there), ETIMEDOUT (none within @p timeout), EINVAL
	/// (before start()), or the transport's or the pump's error (EIO...).
	/// Allocates nothing, throws nothing.
	int waitInputs(std::chrono::nanoseconds timeout) noexcept;

	[[nodiscard]] const CycleResult &lastResult() const noexcept;
	[[nodiscard]] const CyclicStats &stats() const noexcept;
	[[nodiscard]] const CyclicConfig &config() const noexcept;

	/// What the constructor read from the chip, and derived from it:
	[[nodiscard]] FifoPackSizes packSizes() const noexcept;
	[[nodiscard]] PdoSlaveCounts slaveCounts() const noexcept;
	[[nodiscard]] std::uint32_t expectedWkc() const noexcept;
	[[nodiscard]] unsigned rxDepth() const noexcept;
	[[nodiscard]] unsigned txDepth() const noexcept;
	/// The RxFIFO target level in use (CyclicConfig::rxFill resolved).
	[[nodiscard]] unsigned rxFill() const noexcept;
	/// RxPDO frames one command carries, TxPDO frames one answer carries.
	[[nodiscard]] unsigned framesPerWrite() const noexcept;
	[[nodiscard]] unsigned framesPerRead() const noexcept;
	/// The frames go through the kernel's mmap()ed PDO rings (the Device's
	/// transport is a KernelLink); false: FIFO commands.
	[[nodiscard]] bool usesKernelRings() const noexcept;

	class Impl;

private:
	std::unique_ptr<Impl> impl_;
};

} // namespace ecmxf
