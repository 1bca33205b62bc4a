// SPDX-License-Identifier: MIT
// Netlink messages as the kernel sends them, built here with libmnl from
// the numbers written down by hand (nl_numbers.hpp) - 64-bit attributes
// aligned with a pad attribute as nla_put_u64_64bit() does - and decoded
// by the library (ecmxf::decodeEventMessage, decodeCountersMessage).

#include <catch2/catch.hpp>

#include <libmnl/libmnl.h>
#include <linux/genetlink.h>
#include <linux/netlink.h>

#include <cerrno>
#include <cstdint>
#include <span>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/events/events.hpp>

#include "nl_numbers.hpp"

using namespace nlabi;

namespace {

/// One message under construction.
class Msg
{
public:
	Msg(std::uint8_t cmd, std::uint16_t family = 0x1234) : buf_(512)
	{
		nlh_ = mnl_nlmsg_put_header(buf_.data());
		nlh_->nlmsg_type = family;
		auto *g = static_cast<genlmsghdr *>(mnl_nlmsg_put_extra_header(nlh_, sizeof(genlmsghdr)));
		g->cmd = cmd;
		g->version = static_cast<std::uint8_t>(kVersion);
	}
	Msg &u8(int t, std::uint8_t v)
	{
		mnl_attr_put_u8(nlh_, static_cast<std::uint16_t>(t), v);
		return *this;
	}
	Msg &u16(int t, std::uint16_t v)
	{
		mnl_attr_put_u16(nlh_, static_cast<std::uint16_t>(t), v);
		return *this;
	}
	Msg &u32(int t, std::uint32_t v)
	{
		mnl_attr_put_u32(nlh_, static_cast<std::uint16_t>(t), v);
		return *this;
	}
	/// As nla_put_u64_64bit(): a pad attribute first when the payload
	/// would not be 8-byte aligned.
	Msg &u64(int t, std::uint64_t v, int pad = Pad)
	{
		if ((nlh_->nlmsg_len + 4) % 8 != 0)
			mnl_attr_put(nlh_, static_cast<std::uint16_t>(pad), 0, nullptr);
		mnl_attr_put_u64(nlh_, static_cast<std::uint16_t>(t), v);
		return *this;
	}
	Msg &str(int t, const char *s)
	{
		mnl_attr_put_strz(nlh_, static_cast<std::uint16_t>(t), s);
		return *this;
	}
	Msg &flag(int t)
	{
		mnl_attr_put(nlh_, static_cast<std::uint16_t>(t), 0, nullptr);
		return *this;
	}
	Msg &raw(int t, std::vector<std::uint8_t> bytes)
	{
		mnl_attr_put(nlh_, static_cast<std::uint16_t>(t), bytes.size(), bytes.data());
		return *this;
	}
	nlattr *begin(int t) { return mnl_attr_nest_start(nlh_, static_cast<std::uint16_t>(t)); }
	Msg &end(nlattr *n)
	{
		mnl_attr_nest_end(nlh_, n);
		return *this;
	}
	/// The common attributes of an event.
	Msg &event(std::uint32_t type, std::uint32_t seq = 5)
	{
		return u32(DevMinor, 0).str(DevName, "ecmxf0").u32(EventType, type).u64(TimestampNs, 123456789).u32(Seq, seq);
	}
	[[nodiscard]] std::span<const std::uint8_t> bytes() const
	{
		return { reinterpret_cast<const std::uint8_t *>(buf_.data()), nlh_->nlmsg_len };
	}
	nlmsghdr *nlh() { return nlh_; }

private:
	std::vector<std::uint64_t> buf_;
	nlmsghdr *nlh_;
};

int errnoOf(std::span<const std::uint8_t> m, bool counters = false)
{
	try {
		if (counters)
			(void)ecmxf::decodeCountersMessage(m);
		else
			(void)ecmxf::decodeEventMessage(m);
	} catch (const ecmxf::Error &e) {
		return e.errnoValue();
	}
	return 0;
}

} // namespace

TEST_CASE("netlink decode: a state event with the slaves' AL status codes", "[netlink]")
{
	Msg m(CmdEvent);
	m.event(EvState, 17).u32(Old, 0x08).u32(New, 0x10).u32(SlaveCount, 3);
	nlattr *all = m.begin(Slaves);
	nlattr *s = m.begin(Slave);
	m.u16(SaPosition, 1).u8(SaState, 0x12).u16(SaAlStatus, 0x001B).end(s);
	s = m.begin(Slave);
	m.u16(SaPosition, 2).u8(SaState, 0x10).end(s);
	m.end(all).u16(AlStatus, 0x001B).u16(AlSlave, 1);

	const ecmxf::Event e = ecmxf::decodeEventMessage(m.bytes());
	CHECK(e.type == ecmxf::EventType::State);
	CHECK(e.minor == 0);
	CHECK(e.device == "ecmxf0");
	CHECK(e.time == std::chrono::nanoseconds(123456789));
	CHECK(e.seq == 17);
	CHECK(e.suppressed == 0);
	CHECK(e.oldValue == 0x08);
	CHECK(e.newValue == 0x10);
	CHECK(e.haveSlaves);
	CHECK(e.slaveCount == 3);
	CHECK_FALSE(e.slavesIncomplete);
	REQUIRE(e.slaves.size() == 2);
	CHECK(e.slaves[0].position == 1);
	CHECK(e.slaves[0].state == 0x12);
	REQUIRE(e.slaves[0].alStatus);
	CHECK(*e.slaves[0].alStatus == 0x001B);
	CHECK(e.slaves[1].position == 2);
	CHECK_FALSE(e.slaves[1].alStatus);
	REQUIRE(e.alStatus);
	CHECK(*e.alStatus == 0x001B);
	CHECK(*e.alSlave == 1);
}

TEST_CASE("netlink decode: link, reset, WKC burst end, FIFO, async error, device", "[netlink]")
{
	Msg link(CmdEvent);
	link.event(EvLink).u8(LinkUp, 0).u8(ErrStatus, 0x40).u32(Suppressed, 4);
	auto e = ecmxf::decodeEventMessage(link.bytes());
	CHECK(e.type == ecmxf::EventType::Link);
	CHECK_FALSE(e.linkUp);
	CHECK(e.errStatus == 0x40);
	CHECK(e.suppressed == 4);

	Msg reset(CmdEvent);
	reset.event(EvReset).u32(ResetReason, 2).u32(New, 0).u8(EcmStatus, 0x20);
	e = ecmxf::decodeEventMessage(reset.bytes());
	CHECK(e.resetReason == ecmxf::ResetReason::Warm);
	CHECK(e.ecmStatus == 0x20);

	Msg end(CmdEvent);
	end.event(EvWkcBurstEnd).u32(Errors, 255).u64(DurationNs, 7'000'000'001ull).u32(Count, 255);
	e = ecmxf::decodeEventMessage(end.bytes());
	CHECK(e.type == ecmxf::EventType::WkcBurstEnd);
	CHECK(e.errors == 255);
	CHECK(e.duration == std::chrono::nanoseconds(7'000'000'001ll));
	CHECK(e.count == 255);

	Msg fifo(CmdEvent);
	fifo.event(EvFifo).u8(Fifo, 1).u32(Count, 0).u32(Mark, 0).u8(Above, 0);
	e = ecmxf::decodeEventMessage(fifo.bytes());
	CHECK(e.fifo == ecmxf::FifoId::Rx);
	CHECK_FALSE(e.above);

	Msg async(CmdEvent);
	async.event(EvAsyncError).u8(CmdCode, 12).u32(Status, static_cast<std::uint32_t>(-EREMOTEIO)).u8(ErrStatus, 0x0B);
	e = ecmxf::decodeEventMessage(async.bytes());
	CHECK(e.type == ecmxf::EventType::AsyncError);
	CHECK(e.cmdCode == 12);
	CHECK(e.status == -EREMOTEIO);

	Msg dev(CmdEvent);
	dev.event(EvDevice, 0).u32(Action, 2);
	e = ecmxf::decodeEventMessage(dev.bytes());
	CHECK(e.action == ecmxf::DeviceAction::Removed);
}

TEST_CASE("netlink decode: a loss of the cyclic path, its counter and total", "[netlink]")
{
	// a total beyond 32 bits, after a u8 and a u32 (the pad attribute in between)
	Msg loss(CmdEvent);
	loss.event(EvPdoLoss).u8(Loss, LossInRingOverrun).u32(Increase, 37).u64(Total, 0x1'0000'0025ull);
	ecmxf::Event e = ecmxf::decodeEventMessage(loss.bytes());
	CHECK(e.type == ecmxf::EventType::PdoLoss);
	CHECK(ecmxf::eventTypeName(e.type) == "pdo_loss");
	CHECK(e.loss == ecmxf::LossKind::InRingOverrun);
	CHECK(ecmxf::lossKindName(e.loss) == "in_ring_overrun");
	CHECK(e.increase == 37);
	CHECK(e.total == 0x1'0000'0025ull);

	Msg skipped(CmdEvent);
	skipped.event(EvPdoLoss).u8(Loss, LossOutRingSkipped).u32(Increase, 1).u64(Total, 1);
	e = ecmxf::decodeEventMessage(skipped.bytes());
	CHECK(e.loss == ecmxf::LossKind::OutRingSkipped);
	CHECK(ecmxf::lossKindName(e.loss) == "out_ring_skipped");
	CHECK(ecmxf::lossKindName(ecmxf::LossKind::PumpFailure) == "pump_failure");
	CHECK(ecmxf::lossKindName(static_cast<ecmxf::LossKind>(9)) == "unknown");
}

TEST_CASE("netlink decode: unknown attributes and event types are kept apart, not errors", "[netlink]")
{
	Msg m(CmdEvent);
	m.event(42).u32(250, 7).raw(251, { 1, 2, 3 }).u8(LinkUp, 1).flag(SlavesIncomplete);
	const ecmxf::Event e = ecmxf::decodeEventMessage(m.bytes());
	CHECK(static_cast<std::uint32_t>(e.type) == 42);
	CHECK(ecmxf::eventTypeName(e.type) == "unknown");
	CHECK(e.linkUp);
	CHECK(e.slavesIncomplete);
}

TEST_CASE("netlink decode: malformed messages are EPROTO", "[netlink][errors]")
{
	// an attribute of a known type with the wrong size
	Msg shortSeq(CmdEvent);
	shortSeq.u32(EventType, EvLink).raw(Seq, { 1, 2 });
	CHECK(errnoOf(shortSeq.bytes()) == EPROTO);
	// no event type
	Msg noType(CmdEvent);
	noType.u32(DevMinor, 0);
	CHECK(errnoOf(noType.bytes()) == EPROTO);
	// counters where an event is expected, and the other way round
	Msg counters(CmdGetCounters);
	counters.u32(DevMinor, 0);
	CHECK(errnoOf(counters.bytes()) == EPROTO);
	Msg ev(CmdEvent);
	ev.event(EvLink);
	CHECK(errnoOf(ev.bytes(), true) == EPROTO);
	// a length field beyond the bytes given, and fewer bytes than headers
	Msg trunc(CmdEvent);
	trunc.event(EvLink);
	const auto b = trunc.bytes();
	CHECK(errnoOf(b.first(b.size() - 4)) == EPROTO);
	CHECK(errnoOf(b.first(10)) == EPROTO);
	// a slave without its position
	Msg slave(CmdEvent);
	slave.event(EvState);
	nlattr *all = slave.begin(Slaves);
	nlattr *s = slave.begin(Slave);
	slave.u8(SaState, 2).end(s).end(all);
	CHECK(errnoOf(slave.bytes()) == EPROTO);
}

TEST_CASE("netlink decode: counters, one attribute per field of struct ecmxf_counters", "[netlink]")
{
	Msg m(CmdGetCounters);
	m.u32(DevMinor, 3).str(DevName, "ecmxf3");
	nlattr *n = m.begin(Counters);
	for (int a = CExchanges; a <= CInt1Irqs; a++)
		m.u64(a, 1000u + static_cast<std::uint64_t>(a), CPad);
	m.u64(CEvents, 77, CPad).u64(CEventsSuppressed, 5, CPad).u64(CEventsFailed, 1, CPad);
	m.u64(99, 12345, CPad); // a counter of a later version
	m.end(n);
	const ecmxf::NetlinkCounters c = ecmxf::decodeCountersMessage(m.bytes());
	CHECK(c.minor == 3);
	CHECK(c.device == "ecmxf3");
	// the uAPI order: exchanges first, int1_irqs last
	CHECK(c.link.exchanges == 1002);
	CHECK(c.link.badNotReady == 1003);
	CHECK(c.link.badLength == 1007);
	CHECK(c.link.timeouts == 1011);
	CHECK(c.link.chipResets == 1015);
	CHECK(c.link.wkcErrors == 1016);
	CHECK(c.link.txFifoOverruns == 1021);
	CHECK(c.link.int0Irqs == 1022);
	CHECK(c.link.int1Irqs == 1023);
	CHECK(c.events == 77);
	CHECK(c.eventsSuppressed == 5);
	CHECK(c.eventsFailed == 1);

	Msg noNest(CmdGetCounters);
	noNest.u32(DevMinor, 0);
	CHECK(errnoOf(noNest.bytes(), true) == EPROTO);
}
