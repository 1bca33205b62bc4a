// SPDX-License-Identifier: MIT
/**
 * @file types_bus.hpp
 * @brief Value types of the typed commands for bus bring-up, EtherCAT states, slaves, PDO, FIFO and SDO.
 *
 * The commands themselves are Device members (include/ecmxf/device.hpp,
 * section "bus"); Documentation/commands-bus.rst and sdo.rst describe them.
 */
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/export.hpp>
#include <ecmxf/model/pdo_mapping.hpp>

namespace ecmxf {

/// Slave selector meaning "every slave" (STATE_SET, STATE_GET, STATE_CHECK, DCSYNC).
inline constexpr std::uint8_t kAllSlaves = 0xFF;
/// The largest slave position the chip addresses (0..127).
inline constexpr std::uint8_t kMaxSlavePosition = 127;
/// The most bytes one SDO request moves (ECAT_SDO_REQ, manual ver. 050).
inline constexpr std::size_t kSdoMaxBytes = 256;

/// EtherCAT (AL) states as the chip encodes them (ECAT_STATE_SET data 0,
/// ECAT_STATE_GET return value, header byte 0x08; the AL status register
/// values of ETG.1000). None: not a state (no network initialised yet).
enum class State : std::uint8_t {
	None = 0,
	Init = 1,
	PreOp = 2,
	Boot = 3,
	SafeOp = 4,
	Op = 8,
};

/// "INIT", "PRE-OP", "BOOT", "SAFE-OP", "OP", "NONE"; "0x.." for other values.
[[nodiscard]] ECMXF_EXPORT std::string stateName(State s);

/// A state as read back: the state bits (3..0) and the error flag (bit 4).
struct StateReading {
	std::uint8_t raw = 0;   ///< the byte the chip returned
	/// The state in bits 3..0; State::None when they hold no state.
	[[nodiscard]] State state() const noexcept
	{
		const auto s = static_cast<std::uint8_t>(raw & 0x0F);
		return (s == 1 || s == 2 || s == 3 || s == 4 || s == 8) ? static_cast<State>(s) : State::None;
	}
	/// Error flag (0x10): a refused transition, or (all slaves) the bus
	/// is in error.
	[[nodiscard]] bool error() const noexcept { return (raw & 0x10) != 0; }
};

/// The text of an AL status code (AKD2G table, seed 003; ETG.1000.6), e.g.
/// 0x001D "Invalid output configuration SM2 (Rx)"; "unknown AL status
/// code" for codes outside the table.
[[nodiscard]] ECMXF_EXPORT std::string_view alStatusText(std::uint16_t code) noexcept;

/// The text of an SDO abort code (the ETG table of manual ver. 050 under
/// ECM_CMD_ECAT_SDO_ABORTCODE_GET), e.g. 0x06020000 "Object not
/// existing"; "unknown abort code" for codes outside the table.
[[nodiscard]] ECMXF_EXPORT std::string_view sdoAbortText(std::uint32_t code) noexcept;

/// An SDO transfer the slave (or the chip on its behalf) aborted.
class ECMXF_EXPORT SdoError : public Error
{
public:
	SdoError(const std::string &message, int errnoValue, std::uint32_t abortCode,
		 std::optional<std::uint8_t> errorStatus = std::nullopt);
	SdoError(const SdoError &) = default;
	SdoError &operator=(const SdoError &) = default;
	~SdoError() override;
	[[noreturn]] void rethrowWithPrefix(std::string_view prefix) const override;
	/// The CoE abort code (ECAT_SDO_ABORTCODE_GET), 0 when the chip gave none.
	[[nodiscard]] std::uint32_t abortCode() const noexcept { return abortCode_; }

private:
	std::uint32_t abortCode_;
};

/// A state change that a slave refused or did not complete.
class ECMXF_EXPORT AlStatusError : public Error
{
public:
	AlStatusError(const std::string &message, int errnoValue, std::uint8_t slave, State requested,
		      State reached, std::uint16_t alStatusCode,
		      std::optional<std::uint8_t> errorStatus = std::nullopt);
	AlStatusError(const AlStatusError &) = default;
	AlStatusError &operator=(const AlStatusError &) = default;
	~AlStatusError() override;
	[[noreturn]] void rethrowWithPrefix(std::string_view prefix) const override;
	/// Bus position of the (first) slave that failed.
	[[nodiscard]] std::uint8_t slave() const noexcept { return slave_; }
	[[nodiscard]] State requested() const noexcept { return requested_; }
	/// The state the slave is in after the attempt.
	[[nodiscard]] State reached() const noexcept { return reached_; }
	/// Its AL status code (register 0x0134), 0 when it reported none.
	[[nodiscard]] std::uint16_t alStatusCode() const noexcept { return alStatusCode_; }

private:
	std::uint8_t slave_;
	State requested_;
	State reached_;
	std::uint16_t alStatusCode_;
};

/// Distributed clocks of ECAT_INIT_OP and ECAT_DCSYNC.
struct DcConfig {
	/// SYNC0 cycle in ns; also the bus cycle. 0: no DC (the chip runs
	/// the bus free at 1 ms).
	std::uint32_t sync0Ns = 1'000'000;
	std::uint32_t sync1Ns = 0;  ///< SYNC1 cycle in ns
	std::int32_t shiftNs = 0;   ///< shift time in ns (data offset 0x0C)
	/// AssignActivate (ESI "AssignActivate"; register 0x0980/0x0981):
	/// 0x0300 = cyclic unit + SYNC0; 0 disables DC on the slaves. The chip
	/// applies it only to slaves that have DC.
	std::uint16_t assignActivate = 0x0300;
};

/// ECAT_INIT_OP parameters.
struct InitConfig {
	DcConfig dc;
	/// Command parameter 48: "special slave" handling.
	bool specialSlave = false;
	/// Header 0x08 bit 11: use LRW (firmware 0x22 and later; the chip
	/// still falls back to LRD/LWR when a slave lacks LRW).
	bool lrw = true;
	/// Header 0x08 bit 12: bus shift mode (master clock is the reference)
	/// instead of master shift mode (first slave's clock).
	bool busShift = false;
	/// Time allowed for the scan; zero: the command table's 10 s.
	std::chrono::milliseconds timeout{ 0 };
};

/// ECAT_SLV_INFO_GET information codes (command data 0).
enum class SlaveInfoCode : std::uint8_t {
	Vendor = 0,
	Product = 1,
	Revision = 2,
	Name = 3,
	StationAddress = 4,
	Alias = 5,
	State = 6,
	AlStatusCode = 7,
	OutputBytes = 8,
	InputBytes = 9,
	/// Codes 10..13: the slave's distributed clock; named in NEXTW's
	/// EcmDriver.h and referred to by manual ver. 050, value formats as
	/// Documentation/commands-bus.rst decides (see SlaveDc).
	HasDc = 10,
	DcCycle = 11,
	DcShift = 12,
	DcActive = 13,
};

/// ECAT_SLV_INFO_GET codes 10..13: a slave's distributed clock
/// (Documentation/commands-bus.rst, "Slave information"). Firmware of
/// manual ver. 038 may refuse these codes (a command error).
struct SlaveDc {
	bool hasDc = false;       ///< code 10 (1 byte): the slave's ESC supports DC
	std::int32_t cycleNs = 0; ///< code 11 (4 bytes): SYNC0 cycle time in ns; 0 when the slave takes no part in DC
	std::int32_t shiftNs = 0; ///< code 12 (4 bytes, signed): SYNC0 shift time in ns
	bool active = false;      ///< code 13 (1 byte): SYNC0 is active on the slave
};

/// What ECAT_SLV_INFO_GET codes 0..9 tell about one slave (the DC codes
/// 10..13: SlaveDc, Bus::slaveDc()).
struct SlaveInfo {
	std::uint8_t position = 0;       ///< bus position (0-based, as the chip numbers)
	std::uint32_t vendorId = 0;      ///< code 0
	std::uint32_t productCode = 0;   ///< code 1
	std::uint32_t revision = 0;      ///< code 2
	std::string name;                ///< code 3 (SII device name)
	std::uint16_t stationAddress = 0; ///< code 4, configured station address
	std::uint16_t alias = 0;         ///< code 5
	State state = State::None;       ///< code 6 (AL status bits 3..0, read live)
	std::uint16_t alStatusCode = 0;  ///< code 7 (register 0x0134, read live)
	std::uint16_t outputBytes = 0;   ///< code 8, RxPDO bytes in the process image
	std::uint16_t inputBytes = 0;    ///< code 9, TxPDO bytes in the process image
};

/// One mapping entry: object index, subindex and length in bits (the
/// 32-bit value index << 16 | sub << 8 | bits of 0x16xx/0x1Axx).
struct PdoMapEntry {
	std::uint16_t index = 0;
	std::uint8_t sub = 0;
	std::uint8_t bitLength = 0;
	[[nodiscard]] constexpr std::uint32_t value() const noexcept
	{
		return static_cast<std::uint32_t>(index) << 16 | static_cast<std::uint32_t>(sub) << 8 | bitLength;
	}
	[[nodiscard]] static constexpr PdoMapEntry fromValue(std::uint32_t v) noexcept
	{
		return PdoMapEntry{ static_cast<std::uint16_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
				    static_cast<std::uint8_t>(v) };
	}
	friend constexpr bool operator==(const PdoMapEntry &, const PdoMapEntry &) = default;
};

/// One PDO (0x16xx or 0x1Axx) and its entries.
struct PdoDef {
	std::uint16_t index = 0;
	std::vector<PdoMapEntry> entries;
	friend bool operator==(const PdoDef &, const PdoDef &) = default;
};

/// The "3x8" PDO configuration of ECAT_PDO_CONFIG_SET / _GET: one
/// assignment object (0x1C12 RxPDOs, 0x1C13 TxPDOs) of a slave with at
/// most 3 PDOs of at most 8 entries each.
struct PdoConfig {
	std::uint8_t slave = 0;
	std::uint16_t assignIndex = 0x1C12;
	/// The PDOs assigned. From PDO_CONFIG_GET, at most the first 3 with
	/// at most 8 entries each; see pdoCount / entryCounts for the real
	/// numbers.
	std::vector<PdoDef> pdos;
	/// PDO_CONFIG_GET: the number of PDOs the slave has assigned (may be
	/// more than pdos.size()).
	std::uint8_t pdoCount = 0;
	/// PDO_CONFIG_GET: each PDO's real entry count (may exceed 8).
	std::array<std::uint16_t, 3> entryCounts{};
	/// True when pdos holds the complete assignment.
	[[nodiscard]] bool complete() const noexcept
	{
		if (pdoCount > 3)
			return false;
		for (std::size_t i = 0; i < pdos.size() && i < 3; i++)
			if (entryCounts[i] > 8)
				return false;
		return true;
	}
};

/// A sync manager setting (ECAT_CONFIG_SM).
struct SmConfig {
	std::uint16_t startAddress = 0;
	std::uint16_t length = 0;
	std::uint8_t control = 0;   ///< control register (0x0804)
	std::uint8_t activate = 0;  ///< activate register (0x0806)
};

/// Options of one SDO transfer.
struct SdoOptions {
	/// The slave's answer time (SDO_REQ field 0x08, µs); zero: the chip's
	/// default. The library waits this long plus 1 s for the chip.
	std::chrono::microseconds timeout{ 0 };
	/// Upload: the length field (bytes expected; 0 = as long as the
	/// object is). Ignored for downloads (the data's size is sent).
	std::uint16_t length = 0;
	/// CoE complete access. The ECM-XF's SDO_REQ has no field for it
	/// (byte 0x05 is reserved in both manuals): requesting it throws
	/// EOPNOTSUPP before anything is sent (Documentation/sdo.rst).
	bool completeAccess = false;
};

namespace detail {
/// Device::sdoRead<T>(): the object's size is not sizeof(T) (EPROTO).
[[noreturn]] ECMXF_EXPORT void throwSdoSizeMismatch(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
						    std::size_t got, std::size_t want);
} // namespace detail

} // namespace ecmxf
