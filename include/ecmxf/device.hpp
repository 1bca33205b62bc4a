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
#include <ecmxf/link/link.hpp>
#include <ecmxf/bus/types_bus.hpp>
#include <ecmxf/chip/types_chip.hpp>
#include <ecmxf/cia402/types_cia402.hpp>
#include <ecmxf/pdo/types_pdo.hpp>

namespace ecmxf {

class ByteChannel; // <ecmxf/link/byte_channel.hpp>

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

	// ==== typed commands: chip, link, peripherals, EEPROM, FoE, raw,
	// ==== MDIO, mailbox, interrupts, resets (lib/chip/commands_chip.cpp)
	//
	// Documentation/commands-chip.rst describes each call. Arguments out of
	// range throw Error(EINVAL) naming the argument and its range; a
	// command the chip refuses (error status bit 7) throws Error(EINVAL)
	// with the error status; an async command that fails throws
	// Error(EREMOTEIO) with the chip's own error code where it has one.

	// ---- the chip, its link ----

	/// INFO_UPDATE_OP (0): one exchange that refreshes the response
	/// header, optionally with the control-byte actions of @p options.
	ResponseHeader infoUpdate(const InfoUpdateOptions &options = {});
	/// FW_VERSION_GET (56): version, extended version, series, build id.
	[[nodiscard]] FirmwareVersion firmwareVersion();
	/// Firmware, format, header status and counters in one (commands 56,
	/// 20, 130, 131).
	[[nodiscard]] ChipInfo info();
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
	/// SPI_PACK_SIZE_GET (20): the data section size the chip reports.
	[[nodiscard]] std::uint16_t queryDataSize();
	/// SPI_RECONFIG_OP (23): data section of @p bytes (32..1408) from the
	/// next exchange on; the library follows (100 ms hold-off).
	void setDataSize(std::uint16_t bytes);
	/// CRC_TYPE_SET (25): the check word type from the next packet on.
	/// Crc8 and Ccitt exist in firmware of manual ver. 038 only.
	void setCheckType(CheckType type);
	/// CRC_ERR_CNT_CLR (24): clears the SPI CRC error count; returns the
	/// count it had.
	std::uint8_t clearCrcErrorCount();
	/// ECAT_WKC_CONTI_ERR_CNT_GET (130): consecutive WKC errors now.
	[[nodiscard]] std::uint8_t wkcContinuousErrorCount();
	/// ECAT_WKC_CONTI_ERR_MAX_GET (131): the limit (kWkcNoLimit = none).
	[[nodiscard]] std::uint8_t wkcErrorLimit();
	/// ECAT_WKC_CONTI_ERR_MAX_SET (132): stop the process data after more
	/// than @p limit (1..255; kWkcNoLimit = never) consecutive WKC errors.
	void setWkcErrorLimit(std::uint8_t limit);
	/// ECAT_INT_SET_ENABLE (58): INT1 sources and INT0/INT1 polarities.
	void setInterruptConfig(const InterruptConfig &config);
	/// ECAT_INT_GET_ENABLE (59).
	[[nodiscard]] InterruptConfig interruptConfig();
	/// ASYNCCMD_RESET (75): @p actions = async_reset::k* bits (1..7).
	void resetAsyncCommand(std::uint8_t actions);
	/// WARM_RESET (127): the chip restarts with its power-on settings
	/// (112-byte data section, fixed check word); the library follows.
	void warmReset();

	// ---- GPIO (31, 32): masks name GPIO n with bit n, n = 0..19 ----

	/// GpioSetMode (31/0 for GPIO 0..15, 31/8 for GPIO 16..19).
	void gpioSetMode(std::uint32_t lines, GpioMode mode, GpioPull pull = GpioPull::None);
	/// GpioEnableDebounce (31/2, 31/9) for the @p lines.
	void gpioSetDebounce(std::uint32_t lines, bool enable);
	/// GpioSetDebounceClock (31/3): sampling period 2^@p cycle (0..15)
	/// periods of @p clock.
	void gpioSetDebounceClock(unsigned cycle, DebounceClock clock);
	/// GpioIntEnable (31/1): interrupt type of one @p line (0..19).
	void gpioSetInterrupt(unsigned line, GpioEdge edge);
	/// GpioIntClear (31/4, or 31/6 when @p lines names GPIO 16..19).
	void gpioClearInterrupts(std::uint32_t lines);
	/// GpioSetValue (32/0): the output latches of GPIO 0..15.
	void gpioWrite(std::uint16_t values);
	/// GpioExtSetValue (32/2): the output latches of GPIO 0..19.
	void gpioWriteAll(std::uint32_t values);
	/// GpioGetValue (32/1): GPIO 0..15.
	[[nodiscard]] std::uint16_t gpioRead();
	/// GpioExtGetValue (32/3): GPIO 0..19.
	[[nodiscard]] std::uint32_t gpioReadAll();
	/// GpioGetIntFlag (32/5): interrupt flags of GPIO 0..15.
	[[nodiscard]] std::uint16_t gpioInterruptFlags();
	/// GpioExtGetIntFlag (32/7): interrupt flags of GPIO 0..19.
	[[nodiscard]] std::uint32_t gpioInterruptFlagsAll();

	// ---- QEI (33), DAC (34), ADC (35) ----

	/// EncOpen (33/4): counting mode; stops and clears the counter.
	void qeiOpen(QeiMode mode);
	/// EncStart (33/5), EncStop (33/6).
	void qeiStart();
	void qeiStop();
	/// EncGetCount (33/21): the 32-bit counter.
	[[nodiscard]] std::uint32_t qeiCount();
	/// DacOpen (34/20), DacClose (34/21).
	void dacOpen(DacTrigger trigger);
	void dacClose();
	/// DacSetDelayTime (34/22): 0..1023 in 1/96 us.
	void dacSetDelay(std::uint16_t ticks);
	/// DacSetData (34/11): 0..4095 = 0..3.3 V.
	void dacWrite(std::uint16_t value);
	/// DacStartConv (34/0).
	void dacStartConversion();
	/// AdcOpen (35/40), AdcClose (35/41).
	void adcOpen(AdcInputMode mode);
	void adcClose();
	/// AdcConfigSampleModule (35/42): sample @p module (0..15) converts
	/// @p channel (0..15), software trigger. The manuals' own call is
	/// (0, 0) ("reserved, set 0").
	void adcConfigureModule(unsigned module, unsigned channel);
	/// AdcStartConv (35/12): start the modules of @p moduleMask (bits 0..15).
	void adcStart(std::uint16_t moduleMask);
	/// AdcGetDataValidFlag (35/17): the modules of @p moduleMask whose
	/// result is valid.
	[[nodiscard]] std::uint16_t adcValidFlags(std::uint16_t moduleMask);
	/// AdcGetConvData (35/15): the result of @p module (0..4095).
	[[nodiscard]] std::uint16_t adcRead(unsigned module);
	/// adcStart, adcValidFlags until valid (at most 100 polls), adcRead.
	[[nodiscard]] std::uint16_t adcConvert(unsigned module = kAdcDefaultModule);

	// ---- MDIO (81, ver. 050) ----

	/// Reads register @p reg (0..31) of the PHY at @p phy (0..31).
	[[nodiscard]] std::uint16_t mdioRead(unsigned phy, unsigned reg);
	void mdioWrite(unsigned phy, unsigned reg, std::uint16_t value);

	// ---- slaves: EEPROM (38/39), raw datagrams (137/138), FoE (139/140) ----

	/// One word of the SII EEPROM of the slave at bus position @p slave
	/// (0..127); @p timeout is the chip's limit (zero: its default).
	[[nodiscard]] std::uint16_t eepromRead(unsigned slave, std::uint16_t wordAddress,
					       std::chrono::microseconds timeout = {});
	/// @p count words from @p wordAddress on, one EEPROM_REQ each.
	[[nodiscard]] std::vector<std::uint16_t> eepromReadWords(unsigned slave, std::uint16_t wordAddress,
								 std::size_t count);
	void eepromWrite(unsigned slave, std::uint16_t wordAddress, std::uint16_t value,
			 std::chrono::microseconds timeout = {});
	/// RAW_ECAT_FUNC_REQ + RAW_ECAT_FUNC_GET: one datagram.
	DatagramResult rawDatagram(const Datagram &datagram);
	/// FoE read of file @p name from @p slave, whole (FOE_FUNC_REQ
	/// upload into the chip's flash, then flash reads in chunks).
	[[nodiscard]] std::vector<std::uint8_t> foeRead(unsigned slave, std::string_view name,
							const FoeOptions &options = {});
	/// FoE write of @p data as file @p name to @p slave (flash writes in
	/// chunks, then FOE_FUNC_REQ download).
	void foeWrite(unsigned slave, std::string_view name, std::span<const std::uint8_t> data,
		      const FoeOptions &options = {});
	/// The FOE_FUNC_REQ steps on their own: upload a slave's file into the
	/// flash (returns its size), download flash bytes as a file, read and
	/// write the flash (any size; chunked as the data section allows).
	std::uint32_t foeUploadToFlash(unsigned slave, std::string_view name, const FoeOptions &options = {});
	void foeDownloadFromFlash(unsigned slave, std::string_view name, std::uint32_t length,
				  const FoeOptions &options = {});
	[[nodiscard]] std::vector<std::uint8_t> flashRead(std::uint32_t address, std::uint32_t length);
	void flashWrite(std::uint32_t address, std::span<const std::uint8_t> data);

	// ---- mailbox (143/144), emergencies (83), direct assign (82) ----

	/// COE_EMERGENCY (83): up to @p count (1..8) of the newest emergencies
	/// the master read, newest first (fewer when there are fewer).
	[[nodiscard]] std::vector<CoeEmergency> coeEmergencies(unsigned count = 8);
	/// MBX_STAT 0 (144): bus positions whose receive mailbox holds a message.
	[[nodiscard]] std::vector<unsigned> mailboxPending();
	/// MBX_STAT 1: master polling of each slave's receive mailbox
	/// (@p poll[position]), in effect from the next ECAT_RECONFIG_OP.
	void setMailboxPolling(const std::vector<bool> &poll);
	/// MBX_STAT 2: the polling in effect, one flag per slave.
	[[nodiscard]] std::vector<bool> mailboxPolling();
	/// RECV_MAILBOX 0 (143, async): fetch @p slave's receive mailbox into
	/// the chip.
	void fetchMailbox(unsigned slave);
	/// RECV_MAILBOX 1: @p length bytes of the fetched message from @p offset.
	[[nodiscard]] std::vector<std::uint8_t> readMailbox(std::size_t offset, std::size_t length);
	/// fetchMailbox, then the whole message (6-byte mailbox header and the
	/// bytes its length field counts); empty when the mailbox was empty.
	[[nodiscard]] std::vector<std::uint8_t> receiveMailbox(unsigned slave);
	/// DIRECT_ASSIGN 0 (82): use the lengths set below for @p slave.
	void setDirectAssign(unsigned slave, bool enable);
	/// DIRECT_ASSIGN 1: @p slave's process data length on @p side.
	void setDirectAssignLength(unsigned slave, ProcessDataSide side, std::uint16_t bytes);
	// ==== end chip

	// ==== typed commands: bus bring-up, states, slaves, PDO, FIFO, SDO
	// ==== (lib/bus/commands_bus.cpp, lib/bus/sdo.cpp)
	// Slaves are 0-based bus positions as the chip numbers them (0..127);
	// kAllSlaves (0xFF) selects all where the manual allows it. Types in
	// <ecmxf/bus/types_bus.hpp>; Documentation/commands-bus.rst, sdo.rst.

	/// ECAT_INIT_OP (1): scan the network and configure DC; every slave
	/// ends in INIT, the FIFO off.
	void initNetwork(const InitConfig &config = {});
	/// ECAT_RECONFIG_OP (2): rebuild the process image after a PDO
	/// remapping (the header's ECAT state reads INIT afterwards; call
	/// stateUpdate()).
	void reconfigure();
	/// ECAT_INIT_DC_OP (3): apply the DC settings (after dcSync()).
	void initDc();
	/// ECAT_PDO_CONFIG_SET (7): write one assignment object and its PDOs
	/// (at most 3 PDOs of 8 entries: EINVAL beyond; use SDO then).
	void pdoConfigSet(const PdoConfig &config);
	/// ECAT_PDO_CONFIG_REQ (8) + ECAT_PDO_CONFIG_GET (9): read an
	/// assignment object (0x1C12/0x1C13) and its PDOs back from a slave.
	[[nodiscard]] PdoConfig pdoConfigRead(std::uint8_t slave, std::uint16_t assignIndex);
	/// ECAT_PDO_CONFIG_GET (9) alone: the result of the last PDO_CONFIG_REQ.
	[[nodiscard]] PdoConfig pdoConfigGet();
	/// ECAT_STATE_SET (12); waits until the slave(s) reached @p state.
	/// Failure: AlStatusError naming the slave, the state reached and its
	/// AL status code and text.
	void stateSet(std::uint8_t slave, State state);
	/// ECAT_STATE_GET (13): the state the chip last read (see stateUpdate()).
	[[nodiscard]] StateReading stateGet(std::uint8_t slave);
	/// ECAT_SLV_INFO_GET (15), every code (0..9).
	[[nodiscard]] SlaveInfo slaveInfo(std::uint8_t slave);
	/// ECAT_SLV_INFO_GET (15), one code; the bytes the chip returned.
	[[nodiscard]] std::vector<std::uint8_t> slaveInfoRaw(std::uint8_t slave, SlaveInfoCode code);
	/// ECAT_SLV_CNT_GET (16): slaves found by the last INIT_OP.
	[[nodiscard]] std::uint8_t slaveCount();
	/// ECAT_STATE_CHECK (41): STATE_SET + STATE_UPDATE + STATE_GET; the
	/// state reached (failures as stateSet()).
	StateReading stateCheck(std::uint8_t slave, State state);
	/// ECAT_DCSYNC (50): per-slave DC settings; applied by initDc().
	void dcSync(std::uint8_t slave, const DcConfig &dc);
	/// ECAT_STATE_UPDATE (57): read the slaves' states into the chip.
	void stateUpdate();
	/// ECAT_SDO_ABORTCODE_GET (69): the abort code of the last SDO.
	[[nodiscard]] std::uint32_t sdoAbortCode();
	/// ECAT_CONFIG_SM (71): set one sync manager of a slave by hand.
	void configSm(std::uint8_t slave, std::uint8_t sm, const SmConfig &config);
	/// ECAT_CONFIG_FMMU (72). Obsolete (manual ver. 050): the chip
	/// configures the FMMUs itself and overwrites this; kept for
	/// completeness. @p functions: FMMU0..3 function codes.
	void configFmmu(std::uint8_t slave, const std::array<std::uint8_t, 4> &functions);
	/// ECAT_CONFIG_MAP (73): apply a PDO remapping (instead of
	/// RECONFIG_OP for slaves that reset their mapping on it).
	void configMap();
	/// ENABLE_LRW (142): LRW (true, the default) or LRD + LWR.
	void enableLrw(bool enable);

	/// ECAT_SDO_REQ (10) read + ECAT_SDO_GET (11): upload an object.
	/// Failure: SdoError with the abort code (ECAT_SDO_ABORTCODE_GET) and
	/// its text. At most kSdoMaxBytes per request and at most the data
	/// section (EMSGSIZE otherwise).
	[[nodiscard]] std::vector<std::uint8_t> sdoUpload(std::uint8_t slave, std::uint16_t index,
							  std::uint8_t sub, const SdoOptions &options = {});
	/// ECAT_SDO_REQ (10) write: download @p data (1..256 bytes, and
	/// 12 + size within the data section).
	void sdoDownload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
			 std::span<const std::uint8_t> data, const SdoOptions &options = {});
	/// A visible string (trailing NULs dropped).
	[[nodiscard]] std::string sdoReadString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
						const SdoOptions &options = {});
	void sdoWriteString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::string_view value,
			    const SdoOptions &options = {});

	/// Upload an integer or real (little-endian on the bus); the object
	/// must have exactly sizeof(T) bytes (EPROTO otherwise).
	template <typename T>
		requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
	[[nodiscard]] T sdoRead(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
				const SdoOptions &options = {})
	{
		SdoOptions o = options;
		if (o.length == 0)
			o.length = sizeof(T);
		const std::vector<std::uint8_t> b = sdoUpload(slave, index, sub, o);
		if (b.size() != sizeof(T))
			detail::throwSdoSizeMismatch(slave, index, sub, b.size(), sizeof(T));
		using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
			  std::conditional_t<sizeof(T) == 2, std::uint16_t,
			  std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
		U u = 0;
		for (std::size_t i = 0; i < sizeof(T); i++)
			u = static_cast<U>(u | static_cast<U>(static_cast<U>(b[i]) << (8 * i)));
		return std::bit_cast<T>(u);
	}
	/// Download an integer or real (little-endian on the bus).
	template <typename T>
		requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
	void sdoWrite(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, T value,
		      const SdoOptions &options = {})
	{
		using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
			  std::conditional_t<sizeof(T) == 2, std::uint16_t,
			  std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
		const U u = std::bit_cast<U>(value);
		std::array<std::uint8_t, sizeof(T)> b{};
		for (std::size_t i = 0; i < sizeof(T); i++)
			b[i] = static_cast<std::uint8_t>(u >> (8 * i));
		sdoDownload(slave, index, sub, std::span<const std::uint8_t>(b.data(), b.size()), options);
	}
	// ==== end bus

	// ==== typed commands: process data, FIFO, cyclic exchange
	// ==== (lib/pdo/commands_pdo.cpp, lib/pdo/cyclic.cpp)
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
	/// link failed). A command error (error status bit 7) is not a
	/// failure here: look at header.errStatus.
	int transact(const RawCommand &c, std::span<const std::uint8_t> payload, std::span<std::uint8_t> rx,
		     ResponseHeader &header) noexcept;
	/// The current data section size in bytes (112 at power-on): the most
	/// one transact() carries each way.
	[[nodiscard]] std::size_t pdoDataCapacity() const noexcept;
	// ==== end pdo

	// ==== typed commands: the chip's CiA-402 engine (lib/chip/cia402_chip.cpp)
	// Motors are numbered 0..127. With the engine on, the chip owns
	// controlword bits 0-3 and 7 of the motor in every frame. A command the
	// chip refuses (command error) throws ecmxf::Error (EREMOTEIO) saying
	// why it can be refused; bad arguments throw EINVAL.

	/// 402_CONFIG_SET: @p motor is the drive at @p config.slave, with its
	/// controlword and statusword at the given byte offsets of that
	/// slave's process data, and the engine's control byte. Needs the bus
	/// initialized (ECAT_INIT_OP).
	void chip402Configure(unsigned motor, const Chip402Config &config);
	/// 402_STATE_SET: the state the engine walks @p motor to: SWITCH ON
	/// DISABLED, READY TO SWITCH ON, SWITCHED ON, OPERATION ENABLED or
	/// QUICK STOP ACTIVE (else EINVAL).
	void chip402RequestState(unsigned motor, Cia402State target);
	/// 402_STATE_GET: the motor's state as the chip reads its statusword.
	[[nodiscard]] Chip402State chip402State(unsigned motor);
	/// 402_CTL_SET: the control byte, total motor count and slave.
	void chip402SetControl(unsigned motor, const Chip402Control &control);
	/// 402_CTL_GET: the control byte (bit 3 reads 0 again once a single
	/// fault reset is done).
	[[nodiscard]] Chip402Flags chip402Control(unsigned motor);
	/// 402_GET_STATUSWORD: the motor's statusword as the chip last read it.
	[[nodiscard]] std::uint16_t chip402Statusword(unsigned motor);
	/// Polls 402_STATE_GET (every @p poll on the link's clock) until
	/// @p motor is in @p target; throws ecmxf::Error (ETIMEDOUT) naming
	/// the awaited state, the state the motor stays in and its statusword
	/// after @p timeout.
	Cia402State chip402AwaitState(unsigned motor, Cia402State target, std::chrono::nanoseconds timeout,
				      std::chrono::nanoseconds poll = std::chrono::milliseconds(1));
	// ==== end cia402

	// ==== packet trace (lib/trace/trace.cpp)
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
	friend class TraceAccess; // lib/trace/trace.cpp reaches the device's trace slot
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
