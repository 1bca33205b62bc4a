// SPDX-License-Identifier: MIT
/**
 * @file master.hpp
 * @brief The documented bring-up of an EtherCAT network behind an ECM-XF:
 *        init with DC, scan, PDO configuration, start-up SDOs, states, FIFO.
 *
 * The bring-up in one call: ecmxf::Master(dev).bringUp(config); then
 * slaves() and pdos() say what it found (pdos() is what a ProcessImage is
 * built from).
 *
 * Master drives a Device through the sequence of both manuals (spec
 * "Bring-up sequence"; Documentation/master.rst):
 *
 *  1. "init"                ECAT_INIT_OP with the DC settings
 *  2. "scan"                ECAT_SLV_CNT_GET, ECAT_SLV_INFO_GET of each slave
 *  3. "states to PRE-OP"    ECAT_STATE_SET PRE-OP (all slaves)
 *  4. "PDO configuration"   per slave: ECAT_PDO_CONFIG_SET (at most 3 PDOs of
 *                           8 entries) or SDO writes to 0x1C12/0x1C13 and
 *                           0x16xx/0x1Axx, then ECAT_CONFIG_MAP (or
 *                           ECAT_RECONFIG_OP) and a new scan
 *  5. "start-up SDOs"       the listed SDO downloads, in PRE-OP
 *  6. "PDO mapping"         read back each slave's mapping (SDO, or the SII
 *                           for slaves without CoE) into pdos()
 *  7. "states to SAFE-OP", "states to OP"  up to the target state
 *  8. "FIFO enable"         FIFO_PACK_SIZE_GET (Rx, Tx), FIFO_ENABLE
 *
 * A failing step throws the underlying error (Error, SdoError,
 * AlStatusError) with "bring-up step '<name>' failed: " before its message.
 */
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/pdo_mapping.hpp>
#include <ecmxf/model/types_bus.hpp>

namespace ecmxf {

class Device;

/// The PDO assignment of one slave to configure; a direction left unset
/// keeps the slave's current (default) assignment.
struct SlavePdoAssignment {
	std::uint8_t slave = 0;
	std::optional<std::vector<PdoDef>> rxPdos; ///< 0x1C12: outputs (0x16xx)
	std::optional<std::vector<PdoDef>> txPdos; ///< 0x1C13: inputs (0x1Axx)
};

/// One SDO download of the start-up list (applied in PRE-OP).
struct StartupSdo {
	std::uint8_t slave = 0;
	std::uint16_t index = 0;
	std::uint8_t sub = 0;
	std::vector<std::uint8_t> data; ///< little-endian value bytes
};

/// How a PDO remapping is applied to the chip's process image.
enum class RemapCommand {
	ConfigMap,  ///< ECAT_CONFIG_MAP (73): keeps the slaves' new mapping
	Reconfig,   ///< ECAT_RECONFIG_OP (2)
};

/// What Master::bringUp() does.
struct MasterConfig {
	/// ECAT_INIT_OP: DC cycle (SYNC0), SYNC1, shift, AssignActivate, LRW...
	InitConfig init;
	/// Expected slave count; unset: whatever the scan finds (at least 1).
	std::optional<std::size_t> expectedSlaves;
	/// PDO assignments to configure (slaves not listed keep theirs).
	std::vector<SlavePdoAssignment> pdoAssignments;
	RemapCommand remap = RemapCommand::ConfigMap;
	/// SDO downloads applied in PRE-OP, in order.
	std::vector<StartupSdo> startupSdos;
	/// The state to end in: PRE-OP, SAFE-OP or OP.
	State target = State::Op;
	/// Enable the chip's FIFO at the end (needs target OP).
	bool enableFifo = true;
	/// Read every slave's PDO mapping back (pdos()).
	bool readPdoMapping = true;
	/// Called with each step's name ("init", "scan"...) before it runs,
	/// e.g. to show progress; empty: nothing is called.
	std::function<void(std::string_view step)> onStep;
};

/// The bring-up sequence and what it found.
class ECMXF_EXPORT Master
{
public:
	/// A master driving @p device (not owned; it must outlive this).
	explicit Master(Device &device);

	/// Runs the bring-up of @p config (class comment). Throws Error with
	/// "bring-up step '<name>' failed: " and the cause.
	void bringUp(const MasterConfig &config);

	/// The slaves found by the last scan (index = bus position), as
	/// ECAT_SLV_INFO_GET reported them (state: as scanned; see refresh()).
	[[nodiscard]] const std::vector<SlaveInfo> &slaves() const noexcept { return slaves_; }
	/// Each slave's PDO mapping (index = bus position): entries with bit
	/// offsets within the slave's output / input bytes.
	[[nodiscard]] const std::vector<SlavePdos> &pdos() const noexcept { return pdos_; }
	/// The process image sizes the chip reported (FIFO_PACK_SIZE_GET
	/// param 0 RxPDO, 1 TxPDO), once the FIFO step ran; else the sums of
	/// the slaves' output / input bytes.
	[[nodiscard]] std::uint32_t rxPdoSize() const noexcept { return rxPdoSize_; }
	[[nodiscard]] std::uint32_t txPdoSize() const noexcept { return txPdoSize_; }
	/// Byte offset of slave @p position's outputs / inputs in the process
	/// image (the chip lays the slaves out in bus order).
	[[nodiscard]] std::uint32_t outputOffset(std::size_t position) const;
	[[nodiscard]] std::uint32_t inputOffset(std::size_t position) const;

	/// Scans again (ECAT_SLV_CNT_GET, ECAT_SLV_INFO_GET of each slave).
	void rescan();
	/// Reads the PDO mapping of every slave again (pdos()).
	void readPdoMapping();
	/// Reads one slave's mapping: SDO (0x1C12/0x1C13 through
	/// ECAT_PDO_CONFIG_REQ, and plain SDO beyond 3 PDOs of 8 entries) for
	/// slaves with CoE, the SII's RxPDO/TxPDO categories otherwise.
	[[nodiscard]] SlavePdos readSlavePdos(std::uint8_t position);

	[[nodiscard]] Device &device() noexcept { return dev_; }

private:
	Device &dev_;
	std::vector<SlaveInfo> slaves_;
	std::vector<SlavePdos> pdos_;
	std::uint32_t rxPdoSize_ = 0;
	std::uint32_t txPdoSize_ = 0;
};

} // namespace ecmxf
