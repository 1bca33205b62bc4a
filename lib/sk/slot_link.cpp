// SPDX-License-Identifier: MIT
// SlotLink: the slot protocol core over a ByteChannel
// (include/ecmxf/sk/slot_link.hpp, lib/sk/slot_link.hpp,
// Documentation/ecm-sk.rst).

#include "slot_link.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <utility>

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sk/sim_channel.hpp>

namespace ecmxf::sk {

using namespace std::chrono_literals;

std::string skSlave(unsigned slot)
{
	return "slave " + std::to_string(slot - 1);
}

std::string skHex(std::uint32_t v, int digits)
{
	char b[16];
	std::snprintf(b, sizeof(b), "0x%0*X", digits, v);
	return b;
}

namespace {

std::string statesText(unsigned mask)
{
	std::string s;
	for (ecmxf::State st : { ecmxf::State::Init, ecmxf::State::PreOp, ecmxf::State::SafeOp, ecmxf::State::Op })
		if (mask & static_cast<unsigned>(st)) {
			if (!s.empty())
				s += ", ";
			s += stateName(st);
		}
	return s;
}

std::uint64_t ns(std::chrono::nanoseconds t)
{
	return t.count() > 0 ? static_cast<std::uint64_t>(t.count()) : 0;
}

} // namespace

namespace {

/// The channel, and the simulated board behind it: taken apart before
/// either is used, so that the channel has one owner throughout.
std::pair<std::unique_ptr<ByteChannel>, SimBoard *> withBoard(std::unique_ptr<SimBoardChannel> channel)
{
	SimBoard *board = channel ? &channel->board() : nullptr;
	return { std::move(channel), board };
}

} // namespace

SlotLink::SlotLink(std::unique_ptr<ByteChannel> channel, LinkOptions options)
	: SlotLink(std::pair<std::unique_ptr<ByteChannel>, SimBoard *>(std::move(channel), nullptr), options)
{
}

SlotLink::SlotLink(std::unique_ptr<SimBoardChannel> channel, LinkOptions options)
	: SlotLink(withBoard(std::move(channel)), options)
{
}

SlotLink::SlotLink(std::pair<std::unique_ptr<ByteChannel>, SimBoard *> channel, LinkOptions options)
	: channel_(std::move(channel.first))
{
	if (!channel_)
		throw Error("ECM-SK: no channel", EINVAL);
	impl_ = std::make_unique<Impl>(*channel_, channel.second);
	std::uint32_t flags = 0;
	if (options.extensions & ~(ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC))
		throw Error("ECM-SK: extension bits " + skHex(options.extensions, 2) + " (SET_EX has bits 0 and 1)",
			    EINVAL);
	if (options.extensions & ECMSK_EX_CMD_CRC)
		flags |= ECMSK_LINK_TX_CRC;
	if (options.extensions & ECMSK_EX_RSP_CRC)
		flags |= ECMSK_LINK_RX_CRC;
	if (ecmsk_link_init(&impl_->l, options.slotSize, flags))
		throw Error("ECM-SK: slot size " + std::to_string(options.slotSize) +
				    " (12 or 16, the board's CONFIG2)",
			    EINVAL);
	impl_->busyTimeout = options.busyTimeout;
	impl_->mosi.assign(impl_->l.g.frame_size, 0);
	impl_->miso.assign(impl_->l.g.frame_size, 0);
}

SlotLink::~SlotLink() = default;

SimBoard *SlotLink::simulator() noexcept { return impl_->simulator(); }
unsigned SlotLink::slotSize() const noexcept { return impl_->l.g.slot_size; }
unsigned SlotLink::maxSlaves() const noexcept { return impl_->l.g.max_slaves; }
std::size_t SlotLink::frameSize() const noexcept { return impl_->l.g.frame_size; }
ecmxf::State SlotLink::state() const noexcept { return impl_->state(); }

// ---------------------------------------------------------------------------
// The packet trace (the writer: lib/link/trace_writer.cpp)
// ---------------------------------------------------------------------------

void SlotLink::startTrace(std::string_view path)
{
	auto w = std::make_unique<detail::TraceWriter>(path);
	// the SET_EX setting the link works with (fixed until the board's
	// next power-on): the CRC-8 in force in each direction
	w->skFormat(impl_->l.g.slot_size, impl_->l.flags & (ECMSK_LINK_TX_CRC | ECMSK_LINK_RX_CRC));
	auto old = std::exchange(impl_->trace, std::move(w));
	if (old)
		old->close();
}

void SlotLink::stopTrace()
{
	auto w = std::exchange(impl_->trace, nullptr);
	if (w)
		w->close();
}

bool SlotLink::tracing() const noexcept
{
	return impl_->trace != nullptr;
}

void SlotLink::Impl::xfer()
{
	if (!ch.waitReady(busyTimeout))
		throw Error(ch.name() + ": the ECM-SK's Busy line stayed high for " +
				    std::to_string(busyTimeout.count()) + " ms",
			    ETIMEDOUT);
	const std::uint64_t sentNs = ns(ch.now());
	const int pr = ecmsk_link_prepare(&l, mosi.data(), sentNs, 0);
	if (pr) {
		std::fill(mosi.begin(), mosi.end(), 0);
		staged = {};
		stagedCount = 0;
		throw Error(ch.name() + (pr == -EBUSY ? ": an SDO or a GO_HOME is still running"
						      : ": a command in the wrong slot"),
			    -pr);
	}
	// the frame sent is recorded before the transfer: a transfer that
	// fails still shows what was sent
	if (trace)
		trace->skFrame(sentNs, '>', mosi);
	ch.exchange(mosi, miso);
	const std::uint64_t recvNs = ns(ch.now());
	if (trace)
		trace->skFrame(recvNs, '<', miso);
	std::fill(mosi.begin(), mosi.end(), 0);
	staged = {};
	// the response came out while this frame went in: it shows the FIFO
	// without this frame's cyclic commands
	inFlight = stagedCount;
	stagedCount = 0;
	const int cr = ecmsk_link_complete(&l, miso.data(), recvNs, &res);
	if (res.state_done) {
		stateDone = true;
		stateErr = res.state_err;
	}
	if (res.sdo_done) {
		sdoDone = true;
		sdoErr = res.sdo_err;
		sdo = res.sdo;
	}
	if (res.home_done) {
		homeDone = true;
		homeErr = res.home_err;
	}
	if (cr == 0) {
		lastFull = res.ecm.fifo_full;
		if (res.ecm.state == ECMSK_STATE_OP)
			fifoDepth = std::max(fifoDepth, res.ecm.fifo_remaining);
	}
	if (cr)
		throw Error(ch.name() + ": the ECM-SK's response failed its CRC-8", EBADMSG);
}

void SlotLink::Impl::transact()
{
	xfer();
	xfer();
	if (res.refused)
		throw Error(ch.name() + ": the ECM-SK refused the frame for a bad CRC-8 (it checks command "
					"CRCs: give ex=1 or ex=3 in the URI)",
			    EBADMSG);
}

void SlotLink::Impl::knowState()
{
	if (!l.have_rsp)
		xfer();
}

void SlotLink::Impl::require(std::uint16_t cmd, const char *what) const
{
	const unsigned ok = ecmsk_cmd_states(cmd);
	if (!(ok & l.state))
		throw Error(std::string(what) + " is allowed in " + statesText(ok) + "; the ECM-SK is in " +
				    stateName(state()),
			    EPERM);
}

void SlotLink::Impl::checkSlave(unsigned slave, const char *cmd) const
{
	if (slave < 1 || slave > l.g.max_slaves)
		throw Error(std::string(cmd) + ": slave " + std::to_string(slave) + " is outside 1.." +
				    std::to_string(l.g.max_slaves),
			    EINVAL);
}

void SlotLink::Impl::refused(const std::string &cmd, const std::string &why) const
{
	throw Error("the ECM-SK refused " + cmd + " in " + stateName(state()) + ": " + why, EPERM);
}

void SlotLink::Impl::ecmCommand(std::uint16_t cmd, std::uint8_t param, std::uint32_t data1, std::uint32_t data2)
{
	ecmsk_ecm_cmd c{ cmd, param, data1, data2, 0 };
	ecmsk_put_ecm(&l.g, mosi.data(), &c);
	transact();
}

void SlotLink::Impl::slaveCommand(unsigned slave, std::uint8_t cmd, std::uint32_t target, std::uint32_t value)
{
	const char *name = ecmsk_cmd_name(cmd);
	checkSlave(slave, name);
	knowState();
	require(cmd, name);
	ecmsk_slave_cmd c{ cmd, ++nextIndex, target, value, 0 };
	ecmsk_put_slave(&l.g, mosi.data(), slave, &c);
	transact();
	if (!ecmsk_link_answered(&l, slave, miso.data()))
		refused(std::string(name) + " for " + skSlave(slave),
			"not a command for that slave's type (SET_AXIS), mode (DRIVE_MODE) or state");
}

bool SlotLink::Impl::waitDone(const bool &done, std::chrono::nanoseconds start, std::chrono::nanoseconds timeout,
			      std::chrono::nanoseconds period)
{
	const auto end = start + timeout;
	while (!done) {
		if (ch.now() >= end)
			return false;
		ch.sleepFor(period);
		xfer();
	}
	return true;
}

void SlotLink::Impl::sdoRun(const ecmsk_sdo &c, const std::string &what)
{
	ecmsk_put_sdo(&l.g, mosi.data(), &c);
	sdoDone = false;
	const auto start = ch.now();
	xfer();
	if (!waitDone(sdoDone, start, 5s, 250us)) {
		l.sdo.active = false;
		throw Error(what + ": no answer within 5 s", ETIMEDOUT);
	}
	if (sdoErr == -EIO)
		throw SdoError(what + ": aborted, " + skHex(sdo.value, 8) + " " + std::string(sdoAbortText(sdo.value)),
			       EREMOTEIO, sdo.value);
	if (sdoErr == -EACCES)
		refused(what, "SDO is allowed in PRE-OP, SAFE-OP and OP");
	if (sdoErr)
		throw Error(what + ": failed", -sdoErr);
}

} // namespace ecmxf::sk
