// SPDX-License-Identifier: MIT
// The ECM-SK exchange bookkeeping (lib/core/ecmsk-link.c): the answer
// comes one exchange late, SET_STATE / SDO / GO_HOME complete through
// GET_STATUS, the board's CRC-error counter, CRC checks both ways, and
// what the host may not send.  Responses are written byte by byte here.

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <vector>

#include "ecmsk-proto.h"

namespace {

using Frame = std::vector<std::uint8_t>;

struct Host {
	ecmsk_link l{};
	explicit Host(unsigned slot = 12, std::uint32_t flags = 0)
	{
		REQUIRE(ecmsk_link_init(&l, slot, flags) == 0);
	}
	[[nodiscard]] Frame blank() const { return Frame(l.g.frame_size, 0); }
	int send(Frame &mosi, std::uint64_t now = 0, std::uint64_t timeout = 0)
	{
		return ecmsk_link_prepare(&l, mosi.data(), now, timeout);
	}
	ecmsk_result recv(const Frame &miso, std::uint64_t now = 0, int expect = 0)
	{
		ecmsk_result r{};
		REQUIRE(ecmsk_link_complete(&l, miso.data(), now, &r) == expect);
		return r;
	}
	// one exchange of an all-GET_STATUS frame
	ecmsk_result poll(const Frame &miso, std::uint64_t now = 0)
	{
		auto f = blank();
		REQUIRE(send(f, now) == 0);
		return recv(miso, now);
	}
};

Frame rsp(std::size_t size, std::uint8_t cmd, std::uint8_t state, std::uint8_t crcErrors = 0)
{
	Frame f(size, 0);
	f[0] = cmd;
	f[1] = crcErrors;
	f[2] = state;
	return f;
}

void sdoRsp(Frame &f, std::size_t slot, std::uint8_t cmd, std::uint8_t status, std::uint8_t slave,
	    std::uint16_t index, std::uint8_t sub, std::uint32_t value)
{
	std::uint8_t *s = f.data() + slot * 12;
	s[0] = cmd;
	s[1] = status;
	s[2] = slave;
	s[4] = sub;
	s[6] = static_cast<std::uint8_t>(index);
	s[7] = static_cast<std::uint8_t>(index >> 8);
	for (int i = 0; i < 4; i++)
		s[8 + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

void slaveRsp(Frame &f, std::size_t slot, std::uint8_t cmd, std::uint8_t index, std::uint16_t sw)
{
	std::uint8_t *s = f.data() + slot * 12;
	s[0] = cmd;
	s[1] = index;
	s[2] = static_cast<std::uint8_t>(sw);
	s[3] = static_cast<std::uint8_t>(sw >> 8);
}

} // namespace

TEST_CASE("sk link: init refuses bad slot sizes and unknown flags")
{
	ecmsk_link l{};
	CHECK(ecmsk_link_init(&l, 14, 0) == -EINVAL);
	CHECK(ecmsk_link_init(&l, 12, 0x4) == -EINVAL);
	CHECK(ecmsk_link_init(&l, 16, ECMSK_LINK_TX_CRC | ECMSK_LINK_RX_CRC) == 0);
	CHECK(l.g.frame_size == 512);
}

TEST_CASE("sk link: a command's answer is the next exchange's response, not this one's")
{
	Host h;
	auto f = h.blank();
	f[0] = ECMSK_CMD_LIO_RD;
	REQUIRE(h.send(f) == 0);
	// this exchange's response answers what was sent before (nothing)
	auto r0 = rsp(504, 0x00, ECMSK_STATE_INIT);
	h.recv(r0);
	CHECK(ecmsk_link_answered(&h.l, 0, r0.data())); // answers GET_STATUS (0)
	auto f2 = h.blank();
	REQUIRE(h.send(f2) == 0);
	auto r1 = rsp(504, ECMSK_CMD_LIO_RD, ECMSK_STATE_INIT);
	r1[4] = 0x2A;
	auto res = h.recv(r1);
	CHECK(ecmsk_link_answered(&h.l, 0, r1.data()));
	CHECK(res.ecm.data1 == 0x2Au);
	// a response that echoes something else does not answer it
	auto r2 = rsp(504, ECMSK_CMD_LIO_RD, ECMSK_STATE_INIT);
	auto f3 = h.blank();
	REQUIRE(h.send(f3) == 0);
	h.recv(r2);
	CHECK_FALSE(ecmsk_link_answered(&h.l, 0, r2.data())); // GET_STATUS was sent
}

TEST_CASE("sk link: in OP the ECM slot answers with 0xBF, slave slots with Cmd ID and index")
{
	Host h;
	auto f = h.blank();
	f[0] = ECMSK_CMD_SET_FIFO;
	f[2] = ECMSK_FIFO_THRESHOLD;
	f[12] = ECMSK_CMD_SV_ON;
	f[13] = 0x42;
	REQUIRE(h.send(f) == 0);
	h.recv(rsp(504, 0xBF, ECMSK_STATE_OP));
	auto g = h.blank();
	REQUIRE(h.send(g) == 0);
	auto r = rsp(504, 0xBF, ECMSK_STATE_OP);
	slaveRsp(r, 1, ECMSK_CMD_SV_ON, 0x41, 0x0237);
	h.recv(r);
	CHECK(ecmsk_link_answered(&h.l, 0, r.data()));
	CHECK_FALSE(ecmsk_link_answered(&h.l, 1, r.data())); // wrong Command Index
	r[13] = 0x42;
	CHECK(ecmsk_link_answered(&h.l, 1, r.data()));
	CHECK_FALSE(ecmsk_link_answered(&h.l, 42, r.data()));
}

TEST_CASE("sk link: SET_STATE completes when Current State reaches the state asked for")
{
	Host h;
	auto f = h.blank();
	f[0] = ECMSK_CMD_SET_STATE;
	f[4] = ECMSK_STATE_PREOP;
	REQUIRE(h.send(f, 0, 1'000'000) == 0);
	// the response of the same exchange: already PRE-OP, but it cannot
	// answer the command yet
	auto r = h.recv(rsp(504, 0, ECMSK_STATE_PREOP));
	CHECK_FALSE(r.state_done);
	r = h.poll(rsp(504, ECMSK_CMD_SET_STATE, ECMSK_STATE_INIT));
	CHECK_FALSE(r.state_done);
	r = h.poll(rsp(504, 0, ECMSK_STATE_INIT));
	CHECK_FALSE(r.state_done);
	r = h.poll(rsp(504, 0, ECMSK_STATE_PREOP));
	CHECK(r.state_done);
	CHECK(r.state_err == 0);
	CHECK_FALSE(h.l.ecm.active);
	r = h.poll(rsp(504, 0, ECMSK_STATE_PREOP));
	CHECK_FALSE(r.state_done);
}

TEST_CASE("sk link: SET_STATE times out on the caller's clock, a bad state is refused")
{
	Host h;
	auto f = h.blank();
	f[0] = ECMSK_CMD_SET_STATE;
	f[4] = ECMSK_STATE_OP;
	REQUIRE(h.send(f, 100, 1000) == 0);
	auto r = h.recv(rsp(504, 0, ECMSK_STATE_SAFEOP), 500);
	CHECK_FALSE(r.state_done);
	r = h.poll(rsp(504, 0, ECMSK_STATE_SAFEOP), 1100);
	CHECK(r.state_done);
	CHECK(r.state_err == -ETIMEDOUT);

	for (unsigned bad : { 0u, 3u, 5u, 0x10u }) {
		auto g = h.blank();
		g[0] = ECMSK_CMD_SET_STATE;
		g[4] = static_cast<std::uint8_t>(bad);
		CHECK(h.send(g) == -EINVAL);
	}
}

TEST_CASE("sk link: commands in the wrong slot are refused before sending")
{
	Host h;
	auto f = h.blank();
	f[0] = ECMSK_CMD_CSP; // a slave command in the ECM slot
	CHECK(h.send(f) == -EINVAL);
	f = h.blank();
	f[0] = 0x09; // unknown
	CHECK(h.send(f) == -EINVAL);
	f = h.blank();
	f[12 * 3] = ECMSK_CMD_SET_DC; // an ECM command in a slave slot
	CHECK(h.send(f) == -EINVAL);
	f = h.blank();
	f[12 * 41] = ECMSK_CMD_CSP; // a slave command in the SDO slot
	CHECK(h.send(f) == -EINVAL);
	f = h.blank();
	f[12 * 2] = ECMSK_CMD_SDO_RD; // an SDO command in a slave slot
	CHECK(h.send(f) == -EINVAL);
	CHECK(h.l.exchanges == 0u);
}

TEST_CASE("sk link: SDO_RD completes with its value through GET_STATUS in the SDO slot")
{
	Host h;
	auto f = h.blank();
	ecmsk_sdo c{ ECMSK_CMD_SDO_RD, 0, 2, 0, 0, 0x6041, 0 };
	REQUIRE(ecmsk_put_sdo(&h.l.g, f.data(), &c) == 0);
	REQUIRE(h.send(f) == 0);
	auto r = h.recv(rsp(504, 0, ECMSK_STATE_PREOP));
	CHECK_FALSE(r.sdo_done);
	// a second SDO while one is pending
	auto g = h.blank();
	REQUIRE(ecmsk_put_sdo(&h.l.g, g.data(), &c) == 0);
	CHECK(h.send(g) == -EBUSY);

	auto busy = rsp(504, 0, ECMSK_STATE_PREOP);
	sdoRsp(busy, 41, ECMSK_CMD_SDO_RD, ECMSK_SDO_BUSY, 2, 0x6041, 0, 0);
	r = h.poll(busy);
	CHECK_FALSE(r.sdo_done);
	r = h.poll(busy);
	CHECK_FALSE(r.sdo_done);
	auto done = rsp(504, 0, ECMSK_STATE_PREOP);
	sdoRsp(done, 41, ECMSK_CMD_SDO_RD, ECMSK_SDO_DONE, 2, 0x6041, 0, 0x0250);
	r = h.poll(done);
	REQUIRE(r.sdo_done);
	CHECK(r.sdo_err == 0);
	CHECK(r.sdo.value == 0x0250u);
	// now another may start
	REQUIRE(h.send(g) == 0);
}

TEST_CASE("sk link: SDO aborts, answers for another object, answers that are not SDO ones")
{
	SECTION("abort code") {
		Host h;
		auto f = h.blank();
		ecmsk_sdo c{ ECMSK_CMD_SDO_WR, 0, 1, 2, 0, 0x6040, 6 };
		REQUIRE(ecmsk_put_sdo(&h.l.g, f.data(), &c) == 0);
		REQUIRE(h.send(f) == 0);
		h.recv(rsp(504, 0, ECMSK_STATE_PREOP));
		auto a = rsp(504, 0, ECMSK_STATE_PREOP);
		sdoRsp(a, 41, ECMSK_CMD_SDO_WR, ECMSK_SDO_FAILED, 1, 0x6040, 0, 0x06090030);
		auto r = h.poll(a);
		REQUIRE(r.sdo_done);
		CHECK(r.sdo_err == -EIO);
		CHECK(r.sdo.value == 0x06090030u);
	}
	SECTION("another object") {
		Host h;
		auto f = h.blank();
		ecmsk_sdo c{ ECMSK_CMD_SDO_RD, 0, 1, 0, 1, 0x6099, 0 };
		REQUIRE(ecmsk_put_sdo(&h.l.g, f.data(), &c) == 0);
		REQUIRE(h.send(f) == 0);
		h.recv(rsp(504, 0, ECMSK_STATE_PREOP));
		auto a = rsp(504, 0, ECMSK_STATE_PREOP);
		sdoRsp(a, 41, ECMSK_CMD_SDO_RD, ECMSK_SDO_DONE, 1, 0x6099, 2, 5);
		auto r = h.poll(a);
		REQUIRE(r.sdo_done);
		CHECK(r.sdo_err == -EPROTO);
	}
	SECTION("not taken (answered as GET_STATUS, e.g. in INIT)") {
		Host h;
		auto f = h.blank();
		ecmsk_sdo c{ ECMSK_CMD_SDO_RD, 0, 1, 0, 0, 0x1000, 0 };
		REQUIRE(ecmsk_put_sdo(&h.l.g, f.data(), &c) == 0);
		REQUIRE(h.send(f) == 0);
		h.recv(rsp(504, 0, ECMSK_STATE_INIT));
		auto r = h.poll(rsp(504, 0, ECMSK_STATE_INIT));
		REQUIRE(r.sdo_done);
		CHECK(r.sdo_err == -EACCES);
	}
}

TEST_CASE("sk link: GO_HOME completes when bits 10 and 12 are set after homing ran, bit 13 fails it")
{
	Host h;
	auto f = h.blank();
	f[12 * 3] = ECMSK_CMD_GO_HOME;
	f[12 * 3 + 1] = 5;
	REQUIRE(h.send(f, 0, 0) == 0);
	h.recv(rsp(504, 0xBF, ECMSK_STATE_OP));
	// a second GO_HOME anywhere while it runs
	auto g = h.blank();
	g[12 * 4] = ECMSK_CMD_GO_HOME;
	CHECK(h.send(g) == -EBUSY);
	// still the CSP statusword (10 and 12 set): not done
	auto r0 = rsp(504, 0xBF, ECMSK_STATE_OP);
	slaveRsp(r0, 3, ECMSK_CMD_GO_HOME, 5, 0x1637);
	auto r = h.poll(r0);
	CHECK_FALSE(r.home_done);
	auto running = rsp(504, 0xBF, ECMSK_STATE_OP);
	slaveRsp(running, 3, 0, 0, 0x0237);
	r = h.poll(running);
	CHECK_FALSE(r.home_done);
	auto homed = rsp(504, 0xBF, ECMSK_STATE_OP);
	slaveRsp(homed, 3, 0, 0, 0x1637);
	r = h.poll(homed);
	CHECK(r.home_done);
	CHECK(r.home_err == 0);

	REQUIRE(h.send(g) == 0);
	h.recv(rsp(504, 0xBF, ECMSK_STATE_OP));
	auto err = rsp(504, 0xBF, ECMSK_STATE_OP);
	slaveRsp(err, 4, 0, 0, 0x2237);
	r = h.poll(err);
	CHECK(r.home_done);
	CHECK(r.home_err == -EIO);
}

TEST_CASE("sk link: ABORT_HOME and SW_RESET drop what is pending")
{
	Host h;
	auto f = h.blank();
	f[12 * 1] = ECMSK_CMD_GO_HOME;
	REQUIRE(h.send(f) == 0);
	h.recv(rsp(504, 0xBF, ECMSK_STATE_OP));
	CHECK(h.l.home.active);
	auto a = h.blank();
	a[12 * 2] = ECMSK_CMD_ABORT_HOME;
	REQUIRE(h.send(a) == 0);
	h.recv(rsp(504, 0xBF, ECMSK_STATE_OP));
	CHECK_FALSE(h.l.home.active);

	auto s = h.blank();
	ecmsk_sdo c{ ECMSK_CMD_SDO_RD, 0, 1, 0, 0, 0x1000, 0 };
	REQUIRE(ecmsk_put_sdo(&h.l.g, s.data(), &c) == 0);
	s[0] = ECMSK_CMD_SET_STATE;
	s[4] = ECMSK_STATE_INIT;
	REQUIRE(h.send(s) == 0);
	h.recv(rsp(504, 0xBF, ECMSK_STATE_OP));
	CHECK(h.l.sdo.active);
	CHECK(h.l.ecm.active);
	auto reset = h.blank();
	reset[0] = ECMSK_CMD_SW_RESET;
	REQUIRE(h.send(reset) == 0);
	CHECK_FALSE(h.l.sdo.active);
	CHECK_FALSE(h.l.ecm.active);
}

TEST_CASE("sk link: the board's CRC-error counter: increments counted, wrap at 256, the refused SET_STATE fails")
{
	Host h(12, ECMSK_LINK_TX_CRC);
	h.poll(rsp(504, 0, ECMSK_STATE_INIT, 254));
	CHECK(h.l.refused == 0u); // the first value is the board's history
	auto f = h.blank();
	f[0] = ECMSK_CMD_SET_STATE;
	f[4] = ECMSK_STATE_PREOP;
	REQUIRE(h.send(f) == 0);
	CHECK(ecmsk_frame_crc_ok(f.data(), f.size())); // sealed
	auto r = h.recv(rsp(504, 0, ECMSK_STATE_INIT, 254));
	CHECK(r.refused == 0u);
	r = h.poll(rsp(504, 0, ECMSK_STATE_INIT, 255));
	CHECK(r.refused == 1u);
	CHECK(r.state_done);
	CHECK(r.state_err == -EBADMSG);
	r = h.poll(rsp(504, 0, ECMSK_STATE_INIT, 2)); // wrapped: 3 more
	CHECK(r.refused == 3u);
	CHECK(h.l.refused == 4u);
}

TEST_CASE("sk link: without TX CRC byte 3 is sent as 0, with RX CRC a bad response is -EBADMSG")
{
	Host plain;
	auto f = plain.blank();
	f[3] = 0x77;
	f[0] = ECMSK_CMD_LIO_RD;
	REQUIRE(plain.send(f) == 0);
	CHECK(f[3] == 0);

	Host h(16, ECMSK_LINK_RX_CRC);
	auto g = h.blank();
	g[0] = ECMSK_CMD_SET_STATE;
	g[4] = ECMSK_STATE_PREOP;
	REQUIRE(h.send(g, 0, 50) == 0);
	auto bad = rsp(512, 0, ECMSK_STATE_PREOP);
	ecmsk_frame_seal(bad.data(), bad.size());
	bad[100] ^= 1;
	h.recv(bad, 10, -EBADMSG);
	CHECK(h.l.rx_crc_bad == 1u);
	CHECK(h.l.ecm.active);
	// timeouts still fire on bad responses
	auto g2 = h.blank();
	REQUIRE(h.send(g2) == 0);
	ecmsk_result r{};
	CHECK(ecmsk_link_complete(&h.l, bad.data(), 60, &r) == -EBADMSG);
	CHECK(r.state_done);
	CHECK(r.state_err == -ETIMEDOUT);
	auto good = rsp(512, 0, ECMSK_STATE_PREOP);
	ecmsk_frame_seal(good.data(), good.size());
	h.poll(good);
	CHECK(h.l.state == ECMSK_STATE_PREOP);
}

TEST_CASE("sk link: reset forgets exchanges but keeps geometry and flags")
{
	Host h(16, ECMSK_LINK_TX_CRC);
	h.poll(rsp(512, 0, ECMSK_STATE_PREOP, 9));
	ecmsk_link_reset(&h.l);
	CHECK(h.l.exchanges == 0u);
	CHECK_FALSE(h.l.have_rsp);
	CHECK(h.l.g.frame_size == 512);
	CHECK(h.l.flags == ECMSK_LINK_TX_CRC);
}
