// SPDX-License-Identifier: MIT
/**
 * @file sim_slaves.hpp
 * @brief Test and demo hooks of the simulator's slave models (EST-584
 *        stepper, AKD2G-like servo, digital I/O), and their identities.
 *
 * The models are created from network files (Network::makeSlave()); reach
 * their hooks with a cross-cast from the Slave:
 * @code
 *   auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&net.at(0));
 *   auto *io = dynamic_cast<ecmxf::sim::DioModel *>(&net.at(2));
 * @endcode
 * Behaviour and choices are described in Documentation/sim-slaves.rst.
 */
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <ecmxf/export.hpp>

namespace ecmxf::sim {

/// Identities (SII words 0x08..0x0F, object 0x1018) of the simulated
/// models. They are the simulator's own numbers, not the manufacturers'.
namespace model {
inline constexpr std::uint32_t kVendorId = 0x00000E5C;
inline constexpr std::uint32_t kEst584Product = 0x00000584;
inline constexpr std::uint32_t kEst584Revision = 0x00010000;
inline constexpr std::uint32_t kServoProduct = 0x0000A2D2;
inline constexpr std::uint32_t kServoRevision = 0x00020000;
inline constexpr std::uint32_t kDioProduct = 0x00001088;
inline constexpr std::uint32_t kDioRevision = 0x00010000;
} // namespace model

/// Hooks of a CiA-402 drive model (EST-584 and servo).
class ECMXF_EXPORT Cia402Model
{
public:
	virtual ~Cia402Model() = default;
	/// Controlword (0x6040) and statusword (0x6041) as the drive sees them.
	[[nodiscard]] virtual std::uint16_t controlword() const = 0;
	[[nodiscard]] virtual std::uint16_t statusword() const = 0;
	/// Modes of operation display (0x6061).
	[[nodiscard]] virtual std::int8_t modeDisplay() const = 0;
	/// Position actual (0x6064, position units) and velocity actual
	/// (0x606C, position units per second).
	[[nodiscard]] virtual std::int32_t positionActual() const = 0;
	[[nodiscard]] virtual std::int32_t velocityActual() const = 0;
	/// Error code (0x603F).
	[[nodiscard]] virtual std::uint16_t errorCode() const = 0;
	/// Move the shaft by hand: position actual becomes @p position (the
	/// drive does not react, a CSP following error may follow).
	virtual void setPositionActual(std::int32_t position) = 0;
	/// A drive fault: fault reaction (quick-stop ramp), then Fault; an
	/// emergency with @p errorCode is queued and 0x603F = @p errorCode.
	virtual void injectFault(std::uint16_t errorCode) = 0;
};

/// Hooks of the EST-584 stepper model.
class ECMXF_EXPORT Est584Model : public virtual Cia402Model
{
public:
	/// Place the simulated home switch: active at and above shaft position
	/// @p position (the position actual before any homing); nullopt
	/// removes it.
	virtual void setHomeSwitch(std::optional<std::int32_t> position) = 0;
	[[nodiscard]] virtual bool homeSwitchActive() const = 0;
};

/// Hooks of the servo model.
class ECMXF_EXPORT ServoModel : public virtual Cia402Model
{
public:
	/// Torque actual (0x6077), per mille of rated torque.
	[[nodiscard]] virtual std::int16_t torqueActual() const = 0;
	/// External load torque on the shaft (per mille of rated torque).
	virtual void setLoadTorque(std::int16_t permille) = 0;
	/// Contents of the last "firmware.bin" written over FoE (in BOOT).
	[[nodiscard]] virtual std::vector<std::uint8_t> firmware() const = 0;
};

/// Hooks of the digital I/O terminal.
class ECMXF_EXPORT DioModel
{
public:
	virtual ~DioModel() = default;
	/// Output bytes as applied to the terminals (all 0 unless in OP).
	[[nodiscard]] virtual std::span<const std::uint8_t> outputs() const = 0;
	/// Input bytes as the terminals read them.
	[[nodiscard]] virtual std::span<const std::uint8_t> inputs() const = 0;
	/// Set the input bytes (extra bytes ignored, missing ones unchanged).
	virtual void setInputs(std::span<const std::uint8_t> bytes) = 0;
	/// Set one input bit (bit 0 = byte 0 bit 0); out of range is ignored.
	virtual void setInput(unsigned bit, bool value) = 0;
};

} // namespace ecmxf::sim
