// SPDX-License-Identifier: MIT
//
// sk_board.cpp - the simulated ECM-SK firmware (ecmxf::sk::SimBoard).
//
// The board decodes each command frame with the slot protocol core
// (lib/core/ecmsk-*.c), carries out the commands of table 1.3 where the
// state and the slave type allow them, and runs EtherCAT cycles on the
// network's slave models: AL state changes, SDOs through their object
// dictionaries, process data built from their PDO mappings (which the
// firmware writes at PRE-OP -> SAFE-OP), DC, a CiA-402 enable sequence,
// the cyclic FIFO and homing. Documentation/ecm-sk.rst, "The simulator".

#include <ecmxf/sim/sk_board.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <stdexcept>
#include <thread>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/sim/network.hpp>

#include "base/text.hpp"
#include "ecmsk-proto.h"
#include "le.hpp"

namespace ecmxf::sk {

using namespace std::chrono_literals;
using ns = std::chrono::nanoseconds;

// ---------------------------------------------------------------------------
// BoardConfig
// ---------------------------------------------------------------------------

namespace {

std::uint64_t number(const std::string &key, const std::string &value, std::uint64_t lo,
		     std::uint64_t hi)
{
	std::uint64_t v = 0;
	const char *b = value.data(), *e = value.data() + value.size();
	int base = 10;
	if (value.size() > 2 && value[0] == '0' && (value[1] == 'x' || value[1] == 'X')) {
		b += 2;
		base = 16;
	}
	auto [p, ec] = std::from_chars(b, e, v, base);
	if (value.empty() || ec != std::errc() || p != e || v < lo || v > hi)
		throw std::invalid_argument("ECM-SK board setting " + key + "=" + value +
					    ": expected a number in " + std::to_string(lo) +
					    ".." + std::to_string(hi));
	return v;
}

} // namespace

void BoardConfig::set(const std::string &key, const std::string &value)
{
	if (key == "slot") {
		const auto v = number(key, value, 12, 16);
		if (v != 12 && v != 16)
			throw std::invalid_argument("ECM-SK board setting slot=" + value +
						    ": the slot size is 12 or 16 (CONFIG2)");
		slotSize = static_cast<unsigned>(v);
	} else if (key == "test") {
		testMode = number(key, value, 0, 1) != 0;
	} else if (key == "abandon") {
		fifoAbandon = number(key, value, 0, 1) != 0;
	} else if (key == "ex") {
		extensions = static_cast<std::uint32_t>(number(key, value, 0, 3));
	} else if (key == "fifo") {
		fifoDepth = static_cast<unsigned>(number(key, value, 160, 4096));
	} else if (key == "busy_us") {
		busyTime = std::chrono::microseconds(number(key, value, 1, 100000));
	} else if (key == "spi_hz") {
		spiHz = static_cast<std::uint32_t>(number(key, value, 100000, 50000000));
	} else if (key == "lio") {
		lioInputs = static_cast<std::uint32_t>(number(key, value, 0, 63));
	} else if (key == "paced") {
		paced = number(key, value, 0, 1) != 0;
	} else {
		throw std::invalid_argument("unknown ECM-SK board setting '" + key +
					    "' (slot, test, abandon, ex, fifo, busy_us, spi_hz, lio, paced)");
	}
}

BoardConfig BoardConfig::parse(const std::string &settings)
{
	BoardConfig c;
	std::size_t pos = 0;
	while (pos <= settings.size()) {
		std::size_t end = settings.find_first_of("&,", pos);
		if (end == std::string::npos)
			end = settings.size();
		const std::string item = settings.substr(pos, end - pos);
		pos = end + 1;
		if (item.empty())
			continue;
		const auto eq = item.find('=');
		if (eq == std::string::npos || eq == 0)
			throw std::invalid_argument("ECM-SK board setting '" + item +
						    "': expected key=value");
		c.set(item.substr(0, eq), item.substr(eq + 1));
	}
	return c;
}

// ---------------------------------------------------------------------------
// The firmware
// ---------------------------------------------------------------------------

namespace {

constexpr unsigned kAbandonCycles = ECMSK_FIFO_ABANDON_CYCLES;
constexpr ns kResetBusy = 10ms;

std::uint8_t actualType(const sim::Slave &s)
{
	const std::string t = s.typeName();
	if (t == "servo")
		return ECMSK_AXIS_DRIVE;
	if (t == "EST-584")
		return ECMSK_AXIS_STEP;
	if (t == "dio")
		return ECMSK_AXIS_IO;
	if (t == "hsp" || t == "hsp2")
		return ECMSK_AXIS_HSP;
	return ECMSK_AXIS_NONE; // not a kind the ECM-SK supports
}

bool driveLike(std::uint8_t type)
{
	return type == ECMSK_AXIS_DRIVE || type == ECMSK_AXIS_STEP || type == ECMSK_AXIS_HSP;
}

constexpr detail::CodeText<std::uint8_t> kStateNames[] = {
	{ ECMSK_STATE_INIT, "INIT" },
	{ ECMSK_STATE_PREOP, "PRE-OP" },
	{ ECMSK_STATE_SAFEOP, "SAFE-OP" },
	{ ECMSK_STATE_OP, "OP" },
};

std::string_view stateName(std::uint8_t st)
{
	return detail::textOf(kStateNames, st, "?");
}

std::vector<std::uint8_t> le(std::uint64_t v, unsigned n)
{
	std::vector<std::uint8_t> b(n);
	for (unsigned i = 0; i < n; i++)
		b[i] = static_cast<std::uint8_t>(v >> (8 * i));
	return b;
}

struct FifoEntry {
	std::uint8_t slave;
	std::uint8_t cmd;
	std::uint32_t target;
	std::uint32_t value;
	std::uint64_t cycle; // enqueued in
	bool two = false;    // a 2-channel HSP command: target2 too
	std::uint32_t target2 = 0;
};

struct SlaveCtx {
	sim::Slave *s = nullptr;
	std::uint8_t actual = ECMSK_AXIS_NONE;
	bool hsp2 = false; // a 2-channel HSP (channel 2 at index + 0x800)
	std::uint8_t type = ECMSK_AXIS_IO; // SET_AXIS's default topology 0x1
	std::uint8_t mode = ECMSK_MODE_CSP;
	std::uint8_t sync = ECMSK_SYNC_DCSYNC;
	// process data offsets (bytes; -1: not mapped)
	int oCw = -1, oPos = -1, oVel = -1, oTrq = -1, oMode = -1;
	int iSw = -1, iPos = -1, iTrq = -1, iErr = -1, iMode = -1, iDin = -1;
	int oCw2 = -1, oPos2 = -1, oVel2 = -1, oMode2 = -1, iSw2 = -1, iPos2 = -1, iDin2 = -1;
	std::vector<std::uint8_t> out, in;
	// firmware side
	bool enable = false;
	bool faultReset = false;
	bool homing = false;
	int modeOverride = -1; // last SDO_WR to 0x6060 (-1: none)
	bool methodSet = false; // SDO_WR to 0x6098 since the last homing
	std::uint16_t cw = 0;
	std::int32_t tPos = 0, tVel = 0;
	std::int16_t tTrq = 0;
	std::uint32_t ioOut = 0;
	std::uint16_t cw2 = 0;
	std::int32_t tPos2 = 0, tVel2 = 0;
	// inputs
	std::uint16_t sw = 0;
	std::int32_t pos = 0;
	std::int16_t trq = 0;
	std::uint16_t err = 0;
	std::int8_t modeDisp = 0;
	std::uint32_t din = 0;
	std::uint16_t sw2 = 0;
	std::int32_t pos2 = 0;
	std::uint32_t din2 = 0;
	// the slot's answer to the last command
	std::uint8_t ansCmd = 0, ansIdx = 0;
	std::uint32_t ansData = 0;
	bool ansData1 = false; // ansData goes to bytes 4-7 (IO_RD)
};

int findEntry(const std::vector<sim::Pdo> &pdos, std::uint16_t index, std::uint8_t sub = 0)
{
	int bits = 0;
	for (const auto &p : pdos)
		for (const auto &e : p.entries) {
			if (e.index == index && e.subindex == sub && bits % 8 == 0)
				return bits / 8;
			bits += e.bits;
		}
	return -1;
}

template <typename T> void putAt(std::vector<std::uint8_t> &buf, int off, T v)
{
	if (off < 0 || static_cast<std::size_t>(off) + sizeof(T) > buf.size())
		return;
	for (std::size_t i = 0; i < sizeof(T); i++)
		buf[static_cast<std::size_t>(off) + i] =
			static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i));
}

template <typename T> bool getAt(const std::vector<std::uint8_t> &buf, int off, T &v)
{
	if (off < 0 || static_cast<std::size_t>(off) + sizeof(T) > buf.size())
		return false;
	std::uint64_t r = 0;
	for (std::size_t i = 0; i < sizeof(T); i++)
		r |= std::uint64_t{ buf[static_cast<std::size_t>(off) + i] } << (8 * i);
	v = static_cast<T>(r);
	return true;
}

using Cia = Cia402State;

// The drive's CiA-402 state by the statusword's masks
// (include/ecmxf/model/cia402.hpp); the board treats a fault reaction
// as the fault it ends in, and a pattern that is no state as not ready.
Cia ciaState(std::uint16_t sw)
{
	const Cia s = cia402StateFrom(sw).value_or(Cia::NotReadyToSwitchOn);
	return s == Cia::FaultReactionActive ? Cia::Fault : s;
}

} // namespace

struct SimBoard::Impl {
	BoardConfig cfg;
	sim::Network net;
	ecmsk_geom g{};
	BoardStats st;
	std::vector<SlaveCtx> sl; // index 0 = slave 1

	ns now{ 0 };
	ns busyUntil{ 0 };
	ns nextCycle{ 0 };
	std::uint8_t state = ECMSK_STATE_INIT;
	std::uint8_t target = ECMSK_STATE_INIT;
	ns stateStepAt{ 0 };
	std::string lastError;
	std::uint8_t crcErrors = 0;
	std::uint32_t exSaved = 0, exInForce = 0;
	std::uint32_t cycleUs = ECMSK_DC_DEFAULT_US;
	std::uint32_t lioIn = 0, lioOut = 0;
	// slot 0's answer
	std::uint8_t ansCmd = 0;
	std::uint32_t ansData1 = 0, ansData2 = 0;
	// FIFO
	std::vector<FifoEntry> fifo;
	unsigned fifoFull = 0;
	// the threshold in force: entries are held while FIFO remaining is not
	// below it; its default and reset value is the depth (160 on the
	// board the manual describes), which holds nothing
	unsigned threshold = ECMSK_FIFO_THRESHOLD_DEFAULT;
	[[nodiscard]] unsigned thresholdDefault() const { return cfg.fifoDepth; }
	bool homingRunning = false;
	// SDO slot
	ecmsk_sdo sdoAns{};
	bool sdoBusy = false;
	ns sdoDoneAt{ 0 };
	// test mode
	bool testMode = false;

	Impl(sim::Network n, BoardConfig c) : cfg(c), net(std::move(n))
	{
		if (ecmsk_geom_init(&g, cfg.slotSize))
			throw std::invalid_argument("ECM-SK: slot size " + std::to_string(cfg.slotSize) +
						    " (12 or 16)");
		if (net.size() > g.max_slaves)
			throw std::invalid_argument("ECM-SK: " + std::to_string(net.size()) +
						    " slaves, the frame has slots for " +
						    std::to_string(g.max_slaves));
		if (cfg.fifoDepth < ECMSK_FIFO_THRESHOLD_DEFAULT || cfg.fifoDepth > 4096)
			throw std::invalid_argument("ECM-SK: FIFO depth " + std::to_string(cfg.fifoDepth) +
						    " (160..4096)");
		if (cfg.extensions > 3)
			throw std::invalid_argument("ECM-SK: SET_EX setting " +
						    std::to_string(cfg.extensions) + " (0..3)");
		exSaved = cfg.extensions;
		fifo.reserve(cfg.fifoDepth);
		powerOn(false);
	}

	// ---- power and reset ----
	void powerOn(bool resetSlaves)
	{
		sl.assign(net.size(), SlaveCtx{});
		for (std::size_t i = 0; i < net.size(); i++) {
			if (resetSlaves)
				net.at(i).reset();
			sl[i].s = &net.at(i);
			sl[i].actual = actualType(net.at(i));
			sl[i].hsp2 = sl[i].actual == ECMSK_AXIS_HSP &&
				     findEntry(net.at(i).rxPdos(), 0x6840) >= 0;
			sl[i].s->alControl(static_cast<std::uint8_t>(sim::AlState::Init));
		}
		state = target = ECMSK_STATE_INIT;
		opPending = false;
		lastError.clear();
		crcErrors = 0;
		exInForce = exSaved;
		cycleUs = ECMSK_DC_DEFAULT_US;
		lioIn = cfg.lioInputs;
		lioOut = 0;
		ansCmd = 0;
		ansData1 = ansData2 = 0;
		fifo.clear();
		fifoFull = 0;
		threshold = thresholdDefault();
		homingRunning = false;
		sdoAns = {};
		sdoBusy = false;
		nextCycle = now;
		testMode = cfg.testMode;
		if (testMode) {
			// 1.3.4: IO slaves, 1 ms, to OP by itself
			for (auto &s : sl)
				s.type = ECMSK_AXIS_IO;
			requestState(ECMSK_STATE_OP);
		}
	}

	// ---- time ----
	[[nodiscard]] ns cycleTime() const { return std::chrono::microseconds(cycleUs); }
	[[nodiscard]] ns wireTime() const
	{
		return ns(static_cast<std::int64_t>(g.frame_size) * 8 * 1'000'000'000LL / cfg.spiHz);
	}

	// paced: the wall clock since power-on, as virtual time
	const std::chrono::steady_clock::time_point epoch = std::chrono::steady_clock::now();

	void advance(ns dt)
	{
		ns end = now + dt;
		if (cfg.paced) {
			// not ahead of the wall clock; behind it, catch up
			std::this_thread::sleep_until(epoch + end);
			end = std::max(end, std::chrono::duration_cast<ns>(std::chrono::steady_clock::now() - epoch));
		}
		while (nextCycle <= end) {
			now = std::max(now, nextCycle);
			cycle();
			nextCycle += cycleTime();
		}
		now = end;
	}

	// ---- EtherCAT state machine ----
	[[nodiscard]] ns stateStepTime() const
	{
		return 2ms + std::chrono::microseconds(100) * static_cast<long>(sl.size());
	}

	void requestState(std::uint8_t t)
	{
		opPending = false;
		target = t;
		lastError.clear();
		stateStepAt = now + stateStepTime();
	}

	static std::uint8_t nextStateOnPath(std::uint8_t from, std::uint8_t to)
	{
		if (to <= from)
			return to; // downwards in one step
		switch (from) {
		case ECMSK_STATE_INIT: return ECMSK_STATE_PREOP;
		case ECMSK_STATE_PREOP: return ECMSK_STATE_SAFEOP;
		default: return ECMSK_STATE_OP;
		}
	}

	bool fail(const std::string &why)
	{
		lastError = why;
		target = state; // the request ends here
		return false;
	}

	bool alAll(std::uint8_t to)
	{
		for (std::size_t i = 0; i < sl.size(); i++)
			sl[i].s->alControl(to);
		for (std::size_t i = 0; i < sl.size(); i++) {
			const auto &s = *sl[i].s;
			if ((s.alStatus() & 0x0F) != to)
				return fail("slave " + std::to_string(i + 1) + " (" + s.typeName() +
					    ") refused " + std::string(stateName(to)) + ": AL status code 0x" +
					    hex(s.alStatusCode()));
		}
		return true;
	}

	static std::string hex(std::uint32_t v)
	{
		char b[16];
		std::snprintf(b, sizeof(b), "%04X", v);
		return b;
	}

	bool sdoWrite(SlaveCtx &c, std::uint16_t idx, std::uint8_t sub, std::uint64_t v, unsigned n)
	{
		const auto b = le(v, n);
		return c.s->sdoDownload(idx, sub, false, b) == 0;
	}

	void mapPdos(SlaveCtx &c)
	{
		static const std::uint32_t rx[] = { 0x60400010, 0x607A0020, 0x60FF0020, 0x60710010,
						    0x60600008 };
		static const std::uint32_t tx[] = { 0x60410010, 0x60640020, 0x60770010, 0x603F0010,
						    0x60610008, 0x60FD0020 };
		auto map = [&](std::uint16_t assign, std::uint16_t pdo, std::span<const std::uint32_t> want) {
			if (!sdoWrite(c, assign, 0, 0, 1) || !sdoWrite(c, pdo, 0, 0, 1))
				return;
			std::uint8_t k = 1;
			for (std::uint32_t e : want)
				if (sdoWrite(c, pdo, k, e, 4))
					k++;
			sdoWrite(c, pdo, 0, k - 1u, 1);
			sdoWrite(c, assign, 1, pdo, 2);
			sdoWrite(c, assign, 0, 1, 1);
		};
		map(0x1C12, 0x1600, rx);
		map(0x1C13, 0x1A00, tx);
	}

	void bindPdos(SlaveCtx &c)
	{
		const auto rx = c.s->rxPdos(), tx = c.s->txPdos();
		c.out.assign(c.s->outputBytes(), 0);
		c.in.assign(c.s->inputBytes(), 0);
		c.oCw = findEntry(rx, 0x6040);
		c.oPos = findEntry(rx, 0x607A);
		c.oVel = findEntry(rx, 0x60FF);
		c.oTrq = findEntry(rx, 0x6071);
		c.oMode = findEntry(rx, 0x6060);
		c.iSw = findEntry(tx, 0x6041);
		c.iPos = findEntry(tx, 0x6064);
		c.iTrq = findEntry(tx, 0x6077);
		c.iErr = findEntry(tx, 0x603F);
		c.iMode = findEntry(tx, 0x6061);
		c.iDin = findEntry(tx, 0x60FD);
		c.oCw2 = findEntry(rx, 0x6840);
		c.oPos2 = findEntry(rx, 0x687A);
		c.oVel2 = findEntry(rx, 0x68FF);
		c.oMode2 = findEntry(rx, 0x6860);
		c.iSw2 = findEntry(tx, 0x6841);
		c.iPos2 = findEntry(tx, 0x6864);
		c.iDin2 = findEntry(tx, 0x68FD);
	}

	bool toSafeOp()
	{
		for (std::size_t i = 0; i < sl.size(); i++) {
			auto &c = sl[i];
			if (!testMode && c.type != c.actual)
				return fail("slave " + std::to_string(i + 1) + " is a " + c.s->typeName() +
					    " but SET_AXIS made it type " + std::to_string(c.type));
		}
		for (auto &c : sl) {
			if (!driveLike(c.type) || testMode) {
				c.s->configureDc(0, 0, 0, 0);
				continue;
			}
			if (c.actual != ECMSK_AXIS_HSP) // an HSP's own mapping has both channels
				mapPdos(c);
			if (!sdoWrite(c, 0x6060, 0, c.mode, 1))
				return fail(c.s->typeName() + " refused mode of operation " +
					    std::to_string(c.mode));
			if (c.sync == ECMSK_SYNC_DCSYNC && c.s->dcAssignActivate())
				c.s->configureDc(c.s->dcAssignActivate(), cycleUs * 1000u, 0, 0);
			else
				c.s->configureDc(0, 0, 0, 0);
		}
		if (!alAll(static_cast<std::uint8_t>(sim::AlState::SafeOp)))
			return false;
		for (auto &c : sl) {
			bindPdos(c);
			c.enable = c.homing = c.faultReset = false;
			c.modeOverride = -1;
			c.methodSet = false;
		}
		return true;
	}

	bool opPending = false;
	ns opDeadline{ 0 };

	void opStep()
	{
		bool all = true;
		for (std::size_t i = 0; i < sl.size(); i++) {
			const auto &s = *sl[i].s;
			if ((s.alStatus() & 0x0F) == static_cast<std::uint8_t>(sim::AlState::Op))
				continue;
			all = false;
			if ((s.alStatus() & 0x10) || now >= opDeadline) {
				opPending = false;
				fail("slave " + std::to_string(i + 1) + " (" + s.typeName() +
				     ") did not reach OP: AL status code 0x" + hex(s.alStatusCode()));
				return;
			}
		}
		if (!all)
			return;
		opPending = false;
		state = ECMSK_STATE_OP;
		stateStepAt = now + stateStepTime();
	}

	void stateStep()
	{
		if (opPending) {
			opStep();
			return;
		}
		if (target == state || now < stateStepAt)
			return;
		const std::uint8_t next = nextStateOnPath(state, target);
		bool ok = true;
		if (next == ECMSK_STATE_SAFEOP && state == ECMSK_STATE_PREOP) {
			ok = toSafeOp();
		} else if (next == ECMSK_STATE_OP) {
			// S -> O completes with the first valid outputs
			for (auto &c : sl) {
				c.tPos = c.pos; // hold where the axis is
				c.tVel = 0;
				c.tTrq = 0;
				c.s->alControl(static_cast<std::uint8_t>(sim::AlState::Op));
			}
			fifo.clear();
			threshold = thresholdDefault();
			opPending = true;
			opDeadline = now + 100ms;
			return;
		} else {
			ok = alAll(next);
		}
		if (!ok)
			return;
		if (next < ECMSK_STATE_OP) {
			fifo.clear();
			for (auto &c : sl)
				c.enable = c.homing = false;
			homingRunning = false;
		}
		state = next;
		stateStepAt = now + stateStepTime();
	}

	// ---- one EtherCAT cycle ----
	void cycle()
	{
		st.cycles++;
		stateStep();
		if (state == ECMSK_STATE_OP)
			applyFifo();
		const bool pd = state == ECMSK_STATE_SAFEOP || state == ECMSK_STATE_OP;
		const ns dt = cycleTime();
		for (auto &c : sl) {
			if (!pd) {
				c.s->idle(dt);
				continue;
			}
			compose(c);
			c.s->cycle(c.out, state == ECMSK_STATE_OP || opPending, c.in, dt, true);
			parse(c);
		}
		if (testMode && state == ECMSK_STATE_OP) {
			// walking outputs, one step per 100 ms (1.3.4)
			const auto step = static_cast<unsigned>(st.cycles / 100 % 8);
			for (auto &c : sl)
				if (c.actual == ECMSK_AXIS_IO)
					c.ioOut = 1u << step;
		}
		if (sdoBusy && now >= sdoDoneAt)
			finishSdo();
	}

	void applyFifo()
	{
		// CONFIG3: an entry not carried out within 100 cycles is
		// abandoned, held by a threshold or not; it is counted in the FIFO
		// full count the host reads (decision: the one counter of
		// commands the FIFO did not carry out), never dropped unseen
		if (cfg.fifoAbandon) {
			const auto gone = std::erase_if(fifo, [&](const FifoEntry &e) {
				return st.cycles - e.cycle > kAbandonCycles;
			});
			st.fifoAbandoned += gone;
			fifoFull += static_cast<unsigned>(gone);
		}
		if (fifo.empty())
			return;
		if (cfg.fifoDepth - fifo.size() >= threshold)
			return; // prefill: not yet below the threshold
		threshold = thresholdDefault(); // met: back to the default (2.1.6)
		std::array<bool, ECMSK_SLAVES_MAX + 1> taken{};
		std::size_t w = 0;
		for (std::size_t r = 0; r < fifo.size(); r++) {
			FifoEntry &e = fifo[r];
			if (!taken[e.slave]) {
				taken[e.slave] = true;
				apply(sl[e.slave - 1u], e);
				st.fifoApplied++;
				continue;
			}
			fifo[w++] = e;
		}
		fifo.resize(w);
	}

	void apply(SlaveCtx &c, const FifoEntry &e)
	{
		if (e.two) {
			if (e.cmd == ECMSK_CMD_CSP)
				c.tPos2 = static_cast<std::int32_t>(e.target2);
			else
				c.tVel2 = static_cast<std::int32_t>(e.target2);
		}
		switch (e.cmd) {
		case ECMSK_CMD_CSP: c.tPos = static_cast<std::int32_t>(e.target); break;
		case ECMSK_CMD_CSV: c.tVel = static_cast<std::int32_t>(e.target); break;
		default: c.tTrq = static_cast<std::int16_t>(e.target); break;
		}
	}

	void compose(SlaveCtx &c)
	{
		if (c.actual == ECMSK_AXIS_IO) {
			for (std::size_t i = 0; i < c.out.size() && i < 4; i++)
				c.out[i] = static_cast<std::uint8_t>(c.ioOut >> (8 * i));
			return;
		}
		const Cia cs = ciaState(c.sw);
		std::uint16_t cw = 0;
		if (c.faultReset) {
			cw = (c.cw & 0x80) ? 0x00 : 0x80;
			if (cw == 0x80)
				c.faultReset = false;
		} else if (c.enable) {
			switch (cs) {
			case Cia::SwitchOnDisabled: cw = 0x06; break;
			case Cia::ReadyToSwitchOn: cw = 0x07; break;
			case Cia::SwitchedOn:
			case Cia::OperationEnabled:
			case Cia::QuickStopActive: cw = 0x0F; break;
			default: cw = 0x00; break;
			}
		} else {
			cw = (cs == Cia::SwitchOnDisabled || cs == Cia::Fault || cs == Cia::NotReadyToSwitchOn) ? 0x00 : 0x06;
		}
		if (c.homing && cs == Cia::OperationEnabled)
			cw |= 0x10;
		if (cs != Cia::OperationEnabled) {
			c.tPos = c.pos;	// no jump when the drive is enabled
			c.tVel = 0;
			c.tTrq = 0;
		}
		c.cw = cw;
		if (c.hsp2)
			compose2(c);
		const int mode = c.homing ? 6 : c.modeOverride >= 0 ? c.modeOverride : c.mode;
		putAt<std::uint16_t>(c.out, c.oCw, cw);
		putAt<std::int32_t>(c.out, c.oPos, c.tPos);
		putAt<std::int32_t>(c.out, c.oVel, c.tVel);
		putAt<std::int16_t>(c.out, c.oTrq, c.tTrq);
		putAt<std::int8_t>(c.out, c.oMode, static_cast<std::int8_t>(mode));
	}

	// channel 2 of a 2-channel HSP: the same enable sequence, its own targets
	static void compose2(SlaveCtx &c)
	{
		const Cia cs = ciaState(c.sw2);
		std::uint16_t cw = 0x06;
		if (c.enable)
			cw = cs == Cia::SwitchOnDisabled ? 0x06 : cs == Cia::ReadyToSwitchOn ? 0x07 : 0x0F;
		else if (cs == Cia::SwitchOnDisabled || cs == Cia::NotReadyToSwitchOn)
			cw = 0x00;
		if (cs != Cia::OperationEnabled) {
			c.tPos2 = c.pos2;
			c.tVel2 = 0;
		}
		c.cw2 = cw;
		putAt<std::uint16_t>(c.out, c.oCw2, cw);
		putAt<std::int32_t>(c.out, c.oPos2, c.tPos2);
		putAt<std::int32_t>(c.out, c.oVel2, c.tVel2);
		putAt<std::int8_t>(c.out, c.oMode2, static_cast<std::int8_t>(c.mode == ECMSK_MODE_CSV ? 9 : 8));
	}

	void parse(SlaveCtx &c)
	{
		if (c.actual == ECMSK_AXIS_IO) {
			std::uint32_t v = 0;
			for (std::size_t i = 0; i < c.in.size() && i < 4; i++)
				v |= std::uint32_t{ c.in[i] } << (8 * i);
			c.din = v;
			return;
		}
		getAt(c.in, c.iSw, c.sw);
		getAt(c.in, c.iPos, c.pos);
		getAt(c.in, c.iTrq, c.trq);
		getAt(c.in, c.iErr, c.err);
		getAt(c.in, c.iMode, c.modeDisp);
		getAt(c.in, c.iDin, c.din);
		getAt(c.in, c.iSw2, c.sw2);
		getAt(c.in, c.iPos2, c.pos2);
		getAt(c.in, c.iDin2, c.din2);
		if (c.homing) {
			const bool done = (c.sw & ECMSK_SW_HOMED) == ECMSK_SW_HOMED && c.modeDisp == 6;
			if ((c.sw & ECMSK_SW_HOMING_ERROR) || done)
				endHoming(c);
		}
	}

	void endHoming(SlaveCtx &c)
	{
		c.homing = false;
		c.modeOverride = -1;
		c.methodSet = false;
		homingRunning = std::any_of(sl.begin(), sl.end(), [](const SlaveCtx &x) { return x.homing; });
		// back to the DRIVE_MODE mode (2.1.18, hint 2)
		if (c.oMode < 0)
			sdoWrite(c, 0x6060, 0, c.mode, 1);
		c.tPos = c.pos;
	}

	// ---- SDO slot ----
	void startSdo(const ecmsk_sdo &c)
	{
		sdoAns = c;
		sdoAns.status = ECMSK_SDO_BUSY;
		sdoAns.value = 0;
		if (c.cmd == ECMSK_CMD_SDO_RD)
			sdoAns.size = 0;
		sdoBusy = true;
		ns lat = 1ms;
		if (c.slave >= 1 && c.slave <= sl.size())
			lat = sl[c.slave - 1u].s->mailboxLatency();
		sdoDoneAt = now + std::max(lat, cycleTime());
		pendingSdo = c;
	}

	ecmsk_sdo pendingSdo{};

	void finishSdo()
	{
		const ecmsk_sdo &c = pendingSdo;
		sdoBusy = false;
		sdoAns.status = ECMSK_SDO_FAILED;
		if (c.slave < 1 || c.slave > sl.size()) {
			sdoAns.value = sim::abort::GeneralError;
			return;
		}
		SlaveCtx &s = sl[c.slave - 1u];
		std::uint32_t code = 0;
		if (c.cmd == ECMSK_CMD_SDO_RD) {
			std::vector<std::uint8_t> out;
			code = s.s->sdoUpload(c.index, c.subindex, false, out);
			if (!code && out.size() > 4)
				code = sim::abort::LengthTooHigh;
			if (!code) {
				std::uint32_t v = 0;
				for (std::size_t i = 0; i < out.size(); i++)
					v |= std::uint32_t{ out[i] } << (8 * i);
				sdoAns.value = v;
				sdoAns.size = static_cast<std::uint8_t>(out.size());
			}
		} else {
			code = s.s->sdoDownload(c.index, c.subindex, false, le(c.value, c.size));
			if (!code)
				sdoAns.value = c.value; // the object value echoed (table 2.9)
			if (!code && c.index == 0x6060 && c.subindex == 0)
				s.modeOverride = static_cast<std::int8_t>(c.value);
			if (!code && c.index == 0x6098 && c.subindex == 0)
				s.methodSet = true;
		}
		if (code) {
			sdoAns.value = code;
			return;
		}
		sdoAns.status = ECMSK_SDO_DONE;
	}

	// ---- a command frame ----
	bool allowed(std::uint16_t cmd) const { return ecmsk_cmd_states(cmd) & state; }

	void refuse() { st.refused++; }

	void ecmCommand(const ecmsk_ecm_cmd &c)
	{
		ansCmd = static_cast<std::uint8_t>(c.cmd);
		if (c.cmd == ECMSK_CMD_GET_STATUS)
			return; // bytes 1-11 keep the last result (2.1.1)
		if (!ecmsk_cmd_known(c.cmd) || !allowed(c.cmd)) {
			ansCmd = 0;
			refuse();
			return;
		}
		switch (c.cmd) {
		case ECMSK_CMD_SET_STATE:
			if (!ecmsk_state_valid(c.data1))
				break;
			requestState(static_cast<std::uint8_t>(c.data1));
			return;
		case ECMSK_CMD_SET_AXIS: {
			if (c.param >= ECMSK_AXIS_GROUPS)
				break;
			std::uint32_t mismatch = 0;
			std::array<std::uint8_t, 8> types{};
			for (unsigned i = 0; i < 8; i++) {
				const unsigned n = c.param * 8u + i;
				types[i] = static_cast<std::uint8_t>((c.data1 >> (4 * i)) & 0xF);
				if (types[i] == ECMSK_AXIS_NONE)
					continue;
				// a zero nibble (Drive, the topology's default value,
				// table 2.3) for a slave that is not there is what a
				// host sends for "no slave": no mismatch
				if (types[i] == ECMSK_AXIS_DRIVE && n >= sl.size())
					continue;
				if (types[i] > ECMSK_AXIS_STEP)
					mismatch |= 1u << i;
				else if (state == ECMSK_STATE_PREOP &&
					 (n >= sl.size() || sl[n].actual != types[i]))
					mismatch |= 1u << i;
			}
			if (!mismatch)
				for (unsigned i = 0; i < 8; i++) {
					const unsigned n = c.param * 8u + i;
					if (n < sl.size() && types[i] != ECMSK_AXIS_NONE)
						sl[n].type = types[i];
				}
			ansData1 = state == ECMSK_STATE_PREOP ? static_cast<std::uint32_t>(sl.size()) : 0;
			ansData2 = mismatch;
			return;
		}
		case ECMSK_CMD_SET_DC:
			if (!ecmsk_dc_cycle_valid(c.data1) || c.data2 != ECMSK_DC_FIX ||
			    c.data1 > 64000)
				break;
			cycleUs = c.data1;
			return;
		case ECMSK_CMD_SET_EX:
			if (c.data1 > (ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC))
				break;
			exSaved = c.data1; // from the next power-on (2.1.5)
			return;
		case ECMSK_CMD_SET_FIFO:
			if (c.param == ECMSK_FIFO_CLEAR) {
				fifo.clear();
				threshold = thresholdDefault();
				return;
			}
			if (c.param == ECMSK_FIFO_THRESHOLD) {
				threshold = c.data1 ? static_cast<unsigned>(std::min<std::uint32_t>(c.data1, 0xFFFF))
						    : thresholdDefault();
				return;
			}
			break;
		case ECMSK_CMD_LIO_RD:
			ansData1 = lioIn & 0x3F;
			return;
		case ECMSK_CMD_LIO_WR:
			if (c.data1 > 0x3F)
				break;
			lioOut = c.data1;
			return;
		default:
			break;
		}
		ansCmd = 0; // refused: answered as GET_STATUS
		refuse();
	}

	void slaveCommand(unsigned n, const ecmsk_slave_cmd &c)
	{
		SlaveCtx &s = sl[n - 1];
		s.ansCmd = c.cmd;
		s.ansIdx = c.index;
		s.ansData1 = false;
		if (c.cmd == ECMSK_CMD_GET_STATUS)
			return;
		auto no = [&] {
			s.ansCmd = 0;
			refuse();
		};
		if (!ecmsk_cmd_is_slave(c.cmd) || !allowed(c.cmd))
			return no();
		const bool drive = driveLike(s.type) && s.type == s.actual;
		const bool io = s.type == ECMSK_AXIS_IO && s.actual == ECMSK_AXIS_IO;
		switch (c.cmd) {
		case ECMSK_CMD_DRIVE_MODE:
			if (!drive || c.target < ECMSK_MODE_CSP || c.target > ECMSK_MODE_CST || c.value > 1)
				return no();
			if (state == ECMSK_STATE_PREOP) {
				std::vector<std::uint8_t> m;
				if (s.s->sdoUpload(0x6502, 0, false, m) == 0 && m.size() == 4) {
					const std::uint32_t modes = sim::le32(m.data());
					if (!(modes & (1u << (c.target - 1))))
						return no();
				}
			}
			s.mode = static_cast<std::uint8_t>(c.target);
			s.sync = static_cast<std::uint8_t>(c.value);
			return;
		case ECMSK_CMD_ALM_CLR:
			if (!drive)
				return no();
			s.faultReset = true;
			return;
		case ECMSK_CMD_SV_ON:
		case ECMSK_CMD_SV_OFF:
			if (!drive)
				return no();
			s.enable = c.cmd == ECMSK_CMD_SV_ON;
			return;
		case ECMSK_CMD_IO_RD:
			if (!io)
				return no();
			s.ansData = s.din;
			s.ansData1 = true;
			return;
		case ECMSK_CMD_IO_WR:
			if (!io)
				return no();
			s.ioOut = c.target;
			return;
		case ECMSK_CMD_CSP:
		case ECMSK_CMD_CSV:
		case ECMSK_CMD_CST:
			if (!drive || s.mode != c.cmd - ECMSK_CMD_CSP + ECMSK_MODE_CSP)
				return no();
			if (fifo.size() >= cfg.fifoDepth) {
				fifoFull++;
				st.fifoDropped++;
				return; // answered, but dropped and counted (2.1.15)
			}
			if (s.hsp2 && g.slot_size == ECMSK_SLOT16 && c.cmd != ECMSK_CMD_CST) {
				ecmsk_hsp2 h{};
				ecmsk_get_hsp2(&g, frameIn, n, &h);
				fifo.push_back({ static_cast<std::uint8_t>(n), c.cmd, h.pos1, h.io1, st.cycles, true,
						 h.pos2 });
				return;
			}
			fifo.push_back({ static_cast<std::uint8_t>(n), c.cmd, c.target, c.value, st.cycles });
			return;
		case ECMSK_CMD_GO_HOME:
			if (!drive || homingRunning || s.modeOverride != 6 || !s.methodSet)
				return no();
			s.homing = true;
			homingRunning = true;
			return;
		case ECMSK_CMD_ABORT_HOME:
			if (!drive)
				return no();
			for (auto &x : sl)
				if (x.homing)
					endHoming(x);
			return;
		default:
			return no();
		}
	}

	const std::uint8_t *frameIn = nullptr; // the frame being processed

	void process(std::span<const std::uint8_t> mosi)
	{
		st.frames++;
		if ((exInForce & ECMSK_EX_CMD_CRC) && !ecmsk_frame_crc_ok(mosi.data(), mosi.size())) {
			crcErrors++;
			st.crcRefused++;
			return;
		}
		ecmsk_ecm_cmd e{};
		ecmsk_get_ecm_cmd(&g, mosi.data(), &e);
		if (e.cmd == ECMSK_CMD_SW_RESET) {
			busyUntil = now + kResetBusy;
			powerOn(false); // SW_RESET restarts the firmware: SET_EX's setting applies
			return;
		}
		ecmCommand(e);
		frameIn = mosi.data();
		for (unsigned n = 1; n <= sl.size(); n++) {
			ecmsk_slave_cmd c{};
			ecmsk_get_slave_cmd(&g, mosi.data(), n, &c);
			slaveCommand(n, c);
		}
		ecmsk_sdo sdo{};
		ecmsk_get_sdo(&g, mosi.data(), &sdo);
		if (sdo.cmd == ECMSK_CMD_GET_STATUS)
			return;
		if ((sdo.cmd != ECMSK_CMD_SDO_RD && sdo.cmd != ECMSK_CMD_SDO_WR) || !allowed(sdo.cmd) ||
		    sdoBusy ||
		    (sdo.cmd == ECMSK_CMD_SDO_WR && sdo.size != 1 && sdo.size != 2 && sdo.size != 4)) {
			if (!sdoBusy)
				sdoAns = {};
			refuse();
			return;
		}
		startSdo(sdo);
	}

	void respond(std::span<std::uint8_t> miso)
	{
		std::fill(miso.begin(), miso.end(), 0);
		ecmsk_ecm_rsp r{};
		r.cmd = state == ECMSK_STATE_OP ? ECMSK_RSP_OP : ansCmd;
		r.crc_errors = crcErrors;
		r.state = state;
		r.data1 = ansData1;
		r.data2 = ansData2;
		const std::size_t used = fifo.size();
		r.fifo_remaining = static_cast<std::uint16_t>(cfg.fifoDepth - used);
		r.fifo_full = static_cast<std::uint16_t>(fifoFull);
		ecmsk_put_ecm_rsp(&g, miso.data(), &r);
		for (unsigned n = 1; n <= sl.size(); n++) {
			const SlaveCtx &c = sl[n - 1];
			ecmsk_slave_rsp s{};
			s.cmd = c.ansCmd;
			s.index = c.ansIdx;
			if (state == ECMSK_STATE_OP || state == ECMSK_STATE_SAFEOP) {
				s.statusword = c.sw;
				s.position = static_cast<std::uint32_t>(c.pos);
				s.torque = c.actual == ECMSK_AXIS_HSP ? static_cast<std::uint16_t>(c.din)
								       : static_cast<std::uint16_t>(c.trq);
				s.error_code = c.actual == ECMSK_AXIS_HSP ? 0 : c.err;
			}
			if (c.ansData1)
				s.position = c.ansData;
			if (c.hsp2 && g.slot_size == ECMSK_SLOT16) {
				// tables 2.16/2.18: two positions, two input words
				ecmsk_hsp2 h{ s.cmd, s.index, s.statusword, s.position,
					      static_cast<std::uint16_t>(c.din), static_cast<std::uint32_t>(c.pos2),
					      static_cast<std::uint16_t>(c.din2) };
				if (state != ECMSK_STATE_OP && state != ECMSK_STATE_SAFEOP)
					h = { s.cmd, s.index, 0, 0, 0, 0, 0 };
				ecmsk_put_hsp2_rsp(&g, miso.data(), n, &h);
				continue;
			}
			ecmsk_put_slave_rsp(&g, miso.data(), n, &s);
		}
		ecmsk_put_sdo_rsp(&g, miso.data(), &sdoAns);
		if (exInForce & ECMSK_EX_RSP_CRC)
			ecmsk_frame_seal(miso.data(), miso.size());
		else
			miso[ECMSK_CRC_OFFSET] = 0;
	}

	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
	{
		if (mosi.size() != g.frame_size || miso.size() != g.frame_size) {
			st.badLength++;
			std::fill(miso.begin(), miso.end(), 0);
			advance(ns(static_cast<std::int64_t>(std::max(mosi.size(), miso.size())) * 8 *
				   1'000'000'000LL / cfg.spiHz));
			return;
		}
		if (now < busyUntil) {
			st.whileBusy++;
			std::fill(miso.begin(), miso.end(), 0);
			advance(wireTime());
			return;
		}
		respond(miso); // clocked out while the command is clocked in
		advance(wireTime());
		busyUntil = now + cfg.busyTime;
		process(mosi);
	}
};

// ---------------------------------------------------------------------------

SimBoard::SimBoard(sim::Network network, BoardConfig config)
	: d_(std::make_unique<Impl>(std::move(network), config))
{
}

SimBoard::~SimBoard() = default;

const BoardConfig &SimBoard::config() const noexcept { return d_->cfg; }
std::size_t SimBoard::frameSize() const noexcept { return d_->g.frame_size; }
void SimBoard::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	d_->exchange(mosi, miso);
}
bool SimBoard::busy() const noexcept { return d_->now < d_->busyUntil; }
std::chrono::nanoseconds SimBoard::now() const noexcept { return d_->now; }
void SimBoard::advance(std::chrono::nanoseconds dt)
{
	if (dt.count() > 0)
		d_->advance(dt);
}
void SimBoard::powerCycle()
{
	d_->busyUntil = d_->now + kResetBusy;
	d_->powerOn(true);
}
std::uint8_t SimBoard::state() const noexcept { return d_->state; }
std::uint32_t SimBoard::cycleUs() const noexcept { return d_->cycleUs; }
std::uint32_t SimBoard::extensionsInForce() const noexcept { return d_->exInForce; }
std::uint32_t SimBoard::extensionsSaved() const noexcept { return d_->exSaved; }
std::uint32_t SimBoard::lioOutputs() const noexcept { return d_->lioOut; }
void SimBoard::setLioInputs(std::uint32_t inputs) { d_->lioIn = inputs & 0x3F; }
unsigned SimBoard::fifoUsed() const noexcept { return static_cast<unsigned>(d_->fifo.size()); }
unsigned SimBoard::fifoFullCount() const noexcept { return d_->fifoFull; }
unsigned SimBoard::fifoThreshold() const noexcept { return d_->threshold; }
std::uint8_t SimBoard::crcErrors() const noexcept { return d_->crcErrors; }
std::uint8_t SimBoard::slaveType(unsigned position) const
{
	if (position < 1 || position > d_->sl.size())
		return ECMSK_AXIS_NONE;
	return d_->sl[position - 1].type;
}
std::uint8_t SimBoard::driveMode(unsigned position) const
{
	if (position < 1 || position > d_->sl.size())
		return 0;
	return d_->sl[position - 1].mode;
}
std::uint8_t SimBoard::driveSync(unsigned position) const
{
	if (position < 1 || position > d_->sl.size())
		return 0;
	return d_->sl[position - 1].sync;
}
const std::string &SimBoard::lastError() const noexcept { return d_->lastError; }
const BoardStats &SimBoard::stats() const noexcept { return d_->st; }
sim::Network &SimBoard::network() noexcept { return d_->net; }
std::chrono::nanoseconds SimBoard::wireTime() const noexcept { return d_->wireTime(); }

} // namespace ecmxf::sk
