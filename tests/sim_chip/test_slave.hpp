// SPDX-License-Identifier: MIT
//
// Small slave models for the chip tests: just enough of an EtherCAT slave
// to see what the chip does to it. The real slave models (lib/sim/slaves)
// are tested on their own; these stay simple so that a test can state
// exactly what the slave does.
//
// TestSlave: process data of configurable size (inputs from a pattern the
// test sets, outputs recorded), the AL state machine rules of the AKD2G
// document (I->P->S->O in order, 0x0011 for an invalid change, error
// acknowledge), an object dictionary for SDO, emergencies, FoE files, an
// ESC register file and an SII image with identity, mailbox, name string
// and sync managers.
//
// TestDrive: a TestSlave whose outputs are a CiA-402 control word and
// whose inputs are the status word of the drive state machine it runs.

#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <ecmxf/sim/network.hpp>

namespace simtest {

using namespace std::chrono_literals;
namespace sim = ecmxf::sim;

struct SlaveConfig {
	std::uint32_t vendor = 0x0000ABCD;
	std::uint32_t product = 0x00001234;
	std::uint32_t revision = 0x00010002;
	std::uint32_t serial = 0x00C0FFEE;
	std::uint16_t alias = 0;
	std::string name = "TestSlave";
	std::size_t outBytes = 2;
	std::size_t inBytes = 2;
	bool coe = true;
	bool foe = false;
	std::uint16_t dcAssign = 0;
	std::chrono::nanoseconds mbxLatency = 2ms;
	/// Virtual time a state transition takes inside the slave.
	std::chrono::nanoseconds transitionTime = 0ns;
};

class TestSlave : public sim::Slave
{
public:
	explicit TestSlave(SlaveConfig c = {}) : cfg(std::move(c))
	{
		id.vendorId = cfg.vendor;
		id.productCode = cfg.product;
		id.revision = cfg.revision;
		id.serial = cfg.serial;
		id.name = cfg.name;
		inputPattern.assign(cfg.inBytes, 0);
		lastOutputs.assign(cfg.outBytes, 0);
		od[{ 0x1000, 0 }] = { 0x92, 0x01, 0x02, 0x00 };	// device type
		od[{ 0x1008, 0 }] = std::vector<std::uint8_t>(cfg.name.begin(), cfg.name.end());
		od[{ 0x2000, 0 }] = { 0x11, 0x22, 0x33, 0x44 };
		std::vector<std::uint8_t> big(200);
		for (std::size_t i = 0; i < big.size(); i++)
			big[i] = static_cast<std::uint8_t>(i);
		od[{ 0x2001, 0 }] = big;
		readOnly.insert({ 0x1000, 0 });
	}

	// ---- what the tests look at ----
	SlaveConfig cfg;
	sim::Identity id;
	std::uint8_t state = 0x01;
	bool error = false;
	std::uint16_t code = 0;
	std::optional<std::uint8_t> pending;	///< a transition in progress
	std::chrono::nanoseconds pendingLeft{ 0 };
	std::vector<std::uint8_t> alWrites;	///< every AL control value
	/// A transition the slave refuses (to -> AL status code).
	std::map<std::uint8_t, std::uint16_t> refuse;
	std::map<std::pair<std::uint16_t, std::uint8_t>, std::vector<std::uint8_t>> od;
	std::set<std::pair<std::uint16_t, std::uint8_t>> readOnly;
	std::vector<std::tuple<std::uint16_t, std::uint8_t, std::vector<std::uint8_t>>> downloads;
	std::deque<sim::Emergency> emergencies;
	std::map<std::string, std::vector<std::uint8_t>> files;
	std::vector<std::uint8_t> inputPattern;
	std::vector<std::uint8_t> lastOutputs;
	std::uint64_t cycles = 0, validCycles = 0, sync0Cycles = 0;
	std::chrono::nanoseconds lastDt{ 0 }, idleTime{ 0 };
	std::uint16_t dcAssign = 0;
	std::uint32_t dcSync0 = 0, dcSync1 = 0;
	std::int32_t dcShift = 0;
	bool dcConfigured = false;
	bool logOutputs = false;	///< record the outputs of every OP cycle
	std::vector<std::vector<std::uint8_t>> outLog;
	bool counterInput = false;	///< first input byte = cycle counter
	std::array<std::uint8_t, 0x1000> regs{};	///< ESC registers

	// ---- identity, EEPROM ----
	const sim::Identity &identity() const override { return id; }
	std::string typeName() const override { return "test"; }
	std::vector<std::uint16_t> sii() const override
	{
		std::vector<std::uint16_t> w(0x40, 0);
		w[0x04] = cfg.alias;
		w[0x08] = static_cast<std::uint16_t>(cfg.vendor);
		w[0x09] = static_cast<std::uint16_t>(cfg.vendor >> 16);
		w[0x0A] = static_cast<std::uint16_t>(cfg.product);
		w[0x0B] = static_cast<std::uint16_t>(cfg.product >> 16);
		w[0x0C] = static_cast<std::uint16_t>(cfg.revision);
		w[0x0D] = static_cast<std::uint16_t>(cfg.revision >> 16);
		w[0x0E] = static_cast<std::uint16_t>(cfg.serial);
		w[0x0F] = static_cast<std::uint16_t>(cfg.serial >> 16);
		if (cfg.coe) {
			w[0x18] = 0x1000;
			w[0x19] = 128;
			w[0x1A] = 0x1080;
			w[0x1B] = 128;
			w[0x1C] = static_cast<std::uint16_t>(0x0004 | (cfg.foe ? 0x0008 : 0));
		}
		// categories: strings (10), general (30), SyncM (41), end
		std::vector<std::uint8_t> str;
		str.push_back(1);
		str.push_back(static_cast<std::uint8_t>(cfg.name.size()));
		str.insert(str.end(), cfg.name.begin(), cfg.name.end());
		if (str.size() & 1)
			str.push_back(0);
		auto category = [&](std::uint16_t type, const std::vector<std::uint8_t> &bytes) {
			w.push_back(type);
			w.push_back(static_cast<std::uint16_t>(bytes.size() / 2));
			for (std::size_t i = 0; i < bytes.size(); i += 2)
				w.push_back(static_cast<std::uint16_t>(bytes[i] | (bytes[i + 1] << 8)));
		};
		category(10, str);
		std::vector<std::uint8_t> general(32, 0);
		general[3] = 1; // name = string 1
		category(30, general);
		std::vector<std::uint8_t> sm;
		auto addSm = [&](std::uint16_t start, std::uint16_t len, std::uint8_t ctrl,
				 std::uint8_t en, std::uint8_t type) {
			const std::uint8_t b[8] = { static_cast<std::uint8_t>(start),
						    static_cast<std::uint8_t>(start >> 8),
						    static_cast<std::uint8_t>(len),
						    static_cast<std::uint8_t>(len >> 8),
						    ctrl, 0, en, type };
			sm.insert(sm.end(), b, b + 8);
		};
		if (cfg.coe) {
			addSm(0x1000, 128, 0x26, 1, 1);
			addSm(0x1080, 128, 0x22, 1, 2);
		}
		addSm(0x1100, 0, 0x64, 1, 3);
		addSm(0x1400, 0, 0x20, 1, 4);
		category(41, sm);
		w.push_back(0xFFFF);
		return w;
	}
	bool hasCoE() const override { return cfg.coe; }
	bool hasFoE() const override { return cfg.foe; }
	std::uint16_t dcAssignActivate() const override { return cfg.dcAssign; }
	std::chrono::nanoseconds mailboxLatency() const override { return cfg.mbxLatency; }

	// ---- ESC registers ----
	std::uint8_t escRead8(std::uint16_t reg) const override
	{
		return reg < regs.size() ? regs[reg] : 0;
	}
	void escWrite8(std::uint16_t reg, std::uint8_t value) override
	{
		if (reg < regs.size())
			regs[reg] = value;
	}

	// ---- AL state machine ----
	static bool validState(std::uint8_t s)
	{
		return s == 1 || s == 2 || s == 3 || s == 4 || s == 8;
	}
	static bool allowed(std::uint8_t from, std::uint8_t to)
	{
		if (from == to || to == 1)
			return true;
		switch (from) {
		case 1:
			return to == 2 || to == 3;
		case 2:
			return to == 4;
		case 3:
			return false;
		case 4:
			return to == 2 || to == 8;
		case 8:
			return to == 2 || to == 4;
		default:
			return false;
		}
	}
	void alControl(std::uint8_t value) override
	{
		alWrites.push_back(value);
		const std::uint8_t req = value & 0x0F;
		if (error) {
			if (!(value & 0x10))
				return; // an error must be acknowledged first
			error = false;
			code = 0;
		}
		if (!validState(req)) {
			error = true;
			code = sim::alcode::UnknownState;
			return;
		}
		if (!allowed(state, req)) {
			error = true;
			code = sim::alcode::InvalidStateChange;
			return;
		}
		if (auto r = refuse.find(req); r != refuse.end()) {
			error = true;
			code = r->second;
			return;
		}
		if (cfg.transitionTime.count() > 0 && req != state) {
			pending = req;
			pendingLeft = cfg.transitionTime;
			return;
		}
		state = req;
	}
	std::uint8_t alStatus() const override
	{
		return static_cast<std::uint8_t>(state | (error ? 0x10 : 0));
	}
	std::uint16_t alStatusCode() const override { return code; }

	void configureDc(std::uint16_t aa, std::uint32_t s0, std::uint32_t s1, std::int32_t shift) override
	{
		dcAssign = aa;
		dcSync0 = s0;
		dcSync1 = s1;
		dcShift = shift;
		dcConfigured = true;
	}

	// ---- CoE ----
	std::uint32_t sdoUpload(std::uint16_t index, std::uint8_t sub, bool complete,
				std::vector<std::uint8_t> &out) override
	{
		if (complete)
			return sim::abort::CompleteAccessUnsupported;
		const auto it = od.find({ index, sub });
		if (it == od.end())
			return sim::abort::NoObject;
		out = it->second;
		return 0;
	}
	std::uint32_t sdoDownload(std::uint16_t index, std::uint8_t sub, bool complete,
				  std::span<const std::uint8_t> data) override
	{
		if (complete)
			return sim::abort::CompleteAccessUnsupported;
		if (readOnly.count({ index, sub }))
			return sim::abort::ReadOnly;
		downloads.emplace_back(index, sub, std::vector<std::uint8_t>(data.begin(), data.end()));
		od[{ index, sub }] = std::vector<std::uint8_t>(data.begin(), data.end());
		return 0;
	}
	std::optional<sim::Emergency> popEmergency() override
	{
		if (emergencies.empty())
			return std::nullopt;
		sim::Emergency e = emergencies.front();
		emergencies.pop_front();
		return e;
	}

	// ---- FoE ----
	std::uint32_t foeRead(const std::string &name, std::vector<std::uint8_t> &out) override
	{
		const auto it = files.find(name);
		if (it == files.end())
			return 0x8001; // FoE "not found"
		out = it->second;
		return 0;
	}
	std::uint32_t foeWrite(const std::string &name, std::span<const std::uint8_t> data) override
	{
		files[name] = std::vector<std::uint8_t>(data.begin(), data.end());
		return 0;
	}

	// ---- process data ----
	std::vector<sim::Pdo> rxPdos() const override { return {}; }
	std::vector<sim::Pdo> txPdos() const override { return {}; }
	/// The RxPDO size: from the mapping objects when the master wrote
	/// 0x1C12 (PDO_CONFIG_SET), else the configured size.
	std::size_t outputBytes() const override { return mappedBytes(0x1C12, cfg.outBytes); }
	std::size_t inputBytes() const override { return mappedBytes(0x1C13, cfg.inBytes); }

	unsigned cycle(std::span<const std::uint8_t> outputs, bool outputsValid,
		       std::span<std::uint8_t> inputs, std::chrono::nanoseconds dt, bool sync0) override
	{
		cycles++;
		lastDt = dt;
		if (sync0)
			sync0Cycles++;
		progress(dt);
		unsigned wkc = 0;
		if (state == 4 || state == 8) {
			process(outputs, outputsValid, inputs);
			if (!inputs.empty())
				wkc += 1;
		}
		if (state == 8 && outputsValid && !outputs.empty()) {
			validCycles++;
			if (lastOutputs.size() == outputs.size())
				std::memcpy(lastOutputs.data(), outputs.data(), outputs.size());
			else
				lastOutputs.assign(outputs.begin(), outputs.end());
			if (logOutputs)
				outLog.push_back(lastOutputs);
			wkc += 2;
		}
		return wkc;
	}
	void idle(std::chrono::nanoseconds dt) override
	{
		idleTime += dt;
		progress(dt);
	}
	void reset() override
	{
		state = 1;
		error = false;
		code = 0;
	}

protected:
	/// Inputs of one cycle (SAFE-OP and OP).
	virtual void process(std::span<const std::uint8_t>, bool, std::span<std::uint8_t> inputs)
	{
		const std::size_t n = std::min(inputs.size(), inputPattern.size());
		if (n)
			std::memcpy(inputs.data(), inputPattern.data(), n);
		if (counterInput && !inputs.empty())
			inputs[0] = static_cast<std::uint8_t>(cycles);
	}

private:
	void progress(std::chrono::nanoseconds dt)
	{
		if (!pending)
			return;
		pendingLeft -= dt;
		if (pendingLeft.count() <= 0) {
			state = *pending;
			pending.reset();
		}
	}
	std::size_t mappedBytes(std::uint16_t assign, std::size_t dflt) const
	{
		const auto n = od.find({ assign, 0 });
		if (n == od.end() || n->second.empty())
			return dflt;
		std::size_t bits = 0;
		for (unsigned i = 1; i <= n->second[0]; i++) {
			const auto m = od.find({ assign, static_cast<std::uint8_t>(i) });
			if (m == od.end() || m->second.size() < 2)
				continue;
			const auto map = static_cast<std::uint16_t>(m->second[0] | (m->second[1] << 8));
			const auto c = od.find({ map, 0 });
			if (c == od.end() || c->second.empty())
				continue;
			for (unsigned j = 1; j <= c->second[0]; j++) {
				const auto e = od.find({ map, static_cast<std::uint8_t>(j) });
				if (e != od.end() && !e->second.empty())
					bits += e->second[0];
			}
		}
		return bits / 8;
	}
};

/// A CiA-402 drive: outputs = control word (2 bytes), inputs = status word.
class TestDrive : public TestSlave
{
public:
	explicit TestDrive(SlaveConfig c = driveConfig()) : TestSlave(std::move(c)) {}

	static SlaveConfig driveConfig()
	{
		SlaveConfig c;
		c.name = "TestDrive";
		c.outBytes = 4; // control word + 2 bytes the host owns
		c.inBytes = 4;	// status word + 2 bytes
		return c;
	}

	std::uint8_t cia = 0x00;	///< the 402 state code
	std::uint16_t lastCw = 0;
	std::vector<std::uint16_t> cwLog;	///< distinct control words seen
	bool faultResetSeen = false;

	void fault() { cia = 0x08; }

protected:
	void process(std::span<const std::uint8_t> outputs, bool valid,
		     std::span<std::uint8_t> inputs) override
	{
		if (state == 8 && valid && outputs.size() >= 2) {
			const auto cw = static_cast<std::uint16_t>(outputs[0] | (outputs[1] << 8));
			if (cwLog.empty() || cwLog.back() != cw)
				cwLog.push_back(cw);
			step(cw);
			lastCw = cw;
		} else if (cia == 0x00) {
			cia = 0x40; // self test done
		}
		std::uint16_t sw = cia;
		if (cia == 0x40)
			sw = 0x0040;
		sw = static_cast<std::uint16_t>(sw | 0x0200); // remote
		if (inputs.size() >= 2) {
			inputs[0] = static_cast<std::uint8_t>(sw);
			inputs[1] = static_cast<std::uint8_t>(sw >> 8);
		}
		if (inputs.size() >= 4) {
			inputs[2] = 0x5A;
			inputs[3] = 0xA5;
		}
	}

private:
	void step(std::uint16_t cw)
	{
		const bool rise = (cw & 0x80) && !(lastCw & 0x80);
		switch (cia) {
		case 0x00:
			cia = 0x40;
			break;
		case 0x40:
			if ((cw & 0x87) == 0x06)
				cia = 0x21;
			break;
		case 0x21:
			if ((cw & 0x8F) == 0x07)
				cia = 0x23;
			else if (!(cw & 0x02) || (cw & 0x06) == 0x02)
				cia = 0x40;
			break;
		case 0x23:
			if ((cw & 0x8F) == 0x0F)
				cia = 0x27;
			else if ((cw & 0x87) == 0x06)
				cia = 0x21;
			else if (!(cw & 0x02) || (cw & 0x06) == 0x02)
				cia = 0x40;
			break;
		case 0x27:
			if ((cw & 0x8F) == 0x07)
				cia = 0x23;
			else if ((cw & 0x87) == 0x06)
				cia = 0x21;
			else if (!(cw & 0x02))
				cia = 0x40;
			else if ((cw & 0x86) == 0x02)
				cia = 0x07;
			break;
		case 0x07:
			if (!(cw & 0x02))
				cia = 0x40;
			break;
		case 0x08:
			if (rise) {
				faultResetSeen = true;
				cia = 0x40;
			}
			break;
		default:
			break;
		}
	}
};

} // namespace simtest
