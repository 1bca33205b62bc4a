// SPDX-License-Identifier: MIT
//
// slave_base.cpp - ESC registers, AL state machine, SDO, PDO configuration
// and process-data exchange shared by every slave model.

#include "slaves/slave_base.hpp"

#include <ecmxf/sim/slaves.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

#include "slaves/options.hpp"

namespace ecmxf::sim::slaves {

namespace {

using namespace std::chrono_literals;

constexpr std::size_t kMaxEmergencies = 16;
// S->O waits for the first outputs at most this long when the SM watchdog
// is disabled (0x0420 = 0).
constexpr std::chrono::nanoseconds kDefaultOpWait = 100ms;

bool knownState(unsigned s)
{
	return s == 1 || s == 2 || s == 3 || s == 4 || s == 8;
}

// Is to reachable from from in one request (ETG.1000.6 / AKD2G table)?
bool validPath(AlState from, AlState to)
{
	if (from == to)
		return true;
	switch (from) {
	case AlState::Init:
		return to == AlState::PreOp || to == AlState::Boot;
	case AlState::PreOp:
		return to == AlState::Init || to == AlState::SafeOp;
	case AlState::Boot:
		return to == AlState::Init;
	case AlState::SafeOp:
		return to == AlState::Init || to == AlState::PreOp || to == AlState::Op;
	case AlState::Op:
		return to == AlState::Init || to == AlState::PreOp || to == AlState::SafeOp;
	}
	return false;
}

// Copy a whole, byte-aligned value (1, 2, 4 or 8 bytes) with a fixed-size
// memcpy the compiler turns into one move.
inline void copyValue(void *dst, const void *src, std::uint32_t bytes)
{
	if (bytes == 4)
		std::memcpy(dst, src, 4);
	else if (bytes == 2)
		std::memcpy(dst, src, 2);
	else if (bytes == 1)
		std::memcpy(dst, src, 1);
	else
		std::memcpy(dst, src, bytes);
}

// Little-endian bit field access, LSB first (EtherCAT process image order).
inline void putBits(std::uint8_t *buf, std::uint32_t off, std::uint32_t bits, std::uint64_t v)
{
	if ((off & 7) == 0 && (bits & 7) == 0) {
		std::uint8_t *p = buf + (off >> 3);
		for (std::uint32_t i = 0; i < bits / 8; i++)
			p[i] = static_cast<std::uint8_t>(v >> (8 * i));
		return;
	}
	for (std::uint32_t i = 0; i < bits; i++) {
		const std::uint32_t b = off + i;
		const auto mask = static_cast<std::uint8_t>(1u << (b & 7));
		if ((v >> i) & 1)
			buf[b >> 3] = static_cast<std::uint8_t>(buf[b >> 3] | mask);
		else
			buf[b >> 3] = static_cast<std::uint8_t>(buf[b >> 3] & ~mask);
	}
}

inline std::uint64_t getBits(const std::uint8_t *buf, std::uint32_t off, std::uint32_t bits)
{
	std::uint64_t v = 0;
	if ((off & 7) == 0 && (bits & 7) == 0) {
		const std::uint8_t *p = buf + (off >> 3);
		for (std::uint32_t i = 0; i < bits / 8; i++)
			v |= std::uint64_t{ p[i] } << (8 * i);
		return v;
	}
	for (std::uint32_t i = 0; i < bits; i++) {
		const std::uint32_t b = off + i;
		if ((buf[b >> 3] >> (b & 7)) & 1)
			v |= std::uint64_t{ 1 } << i;
	}
	return v;
}

} // namespace

SlaveBase::SlaveBase(BaseConfig cfg)
	: cfg_(std::move(cfg)), reg_(std::make_unique<std::uint8_t[]>(esc::Size))
{
}

SlaveBase::~SlaveBase() = default;

std::uint16_t SlaveBase::checkTransition(AlState, AlState)
{
	return 0;
}

void SlaveBase::onAlChange(AlState, AlState, bool) {}

void SlaveBase::onPowerOn() {}

// ---- setup ----

void SlaveBase::addPdoMapping(std::uint16_t index, bool rx,
			      const std::vector<std::uint32_t> &defaults)
{
	if (defaults.size() > cfg_.maxEntriesPerPdo)
		throw std::logic_error("PDO default mapping longer than the PDO");
	PdoMap &m = maps_.emplace_back();
	m.index = index;
	m.rx = rx;
	m.entries.assign(cfg_.maxEntriesPerPdo, 0);
	const char *name = rx ? "RxPDO mapping" : "TxPDO mapping";
	od_.record(index, name, Access::RWPreOp, &m.count)
		.def(static_cast<std::int64_t>(defaults.size()))
		.onCheck([this, &m](std::uint64_t v) { return checkMapCount(m, v); })
		.onAfter([this] { rebuildMapping(); });
	for (unsigned i = 1; i <= cfg_.maxEntriesPerPdo; i++) {
		od_.sub(index, static_cast<std::uint8_t>(i), "Mapping entry", DataType::U32,
			Access::RWPreOp, &m.entries[i - 1])
			.def(i <= defaults.size() ? defaults[i - 1] : 0)
			.onCheck([this, &m](std::uint64_t v) -> std::uint32_t {
				if (m.count != 0)
					return abort::SubindexCannotBeWritten;
				return checkMapEntry(m.rx, static_cast<std::uint32_t>(v));
			});
	}
}

void SlaveBase::addIdentityObjects()
{
	using DT = DataType;
	using A = Access;
	od_.sub(0x1018, 1, "Vendor ID", DT::U32, A::RO).def(cfg_.identity.vendorId);
	od_.sub(0x1018, 2, "Product code", DT::U32, A::RO).def(cfg_.identity.productCode);
	od_.sub(0x1018, 3, "Revision", DT::U32, A::RO).def(cfg_.identity.revision);
	od_.sub(0x1018, 4, "Serial number", DT::U32, A::RO).def(cfg_.identity.serial);
	const std::uint8_t smTypes[] = { 1, 2, 3, 4 };
	for (std::uint8_t s = 1; s <= 4; s++)
		od_.sub(0x1C00, s, "Sync manager type", DT::U8, A::RO).def(smTypes[s - 1]);
}

void SlaveBase::addPdoAssignment(bool rx, const std::vector<std::uint16_t> &defaults)
{
	PdoAssign &a = rx ? rxAssign_ : txAssign_;
	const auto n = static_cast<std::size_t>(
		std::count_if(maps_.begin(), maps_.end(), [rx](const PdoMap &m) { return m.rx == rx; }));
	if (defaults.size() > n)
		throw std::logic_error("PDO default assignment longer than the PDO list");
	a.pdos.assign(n, 0);
	const std::uint16_t index = rx ? 0x1C12 : 0x1C13;
	od_.record(index, rx ? "RxPDO assign" : "TxPDO assign", Access::RWPreOp, &a.count)
		.def(static_cast<std::int64_t>(defaults.size()))
		.onCheck([this, rx](std::uint64_t v) { return checkAssignCount(rx, v); })
		.onAfter([this] { rebuildMapping(); });
	for (std::size_t i = 1; i <= n; i++) {
		od_.sub(index, static_cast<std::uint8_t>(i), "PDO index", DataType::U16,
			Access::RWPreOp, &a.pdos[i - 1])
			.def(i <= defaults.size() ? defaults[i - 1] : 0)
			.onCheck([this, rx, &a](std::uint64_t v) -> std::uint32_t {
				if (a.count != 0)
					return abort::SubindexCannotBeWritten;
				if (v == 0)
					return 0;
				const PdoMap *m = findMap(static_cast<std::uint16_t>(v));
				return m && m->rx == rx ? 0 : abort::ValueRange;
			});
	}
}

void SlaveBase::identify(OptionReader &o, unsigned position, std::uint32_t product,
			 std::uint32_t revision, const std::string &defaultName)
{
	cfg_.typeName = o.type();
	cfg_.identity.vendorId = model::kVendorId;
	cfg_.identity.productCode = product;
	cfg_.identity.revision = revision;
	o.common(position, cfg_.identity, cfg_.alias, defaultName);
}

void SlaveBase::readMailboxLatency(OptionReader &o, std::int64_t defaultUs)
{
	cfg_.mailboxLatency = std::chrono::microseconds(
		o.integer("mailbox_latency_us", 0, 10'000'000).value_or(defaultUs));
}

void SlaveBase::finishSetup()
{
	SiiDescription d;
	d.pdiControl = cfg_.pdiControl;
	d.alias = cfg_.alias;
	d.identity = cfg_.identity;
	d.group = cfg_.siiGroup;
	d.order = cfg_.siiOrder;
	d.coeDetails = cfg_.coeDetails;
	d.ds402Channels = cfg_.ds402Channels;
	if (cfg_.coe || cfg_.foe) {
		d.stdRxOffset = cfg_.mbxOutStart;
		d.stdRxSize = cfg_.mbxOutLen;
		d.stdTxOffset = cfg_.mbxInStart;
		d.stdTxSize = cfg_.mbxInLen;
		d.protocols = static_cast<std::uint16_t>((cfg_.coe ? mbxproto::CoE : 0) |
							 (cfg_.foe ? mbxproto::FoE : 0));
		d.foeDetails = cfg_.foe ? 1 : 0;
		if (cfg_.bootMailbox) {
			d.bootRxOffset = cfg_.bootOutStart;
			d.bootRxSize = cfg_.bootOutLen;
			d.bootTxOffset = cfg_.bootInStart;
			d.bootTxSize = cfg_.bootInLen;
		}
	}
	od_.resetToDefaults(); // the default mapping decides the SM lengths below
	rebuildMapping();
	std::vector<SiiSyncManager> sms;
	if (cfg_.coe || cfg_.foe) {
		sms.push_back({ cfg_.mbxOutStart, cfg_.mbxOutLen, 0x26, true, 1 });
		sms.push_back({ cfg_.mbxInStart, cfg_.mbxInLen, 0x22, true, 2 });
		d.fmmus = { 1, 2, 3 };
	} else {
		d.fmmus = { 1, 2 };
	}
	sms.push_back({ cfg_.pdOutStart, static_cast<std::uint16_t>(outBytes_), 0x64,
			outBytes_ > 0, 3 });
	sms.push_back({ cfg_.pdInStart, static_cast<std::uint16_t>(inBytes_), 0x20, inBytes_ > 0,
			4 });
	d.syncManagers = sms;
	for (bool rx : { true, false }) {
		for (const Pdo &p : pdos(rx)) {
			SiiPdo sp;
			sp.index = p.index;
			sp.sm = rx ? cfg_.pdOutSm : cfg_.pdInSm;
			for (const PdoEntry &e : p.entries) {
				const Entry *oe = od_.find(e.index, e.subindex);
				sp.entries.push_back({ e.index, e.subindex,
						       oe ? typeInfo(oe->type).coeIndex : std::uint8_t{ 0 },
						       e.bits });
			}
			(rx ? d.rxPdos : d.txPdos).push_back(sp);
		}
	}
	eeprom_ = buildSii(d);
	reset();
}

// ---- power-on ----

void SlaveBase::reset()
{
	std::fill_n(reg_.get(), esc::Size, std::uint8_t{ 0 });
	reg_[esc::Type] = cfg_.escType;
	reg_[esc::Revision] = 0x00;
	setReg16(esc::Build, 0x0002);
	reg_[esc::FmmusSupported] = 8;
	reg_[esc::SmsSupported] = 8;
	reg_[esc::RamSize] = 8;
	reg_[esc::PortDescriptor] = 0x0F;
	setReg16(esc::Features, cfg_.escFeatures);
	setReg16(esc::DlControl, 0x0001);

	const bool eepromOk = eeprom_.size() >= 8 &&
			      (eeprom_[siiword::Checksum] & 0xFF) == siiChecksum(eeprom_.data());
	const std::uint16_t eepromAlias = eepromOk ? eeprom_[siiword::StationAlias] : 0;
	// DL status: PDI operational (EEPROM loaded), port 0 link and
	// communication, port 1 loop closed.
	setReg16(esc::DlStatus, static_cast<std::uint16_t>((eepromOk ? 0x0001 : 0) | 0x0010 |
							   0x0200 | 0x0400));
	if (eepromOk) {
		setReg16(esc::PdiControl, eeprom_[siiword::PdiControl]);
		setReg16(esc::PdiConfig, eeprom_[siiword::PdiConfig]);
	}
	setReg16(esc::WdDivider, 0x09C2);  // 100 us
	setReg16(esc::WdTimePdi, 1000);
	setReg16(esc::WdTimePd, 1000);     // 100 ms
	wdExpired_ = false;
	setReg16(esc::SiiControl, static_cast<std::uint16_t>(0x0040 | (eepromOk ? 0 : 0x0800)));
	updateWatchdogTime();

	localTimeNs_ = 0;
	state_ = AlState::Init;
	alErr_ = false;
	alCode_ = 0;
	pendingOp_ = false;
	pendingFor_ = {};
	sinceOutputs_ = {};
	outputsSeen_ = false;
	dcShiftNs_ = 0;
	emcy_.clear();

	od_.resetToDefaults();
	od_.applyStored(stored_);
	rebuildMapping();
	onPowerOn();
	setReg16(esc::StationAlias, powerOnAlias(eepromAlias));
	publishAl();
}

// ---- registers ----

std::uint16_t SlaveBase::reg16(std::uint16_t at) const
{
	return static_cast<std::uint16_t>(reg_[at] | reg_[at + 1u] << 8);
}

std::uint32_t SlaveBase::reg32(std::uint16_t at) const
{
	return static_cast<std::uint32_t>(reg16(at)) |
	       static_cast<std::uint32_t>(reg16(static_cast<std::uint16_t>(at + 2))) << 16;
}

void SlaveBase::setReg16(std::uint16_t at, std::uint16_t v)
{
	reg_[at] = static_cast<std::uint8_t>(v & 0xFF);
	reg_[at + 1u] = static_cast<std::uint8_t>(v >> 8);
}

std::uint8_t SlaveBase::escRead8(std::uint16_t reg) const
{
	if (reg >= esc::Size)
		return 0;
	if (reg == esc::WdStatusPd)
		return wdExpired_ ? 0x00 : 0x01;
	if (reg >= esc::DcSystemTime && reg < esc::DcSystemTime + 8)
		return static_cast<std::uint8_t>(localTimeNs_ >> (8 * (reg - esc::DcSystemTime)));
	return reg_[reg];
}

void SlaveBase::escWrite8(std::uint16_t reg, std::uint8_t value)
{
	if (reg >= esc::Size)
		return;
	// Read-only for the master: information, alias, DL/AL status, system time.
	if (reg < esc::StationAddress || reg == esc::StationAlias ||
	    reg == esc::StationAlias + 1 || (reg >= esc::DlStatus && reg < esc::DlStatus + 2) ||
	    (reg >= esc::AlStatus && reg < esc::AlStatus + 6) ||
	    (reg >= esc::PdiControl && reg < 0x0200) ||
	    (reg >= esc::DcSystemTime && reg < esc::DcSystemTime + 8))
		return;
	if (reg == esc::AlControl) {
		alControl(value);
		return;
	}
	if (reg == esc::SiiControl + 1) {
		siiCommand(value);
		return;
	}
	if (reg == esc::SiiControl) {
		reg_[reg] = static_cast<std::uint8_t>((reg_[reg] & 0xFE) | (value & 0x01));
		return;
	}
	reg_[reg] = value;
	if ((reg >= esc::WdDivider && reg < esc::WdDivider + 2) ||
	    (reg >= esc::WdTimePd && reg < esc::WdTimePd + 2))
		updateWatchdogTime();
}

void SlaveBase::updateWatchdogTime()
{
	const std::int64_t unitNs = (std::int64_t{ reg16(esc::WdDivider) } + 2) * 40;
	wdTime_ = std::chrono::nanoseconds(unitNs * reg16(esc::WdTimePd));
}

// SII EEPROM interface: 0x0502 bits 8..10 = command (1 read, 2 write,
// 4 reload), executed at once (never busy). Reads deliver 8 bytes.
void SlaveBase::siiCommand(std::uint8_t cmd)
{
	const std::uint32_t addr = reg32(esc::SiiAddress);
	std::uint8_t status = 0;
	switch (cmd & 0x07) {
	case 1:
		for (unsigned i = 0; i < 4; i++) {
			const std::uint32_t a = addr + i;
			const std::uint16_t w = a < eeprom_.size() ? eeprom_[a] : 0xFFFF;
			setReg16(static_cast<std::uint16_t>(esc::SiiData + 2 * i), w);
		}
		if (addr >= eeprom_.size())
			status |= 0x20; // acknowledge/command error
		break;
	case 2:
		if (!(reg_[esc::SiiControl] & 0x01))
			status |= 0x40; // write enable error
		else if (addr >= eeprom_.size())
			status |= 0x20;
		else
			eeprom_[addr] = reg16(esc::SiiData);
		reg_[esc::SiiControl] &= 0xFE;
		break;
	case 4: {
		const bool ok = (eeprom_[siiword::Checksum] & 0xFF) == siiChecksum(eeprom_.data());
		if (ok)
			setReg16(esc::StationAlias, eeprom_[siiword::StationAlias]);
		else
			status |= 0x08; // checksum error
		break;
	}
	default:
		if (cmd & 0x07)
			status |= 0x20;
		break;
	}
	reg_[esc::SiiControl + 1] = status;
}

// ---- DC ----

bool SlaveBase::sync0Active() const
{
	return (reg_[esc::DcActivation] & 0x03) == 0x03;
}

std::uint32_t SlaveBase::sync0CycleNs() const
{
	return reg32(esc::DcSync0Cycle);
}

void SlaveBase::configureDc(std::uint16_t assignActivate, std::uint32_t sync0CycleNs,
			    std::uint32_t sync1CycleNs, std::int32_t shiftNs)
{
	setReg16(esc::DcCyclicUnitControl, assignActivate);
	setReg16(esc::DcSync0Cycle, static_cast<std::uint16_t>(sync0CycleNs & 0xFFFF));
	setReg16(esc::DcSync0Cycle + 2, static_cast<std::uint16_t>(sync0CycleNs >> 16));
	setReg16(esc::DcSync1Cycle, static_cast<std::uint16_t>(sync1CycleNs & 0xFFFF));
	setReg16(esc::DcSync1Cycle + 2, static_cast<std::uint16_t>(sync1CycleNs >> 16));
	dcShiftNs_ = shiftNs;
	if (state_ == AlState::Op) {
		if (const std::uint16_t code = checkTransition(AlState::SafeOp, AlState::Op))
			alError(AlState::SafeOp, code);
	}
}

// ---- AL state machine ----

std::uint8_t SlaveBase::alStatus() const
{
	return static_cast<std::uint8_t>(static_cast<unsigned>(state_) | (alErr_ ? 0x10u : 0u));
}

void SlaveBase::publishAl()
{
	reg_[esc::AlStatus] = alStatus();
	reg_[esc::AlStatus + 1] = 0;
	setReg16(esc::AlStatusCode, alCode_);
}

void SlaveBase::enterState(AlState to)
{
	const AlState from = state_;
	state_ = to;
	pendingOp_ = false;
	publishAl();
	if (from != to)
		onAlChange(from, to, false);
}

void SlaveBase::alError(AlState to, std::uint16_t code)
{
	const AlState from = state_;
	state_ = to;
	alErr_ = true;
	alCode_ = code;
	pendingOp_ = false;
	publishAl();
	if (from != to)
		onAlChange(from, to, true);
}

void SlaveBase::alControl(std::uint8_t value)
{
	reg_[esc::AlControl] = value;
	const bool ack = value & 0x10;
	const unsigned req = value & 0x0F;
	const auto cur = static_cast<unsigned>(state_);

	if (ack) {
		alErr_ = false;
		alCode_ = 0;
	} else if (alErr_ && req > cur) {
		return; // an unacknowledged error blocks requests for higher states
	}
	if (!knownState(req)) {
		alError(state_ == AlState::Op ? AlState::SafeOp : state_, alcode::UnknownState);
		return;
	}
	const auto to = static_cast<AlState>(req);
	if (to == state_) {
		if (pendingOp_ && to == AlState::SafeOp)
			pendingOp_ = false;
		publishAl();
		return;
	}
	if (!validPath(state_, to)) {
		alError(state_, alcode::InvalidStateChange);
		return;
	}
	if (req < cur) { // downward: always possible, an error stays until acknowledged
		enterState(to);
		return;
	}
	std::uint16_t code = 0;
	switch (to) {
	case AlState::PreOp:
		code = checkMailboxSm(false);
		break;
	case AlState::Boot:
		code = cfg_.bootMailbox ? checkMailboxSm(true) : alcode::InvalidMbxBootConfig;
		break;
	case AlState::SafeOp:
		code = checkMappingLimits();
		if (!code)
			code = checkProcessDataSm();
		if (!code)
			code = checkTransition(AlState::PreOp, AlState::SafeOp);
		break;
	case AlState::Op:
		code = checkTransition(AlState::SafeOp, AlState::Op);
		if (!code && outBytes_ > 0) {
			const auto wait = wdTime_.count() > 0 ? wdTime_ : kDefaultOpWait;
			if (!outputsSeen_ || sinceOutputs_ > wait) {
				// Wait in SAFE-OP for the first valid outputs.
				if (!pendingOp_) {
					pendingOp_ = true;
					pendingFor_ = {};
				}
				publishAl();
				return;
			}
		}
		break;
	case AlState::Init:
		break;
	}
	if (code) {
		alError(state_, code);
		return;
	}
	enterState(to);
}

// SM0/SM1 as configured by the master, checked only if the master wrote
// them (an all-zero SM means "left to the chip").
std::uint16_t SlaveBase::checkMailboxSm(bool boot) const
{
	if (!cfg_.coe && !cfg_.foe)
		return 0;
	auto configured = [&](unsigned sm) {
		for (unsigned i = 0; i < 8; i++)
			if (reg_[esc::Sm0 + 8 * sm + i])
				return true;
		return false;
	};
	auto ok = [&](unsigned sm, std::uint16_t start, std::uint16_t len) {
		const auto base = static_cast<std::uint16_t>(esc::Sm0 + 8 * sm);
		return !configured(sm) ||
		       (reg16(base) == start && reg16(static_cast<std::uint16_t>(base + 2)) == len);
	};
	const bool good = boot ? ok(0, cfg_.bootOutStart, cfg_.bootOutLen) &&
					 ok(1, cfg_.bootInStart, cfg_.bootInLen)
			       : ok(0, cfg_.mbxOutStart, cfg_.mbxOutLen) &&
					 ok(1, cfg_.mbxInStart, cfg_.mbxInLen);
	if (good)
		return 0;
	return boot ? alcode::InvalidMbxBootConfig : alcode::InvalidMbxConfig;
}

std::uint16_t SlaveBase::checkProcessDataSm() const
{
	auto lengthOk = [&](unsigned sm, std::size_t bytes) {
		const auto base = static_cast<std::uint16_t>(esc::Sm0 + 8 * sm);
		bool configured = false;
		for (unsigned i = 0; i < 8; i++)
			configured |= reg_[base + i] != 0;
		return !configured || reg16(static_cast<std::uint16_t>(base + 2)) == bytes;
	};
	if (!lengthOk(cfg_.pdOutSm, outBytes_))
		return alcode::InvalidOutputConfig;
	if (!lengthOk(cfg_.pdInSm, inBytes_))
		return alcode::InvalidInputConfig;
	return 0;
}

std::uint16_t SlaveBase::checkMappingLimits() const
{
	if (!rxMapValid_ || rxBits_ % 8 != 0 || outBytes_ > cfg_.maxOutBytes)
		return alcode::InvalidOutputMapping;
	if (!txMapValid_ || txBits_ % 8 != 0 || inBytes_ > cfg_.maxInBytes)
		return alcode::InvalidInputMapping;
	return 0;
}

// ---- CoE ----

std::uint32_t SlaveBase::sdoUpload(std::uint16_t index, std::uint8_t subindex, bool complete,
				   std::vector<std::uint8_t> &out)
{
	out.clear();
	if (!cfg_.coe)
		return abort::NoObjectDictionary;
	if (state_ == AlState::Init || state_ == AlState::Boot)
		return abort::CannotTransferState;
	return od_.upload(index, subindex, complete, out);
}

std::uint32_t SlaveBase::sdoDownload(std::uint16_t index, std::uint8_t subindex, bool complete,
				     std::span<const std::uint8_t> data)
{
	if (!cfg_.coe)
		return abort::NoObjectDictionary;
	if (state_ == AlState::Init || state_ == AlState::Boot)
		return abort::CannotTransferState;
	return od_.download(index, subindex, complete, data, state_, cfg_.clampOnRange);
}

std::optional<Emergency> SlaveBase::popEmergency()
{
	if (emcy_.empty())
		return std::nullopt;
	Emergency e = emcy_.front();
	emcy_.pop_front();
	return e;
}

void SlaveBase::pushEmergency(const Emergency &e)
{
	if (emcy_.size() >= kMaxEmergencies)
		emcy_.pop_front();
	emcy_.push_back(e);
}

void SlaveBase::saveParameters()
{
	stored_ = od_.storableValues();
}

void SlaveBase::restoreDefaults(bool immediate)
{
	if (immediate)
		od_.restoreStorableDefaults();
	stored_.clear();
}

// ---- PDO configuration ----

const SlaveBase::PdoMap *SlaveBase::findMap(std::uint16_t index) const
{
	for (const auto &m : maps_)
		if (m.index == index)
			return &m;
	return nullptr;
}

std::uint32_t SlaveBase::checkMapEntry(bool rx, std::uint32_t value) const
{
	if (value == 0)
		return 0;
	const auto index = static_cast<std::uint16_t>(value >> 16);
	const auto sub = static_cast<std::uint8_t>((value >> 8) & 0xFF);
	const auto bits = value & 0xFF;
	if (index < 0x0008) // gap (index 0) or dummy data-type entry
		return bits > 0 ? 0 : abort::NotMappable;
	const Entry *e = od_.find(index, sub);
	if (!e || !(e->pdo & (rx ? RxPdo : TxPdo)) || typeInfo(e->type).bits != bits)
		return abort::NotMappable;
	return 0;
}

std::uint32_t SlaveBase::checkMapCount(const PdoMap &m, std::uint64_t count) const
{
	if (count > m.entries.size())
		return abort::ValueTooHigh;
	std::uint32_t bits = 0;
	for (std::size_t i = 0; i < count; i++) {
		const std::uint32_t v = m.entries[i];
		if (v == 0 || checkMapEntry(m.rx, v))
			return abort::NotMappable;
		bits += v & 0xFF;
	}
	if (bits > cfg_.maxPdoBytes * 8)
		return abort::PdoLengthExceeded;
	return 0;
}

std::uint32_t SlaveBase::checkAssignCount(bool rx, std::uint64_t count) const
{
	const PdoAssign &a = rx ? rxAssign_ : txAssign_;
	if (count > a.pdos.size())
		return abort::ValueTooHigh;
	for (std::size_t i = 0; i < count; i++) {
		const PdoMap *m = findMap(a.pdos[i]);
		if (!m || m->rx != rx)
			return abort::ValueRange;
		for (std::size_t j = 0; j < i; j++)
			if (a.pdos[j] == a.pdos[i])
				return abort::ValueRange;
	}
	return 0;
}

void SlaveBase::rebuildMapping()
{
	for (bool rx : { true, false }) {
		const PdoAssign &a = rx ? rxAssign_ : txAssign_;
		auto &slots = rx ? rxSlots_ : txSlots_;
		bool valid = true;
		std::uint32_t bit = 0;
		slots.clear();
		for (std::size_t i = 0; i < a.count && i < a.pdos.size(); i++) {
			const PdoMap *m = findMap(a.pdos[i]);
			if (!m || m->rx != rx) {
				valid = false;
				continue;
			}
			for (std::size_t k = 0; k < m->count && k < m->entries.size(); k++) {
				const std::uint32_t v = m->entries[k];
				const auto index = static_cast<std::uint16_t>(v >> 16);
				const auto sub = static_cast<std::uint8_t>((v >> 8) & 0xFF);
				const std::uint32_t bits = v & 0xFF;
				Slot s;
				s.bitOffset = bit;
				s.bits = bits;
				if (index >= 0x0008) {
					Entry *e = od_.find(index, sub);
					if (e && typeInfo(e->type).bits == bits)
						s.bind = e->bind;
					else
						valid = false;
				}
				s.bytes = bits / 8;
				s.direct = std::endian::native == std::endian::little && s.bind.ptr &&
					   s.bind.type != DataType::Bool && bit % 8 == 0 && bits % 8 == 0;
				slots.push_back(s);
				bit += bits;
			}
		}
		if (rx) {
			rxBits_ = bit;
			outBytes_ = (bit + 7) / 8;
			rxMapValid_ = valid;
		} else {
			txBits_ = bit;
			inBytes_ = (bit + 7) / 8;
			txMapValid_ = valid;
		}
	}
}

std::vector<Pdo> SlaveBase::pdos(bool rx) const
{
	std::vector<Pdo> out;
	const PdoAssign &a = rx ? rxAssign_ : txAssign_;
	for (std::size_t i = 0; i < a.count && i < a.pdos.size(); i++) {
		const PdoMap *m = findMap(a.pdos[i]);
		if (!m)
			continue;
		Pdo p;
		p.index = m->index;
		for (std::size_t k = 0; k < m->count && k < m->entries.size(); k++) {
			const std::uint32_t v = m->entries[k];
			p.entries.push_back({ static_cast<std::uint16_t>(v >> 16),
					      static_cast<std::uint8_t>((v >> 8) & 0xFF),
					      static_cast<std::uint8_t>(v & 0xFF) });
		}
		out.push_back(std::move(p));
	}
	return out;
}

std::vector<Pdo> SlaveBase::rxPdos() const
{
	return pdos(true);
}

std::vector<Pdo> SlaveBase::txPdos() const
{
	return pdos(false);
}

// ---- process data ----

void SlaveBase::advanceTime(std::chrono::nanoseconds dt, bool outputsValid)
{
	localTimeNs_ += static_cast<std::uint64_t>(dt.count() > 0 ? dt.count() : 0);
	if (outputsValid) {
		sinceOutputs_ = {};
		outputsSeen_ = true;
		wdExpired_ = false;
	} else {
		sinceOutputs_ += dt;
	}
	if (state_ == AlState::SafeOp && pendingOp_) {
		if (outputsValid) {
			enterState(AlState::Op);
		} else {
			pendingFor_ += dt;
			const auto wait = wdTime_.count() > 0 ? wdTime_ : kDefaultOpWait;
			if (pendingFor_ > wait)
				alError(AlState::SafeOp, alcode::SmWatchdog);
		}
	}
	// SM watchdog: outputs stopped arriving in OP.
	if (state_ == AlState::Op && outBytes_ > 0 && wdTime_.count() > 0 &&
	    sinceOutputs_ > wdTime_) {
		wdExpired_ = true;
		alError(AlState::SafeOp, alcode::SmWatchdog);
	}
}

unsigned SlaveBase::cycle(std::span<const std::uint8_t> outputs, bool outputsValid,
			  std::span<std::uint8_t> inputs, std::chrono::nanoseconds dt, bool)
{
	advanceTime(dt, outputsValid);
	unsigned wkc = 0;
	bool applied = false;
	if (state_ == AlState::Op && outputsValid && outBytes_ > 0 &&
	    outputs.size() >= outBytes_) {
		const std::uint8_t *buf = outputs.data();
		for (const Slot &s : rxSlots_) {
			if (s.direct)
				copyValue(s.bind.ptr, buf + s.bitOffset / 8, s.bytes);
			else if (s.bind.ptr)
				storeRaw(s.bind, getBits(buf, s.bitOffset, s.bits));
		}
		applied = true;
		wkc += 2;
	}
	step(dt, applied);
	if ((state_ == AlState::SafeOp || state_ == AlState::Op) && inBytes_ > 0 &&
	    inputs.size() >= inBytes_) {
		std::uint8_t *buf = inputs.data();
		for (const Slot &s : txSlots_) {
			if (s.direct)
				copyValue(buf + s.bitOffset / 8, s.bind.ptr, s.bytes);
			else
				putBits(buf, s.bitOffset, s.bits, s.bind.ptr ? loadRaw(s.bind) : 0);
		}
		wkc += 1;
	}
	return wkc;
}

void SlaveBase::idle(std::chrono::nanoseconds dt)
{
	advanceTime(dt, false);
	step(dt, false);
}

} // namespace ecmxf::sim::slaves
