// SPDX-License-Identifier: MIT
/**
 * @file board.hpp
 * @brief The ECM-SK starter kit: typed commands of its slot protocol
 *        (bring-up, SDO, servo on/off, alarm clear, IO, homing) and an
 *        allocation-free cyclic path with FIFO back-pressure.
 *
 * A Board runs the slot protocol core (lib/core/ecmsk-*.c) over a
 * ByteChannel: the in-process simulator ("sk-sim:"), an
 * `ecmxf-sim --board ecm-sk --socket` server ("sk-unix:") or spidev with
 * the Busy line on libgpiod ("sk-spidev:"). Errors are ecmxf::Error (SDO
 * aborts: ecmxf::SdoError with the abort code and its text), with the
 * command's manual name and the board's state in the message. The CiA-402
 * vocabulary (statusword bits) is that of include/ecmxf/cia402.
 * Documentation/ecm-sk.rst.
 *
 * Thread safety: none; one thread uses a Board at a time.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>

namespace ecmxf::sk {

class SimBoard;
class SimBoardChannel;

/// EtherCAT states as the board reports them (Current State).
enum class State : std::uint8_t { Init = 0x01, PreOp = 0x02, SafeOp = 0x04, Op = 0x08 };
/// The slave kinds of SET_AXIS.
enum class SlaveType : std::uint8_t { Drive = 0x0, Io = 0x1, Hsp = 0x2, Step = 0x3, None = 0xF };
/// DRIVE_MODE's modes of operation.
enum class Mode : std::uint8_t { Csp = 8, Csv = 9, Cst = 10 };
/// DRIVE_MODE's synchronisation.
enum class Sync : std::uint8_t { FreeRun = 0, DcSync = 1 };

[[nodiscard]] ECMXF_EXPORT std::string_view stateName(State s) noexcept;
[[nodiscard]] ECMXF_EXPORT std::string_view slaveTypeName(SlaveType t) noexcept;

/// What the host must be told about the board (it cannot ask it).
struct LinkOptions {
	unsigned slotSize = 12;	      ///< CONFIG2: 12 or 16
	std::uint32_t extensions = 0; ///< SET_EX setting in force: bit 0 command CRC, bit 1 response CRC
	std::chrono::milliseconds busyTimeout{ 100 }; ///< longest wait for Busy to fall
};

/// Slot 0 of the last response.
struct BoardStatus {
	State state = State::Init;
	std::uint8_t crcErrors = 0;	  ///< the board's counter of refused frames (Error Code)
	std::uint16_t fifoRemaining = 0; ///< in OP
	std::uint16_t fifoFull = 0;	  ///< in OP: cyclic commands dropped, FIFO full
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

/// The outcome of one cyclic exchange (Board::cycle()).
enum class CycleStatus : std::uint8_t {
	Ok,
	FifoOverflow, ///< the board dropped cyclic commands (FIFO full count rose)
	BadResponse,  ///< the response's CRC was wrong (its data is not used)
	Busy,	      ///< Busy did not fall in time: nothing was sent
	Link,	      ///< the channel failed (see Board::lastError())
};

struct CycleResult {
	CycleStatus status = CycleStatus::Ok;
	std::uint16_t fifoRemaining = 0;
	std::uint16_t fifoFull = 0;
	std::uint16_t dropped = 0; ///< rise of the FIFO full count with this response
	unsigned staged = 0;	   ///< cyclic commands this exchange carried
};

/// One ECM-SK board.
class ECMXF_EXPORT Board
{
public:
	/// Runs over @p channel with @p options. Throws ecmxf::Error (EINVAL)
	/// for a bad slot size or extension bits.
	Board(std::unique_ptr<ByteChannel> channel, LinkOptions options = {});
	/// Runs over the in-process simulated board of @p channel, which
	/// simulator() then gives.
	Board(std::unique_ptr<SimBoardChannel> channel, LinkOptions options = {});
	~Board();
	Board(const Board &) = delete;
	Board &operator=(const Board &) = delete;

	/// Opens "sk-sim:[file][?settings]", "sk-unix:PATH[?slot=&ex=]" or
	/// "sk-spidev:/dev/spidevB.C?busy=<chip>:<line>[&slot=12|16][&speed=<Hz>]
	/// [&ex=0..3]" (Documentation/ecm-sk.rst, "Device URIs"). Throws
	/// ecmxf::Error (EINVAL) naming the bad part.
	[[nodiscard]] static std::unique_ptr<Board> open(std::string_view uri);
	/// Is @p uri one of the ECM-SK forms ("sk-...:")?
	[[nodiscard]] static bool isSkUri(std::string_view uri) noexcept;

	[[nodiscard]] ByteChannel &channel() noexcept { return *channel_; }
	/// The simulated board behind an "sk-sim:" channel, else null.
	[[nodiscard]] SimBoard *simulator() noexcept;
	[[nodiscard]] unsigned slotSize() const noexcept;
	[[nodiscard]] unsigned maxSlaves() const noexcept;
	[[nodiscard]] std::size_t frameSize() const noexcept;

	// ---- acyclic commands (block; throw ecmxf::Error) ----
	/// One GET_STATUS exchange; the board's slot 0.
	BoardStatus status();
	/// The state of the last response (no exchange).
	[[nodiscard]] State state() const noexcept;
	/// SET_STATE, then GET_STATUS until Current State is @p s. Throws
	/// ETIMEDOUT naming the state the board stayed in.
	void setState(State s, std::chrono::milliseconds timeout = std::chrono::seconds(2));
	/// SET_AXIS for every group that @p types reaches; returns the slaves
	/// detected (0 in INIT). Throws EPERM when the board refuses types,
	/// naming the slaves whose type is not theirs.
	unsigned setAxes(std::span<const SlaveType> types);
	/// The slaves detected (SET_AXIS of group 0 with no types: in PRE-OP).
	unsigned slaveCount();
	/// In PRE-OP: finds each slave's type by SET_AXIS itself (the board
	/// checks types against the slaves and names those that do not
	/// match: each is tried as Drive, STEP, HSP, IO in turn), leaves the
	/// types set and returns them (one per slave detected).
	std::vector<SlaveType> detectAxes();
	/// SET_DC: 250 * 2^n us. EINVAL for other values.
	void setCycleTime(std::uint32_t microseconds);
	/// SET_EX (effective from the next power-on of the board).
	void setExtensions(std::uint32_t bits);
	/// DRIVE_MODE for slave @p slave (1-based).
	void driveMode(unsigned slave, Mode mode, Sync sync = Sync::DcSync);
	/// SDO_RD through the SDO slot; @p size receives the object's size.
	/// Throws SdoError (EREMOTEIO) with the abort code.
	std::uint32_t sdoRead(unsigned slave, std::uint16_t index, std::uint8_t subindex,
			      unsigned *size = nullptr);
	/// SDO_WR of @p size (1, 2 or 4) bytes.
	void sdoWrite(unsigned slave, std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
		      unsigned size);
	/// Typed SDO: the object's size must be sizeof(T) (EMSGSIZE otherwise).
	template <typename T> T sdoRead(unsigned slave, std::uint16_t index, std::uint8_t subindex)
	{
		static_assert(std::is_integral_v<T> && sizeof(T) <= 4);
		unsigned size = 0;
		const std::uint32_t v = sdoRead(slave, index, subindex, &size);
		checkSize(index, subindex, size, sizeof(T));
		return static_cast<T>(v);
	}
	template <typename T> void sdoWrite(unsigned slave, std::uint16_t index, std::uint8_t subindex, T value)
	{
		static_assert(std::is_integral_v<T> && sizeof(T) <= 4);
		sdoWrite(slave, index, subindex,
			 static_cast<std::uint32_t>(static_cast<std::make_unsigned_t<T>>(value)), sizeof(T));
	}
	/// SV_ON / SV_OFF / ALM_CLR: the board answers at once; the drive
	/// follows over some cycles (see waitEnabled()).
	void servoOn(unsigned slave);
	void servoOff(unsigned slave);
	void alarmClear(unsigned slave);
	/// GET_STATUS until slave @p slave is in Operation enabled.
	void waitEnabled(unsigned slave, std::chrono::milliseconds timeout = std::chrono::seconds(2));
	/// IO_RD / IO_WR (IO slaves, OP).
	std::uint32_t ioRead(unsigned slave);
	void ioWrite(unsigned slave, std::uint32_t outputs);
	/// LIO_RD / LIO_WR: the ECM IC's own inputs/outputs 0..5.
	std::uint32_t lioRead();
	void lioWrite(std::uint32_t outputs);
	/// Homing: SDO_WR 0x6060 = 6 and 0x6098 = @p method, GO_HOME, then
	/// GET_STATUS until statusword bits 10 and 12 (EIO on bit 13).
	void home(unsigned slave, std::int8_t method, std::chrono::milliseconds timeout = std::chrono::seconds(30));
	/// ABORT_HOME (all slaves).
	void abortHome(unsigned slave);
	/// SW_RESET: the board restarts in INIT.
	void reset();
	/// Slave @p slave's slot of the last response.
	[[nodiscard]] AxisStatus axis(unsigned slave) const;

	// ---- cyclic path: allocation-free, never throws ----
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
	/// A 2-channel HSP's slot of the last response. Throws EINVAL with
	/// 12-byte slots or a slave out of range.
	[[nodiscard]] Hsp2Status hsp2(unsigned slave) const;
	/// Waits for Busy to fall, exchanges one frame with the staged
	/// commands, and reports the FIFO.
	CycleResult cycle() noexcept;
	/// The message of the last CycleStatus::Link (empty otherwise).
	[[nodiscard]] const std::string &lastError() const noexcept { return lastError_; }

private:
	Board(std::pair<std::unique_ptr<ByteChannel>, SimBoard *> channel, LinkOptions options);
	struct Link;
	void xfer();
	void transact();
	void require(std::uint16_t cmd, const char *what) const;
	void checkSlave(unsigned slave, const char *cmd) const;
	void slaveCommand(unsigned slave, std::uint8_t cmd, std::uint32_t target = 0, std::uint32_t value = 0);
	[[noreturn]] void refused(const std::string &cmd, const std::string &why) const;
	static void checkSize(std::uint16_t index, std::uint8_t sub, unsigned size, std::size_t want);

	std::unique_ptr<ByteChannel> channel_;
	std::unique_ptr<Link> link_;
	std::string lastError_;
	SimBoard *sim_ = nullptr; ///< the simulated board behind channel_, if any
};

} // namespace ecmxf::sk
