// SPDX-License-Identifier: MIT
//
// chip_master.cpp - the EtherCAT master inside the simulated ECM-XF: the
// network scan of ECAT_INIT_OP (station addresses, SII, sync managers,
// DC), the process image layout, the AL state machine requests of
// ECAT_STATE_SET, the master's view of the ECAT state, and the bus cycle
// (RxFIFO -> outputs, slave cycles, working counter, inputs -> TxFIFO,
// interrupt flags).

#include "chip_impl.hpp"

#include <algorithm>
#include <cstring>

namespace ecmxf::sim {

namespace {

/// AL control / status register bits.
constexpr std::uint8_t kAlError = 0x10;

/// Minimum DC cycle of the ECM-XF.
constexpr Nanos kMinCycle = 125 * kUs;
/// Bus cycle without DC (SYNC0 cycle 0): free run at 1 ms.
constexpr Nanos kFreeRunCycle = kMs;
/// How long the master waits for slaves to reach a requested state.
constexpr Nanos kStateTimeout = 5 * kSec;
/// How long INIT_OP waits for the Ethernet link.
constexpr Nanos kLinkWait = 3 * kSec;
/// DC "stable" after this much time of synchronised cycles.
constexpr Nanos kDcSettle = 100 * kMs;

/// SII (EEPROM) as bytes, for the category parser.
std::uint8_t siiByte(const std::vector<std::uint16_t> &w, std::size_t byte)
{
	const std::size_t i = byte / 2;
	if (i >= w.size())
		return 0xFF;
	return static_cast<std::uint8_t>(byte & 1 ? w[i] >> 8 : w[i]);
}

struct SiiInfo {
	std::string name;
	std::vector<SlaveRec::SmDesc> sms;
};

/// Parse the SII categories from word 0x40 on: strings (10), general
/// (30, the device name) and sync managers (41).
SiiInfo parseSii(const std::vector<std::uint16_t> &w)
{
	SiiInfo info;
	std::vector<std::string> strings;
	unsigned nameIdx = 0;
	std::size_t word = 0x40;
	for (int guard = 0; guard < 64 && word + 1 < w.size(); guard++) {
		const std::uint16_t type = w[word];
		const std::size_t size = w[word + 1];
		if (type == 0xFFFF)
			break;
		const std::size_t start = (word + 2) * 2; // first byte of the data
		if (type == 10) {
			const unsigned count = siiByte(w, start);
			std::size_t p = start + 1;
			for (unsigned i = 0; i < count && p < start + size * 2; i++) {
				const unsigned len = siiByte(w, p++);
				std::string s;
				for (unsigned k = 0; k < len; k++)
					s += static_cast<char>(siiByte(w, p++));
				strings.push_back(std::move(s));
			}
		} else if (type == 30) {
			nameIdx = siiByte(w, start + 3);
		} else if (type == 41) {
			for (std::size_t i = 0; i + 8 <= size * 2; i += 8) {
				SlaveRec::SmDesc d;
				const std::size_t b = start + i;
				d.start = static_cast<std::uint16_t>(siiByte(w, b) | siiByte(w, b + 1) << 8);
				d.len = static_cast<std::uint16_t>(siiByte(w, b + 2) | siiByte(w, b + 3) << 8);
				d.control = siiByte(w, b + 4);
				d.enable = siiByte(w, b + 6);
				d.type = siiByte(w, b + 7);
				info.sms.push_back(d);
			}
		}
		word += 2 + size;
	}
	if (nameIdx >= 1 && nameIdx <= strings.size())
		info.name = strings[nameIdx - 1];
	return info;
}

} // namespace

// ----------------------------------------------------------------------
// reachability, registers, SII
// ----------------------------------------------------------------------

bool Chip::Impl::reachable(std::size_t pos) const
{
	return !faults_.linkLost && pos < net_.size() &&
	       static_cast<long>(pos) != static_cast<long>(faults_.slaveDropped);
}

std::uint8_t Chip::Impl::regRead(std::size_t pos, std::uint16_t reg) const
{
	const Slave &s = net_.at(pos);
	switch (reg) {
	case 0x0010:
		return static_cast<std::uint8_t>(pos < stations_.size() ? stations_[pos] : 0);
	case 0x0011:
		return static_cast<std::uint8_t>(pos < stations_.size() ? stations_[pos] >> 8 : 0);
	case 0x0130:
		return s.alStatus();
	case 0x0131:
		return 0;
	case 0x0134:
		return static_cast<std::uint8_t>(s.alStatusCode());
	case 0x0135:
		return static_cast<std::uint8_t>(s.alStatusCode() >> 8);
	default:
		return s.escRead8(reg);
	}
}

void Chip::Impl::regWrite(std::size_t pos, std::uint16_t reg, std::uint8_t v)
{
	Slave &s = net_.at(pos);
	if (stations_.size() < net_.size())
		stations_.resize(net_.size(), 0);
	switch (reg) {
	case 0x0010:
		stations_[pos] = static_cast<std::uint16_t>((stations_[pos] & 0xFF00) | v);
		s.escWrite8(reg, v);
		return;
	case 0x0011:
		stations_[pos] = static_cast<std::uint16_t>((stations_[pos] & 0x00FF) | (v << 8));
		s.escWrite8(reg, v);
		return;
	case 0x0120:
		s.alControl(v);
		return;
	case 0x0121:
		return;
	default:
		s.escWrite8(reg, v);
		return;
	}
}

std::uint16_t Chip::Impl::siiWord(std::size_t pos, std::uint16_t addr,
				  const std::vector<std::uint16_t> &sii) const
{
	const auto o = eepromOverlay_.find(pos);
	if (o != eepromOverlay_.end()) {
		const auto w = o->second.find(addr);
		if (w != o->second.end())
			return w->second;
	}
	return addr < sii.size() ? sii[addr] : 0xFFFF;
}

// ----------------------------------------------------------------------
// INIT_OP
// ----------------------------------------------------------------------

bool Chip::Impl::startInitOp(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in)
{
	// byte 1: 0x81 (manual ver. 050); a lenient firmware takes 0x00 too
	// (ChipConfig::initOpLenient)
	if (in.size() < 16 || in[0] != 0xFF || (in[1] != 0x81 && !(cfg_.initOpLenient && in[1] == 0x00)))
		return false;
	initFifoOn_ = in[1] == 0x00;
	const std::uint16_t aa = le16(&in[2]);
	const std::uint32_t sync0 = le32(&in[4]);
	const std::uint32_t sync1 = le32(&in[8]);
	const auto shift = static_cast<std::int32_t>(le32(&in[12])); // 0x0C, not 0x12
	lrw_ = (h.reserved & ECMXF_RSV_LRW) != 0;
	busShift_ = (h.reserved & ECMXF_RSV_BUS_SHIFT) != 0;
	initParam_ = h.param;
	skipLinkWait_ = false;

	// the master stops the bus and forgets the network while it scans
	cyclesOn_ = false;
	initialized_ = false;
	layoutValid_ = false;
	wkcStopped_ = false;
	opReached_ = false;
	dcActive_ = false;
	slaves_.clear();
	slots_.clear();
	ecatState_ = ECMXF_ECAT_NONE;
	rxSize_ = txSize_ = 0;
	rebuildFifos();

	const Nanos t0 = now_;
	startJob(ECMXF_CMD_ECAT_INIT_OP, kMs,
		 [this, t0, aa, sync0, sync1, shift, phase = 0]() mutable {
			 switch (phase) {
			 case 0: // wait for the Ethernet link
				 if (faults_.linkLost) {
					 if (!skipLinkWait_ && now_ - t0 < kLinkWait) {
						 job_.next = now_ + 10 * kMs;
						 return AsyncJob::Step::Running;
					 }
					 linkAtInit_ = false;
					 return AsyncJob::Step::Failed;
				 }
				 phase = 1;
				 job_.next = now_ + 20 * kMs +
					     static_cast<Nanos>(std::min<std::size_t>(net_.size(), 128)) * kMs;
				 return AsyncJob::Step::Running;
			 case 1: // scan and configure
				 if (faults_.linkLost)
					 return AsyncJob::Step::Failed;
				 scanNetwork(aa, sync0, sync1, shift);
				 if (slaves_.empty())
					 return AsyncJob::Step::Failed;
				 phase = 2;
				 job_.next = now_ + kMs;
				 return AsyncJob::Step::Running;
			 default: { // wait until every slave is in INIT
				 bool all = true;
				 for (std::size_t p = 0; p < slaves_.size(); p++) {
					 if (!reachable(p)) {
						 refreshStates();
						 return AsyncJob::Step::Failed;
					 }
					 const std::uint8_t al = slaves_[p].slave->alStatus();
					 if ((al & 0x0F) != ECMXF_ECAT_INIT || (al & kAlError))
						 all = false;
				 }
				 return stateWaitStep(all, t0);
			 }
			 }
		 });
	return true;
}

void Chip::Impl::scanNetwork(std::uint16_t aa, std::uint32_t sync0, std::uint32_t sync1,
			     std::int32_t shift)
{
	// a slave that does not answer ends the chain: the scan finds the
	// slaves before it
	std::size_t n = std::min<std::size_t>(net_.size(), 128);
	if (faults_.slaveDropped >= 0 && static_cast<std::size_t>(faults_.slaveDropped) < n)
		n = static_cast<std::size_t>(faults_.slaveDropped);
	slaves_.assign(n, SlaveRec{});
	slots_.clear();
	stations_.assign(net_.size(), 0);
	for (std::size_t pos = 0; pos < n; pos++) {
		SlaveRec &r = slaves_[pos];
		r.slave = &net_.at(pos);
		const auto station = static_cast<std::uint16_t>(0x1001 + pos);
		regWrite(pos, 0x0010, static_cast<std::uint8_t>(station));
		regWrite(pos, 0x0011, static_cast<std::uint8_t>(station >> 8));

		const std::vector<std::uint16_t> sii = r.slave->sii();
		auto word = [&](std::uint16_t a) { return siiWord(pos, a, sii); };
		auto dword = [&](std::uint16_t a) {
			return static_cast<std::uint32_t>(word(a)) |
			       (static_cast<std::uint32_t>(word(static_cast<std::uint16_t>(a + 1))) << 16);
		};
		r.alias = word(0x0004);
		r.vendor = dword(0x0008);
		r.product = dword(0x000A);
		r.revision = dword(0x000C);
		r.serial = dword(0x000E);
		r.mbxOutOff = word(0x0018);
		r.mbxOutSize = word(0x0019);
		r.mbxInOff = word(0x001A);
		r.mbxInSize = word(0x001B);
		r.bootOutOff = word(0x0014);
		r.bootOutSize = word(0x0015);
		r.bootInOff = word(0x0016);
		r.bootInSize = word(0x0017);
		const SiiInfo info = parseSii(sii);
		r.name = info.name.empty() ? r.slave->identity().name : info.name;
		r.sms = info.sms;
		r.coe = r.slave->hasCoE();
		r.foe = r.slave->hasFoE();
		r.mbxPoll = r.mbxPollPending = r.coe;

		// back to INIT, acknowledging an error
		requestState(pos, ECMXF_ECAT_INIT);

		r.dcAssign = r.slave->dcAssignActivate() ? aa : 0;
		r.dcSync0 = sync0;
		r.dcSync1 = sync1;
		r.dcShift = shift;
	}
	applyDc();
	buildLayout();

	cycleNs_ = sync0 ? std::max<Nanos>(sync0, kMinCycle) : kFreeRunCycle;
	nextCycle_ = now_ + cycleNs_;
	cycleCount_ = 0;
	emcyEvery_ = static_cast<unsigned>(std::max<Nanos>(1, kMs / cycleNs_));
	cyclesOn_ = true;
	initialized_ = true;
	ethInit_ = true;
	linkAtInit_ = true;
	wkcErrCnt_ = 0;
	wkcConti_ = 0;
	// data byte 1 = 0x81: FIFO off until the host enables it; 0x00 (a
	// lenient firmware): on, as manual ver. 038's default
	fifoEnabled_ = initFifoOn_;
	ecatState_ = ECMXF_ECAT_INIT;
}

void Chip::Impl::applyDc()
{
	dcActive_ = false;
	for (SlaveRec &r : slaves_) {
		r.slave->configureDc(r.dcAssign, r.dcSync0, r.dcSync1, r.dcShift);
		r.sync0Active = (r.dcAssign & 0x0200) && r.dcSync0 > 0;
		dcActive_ = dcActive_ || r.sync0Active;
	}
	dcStableAt_ = now_ + kDcSettle;
	buildSlots();
}

void Chip::Impl::buildSlots()
{
	slots_.resize(slaves_.size());
	for (std::size_t pos = 0; pos < slaves_.size(); pos++) {
		const SlaveRec &r = slaves_[pos];
		slots_[pos] = CycleSlot{ r.slave, static_cast<std::uint32_t>(r.outOff),
					 static_cast<std::uint32_t>(r.outLen),
					 static_cast<std::uint32_t>(r.inOff),
					 static_cast<std::uint32_t>(r.inLen), r.sync0Active };
	}
}

void Chip::Impl::writeSm(std::size_t pos, unsigned sm, const SlaveRec::SmDesc &d)
{
	const auto base = static_cast<std::uint16_t>(0x0800 + 8 * sm);
	regWrite(pos, base, static_cast<std::uint8_t>(d.start));
	regWrite(pos, static_cast<std::uint16_t>(base + 1), static_cast<std::uint8_t>(d.start >> 8));
	regWrite(pos, static_cast<std::uint16_t>(base + 2), static_cast<std::uint8_t>(d.len));
	regWrite(pos, static_cast<std::uint16_t>(base + 3), static_cast<std::uint8_t>(d.len >> 8));
	regWrite(pos, static_cast<std::uint16_t>(base + 4), d.control);
	regWrite(pos, static_cast<std::uint16_t>(base + 6), d.enable);
}

void Chip::Impl::writeSyncManagers(std::size_t pos)
{
	SlaveRec &r = slaves_[pos];
	auto write = [&](unsigned sm, const SlaveRec::SmDesc &d) { writeSm(pos, sm, d); };
	// the SII's sync managers, with the process data lengths of the layout
	for (std::size_t sm = 0; sm < r.sms.size() && sm < 16; sm++) {
		SlaveRec::SmDesc d = r.sms[sm];
		if (d.type == 3)
			d.len = static_cast<std::uint16_t>(r.outLen);
		else if (d.type == 4)
			d.len = static_cast<std::uint16_t>(r.inLen);
		if (d.type == 3 || d.type == 4)
			d.enable = d.len ? 1 : 0;
		write(static_cast<unsigned>(sm), d);
	}
	// without a SyncM category: the mailbox from the SII header words
	if (r.sms.empty() && r.mbxOutSize && r.mbxInSize) {
		write(0, SlaveRec::SmDesc{ r.mbxOutOff, r.mbxOutSize, 0x26, 1, 1 });
		write(1, SlaveRec::SmDesc{ r.mbxInOff, r.mbxInSize, 0x22, 1, 2 });
	}
	for (unsigned sm = 0; sm < 16; sm++)
		if (r.smOverrideMask & (1u << sm))
			write(sm, r.smOverride[sm]);
}

void Chip::Impl::buildLayout()
{
	std::size_t out = 0, in = 0;
	inSlaves_ = outSlaves_ = 0;
	for (std::size_t pos = 0; pos < slaves_.size(); pos++) {
		SlaveRec &r = slaves_[pos];
		const std::size_t ol = r.daEnabled ? r.daOut : r.slave->outputBytes();
		const std::size_t il = r.daEnabled ? r.daIn : r.slave->inputBytes();
		r.outOff = out;
		r.outLen = ol;
		r.inOff = in;
		r.inLen = il;
		out += ol;
		in += il;
		if (il)
			inSlaves_++;
		if (ol)
			outSlaves_++;
		// MBX_STAT polling changes take effect here (RECONFIG_OP)
		r.mbxPoll = r.mbxPollPending;
		writeSyncManagers(pos);
	}
	rxSize_ = out;
	txSize_ = in;
	outImage_.assign(out, 0);
	inImage_.assign(in, 0);
	layoutValid_ = true;
	wkcStopped_ = false;
	wkcConti_ = 0;
	rebuildFifos();
	buildSlots();
}

// ----------------------------------------------------------------------
// AL states
// ----------------------------------------------------------------------

void Chip::Impl::requestState(std::size_t pos, std::uint8_t state)
{
	Slave &s = net_.at(pos);
	const SlaveRec &r = slaves_[pos];
	const unsigned cur = s.alStatus() & 0x0Fu;
	if (state == ECMXF_ECAT_BOOT && cur == ECMXF_ECAT_INIT && r.bootOutSize && r.bootInSize) {
		// INIT -> BOOT: SM0/SM1 carry the bootstrap mailbox (SII 0x14..0x17)
		writeSm(pos, 0, SlaveRec::SmDesc{ r.bootOutOff, r.bootOutSize, 0x26, 1, 1 });
		writeSm(pos, 1, SlaveRec::SmDesc{ r.bootInOff, r.bootInSize, 0x22, 1, 2 });
	} else if (state == ECMXF_ECAT_PREOP && cur == ECMXF_ECAT_INIT) {
		// back from BOOT (through INIT): the standard mailbox again
		writeSyncManagers(pos);
	}
	const std::uint8_t ack = (s.alStatus() & kAlError) ? kAlError : 0;
	regWrite(pos, 0x0120, static_cast<std::uint8_t>(state | ack));
}

std::uint8_t Chip::Impl::commonState() const
{
	if (slaves_.empty())
		return ECMXF_ECAT_INIT;
	std::uint8_t low = ECMXF_ECAT_OP;
	for (const SlaveRec &r : slaves_) {
		if (r.cachedAl & kAlError)
			return ECMXF_ECAT_ERROR;
		const std::uint8_t st = r.cachedAl & 0x0F;
		if (st == 0)
			return ECMXF_ECAT_ERROR; // not a state: the slave is broken
		low = std::min(low, st);
	}
	return low;
}

AsyncJob::Step Chip::Impl::stateWaitStep(bool reached, Nanos t0)
{
	if (reached) {
		refreshStates();
		return AsyncJob::Step::Done;
	}
	if (now_ - t0 > kStateTimeout) {
		refreshStates();
		return AsyncJob::Step::Failed;
	}
	job_.next = now_ + kMs;
	return AsyncJob::Step::Running;
}

void Chip::Impl::refreshStates()
{
	if (!initialized_)
		return;
	bool missing = faults_.linkLost;
	for (std::size_t pos = 0; pos < slaves_.size(); pos++) {
		if (!reachable(pos)) {
			missing = true;
			continue;
		}
		slaves_[pos].cachedAl = static_cast<std::uint8_t>(slaves_[pos].slave->alStatus() & 0x1F);
	}
	ecatState_ = missing ? static_cast<std::uint8_t>(ECMXF_ECAT_ERROR) : commonState();
	if (ecatState_ == ECMXF_ECAT_OP)
		opReached_ = true;
	else if (ecatState_ != ECMXF_ECAT_ERROR)
		opReached_ = false;
}

bool Chip::Impl::startStateSet(std::uint8_t sel, std::uint8_t state, bool check)
{
	if (!initialized_)
		return false;
	if (state != ECMXF_ECAT_INIT && state != ECMXF_ECAT_PREOP && state != ECMXF_ECAT_BOOT &&
	    state != ECMXF_ECAT_SAFEOP && state != ECMXF_ECAT_OP)
		return false;
	if (sel != 0xFF && sel >= slaves_.size())
		return false;
	const Nanos t0 = now_;
	const std::uint8_t code = check ? ECMXF_CMD_ECAT_STATE_CHECK : ECMXF_CMD_ECAT_STATE_SET;
	startJob(code, 500 * kUs, [this, sel, state, t0, phase = 0]() mutable {
		const std::size_t first = sel == 0xFF ? 0 : sel;
		const std::size_t last = sel == 0xFF ? slaves_.size() : sel + std::size_t{ 1 };
		if (phase == 0) {
			for (std::size_t p = first; p < last; p++) {
				if (!reachable(p)) { // no working counter on the AL control write
					refreshStates();
					return AsyncJob::Step::Failed;
				}
				requestState(p, state);
			}
			phase = 1;
			job_.next = now_ + kMs;
			return AsyncJob::Step::Running;
		}
		bool all = true;
		for (std::size_t p = first; p < last; p++) {
			if (!reachable(p)) {
				refreshStates();
				return AsyncJob::Step::Failed;
			}
			const std::uint8_t al = slaves_[p].slave->alStatus();
			if (al & kAlError) { // refused: AL status code says why
				refreshStates();
				return AsyncJob::Step::Failed;
			}
			if ((al & 0x0F) != state)
				all = false;
		}
		return stateWaitStep(all, t0);
	});
	return true;
}

// ----------------------------------------------------------------------
// the bus cycle
// ----------------------------------------------------------------------

std::uint16_t Chip::Impl::expectedWkc() const
{
	return static_cast<std::uint16_t>(inSlaves_ + 2 * outSlaves_);
}

void Chip::Impl::stopExchange()
{
	// WKC_CONTI_ERR_MAX exceeded: no more process data; ECM status bits
	// 4 (PDO configured) and 6 (FIFO enabled) read 0
	wkcStopped_ = true;
	fifoEnabled_ = false;
}

void Chip::Impl::busCycle()
{
	stats_.busCycles++;
	cycleCount_++;
	const Nanos dtNs = cycleNs_;
	const std::chrono::nanoseconds dt(dtNs);
	const bool link = !faults_.linkLost;
	const bool exchange = layoutValid_ && !wkcStopped_;

	// outputs of this cycle: the next RxFIFO frame, or the last outputs
	if (exchange && fifoEnabled_) {
		const std::size_t before = rxFifo_.count();
		if (rxFifo_.pop(outImage_.data())) {
			stats_.rxPopped++;
			rxPopped(before);
		} else {
			stats_.rxUnderruns++;
		}
	}
	if (exchange)
		apply402();

	unsigned wkc = 0;
	bool missing = !link;
	std::uint8_t *out = outImage_.data();
	std::uint8_t *in = inImage_.data();
	const std::size_t n = slots_.size();
	const auto dropped = static_cast<std::size_t>(faults_.slaveDropped); // -1: none
	for (std::size_t pos = 0; pos < n; pos++) {
		const CycleSlot &c = slots_[pos];
		if (!link || pos == dropped) {
			c.slave->idle(dt); // no frame reaches it
			missing = true;
			continue;
		}
		if (!exchange) {
			c.slave->idle(dt);
			continue;
		}
		wkc += c.slave->cycle(std::span<const std::uint8_t>(out + c.outOff, c.outLen), true,
				      std::span<std::uint8_t>(in + c.inOff, c.inLen), dt, c.sync0);
	}
	// slaves added to the network after the scan only see time pass
	for (std::size_t pos = n; pos < net_.size(); pos++)
		net_.at(pos).idle(dt);

	lastWkc_ = static_cast<std::uint16_t>(wkc);
	if (link)
		intFlags_ |= ECMXF_INT_ECAT_PKT; // the frame came back
	else
		linkAtInit_ = false;
	if (missing && initialized_)
		ecatState_ = ECMXF_ECAT_ERROR;

	if (exchange && opReached_) {
		if (wkc != expectedWkc()) {
			stats_.wkcErrors++;
			if (wkcErrCnt_ < 255)
				wkcErrCnt_++;
			if (wkcConti_ < 255)
				wkcConti_++;
			intFlags_ |= ECMXF_INT_WKC_ERR;
			if (wkcMax_ != 255 && wkcConti_ > wkcMax_)
				stopExchange();
		} else {
			wkcConti_ = 0;
		}
	}

	if (exchange && fifoEnabled_ && link) {
		const std::size_t before = txFifo_.count();
		stats_.txPushed++;
		if (txFifo_.pushDropOldest(inImage_.data()))
			stats_.txDropped++;
		txPushed(before);
	}

	if (cycleCount_ % emcyEvery_ == 0)
		pollEmergencies();
}

} // namespace ecmxf::sim
