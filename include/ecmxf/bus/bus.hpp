// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/bus/bus.hpp
 * @brief The bus commands: bring-up, states, slave information, PDO
 *        configuration, sync managers, FMMUs, mapping, LRW.
 *
 * Bus calls: dev.bus().initNetwork(), stateSet(), stateGet(),
 * slaveInfo(), slaveCount(), pdoConfigSet()... (the SDO transfers are
 * dev.sdo(), <ecmxf/bus/sdo.hpp>; the bring-up in one call is Master,
 * <ecmxf/bus/master.hpp>).
 *
 * Slaves are 0-based bus positions as the chip numbers them (0..127);
 * kAllSlaves (0xFF) selects all where the manual allows it. Types in
 * <ecmxf/model/types_bus.hpp>; Documentation/commands-bus.rst.
 *
 * A Bus is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::bus() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_bus.hpp>

namespace ecmxf {

class Device;

/// The bus commands: bring-up, states, slave information, PDO
/// configuration, sync managers, FMMUs, mapping, LRW.
class ECMXF_EXPORT Bus
{
public:
	/// The view of @p device's bus commands.
	explicit Bus(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	/// ECAT_INIT_OP (1): scan the network and configure DC; every slave
	/// ends in INIT, the FIFO off.
	void initNetwork(const InitConfig &config = {}) const;
	/// ECAT_RECONFIG_OP (2): rebuild the process image after a PDO
	/// remapping (the header's ECAT state reads INIT afterwards; call
	/// stateUpdate()).
	void reconfigure() const;
	/// ECAT_INIT_DC_OP (3): apply the DC settings (after dcSync()).
	void initDc() const;
	/// ECAT_PDO_CONFIG_SET (7): write one assignment object and its PDOs
	/// (at most 3 PDOs of 8 entries: EINVAL beyond; use SDO then).
	void pdoConfigSet(const PdoConfig &config) const;
	/// ECAT_PDO_CONFIG_REQ (8) + ECAT_PDO_CONFIG_GET (9): read an
	/// assignment object (0x1C12/0x1C13) and its PDOs back from a slave.
	[[nodiscard]] PdoConfig pdoConfigRead(std::uint8_t slave, std::uint16_t assignIndex) const;
	/// ECAT_PDO_CONFIG_GET (9) alone: the result of the last PDO_CONFIG_REQ.
	[[nodiscard]] PdoConfig pdoConfigGet() const;
	/// ECAT_STATE_SET (12); waits until the slave(s) reached @p state.
	/// Failure: AlStatusError naming the slave, the state reached and its
	/// AL status code and text.
	void stateSet(std::uint8_t slave, State state) const;
	/// ECAT_STATE_GET (13): the state the chip last read (see stateUpdate()).
	[[nodiscard]] StateReading stateGet(std::uint8_t slave) const;
	/// ECAT_SLV_INFO_GET (15), every code (0..9).
	[[nodiscard]] SlaveInfo slaveInfo(std::uint8_t slave) const;
	/// ECAT_SLV_INFO_GET (15), one code (0..13); the bytes the chip returned.
	[[nodiscard]] std::vector<std::uint8_t> slaveInfoRaw(std::uint8_t slave, SlaveInfoCode code) const;
	/// ECAT_SLV_INFO_GET (15), codes 10..13: the slave's distributed
	/// clock. Throws ecmxf::Error (EINVAL, command error) when the firmware
	/// does not know the codes, EPROTO for an answer shorter than the
	/// code's value.
	[[nodiscard]] SlaveDc slaveDc(std::uint8_t slave) const;
	/// ECAT_SLV_CNT_GET (16): slaves found by the last INIT_OP.
	[[nodiscard]] std::uint8_t slaveCount() const;
	/// ECAT_STATE_CHECK (41): STATE_SET + STATE_UPDATE + STATE_GET; the
	/// state reached (failures as stateSet()).
	StateReading stateCheck(std::uint8_t slave, State state) const;
	/// ECAT_DCSYNC (50): per-slave DC settings; applied by initDc().
	void dcSync(std::uint8_t slave, const DcConfig &dc) const;
	/// ECAT_STATE_UPDATE (57): read the slaves' states into the chip.
	void stateUpdate() const;
	/// ECAT_SDO_ABORTCODE_GET (69): the abort code of the last SDO.
	[[nodiscard]] std::uint32_t sdoAbortCode() const;
	/// ECAT_CONFIG_SM (71): set one sync manager of a slave by hand.
	void configSm(std::uint8_t slave, std::uint8_t sm, const SmConfig &config) const;
	/// ECAT_CONFIG_FMMU (72). Obsolete (manual ver. 050): the chip
	/// configures the FMMUs itself and overwrites this; kept for
	/// completeness. @p functions: FMMU0..3 function codes.
	void configFmmu(std::uint8_t slave, const std::array<std::uint8_t, 4> &functions) const;
	/// ECAT_CONFIG_MAP (73): apply a PDO remapping (instead of
	/// RECONFIG_OP for slaves that reset their mapping on it).
	void configMap() const;
	/// ENABLE_LRW (142): LRW (true, the default) or LRD + LWR.
	void enableLrw(bool enable) const;

private:
	Device *dev_;
};

} // namespace ecmxf
