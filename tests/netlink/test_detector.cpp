// SPDX-License-Identifier: MIT
// The protocol core's header event detector (lib/core/ecmxf-events.c) as
// the kernel calls it: the order of the events of one header, the most one
// header can give, a WKC burst ended by time (ecmxf_det_poll and its
// deadline), a reset ending a running burst first, and the core's type
// numbers being the uAPI's; ecmxf::EventDetector made with a Device reads
// the slaves' states and AL status codes for a state that went down, as the
// kernel's netlink unit does (kmod/ecmxf-netlink.c, "AL status query").

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/events/events.hpp>
#include <ecmxf/sim/chip.hpp>

#include <linux/ecmxf_netlink.h>

#include "ecmxf-events.h"

static_assert(ECMXF_DET_RESET == static_cast<int>(ECMXF_NL_EV_RESET));
static_assert(ECMXF_DET_LINK == static_cast<int>(ECMXF_NL_EV_LINK));
static_assert(ECMXF_DET_STATE == static_cast<int>(ECMXF_NL_EV_STATE));
static_assert(ECMXF_DET_ERROR_STATUS == static_cast<int>(ECMXF_NL_EV_ERROR_STATUS));
static_assert(ECMXF_DET_ECM_STATUS == static_cast<int>(ECMXF_NL_EV_ECM_STATUS));
static_assert(ECMXF_DET_CRC_ERRORS == static_cast<int>(ECMXF_NL_EV_CRC_ERRORS));
static_assert(ECMXF_DET_WKC_BURST == static_cast<int>(ECMXF_NL_EV_WKC_BURST));
static_assert(ECMXF_DET_WKC_BURST_END == static_cast<int>(ECMXF_NL_EV_WKC_BURST_END));
static_assert(ECMXF_DET_FIFO == static_cast<int>(ECMXF_NL_EV_FIFO));

namespace {

constexpr std::uint64_t kMs = 1'000'000;

ecmxf_rsp_hdr op()
{
	ecmxf_rsp_hdr h{};
	h.ecat_state = 0x08;
	h.err_status = 0x03;
	h.ecm_status = 0x18;
	return h;
}

struct Det {
	ecmxf_det d{};
	explicit Det(std::uint64_t quietMs = 100)
	{
		ecmxf_det_cfg c{};
		c.tx_high = 10;
		c.rx_low = 0;
		c.wkc_quiet_ns = quietMs * kMs;
		ecmxf_det_init(&d, &c);
	}
	std::vector<ecmxf_det_event> feed(const ecmxf_rsp_hdr &h, std::uint64_t t)
	{
		ecmxf_det_event ev[ECMXF_DET_MAX_EVENTS];
		const unsigned n = ecmxf_det_feed(&d, &h, t, ev);
		REQUIRE(n <= ECMXF_DET_MAX_EVENTS);
		return { ev, ev + n };
	}
};

} // namespace

TEST_CASE("detector: defaults, baseline, and every kind in one header in a fixed order", "[detector]")
{
	ecmxf_det d;
	ecmxf_det_init(&d, nullptr);
	CHECK_FALSE(ecmxf_det_have_baseline(&d));
	ecmxf_det_event ev[ECMXF_DET_MAX_EVENTS];
	ecmxf_rsp_hdr a = op();
	a.rx_fifo_cnt = 3;
	CHECK(ecmxf_det_feed(&d, &a, 0, ev) == 0);
	CHECK(ecmxf_det_have_baseline(&d));
	CHECK(ecmxf_det_deadline(&d) == UINT64_MAX);

	ecmxf_rsp_hdr b = a;
	b.ecat_state = 0x10;      // state
	b.err_status = 0x00 | 0x20; // link down, link at INIT_OP cleared, FIFO error set
	b.ecm_status = 0x18 | 0x04; // DC stable
	b.crc_err_cnt = 2;
	b.wkc_err_cnt = 9;
	b.tx_fifo_cnt = 10; // reaches the default high mark 10
	b.rx_fifo_cnt = 0;  // falls to the default low mark 0
	const unsigned n = ecmxf_det_feed(&d, &b, 5 * kMs, ev);
	REQUIRE(n == 8);
	const int want[] = { ECMXF_DET_STATE,      ECMXF_DET_LINK,       ECMXF_DET_ERROR_STATUS,
			     ECMXF_DET_ECM_STATUS, ECMXF_DET_CRC_ERRORS, ECMXF_DET_WKC_BURST,
			     ECMXF_DET_FIFO,       ECMXF_DET_FIFO };
	for (unsigned i = 0; i < n; i++) {
		CHECK(ev[i].type == want[i]);
		CHECK(ev[i].time_ns == 5 * kMs);
		CHECK(ev[i].err_status == 0x20);
	}
	CHECK(ev[0].old_val == 0x08);
	CHECK(ev[0].new_val == 0x10);
	CHECK(ev[1].new_val == 0); // down
	CHECK(ev[2].old_val == 0x03);
	CHECK(ev[2].new_val == 0x20);
	CHECK(ev[3].old_val == 0x18);
	CHECK(ev[3].new_val == 0x1C);
	CHECK(ev[4].increase == 2);
	CHECK(ev[5].increase == 9);
	CHECK(ev[5].count == 9);
	CHECK(ev[6].fifo == ECMXF_DET_FIFO_TX);
	CHECK(ev[6].above);
	CHECK(ev[6].mark == 10);
	CHECK(ev[7].fifo == ECMXF_DET_FIFO_RX);
	CHECK_FALSE(ev[7].above);
	// the burst ends 100 ms (the default) after its last increase
	CHECK(ecmxf_det_deadline(&d) == 105 * kMs);
}

TEST_CASE("detector: a WKC burst ends by time, through poll, once", "[detector]")
{
	Det t(100);
	ecmxf_rsp_hdr h = op();
	t.feed(h, 0);
	h.wkc_err_cnt = 1;
	REQUIRE(t.feed(h, 10 * kMs).size() == 1);
	for (std::uint8_t c = 2; c <= 50; c++) { // one error per ms: one burst
		h.wkc_err_cnt = c;
		CHECK(t.feed(h, (9 + c) * kMs).empty());
	}
	// last increase at 59 ms
	CHECK(ecmxf_det_deadline(&t.d) == 159 * kMs);
	ecmxf_det_event ev[1];
	CHECK(ecmxf_det_poll(&t.d, 158 * kMs, ev) == 0);
	REQUIRE(ecmxf_det_poll(&t.d, 159 * kMs, ev) == 1);
	CHECK(ev[0].type == ECMXF_DET_WKC_BURST_END);
	CHECK(ev[0].errors == 50);
	CHECK(ev[0].duration_ns == 49 * kMs);
	CHECK(ev[0].count == 50);
	CHECK(ecmxf_det_poll(&t.d, 500 * kMs, ev) == 0);
	CHECK(ecmxf_det_deadline(&t.d) == UINT64_MAX);
}

TEST_CASE("detector: a reset ends a running burst first, then is the only event", "[detector]")
{
	Det t(100);
	ecmxf_rsp_hdr h = op();
	t.feed(h, 0);
	h.wkc_err_cnt = 7;
	t.feed(h, kMs);
	ecmxf_rsp_hdr nop = h;
	nop.ecm_status |= 0x20;
	nop.ecat_state = 0x10; // would be a state event without the reset
	nop.crc_err_cnt = 3;
	const auto ev = t.feed(nop, 2 * kMs);
	REQUIRE(ev.size() == 2);
	CHECK(ev[0].type == ECMXF_DET_WKC_BURST_END);
	CHECK(ev[0].errors == 7);
	CHECK(ev[1].type == ECMXF_DET_RESET);
	CHECK(ev[1].new_val == 0x10);
	CHECK(ev[1].ecm_status == nop.ecm_status);
	// "Ethernet initialised" cleared, and the state back to 0, are resets too
	Det u;
	u.feed(op(), 0);
	ecmxf_rsp_hdr cleared = op();
	cleared.ecm_status = 0x10;
	REQUIRE(u.feed(cleared, 1).size() == 1);
	const auto back = u.feed(op(), 2); // bit 3 back: not a reset, an ECM status change
	REQUIRE(back.size() == 1);
	CHECK(back[0].type == ECMXF_DET_ECM_STATUS);
	ecmxf_rsp_hdr none = op();
	none.ecat_state = 0;
	REQUIRE(u.feed(none, 3).size() == 1);
	CHECK(u.feed(none, 4).empty());
}

TEST_CASE("detector: rebase forgets the baseline and ends a burst", "[detector]")
{
	Det t;
	ecmxf_rsp_hdr h = op();
	t.feed(h, 0);
	h.wkc_err_cnt = 2;
	t.feed(h, kMs);
	ecmxf_det_event ev[1];
	REQUIRE(ecmxf_det_rebase(&t.d, 3 * kMs, ev) == 1);
	CHECK(ev[0].type == ECMXF_DET_WKC_BURST_END);
	CHECK(ev[0].time_ns == 3 * kMs);
	CHECK_FALSE(ecmxf_det_have_baseline(&t.d));
	h.ecat_state = 0x01;
	CHECK(t.feed(h, 4 * kMs).empty()); // baseline again
	CHECK(ecmxf_det_rebase(&t.d, 5 * kMs, ev) == 0);
}

// ------------------------------------------- EventDetector with a Device

namespace {

/// The default simulated network in OP, and a detector bound to it whose
/// baseline is the OP header.
struct SimBus {
	std::unique_ptr<ecmxf::Device> dev = ecmxf::Device::open("sim:");
	ecmxf::EventDetector det{ *dev };

	SimBus()
	{
		const ecmxf::Bus bus = dev->bus();
		bus.initNetwork();
		for (const auto s : { ecmxf::State::PreOp, ecmxf::State::SafeOp, ecmxf::State::Op })
			bus.stateSet(ecmxf::kAllSlaves, s);
		REQUIRE(det.feed(dev->chip().infoUpdate(), dev->link().now()).empty());
	}
	/// The state events of the next poll, after @p ms.
	std::vector<ecmxf::Event> stateEvents(int ms)
	{
		dev->link().sleepFor(std::chrono::milliseconds(ms));
		std::vector<ecmxf::Event> out;
		for (ecmxf::Event &e : det.feed(dev->chip().infoUpdate(), dev->link().now()))
			if (e.type == ecmxf::EventType::State)
				out.push_back(std::move(e));
		return out;
	}
};

} // namespace

TEST_CASE("EventDetector with a device: a slave that drops out is read as the kernel reads it",
	  "[detector][slaves]")
{
	SimBus b;
	b.dev->link().simulator()->faults().slaveDropped = 1;
	const auto ev = b.stateEvents(20);
	REQUIRE(ev.size() == 1);
	const ecmxf::Event &e = ev[0];
	CHECK(e.oldValue == 0x08);
	CHECK((e.newValue & 0x10) != 0);
	CHECK(ecmxf::stateWentDown(e));
	CHECK(e.haveSlaves);
	CHECK_FALSE(e.slavesIncomplete);
	CHECK(e.slaveCount == 3);
	// slave 1 does not answer (ERROR alone): no AL status asked
	REQUIRE(e.slaves.size() == 1);
	CHECK(e.slaves[0].position == 1);
	CHECK(e.slaves[0].state == 0x10);
	CHECK_FALSE(e.slaves[0].alStatus.has_value());
	CHECK_FALSE(e.alStatus.has_value());
	// the reading left no command error behind
	CHECK((b.dev->lastHeader().errStatus & 0x80) == 0);
}

TEST_CASE("EventDetector with a device: the AL status code of a slave that refused a state",
	  "[detector][slaves]")
{
	SimBus b;
	// every slave from OP to BOOT: refused (an invalid transition), the
	// slaves stay in OP with the error bit and an AL status code
	CHECK_THROWS_AS(b.dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::Boot), ecmxf::Error);
	const auto ev = b.stateEvents(5);
	REQUIRE(ev.size() == 1);
	const ecmxf::Event &e = ev[0];
	INFO("state 0x" << std::hex << e.oldValue << " -> 0x" << e.newValue);
	CHECK(ecmxf::stateWentDown(e));
	REQUIRE_FALSE(e.slaves.empty());
	REQUIRE(e.slaves[0].alStatus.has_value());
	CHECK(*e.slaves[0].alStatus != 0);
	REQUIRE(e.alStatus.has_value());
	CHECK(e.alStatus == e.slaves[0].alStatus);
	CHECK(e.alSlave == e.slaves[0].position);
}

TEST_CASE("EventDetector with a device: up is no reason to read the slaves, without a device nothing is read",
	  "[detector][slaves]")
{
	ecmxf::Event up;
	up.type = ecmxf::EventType::State;
	up.oldValue = 0x02;
	up.newValue = 0x08;
	CHECK_FALSE(ecmxf::stateWentDown(up));
	up.oldValue = 0x08;
	up.newValue = 0x04;
	CHECK(ecmxf::stateWentDown(up));
	up.type = ecmxf::EventType::ErrorStatus;
	CHECK_FALSE(ecmxf::stateWentDown(up));

	// an unbound detector reports the change alone
	auto dev = ecmxf::Device::open("sim:");
	ecmxf::EventDetector det;
	dev->bus().initNetwork();
	(void)det.feed(dev->chip().infoUpdate(), dev->link().now());
	dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);
	dev->link().simulator()->faults().linkLost = true;
	dev->link().sleepFor(std::chrono::milliseconds(5));
	bool sawState = false;
	for (const ecmxf::Event &e : det.feed(dev->chip().infoUpdate(), dev->link().now()))
		if (e.type == ecmxf::EventType::State) {
			sawState = true;
			CHECK_FALSE(e.haveSlaves);
			CHECK(e.slaves.empty());
		}
	CHECK(sawState);
}
