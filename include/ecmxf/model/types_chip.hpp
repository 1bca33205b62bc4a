// SPDX-License-Identifier: MIT
/**
 * @file types_chip.hpp
 * @brief Value types of the typed commands for the chip, its link and peripherals, EEPROM, FoE, raw datagrams, MDIO, mailbox.
 *
 * The calls that use them are the "chip" section of Device
 * (include/ecmxf/device.hpp); Documentation/commands-chip.rst describes
 * every call, its command and the choices made where the manuals are
 * silent.
 */
#pragma once

#include <ecmxf/export.hpp>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/protocol.hpp>

namespace ecmxf {

// ---------------------------------------------------------------------------
// firmware, link, chip summary
// ---------------------------------------------------------------------------

/// Master series of FW_VERSION_GET data byte 3 (ver. 050). The manual lists
/// ECM-XF, ECM-XFL, ECM-XFU and ECM-XM without their codes; the library
/// numbers them in that order (0 = ECM-XF, what the simulator reports).
enum class MasterSeries : std::uint8_t {
	XF = 0,
	XFL = 1,
	XFU = 2,
	XM = 3,
};

/// FW_VERSION_GET (56).
struct FirmwareVersion {
	/// The firmware version (the return value), e.g. 0x30.
	std::uint8_t version = 0;
	/// The chip answered the 20 data bytes of ver. 050. false: firmware of
	/// the ver. 038 manual, which answers the version only; the fields
	/// below are then zero / empty.
	bool detailed = false;
	/// Extended version (data byte 1).
	std::uint8_t extendedVersion = 0;
	/// Master series code as sent (data byte 3).
	std::uint8_t seriesCode = 0;
	/// The series, when seriesCode is one the library knows.
	std::optional<MasterSeries> series;
	/// Build identifier (data bytes 4..19, "internal use") as sent.
	std::array<std::uint8_t, 16> buildIdBytes{};
	/// The build identifier as text: the bytes up to the first NUL when
	/// they are printable ASCII, else their hex digits.
	std::string buildId;
};

/// Everything the chip says about itself (Device::info()).
struct ChipInfo {
	FirmwareVersion firmware;
	/// Data section size the chip reports (SPI_PACK_SIZE_GET) and the
	/// packet size on the wire (header + data + trailer).
	std::uint16_t dataSize = 0;
	std::size_t packetSize = 0;
	/// Check word type in use (the library's engine, which follows
	/// CRC_TYPE_SET; the ECM status bits 1-0 of every response agree).
	CheckType checkType = CheckType::Fixed;
	/// Which bytes the chip's CRC covers, as found from its answers once a
	/// CRC was in force (Link::crcCoverage(); Documentation/protocol-core.rst,
	/// "Firmware variants"); Unknown before.
	CrcCoverage crcCoverage = CrcCoverage::Unknown;
	/// Response header bytes of the last exchange: EtherCAT state (0x08),
	/// error status (0x09), ECM status (0x0A), interrupt flags (0x10).
	std::uint8_t ecatState = 0;
	std::uint8_t errorStatus = 0;
	std::uint8_t ecmStatus = 0;
	std::uint32_t interruptFlags = 0;
	/// Counters: SPI CRC errors (header 0x04), WKC errors (header 0x05).
	std::uint8_t crcErrors = 0;
	std::uint8_t wkcErrors = 0;
	/// Consecutive WKC errors now (ECAT_WKC_CONTI_ERR_CNT_GET, ver. 050
	/// only: empty when the firmware refuses the command).
	std::optional<std::uint8_t> wkcContinuousErrors;
	/// The limit of consecutive WKC errors (255 = none).
	std::uint8_t wkcErrorLimit = 0;
};

/// INFO_UPDATE_OP (0) with the control-byte actions of ver. 050.
struct InfoUpdateOptions {
	/// Control bit 0: refresh the ECAT state from the slaves.
	bool refreshEcatState = false;
	/// Control bit 1: clear the SPI CRC error count (header 0x04).
	bool clearCrcErrorCount = false;
	/// Error-status bits to clear, at their error-status positions:
	/// bit 3 async error, 4 SPI error, 5 FIFO error, 6 SPI CRC error,
	/// 7 command error (control bits 3..7). Bits 0..2 are not clearable.
	std::uint8_t clearErrorBits = 0;
};

/// WKC_CONTI_ERR_MAX value meaning "never stop the process data".
inline constexpr std::uint8_t kWkcNoLimit = 255;

// ---------------------------------------------------------------------------
// interrupts
// ---------------------------------------------------------------------------

/// Interrupt flag / enable bits of the response header 0x10 and of
/// ECAT_INT_SET_ENABLE's u32CompIntEnable.
namespace irq {
inline constexpr std::uint32_t kEcatPacket = 1u << 31; ///< EtherCAT frame received (bus cycle)
inline constexpr std::uint32_t kEncoder = 1u << 29;    ///< encoder (QEI) flag; enabled by InterruptConfig::qei*
inline constexpr std::uint32_t kRxFifoLow = 1u << 25;  ///< RxFIFO fell to its low mark
inline constexpr std::uint32_t kTxFifoHigh = 1u << 24; ///< TxFIFO reached its high mark
inline constexpr std::uint32_t kCrcError = 1u << 23;   ///< SPI CRC error
inline constexpr std::uint32_t kWkcError = 1u << 22;   ///< working counter error
/// The bits ECAT_INT_SET_ENABLE can enable in its 32-bit word.
inline constexpr std::uint32_t kEnableMask = kEcatPacket | kRxFifoLow | kTxFifoHigh | kCrcError | kWkcError;
} // namespace irq

/// ECAT_INT_SET_ENABLE (58) / ECAT_INT_GET_ENABLE (59): what drives INT1,
/// and the polarities of INT0 and INT1 (ver. 050 bit meanings).
struct InterruptConfig {
	/// irq::k* bits (only those of irq::kEnableMask).
	std::uint32_t sources = 0;
	/// GPIO input interrupts of GPIO 0..11 (bit n = GPIO n).
	std::uint16_t gpioLines = 0;
	/// QEI interrupt sources (u8PeripIntEnable bits 4, 5, 6).
	bool qeiIndex = false;
	bool qeiCompare = false;
	bool qeiOverflow = false;
	/// INT0 ("ready") active high (parameter bit 1; power-on true).
	bool int0ActiveHigh = true;
	/// INT1 (events) active high (parameter bit 0; power-on false).
	bool int1ActiveHigh = false;

	friend bool operator==(const InterruptConfig &, const InterruptConfig &) = default;
};

/// ASYNCCMD_RESET (75) command parameter bits.
namespace async_reset {
inline constexpr std::uint8_t kClearBusy = 1u << 0;   ///< clear the async busy flag
inline constexpr std::uint8_t kSkipLinkWait = 1u << 1; ///< skip the wait for the Ethernet link
inline constexpr std::uint8_t kAbandon = 1u << 2;     ///< abandon the last async command
} // namespace async_reset

// ---------------------------------------------------------------------------
// GPIO, QEI, DAC, ADC
// ---------------------------------------------------------------------------

/// Number of GPIO lines (GPIO 0..19); masks name line n with bit n.
inline constexpr unsigned kGpioLines = 20;

/// GPIO_CONFIG_SET mode.
enum class GpioMode : std::uint8_t {
	Input = 0,
	Output = 1,              ///< push-pull
	OpenDrain = 2,
	QuasiBidirectional = 3,
};

/// GPIO_CONFIG_SET pull resistor.
enum class GpioPull : std::uint8_t {
	None = 0,
	Up = 1,
	Down = 2,
};

/// GPIO interrupt type (GPIO_CONFIG_SET sub-operation 1).
enum class GpioEdge : std::uint8_t {
	Disabled = 0,
	Both = 1,
	Falling = 2,
	Rising = 3,
};

/// Clock of the GPIO debounce sampler.
enum class DebounceClock : std::uint8_t {
	Core192MHz = 0,
	LowSpeed10kHz = 1,
};

/// QEI_FUNC_OP EncOpen counting mode.
enum class QeiMode : std::uint32_t {
	X4Free = 0x000,
	X2Free = 0x100,
	X4Compare = 0x200,
	X2Compare = 0x300,
};

/// DAC_FUNC_OP DacOpen trigger: what starts a conversion.
enum class DacTrigger : std::uint32_t {
	SetData = 0x0000,     ///< every dacWrite()
	StartConv = 0x0010,   ///< dacStartConversion()
	PinLow = 0x0030,      ///< DAC_ST pin low
	PinHigh = 0x1030,     ///< DAC_ST pin high
	PinRising = 0x2030,   ///< DAC_ST rising edge
	PinFalling = 0x3030,  ///< DAC_ST falling edge
};

/// ADC_FUNC_OP AdcOpen input mode.
enum class AdcInputMode : std::uint32_t {
	SingleEnded = 0x000,
	Differential = 0x100,
};

/// The ADC sample module and mask the manuals' own sequence uses
/// (StartConv / GetDataValidFlag "set 0x1000", GetConvData "set 12").
inline constexpr unsigned kAdcDefaultModule = 12;

// ---------------------------------------------------------------------------
// slaves: EEPROM, raw datagrams, FoE, mailbox, emergencies, direct assign
// ---------------------------------------------------------------------------

/// EtherCAT datagram commands of RAW_ECAT_FUNC_REQ (ver. 050 op codes).
enum class DatagramCommand : std::uint8_t {
	APRD = 1,
	APWR = 2,
	FPRD = 4,
	FPWR = 5,
	BRD = 7,
	BWR = 8,
	LRD = 10,
	LWR = 11,
	LRW = 12,
	ARMW = 13,
	FRMW = 14,
};

/// One raw datagram (RAW_ECAT_FUNC_REQ).
struct Datagram {
	DatagramCommand command = DatagramCommand::BRD;
	/// Address position: auto-increment (APxx/ARMW: autoIncrementAddress()
	/// of the slave position), configured station address (FPxx/FRMW),
	/// ignored otherwise.
	std::uint16_t adp = 0;
	/// Address offset: the ESC register (not for LRD/LWR/LRW).
	std::uint16_t ado = 0;
	/// Logical address (LRD/LWR/LRW).
	std::uint32_t logicalAddress = 0;
	/// Bytes to write (writes, LRW, RMW) or, for reads, as many bytes as
	/// are to be read (their values are sent but ignored). 1..256.
	std::vector<std::uint8_t> data;
	/// The chip's time limit; zero: the chip's default.
	std::chrono::microseconds timeout{ 0 };
};

/// What came back for a Datagram (RAW_ECAT_FUNC_GET).
struct DatagramResult {
	std::uint16_t workingCounter = 0;
	std::vector<std::uint8_t> data;
};

/// ADP of an auto-increment datagram addressing bus position @p position.
[[nodiscard]] constexpr std::uint16_t autoIncrementAddress(unsigned position) noexcept
{
	return static_cast<std::uint16_t>(0x10000u - position);
}

/// DIRECT_ASSIGN (82) side of the process data.
enum class ProcessDataSide : std::uint8_t {
	Output = 0, ///< RxPDO (master to slave)
	Input = 1,  ///< TxPDO (slave to master)
};

/// One entry of COE_EMERGENCY (83): an emergency the master read.
struct CoeEmergency {
	std::uint8_t entry = 0;       ///< 0 = the newest
	std::uint8_t slave = 0;       ///< bus position
	std::uint16_t sequence = 0;   ///< emergencies read since the chip started (from 1)
	std::uint16_t errorCode = 0;  ///< CiA error code
	std::uint8_t errorRegister = 0;
	std::array<std::uint8_t, 5> data{};

	friend bool operator==(const CoeEmergency &, const CoeEmergency &) = default;
};

/// FOE_FUNC_REQ staging flash size (start addresses 0..0x3FFFF).
inline constexpr std::uint32_t kFoeFlashSize = 0x40000;

/// Options of foeRead()/foeWrite().
struct FoeOptions {
	/// FoE file password.
	std::uint32_t password = 0;
	/// Where the file is staged in the chip's flash.
	std::uint32_t flashAddress = 0;
	/// The chip's time limit for the FoE transfer; zero: the chip's default.
	std::chrono::microseconds timeout{ 0 };
};

} // namespace ecmxf
