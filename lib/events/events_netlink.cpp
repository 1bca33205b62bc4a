// SPDX-License-Identifier: MIT
// The kernel module's generic netlink family "ecmxf" through libmnl:
// EventSubscriber (the "events" group), the counters command, and the
// decoders of both kinds of messages (<linux/ecmxf_netlink.h>).

#include <ecmxf/error.hpp>
#include <ecmxf/events/events.hpp>

#include <libmnl/libmnl.h>
#include <linux/genetlink.h>
#include <linux/netlink.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include "base/os.hpp"
#include "uapi/linux/ecmxf_netlink.h"

namespace ecmxf {

namespace {

/// libmnl's receive buffer size (a page, at most 8 KiB).
std::size_t bufferSize()
{
	return static_cast<std::size_t>(MNL_SOCKET_BUFFER_SIZE);
}

[[noreturn]] void fail(const std::string &what, int err)
{
	detail::throwErrno("netlink: " + what, err);
}

[[noreturn]] void malformed(const std::string &what)
{
	throw Error("netlink: malformed ecmxf message: " + what, EPROTO);
}

/// One whole message copied to 8-byte aligned storage.
struct Aligned {
	std::vector<std::uint64_t> words;
	const nlmsghdr *nlh = nullptr;

	explicit Aligned(std::span<const std::uint8_t> msg)
	{
		if (msg.size() < NLMSG_HDRLEN + GENL_HDRLEN)
			malformed("shorter than its headers");
		words.resize((msg.size() + 7) / 8);
		std::memcpy(words.data(), msg.data(), msg.size());
		nlh = reinterpret_cast<const nlmsghdr *>(words.data());
		if (nlh->nlmsg_len > msg.size() || nlh->nlmsg_len < NLMSG_HDRLEN + GENL_HDRLEN)
			malformed("length field " + std::to_string(nlh->nlmsg_len) + " for " +
				  std::to_string(msg.size()) + " bytes");
	}
	[[nodiscard]] const genlmsghdr *genl() const
	{
		return static_cast<const genlmsghdr *>(mnl_nlmsg_get_payload(nlh));
	}
};

/// Calls @p f for each attribute in [first, first + len).
void forEach(const nlattr *first, int len, const std::function<void(const nlattr *)> &f)
{
	for (const nlattr *a = first; mnl_attr_ok(a, len);) {
		f(a);
		const nlattr *next = mnl_attr_next(a);
		len -= static_cast<int>(reinterpret_cast<const char *>(next) - reinterpret_cast<const char *>(a));
		a = next;
	}
}

void forEachTop(const nlmsghdr *nlh, const std::function<void(const nlattr *)> &f)
{
	const auto *first = static_cast<const nlattr *>(mnl_nlmsg_get_payload_offset(nlh, GENL_HDRLEN));
	const int len = static_cast<int>(nlh->nlmsg_len) - static_cast<int>(NLMSG_HDRLEN + GENL_HDRLEN);
	forEach(first, len, f);
}

void forEachNested(const nlattr *nest, const std::function<void(const nlattr *)> &f)
{
	forEach(static_cast<const nlattr *>(mnl_attr_get_payload(nest)),
		static_cast<int>(mnl_attr_get_payload_len(nest)), f);
}

void need(const nlattr *a, mnl_attr_data_type t, const char *name)
{
	if (mnl_attr_validate(a, t) < 0)
		malformed(std::string("attribute ") + name + " has the wrong size");
}

/// The value of attribute @p a (named @p n in the error) as @p Get reads
/// it, once it has the size of a @p Type.
template <typename T, mnl_attr_data_type Type, auto Get>
T attr(const nlattr *a, const char *n)
{
	need(a, Type, n);
	return Get(a);
}

constexpr auto u8 = attr<std::uint8_t, MNL_TYPE_U8, mnl_attr_get_u8>;
constexpr auto u16 = attr<std::uint16_t, MNL_TYPE_U16, mnl_attr_get_u16>;
constexpr auto u32 = attr<std::uint32_t, MNL_TYPE_U32, mnl_attr_get_u32>;
constexpr auto u64 = attr<std::uint64_t, MNL_TYPE_U64, mnl_attr_get_u64>;
constexpr auto str = attr<std::string, MNL_TYPE_NUL_STRING, mnl_attr_get_str>;

SlaveAlStatus decodeSlave(const nlattr *nest)
{
	SlaveAlStatus s;
	bool pos = false;
	forEachNested(nest, [&](const nlattr *a) {
		switch (mnl_attr_get_type(a)) {
		case ECMXF_NL_SA_POSITION:
			s.position = u16(a, "SA_POSITION");
			pos = true;
			break;
		case ECMXF_NL_SA_STATE:
			s.state = u8(a, "SA_STATE");
			break;
		case ECMXF_NL_SA_AL_STATUS:
			s.alStatus = u16(a, "SA_AL_STATUS");
			break;
		default:
			break;
		}
	});
	if (!pos)
		malformed("a slave without its position");
	return s;
}

} // namespace

Event decodeEventMessage(std::span<const std::uint8_t> msg)
{
	const Aligned m(msg);
	if (m.genl()->cmd != ECMXF_NL_CMD_EVENT)
		malformed("command " + std::to_string(m.genl()->cmd) + " is not ECMXF_NL_CMD_EVENT");
	Event e;
	bool haveType = false;
	forEachTop(m.nlh, [&](const nlattr *a) {
		switch (mnl_attr_get_type(a)) {
		case ECMXF_NL_A_DEV_MINOR: e.minor = u32(a, "DEV_MINOR"); break;
		case ECMXF_NL_A_DEV_NAME: e.device = str(a, "DEV_NAME"); break;
		case ECMXF_NL_A_EVENT_TYPE:
			e.type = static_cast<EventType>(u32(a, "EVENT_TYPE"));
			haveType = true;
			break;
		case ECMXF_NL_A_TIMESTAMP_NS:
			e.time = std::chrono::nanoseconds(static_cast<std::int64_t>(u64(a, "TIMESTAMP_NS")));
			break;
		case ECMXF_NL_A_SEQ: e.seq = u32(a, "SEQ"); break;
		case ECMXF_NL_A_SUPPRESSED: e.suppressed = u32(a, "SUPPRESSED"); break;
		case ECMXF_NL_A_OLD: e.oldValue = u32(a, "OLD"); break;
		case ECMXF_NL_A_NEW: e.newValue = u32(a, "NEW"); break;
		case ECMXF_NL_A_LINK_UP: e.linkUp = u8(a, "LINK_UP") != 0; break;
		case ECMXF_NL_A_ERR_STATUS: e.errStatus = u8(a, "ERR_STATUS"); break;
		case ECMXF_NL_A_ECM_STATUS: e.ecmStatus = u8(a, "ECM_STATUS"); break;
		case ECMXF_NL_A_COUNT: e.count = u32(a, "COUNT"); break;
		case ECMXF_NL_A_INCREASE: e.increase = u32(a, "INCREASE"); break;
		case ECMXF_NL_A_ERRORS: e.errors = u32(a, "ERRORS"); break;
		case ECMXF_NL_A_DURATION_NS:
			e.duration = std::chrono::nanoseconds(static_cast<std::int64_t>(u64(a, "DURATION_NS")));
			break;
		case ECMXF_NL_A_FIFO: e.fifo = u8(a, "FIFO") == ECMXF_NL_FIFO_RX ? FifoId::Rx : FifoId::Tx; break;
		case ECMXF_NL_A_MARK: e.mark = u32(a, "MARK"); break;
		case ECMXF_NL_A_ABOVE: e.above = u8(a, "ABOVE") != 0; break;
		case ECMXF_NL_A_RESET_REASON: e.resetReason = static_cast<ResetReason>(u32(a, "RESET_REASON")); break;
		case ECMXF_NL_A_CMD_CODE: e.cmdCode = u8(a, "CMD_CODE"); break;
		case ECMXF_NL_A_STATUS: e.status = static_cast<std::int32_t>(u32(a, "STATUS")); break;
		case ECMXF_NL_A_SLAVE_COUNT:
			e.slaveCount = u32(a, "SLAVE_COUNT");
			e.haveSlaves = true;
			break;
		case ECMXF_NL_A_SLAVES:
			need(a, MNL_TYPE_NESTED, "SLAVES");
			e.haveSlaves = true;
			forEachNested(a, [&](const nlattr *s) {
				if (mnl_attr_get_type(s) == ECMXF_NL_A_SLAVE) {
					need(s, MNL_TYPE_NESTED, "SLAVE");
					e.slaves.push_back(decodeSlave(s));
				}
			});
			break;
		case ECMXF_NL_A_AL_STATUS: e.alStatus = u16(a, "AL_STATUS"); break;
		case ECMXF_NL_A_AL_SLAVE: e.alSlave = u16(a, "AL_SLAVE"); break;
		case ECMXF_NL_A_SLAVES_INCOMPLETE: e.slavesIncomplete = true; break;
		case ECMXF_NL_A_ACTION: e.action = static_cast<DeviceAction>(u32(a, "ACTION")); break;
		case ECMXF_NL_A_LOSS: e.loss = static_cast<LossKind>(u8(a, "LOSS")); break;
		case ECMXF_NL_A_TOTAL: e.total = u64(a, "TOTAL"); break;
		default: break;
		}
	});
	if (!haveType)
		malformed("an event without ECMXF_NL_A_EVENT_TYPE");
	return e;
}

NetlinkCounters decodeCountersMessage(std::span<const std::uint8_t> msg)
{
	const Aligned m(msg);
	if (m.genl()->cmd != ECMXF_NL_CMD_GET_COUNTERS)
		malformed("command " + std::to_string(m.genl()->cmd) + " is not ECMXF_NL_CMD_GET_COUNTERS");
	NetlinkCounters c;
	bool nest = false;
	std::uint64_t *fields[] = {
		&c.link.exchanges, &c.link.badNotReady, &c.link.badStart, &c.link.badEnd,
		&c.link.badCheck, &c.link.badLength, &c.link.retries, &c.link.polls,
		&c.link.exhausted, &c.link.timeouts, &c.link.asyncErrors, &c.link.busyRejects,
		&c.link.lostAnswers, &c.link.chipResets, &c.link.wkcErrors, &c.link.outRingUnderruns,
		&c.link.inRingOverruns, &c.link.rxFifoUnderruns, &c.link.rxFifoOverruns,
		&c.link.txFifoOverruns, &c.link.int0Irqs, &c.link.int1Irqs,
	};
	static_assert(sizeof(fields) / sizeof(fields[0]) == ECMXF_NL_C_INT1_IRQS - ECMXF_NL_C_EXCHANGES + 1);
	forEachTop(m.nlh, [&](const nlattr *a) {
		switch (mnl_attr_get_type(a)) {
		case ECMXF_NL_A_DEV_MINOR: c.minor = u32(a, "DEV_MINOR"); break;
		case ECMXF_NL_A_DEV_NAME: c.device = str(a, "DEV_NAME"); break;
		case ECMXF_NL_A_COUNTERS:
			need(a, MNL_TYPE_NESTED, "COUNTERS");
			nest = true;
			forEachNested(a, [&](const nlattr *k) {
				const unsigned t = mnl_attr_get_type(k);
				if (t >= ECMXF_NL_C_EXCHANGES && t <= ECMXF_NL_C_INT1_IRQS)
					*fields[t - ECMXF_NL_C_EXCHANGES] = u64(k, "counter");
				else if (t == ECMXF_NL_C_EVENTS)
					c.events = u64(k, "C_EVENTS");
				else if (t == ECMXF_NL_C_EVENTS_SUPPRESSED)
					c.eventsSuppressed = u64(k, "C_EVENTS_SUPPRESSED");
				else if (t == ECMXF_NL_C_EVENTS_FAILED)
					c.eventsFailed = u64(k, "C_EVENTS_FAILED");
			});
			break;
		default: break;
		}
	});
	if (!nest)
		malformed("counters without ECMXF_NL_A_COUNTERS");
	return c;
}

// ---- sockets --------------------------------------------------------------

namespace {

/// A bound NETLINK_GENERIC socket (libmnl) that runs requests.
struct NlSocket {
	struct Closer {
		void operator()(mnl_socket *s) const noexcept { mnl_socket_close(s); }
	};
	std::unique_ptr<mnl_socket, Closer> owned;
	mnl_socket *nl = nullptr; ///< owned.get()
	unsigned portid = 0;
	unsigned seq = 0;

	NlSocket() : owned(mnl_socket_open(NETLINK_GENERIC)), nl(owned.get())
	{
		if (!nl)
			fail("socket(NETLINK_GENERIC)", errno);
		if (mnl_socket_bind(nl, 0, MNL_SOCKET_AUTOPID) < 0)
			fail("bind", errno);
		portid = mnl_socket_get_portid(nl);
		seq = static_cast<unsigned>(::time(nullptr));
	}
	NlSocket(const NlSocket &) = delete;
	NlSocket &operator=(const NlSocket &) = delete;

	/// Sends @p nlh and hands every answer message to @p each until the
	/// ACK (or NLMSG_DONE). Throws on errors (the kernel's errno).
	void request(nlmsghdr *nlh, const std::string &what,
		     const std::function<void(const nlmsghdr *)> &each)
	{
		nlh->nlmsg_seq = ++seq;
		if (mnl_socket_sendto(nl, nlh, nlh->nlmsg_len) < 0)
			fail(what + ": send", errno);
		std::vector<std::uint64_t> buf(bufferSize() / 8);
		for (;;) {
			const ssize_t n = mnl_socket_recvfrom(nl, buf.data(), buf.size() * 8);
			if (n < 0)
				fail(what + ": receive", errno);
			int len = static_cast<int>(n);
			for (const auto *m = reinterpret_cast<const nlmsghdr *>(buf.data()); mnl_nlmsg_ok(m, len);
			     m = mnl_nlmsg_next(m, &len)) {
				if (m->nlmsg_seq != seq)
					continue;
				if (m->nlmsg_type == NLMSG_ERROR) {
					const auto *err = static_cast<const nlmsgerr *>(mnl_nlmsg_get_payload(m));
					if (err->error == 0)
						return; // the ACK
					fail(what, -err->error);
				}
				if (m->nlmsg_type == NLMSG_DONE)
					return;
				each(m);
			}
		}
	}
};

struct Family {
	std::uint16_t id = 0;
	std::uint32_t eventsGroup = 0;
	bool haveGroup = false;
};

/// CTRL_CMD_GETFAMILY "ecmxf": its id and the id of its "events" group.
Family resolveFamily(NlSocket &s)
{
	std::vector<std::uint64_t> buf(bufferSize() / 8);
	nlmsghdr *nlh = mnl_nlmsg_put_header(buf.data());
	nlh->nlmsg_type = GENL_ID_CTRL;
	nlh->nlmsg_flags = NLM_F_REQUEST | NLM_F_ACK;
	auto *g = static_cast<genlmsghdr *>(mnl_nlmsg_put_extra_header(nlh, sizeof(genlmsghdr)));
	g->cmd = CTRL_CMD_GETFAMILY;
	g->version = 1;
	mnl_attr_put_strz(nlh, CTRL_ATTR_FAMILY_NAME, ECMXF_GENL_NAME);
	Family f;
	try {
		s.request(nlh, "resolving family '" ECMXF_GENL_NAME "'", [&](const nlmsghdr *m) {
			forEachTop(m, [&](const nlattr *a) {
				if (mnl_attr_get_type(a) == CTRL_ATTR_FAMILY_ID) {
					f.id = u16(a, "CTRL_ATTR_FAMILY_ID");
				} else if (mnl_attr_get_type(a) == CTRL_ATTR_MCAST_GROUPS) {
					forEachNested(a, [&](const nlattr *grp) {
						std::string name;
						std::uint32_t id = 0;
						bool haveId = false;
						forEachNested(grp, [&](const nlattr *x) {
							if (mnl_attr_get_type(x) == CTRL_ATTR_MCAST_GRP_NAME)
								name = str(x, "CTRL_ATTR_MCAST_GRP_NAME");
							else if (mnl_attr_get_type(x) == CTRL_ATTR_MCAST_GRP_ID) {
								id = u32(x, "CTRL_ATTR_MCAST_GRP_ID");
								haveId = true;
							}
						});
						if (name == ECMXF_GENL_MCGRP_EVENTS && haveId) {
							f.eventsGroup = id;
							f.haveGroup = true;
						}
					});
				}
			});
		});
	} catch (const Error &e) {
		if (e.errnoValue() == ENOENT)
			throw Error("netlink: the generic netlink family '" ECMXF_GENL_NAME
				    "' does not exist (is ecmxf.ko loaded?)",
				    ENOENT);
		throw;
	}
	if (!f.id)
		malformed("the controller gave no family id");
	return f;
}

std::vector<NetlinkCounters> countersRequest(std::optional<std::uint32_t> minor)
{
	NlSocket s;
	const Family f = resolveFamily(s);
	std::vector<std::uint64_t> buf(bufferSize() / 8);
	nlmsghdr *nlh = mnl_nlmsg_put_header(buf.data());
	nlh->nlmsg_type = f.id;
	nlh->nlmsg_flags = NLM_F_REQUEST | NLM_F_ACK | (minor ? 0 : NLM_F_DUMP);
	auto *g = static_cast<genlmsghdr *>(mnl_nlmsg_put_extra_header(nlh, sizeof(genlmsghdr)));
	g->cmd = ECMXF_NL_CMD_GET_COUNTERS;
	g->version = ECMXF_GENL_VERSION;
	if (minor)
		mnl_attr_put_u32(nlh, ECMXF_NL_A_DEV_MINOR, *minor);
	std::vector<NetlinkCounters> out;
	const std::string what = minor ? "counters of ecmxf" + std::to_string(*minor) : "counters dump";
	s.request(nlh, what, [&](const nlmsghdr *m) {
		if (m->nlmsg_type != f.id)
			return;
		out.push_back(decodeCountersMessage(std::span<const std::uint8_t>(
			reinterpret_cast<const std::uint8_t *>(m), m->nlmsg_len)));
	});
	return out;
}

} // namespace

struct EventSubscriber::Socket : NlSocket {
};

NetlinkCounters readNetlinkCounters(std::uint32_t minor)
{
	auto v = countersRequest(minor);
	if (v.size() != 1)
		malformed("the counters request gave " + std::to_string(v.size()) + " answers");
	return v.front();
}

std::vector<NetlinkCounters> dumpNetlinkCounters()
{
	return countersRequest(std::nullopt);
}

EventSubscriber::EventSubscriber() : sock_(std::make_unique<Socket>())
{
	const Family f = resolveFamily(*sock_);
	if (!f.haveGroup)
		malformed("the family has no multicast group '" ECMXF_GENL_MCGRP_EVENTS "'");
	family_ = f.id;
	unsigned grp = f.eventsGroup;
	if (mnl_socket_setsockopt(sock_->nl, NETLINK_ADD_MEMBERSHIP, &grp, sizeof(grp)) < 0)
		fail("joining the group '" ECMXF_GENL_MCGRP_EVENTS "'", errno);
	buf_.resize(bufferSize());
}

EventSubscriber::~EventSubscriber() = default;

int EventSubscriber::fd() const noexcept
{
	return mnl_socket_get_fd(sock_->nl);
}

std::optional<Event> EventSubscriber::next(std::optional<std::chrono::milliseconds> timeout)
{
	for (;;) {
		// the rest of the last datagram first
		while (bufPos_ < bufLen_) {
			const auto *m = reinterpret_cast<const nlmsghdr *>(buf_.data() + bufPos_);
			int left = static_cast<int>(bufLen_ - bufPos_);
			if (!mnl_nlmsg_ok(m, left)) {
				bufPos_ = bufLen_;
				break;
			}
			bufPos_ += NLMSG_ALIGN(m->nlmsg_len);
			if (m->nlmsg_type != family_)
				continue;
			const auto *g = static_cast<const genlmsghdr *>(mnl_nlmsg_get_payload(m));
			if (g->cmd != ECMXF_NL_CMD_EVENT)
				continue;
			return decodeEventMessage(
				std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t *>(m), m->nlmsg_len));
		}
		pollfd p{ fd(), POLLIN, 0 };
		const int ms = timeout ? static_cast<int>(timeout->count()) : -1;
		const int r = ::poll(&p, 1, ms);
		if (r < 0) {
			if (errno == EINTR)
				return std::nullopt;
			fail("poll", errno);
		}
		if (r == 0)
			return std::nullopt;
		const ssize_t n = mnl_socket_recvfrom(sock_->nl, buf_.data(), buf_.size());
		if (n < 0) {
			if (errno == ENOBUFS) {
				lost_++;
				continue;
			}
			if (errno == EINTR)
				return std::nullopt;
			fail("receive", errno);
		}
		bufLen_ = static_cast<std::size_t>(n);
		bufPos_ = 0;
	}
}

} // namespace ecmxf
