// SPDX-License-Identifier: MIT
/**
 * @file verbs.hpp
 * @brief The verbs both SPI masters have (ECM-XF and ECM-SK), behind one
 *        small interface: info, slave list, states, SDO upload/download,
 *        drive enable/disable/alarm clear, slave I/O, reset.
 *
 * MasterVerbs::open() opens the master a device URI names
 * (<ecmxf/device_uri.hpp>): an ECM-XF Device ("sim:", "unix:",
 * "spidev:", "/dev/ecmxfN") or an ECM-SK sk::Board ("sk-sim:",
 * "sk-unix:", "sk-spidev:"); verbsOf() adapts one you have. Each verb
 * does the thing, or throws ecmxf::Error with errno ENOTSUP and the
 * reason ("not on the ECM-SK: ...", "not on the ECM-XF: ..."). Slave
 * positions count from 0 on both masters (the ECM-SK's frame slot is the
 * position + 1). ecmxf-util runs its shared commands through it.
 * Documentation/library.rst, "One interface for both masters".
 *
 * Thread safety: that of the master behind it (none).
 */
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/model/types_cia402.hpp>

namespace ecmxf {

class Device;
namespace sk {
class Board;
}

/// Which master a MasterVerbs drives.
enum class MasterKind : std::uint8_t { EcmXf, EcmSk };

/// "ECM-XF", "ECM-SK".
[[nodiscard]] ECMXF_EXPORT std::string_view masterKindName(MasterKind k) noexcept;

/// One slave as the slave list shows it.
struct SlaveSummary {
	unsigned position = 0;	 ///< from 0
	State state = State::None; ///< the slave's (ECM-XF) or the bus's (ECM-SK: no per-slave states)
	std::string kind;	 ///< what the master calls it (ECM-SK: its SET_AXIS type); empty: unknown
	std::optional<std::uint32_t> vendorId;	  ///< 0x1018:01, when it could be read
	std::optional<std::uint32_t> productCode; ///< 0x1018:02
};

/// The verbs both masters have.
class ECMXF_EXPORT MasterVerbs
{
public:
	virtual ~MasterVerbs();

	/// Opens the master @p uri names. Throws ecmxf::Error (EINVAL) for a
	/// bad URI, as Device::open() and sk::Board::open() do.
	[[nodiscard]] static std::unique_ptr<MasterVerbs> open(std::string_view uri);

	[[nodiscard]] virtual MasterKind kind() const noexcept = 0;
	/// The Device behind an ECM-XF, else null.
	[[nodiscard]] virtual Device *device() noexcept { return nullptr; }
	/// The Board behind an ECM-SK, else null.
	[[nodiscard]] virtual sk::Board *board() noexcept { return nullptr; }

	/// The bus's EtherCAT state (ECM-XF: STATE_GET of every slave;
	/// ECM-SK: Current State).
	[[nodiscard]] virtual State state() = 0;
	/// Requests @p s for the whole bus and waits for it.
	virtual void requestState(State s) = 0;
	/// The slaves on the bus (ECM-XF: after a scan; ECM-SK: in PRE-OP,
	/// the count SET_AXIS answers).
	[[nodiscard]] virtual unsigned slaveCount() = 0;
	/// The slave list (identity by SDO where the slave answers).
	[[nodiscard]] virtual std::vector<SlaveSummary> slaves() = 0;

	/// SDO upload of @p index:@p sub from slave @p position (ECM-SK: at
	/// most 4 bytes, the SDO slot's).
	[[nodiscard]] virtual std::vector<std::uint8_t> upload(unsigned position, std::uint16_t index,
								std::uint8_t sub) = 0;
	/// SDO download (ECM-SK: 1, 2 or 4 bytes).
	virtual void download(unsigned position, std::uint16_t index, std::uint8_t sub,
			      std::span<const std::uint8_t> data) = 0;

	/// CiA-402: the drive at @p position to Operation enabled, to Switch
	/// on disabled, or out of a fault; returns the statusword after.
	/// ECM-XF: the host-side state machine over SDO (0x6040/0x6041);
	/// ECM-SK: SV_ON (and the wait), SV_OFF, ALM_CLR, in OP.
	virtual std::uint16_t driveEnable(unsigned position) = 0;
	virtual std::uint16_t driveDisable(unsigned position) = 0;
	virtual std::uint16_t driveAlarmClear(unsigned position) = 0;

	/// The first 4 input / output bytes of an I/O slave.
	[[nodiscard]] virtual std::uint32_t ioRead(unsigned position) = 0;
	virtual void ioWrite(unsigned position, std::uint32_t outputs) = 0;

	/// Restarts the master (ECM-XF: WARM_RESET, power-on settings;
	/// ECM-SK: SW_RESET, back in INIT).
	virtual void reset() = 0;
};

/// The verbs of @p device / @p board (not owned: it must outlive them).
[[nodiscard]] ECMXF_EXPORT std::unique_ptr<MasterVerbs> verbsOf(Device &device);
[[nodiscard]] ECMXF_EXPORT std::unique_ptr<MasterVerbs> verbsOf(sk::Board &board);

/// The host-side CiA-402 state machine (Cia402Stepper) over SDO
/// (0x6040/0x6041) of the ECM-XF drive at @p position, to @p target; with
/// @p faultResetOnly, only out of a fault (else nothing is written). The
/// statusword after. What MasterVerbs::driveEnable() and the others do on
/// an ECM-XF; `ecmxf-util cia402` uses it for every target.
ECMXF_EXPORT std::uint16_t cia402WalkBySdo(Device &device, std::uint8_t position, Cia402State target,
					   bool faultResetOnly = false);

/// Has no one initialised the bus behind the ECM-XF @p device yet (no
/// slaves, EtherCAT state 0 in the last header)?
[[nodiscard]] ECMXF_EXPORT bool busDown(Device &device);
/// When busDown(): ECAT_INIT_OP, then with @p preOp all slaves to PRE-OP
/// (when there are any); nothing when the bus is up. The slave count after.
/// The rule ecmxf-util follows before a bus command, and the Python
/// binding's open().
ECMXF_EXPORT unsigned ensureBusUp(Device &device, bool preOp);

/// The ECM-SK frame slot of the slave at @p position (from 0, as the
/// verbs count): position + 1; Error(EINVAL) outside the board's slots.
/// The verbs' rule, and the Python binding's for the board's own calls.
[[nodiscard]] ECMXF_EXPORT unsigned boardSlot(const sk::Board &board, unsigned position);

/// Error(ENOTSUP): "not on the <master>: <why>".
[[noreturn]] ECMXF_EXPORT void throwNotOn(MasterKind master, std::string_view why);

} // namespace ecmxf
