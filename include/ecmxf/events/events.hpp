// SPDX-License-Identifier: MIT
/**
 * @file events.hpp
 * @brief Events of a chip: from the kernel module over generic netlink
 *        (EventSubscriber), or detected from polled response headers
 *        (EventDetector), as one typed ecmxf::Event.
 *
 * The kernel module multicasts its events on the group "events" of the
 * generic netlink family "ecmxf" (<linux/ecmxf_netlink.h>,
 * Documentation/driver.rst "Events (generic netlink)"). The module finds
 * them with the protocol core's detector (lib/core/ecmxf-events.c); a
 * host that drives the chip itself (sim:, spidev:) runs the same detector
 * through EventDetector, so both report the same events for the same
 * headers. This header does not include the uAPI header nor libmnl.
 */
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/export.hpp>
#include <ecmxf/link/link.hpp>

namespace ecmxf {

/// Kinds of events (the values of enum ecmxf_nl_event).
enum class EventType : std::uint32_t {
	Device = 1,      ///< a device was probed or is being removed (action)
	Reset = 2,       ///< the chip reset, or the kernel resynchronised the link (resetReason)
	Link = 3,        ///< the EtherCAT link went up or down (linkUp)
	State = 4,       ///< the ECAT state changed (oldValue -> newValue; slaves)
	ErrorStatus = 5, ///< error status bits 1..7 changed (oldValue -> newValue)
	EcmStatus = 6,   ///< ECM status bits 2, 3, 4, 6 changed (oldValue -> newValue)
	CrcErrors = 7,   ///< the SPI CRC error count went up (increase, count)
	WkcBurst = 8,    ///< WKC errors started (increase, count)
	WkcBurstEnd = 9, ///< a WKC burst is over (errors, duration, count)
	Fifo = 10,       ///< a FIFO count crossed its mark (fifo, count, mark, above)
	AsyncError = 11, ///< an async command failed (cmdCode, status, errStatus)
	PdoLoss = 12,    ///< a counter of the cyclic path (PDO rings, pump) went up (loss, increase, total)
};

/// The name of an event type as `ecmxf-util monitor` prints it ("state",
/// "wkc_burst", ...), or "unknown" for a value this library does not know.
[[nodiscard]] ECMXF_EXPORT std::string eventTypeName(EventType t);

/// Event::fifo.
enum class FifoId : std::uint8_t {
	Tx = 0, ///< the chip's TxFIFO (inputs waiting for the host)
	Rx = 1, ///< the chip's RxFIFO (outputs waiting for the bus)
};

/// Event::loss: which counter of the cyclic path went up (enum ecmxf_nl_loss;
/// the LinkCounters field of the same name).
enum class LossKind : std::uint8_t {
	OutRingUnderrun = 0, ///< the output ring was empty when the chip's RxFIFO wanted a frame
	InRingOverrun = 1,   ///< input frames dropped: the input ring was full
	RxFifoUnderrun = 2,  ///< the chip's RxFIFO ran empty (the bus repeats the last outputs)
	RxFifoOverrun = 3,   ///< the chip refused output frames: its RxFIFO was full
	TxFifoOverrun = 4,   ///< the chip's TxFIFO was full: it dropped its oldest input frames
	OutRingSkipped = 5,  ///< output frames the pump skipped when it had fallen behind
	PumpFailure = 6,     ///< pump commands that failed (their frames lost, never sent again)
};

/// The name of a LossKind as `ecmxf-util monitor` prints it
/// ("in_ring_overrun", ...), or "unknown".
[[nodiscard]] ECMXF_EXPORT std::string lossKindName(LossKind k);

/// Event::resetReason.
enum class ResetReason : std::uint32_t {
	Unknown = 0, ///< not said (a polled detector cannot tell)
	Chip = 1,    ///< the chip restarted, seen in a header
	Warm = 2,    ///< the chip restarted after a WARM_RESET the kernel sent
	Link = 3,    ///< the kernel resynchronised the link (ECMXF_RESET_F_LINK)
};

/// Event::action.
enum class DeviceAction : std::uint32_t {
	Unknown = 0,
	Added = 1,   ///< probed, link up
	Removed = 2, ///< going away
};

/// A slave not in OP, with its AL status code, in a State event.
struct SlaveAlStatus {
	std::uint16_t position = 0;
	/// ECAT_STATE_GET of the slave (bit 4: error; 0x10 alone: it does not answer).
	std::uint8_t state = 0;
	/// ECAT_SLV_INFO_GET code 7; empty for a slave that does not answer.
	std::optional<std::uint16_t> alStatus;
};

/// One event. Which members mean something depends on type (see
/// EventType); the others keep their defaults.
struct Event {
	EventType type = EventType::Device;
	std::uint32_t minor = 0; ///< N of /dev/ecmxfN (netlink)
	std::string device;      ///< "ecmxfN" (netlink); empty from an EventDetector
	/// When the event was seen: CLOCK_MONOTONIC from the kernel; from an
	/// EventDetector, the time passed to it.
	std::chrono::nanoseconds time{ 0 };
	std::uint32_t seq = 0;        ///< kernel's per-device event number
	std::uint32_t suppressed = 0; ///< events of this type the kernel's rate limit held back before this one

	std::uint32_t oldValue = 0; ///< State, ErrorStatus, EcmStatus
	std::uint32_t newValue = 0; ///< State, ErrorStatus, EcmStatus; Reset, Device: the ECAT state
	bool linkUp = false;        ///< Link (and Device added)
	std::uint8_t errStatus = 0; ///< error status byte of the header (Link, AsyncError, Device)
	std::uint8_t ecmStatus = 0; ///< ECM status byte of the header (Reset, Device)
	std::uint32_t count = 0;    ///< CrcErrors, WkcBurst, WkcBurstEnd: the counter; Fifo: the FIFO count
	std::uint32_t increase = 0; ///< CrcErrors, WkcBurst, PdoLoss
	std::uint32_t errors = 0;   ///< WkcBurstEnd: errors of the whole burst
	std::chrono::nanoseconds duration{ 0 }; ///< WkcBurstEnd: first to last header with new errors
	FifoId fifo = FifoId::Tx;   ///< Fifo
	std::uint32_t mark = 0;     ///< Fifo
	bool above = false;         ///< Fifo: TxFIFO at/above its high mark, RxFIFO above its low mark
	ResetReason resetReason = ResetReason::Unknown;
	DeviceAction action = DeviceAction::Unknown;
	std::uint8_t cmdCode = 0; ///< AsyncError: the command code
	int status = 0;           ///< AsyncError: negative errno (-EREMOTEIO, -EBUSY, -ETIMEDOUT)
	LossKind loss = LossKind::OutRingUnderrun; ///< PdoLoss: which counter (increase: by how much)
	std::uint64_t total = 0;  ///< PdoLoss: that counter since probe

	/// State: the kernel read the slaves (a change down or into ERROR).
	bool haveSlaves = false;
	std::uint32_t slaveCount = 0;      ///< slaves on the bus
	std::vector<SlaveAlStatus> slaves; ///< the ones not in OP
	bool slavesIncomplete = false;     ///< not every slave could be read
	/// The first non-zero AL status code among slaves, and whose.
	std::optional<std::uint16_t> alStatus;
	std::optional<std::uint16_t> alSlave;
};

/// A State event that went to a lower state or into ERROR: the kind for
/// which the kernel reads the slaves' states and AL status codes before it
/// sends the event.
[[nodiscard]] ECMXF_EXPORT bool stateWentDown(const Event &event) noexcept;

/// Fills @p event's slaves as the kernel does for its state events
/// (kmod/ecmxf-netlink.c, "AL status query"): ECAT_SLV_CNT_GET, then
/// ECAT_STATE_GET of every slave and, for each slave not in OP that
/// answers (not ERROR alone), ECAT_SLV_INFO_GET code 7, its AL status
/// code; at most 64 slaves. Sets haveSlaves, slaveCount, slaves (the ones
/// not in OP), alStatus and alSlave (the first non-zero code). A command
/// that fails or that the chip refuses ends the reading with
/// slavesIncomplete set, as the kernel's does; nothing is thrown for it.
ECMXF_EXPORT void readSlaveStatus(Device &device, Event &event);

/// The protocol core's event detector (lib/core/ecmxf-events.c) for a
/// host that polls the chip itself. Feed every response header. A
/// detector made with a Device also reads the slaves' AL status codes
/// for the state events that went down (readSlaveStatus()), so its State
/// events carry what the kernel's do.
class ECMXF_EXPORT EventDetector
{
public:
	struct Config {
		std::uint8_t txHigh = 10; ///< TxFIFO high mark
		std::uint8_t rxLow = 0;   ///< RxFIFO low mark
		/// A WKC burst ends after this long without new errors.
		std::chrono::nanoseconds wkcQuiet = std::chrono::milliseconds(100);
	};
	EventDetector();
	explicit EventDetector(const Config &config);
	/// A detector whose State events that went down (stateWentDown())
	/// come with the slaves of @p device (readSlaveStatus()), read in
	/// feed(). @p device must outlive the detector.
	explicit EventDetector(Device &device);
	EventDetector(Device &device, const Config &config);
	~EventDetector();
	EventDetector(EventDetector &&) noexcept;
	EventDetector &operator=(EventDetector &&) noexcept;

	/// The events of @p header, which arrived at @p now (any monotonic
	/// origin). The first header (and the first after rebase()) is the
	/// baseline and gives none. A detector made with a Device reads the
	/// slaves here (the device's commands, through any error).
	std::vector<Event> feed(const ResponseHeader &header, std::chrono::nanoseconds now);
	/// The end of a WKC burst whose quiet time has passed by @p now.
	std::vector<Event> poll(std::chrono::nanoseconds now);
	/// Forget the baseline (e.g. after a reset the host saw by other
	/// means); a running WKC burst ends now.
	std::vector<Event> rebase(std::chrono::nanoseconds now);
	/// When poll() may have an event; empty when no burst runs.
	[[nodiscard]] std::optional<std::chrono::nanoseconds> deadline() const;

private:
	struct Impl;
	std::unique_ptr<Impl> impl_;
};

/// Counters of one device (ECMXF_NL_CMD_GET_COUNTERS).
struct NetlinkCounters {
	std::uint32_t minor = 0;
	std::string device;    ///< "ecmxfN"
	LinkCounters link;   ///< the fields of struct ecmxf_counters
	std::uint64_t events = 0;           ///< events the kernel detected
	std::uint64_t eventsSuppressed = 0; ///< not sent: rate limit
	std::uint64_t eventsFailed = 0;     ///< not sent: no memory, socket buffers full
};

/// A subscription to the kernel module's events (libmnl, RAII: the socket
/// closes with the object). Joining the group needs no privilege.
class ECMXF_EXPORT EventSubscriber
{
public:
	/// Opens a generic netlink socket, resolves the family "ecmxf" and its
	/// group "events" and joins it. Throws ecmxf::Error: ENOENT when the
	/// family does not exist (ecmxf.ko not loaded), or the system's errno.
	EventSubscriber();
	~EventSubscriber();
	EventSubscriber(const EventSubscriber &) = delete;
	EventSubscriber &operator=(const EventSubscriber &) = delete;

	/// The next event, waiting at most @p timeout (forever when empty);
	/// std::nullopt on timeout or when interrupted by a signal. Messages
	/// the socket lost (ENOBUFS) are counted in lost() and skipped.
	std::optional<Event> next(std::optional<std::chrono::milliseconds> timeout = std::nullopt);
	/// The socket, for poll()/epoll (readable: call next()).
	[[nodiscard]] int fd() const noexcept;
	/// Times the socket reported lost messages (its buffer overflowed).
	[[nodiscard]] std::uint64_t lost() const noexcept { return lost_; }
	[[nodiscard]] std::uint16_t familyId() const noexcept { return family_; }

private:
	struct Socket;
	std::unique_ptr<Socket> sock_;
	std::uint16_t family_ = 0;
	std::uint64_t lost_ = 0;
	std::vector<std::uint8_t> buf_;
	std::size_t bufLen_ = 0, bufPos_ = 0;
};

/// ECMXF_NL_CMD_GET_COUNTERS for /dev/ecmxf@p minor. Throws ecmxf::Error:
/// ENOENT without the family, ENODEV without that device.
[[nodiscard]] ECMXF_EXPORT NetlinkCounters readNetlinkCounters(std::uint32_t minor);
/// ECMXF_NL_CMD_GET_COUNTERS as a dump: every device, by minor.
[[nodiscard]] ECMXF_EXPORT std::vector<NetlinkCounters> dumpNetlinkCounters();

/// Decoders of one whole netlink message (struct nlmsghdr, genlmsghdr,
/// attributes) of the family, whatever its family id; for tools and
/// tests. Throw ecmxf::Error (EPROTO) when the message is not an event
/// (or counters) message or is malformed; attributes they do not know are
/// skipped.
[[nodiscard]] ECMXF_EXPORT Event decodeEventMessage(std::span<const std::uint8_t> msg);
[[nodiscard]] ECMXF_EXPORT NetlinkCounters decodeCountersMessage(std::span<const std::uint8_t> msg);

} // namespace ecmxf
