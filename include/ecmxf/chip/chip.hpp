// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/chip/chip.hpp
 * @brief The chip itself: firmware, link format, counters, interrupts,
 *        resets.
 *
 * Chip calls: dev.chip().firmwareVersion(), info(), setDataSize(),
 * setCheckType(), setInterruptConfig(), warmReset()...
 *
 * Typed calls for INFO_UPDATE_OP, FW_VERSION_GET, SPI_PACK_SIZE_GET,
 * SPI_RECONFIG_OP, CRC_TYPE_SET, CRC_ERR_CNT_CLR, the WKC error counters,
 * ECAT_INT_SET/GET_ENABLE, ASYNCCMD_RESET and WARM_RESET
 * (Documentation/commands-chip.rst). Arguments out of range throw
 * Error(EINVAL) naming the argument and its range; a command the chip
 * refuses (error status bit 7) throws Error(EINVAL) with the error status.
 *
 * A Chip is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::chip() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <cstdint>

#include <ecmxf/export.hpp>
#include <ecmxf/device.hpp> // ResponseHeader
#include <ecmxf/model/types_chip.hpp>

namespace ecmxf {

class Device;

/// The chip itself: firmware, link format, counters, interrupts, resets.
class ECMXF_EXPORT Chip
{
public:
	/// The view of @p device's chip and its link.
	explicit Chip(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	/// INFO_UPDATE_OP (0): one exchange that refreshes the response
	/// header, optionally with the control-byte actions of @p options.
	ResponseHeader infoUpdate(const InfoUpdateOptions &options = {}) const;
	/// FW_VERSION_GET (56): version, extended version, series, build id.
	[[nodiscard]] FirmwareVersion firmwareVersion() const;
	/// Firmware, format, header status and counters in one (commands 56,
	/// 20, 130, 131).
	[[nodiscard]] ChipInfo info() const;
	/// SPI_PACK_SIZE_GET (20): the data section size the chip reports.
	[[nodiscard]] std::uint16_t queryDataSize() const;
	/// SPI_RECONFIG_OP (23): data section of @p bytes (32..1408) from the
	/// next exchange on; the library follows (100 ms hold-off).
	void setDataSize(std::uint16_t bytes) const;
	/// CRC_TYPE_SET (25): the check word type from the next packet on.
	/// Crc8 and Ccitt exist in firmware of manual ver. 038 only.
	void setCheckType(CheckType type) const;
	/// CRC_ERR_CNT_CLR (24): clears the SPI CRC error count; returns the
	/// count it had.
	std::uint8_t clearCrcErrorCount() const;
	/// ECAT_WKC_CONTI_ERR_CNT_GET (130): consecutive WKC errors now.
	[[nodiscard]] std::uint8_t wkcContinuousErrorCount() const;
	/// ECAT_WKC_CONTI_ERR_MAX_GET (131): the limit (kWkcNoLimit = none).
	[[nodiscard]] std::uint8_t wkcErrorLimit() const;
	/// ECAT_WKC_CONTI_ERR_MAX_SET (132): stop the process data after more
	/// than @p limit (1..255; kWkcNoLimit = never) consecutive WKC errors.
	void setWkcErrorLimit(std::uint8_t limit) const;
	/// ECAT_INT_SET_ENABLE (58): INT1 sources and INT0/INT1 polarities.
	void setInterruptConfig(const InterruptConfig &config) const;
	/// ECAT_INT_GET_ENABLE (59).
	[[nodiscard]] InterruptConfig interruptConfig() const;
	/// ASYNCCMD_RESET (75): @p actions = async_reset::k* bits (1..7).
	void resetAsyncCommand(std::uint8_t actions) const;
	/// WARM_RESET (127): the chip restarts with its power-on settings
	/// (112-byte data section, fixed check word); the library follows.
	void warmReset() const;

private:
	Device *dev_;
};

} // namespace ecmxf
