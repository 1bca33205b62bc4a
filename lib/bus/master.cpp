// SPDX-License-Identifier: MIT
// Master: the bring-up sequence of both manuals over a Device, the scanned
// slaves and their PDO mappings (include/ecmxf/bus/master.hpp,
// Documentation/master.rst).
//
// FIFO_PACK_SIZE_GET (19) and FIFO_ENABLE (18) are sent raw through
// Device::command() here; the typed process-data calls live in another
// part of the library (lib/pdo/process_data.cpp).

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/master.hpp>

#include "bus/bus_internal.hpp"

#include <algorithm>
#include <cerrno>
#include <functional>
#include <string>
#include <vector>

#include <ecmxf/model/objects.hpp>

#include "ecmxf-proto.h"

namespace ecmxf {

namespace {

/// SII word addresses and categories (ETG.2010).
constexpr std::uint16_t kSiiMailboxProtocol = 0x001C;
constexpr std::uint16_t kSiiFirstCategory = 0x0040;
constexpr std::uint16_t kSiiCatTxPdo = 50;
constexpr std::uint16_t kSiiCatRxPdo = 51;
constexpr std::uint16_t kSiiCatEnd = 0xFFFF;
constexpr std::uint16_t kMbxCoE = 0x0004;

/// The name of object @p index, @p sub (the standard objects of
/// <ecmxf/model/objects.hpp>); "" when it has none there.
std::string objectName(std::uint16_t index, std::uint8_t sub)
{
	// 0x6099 has a name for each subindex; the others are named by index
	const auto o = standardObject(index, index == 0x6099 ? sub : 0);
	return o ? std::string(o->name) : std::string();
}

/// Where the bytes of slave @p position start in the process image: the
/// @p bytes of the slaves before it added up; @p caller names the call in
/// the error.
std::uint32_t imageOffset(const std::vector<SlaveInfo> &slaves, std::size_t position,
			  std::uint16_t SlaveInfo::*bytes, const char *caller)
{
	if (position >= slaves.size())
		throw Error(std::string(caller) + ": slave " + std::to_string(position) + " out of range (0.." +
				    std::to_string(slaves.size()) + " slaves scanned)",
			    EINVAL);
	std::uint32_t off = 0;
	for (std::size_t p = 0; p < position; p++)
		off += slaves[p].*bytes;
	return off;
}

std::string slaveLabel(const std::vector<SlaveInfo> &slaves, std::size_t pos)
{
	std::string s = "slave " + std::to_string(pos);
	if (pos < slaves.size() && !slaves[pos].name.empty())
		s.append(" (").append(slaves[pos].name).append(")");
	return s;
}

void step(const char *name, const std::function<void()> &fn)
{
	try {
		fn();
	} catch (const Error &) {
		bus::rethrowWithPrefix(std::string("bring-up step '").append(name).append("' failed: "));
	}
}

/// One SII word through EEPROM_REQ (38) / EEPROM_GET (39).
std::uint16_t siiWord(Device &dev, std::uint8_t pos, std::uint16_t addr)
{
	return SlaveAccess(dev).eepromRead(pos, addr);
}

/// Appends the entries of @p pdos to @p out with running bit offsets.
void addEntries(std::vector<PdoEntryInfo> &out, const std::vector<PdoDef> &pdos)
{
	std::uint32_t bit = 0;
	for (const PdoDef &p : pdos) {
		for (const PdoMapEntry &e : p.entries) {
			PdoEntryInfo i;
			i.pdo = p.index;
			i.index = e.index;
			i.sub = e.sub;
			i.bitLength = e.bitLength;
			i.bitOffset = bit;
			i.name = e.index ? objectName(e.index, e.sub) : std::string();
			bit += e.bitLength;
			out.push_back(std::move(i));
		}
	}
}

/// An assignment through CoE: ECAT_PDO_CONFIG_REQ, and plain SDO reads
/// when it holds more than the command's 3 PDOs of 8 entries.
std::vector<PdoDef> readAssignment(Device &dev, std::uint8_t pos, std::uint16_t assign)
{
	const PdoConfig c = dev.bus().pdoConfigRead(pos, assign);
	if (c.complete())
		return c.pdos;
	std::vector<PdoDef> pdos;
	const auto n = dev.sdo().read<std::uint8_t>(pos, assign, 0);
	for (unsigned i = 1; i <= n; i++) {
		PdoDef p;
		p.index = dev.sdo().read<std::uint16_t>(pos, assign, static_cast<std::uint8_t>(i));
		const auto m = dev.sdo().read<std::uint8_t>(pos, p.index, 0);
		for (unsigned j = 1; j <= m; j++)
			p.entries.push_back(PdoMapEntry::fromValue(
				dev.sdo().read<std::uint32_t>(pos, p.index, static_cast<std::uint8_t>(j))));
		pdos.push_back(std::move(p));
	}
	return pdos;
}

/// The RxPDO (51) and TxPDO (50) categories of a slave's SII; PDOs with
/// sync manager 0xFF (not assigned) are left out.
void readSiiPdos(Device &dev, std::uint8_t pos, std::vector<PdoDef> &rx, std::vector<PdoDef> &tx)
{
	std::uint16_t word = kSiiFirstCategory;
	for (int guard = 0; guard < 64; guard++) {
		const std::uint16_t type = siiWord(dev, pos, word);
		if (type == kSiiCatEnd)
			return;
		const std::uint16_t size = siiWord(dev, pos, static_cast<std::uint16_t>(word + 1));
		if (type == kSiiCatTxPdo || type == kSiiCatRxPdo) {
			std::vector<std::uint8_t> b;
			for (std::uint16_t i = 0; i < size; i++)
				bus::put16(b, siiWord(dev, pos, static_cast<std::uint16_t>(word + 2 + i)));
			std::size_t o = 0;
			while (o + 8 <= b.size()) {
				PdoDef p;
				p.index = bus::le16(b, o);
				const unsigned n = b[o + 2];
				const unsigned sm = b[o + 3];
				o += 8;
				for (unsigned j = 0; j < n && o + 8 <= b.size(); j++, o += 8)
					p.entries.push_back(PdoMapEntry{ bus::le16(b, o), b[o + 2], b[o + 5] });
				if (sm != 0xFF)
					(type == kSiiCatRxPdo ? rx : tx).push_back(std::move(p));
			}
		}
		word = static_cast<std::uint16_t>(word + 2 + size);
	}
}

/// Writes one assignment through SDO (the ETG.1020 order: count 0,
/// mappings, PDO list, count).
void writeAssignmentSdo(Device &dev, std::uint8_t pos, std::uint16_t assign, const std::vector<PdoDef> &pdos)
{
	dev.sdo().write<std::uint8_t>(pos, assign, 0, 0);
	for (const PdoDef &p : pdos) {
		dev.sdo().write<std::uint8_t>(pos, p.index, 0, 0);
		for (std::size_t j = 0; j < p.entries.size(); j++)
			dev.sdo().write<std::uint32_t>(pos, p.index, static_cast<std::uint8_t>(j + 1), p.entries[j].value());
		dev.sdo().write<std::uint8_t>(pos, p.index, 0, static_cast<std::uint8_t>(p.entries.size()));
	}
	for (std::size_t i = 0; i < pdos.size(); i++)
		dev.sdo().write<std::uint16_t>(pos, assign, static_cast<std::uint8_t>(i + 1), pdos[i].index);
	dev.sdo().write<std::uint8_t>(pos, assign, 0, static_cast<std::uint8_t>(pdos.size()));
}

void writeAssignment(Device &dev, std::uint8_t pos, std::uint16_t assign, const std::vector<PdoDef> &pdos)
{
	const bool fits = pdos.size() <= 3 && std::all_of(pdos.begin(), pdos.end(), [](const PdoDef &p) {
				  return p.entries.size() <= 8;
			  });
	if (!fits) {
		writeAssignmentSdo(dev, pos, assign, pdos);
		return;
	}
	PdoConfig c;
	c.slave = pos;
	c.assignIndex = assign;
	c.pdos = pdos;
	dev.bus().pdoConfigSet(c);
}

std::uint32_t bits(const std::vector<PdoEntryInfo> &v)
{
	std::uint32_t n = 0;
	for (const auto &e : v)
		n += e.bitLength;
	return n;
}

} // namespace

Master::Master(Device &device) : dev_(device) {}

void Master::rescan()
{
	const std::uint8_t n = dev_.bus().slaveCount();
	std::vector<SlaveInfo> found;
	found.reserve(n);
	for (unsigned p = 0; p < n; p++)
		found.push_back(dev_.bus().slaveInfo(static_cast<std::uint8_t>(p)));
	slaves_ = std::move(found);
	rxPdoSize_ = txPdoSize_ = 0;
	for (const SlaveInfo &s : slaves_) {
		rxPdoSize_ += s.outputBytes;
		txPdoSize_ += s.inputBytes;
	}
}

std::uint32_t Master::outputOffset(std::size_t position) const
{
	return imageOffset(slaves_, position, &SlaveInfo::outputBytes, "Master::outputOffset");
}

std::uint32_t Master::inputOffset(std::size_t position) const
{
	return imageOffset(slaves_, position, &SlaveInfo::inputBytes, "Master::inputOffset");
}

SlavePdos Master::readSlavePdos(std::uint8_t position)
{
	if (position >= slaves_.size())
		throw Error("Master::readSlavePdos: slave " + std::to_string(position) + " out of range (" +
				    std::to_string(slaves_.size()) + " slaves scanned)",
			    EINVAL);
	const SlaveInfo &s = slaves_[position];
	std::vector<PdoDef> rx, tx;
	const bool coe = (siiWord(dev_, position, kSiiMailboxProtocol) & kMbxCoE) != 0;
	if (coe) {
		rx = readAssignment(dev_, position, 0x1C12);
		tx = readAssignment(dev_, position, 0x1C13);
	} else {
		readSiiPdos(dev_, position, rx, tx);
	}
	SlavePdos r;
	addEntries(r.outputs, rx);
	addEntries(r.inputs, tx);
	r.outputBytes = s.outputBytes;
	r.inputBytes = s.inputBytes;
	const std::string src = coe ? "the slave's 0x1C12/0x1C13 assignment" : "its SII";
	if (bits(r.outputs) != r.outputBytes * 8u || bits(r.inputs) != r.inputBytes * 8u)
		throw Error(slaveLabel(slaves_, position) + ": the PDO mapping read from " + src + " has " +
				    std::to_string(bits(r.outputs)) + " output bits and " + std::to_string(bits(r.inputs)) +
				    " input bits, but the chip's process image gives it " + std::to_string(r.outputBytes) +
				    " output and " + std::to_string(r.inputBytes) +
				    " input bytes (remapped without ECAT_CONFIG_MAP / ECAT_RECONFIG_OP?)",
			    EPROTO);
	return r;
}

void Master::readPdoMapping()
{
	std::vector<SlavePdos> all;
	all.reserve(slaves_.size());
	for (std::size_t p = 0; p < slaves_.size(); p++)
		all.push_back(readSlavePdos(static_cast<std::uint8_t>(p)));
	pdos_ = std::move(all);
}

void Master::bringUp(const MasterConfig &config)
{
	if (config.target != State::PreOp && config.target != State::SafeOp && config.target != State::Op)
		throw Error("Master::bringUp: target state " + stateName(config.target) +
				    " not one of PRE-OP, SAFE-OP, OP",
			    EINVAL);
	if (config.enableFifo && config.target != State::Op)
		throw Error("Master::bringUp: enableFifo needs target state OP (the manual enables the FIFO in OP), "
			    "target is " + stateName(config.target),
			    EINVAL);
	slaves_.clear();
	pdos_.clear();
	const auto step = [&config](const char *name, const std::function<void()> &fn) {
		if (config.onStep)
			config.onStep(name);
		ecmxf::step(name, fn);
	};

	step("init", [&] { dev_.bus().initNetwork(config.init); });
	step("scan", [&] {
		rescan();
		if (config.expectedSlaves && slaves_.size() != *config.expectedSlaves)
			throw Error("found " + std::to_string(slaves_.size()) + " slaves, expected " +
					    std::to_string(*config.expectedSlaves),
				    ENODEV);
		if (slaves_.empty())
			throw Error("no slaves found", ENODEV);
	});
	step("states to PRE-OP", [&] { dev_.bus().stateSet(kAllSlaves, State::PreOp); });
	if (!config.pdoAssignments.empty())
		step("PDO configuration", [&] {
			for (const SlavePdoAssignment &a : config.pdoAssignments) {
				if (a.slave >= slaves_.size())
					throw Error("PDO assignment for slave " + std::to_string(a.slave) + ": only " +
							    std::to_string(slaves_.size()) + " slaves on the bus",
						    EINVAL);
				if (a.rxPdos)
					writeAssignment(dev_, a.slave, 0x1C12, *a.rxPdos);
				if (a.txPdos)
					writeAssignment(dev_, a.slave, 0x1C13, *a.txPdos);
			}
			if (config.remap == RemapCommand::ConfigMap) {
				dev_.bus().configMap();
			} else {
				dev_.bus().reconfigure();
				dev_.bus().stateUpdate(); // the header reads INIT after RECONFIG_OP
			}
			rescan();
		});
	if (!config.startupSdos.empty())
		step("start-up SDOs", [&] {
			for (const StartupSdo &s : config.startupSdos)
				dev_.sdo().download(s.slave, s.index, s.sub, s.data);
		});
	if (config.readPdoMapping)
		step("PDO mapping", [&] { readPdoMapping(); });
	if (config.target == State::SafeOp || config.target == State::Op)
		step("states to SAFE-OP", [&] { dev_.bus().stateSet(kAllSlaves, State::SafeOp); });
	if (config.target == State::Op)
		step("states to OP", [&] { dev_.bus().stateSet(kAllSlaves, State::Op); });
	if (config.enableFifo)
		step("FIFO enable", [&] {
			std::uint32_t size[2] = { 0, 0 };
			for (std::uint8_t dir = 0; dir < 2; dir++) {
				const Response r = detail::immediate(dev_, bus::cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, dir),
								  dir ? "FIFO_PACK_SIZE_GET TxPDO" : "FIFO_PACK_SIZE_GET RxPDO");
				size[dir] = bus::le16(r.data);
			}
			if (size[0] != rxPdoSize_ || size[1] != txPdoSize_)
				throw Error("FIFO_PACK_SIZE_GET reports " + std::to_string(size[0]) + " RxPDO and " +
						    std::to_string(size[1]) + " TxPDO bytes, the slaves have " +
						    std::to_string(rxPdoSize_) + " output and " + std::to_string(txPdoSize_) +
						    " input bytes",
					    EPROTO);
			detail::immediate(dev_, bus::cmd(ECMXF_CMD_FIFO_ENABLE, 1), "FIFO_ENABLE");
			if (!(dev_.lastHeader().ecmStatus & ECMXF_STS_FIFO_EN))
				throw Error("FIFO_ENABLE: the chip does not report the FIFO enabled (ECM status bit 6)",
					    EPROTO);
		});
}

} // namespace ecmxf
