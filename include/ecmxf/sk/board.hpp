// SPDX-License-Identifier: MIT
/**
 * @file board.hpp
 * @brief The ECM-SK starter kit: a SlotLink and the view classes of its
 *        typed commands (bring-up, SDO, servo on/off, alarm clear, IO,
 *        homing, an allocation-free cyclic path with FIFO back-pressure).
 *
 * A Board runs the slot protocol (SlotLink, <ecmxf/sk/slot_link.hpp>)
 * over a ByteChannel: the in-process simulator ("sk-sim:"), an
 * `ecmxf-sim --board ecm-sk --socket` server ("sk-unix:") or spidev with
 * the Busy line on libgpiod ("sk-spidev:"). Its commands are grouped in
 * views as the ECM-XF Device's are: board.states(), board.setup(),
 * board.sdo(), board.drives(), board.io(), board.cyclic()
 * (<ecmxf/sk/board_views.hpp>). Errors are ecmxf::Error (SDO aborts:
 * ecmxf::SdoError with the abort code and its text), with the command's
 * manual name and the board's state in the message. The EtherCAT states
 * are ecmxf::State, the CiA-402 vocabulary that of include/ecmxf/cia402.
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
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/sk/board_views.hpp>
#include <ecmxf/sk/slot_link.hpp>
#include <ecmxf/sk/types_sk.hpp>

/// The flat members Board had before its views: kept one release.
#define ECMXF_SK_FLAT(view) [[deprecated("use Board::" view)]]

namespace ecmxf::sk {

/// One ECM-SK board.
class ECMXF_EXPORT Board
{
public:
	/// Runs over @p channel with @p options. Throws ecmxf::Error (EINVAL)
	/// for a bad slot size or extension bits.
	explicit Board(std::unique_ptr<ByteChannel> channel, LinkOptions options = {});
	/// Runs over the in-process simulated board of @p channel, which
	/// simulator() then gives.
	explicit Board(std::unique_ptr<SimBoardChannel> channel, LinkOptions options = {});
	~Board();
	Board(const Board &) = delete;
	Board &operator=(const Board &) = delete;

	/// Opens "sk-sim:[file][?settings]", "sk-unix:PATH[?slot=&ex=]" or
	/// "sk-spidev:/dev/spidevB.C?busy=<chip>:<line>[&slot=12|16][&speed=<Hz>]
	/// [&ex=0..3]", parsed by ecmxf::parseDeviceUri()
	/// (<ecmxf/device_uri.hpp>); each may add trace=<file>, which starts
	/// startTrace(<file>). Throws ecmxf::Error (EINVAL) naming the bad
	/// part, or for an ECM-XF URI; a trace file that cannot be created
	/// throws as startTrace() does.
	[[nodiscard]] static std::unique_ptr<Board> open(std::string_view uri);
	/// Is @p uri one of the ECM-SK forms ("sk-...:")?
	[[nodiscard]] static bool isSkUri(std::string_view uri) noexcept;

	/// The link the views run on.
	[[nodiscard]] SlotLink &link() noexcept { return link_; }
	[[nodiscard]] ByteChannel &channel() noexcept { return link_.channel(); }
	/// The simulated board behind an "sk-sim:" channel, else null.
	[[nodiscard]] SimBoard *simulator() noexcept { return link_.simulator(); }
	[[nodiscard]] unsigned slotSize() const noexcept { return link_.slotSize(); }
	[[nodiscard]] unsigned maxSlaves() const noexcept { return link_.maxSlaves(); }
	[[nodiscard]] std::size_t frameSize() const noexcept { return link_.frameSize(); }
	/// The state of the last response (no exchange).
	[[nodiscard]] ecmxf::State state() const noexcept { return link_.state(); }

	// ---- packet trace (SlotLink::startTrace(), Documentation/trace.rst) ----
	/// Records every frame exchanged from now on to @p path (text, or
	/// pcapng for a name ending in ".pcapng"); the URI option
	/// trace=<file> starts it in open(). Throws ecmxf::Error with the
	/// path and the system's reason.
	void startTrace(std::string_view path) { link_.startTrace(path); }
	/// Closes the trace; throws ecmxf::Error when any write failed
	/// ("writing the trace file \"/dev/full\" failed: No space left on
	/// device"). No-op without a trace.
	void stopTrace() { link_.stopTrace(); }
	/// Is a trace being recorded?
	[[nodiscard]] bool tracing() const noexcept { return link_.tracing(); }

	// ---- the views ----
	[[nodiscard]] BoardStates states() noexcept { return BoardStates(link_); }
	[[nodiscard]] BoardSetup setup() noexcept { return BoardSetup(link_); }
	[[nodiscard]] BoardSdo sdo() noexcept { return BoardSdo(link_); }
	[[nodiscard]] BoardDrives drives() noexcept { return BoardDrives(link_); }
	[[nodiscard]] BoardIo io() noexcept { return BoardIo(link_); }
	[[nodiscard]] BoardCyclic cyclic() noexcept { return BoardCyclic(link_); }

	// ---- the flat members of before: deprecated forwarders, one release ----
	ECMXF_SK_FLAT("states().status()") BoardStatus status() { return states().status(); }
	ECMXF_SK_FLAT("states().set()")
	void setState(ecmxf::State s, std::chrono::milliseconds timeout = std::chrono::seconds(2))
	{
		states().set(s, timeout);
	}
	ECMXF_SK_FLAT("states().reset()") void reset() { states().reset(); }
	ECMXF_SK_FLAT("setup().setAxes()") unsigned setAxes(std::span<const SlaveType> types)
	{
		return setup().setAxes(types);
	}
	ECMXF_SK_FLAT("setup().slaveCount()") unsigned slaveCount() { return setup().slaveCount(); }
	ECMXF_SK_FLAT("setup().detectAxes()") std::vector<SlaveType> detectAxes() { return setup().detectAxes(); }
	ECMXF_SK_FLAT("setup().setCycleTime()") void setCycleTime(std::uint32_t us) { setup().setCycleTime(us); }
	ECMXF_SK_FLAT("setup().setExtensions()") void setExtensions(std::uint32_t bits)
	{
		setup().setExtensions(bits);
	}
	ECMXF_SK_FLAT("drives().setMode()") void driveMode(unsigned slave, Mode mode, Sync sync = Sync::DcSync)
	{
		drives().setMode(slave, mode, sync);
	}
	ECMXF_SK_FLAT("sdo().read()")
	std::uint32_t sdoRead(unsigned slave, std::uint16_t index, std::uint8_t subindex, unsigned *size = nullptr)
	{
		return sdo().read(slave, index, subindex, size);
	}
	ECMXF_SK_FLAT("sdo().write()")
	void sdoWrite(unsigned slave, std::uint16_t index, std::uint8_t subindex, std::uint32_t value, unsigned size)
	{
		sdo().write(slave, index, subindex, value, size);
	}
	template <typename T>
	ECMXF_SK_FLAT("sdo().read<T>()") T sdoRead(unsigned slave, std::uint16_t index, std::uint8_t subindex)
	{
		return sdo().read<T>(slave, index, subindex);
	}
	template <typename T>
	ECMXF_SK_FLAT("sdo().write<T>()")
	void sdoWrite(unsigned slave, std::uint16_t index, std::uint8_t subindex, T value)
	{
		sdo().write<T>(slave, index, subindex, value);
	}
	ECMXF_SK_FLAT("drives().servoOn()") void servoOn(unsigned slave) { drives().servoOn(slave); }
	ECMXF_SK_FLAT("drives().servoOff()") void servoOff(unsigned slave) { drives().servoOff(slave); }
	ECMXF_SK_FLAT("drives().alarmClear()") void alarmClear(unsigned slave) { drives().alarmClear(slave); }
	ECMXF_SK_FLAT("drives().waitEnabled()")
	void waitEnabled(unsigned slave, std::chrono::milliseconds timeout = std::chrono::seconds(2))
	{
		drives().waitEnabled(slave, timeout);
	}
	ECMXF_SK_FLAT("drives().home()")
	void home(unsigned slave, std::int8_t method, std::chrono::milliseconds timeout = std::chrono::seconds(30))
	{
		drives().home(slave, method, timeout);
	}
	ECMXF_SK_FLAT("drives().abortHome()") void abortHome(unsigned slave) { drives().abortHome(slave); }
	ECMXF_SK_FLAT("drives().axis()") AxisStatus axis(unsigned slave) const
	{
		return BoardDrives(const_cast<SlotLink &>(link_)).axis(slave);
	}
	ECMXF_SK_FLAT("drives().hsp2()") Hsp2Status hsp2(unsigned slave) const
	{
		return BoardDrives(const_cast<SlotLink &>(link_)).hsp2(slave);
	}
	ECMXF_SK_FLAT("io().read()") std::uint32_t ioRead(unsigned slave) { return io().read(slave); }
	ECMXF_SK_FLAT("io().write()") void ioWrite(unsigned slave, std::uint32_t outputs) { io().write(slave, outputs); }
	ECMXF_SK_FLAT("io().readLocal()") std::uint32_t lioRead() { return io().readLocal(); }
	ECMXF_SK_FLAT("io().writeLocal()") void lioWrite(std::uint32_t outputs) { io().writeLocal(outputs); }
	ECMXF_SK_FLAT("cyclic().stage()")
	bool stage(unsigned slave, Mode mode, std::int32_t target, std::uint32_t output = 0) noexcept
	{
		return cyclic().stage(slave, mode, target, output);
	}
	ECMXF_SK_FLAT("cyclic().stage2()")
	bool stage2(unsigned slave, Mode mode, std::int32_t target1, std::int32_t target2, std::uint16_t output1 = 0,
		    std::uint16_t output2 = 0) noexcept
	{
		return cyclic().stage2(slave, mode, target1, target2, output1, output2);
	}
	ECMXF_SK_FLAT("cyclic().cycle()") CycleResult cycle() noexcept { return cyclic().cycle(); }
	ECMXF_SK_FLAT("cyclic().lastError()") const std::string &lastError() const noexcept
	{
		return BoardCyclic(const_cast<SlotLink &>(link_)).lastError();
	}

private:
	SlotLink link_;
};

/// The board to OP the way ecmxf-util brings it there: from INIT to
/// PRE-OP, the axes detected (SET_AXIS) and every drive set to CSP
/// (DRIVE_MODE), then OP. Nothing when the board is in OP already.
/// Documentation/ecm-sk.rst.
ECMXF_EXPORT void bringUpToOp(Board &board);

} // namespace ecmxf::sk

#undef ECMXF_SK_FLAT
