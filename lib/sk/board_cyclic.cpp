// SPDX-License-Identifier: MIT
// BoardCyclic: the ECM-SK's cyclic path, allocation-free and never
// throwing (include/ecmxf/sk/board_views.hpp).

#include <ecmxf/sk/board_views.hpp>

#include <cerrno>
#include <exception>

#include <ecmxf/error.hpp>

#include "slot_link.hpp"

namespace ecmxf::sk {

namespace {

// room for one more cyclic command in the FIFO, as the board last
// reported it, less those staged and in flight: the back-pressure. And
// never more than CONFIG3's 100 queued (FIFO used, as the depth less the
// remaining space, plus those staged and in flight): one entry per slave
// is applied per cycle, so none waits long enough to be abandoned.
bool fifoRoom(const SlotLink::Impl &k) noexcept
{
	const unsigned ahead = k.stagedCount + k.inFlight;
	const unsigned remaining = k.res.ecm.fifo_remaining;
	const unsigned used = k.fifoDepth > remaining ? k.fifoDepth - remaining : 0u;
	return ahead < remaining && used + ahead < ECMSK_FIFO_ABANDON_CYCLES;
}

} // namespace

bool BoardCyclic::stage(unsigned slave, Mode mode, std::int32_t target, std::uint32_t output) noexcept
{
	auto &k = link_->impl();
	if (slave < 1 || slave > k.l.g.max_slaves || k.staged[slave])
		return false;
	if (k.l.state != ECMSK_STATE_OP || !fifoRoom(k))
		return false;
	const auto cmd = static_cast<std::uint8_t>(ECMSK_CMD_CSP + (static_cast<unsigned>(mode) - ECMSK_MODE_CSP));
	ecmsk_slave_cmd c{ cmd, ++k.nextIndex, static_cast<std::uint32_t>(target), output, 0 };
	if (ecmsk_put_slave(&k.l.g, k.mosi.data(), slave, &c))
		return false;
	k.staged[slave] = true;
	k.stagedCount++;
	return true;
}

bool BoardCyclic::stage2(unsigned slave, Mode mode, std::int32_t target1, std::int32_t target2,
			 std::uint16_t output1, std::uint16_t output2) noexcept
{
	auto &k = link_->impl();
	if (k.l.g.slot_size != ECMSK_SLOT16 || mode == Mode::Cst)
		return false;
	if (slave < 1 || slave > k.l.g.max_slaves || k.staged[slave] || k.l.state != ECMSK_STATE_OP)
		return false;
	if (!fifoRoom(k))
		return false;
	const auto cmd = static_cast<std::uint8_t>(mode == Mode::Csp ? ECMSK_CMD_CSP : ECMSK_CMD_CSV);
	ecmsk_hsp2 c{ cmd, ++k.nextIndex, 0, static_cast<std::uint32_t>(target1), output1,
		      static_cast<std::uint32_t>(target2), output2 };
	if (ecmsk_put_hsp2(&k.l.g, k.mosi.data(), slave, &c))
		return false;
	k.staged[slave] = true;
	k.stagedCount++;
	return true;
}

CycleResult BoardCyclic::cycle() noexcept
{
	auto &k = link_->impl();
	CycleResult r;
	r.staged = k.stagedCount;
	const std::uint16_t before = k.lastFull;
	try {
		if (!k.ch.waitReady(k.busyTimeout)) {
			r.status = CycleStatus::Busy;
			return r;
		}
		k.xfer();
	} catch (const Error &e) {
		r.status = e.errnoValue() == EBADMSG ? CycleStatus::BadResponse : CycleStatus::Link;
		if (r.status == CycleStatus::Link)
			k.lastError = e.what();
		return r;
	} catch (const std::exception &e) {
		k.lastError = e.what();
		r.status = CycleStatus::Link;
		return r;
	}
	r.fifoRemaining = k.res.ecm.fifo_remaining;
	r.fifoFull = k.res.ecm.fifo_full;
	r.dropped = static_cast<std::uint16_t>(r.fifoFull - before);
	if (r.dropped)
		r.status = CycleStatus::FifoOverflow;
	return r;
}

const std::string &BoardCyclic::lastError() const noexcept
{
	return link_->impl().lastError;
}

} // namespace ecmxf::sk
