// SPDX-License-Identifier: MIT
/**
 * @file types_sk.hpp
 * @brief Value types of the ECM-SK (slave types, modes, the slots of a
 *        response, the cyclic result); the EtherCAT states are the
 *        ECM-XF's ecmxf::State. Documentation/ecm-sk.rst.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_bus.hpp>

namespace ecmxf::sk {

/// EtherCAT states as the board reports them (Current State): the
/// ECM-XF's ecmxf::State (the codes agree: INIT 0x01, PRE-OP 0x02,
/// SAFE-OP 0x04, OP 0x08). The old name stays one release.
using State [[deprecated("use ecmxf::State (<ecmxf/model/types_bus.hpp>)")]] = ecmxf::State;
/// "INIT", "PRE-OP", "SAFE-OP", "OP": ecmxf::stateName() (it returns
/// std::string; sk::stateName() returned std::string_view).
using ecmxf::stateName;
/// The slave kinds of SET_AXIS.
enum class SlaveType : std::uint8_t { Drive = 0x0, Io = 0x1, Hsp = 0x2, Step = 0x3, None = 0xF };
/// DRIVE_MODE's modes of operation.
enum class Mode : std::uint8_t { Csp = 8, Csv = 9, Cst = 10 };
/// DRIVE_MODE's synchronisation.
enum class Sync : std::uint8_t { FreeRun = 0, DcSync = 1 };

[[nodiscard]] ECMXF_EXPORT std::string_view slaveTypeName(SlaveType t) noexcept;

/// What the host must be told about the board (it cannot ask it).
struct LinkOptions {
	unsigned slotSize = 12;	      ///< CONFIG2: 12 or 16
	std::uint32_t extensions = 0; ///< SET_EX setting in force: bit 0 command CRC, bit 1 response CRC
	std::chrono::milliseconds busyTimeout{ 100 }; ///< longest wait for Busy to fall
};

/// Slot 0 of the last response.
struct BoardStatus {
	ecmxf::State state = ecmxf::State::Init;
	std::uint8_t crcErrors = 0;	  ///< the board's counter of refused frames (Error Code)
	std::uint16_t fifoRemaining = 0; ///< in OP
	std::uint16_t fifoFull = 0;	  ///< in OP: cyclic commands dropped (FIFO full; the simulator: or abandoned)
};

/// A slave slot of the last response.
struct AxisStatus {
	std::uint8_t cmd = 0;		///< the command answered
	std::uint8_t index = 0;		///< its Command Index
	std::uint16_t statusword = 0;	///< 0x6041
	std::int32_t position = 0;	///< 0x6064 (IO_RD: the inputs)
	std::int16_t torque = 0;	///< 0x6077 (HSP: input status)
	std::uint16_t errorCode = 0;	///< 0x603F
};

/// A 2-channel HSP's slot of the last response (16-byte slots, tables
/// 2.16 and 2.18).
struct Hsp2Status {
	std::uint8_t cmd = 0;
	std::uint8_t index = 0;
	std::uint16_t statusword = 0; ///< channel 1's
	std::int32_t position1 = 0;
	std::uint16_t inputs1 = 0;
	std::int32_t position2 = 0;
	std::uint16_t inputs2 = 0;
};

/// The outcome of one cyclic exchange (BoardCyclic::cycle()).
enum class CycleStatus : std::uint8_t {
	Ok,
	FifoOverflow, ///< the board dropped cyclic commands (FIFO full count rose: full, or abandoned after 100 cycles)
	BadResponse,  ///< the response's CRC was wrong (its data is not used)
	Busy,	      ///< Busy did not fall in time: nothing was sent
	Link,	      ///< the channel failed (see BoardCyclic::lastError())
};

struct CycleResult {
	CycleStatus status = CycleStatus::Ok;
	std::uint16_t fifoRemaining = 0;
	std::uint16_t fifoFull = 0;
	std::uint16_t dropped = 0; ///< rise of the FIFO full count with this response
	unsigned staged = 0;	   ///< cyclic commands this exchange carried
};

} // namespace ecmxf::sk
