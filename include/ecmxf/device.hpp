// SPDX-License-Identifier: MIT
/**
 * @file device.hpp
 * @brief One ECM-XF chip over a Link, with the synchronous raw command
 *        call that every typed call goes through.
 *
 * A Device owns its Link (include/ecmxf/link/link.hpp): the protocol
 * core's engine over a byte channel, or the kernel module's /dev/ecmxfN.
 * command() sends one command and returns its answer, or for an async
 * command waits for its completion; failures are thrown as ecmxf::Error
 * with a message in the field's words, the same whatever the link.
 * The typed commands are in view classes that a Device hands out (chip(),
 * peripherals(), chip402(), slaves(), bus(), sdo(), pdo()); this header
 * only declares them: include the header of each view you call
 * (Documentation/library.rst, "The typed calls").
 *
 * Thread safety: a Device is not thread-safe; one thread at a time calls
 * it.
 */
#pragma once

#include <array>
#include <bit>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>

namespace ecmxf {

class ByteChannel; // <ecmxf/link/byte_channel.hpp>

// The typed command views (Device::chip() ... Device::pdo()); include the
// view's header to call one.
class Chip;
class Peripherals;
class Chip402;
class SlaveAccess;
class Bus;
class Sdo;
class ProcessData;

/// One command as the host sends it (command header fields and data).
struct Command {
	std::uint8_t code = 0;               ///< command code (0x0C)
	std::uint8_t param = 0;              ///< command parameter (0x0D)
	std::array<std::uint8_t, 4> data{};  ///< parametric data 0..3 (0x04..0x07)
	/// Data length field (0x0E); unset: the payload size. Some commands
	/// use it as a parameter (e.g. SPI_RECONFIG_OP: the new data size).
	std::optional<std::uint16_t> len;
	std::uint16_t reserved = 0;          ///< reserved word (0x08), e.g. INIT_OP's LRW bit
	/// Control byte (0x0A). The engine adds its own clear bits (async and
	/// command error) after a failed command.
	std::uint8_t control = 0;
	/// Data section bytes, at most the current data size (112 at power-on).
	std::vector<std::uint8_t> payload;
	/// Time allowed from sending to the answer, and for an async command
	/// to its completion; zero selects the command table's default
	/// (100 ms for immediate commands, e.g. 10 s for ECAT_INIT_OP).
	std::chrono::microseconds timeout{ 0 };
};

/// A command for Device::transact(): the header fields of Command without
/// anything that allocates (the data section is a separate span).
struct RawCommand {
	std::uint8_t code = 0;               ///< command code (0x0C)
	std::uint8_t param = 0;              ///< command parameter (0x0D)
	std::array<std::uint8_t, 4> data{};  ///< parametric data 0..3 (0x04..0x07)
	/// Data length field (0x0E); negative: the payload size.
	std::int32_t len = -1;
	std::uint16_t reserved = 0;          ///< reserved word (0x08)
	std::uint8_t control = 0;            ///< control byte (0x0A)
	/// Zero selects the command table's default (see Command::timeout).
	std::chrono::microseconds timeout{ 0 };
};


/// The answer to a command.
struct Response {
	/// The answering header; for an async command, the header in which
	/// the chip reported completion (busy bit clear).
	ResponseHeader header;
	/// The data section bytes of the answer (header.len of them, from the
	/// chip's immediate answer).
	std::vector<std::uint8_t> data;
	/// The return value (header 0x0D), e.g. the count of SLV_CNT_GET.
	std::uint8_t ret = 0;
};

/// One ECM-XF chip behind a Link.
class ECMXF_EXPORT Device
{
public:
	/// Opens the device named by @p uri (include/ecmxf/device_uri.hpp):
	///  - "sim:" an in-process simulated chip with the default network
	///    (virtual time);
	///  - "sim:<network file>" an in-process simulated chip with the
	///    network in that file (Documentation/simulator.rst);
	///  - "/dev/ecmxfN" the kernel module's device (KernelLink);
	///  - "unix:PATH" an `ecmxf-sim --socket PATH` server (UnixChannel):
	///    the simulated chip keeps its state between opens;
	///  - "spidev:/dev/spidevB.C?int0=<chip>:<line>&int1=<chip>:<line>
	///    &speed=<Hz>&mode=<0..3>" spidev + libgpiod (SpidevChannel).
	/// Any of them may add the option trace=<file> (startTrace()).
	/// Throws ecmxf::Error: EINVAL for a bad URI (naming the bad part),
	/// the system's errno when the device cannot be opened.
	[[nodiscard]] static std::unique_ptr<Device> open(std::string_view uri);

	/// A device over @p link, which it owns. Throws ecmxf::Error (EINVAL)
	/// for a null link.
	explicit Device(std::unique_ptr<Link> link);
	/// A device over an EngineLink over @p channel, which it owns. The chip
	/// is assumed to be in its power-on format (112-byte data section,
	/// fixed check word).
	explicit Device(std::unique_ptr<ByteChannel> channel);
	~Device();
	Device(const Device &) = delete;
	Device &operator=(const Device &) = delete;

	/// Sends @p c and waits for its answer; for an async command (e.g.
	/// ECAT_INIT_OP, ECAT_STATE_SET, ECAT_SDO_REQ) also for its completion
	/// (the chip's busy bit clearing). Blocks the calling thread (real
	/// links) or advances virtual time (simulator) for at most the
	/// command's timeout plus one exchange. Throws ecmxf::Error when the
	/// command fails; nothing is left in flight afterwards.
	Response command(const Command &c);

	/// Runs the async command @p c and its result fetch @p fetch (the
	/// *_GET partner, an immediate command: ECAT_SDO_GET after
	/// ECAT_SDO_REQ...) and returns the fetch's answer. Over an engine
	/// link the fetch is the poll of the running command: the exchange
	/// that sees the completion also brings the result (see
	/// Documentation/protocol-core.rst, "Pipelining"); other links run
	/// the two one after the other. Throws @p c's failure as command()
	/// does (the fetch is then not sent), else the fetch's.
	Response commandWithFetch(const Command &c, const Command &fetch);

	/// The pause between two polls (INFO_UPDATE exchanges) of a running
	/// async command. The default, zero, polls back to back, each poll
	/// waiting only for INT0 "ready": no fixed sleeps, the completion is
	/// seen one exchange after the chip reports it. A positive interval
	/// trades that latency for fewer SPI exchanges while the chip works
	/// (e.g. during the seconds of ECAT_INIT_OP). Engine links only;
	/// the kernel module polls on its own.
	void setAsyncPollInterval(std::chrono::nanoseconds interval) noexcept;
	[[nodiscard]] std::chrono::nanoseconds asyncPollInterval() const noexcept;

	/// The least time any command is allowed (command() and transact(),
	/// and so every typed call): a command whose own timeout, or whose
	/// command table default when it sets none, is shorter gets
	/// @p floor instead. Zero (the default) keeps the table's times. For
	/// hosts that can stall longer than the table's 100 ms for reasons of
	/// their own (a loaded or emulated machine, a chip shared by several
	/// applications through the kernel's queue).
	void setMinimumTimeout(std::chrono::microseconds floor) noexcept;
	[[nodiscard]] std::chrono::microseconds minimumTimeout() const noexcept;

	// ==== the packet format the library's engine uses
	/// The data section size the library's engine uses now (no exchange).
	[[nodiscard]] std::uint16_t dataSize() const;
	/// The check word type the library's engine uses now (no exchange).
	[[nodiscard]] CheckType checkType() const;
	/// Tells the library's engine the packet format the chip speaks now,
	/// without an exchange: for a chip that another driver (e.g. ecmxf.ko,
	/// which sets CRC-32 at probe) reconfigured and did not reset. The
	/// spidev URI options size= and check= call it. Engine links only:
	/// EOPNOTSUPP over the kernel link (its far side tracks the
	/// format); EINVAL for a size outside 32..1408.
	void assumeFormat(std::uint16_t dataSize, CheckType check);

	/// The raw command path of the cyclic exchange: like command(), but
	/// allocates nothing and throws nothing. @p payload is the data
	/// section (at most pdoDataCapacity() bytes); the answer's data goes to
	/// @p rx (header.len bytes of it; a longer answer gives EMSGSIZE; an
	/// empty @p rx drops the data) and its header to @p header. Returns 0, or the positive errno value that
	/// command() would have thrown (ETIMEDOUT, EBADMSG, EPROTO, EIO, EBUSY,
	/// EREMOTEIO, ECONNRESET, EMSGSIZE, ECANCELED; EIO also when the
	/// link failed). A command error (error status bit 7) is not a
	/// failure here: look at header.errStatus.
	int transact(const RawCommand &c, std::span<const std::uint8_t> payload, std::span<std::uint8_t> rx,
		     ResponseHeader &header) noexcept;
	/// The link request transact() would run for @p c (its timeout raised
	/// to minimumTimeout()), for callers that hand several to
	/// Link::runBatch() (the cyclic path). Allocates nothing.
	[[nodiscard]] RawRequest request(const RawCommand &c, std::span<const std::uint8_t> payload,
					 std::span<std::uint8_t> rx) const noexcept;
	/// The current data section size in bytes (112 at power-on): the most
	/// one transact() carries each way.
	[[nodiscard]] std::size_t pdoDataCapacity() const noexcept;

	// ==== the typed commands: one view class each
	//
	// Each accessor returns a cheap, non-owning view of this device (it
	// must not outlive it); include the view's header to call it, e.g.
	//   #include <ecmxf/bus/bus.hpp>
	//   dev.bus().stateSet(kAllSlaves, State::PreOp);
	// Documentation/library.rst lists them.

	/// The chip: firmware, link format, counters, interrupts, resets
	/// (<ecmxf/chip/chip.hpp>).
	[[nodiscard]] Chip chip() noexcept;
	/// GPIO, QEI, DAC, ADC, MDIO (<ecmxf/chip/peripherals.hpp>).
	[[nodiscard]] Peripherals peripherals() noexcept;
	/// The chip's CiA-402 engine (<ecmxf/chip/chip402.hpp>).
	[[nodiscard]] Chip402 chip402() noexcept;
	/// EEPROM, raw datagrams, FoE and flash, mailbox, emergencies, direct
	/// assignment (<ecmxf/bus/slave_access.hpp>).
	[[nodiscard]] SlaveAccess slaves() noexcept;
	/// Bus bring-up, states, slave information, PDO configuration
	/// (<ecmxf/bus/bus.hpp>).
	[[nodiscard]] Bus bus() noexcept;
	/// SDO transfers (<ecmxf/bus/sdo.hpp>).
	[[nodiscard]] Sdo sdo() noexcept;
	/// Process data and the PDO FIFO (<ecmxf/pdo/process_data.hpp>).
	[[nodiscard]] ProcessData pdo() noexcept;
	// ==== end typed commands

	// ==== packet trace (lib/device/device.cpp; the writer lib/link/trace_writer.cpp)
	/// Starts recording every exchange to the file @p path (created or
	/// truncated), in the text format of Documentation/trace.rst
	/// (include/ecmxf/trace/trace.hpp decodes it): over an engine link each
	/// MOSI/MISO packet with the channel's clock, over the kernel
	/// link each command's request and response. Replaces a trace
	/// already running. Throws ecmxf::Error when the file cannot be
	/// created.
	void startTrace(std::string_view path);
	/// Stops recording and closes the file. Throws ecmxf::Error when
	/// writing the trace failed at any point (e.g. disk full); no-op
	/// without a trace.
	void stopTrace();
	/// Is a trace being recorded?
	[[nodiscard]] bool tracing() const noexcept;
	// ==== end trace

	/// The latest valid response header of any exchange (ECAT state,
	/// error status, FIFO counts...); all zero before the first one.
	[[nodiscard]] ResponseHeader lastHeader() const;

	/// The link this device owns: its clock, its counters and its
	/// capabilities (include/ecmxf/link/link.hpp).
	[[nodiscard]] Link &link() noexcept;
	[[nodiscard]] const Link &link() const noexcept;

private:
	class Impl;
	std::unique_ptr<Impl> impl_;
};

} // namespace ecmxf
