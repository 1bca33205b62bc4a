// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/bus/slave_access.hpp
 * @brief Direct access to the slaves through the chip: EEPROM, raw
 *        datagrams, FoE and the staging flash, the receive mailbox,
 *        emergencies, direct assignment.
 *
 * Slave access: dev.slaves().eepromRead(), foeRead(), foeWrite(),
 * rawDatagram(), receiveMailbox(), coeEmergencies()...
 *
 * Typed calls for EEPROM_REQ/GET, RAW_ECAT_FUNC_REQ/GET, FOE_FUNC_REQ/GET,
 * MBX_STAT, RECV_MAILBOX, COE_EMERGENCY and DIRECT_ASSIGN
 * (Documentation/commands-chip.rst). They reach the slaves on the bus, so
 * they live with the bus commands (lib/bus/slave_access.cpp). Arguments out
 * of range throw Error(EINVAL); a command the chip refuses throws
 * Error(EINVAL); an async command that fails throws Error(EREMOTEIO) with
 * the chip's own error code where it has one.
 *
 * A SlaveAccess is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::slaves() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_chip.hpp>
#include <ecmxf/model/types_pdo.hpp>

namespace ecmxf {

class Device;

/// Direct access to the slaves through the chip: EEPROM, raw datagrams,
/// FoE and the staging flash, the receive mailbox, emergencies, direct
/// assignment.
class ECMXF_EXPORT SlaveAccess
{
public:
	/// The view of @p device's slave access.
	explicit SlaveAccess(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	// ---- slaves: EEPROM (38/39), raw datagrams (137/138), FoE (139/140) ----

	/// One word of the SII EEPROM of the slave at bus position @p slave
	/// (0..127); @p timeout is the chip's limit (zero: its default).
	[[nodiscard]] std::uint16_t eepromRead(unsigned slave, std::uint16_t wordAddress,
					       std::chrono::microseconds timeout = {}) const;
	/// @p count words from @p wordAddress on, one EEPROM_REQ each.
	[[nodiscard]] std::vector<std::uint16_t> eepromReadWords(unsigned slave, std::uint16_t wordAddress,
								 std::size_t count) const;
	void eepromWrite(unsigned slave, std::uint16_t wordAddress, std::uint16_t value,
			 std::chrono::microseconds timeout = {}) const;
	/// RAW_ECAT_FUNC_REQ + RAW_ECAT_FUNC_GET: one datagram.
	DatagramResult rawDatagram(const Datagram &datagram) const;
	/// FoE read of file @p name from @p slave, whole (FOE_FUNC_REQ
	/// upload into the chip's flash, then flash reads in chunks).
	[[nodiscard]] std::vector<std::uint8_t> foeRead(unsigned slave, std::string_view name,
							const FoeOptions &options = {}) const;
	/// FoE write of @p data as file @p name to @p slave (flash writes in
	/// chunks, then FOE_FUNC_REQ download). A slave in INIT (no mailbox) is
	/// refused (EPERM, naming its state) before anything is staged;
	/// @p progress (may be empty) follows the staging (bytes done, in all).
	void foeWrite(unsigned slave, std::string_view name, std::span<const std::uint8_t> data,
		      const FoeOptions &options = {},
		      const std::function<void(std::size_t, std::size_t)> &progress = {}) const;
	/// The FOE_FUNC_REQ steps on their own: upload a slave's file into the
	/// flash (returns its size), download flash bytes as a file, read and
	/// write the flash (any size; chunked as the data section allows).
	std::uint32_t foeUploadToFlash(unsigned slave, std::string_view name, const FoeOptions &options = {}) const;
	void foeDownloadFromFlash(unsigned slave, std::string_view name, std::uint32_t length,
				  const FoeOptions &options = {}) const;
	[[nodiscard]] std::vector<std::uint8_t> flashRead(std::uint32_t address, std::uint32_t length) const;
	/// @p progress (may be empty) after each chunk: bytes done, in all.
	void flashWrite(std::uint32_t address, std::span<const std::uint8_t> data,
			const std::function<void(std::size_t, std::size_t)> &progress = {}) const;

	// ---- mailbox (143/144), emergencies (83), direct assign (82) ----

	/// COE_EMERGENCY (83): up to @p count (1..8) of the newest emergencies
	/// the master read, newest first (fewer when there are fewer).
	[[nodiscard]] std::vector<CoeEmergency> coeEmergencies(unsigned count = 8) const;
	/// MBX_STAT 0 (144): bus positions whose receive mailbox holds a message.
	[[nodiscard]] std::vector<unsigned> mailboxPending() const;
	/// MBX_STAT 1: master polling of each slave's receive mailbox
	/// (@p poll[position]), in effect from the next ECAT_RECONFIG_OP.
	void setMailboxPolling(const std::vector<bool> &poll) const;
	/// MBX_STAT 2: the polling in effect, one flag per slave.
	[[nodiscard]] std::vector<bool> mailboxPolling() const;
	/// RECV_MAILBOX 0 (143, async): fetch @p slave's receive mailbox into
	/// the chip.
	void fetchMailbox(unsigned slave) const;
	/// RECV_MAILBOX 1: @p length bytes of the fetched message from @p offset.
	[[nodiscard]] std::vector<std::uint8_t> readMailbox(std::size_t offset, std::size_t length) const;
	/// fetchMailbox, then the whole message (6-byte mailbox header and the
	/// bytes its length field counts); empty when the mailbox was empty.
	[[nodiscard]] std::vector<std::uint8_t> receiveMailbox(unsigned slave) const;
	/// DIRECT_ASSIGN 0 (82): use the lengths set below for @p slave.
	void setDirectAssign(unsigned slave, bool enable) const;
	/// DIRECT_ASSIGN 1: @p slave's process data length on @p side.
	void setDirectAssignLength(unsigned slave, ProcessDataSide side, std::uint16_t bytes) const;

private:
	Device *dev_;
};

} // namespace ecmxf
