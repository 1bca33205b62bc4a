// SPDX-License-Identifier: MIT
/**
 * @file link.hpp
 * @brief The Link: the one command-level interface between the library and
 *        one ECM-XF chip.
 *
 * Everything above the link (Device and the typed calls, Master, SDO, PDO,
 * CiA-402) hands whole commands to Link::run() and reads their outcome;
 * nothing above it knows how the command travels. Two implementations:
 *  - EngineLink (engine_link.hpp): the shared protocol core's loop
 *    (lib/core) over a ByteChannel (byte_channel.hpp): the in-process
 *    simulator, an ecmxf-sim server's Unix socket, or spidev + libgpiod;
 *  - KernelLink (kernel_link.hpp): /dev/ecmxfN, whose kernel module runs
 *    its own copy of the protocol core.
 * What only some links have is a capability with a default here: resets
 * the kernel reserves for itself (reset()), the cyclic PDO path through
 * the kernel's rings (openPdoRings()), counters, the simulator behind the
 * link (simulator()). Where events come from follows from the device URI:
 * /dev/ecmxfN has the kernel's over generic netlink (EventSubscriber,
 * KernelLink::minorOf()), every other link's are found by polling response
 * headers (EventDetector).
 * Documentation/architecture.rst draws the layers.
 *
 * Thread safety: a Link is not thread-safe; its one owner (a Device) calls
 * it from one thread at a time.
 */
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>

#include <ecmxf/export.hpp>
#include <ecmxf/protocol.hpp>

namespace ecmxf {

namespace sim {
class Chip;
}
namespace detail {
class TraceWriter;
class PdoRings;
} // namespace detail

/// The fields of a response header (chip to host).
struct ResponseHeader {
	std::uint8_t crcErrCnt = 0;   ///< SPI CRC error count (0x04)
	std::uint8_t wkcErrCnt = 0;   ///< WKC error count (0x05)
	std::uint8_t txFifoCnt = 0;   ///< TxPDOs in the chip's TxFIFO not yet read (0x06)
	std::uint8_t rxFifoCnt = 0;   ///< RxPDOs in the chip's RxFIFO not yet sent (0x07)
	std::uint8_t ecatState = 0;   ///< EtherCAT state (0x08): 1 INIT, 2 PRE-OP, 4 SAFE-OP, 8 OP, 0x10 ERROR
	std::uint8_t errStatus = 0;   ///< error status (0x09): bit 3 async error, bit 7 command error...
	std::uint8_t ecmStatus = 0;   ///< ECM status (0x0A): bits 1-0 check type, bit 7 busy...
	std::uint8_t index = 0;       ///< index of the command answered (0x0B)
	std::uint8_t code = 0;        ///< command code answered (0x0C)
	std::uint8_t ret = 0;         ///< return value (0x0D)
	std::uint16_t len = 0;        ///< valid data length (0x0E)
	std::uint32_t intFlags = 0;   ///< interrupt flags (0x10)
	std::array<std::uint8_t, 2> gpioIntFlag{}; ///< GPIO interrupt flags low/high (0x14, 0x15)
	std::array<std::uint8_t, 2> gpioIn{};      ///< GPIO inputs low/high (0x16, 0x17)
};

/// One whole command for Link::run(): the command header fields the host
/// chooses (packet bytes 0x04..0x17 except the index, which the protocol
/// core allocates) and the data. Plain data: building one allocates
/// nothing.
struct RawRequest {
	std::array<std::uint8_t, 4> data{};      ///< parametric data 0..3 (0x04..0x07)
	std::uint16_t reserved = 0;              ///< the word at 0x08 (LRW, bus shift, GPIO out valid)
	std::uint8_t control = 0;                ///< control byte (0x0A)
	std::uint8_t code = 0;                   ///< command code (0x0C)
	std::uint8_t param = 0;                  ///< command parameter (0x0D)
	std::uint16_t len = 0;                   ///< data length field (0x0E), sent as given
	std::uint32_t intClear = 0;              ///< interrupt clear (0x10)
	std::array<std::uint8_t, 2> gpioIntClear{}; ///< GPIO interrupt clear low/high (0x14, 0x15)
	std::array<std::uint8_t, 2> gpioOut{};   ///< GPIO outputs low/high (0x16, 0x17)
	std::span<const std::uint8_t> tx;        ///< data section bytes to send (rest zero)
	std::span<std::uint8_t> rx;              ///< where the answer's data goes
	/// Time allowed until the answer (async: until completion), in
	/// microseconds; 0 selects the command table's default.
	std::uint32_t timeoutUs = 0;
	/// Leave the chip's async / command error bits set after a failure
	/// (ECMXF_CMD_F_NO_AUTO_CLEAR).
	bool noAutoClear = false;
	/// In a batch (Link::runBatch()): this request is the result fetch
	/// (the *_GET partner) of the async request before it. A link that
	/// pipelines sends it as the poll of the running command, so the
	/// exchange that detects the completion also brings the result; it
	/// is not sent (status -ECANCELED) when the async command fails.
	bool fetchesPrevious = false;
};

/// The outcome of a RawRequest.
struct RawResult {
	/// 0, or the command's negative errno as the protocol core reports it
	/// (-ETIMEDOUT, -EBUSY, -EREMOTEIO, -EBADMSG / -EPROTO / -EIO,
	/// -ECONNRESET, -EMSGSIZE, -ECANCELED), or the negative errno of a
	/// failure of the link itself (then linkFailure says what failed).
	int status = 0;
	/// The header that answered (for an async command: the one that
	/// ended the busy phase); meaningful when the chip answered.
	ResponseHeader header;
	/// Bytes of answer data written to RawRequest::rx.
	std::size_t rxLen = 0;

	// ---- what the link can tell about a failure (for the error's text)
	/// Not null: the link itself failed (a system call, the channel) or
	/// refused the command before sending it; a text that lives as long as
	/// the link, naming the device where a system call failed, e.g.
	/// "/dev/ecmxf0: ECMXF_IOC_CMD failed: Bad address".
	const char *linkFailure = nullptr;
	/// The chip answered and ran the command as an async one (the busy
	/// phase was seen); unknown (false) over links that do not tell.
	bool ranAsync = false;
	/// The time the link waited before -ETIMEDOUT, in microseconds (0:
	/// the link does not tell; the request's or the table's limit).
	std::uint32_t waitedUs = 0;
	/// -EBADMSG/-EPROTO/-EIO: the number of bad packets in a row that made
	/// the link give up (0: the link does not tell, or the answer was lost
	/// and the command is not safe to repeat, see answerLost).
	unsigned badPackets = 0;
	/// The kind of the last bad packet (the protocol core's fault name),
	/// or null.
	const char *fault = nullptr;
	/// -EPROTO: the answer was lost on the wire and the command, which may
	/// have run, is not safe to send again.
	bool answerLost = false;
};

/// What Link::reset() does.
enum class LinkReset : std::uint8_t {
	AsyncCmd, ///< ASYNCCMD_RESET with a parameter (bits 0..2)
	Warm,     ///< WARM_RESET: the chip restarts with its power-on format
	Link,     ///< forget the link state and resynchronise (kernel link only)
};

/// Counts a link keeps since it was made (the kernel link: since probe,
/// the fields of struct ecmxf_counters; the engine link: its protocol
/// core's counts, the kernel-only fields zero).
struct LinkCounters {
	std::uint64_t exchanges = 0, badNotReady = 0, badStart = 0, badEnd = 0, badCheck = 0,
		      badLength = 0, retries = 0, polls = 0, exhausted = 0, timeouts = 0,
		      asyncErrors = 0, busyRejects = 0, lostAnswers = 0, chipResets = 0,
		      wkcErrors = 0, outRingUnderruns = 0, inRingOverruns = 0, rxFifoUnderruns = 0,
		      rxFifoOverruns = 0, txFifoOverruns = 0, int0Irqs = 0, int1Irqs = 0;
};

/// The fields of @p k with their names in struct ecmxf_counters, in its
/// order (for printing them).
inline std::array<std::pair<const char *, std::uint64_t>, 22> counterFields(const LinkCounters &k)
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

/// The one command-level interface to a chip.
class ECMXF_EXPORT Link
{
public:
	Link() = default;
	Link(const Link &) = delete;
	Link &operator=(const Link &) = delete;
	virtual ~Link();

	/// Runs @p req to its end (for an async command: to its completion)
	/// and puts the outcome in @p res (reset first). Never throws; on the
	/// cyclic path (no trace, no failure) allocates nothing.
	virtual void run(const RawRequest &req, RawResult &res) noexcept = 0;

	/// Runs @p reqs in order, results in @p res (the same length; reset
	/// first): a link that pipelines (an engine link) sends each command in
	/// the exchange that fetches the previous one's answer, and an async
	/// command's fetch (RawRequest::fetchesPrevious) as its poll. With
	/// @p leaveLast the last command's answer may stay in flight: it is
	/// fetched by the next exchange on this link (the next run(),
	/// runBatch() or settle()), which fills its RawResult (status
	/// -EINPROGRESS until then); that result and the request's rx buffer
	/// must live until then. The default runs the
	/// requests one by one with run(). Never throws.
	virtual void runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res,
			      bool leaveLast = false) noexcept;
	/// Fetches every answer runBatch() left in flight. Never throws.
	virtual void settle() noexcept {}

	/// The data section size in force now (no exchange).
	[[nodiscard]] virtual std::uint16_t dataSize() const noexcept = 0;
	/// The check word type in force now (no exchange).
	[[nodiscard]] virtual CheckType checkType() const noexcept = 0;
	/// The latest header the chip sent, if any.
	[[nodiscard]] virtual std::optional<ResponseHeader> lastHeader() const noexcept = 0;
	/// Which bytes the chip's CRC covers, as the link found it from the
	/// chip's answers (Unknown by default, and until a CRC was in force).
	[[nodiscard]] virtual CrcCoverage crcCoverage() const noexcept { return CrcCoverage::Unknown; }
	/// How messages name the link: its device URI ("sim:", "/dev/ecmxf0",
	/// "unix:/tmp/s", "spidev:/dev/spidev0.0").
	[[nodiscard]] virtual std::string name() const = 0;

	/// The link's clock, monotonic, any origin: virtual time over the
	/// simulator, the steady clock otherwise. Timeouts above the link (the
	/// 402 helpers, the cyclic loop) are measured on it.
	[[nodiscard]] virtual std::chrono::nanoseconds now() const;
	/// Lets @p duration pass on the link's clock (sleeps, or advances the
	/// simulator's virtual time).
	virtual void sleepFor(std::chrono::nanoseconds duration);
	/// Sleeps until now() reads @p deadline (absolute, on the link's
	/// clock); returns at once when it has passed. The default sleeps for
	/// deadline - now(); the kernel link and the spidev channel sleep
	/// with one absolute clock_nanosleep() (Cyclic::waitNextCycle()).
	virtual void sleepUntil(std::chrono::nanoseconds deadline);
	/// A time not later than now() that the link knows without reading
	/// the clock (spidev: the time of INT0's last ready edge or of the
	/// end of the last sleep); for estimates between exchanges, never to
	/// start a timeout. The default is now().
	[[nodiscard]] virtual std::chrono::nanoseconds coarseNow() const { return now(); }

	// ---- capabilities: what only some links have

	/// ASYNCCMD_RESET (param: its bits 0..2) or WARM_RESET, and the link
	/// follows (after WARM_RESET: the power-on format); LinkReset::Link
	/// resynchronises the kernel's link. The default runs the reset as a
	/// command through run(); the kernel link uses ECMXF_IOC_RESET (its
	/// ECMXF_IOC_CMD refuses both commands). Throws ecmxf::Error.
	virtual void reset(LinkReset kind, std::uint32_t param = 0, std::uint32_t timeoutUs = 0);

	/// Tells the link the packet format the chip speaks now, without an
	/// exchange (a chip another driver reconfigured). Links whose far side
	/// tracks the format itself (the kernel) refuse with EOPNOTSUPP; a size
	/// outside 32..1408 or a check type outside 0..3: EINVAL.
	virtual void assumeFormat(std::uint16_t dataSize, CheckType check);

	/// The pause between the polls of a running async command (links that
	/// poll themselves, the kernel, ignore it). Zero: back to back.
	virtual void setAsyncPollInterval(std::chrono::nanoseconds interval) noexcept;
	[[nodiscard]] virtual std::chrono::nanoseconds asyncPollInterval() const noexcept;

	/// Whether a second command may ride in the exchange that fetches the
	/// first one's answer (engine links; on by default). Off: one command
	/// per two exchanges and INFO_UPDATE polls, as before pipelining (for
	/// comparison). Links that cannot pipeline ignore it.
	virtual void setPipelining(bool on) noexcept { (void)on; }
	[[nodiscard]] virtual bool pipelining() const noexcept { return false; }

	/// What the link counted. Throws ecmxf::Error when it cannot be read.
	[[nodiscard]] virtual LinkCounters counters() const = 0;

	/// The simulated chip behind the link when it is the in-process
	/// simulator, else null.
	[[nodiscard]] virtual sim::Chip *simulator() noexcept { return nullptr; }

	/// The cyclic path's PDO rings of the kernel module (claim, ring
	/// memory, wait for inputs), or null when the link has none (the
	/// cyclic path then runs the FIFO commands through run()). Throws
	/// ecmxf::Error when the rings exist but cannot be had (EBUSY: claimed
	/// by another process). Internal type: lib/link/pdo_rings.hpp.
	[[nodiscard]] virtual std::unique_ptr<detail::PdoRings> openPdoRings();

	/// An operator's way out when the process that holds the kernel
	/// module's claim hangs (ECMXF_IOC_CLAIM_BREAK, needs CAP_SYS_ADMIN):
	/// its rings stop and this link's file holds the claim until it is
	/// closed, so that it can bring the bus to a safe state. Returns the
	/// pid of the process whose claim was broken (0 when it is not visible
	/// in the caller's pid namespace), or nullopt when no claim was held. Links without a claim (everything but the kernel module)
	/// throw ecmxf::Error with EOPNOTSUPP.
	virtual std::optional<std::uint32_t> breakClaim();

	/// Records every exchange to @p trace (null: stop), in the records of
	/// the link's kind: SPI packets (engine link) or request/response
	/// (kernel link); writes the link's first record (its format) at once.
	/// The writer outlives the link's use of it. Internal type:
	/// lib/link/trace_writer.hpp.
	virtual void attachTrace(detail::TraceWriter *trace) noexcept = 0;
};

} // namespace ecmxf
