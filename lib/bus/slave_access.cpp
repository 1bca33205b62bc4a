// SPDX-License-Identifier: MIT
// SlaveAccess (include/ecmxf/bus/slave_access.hpp): the slaves reached
// through the chip's own commands: SII EEPROM, raw datagrams, FoE and the
// chip's staging flash, the receive mailbox, emergencies and direct
// assignment (Documentation/commands-chip.rst). These address slaves on
// the bus, so they live with the bus commands; they run through the one
// command runner (lib/device/runner.hpp) and name the slave, and the
// chip's own error code where it has one, in their errors.

#include <ecmxf/bus/slave_access.hpp>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/model/status.hpp>

#include <algorithm>
#include <cerrno>
#include <string>

#include "device/runner.hpp"
#include "ecmxf-proto.h"

namespace ecmxf {

using namespace detail; // the command runner and its helpers
using std::chrono::microseconds;

namespace {

constexpr unsigned kMaxSlaves = 128;        // "slave number 0~127" (EEPROM_REQ)
constexpr std::size_t kRawMax = 256;        // RAW_ECAT_FUNC_REQ: n <= 256
constexpr std::size_t kFoeChunk = 256;      // FOE_FUNC_REQ flash read/write: n <= 256
constexpr std::size_t kReqHeader = 20;      // RAW/FOE request header bytes

void checkSlave(const std::string &what, unsigned slave)
{
	if (slave >= kMaxSlaves)
		invalid(what, "slave position " + std::to_string(slave) + " is out of range (0..127)");
}

std::vector<bool> bitsOf(const std::vector<std::uint8_t> &bytes, unsigned count)
{
	std::vector<bool> out(count);
	for (unsigned p = 0; p < count; p++)
		out[p] = p / 8 < bytes.size() && ((static_cast<unsigned>(bytes[p / 8]) >> (p % 8)) & 1u);
	return out;
}

} // namespace

SlaveAccess Device::slaves() noexcept
{
	return SlaveAccess(*this);
}

// ===========================================================================
// EEPROM
// ===========================================================================

namespace {

constexpr CodeText<unsigned> kEepromErrors[] = {
	{ 1, "address beyond the slave's EEPROM" },
	{ 2, "no answer from the slave" },
};

std::string eepromErrorText(unsigned code)
{
	std::string s = "EEPROM_GET error code " + std::to_string(code);
	const std::string_view why = textOf(kEepromErrors, code, {});
	if (!why.empty())
		s.append(" (").append(why).append(")");
	return s;
}

/// EEPROM_REQ + EEPROM_GET; returns the EEPROM_GET answer.
Response eepromOp(Device &d, unsigned op, unsigned slave, std::uint16_t addr, std::uint16_t value,
		  microseconds timeout)
{
	std::string what = op ? "EEPROM write of " : "EEPROM read of ";
	what.append(slaveText(slave)).append(", word ").append(hex(addr, 4));
	checkSlave(what, slave);
	Command c = detail::cmd(ECMXF_CMD_EEPROM_REQ);
	c.payload.assign(12, 0);
	detail::put16At(c.payload, 0, op);
	detail::put16At(c.payload, 2, slave);
	detail::put16At(c.payload, 4, addr);
	detail::put16At(c.payload, 6, value);
	detail::put32At(c.payload, 8, chipTimeoutField(what, timeout));
	c.timeout = hostTimeout(timeout, ECMXF_CMD_EEPROM_REQ);
	async(d, c, what, slaveText(slave) + " does not exist", [&d] {
		return eepromErrorText(immediate(d, detail::cmd(ECMXF_CMD_EEPROM_GET)).ret);
	});
	const Response r = immediate(d, detail::cmd(ECMXF_CMD_EEPROM_GET), what);
	if (r.ret != 0)
		throw Error(what + ": EEPROM_REQ completed, but " + eepromErrorText(r.ret), EREMOTEIO,
			    r.header.errStatus);
	return r;
}

} // namespace

std::uint16_t SlaveAccess::eepromRead(unsigned slave, std::uint16_t wordAddress, microseconds timeout) const
{
	const Response r = eepromOp(*dev_, 0, slave, wordAddress, 0, timeout);
	needData("EEPROM_GET (" + slaveText(slave) + ", word " + hex(wordAddress, 4) + ")", r, 2);
	return le16(r.data, 0);
}

std::vector<std::uint16_t> SlaveAccess::eepromReadWords(unsigned slave, std::uint16_t wordAddress, std::size_t count) const
{
	if (count == 0 || wordAddress + count > 0x10000)
		invalid("EEPROM read of " + slaveText(slave),
			std::to_string(count) + " words from word " + hex(wordAddress, 4) +
				" do not fit the EEPROM's address space (1..65536 words up to word 0xFFFF)");
	std::vector<std::uint16_t> out;
	out.reserve(count);
	for (std::size_t i = 0; i < count; i++)
		out.push_back(eepromRead(slave, static_cast<std::uint16_t>(wordAddress + i)));
	return out;
}

void SlaveAccess::eepromWrite(unsigned slave, std::uint16_t wordAddress, std::uint16_t value, microseconds timeout) const
{
	eepromOp(*dev_, 1, slave, wordAddress, value, timeout);
}

// ===========================================================================
// raw datagrams
// ===========================================================================

DatagramResult SlaveAccess::rawDatagram(const Datagram &dg) const
{
	const auto op = static_cast<unsigned>(dg.command);
	static constexpr const char *kNames[] = { "",    "APRD", "APWR", "",    "FPRD", "FPWR", "",    "BRD",
						  "BWR", "",     "LRD",  "LWR",  "LRW",  "ARMW", "FRMW" };
	const bool known = op < 15 && kNames[op][0] != '\0';
	std::string what = "RAW_ECAT_FUNC_REQ";
	if (!known)
		invalid(what, "datagram command " + std::to_string(op) +
				      " is not one the chip sends (1 APRD, 2 APWR, 4 FPRD, 5 FPWR, 7 BRD, 8 BWR, 10 "
				      "LRD, 11 LWR, 12 LRW, 13 ARMW, 14 FRMW)");
	what = std::string(kNames[op]) + " ADP " + hex(dg.adp, 4) + " ADO " + hex(dg.ado, 4);
	const std::size_t n = dg.data.size();
	if (n == 0 || n > kRawMax)
		invalid(what, "datagram length " + std::to_string(n) + " is out of range (1..256 bytes)");
	if (kReqHeader + n > dev_->dataSize())
		throw Error(what + ": RAW_ECAT_FUNC_REQ: " + std::to_string(n) + " data bytes need a data section of " +
				    std::to_string(kReqHeader + n) + " bytes, the link has " +
				    std::to_string(dev_->dataSize()) + " (setDataSize())",
			    EMSGSIZE);
	Command c = detail::cmd(ECMXF_CMD_RAW_ECAT_FUNC_REQ);
	c.payload.assign(kReqHeader + n, 0);
	c.payload[0] = static_cast<std::uint8_t>(op);
	detail::put16At(c.payload, 2, static_cast<std::uint32_t>(n));
	detail::put16At(c.payload, 4, dg.adp);
	detail::put16At(c.payload, 6, dg.ado);
	detail::put32At(c.payload, 8, dg.logicalAddress);
	detail::put32At(c.payload, 12, chipTimeoutField(what, dg.timeout));
	std::copy(dg.data.begin(), dg.data.end(), c.payload.begin() + kReqHeader);
	c.timeout = hostTimeout(dg.timeout, ECMXF_CMD_RAW_ECAT_FUNC_REQ);
	async(*dev_, c, what, {});
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_RAW_ECAT_FUNC_GET), what);
	needData(what + ": RAW_ECAT_FUNC_GET", r, kReqHeader + n);
	DatagramResult out;
	out.workingCounter = le16(r.data, 16);
	out.data.assign(r.data.begin() + static_cast<long>(kReqHeader),
			r.data.begin() + static_cast<long>(kReqHeader + n));
	return out;
}

// ===========================================================================
// FoE and the chip's staging flash
// ===========================================================================

namespace {

using detail::quoted;

std::string foeFailure(Device &d)
{
	const Response r = immediate(d, detail::cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET));
	if (r.data.size() < 4)
		return "no error code (ECAT_SDO_ABORTCODE_GET answered " + std::to_string(r.data.size()) + " bytes)";
	const std::uint32_t code = le32(r.data, 0);
	return "FoE error " + hex(code, 8) + " (" + std::string(foeErrorText(code)) + ")";
}

/// FOE_FUNC_REQ header (20 bytes) followed by @p extra bytes.
Command foeRequest(unsigned slave, unsigned op, std::uint32_t password, std::uint32_t length,
		   std::uint32_t timeoutUs, std::uint32_t address, std::span<const std::uint8_t> extra)
{
	Command c = detail::cmd(ECMXF_CMD_FOE_FUNC_REQ);
	c.payload.assign(kReqHeader + extra.size(), 0);
	c.payload[0] = static_cast<std::uint8_t>(slave);
	c.payload[2] = static_cast<std::uint8_t>(op);
	detail::put32At(c.payload, 4, password);
	detail::put32At(c.payload, 8, length);
	detail::put32At(c.payload, 12, timeoutUs);
	detail::put32At(c.payload, 16, address);
	std::copy(extra.begin(), extra.end(), c.payload.begin() + kReqHeader);
	return c;
}

void checkFoeName(Device &d, const std::string &what, std::string_view name)
{
	if (name.empty())
		invalid(what, "empty file name");
	if (name.find('\0') != std::string_view::npos)
		invalid(what, "the file name contains a NUL byte");
	if (kReqHeader + name.size() > d.dataSize())
		throw Error(what + ": the file name (" + std::to_string(name.size()) +
				    " bytes) does not fit the data section (at most " +
				    std::to_string(d.dataSize() - kReqHeader) + " bytes now; setDataSize())",
			    EMSGSIZE);
}

void checkFlash(const std::string &what, std::uint32_t address, std::uint64_t length)
{
	if (address >= kFoeFlashSize)
		invalid(what, "flash address " + hex(address, 5) + " is out of range (0..0x3FFFF)");
	if (length > kFoeFlashSize - address)
		invalid(what, std::to_string(length) + " bytes from flash address " + hex(address, 5) +
				      " run past the end of the 256 KiB flash (0x40000)");
}

} // namespace

std::uint32_t SlaveAccess::foeUploadToFlash(unsigned slave, std::string_view name, const FoeOptions &o) const
{
	const std::string what = "FoE read of " + quoted(name) + " from " + slaveText(slave);
	checkSlave(what, slave);
	checkFoeName(*dev_, what, name);
	checkFlash(what, o.flashAddress, 0);
	const std::uint32_t tmo = chipTimeoutField(what, o.timeout);
	Command c = foeRequest(slave, 1, o.password, 0, tmo, o.flashAddress,
			       std::span(reinterpret_cast<const std::uint8_t *>(name.data()), name.size()));
	c.timeout = hostTimeout(o.timeout, ECMXF_CMD_FOE_FUNC_REQ);
	async(*dev_, c, what, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)",
	      [this] { return foeFailure(*dev_); });
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_FOE_FUNC_GET), what);
	needData(what + ": FOE_FUNC_GET", r, 4);
	return le32(r.data, 0);
}

void SlaveAccess::foeDownloadFromFlash(unsigned slave, std::string_view name, std::uint32_t length, const FoeOptions &o) const
{
	const std::string what = "FoE write of " + quoted(name) + " to " + slaveText(slave);
	checkSlave(what, slave);
	checkFoeName(*dev_, what, name);
	checkFlash(what, o.flashAddress, length);
	const std::uint32_t tmo = chipTimeoutField(what, o.timeout);
	Command c = foeRequest(slave, 2, o.password, length, tmo, o.flashAddress,
			       std::span(reinterpret_cast<const std::uint8_t *>(name.data()), name.size()));
	c.timeout = hostTimeout(o.timeout, ECMXF_CMD_FOE_FUNC_REQ);
	async(*dev_, c, what, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)",
	      [this] { return foeFailure(*dev_); });
}

std::vector<std::uint8_t> SlaveAccess::flashRead(std::uint32_t address, std::uint32_t length) const
{
	const std::string base = "FOE_FUNC_REQ flash read";
	checkFlash(base, address, length);
	const std::size_t chunk = std::min<std::size_t>(kFoeChunk, dev_->dataSize());
	std::vector<std::uint8_t> out;
	out.reserve(length);
	for (std::uint32_t done = 0; done < length;) {
		const auto n = static_cast<std::uint32_t>(std::min<std::size_t>(chunk, length - done));
		const std::uint32_t at = address + done;
		const std::string what = base + " of " + std::to_string(n) + " bytes at " + hex(at, 5);
		async(*dev_, foeRequest(0, 3, 0, n, 0, at, {}), what, {});
		const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_FOE_FUNC_GET), what);
		needData(what + ": FOE_FUNC_GET", r, n);
		out.insert(out.end(), r.data.begin(), r.data.begin() + n);
		done += n;
	}
	return out;
}

void SlaveAccess::flashWrite(std::uint32_t address, std::span<const std::uint8_t> data,
			     const std::function<void(std::size_t, std::size_t)> &progress) const
{
	const std::string base = "FOE_FUNC_REQ flash write";
	checkFlash(base, address, data.size());
	const std::size_t chunk = std::min<std::size_t>(kFoeChunk, dev_->dataSize() - kReqHeader);
	for (std::size_t done = 0; done < data.size();) {
		const std::size_t n = std::min(chunk, data.size() - done);
		const auto at = static_cast<std::uint32_t>(address + done);
		const std::string what = base + " of " + std::to_string(n) + " bytes at " + hex(at, 5);
		async(*dev_, foeRequest(0, 4, 0, static_cast<std::uint32_t>(n), 0, at, data.subspan(done, n)), what, {});
		done += n;
		if (progress)
			progress(done, data.size());
	}
}

std::vector<std::uint8_t> SlaveAccess::foeRead(unsigned slave, std::string_view name, const FoeOptions &o) const
{
	const std::uint32_t size = foeUploadToFlash(slave, name, o);
	if (size > kFoeFlashSize - o.flashAddress)
		throw Error("FoE read of " + quoted(name) + " from " + slaveText(slave) + ": FOE_FUNC_GET reports " +
				    std::to_string(size) + " bytes, more than the flash holds from " +
				    hex(o.flashAddress, 5),
			    EPROTO);
	return flashRead(o.flashAddress, size);
}

void SlaveAccess::foeWrite(unsigned slave, std::string_view name, std::span<const std::uint8_t> data, const FoeOptions &o,
			   const std::function<void(std::size_t, std::size_t)> &progress) const
{
	const std::string what = "FoE write of " + quoted(name) + " to " + slaveText(slave);
	checkSlave(what, slave);
	checkFoeName(*dev_, what, name);
	checkFlash(what, o.flashAddress, data.size());
	// FoE needs the slave's mailbox: say so before the file is staged
	const State st = Bus(*dev_).slaveInfo(static_cast<std::uint8_t>(slave)).state;
	if ((static_cast<unsigned>(st) & 0x0Fu) == static_cast<unsigned>(State::Init))
		throw Error(what + ": the slave is in INIT and has no mailbox (PRE-OP, SAFE-OP, OP or BOOT; firmware "
				   "files usually need BOOT)",
			    EPERM);
	flashWrite(o.flashAddress, data, progress);
	foeDownloadFromFlash(slave, name, static_cast<std::uint32_t>(data.size()), o);
}

// ===========================================================================
// emergencies, receive mailbox, direct assignment
// ===========================================================================

std::vector<CoeEmergency> SlaveAccess::coeEmergencies(unsigned count) const
{
	const std::string what = "COE_EMERGENCY";
	if (count == 0 || count > 8)
		invalid(what, "count " + std::to_string(count) + " is out of range (1..8)");
	if (12u * count > dev_->dataSize())
		throw Error(what + ": " + std::to_string(count) + " entries need " + std::to_string(12 * count) +
				    " data bytes, the data section has " + std::to_string(dev_->dataSize()),
			    EMSGSIZE);
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_COE_EMERGENCY, static_cast<std::uint8_t>(count)));
	needData(what, r, 12u * count);
	std::vector<CoeEmergency> out;
	for (std::size_t i = 0; i < count; i++) {
		const std::size_t o = 12 * i;
		if (r.data[o] == 0xFF)
			continue; // no such emergency
		CoeEmergency e;
		e.entry = r.data[o];
		e.slave = r.data[o + 1];
		e.sequence = le16(r.data, o + 2);
		e.errorCode = le16(r.data, o + 4);
		e.errorRegister = r.data[o + 6];
		std::copy_n(r.data.begin() + static_cast<long>(o + 7), 5, e.data.begin());
		out.push_back(e);
	}
	return out;
}

std::vector<unsigned> SlaveAccess::mailboxPending() const
{
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_MBX_STAT, 0));
	std::vector<unsigned> out;
	for (std::size_t i = 0; i < r.data.size() * 8; i++)
		if ((static_cast<unsigned>(r.data[i / 8]) >> (i % 8)) & 1u)
			out.push_back(static_cast<unsigned>(i));
	return out;
}

void SlaveAccess::setMailboxPolling(const std::vector<bool> &poll) const
{
	const std::string what = "MBX_STAT (set polling)";
	const unsigned n = Bus(*dev_).slaveCount();
	if (poll.size() != n)
		invalid(what, std::to_string(poll.size()) + " polling flags given for " + std::to_string(n) +
				      " slaves (one per slave found by ECAT_INIT_OP)");
	if (n == 0)
		invalid(what, "no slaves (run ECAT_INIT_OP first)");
	Command c = detail::cmd(ECMXF_CMD_MBX_STAT, 1);
	c.payload.assign((n + 7) / 8, 0);
	for (unsigned p = 0; p < n; p++)
		if (poll[p])
			c.payload[p / 8] = static_cast<std::uint8_t>(c.payload[p / 8] | 1u << (p % 8));
	immediate(*dev_, c);
}

std::vector<bool> SlaveAccess::mailboxPolling() const
{
	const unsigned n = Bus(*dev_).slaveCount();
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_MBX_STAT, 2));
	needData("MBX_STAT (polling)", r, (n + 7) / 8);
	return bitsOf(r.data, n);
}

void SlaveAccess::fetchMailbox(unsigned slave) const
{
	const std::string what = "RECV_MAILBOX of " + slaveText(slave);
	checkSlave(what, slave);
	Command c = detail::cmdData(ECMXF_CMD_RECV_MAILBOX, 0, static_cast<std::uint8_t>(slave));
	async(*dev_, c, what, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)",
	      [slave] { return slaveText(slave) + " did not answer"; });
}

std::vector<std::uint8_t> SlaveAccess::readMailbox(std::size_t offset, std::size_t length) const
{
	const std::string what = "RECV_MAILBOX (read)";
	if (offset >= 64u * 256u)
		invalid(what, "offset " + std::to_string(offset) + " is out of range (0..16383)");
	if (length == 0 || length > dev_->dataSize())
		invalid(what, "length " + std::to_string(length) + " is out of range (1.." +
				      std::to_string(dev_->dataSize()) + ", the data section)");
	Command c = detail::cmdData(ECMXF_CMD_RECV_MAILBOX, 1, static_cast<std::uint8_t>(offset % 64),
			     static_cast<std::uint8_t>(offset / 64), static_cast<std::uint8_t>(length % 64),
			     static_cast<std::uint8_t>(length / 64));
	const Response r = immediate(*dev_, c);
	needData(what, r, length);
	return std::vector<std::uint8_t>(r.data.begin(), r.data.begin() + static_cast<long>(length));
}

std::vector<std::uint8_t> SlaveAccess::receiveMailbox(unsigned slave) const
{
	fetchMailbox(slave);
	std::vector<std::uint8_t> msg = readMailbox(0, 6);
	const std::size_t total = 6u + le16(msg, 0);
	if (total == 6)
		return {}; // the mailbox was empty
	while (msg.size() < total) {
		const std::size_t n = std::min<std::size_t>(total - msg.size(), dev_->dataSize());
		const std::vector<std::uint8_t> part = readMailbox(msg.size(), n);
		msg.insert(msg.end(), part.begin(), part.end());
	}
	return msg;
}

void SlaveAccess::setDirectAssign(unsigned slave, bool enable) const
{
	const std::string what = "DIRECT_ASSIGN (enable) for " + slaveText(slave);
	checkSlave(what, slave);
	immediate(*dev_, detail::cmdData(ECMXF_CMD_DIRECT_ASSIGN, 0, static_cast<std::uint8_t>(slave),
				  static_cast<std::uint8_t>(enable ? 1 : 0)),
		  {},
		  slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)");
}

void SlaveAccess::setDirectAssignLength(unsigned slave, ProcessDataSide side, std::uint16_t bytes) const
{
	const std::string what = "DIRECT_ASSIGN (length) for " + slaveText(slave);
	checkSlave(what, slave);
	const auto s = static_cast<unsigned>(side);
	if (s > 1)
		invalid(what, "side " + std::to_string(s) + " is out of range (0 output, 1 input)");
	immediate(*dev_, detail::cmdData(ECMXF_CMD_DIRECT_ASSIGN, 1, static_cast<std::uint8_t>(slave),
				  static_cast<std::uint8_t>(s), static_cast<std::uint8_t>(bytes),
				  static_cast<std::uint8_t>(bytes >> 8)),
		  {}, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)");
}

} // namespace ecmxf
