// SPDX-License-Identifier: MIT
//
// chip_mailbox.cpp - the acyclic services of the simulated ECM-XF: CoE
// SDO transfers (ECAT_SDO_REQ, PDO configuration through SDO), the slave
// EEPROM (EEPROM_REQ), raw datagrams (RAW_ECAT_FUNC_REQ), FoE and its
// staging flash (FOE_FUNC_REQ), the receive mailbox (RECV_MAILBOX,
// MBX_STAT) and CoE emergencies (COE_EMERGENCY).
//
// Each async service checks its parameters when it starts (bad ones are a
// command error, nothing runs), then does its work when the virtual time
// it takes on the bus has passed.

#include "chip_impl.hpp"

#include <algorithm>
#include <cstring>

namespace ecmxf::sim {

namespace {

using Step = AsyncJob::Step;

constexpr Nanos kDefaultSdoTimeout = kSec;	///< SDO timeout field 0
constexpr Nanos kDefaultTimeout = 100 * kMs;	///< EEPROM/raw timeout field 0
constexpr std::size_t kMaxSdo = 256;
constexpr std::uint32_t kFlashSize = 0x40000;

/// The timeout of a request in virtual ns (field in µs, 0 = default).
Nanos timeoutOf(std::uint32_t us, Nanos dflt)
{
	return us ? static_cast<Nanos>(us) * kUs : dflt;
}

struct SdoWrite {
	std::uint16_t index;
	std::uint8_t sub;
	std::vector<std::uint8_t> data;
};

std::vector<std::uint8_t> le(std::uint32_t v, std::size_t n)
{
	std::vector<std::uint8_t> b(n);
	for (std::size_t i = 0; i < n; i++)
		b[i] = static_cast<std::uint8_t>(v >> (8 * i));
	return b;
}

std::uint32_t fromLe(const std::vector<std::uint8_t> &b)
{
	std::uint32_t v = 0;
	for (std::size_t i = 0; i < b.size() && i < 4; i++)
		v |= static_cast<std::uint32_t>(b[i]) << (8 * i);
	return v;
}

} // namespace

// ----------------------------------------------------------------------
// SDO
// ----------------------------------------------------------------------

std::uint32_t Chip::Impl::sdoCheck(std::size_t pos) const
{
	if (!reachable(pos))
		return abort::Timeout;
	const SlaveRec &r = slaves_[pos];
	if (!r.coe)
		return abort::NoObjectDictionary; // no CoE mailbox at all
	const unsigned st = r.slave->alStatus() & 0x0F;
	if (st == ECMXF_ECAT_INIT || st == ECMXF_ECAT_BOOT)
		return abort::CannotTransferState; // mailbox not running in INIT
	return 0;
}

std::uint32_t Chip::Impl::sdoCheck(std::size_t pos, std::uint32_t forced) const
{
	const std::uint32_t ab = sdoCheck(pos);
	return ab ? ab : forced;
}

std::uint32_t Chip::Impl::startSdoAborts()
{
	abortCode_ = 0;
	const std::uint32_t forced = faults_.forcedSdoAbort;
	faults_.forcedSdoAbort = 0;
	return forced;
}

AsyncJob::Step Chip::Impl::endMailboxJob(std::uint32_t abortCode)
{
	abortCode_ = abortCode;
	return abortCode ? AsyncJob::Step::Failed : AsyncJob::Step::Done;
}

Nanos Chip::Impl::sdoTime(std::size_t pos, std::size_t bytes) const
{
	Nanos lat = slaves_[pos].slave->mailboxLatency().count();
	if (lat < 100 * kUs)
		lat = 100 * kUs;
	// one mailbox round trip, plus one per further 128 bytes (segments)
	return lat * static_cast<Nanos>(1 + bytes / 128);
}

bool Chip::Impl::startSdo(std::span<const std::uint8_t> in)
{
	if (!initialized_ || in.size() < 12)
		return false;
	const unsigned op = in[0];
	const std::size_t pos = in[1];
	const std::uint16_t index = le16(&in[2]);
	const std::uint8_t sub = in[4];
	const std::size_t len = le16(&in[6]);
	const Nanos tmo = timeoutOf(le32(&in[8]), kDefaultSdoTimeout);
	if (op > 1 || pos >= slaves_.size() || len > kMaxSdo)
		return false;
	std::vector<std::uint8_t> wdata;
	if (op == 0) {
		if (12 + len > in.size())
			return false;
		wdata.assign(in.begin() + 12, in.begin() + 12 + static_cast<long>(len));
	}
	const std::uint32_t forced = startSdoAborts();
	// SDO_GET returns what the last read brought back (both manuals): a
	// read clears it (empty while it runs and after it failed), a write
	// leaves it alone
	if (op == 1)
		sdoData_.clear();
	// a read's size is the length field (0: one mailbox round trip)
	Nanos dur = reachable(pos) ? sdoTime(pos, len) : tmo;
	const bool late = dur > tmo;
	if (late)
		dur = tmo;
	startJob(ECMXF_CMD_ECAT_SDO_REQ, dur,
		 [this, op, pos, index, sub, len, wdata = std::move(wdata), forced, late] {
			 std::uint32_t ab = sdoCheck(pos);
			 if (!ab && late)
				 ab = abort::Timeout;
			 if (!ab && forced)
				 ab = forced;
			 Slave &s = *slaves_[pos].slave;
			 if (!ab && op == 0) {
				 ab = s.sdoDownload(index, sub, false, wdata);
			 } else if (!ab) {
				 std::vector<std::uint8_t> data;
				 ab = s.sdoUpload(index, sub, false, data);
				 if (!ab) {
					 std::size_t n = std::min(data.size(), kMaxSdo);
					 if (len)
						 n = std::min(n, len);
					 sdoData_.assign(data.begin(), data.begin() + static_cast<long>(n));
				 }
			 }
			 return endMailboxJob(ab);
		 });
	return true;
}

// ----------------------------------------------------------------------
// PDO configuration through SDO
// ----------------------------------------------------------------------

bool Chip::Impl::startPdoConfigSet(std::span<const std::uint8_t> in)
{
	if (!initialized_ || in.size() < 0x10)
		return false;
	const std::size_t pos = in[0];
	const unsigned count = in[1];
	const std::uint16_t assign = le16(&in[2]);
	if (pos >= slaves_.size() || count > 3)
		return false;
	std::uint16_t map[3], objs[3];
	for (unsigned i = 0; i < 3; i++) {
		map[i] = le16(&in[4 + 2 * i]);
		objs[i] = le16(&in[0x0A + 2 * i]);
	}
	std::vector<SdoWrite> w;
	w.push_back({ assign, 0, { 0 } });
	for (unsigned i = 0; i < count; i++) {
		if (objs[i] > 8 || 0x10 + 0x20 * i + 4 * objs[i] > in.size())
			return false;
		w.push_back({ map[i], 0, { 0 } });
		for (unsigned j = 0; j < objs[i]; j++) {
			const std::uint32_t entry = le32(&in[0x10 + 0x20 * i + 4 * j]);
			w.push_back({ map[i], static_cast<std::uint8_t>(j + 1), le(entry, 4) });
		}
		w.push_back({ map[i], 0, { static_cast<std::uint8_t>(objs[i]) } });
	}
	for (unsigned i = 0; i < count; i++)
		w.push_back({ assign, static_cast<std::uint8_t>(i + 1), le(map[i], 2) });
	w.push_back({ assign, 0, { static_cast<std::uint8_t>(count) } });

	const std::uint32_t forced = startSdoAborts();
	const Nanos dur = (reachable(pos) ? sdoTime(pos, 4) : kDefaultSdoTimeout) *
			  (reachable(pos) ? static_cast<Nanos>(w.size()) : 1);
	startJob(ECMXF_CMD_ECAT_PDO_CONFIG_SET, dur, [this, pos, w = std::move(w), forced] {
		std::uint32_t ab = sdoCheck(pos, forced);
		for (std::size_t i = 0; !ab && i < w.size(); i++)
			ab = slaves_[pos].slave->sdoDownload(w[i].index, w[i].sub, false, w[i].data);
		return endMailboxJob(ab);
	});
	return true;
}

bool Chip::Impl::startPdoConfigReq(std::span<const std::uint8_t> in)
{
	if (!initialized_ || in.size() < 4)
		return false;
	const std::size_t pos = in[0];
	const std::uint16_t assign = le16(&in[2]);
	if (pos >= slaves_.size())
		return false;
	const std::uint32_t forced = startSdoAborts();
	const Nanos first = reachable(pos) ? sdoTime(pos, 4) : kDefaultSdoTimeout;
	startJob(ECMXF_CMD_ECAT_PDO_CONFIG_REQ, first,
		 [this, pos, assign, forced, phase = 0, ok = false]() mutable {
			 if (phase == 1)
				 return ok ? Step::Done : Step::Failed;
			 // read everything now; the job stays busy for the time the
			 // transfers take on the bus
			 std::uint32_t ab = sdoCheck(pos, forced);
			 Slave &s = *slaves_[pos].slave;
			 std::vector<std::uint8_t> v;
			 auto read = [&](std::uint16_t idx, std::uint8_t sub) -> std::uint32_t {
				 v.clear();
				 if (!ab)
					 ab = s.sdoUpload(idx, sub, false, v);
				 return ab ? 0 : fromLe(v);
			 };
			 std::array<std::uint8_t, 112> cfg{};
			 unsigned transfers = 1;
			 const std::uint32_t count = read(assign, 0) & 0xFF;
			 cfg[0] = static_cast<std::uint8_t>(pos);
			 cfg[1] = static_cast<std::uint8_t>(count);
			 put16(&cfg[2], assign);
			 for (unsigned i = 0; !ab && i < std::min<std::uint32_t>(count, 3); i++) {
				 const auto map = static_cast<std::uint16_t>(read(assign, static_cast<std::uint8_t>(i + 1)));
				 const std::uint32_t objs = read(map, 0) & 0xFF;
				 transfers += 2;
				 put16(&cfg[4 + 2 * i], map);
				 put16(&cfg[0x0A + 2 * i], static_cast<std::uint16_t>(objs));
				 for (unsigned j = 0; !ab && j < std::min<std::uint32_t>(objs, 8); j++) {
					 put32(&cfg[0x10 + 0x20 * i + 4 * j],
					       read(map, static_cast<std::uint8_t>(j + 1)));
					 transfers++;
				 }
			 }
			 abortCode_ = ab;
			 ok = ab == 0;
			 if (ok)
				 pdoCfg_ = cfg;
			 phase = 1;
			 job_.next = now_ + (ab ? 1 : sdoTime(pos, 4) * (transfers - 1));
			 return Step::Running;
		 });
	return true;
}

// ----------------------------------------------------------------------
// EEPROM
// ----------------------------------------------------------------------

bool Chip::Impl::startEeprom(std::span<const std::uint8_t> in)
{
	if (in.size() < 12)
		return false;
	const unsigned op = le16(&in[0]);
	const std::size_t pos = le16(&in[2]);
	const std::uint16_t addr = le16(&in[4]);
	const std::uint16_t value = le16(&in[6]);
	const Nanos tmo = timeoutOf(le32(&in[8]), kDefaultTimeout);
	if (op > 1 || pos >= net_.size())
		return false;
	eepromData_.clear();
	eepromRet_ = 0;
	const Nanos dur = !reachable(pos) ? tmo : op ? 10 * kMs : 500 * kUs;
	startJob(ECMXF_CMD_EEPROM_REQ, dur, [this, op, pos, addr, value] {
		if (!reachable(pos)) {
			eepromRet_ = 2; // no answer from the slave
			return Step::Failed;
		}
		const std::vector<std::uint16_t> sii = net_.at(pos).sii();
		if (addr >= sii.size()) {
			eepromRet_ = 1; // beyond the EEPROM
			return Step::Failed;
		}
		if (op == 0) {
			const std::uint16_t w = siiWord(pos, addr, sii);
			eepromData_ = { static_cast<std::uint8_t>(w), static_cast<std::uint8_t>(w >> 8) };
		} else {
			eepromOverlay_[pos][addr] = value;
		}
		eepromRet_ = 0;
		return Step::Done;
	});
	return true;
}

// ----------------------------------------------------------------------
// raw datagrams
// ----------------------------------------------------------------------

bool Chip::Impl::startRaw(std::span<const std::uint8_t> in)
{
	if (in.size() < 20)
		return false;
	const unsigned op = in[0];
	const std::size_t n = le16(&in[2]);
	const std::uint16_t adp = le16(&in[4]);
	const std::uint16_t ado = le16(&in[6]);
	static constexpr unsigned kOps[] = { 1, 2, 4, 5, 7, 8, 10, 11, 12, 13, 14 };
	if (std::find(std::begin(kOps), std::end(kOps), op) == std::end(kOps))
		return false;
	if (n > 256 || 20 + n > in.size())
		return false;
	std::vector<std::uint8_t> req(in.begin(), in.begin() + static_cast<long>(20 + n));
	const Nanos dur = 200 * kUs + static_cast<Nanos>(n) * 80;
	startJob(ECMXF_CMD_RAW_ECAT_FUNC_REQ, dur, [this, op, n, adp, ado, req = std::move(req)] {
		if (stations_.size() < net_.size())
			stations_.resize(net_.size(), 0);
		std::vector<std::uint8_t> data(req.begin() + 20, req.end());
		unsigned wkc = 0;
		auto readInto = [&](std::size_t pos, std::uint8_t *dst) {
			for (std::size_t i = 0; i < n; i++)
				dst[i] = regRead(pos, static_cast<std::uint16_t>(ado + i));
		};
		auto write = [&](std::size_t pos, const std::uint8_t *src) {
			for (std::size_t i = 0; i < n; i++)
				regWrite(pos, static_cast<std::uint16_t>(ado + i), src[i]);
		};
		// the slave an auto-increment / fixed address selects (or none)
		const std::size_t none = static_cast<std::size_t>(-1);
		auto autoPos = [&]() {
			const std::size_t p = static_cast<std::uint16_t>(0x10000u - adp);
			return p < net_.size() ? p : none;
		};
		auto fixedPos = [&]() {
			for (std::size_t p = 0; p < net_.size(); p++)
				if (stations_[p] == adp)
					return p;
			return none;
		};
		switch (op) {
		case 1: // APRD
		case 4: { // FPRD
			const std::size_t p = op == 1 ? autoPos() : fixedPos();
			if (p != none && reachable(p)) {
				readInto(p, data.data());
				wkc = 1;
			}
			break;
		}
		case 2: // APWR
		case 5: { // FPWR
			const std::size_t p = op == 2 ? autoPos() : fixedPos();
			if (p != none && reachable(p)) {
				write(p, data.data());
				wkc = 1;
			}
			break;
		}
		case 7: { // BRD: the slaves' bytes OR'ed together
			std::fill(data.begin(), data.end(), 0);
			std::vector<std::uint8_t> one(n);
			for (std::size_t p = 0; p < net_.size(); p++) {
				if (!reachable(p))
					continue;
				readInto(p, one.data());
				for (std::size_t i = 0; i < n; i++)
					data[i] = static_cast<std::uint8_t>(data[i] | one[i]);
				wkc++;
			}
			break;
		}
		case 8: // BWR
			for (std::size_t p = 0; p < net_.size(); p++) {
				if (!reachable(p))
					continue;
				write(p, data.data());
				wkc++;
			}
			break;
		case 13: // ARMW
		case 14: { // FRMW
			const std::size_t p = op == 13 ? autoPos() : fixedPos();
			if (p != none && reachable(p)) {
				readInto(p, data.data());
				wkc++;
				for (std::size_t q = 0; q < net_.size(); q++) {
					if (q == p || !reachable(q))
						continue;
					write(q, data.data());
					wkc++;
				}
			}
			break;
		}
		default: // LRD, LWR, LRW: no FMMU maps the logical address space
			break;
		}
		rawResult_.assign(req.begin(), req.begin() + 20);
		put16(&rawResult_[16], static_cast<std::uint16_t>(wkc));
		rawResult_[18] = rawResult_[19] = 0;
		rawResult_.insert(rawResult_.end(), data.begin(), data.end());
		return Step::Done;
	});
	return true;
}

// ----------------------------------------------------------------------
// FoE and the staging flash
// ----------------------------------------------------------------------

bool Chip::Impl::startFoe(std::span<const std::uint8_t> in, std::size_t cmdLen)
{
	if (in.size() < 20)
		return false;
	const std::size_t pos = in[0];
	const unsigned op = in[2];
	const std::uint32_t flen = le32(&in[8]);
	const std::uint32_t addr = le32(&in[16]);
	const std::size_t extra = cmdLen >= 20 ? std::min(cmdLen - 20, in.size() - 20) : 0;
	if (addr >= kFlashSize)
		return false;
	foeResult_.clear();
	// the staging flash, erased (0xFF), made at its first use: most chips
	// never use it (a fuzzer or a test makes thousands)
	if (flash_.empty())
		flash_.assign(kFlashSize, 0xFF);
	switch (op) {
	case 1: // upload: slave file -> flash
	case 2: { // download: flash -> slave file
		if (!initialized_ || pos >= slaves_.size())
			return false;
		if (op == 2 && flen > kFlashSize - addr)
			return false;
		std::string name(reinterpret_cast<const char *>(in.data() + 20), extra);
		name = name.substr(0, name.find('\0'));
		const Nanos lat = reachable(pos) ? sdoTime(pos, 0) : kDefaultSdoTimeout;
		const Nanos dur = lat + (op == 2 ? static_cast<Nanos>(flen) * kUs : 0);
		startJob(ECMXF_CMD_FOE_FUNC_REQ, dur, [this, pos, op, flen, addr, name] {
			Slave &s = *slaves_[pos].slave;
			std::uint32_t code = 0;
			if (!reachable(pos))
				code = abort::Timeout;
			else if (!slaves_[pos].foe)
				code = abort::GeneralError; // no FoE on this slave
			if (!code && op == 1) {
				std::vector<std::uint8_t> file;
				code = s.foeRead(name, file);
				if (!code && file.size() > kFlashSize - addr)
					code = abort::OutOfMemory;
				if (!code) {
					std::copy(file.begin(), file.end(), flash_.begin() + addr);
					foeResult_ = le(static_cast<std::uint32_t>(file.size()), 4);
				}
			} else if (!code) {
				code = s.foeWrite(name, std::span<const std::uint8_t>(flash_.data() + addr, flen));
			}
			return endMailboxJob(code);
		});
		return true;
	}
	case 3: // read flash
		if (flen > 256 || flen > kFlashSize - addr)
			return false;
		startJob(ECMXF_CMD_FOE_FUNC_REQ, 100 * kUs, [this, flen, addr] {
			foeResult_.assign(flash_.begin() + addr, flash_.begin() + addr + flen);
			return Step::Done;
		});
		return true;
	case 4: { // write flash
		if (flen > 256 || flen > kFlashSize - addr || 20 + flen > in.size())
			return false;
		std::vector<std::uint8_t> data(in.begin() + 20, in.begin() + 20 + flen);
		startJob(ECMXF_CMD_FOE_FUNC_REQ, 2 * kMs, [this, addr, data = std::move(data)] {
			std::copy(data.begin(), data.end(), flash_.begin() + addr);
			return Step::Done;
		});
		return true;
	}
	default:
		return false;
	}
}

// ----------------------------------------------------------------------
// receive mailbox, emergencies
// ----------------------------------------------------------------------

namespace {

/// A CoE emergency as it arrives in the master's receive mailbox:
/// mailbox header (6), CoE header (2, service 1 = emergency), 8 bytes.
void encodeEmergency(const Emergency &e, std::array<std::uint8_t, 16> &f)
{
	f.fill(0);
	put16(&f[0], 10);	// length after the mailbox header
	f[5] = 0x03;		// type CoE
	put16(&f[6], 0x1000);	// CoE service 1: emergency
	put16(&f[8], e.errorCode);
	f[10] = e.errorRegister;
	std::memcpy(&f[11], e.data, 5);
}

} // namespace

void Chip::Impl::logEmergency(std::size_t pos, const Emergency &e)
{
	EmergencyLog &l = emcyLog_[emcyHead_];
	l.seq = ++emcySeq_;
	l.slave = static_cast<std::uint8_t>(pos);
	l.emcy = e;
	emcyHead_ = (emcyHead_ + 1) % emcyLog_.size();
	emcyCount_ = std::min(emcyCount_ + 1, emcyLog_.size());
}

void Chip::Impl::pollEmergency(std::size_t pos)
{
	SlaveRec &r = slaves_[pos];
	if (!r.coe || !reachable(pos))
		return;
	const unsigned st = r.slave->alStatus() & 0x0F;
	if (st == ECMXF_ECAT_INIT || st == ECMXF_ECAT_BOOT)
		return;
	if (r.mbxPoll) {
		// the master reads the mailbox itself and logs what it finds
		for (int i = 0; i < 8; i++) {
			const std::optional<Emergency> e = r.slave->popEmergency();
			if (!e)
				break;
			logEmergency(pos, *e);
		}
	} else if (r.mbxLen == 0) {
		// not polled: the message waits in the slave's mailbox (MBX_STAT)
		if (const std::optional<Emergency> e = r.slave->popEmergency()) {
			encodeEmergency(*e, r.mbxFrame);
			r.mbxLen = 16;
		}
	}
}

void Chip::Impl::pollEmergencies()
{
	for (std::size_t pos = 0; pos < slaves_.size(); pos++)
		pollEmergency(pos);
}

Chip::Impl::Result Chip::Impl::coeEmergency(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out)
{
	Result r;
	const std::size_t n = h.param;
	if (n == 0 || n > 8 || 12 * n > out.size())
		return Result::error();
	pollEmergencies();
	for (std::size_t i = 0; i < n; i++) {
		std::uint8_t *e = out.data() + 12 * i;
		std::memset(e, 0, 12);
		if (i >= emcyCount_) {
			e[0] = 0xFF; // no such emergency
			continue;
		}
		const EmergencyLog &l =
			emcyLog_[(emcyHead_ + emcyLog_.size() - 1 - i) % emcyLog_.size()];
		e[0] = static_cast<std::uint8_t>(i);
		e[1] = l.slave;
		put16(e + 2, l.seq);
		put16(e + 4, l.emcy.errorCode);
		e[6] = l.emcy.errorRegister;
		std::memcpy(e + 7, l.emcy.data, 5);
	}
	r.len = 12 * n;
	return r;
}

bool Chip::Impl::startRecvMailbox(const ecmxf_cmd_hdr &h)
{
	const std::size_t pos = h.data[0];
	if (!initialized_ || pos >= slaves_.size())
		return false;
	const Nanos dur = reachable(pos) ? sdoTime(pos, 0) : kDefaultTimeout;
	startJob(ECMXF_CMD_RECV_MAILBOX, dur, [this, pos] {
		if (!reachable(pos))
			return Step::Failed;
		SlaveRec &r = slaves_[pos];
		mbxRead_.clear();
		if (r.mbxLen == 0 && r.coe) {
			if (const std::optional<Emergency> e = r.slave->popEmergency()) {
				encodeEmergency(*e, r.mbxFrame);
				r.mbxLen = 16;
			}
		}
		if (r.mbxLen) {
			mbxRead_.assign(r.mbxFrame.begin(), r.mbxFrame.begin() + r.mbxLen);
			Emergency e;
			e.errorCode = le16(&r.mbxFrame[8]);
			e.errorRegister = r.mbxFrame[10];
			std::memcpy(e.data, &r.mbxFrame[11], 5);
			logEmergency(pos, e);
			r.mbxLen = 0;
		}
		return Step::Done;
	});
	return true;
}

Chip::Impl::Result Chip::Impl::recvMailboxRead(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out)
{
	Result r;
	const std::size_t start = h.data[1] * 64u + h.data[0];
	const std::size_t len = h.data[3] * 64u + h.data[2];
	if (len > out.size())
		return Result::error();
	for (std::size_t i = 0; i < len; i++)
		out[i] = start + i < mbxRead_.size() ? mbxRead_[start + i] : 0;
	r.len = len;
	return r;
}

Chip::Impl::Result Chip::Impl::mbxStat(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
				       std::span<std::uint8_t> out)
{
	Result r;
	const std::size_t n = (slaves_.size() + 7) / 8;
	if (n > out.size() || h.param > 2)
		return Result::error();
	switch (h.param) {
	case 0: // which slaves have data in their receive mailbox
		pollEmergencies();
		std::memset(out.data(), 0, n);
		for (std::size_t p = 0; p < slaves_.size(); p++)
			if (slaves_[p].mbxLen)
				out[p / 8] = static_cast<std::uint8_t>(out[p / 8] | (1u << (p % 8)));
		r.len = n;
		break;
	case 1: // polling on/off per slave, from the next RECONFIG_OP on
		for (std::size_t p = 0; p < slaves_.size(); p++)
			slaves_[p].mbxPollPending = (in[p / 8] >> (p % 8)) & 1;
		break;
	default: // which slaves the master polls
		std::memset(out.data(), 0, n);
		for (std::size_t p = 0; p < slaves_.size(); p++)
			if (slaves_[p].mbxPoll)
				out[p / 8] = static_cast<std::uint8_t>(out[p / 8] | (1u << (p % 8)));
		r.len = n;
		break;
	}
	return r;
}

} // namespace ecmxf::sim
