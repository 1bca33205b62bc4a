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
	/// Opens the device named by @p uri:
	///  - "sim:" an in-process simulated chip with the default network
	///    (virtual time);
	///  - "sim:<network file>" an in-process simulated chip with the
	///    network in that file (Documentation/simulator.rst).
	/// Throws ecmxf::Error (EINVAL) for anything else: /dev/ecmxfN and
	/// spidev: transports are not implemented yet.
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
	// Documentation/process-data.rst. Every call throws ecmxf::Error; an
	// argument out of range is refused with EINVAL before anything is
	// sent; a command the chip refuses (error status bit 7) throws
	// EREMOTEIO naming the command.

	/// ECAT_PDO_WC_GET parameters 1 and 2: slaves with inputs / outputs.
	[[nodiscard]] PdoSlaveCounts pdoSlaveCounts();
	/// ECAT_PDO_WC_GET parameter 3: the working counter of the last cycle.
	[[nodiscard]] std::uint32_t pdoWorkingCounter();

	/// ECAT_PDO_DATA_FIFO_OP: pushes @p frames RxPDO frames (@p rxFrames
	/// holds them back to back, frames x RxPDO size bytes; none: no write)
	/// into the RxFIFO, and with @p read pops as many TxPDO frames as fit
	/// in the data section. @p frames 0..255; the bytes must divide evenly
	/// into @p frames and fit the data section.
	PdoFifoResult pdoFifoExchange(std::span<const std::uint8_t> rxFrames, unsigned frames, bool read);

	/// ECAT_PDO_DATA_OP, read only: the current input image (TxPDO size).
	[[nodiscard]] std::vector<std::uint8_t> pdoRead();
	/// ECAT_PDO_DATA_OP, write only: the outputs that go out while the FIFO
	/// is off or empty (pre-load them before FIFO_ENABLE). At most the
	/// RxPDO size is taken; empty @p outputs is refused (EINVAL).
	void pdoWrite(std::span<const std::uint8_t> outputs);
	/// ECAT_PDO_DATA_OP, both: writes @p outputs, returns the inputs.
	[[nodiscard]] std::vector<std::uint8_t> pdoWriteRead(std::span<const std::uint8_t> outputs);

	/// FIFO_ENABLE: the bus cycle consumes the RxFIFO and fills the TxFIFO
	/// only while enabled (ECAT_INIT_OP disables it).
	void fifoEnable(bool enable);
	/// FIFO_PACK_SIZE_GET parameters 0 and 1: the frame sizes.
	[[nodiscard]] FifoPackSizes fifoPackSizes();
	/// FIFO_CLR_OP: empties one or both FIFOs.
	void fifoClear(FifoSelect which = FifoSelect::Both);
	/// FIFO_GET_TX_CNT / FIFO_GET_RX_CNT: the FIFO depths (frames).
	[[nodiscard]] unsigned fifoTxCount();
	[[nodiscard]] unsigned fifoRxCount();
	/// FIFO_SET_TX_CNT / FIFO_SET_RX_CNT: one depth, 1..255, such that
	/// RxCount x RxPDO size + TxCount x TxPDO size <= 0x4000 with the other
	/// FIFO's present depth (checked before sending: EINVAL naming both).
	/// Both FIFOs are rebuilt empty.
	void fifoSetTxCount(unsigned count);
	void fifoSetRxCount(unsigned count);
	/// Both depths at once, in the order the budget allows.
	void fifoSetCounts(unsigned rxCount, unsigned txCount);
	/// FIFO_INIT: rebuilds both FIFOs, empty, with the present depths.
	void fifoInit();
	/// ECAT_SET_FIFO_TH: the TxFIFO high and RxFIFO low marks.
	void fifoSetThresholds(const FifoThresholds &thresholds);

	/// The raw command path of the cyclic exchange: like command(), but
	/// allocates nothing and throws nothing. @p payload is the data
	/// section (at most pdoDataCapacity() bytes); the answer's data goes to
	/// @p rx (header.len bytes of it; a longer answer gives EMSGSIZE; an
	/// empty @p rx drops the data) and its header to @p header. Returns 0, or the positive errno value that
	/// command() would have thrown (ETIMEDOUT, EBADMSG, EPROTO, EIO, EBUSY,
	/// EREMOTEIO, ECONNRESET, EMSGSIZE, ECANCELED; EIO also when the
	/// transport threw). A command error (error status bit 7) is not a
	/// failure here: look at header.errStatus.
	int transact(const RawCommand &c, std::span<const std::uint8_t> payload, std::span<std::uint8_t> rx,
		     ResponseHeader &header) noexcept;
	/// The current data section size in bytes (112 at power-on): the most
	/// one transact() carries each way.
	[[nodiscard]] std::size_t pdoDataCapacity() const noexcept;
	// ==== end pdo

	// ==== typed commands: the chip's CiA-402 engine (lib/cia402_chip.cpp)
	// ==== end cia402

	// ==== packet trace (lib/trace.cpp)
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
