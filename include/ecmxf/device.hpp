// SPDX-License-Identifier: MIT
/**
 * @file device.hpp
 * @brief One ECM-XF chip: the protocol engine over a Transport, with a
 *        synchronous raw command call.
 *
 * A Device owns its Transport and one instance of the protocol core's
 * exchange engine (Documentation/protocol-core.rst). command() sends one
 * command and returns its answer, or for an async command waits for its
 * completion; failures are thrown as ecmxf::Error with a message in the
 * field's words.
 *
 * Thread safety: a Device is not thread-safe; one thread at a time calls
 * it.
 */
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/types_bus.hpp>
#include <ecmxf/types_chip.hpp>
#include <ecmxf/types_cia402.hpp>
#include <ecmxf/types_pdo.hpp>

namespace ecmxf {

class Transport; // include <ecmxf/transport.hpp> to use it

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

/// One ECM-XF chip behind a Transport.
class ECMXF_EXPORT Device
{
public:
	/// Opens the device named by @p uri (include/ecmxf/device_uri.hpp):
	///  - "sim:" an in-process simulated chip with the default network
	///    (virtual time);
	///  - "sim:<network file>" an in-process simulated chip with the
	///    network in that file (Documentation/simulator.rst);
	///  - "/dev/ecmxfN" the kernel module's device (KernelTransport);
	///  - "spidev:/dev/spidevB.C?int0=<chip>:<line>&int1=<chip>:<line>
	///    &speed=<Hz>&mode=<0..3>" spidev + libgpiod (SpidevTransport).
	/// Any of them may add the option trace=<file> (startTrace()).
	/// Throws ecmxf::Error: EINVAL for a bad URI (naming the bad part),
	/// the system's errno when the device cannot be opened.
	[[nodiscard]] static std::unique_ptr<Device> open(std::string_view uri);

	/// A device over @p transport, which it owns. The chip is assumed to
	/// be in its power-on format (112-byte data section, fixed check word).
	explicit Device(std::unique_ptr<Transport> transport);
	~Device();
	Device(const Device &) = delete;
	Device &operator=(const Device &) = delete;

	/// Sends @p c and waits for its answer; for an async command (e.g.
	/// ECAT_INIT_OP, ECAT_STATE_SET, ECAT_SDO_REQ) also for its completion
	/// (the chip's busy bit clearing). Blocks the calling thread (real
	/// transports) or advances virtual time (simulator) for at most the
	/// command's timeout plus one exchange. Throws ecmxf::Error when the
	/// command fails; nothing is left in flight afterwards.
	Response command(const Command &c);

	// ==== typed commands: chip, link, peripherals, EEPROM, FoE, raw,
	// ==== MDIO, mailbox, interrupts, resets (lib/commands_chip.cpp)
	// ==== end chip

	// ==== typed commands: bus bring-up, states, slaves, PDO, FIFO, SDO
	// ==== (lib/commands_bus.cpp, lib/sdo.cpp)
	// ==== end bus

	// ==== typed commands: process data, FIFO, cyclic exchange
	// ==== (lib/commands_pdo.cpp, lib/cyclic.cpp)
	// ==== end pdo

	// ==== typed commands: the chip's CiA-402 engine (lib/cia402_chip.cpp)
	// ==== end cia402

	// ==== packet trace (lib/trace.cpp)
	/// Starts recording every exchange to the file @p path (created or
	/// truncated), in the text format of Documentation/trace.rst
	/// (include/ecmxf/trace.hpp decodes it): for byte transports each
	/// MOSI/MISO packet with the transport's clock, for the kernel
	/// transport each command's request and response. Replaces a trace
	/// already running. Throws ecmxf::Error when the file cannot be
	/// created.
	void startTrace(std::string_view path);
	/// Stops recording and closes the file. Throws ecmxf::Error when
	/// writing the trace failed at any point (e.g. disk full); no-op
	/// without a trace.
	void stopTrace();
	/// Is a trace being recorded?
	[[nodiscard]] bool tracing() const noexcept;
	friend class TraceAccess; // lib/trace.cpp reaches the device's trace slot
	// ==== end trace

	/// The latest valid response header of any exchange (ECAT state,
	/// error status, FIFO counts...); all zero before the first one.
	[[nodiscard]] ResponseHeader lastHeader() const;

	/// The transport this device owns.
	[[nodiscard]] Transport &transport() noexcept;

private:
	class Impl;
	std::unique_ptr<Impl> impl_;
};

} // namespace ecmxf
