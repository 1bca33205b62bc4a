// SPDX-License-Identifier: MIT
/**
 * @file board_views.hpp
 * @brief The ECM-SK's typed commands, grouped in view classes over a
 *        SlotLink as the ECM-XF's are over a Device: states, setup, SDO,
 *        drives, I/O and the cyclic path.
 *
 * Get them from a Board (board.states(), board.sdo(), ...) or construct
 * them from a SlotLink&; they are references, cheap to copy. Acyclic calls
 * block and throw ecmxf::Error (Documentation/ecm-sk.rst, "The library");
 * BoardCyclic allocates nothing and never throws. Positions are the
 * frame's slot numbers (1-based).
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/sk/slot_link.hpp>
#include <ecmxf/sk/types_sk.hpp>

namespace ecmxf::sk {

/// The EtherCAT state of the board: GET_STATUS, SET_STATE, SW_RESET.
class ECMXF_EXPORT BoardStates
{
public:
	explicit BoardStates(SlotLink &link) noexcept : link_(&link) {}
	/// One GET_STATUS exchange; the board's slot 0.
	BoardStatus status();
	/// The state of the last response (no exchange).
	[[nodiscard]] ecmxf::State state() const noexcept { return link_->state(); }
	/// SET_STATE, then GET_STATUS until Current State is @p s. Throws
	/// ETIMEDOUT naming the state the board stayed in.
	void set(ecmxf::State s, std::chrono::milliseconds timeout = std::chrono::seconds(2));
	/// SW_RESET: the board restarts in INIT.
	void reset();

private:
	SlotLink *link_;
};

/// The bring-up settings: SET_AXIS, SET_DC, SET_EX.
class ECMXF_EXPORT BoardSetup
{
public:
	explicit BoardSetup(SlotLink &link) noexcept : link_(&link) {}
	/// SET_AXIS for every group that @p types reaches; returns the slaves
	/// detected (0 in INIT). Throws EPERM when the board refuses types,
	/// naming the slaves whose type is not theirs.
	unsigned setAxes(std::span<const SlaveType> types);
	/// The slaves detected (SET_AXIS of group 0 with no types: in PRE-OP).
	unsigned slaveCount();
	/// In PRE-OP: finds each slave's type by SET_AXIS itself (each is tried
	/// as Drive, STEP, HSP, IO in turn), leaves the types set and returns
	/// them (one per slave detected).
	std::vector<SlaveType> detectAxes();
	/// SET_DC: 250 * 2^n us. EINVAL for other values.
	void setCycleTime(std::uint32_t microseconds);
	/// SET_EX (effective from the next power-on of the board).
	void setExtensions(std::uint32_t bits);

private:
	SlotLink *link_;
};

/// SDO_RD / SDO_WR through the SDO slot (at most 4 bytes).
class ECMXF_EXPORT BoardSdo
{
public:
	explicit BoardSdo(SlotLink &link) noexcept : link_(&link) {}
	/// SDO_RD; @p size receives the object's size. Throws SdoError
	/// (EREMOTEIO) with the abort code.
	std::uint32_t read(unsigned slave, std::uint16_t index, std::uint8_t subindex, unsigned *size = nullptr);
	/// SDO_WR of @p size (1, 2 or 4) bytes.
	void write(unsigned slave, std::uint16_t index, std::uint8_t subindex, std::uint32_t value, unsigned size);
	/// Typed SDO: the object's size must be sizeof(T) (EMSGSIZE otherwise).
	template <typename T> T read(unsigned slave, std::uint16_t index, std::uint8_t subindex)
	{
		static_assert(std::is_integral_v<T> && sizeof(T) <= 4);
		unsigned size = 0;
		const std::uint32_t v = read(slave, index, subindex, &size);
		checkSize(index, subindex, size, sizeof(T));
		return static_cast<T>(v);
	}
	template <typename T> void write(unsigned slave, std::uint16_t index, std::uint8_t subindex, T value)
	{
		static_assert(std::is_integral_v<T> && sizeof(T) <= 4);
		write(slave, index, subindex, static_cast<std::uint32_t>(static_cast<std::make_unsigned_t<T>>(value)),
		      sizeof(T));
	}

private:
	static void checkSize(std::uint16_t index, std::uint8_t sub, unsigned size, std::size_t want);
	SlotLink *link_;
};

/// The drives: DRIVE_MODE, SV_ON/SV_OFF, ALM_CLR, homing, their slots.
class ECMXF_EXPORT BoardDrives
{
public:
	explicit BoardDrives(SlotLink &link) noexcept : link_(&link) {}
	/// DRIVE_MODE for slave @p slave.
	void setMode(unsigned slave, Mode mode, Sync sync = Sync::DcSync);
	/// SV_ON / SV_OFF / ALM_CLR: the board answers at once; the drive
	/// follows over some cycles (see waitEnabled()).
	void servoOn(unsigned slave);
	void servoOff(unsigned slave);
	void alarmClear(unsigned slave);
	/// GET_STATUS until slave @p slave is in Operation enabled (the
	/// CiA-402 decoder of <ecmxf/model/cia402.hpp>).
	void waitEnabled(unsigned slave, std::chrono::milliseconds timeout = std::chrono::seconds(2));
	/// Brings slave @p slave's drive to a halt in the board's terms (the
	/// ECM-SK has no quick-stop command and owns the controlword): SV_OFF,
	/// then GET_STATUS until the power stage is off (neither OPERATION
	/// ENABLED, QUICK STOP ACTIVE nor SWITCHED ON) and returns its slot;
	/// ETIMEDOUT naming the statusword after @p timeout. What
	/// `ecmxf-util cia402` does on SIGINT/SIGTERM/SIGHUP.
	AxisStatus halt(unsigned slave, std::chrono::milliseconds timeout = std::chrono::seconds(1));
	/// Homing: SDO_WR 0x6060 = 6 and 0x6098 = @p method, GO_HOME, then
	/// GET_STATUS until statusword bits 10 and 12 (EIO on bit 13).
	void home(unsigned slave, std::int8_t method, std::chrono::milliseconds timeout = std::chrono::seconds(30));
	/// ABORT_HOME (all slaves).
	void abortHome(unsigned slave);
	/// Slave @p slave's slot of the last response.
	[[nodiscard]] AxisStatus axis(unsigned slave) const;
	/// A 2-channel HSP's slot of the last response. Throws EINVAL with
	/// 12-byte slots or a slave out of range.
	[[nodiscard]] Hsp2Status hsp2(unsigned slave) const;

private:
	SlotLink *link_;
};

/// IO_RD / IO_WR (IO slaves, OP) and LIO_RD / LIO_WR (the ECM IC's own
/// inputs/outputs 0..5).
class ECMXF_EXPORT BoardIo
{
public:
	explicit BoardIo(SlotLink &link) noexcept : link_(&link) {}
	std::uint32_t read(unsigned slave);
	void write(unsigned slave, std::uint32_t outputs);
	std::uint32_t readLocal();
	void writeLocal(std::uint32_t outputs);

private:
	SlotLink *link_;
};

/// The cyclic path: CSP/CSV/CST targets into the FIFO, one exchange per
/// cycle. Allocation-free, never throws.
class ECMXF_EXPORT BoardCyclic
{
public:
	explicit BoardCyclic(SlotLink &link) noexcept : link_(&link) {}
	/// Queues a CSP/CSV/CST command for slave @p slave into the next
	/// exchange. False (nothing staged) for a slave out of range, a slave
	/// already staged, or when the FIFO's remaining space (as last
	/// reported) has no room for it: back-pressure the caller sees.
	bool stage(unsigned slave, Mode mode, std::int32_t target, std::uint32_t output = 0) noexcept;
	/// Like stage(), for both channels of a 2-channel HSP (16-byte slots;
	/// CSP or CSV): one command, one FIFO entry. False also with 12-byte
	/// slots or CST.
	bool stage2(unsigned slave, Mode mode, std::int32_t target1, std::int32_t target2,
		    std::uint16_t output1 = 0, std::uint16_t output2 = 0) noexcept;
	/// Waits for Busy to fall, exchanges one frame with the staged
	/// commands, and reports the FIFO.
	CycleResult cycle() noexcept;
	/// The message of the last CycleStatus::Link (empty otherwise).
	[[nodiscard]] const std::string &lastError() const noexcept;

private:
	SlotLink *link_;
};

} // namespace ecmxf::sk
