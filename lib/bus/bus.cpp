// SPDX-License-Identifier: MIT
// Bus (include/ecmxf/bus/bus.hpp), the typed bus commands: INIT_OP, RECONFIG_OP, INIT_DC_OP, PDO_CONFIG_SET/REQ/GET,
// STATE_SET/GET/CHECK/UPDATE, SLV_INFO_GET, SLV_CNT_GET, DCSYNC,
// SDO_ABORTCODE_GET, CONFIG_SM/FMMU/MAP, ENABLE_LRW. Payload layouts after
// manual ver. 050 and the decisions of the protocol digest
// (Documentation/commands-bus.rst). SDO is in lib/bus/sdo.cpp; every
// command runs through the one command runner (lib/device/runner.hpp).

#include <ecmxf/bus/bus.hpp>

#include "bus/bus_internal.hpp"
#include "device/runner.hpp"

#include <algorithm>
#include <cerrno>
#include <string>
#include <vector>

#include "ecmxf-proto.h"

namespace ecmxf {

using detail::cmd;
using detail::hex;

Bus Device::bus() noexcept
{
	return Bus(*this);
}

using bus::slaveLabel;

namespace {

void dcPayload(std::vector<std::uint8_t> &d, const DcConfig &dc)
{
	bus::put32(d, dc.sync0Ns);
	bus::put32(d, dc.sync1Ns);
	bus::put32(d, static_cast<std::uint32_t>(dc.shiftNs)); // at 0x0C (the table's 0x12 is a typo)
}

struct SlaveState {
	std::uint8_t pos;
	bool answered;
	State state;
	std::uint16_t code;
};

/// After a failed STATE_SET/STATE_CHECK: which slaves did not get there,
/// and why (their AL state and AL status code, read live).
[[noreturn]] void stateFailure(const Bus &dev, const char *cmdName, std::uint8_t slave, State want, const Error &e)
{
	std::vector<std::uint8_t> positions;
	if (slave == kAllSlaves) {
		std::uint8_t n = 0;
		try {
			n = dev.slaveCount();
		} catch (const Error &) {
			n = 0;
		}
		for (unsigned p = 0; p < n; p++)
			positions.push_back(static_cast<std::uint8_t>(p));
	} else {
		positions.push_back(slave);
	}

	std::vector<SlaveState> bad;
	for (std::uint8_t p : positions) {
		SlaveState s{ p, false, State::None, 0 };
		try {
			const auto st = dev.slaveInfoRaw(p, SlaveInfoCode::State);
			const auto code = dev.slaveInfoRaw(p, SlaveInfoCode::AlStatusCode);
			s.answered = true;
			s.state = StateReading{ st.empty() ? std::uint8_t{ 0 } : st[0] }.state();
			s.code = bus::le16(code);
		} catch (const Error &) {
			s.answered = false;
		}
		if (!s.answered || s.state != want || s.code != 0)
			bad.push_back(s);
	}

	auto describe = [&](const SlaveState &s) {
		std::string name;
		try {
			const auto n = dev.slaveInfoRaw(s.pos, SlaveInfoCode::Name);
			name.assign(n.begin(), std::find(n.begin(), n.end(), std::uint8_t{ 0 }));
		} catch (const Error &) {
		}
		std::string head = "slave " + std::to_string(s.pos);
		if (!name.empty())
			head.append(" (").append(name).append(")");
		std::string why;
		if (!s.answered)
			why = "the slave does not answer (not reachable on the bus)";
		else if (s.code)
			why = "stays in " + stateName(s.state) + ", AL status " + hex(s.code, 4) + " " +
			      std::string(alStatusText(s.code));
		else
			why = "stays in " + stateName(s.state) + " (AL status 0x0000 No error: the request did not "
								  "reach it or it did not finish in the chip's time)";
		return std::make_pair(head, why);
	};

	const std::string what = std::string(cmdName).append(" ").append(stateName(want));
	if (bad.empty())
		throw AlStatusError(std::string(what).append(" for ").append(slaveLabel(slave)).append(
					    " failed (error status bit 3), but every slave reports ").append(stateName(want)).append(" now"),
				    EREMOTEIO, slave, want, want, 0, e.errorStatus());
	const auto first = describe(bad.front());
	std::string msg = first.first + ": " + what + (slave == kAllSlaves ? " (all slaves)" : "") + " failed: " +
			  first.second;
	for (std::size_t i = 1; i < bad.size(); i++) {
		const auto more = describe(bad[i]);
		msg.append("; ").append(more.first).append(": ").append(more.second);
	}
	throw AlStatusError(msg, bad.front().answered ? EREMOTEIO : EHOSTUNREACH, bad.front().pos, want,
			    bad.front().state, bad.front().code, e.errorStatus());
}

/// ECAT_STATE_SET or ECAT_STATE_CHECK (@p code, named @p name): @p slave
/// to @p state, waiting for it; a failure on the bus is explained by
/// stateFailure().
void requestState(const Bus &b, std::uint8_t code, const char *name, std::uint8_t slave, State state)
{
	bus::checkSlave(slave, name, true);
	bus::checkState(state, name);
	Command c = cmd(code, slave);
	c.data[0] = static_cast<std::uint8_t>(state);
	const std::string what = std::string(name) + " " + stateName(state) + " for " + slaveLabel(slave);
	try {
		detail::async(b.device(), c, what, {}, {}, slave);
	} catch (const Error &e) {
		if (e.errnoValue() != EREMOTEIO)
			throw;
		stateFailure(b, name, slave, state, e);
	}
}

PdoConfig decodePdoConfig(const std::vector<std::uint8_t> &d)
{
	PdoConfig c;
	if (d.size() < 0x10)
		throw Error("ECAT_PDO_CONFIG_GET: answer of " + std::to_string(d.size()) +
				    " bytes, expected 112 (a PDO configuration)",
			    EPROTO);
	c.slave = d[0];
	c.pdoCount = d[1];
	c.assignIndex = bus::le16(d, 2);
	const unsigned n = std::min<unsigned>(c.pdoCount, 3);
	for (unsigned i = 0; i < n; i++) {
		PdoDef p;
		p.index = bus::le16(d, 4 + 2 * i);
		c.entryCounts[i] = bus::le16(d, 0x0A + 2 * i);
		const unsigned objs = std::min<unsigned>(c.entryCounts[i], 8);
		for (unsigned j = 0; j < objs; j++)
			p.entries.push_back(PdoMapEntry::fromValue(bus::le32(d, 0x10 + 0x20 * i + 4 * j)));
		c.pdos.push_back(std::move(p));
	}
	return c;
}

} // namespace

void Bus::initNetwork(const InitConfig &config) const
{
	Command c = cmd(ECMXF_CMD_ECAT_INIT_OP, config.specialSlave ? 48 : 0);
	c.payload = { 0xFF, 0x81 };
	bus::put16(c.payload, config.dc.assignActivate);
	dcPayload(c.payload, config.dc);
	c.reserved = static_cast<std::uint16_t>((config.lrw ? ECMXF_RSV_LRW : 0u) |
						(config.busShift ? ECMXF_RSV_BUS_SHIFT : 0u));
	c.timeout = config.timeout;
	try {
		detail::async(*dev_, c, "ECAT_INIT_OP");
	} catch (const Error &e) {
		if (e.errnoValue() != EREMOTEIO)
			throw;
		const ResponseHeader h = dev_->lastHeader();
		std::string why = "no slave answered";
		if (!(h.errStatus & ECMXF_ERR_LINK_HW))
			why = "no Ethernet link (error status bit 0 clear)";
		else if (!(h.errStatus & ECMXF_ERR_LINK_SW))
			why = "the link was lost during the scan (error status bit 1 clear)";
		throw Error("ECAT_INIT_OP: the network scan failed: " + why, EREMOTEIO, e.errorStatus());
	}
}

void Bus::reconfigure() const
{
	detail::async(*dev_, cmd(ECMXF_CMD_ECAT_RECONFIG_OP), "ECAT_RECONFIG_OP");
}

void Bus::initDc() const
{
	detail::async(*dev_, cmd(ECMXF_CMD_ECAT_INIT_DC_OP), "ECAT_INIT_DC_OP");
}

void Bus::pdoConfigSet(const PdoConfig &config) const
{
	const std::string what = "ECAT_PDO_CONFIG_SET " + hex(config.assignIndex, 4) + " of slave " +
				 std::to_string(config.slave);
	bus::checkSlave(config.slave, "ECAT_PDO_CONFIG_SET", false);
	if (config.pdos.size() > 3)
		throw Error(what + ": " + std::to_string(config.pdos.size()) +
				    " PDOs, the command holds at most 3 (assign more through SDO)",
			    EINVAL);
	Command c = cmd(ECMXF_CMD_ECAT_PDO_CONFIG_SET);
	c.payload.assign(112, 0);
	c.payload[0] = config.slave;
	c.payload[1] = static_cast<std::uint8_t>(config.pdos.size());
	c.payload[2] = static_cast<std::uint8_t>(config.assignIndex);
	c.payload[3] = static_cast<std::uint8_t>(config.assignIndex >> 8);
	for (std::size_t i = 0; i < config.pdos.size(); i++) {
		const PdoDef &p = config.pdos[i];
		if (p.entries.size() > 8)
			throw Error(what + ": PDO " + hex(p.index, 4) + " has " + std::to_string(p.entries.size()) +
					    " entries, the command holds at most 8 per PDO (map it through SDO)",
				    EINVAL);
		c.payload[4 + 2 * i] = static_cast<std::uint8_t>(p.index);
		c.payload[5 + 2 * i] = static_cast<std::uint8_t>(p.index >> 8);
		c.payload[0x0A + 2 * i] = static_cast<std::uint8_t>(p.entries.size());
		for (std::size_t j = 0; j < p.entries.size(); j++) {
			const std::uint32_t v = p.entries[j].value();
			for (std::size_t k = 0; k < 4; k++)
				c.payload[0x10 + 0x20 * i + 4 * j + k] = static_cast<std::uint8_t>(v >> (8 * k));
		}
	}
	try {
		detail::async(*dev_, c, what, {}, {}, config.slave);
	} catch (const Error &e) {
		bus::throwSdoAbort(*this, what, e);
	}
}

PdoConfig Bus::pdoConfigRead(std::uint8_t slave, std::uint16_t assignIndex) const
{
	bus::checkSlave(slave, "ECAT_PDO_CONFIG_REQ", false);
	const std::string what = "ECAT_PDO_CONFIG_REQ " + hex(assignIndex, 4) + " of slave " + std::to_string(slave);
	Command c = cmd(ECMXF_CMD_ECAT_PDO_CONFIG_REQ);
	c.payload = { slave, 0 };
	bus::put16(c.payload, assignIndex);
	try {
		detail::async(*dev_, c, what, {}, {}, slave);
	} catch (const Error &e) {
		bus::throwSdoAbort(*this, what, e);
	}
	return pdoConfigGet();
}

PdoConfig Bus::pdoConfigGet() const
{
	return decodePdoConfig(detail::immediate(*dev_, cmd(ECMXF_CMD_ECAT_PDO_CONFIG_GET), "ECAT_PDO_CONFIG_GET").data);
}

void Bus::stateSet(std::uint8_t slave, State state) const
{
	requestState(*this, ECMXF_CMD_ECAT_STATE_SET, "ECAT_STATE_SET", slave, state);
}

StateReading Bus::stateGet(std::uint8_t slave) const
{
	bus::checkSlave(slave, "ECAT_STATE_GET", true);
	const Response r = detail::immediate(*dev_, cmd(ECMXF_CMD_ECAT_STATE_GET, slave),
					  "ECAT_STATE_GET for " + slaveLabel(slave));
	return StateReading{ r.ret };
}

std::vector<std::uint8_t> Bus::slaveInfoRaw(std::uint8_t slave, SlaveInfoCode code) const
{
	bus::checkSlave(slave, "ECAT_SLV_INFO_GET", false);
	const auto n = static_cast<unsigned>(code);
	if (n > 13)
		throw Error("ECAT_SLV_INFO_GET: information code " + std::to_string(n) + " out of range (0..13)", EINVAL);
	Command c = cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, slave);
	c.data[0] = static_cast<std::uint8_t>(n);
	return detail::immediate(*dev_, c,
			      "ECAT_SLV_INFO_GET code " + std::to_string(n) + " of slave " + std::to_string(slave))
		.data;
}

SlaveDc Bus::slaveDc(std::uint8_t slave) const
{
	const auto get = [&](SlaveInfoCode code, std::size_t size, const char *what) {
		std::vector<std::uint8_t> d = slaveInfoRaw(slave, code);
		if (d.size() < size)
			throw Error("ECAT_SLV_INFO_GET code " + std::to_string(static_cast<unsigned>(code)) + " (" +
					    what + ") of slave " + std::to_string(slave) + ": " +
					    std::to_string(d.size()) + " data bytes, expected " + std::to_string(size),
				    EPROTO);
		return d;
	};
	SlaveDc dc;
	dc.hasDc = get(SlaveInfoCode::HasDc, 1, "has DC")[0] != 0;
	dc.cycleNs = static_cast<std::int32_t>(bus::le32(get(SlaveInfoCode::DcCycle, 4, "DC cycle")));
	dc.shiftNs = static_cast<std::int32_t>(bus::le32(get(SlaveInfoCode::DcShift, 4, "DC shift")));
	dc.active = get(SlaveInfoCode::DcActive, 1, "DC active")[0] != 0;
	return dc;
}

SlaveInfo Bus::slaveInfo(std::uint8_t slave) const
{
	SlaveInfo s;
	s.position = slave;
	s.vendorId = bus::le32(slaveInfoRaw(slave, SlaveInfoCode::Vendor));
	s.productCode = bus::le32(slaveInfoRaw(slave, SlaveInfoCode::Product));
	s.revision = bus::le32(slaveInfoRaw(slave, SlaveInfoCode::Revision));
	const auto name = slaveInfoRaw(slave, SlaveInfoCode::Name);
	s.name.assign(name.begin(), std::find(name.begin(), name.end(), std::uint8_t{ 0 }));
	s.stationAddress = bus::le16(slaveInfoRaw(slave, SlaveInfoCode::StationAddress));
	s.alias = bus::le16(slaveInfoRaw(slave, SlaveInfoCode::Alias));
	const auto st = slaveInfoRaw(slave, SlaveInfoCode::State);
	s.state = StateReading{ st.empty() ? std::uint8_t{ 0 } : st[0] }.state();
	s.alStatusCode = bus::le16(slaveInfoRaw(slave, SlaveInfoCode::AlStatusCode));
	s.outputBytes = bus::le16(slaveInfoRaw(slave, SlaveInfoCode::OutputBytes));
	s.inputBytes = bus::le16(slaveInfoRaw(slave, SlaveInfoCode::InputBytes));
	return s;
}

std::uint8_t Bus::slaveCount() const
{
	return detail::immediate(*dev_, cmd(ECMXF_CMD_ECAT_SLV_CNT_GET), "ECAT_SLV_CNT_GET").ret;
}

StateReading Bus::stateCheck(std::uint8_t slave, State state) const
{
	requestState(*this, ECMXF_CMD_ECAT_STATE_CHECK, "ECAT_STATE_CHECK", slave, state);
	return stateGet(slave);
}

void Bus::dcSync(std::uint8_t slave, const DcConfig &dc) const
{
	bus::checkSlave(slave, "ECAT_DCSYNC", true);
	Command c = cmd(ECMXF_CMD_ECAT_DCSYNC);
	c.payload = { slave, 0 };
	bus::put16(c.payload, dc.assignActivate);
	dcPayload(c.payload, dc);
	detail::async(*dev_, c, "ECAT_DCSYNC for " + slaveLabel(slave), {}, {}, slave);
}

void Bus::stateUpdate() const
{
	detail::async(*dev_, cmd(ECMXF_CMD_ECAT_STATE_UPDATE), "ECAT_STATE_UPDATE");
}

std::uint32_t Bus::sdoAbortCode() const
{
	const Response r =
		detail::immediate(*dev_, cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET), "ECAT_SDO_ABORTCODE_GET");
	if (r.data.size() < 4)
		throw Error("ECAT_SDO_ABORTCODE_GET: answer of " + std::to_string(r.data.size()) +
				    " bytes, expected 4",
			    EPROTO);
	return bus::le32(r.data);
}

void Bus::configSm(std::uint8_t slave, std::uint8_t sm, const SmConfig &config) const
{
	bus::checkSlave(slave, "ECAT_CONFIG_SM", false);
	if (sm > 15)
		throw Error("ECAT_CONFIG_SM: sync manager " + std::to_string(sm) + " out of range (0..15)", EINVAL);
	Command c = cmd(ECMXF_CMD_ECAT_CONFIG_SM);
	c.payload = { slave, sm };
	bus::put16(c.payload, config.startAddress);
	bus::put16(c.payload, config.length);
	c.payload.push_back(config.control);
	c.payload.push_back(config.activate);
	detail::immediate(*dev_, c, "ECAT_CONFIG_SM " + std::to_string(sm) + " of slave " + std::to_string(slave),
			  "is the slave on the bus?");
}

void Bus::configFmmu(std::uint8_t slave, const std::array<std::uint8_t, 4> &functions) const
{
	bus::checkSlave(slave, "ECAT_CONFIG_FMMU", false);
	Command c = cmd(ECMXF_CMD_ECAT_CONFIG_FMMU);
	c.payload = { slave, functions[0], functions[1], functions[2], functions[3] };
	detail::immediate(*dev_, c, "ECAT_CONFIG_FMMU of slave " + std::to_string(slave), "is the slave on the bus?");
}

void Bus::configMap() const
{
	detail::async(*dev_, cmd(ECMXF_CMD_ECAT_CONFIG_MAP), "ECAT_CONFIG_MAP");
}

void Bus::enableLrw(bool enable) const
{
	detail::immediate(*dev_, cmd(ECMXF_CMD_ENABLE_LRW, enable ? 1 : 0), "ENABLE_LRW");
}

} // namespace ecmxf
