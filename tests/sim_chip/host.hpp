// SPDX-License-Identifier: MIT
//
// A raw host for the chip tests: builds command packets with the protocol
// core's codec, exchanges them with the simulated chip and decodes what
// comes back. It applies the exchange rules by hand, so that a test sees
// exactly what the chip does:
//
//   send(c)  one exchange with a fresh index; returns what the chip
//            shifted out meanwhile: the answer to the PREVIOUS packet.
//   cmd(c)   send(c), then the identical packet again: the chip runs the
//            repeat as INFO_UPDATE and shifts out the answer to c.
//
// Before every exchange the host waits until the chip is ready (INT0),
// advancing virtual time in small steps.

#pragma once

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <thread>
#include <vector>

#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

#include "ecmxf-proto.h"
#include "test_slave.hpp"

namespace simtest {

/// One command packet to send.
struct Cmd {
	ecmxf_cmd_hdr h{};
	std::vector<std::uint8_t> data;

	explicit Cmd(std::uint8_t code, std::uint8_t param = 0)
	{
		h.code = code;
		h.param = param;
	}
	Cmd &d(std::uint8_t d0, std::uint8_t d1 = 0, std::uint8_t d2 = 0, std::uint8_t d3 = 0)
	{
		h.data[0] = d0;
		h.data[1] = d1;
		h.data[2] = d2;
		h.data[3] = d3;
		return *this;
	}
	/// Data section bytes; the data length field becomes their number.
	Cmd &payload(std::vector<std::uint8_t> bytes)
	{
		data = std::move(bytes);
		h.len = static_cast<std::uint16_t>(data.size());
		return *this;
	}
	Cmd &len(std::uint16_t l)
	{
		h.len = l;
		return *this;
	}
	Cmd &control(std::uint8_t c)
	{
		h.control = c;
		return *this;
	}
	Cmd &reserved(std::uint16_t r)
	{
		h.reserved = r;
		return *this;
	}
	Cmd &intClear(std::uint32_t m)
	{
		h.int_clear = m;
		return *this;
	}
};

/// A decoded response.
struct Rsp {
	ecmxf_fault fault = ECMXF_FAULT_NONE;
	ecmxf_rsp_hdr h{};
	std::vector<std::uint8_t> data;	///< h.len bytes

	[[nodiscard]] bool ok() const { return fault == ECMXF_FAULT_NONE; }
	[[nodiscard]] bool busy() const { return h.ecm_status & ECMXF_STS_BUSY; }
	[[nodiscard]] bool nop() const { return h.ecm_status & ECMXF_STS_NOP; }
	[[nodiscard]] bool cmdError() const { return h.err_status & ECMXF_ERR_CMD; }
	[[nodiscard]] bool asyncError() const { return h.err_status & ECMXF_ERR_ASYNC; }
	[[nodiscard]] std::uint16_t u16(std::size_t off = 0) const
	{
		REQUIRE(off + 2 <= data.size());
		return static_cast<std::uint16_t>(data[off] | (data[off + 1] << 8));
	}
	[[nodiscard]] std::uint32_t u32(std::size_t off = 0) const
	{
		REQUIRE(off + 4 <= data.size());
		return static_cast<std::uint32_t>(data[off]) | (static_cast<std::uint32_t>(data[off + 1]) << 8) |
		       (static_cast<std::uint32_t>(data[off + 2]) << 16) |
		       (static_cast<std::uint32_t>(data[off + 3]) << 24);
	}
};

inline std::vector<std::uint8_t> le32v(std::uint32_t v)
{
	return { static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8),
		 static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 24) };
}

inline void append(std::vector<std::uint8_t> &v, std::initializer_list<std::uint8_t> b)
{
	v.insert(v.end(), b);
}

inline void append16(std::vector<std::uint8_t> &v, std::uint16_t x)
{
	v.push_back(static_cast<std::uint8_t>(x));
	v.push_back(static_cast<std::uint8_t>(x >> 8));
}

inline void append32(std::vector<std::uint8_t> &v, std::uint32_t x)
{
	append16(v, static_cast<std::uint16_t>(x));
	append16(v, static_cast<std::uint16_t>(x >> 16));
}

class Host
{
public:
	explicit Host(ecmxf::sim::Chip &c) : chip(c) {}

	ecmxf::sim::Chip &chip;
	ecmxf_check check = ECMXF_CHECK_FIXED;	///< check type of packets and answers
	std::size_t dataSize = ECMXF_DATA_DEFAULT;
	std::uint8_t index = 0;

	/// The chip runs in paced time: wait by sleeping, not by advancing.
	bool paced = false;

	/// Let @p dt pass: virtual time, or real time for a paced chip.
	void pass(std::chrono::nanoseconds dt)
	{
		if (paced)
			std::this_thread::sleep_for(dt);
		else
			chip.advance(dt);
	}

	/// Wait until the chip is ready (INT0).
	void waitReady(std::chrono::nanoseconds max = std::chrono::seconds(1))
	{
		const auto t0 = chip.now();
		while (!chip.ready()) {
			if (chip.now() - t0 > max)
				FAIL("the chip stayed busy for more than " << max.count() << " ns");
			pass(std::chrono::microseconds(10));
		}
	}

	std::vector<std::uint8_t> encode(const Cmd &c, ecmxf_check ck, std::size_t ds) const
	{
		std::vector<std::uint8_t> p(ECMXF_PKT_SIZE(ds));
		REQUIRE(ecmxf_encode_cmd(p.data(), p.size(), ck, &c.h, c.data.data(), c.data.size()) == 0);
		return p;
	}
	std::vector<std::uint8_t> encode(const Cmd &c) const { return encode(c, check, dataSize); }

	Rsp decode(const std::vector<std::uint8_t> &miso, ecmxf_check ck) const
	{
		Rsp r;
		const std::uint8_t *d = nullptr;
		r.fault = ecmxf_decode_rsp(miso.data(), miso.size(), ck, &r.h, &d);
		if (r.ok())
			r.data.assign(d, d + r.h.len);
		return r;
	}
	Rsp decode(const std::vector<std::uint8_t> &miso) const { return decode(miso, check); }

	/// One exchange of raw bytes (after waiting for ready).
	std::vector<std::uint8_t> xfer(const std::vector<std::uint8_t> &mosi)
	{
		waitReady();
		return chip.exchange(mosi);
	}

	/// Give @p c a fresh index.
	Cmd fresh(Cmd c)
	{
		c.h.index = ++index;
		return c;
	}

	/// Send @p c once (fresh index); returns the answer to the previous packet.
	Rsp send(Cmd c)
	{
		last = fresh(std::move(c));
		return decode(xfer(encode(last)));
	}

	/// Send @p c and fetch its answer by repeating the same packet.
	Rsp cmd(Cmd c)
	{
		send(std::move(c));
		return repeat();
	}

	/// Re-send the last packet (the chip runs it as INFO_UPDATE).
	Rsp repeat() { return decode(xfer(encode(last))); }

	/// A fresh INFO_UPDATE and its answer: the current header.
	Rsp info() { return cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP)); }

	/// Poll INFO_UPDATE every @p step until the busy bit clears.
	Rsp waitIdle(std::chrono::nanoseconds step = std::chrono::milliseconds(1),
		     std::chrono::nanoseconds max = std::chrono::seconds(20))
	{
		const auto t0 = chip.now();
		for (;;) {
			Rsp r = info();
			REQUIRE(r.ok());
			if (!r.busy())
				return r;
			REQUIRE(chip.now() - t0 < max);
			pass(step);
		}
	}

	/// An async command: its immediate answer must be accepted (no command
	/// error; older error bits 3 and 7 are cleared with it); returns the
	/// header after busy cleared.
	Rsp async(Cmd c)
	{
		// stale error bits would blur the checks: clear them with the
		// command (not with the repeat, which would clear our own)
		c.h.control |= ECMXF_CTL_CLR_CMD_ERR | ECMXF_CTL_CLR_ASYNC_ERR;
		send(std::move(c));
		last.h.control = 0;
		const Rsp a = repeat();
		REQUIRE(a.ok());
		REQUIRE(a.h.code == last.h.code);
		REQUIRE_FALSE(a.cmdError());
		return waitIdle();
	}

	/// Consume the power-on NOP.
	Rsp sync() { return send(Cmd(ECMXF_CMD_INFO_UPDATE_OP)); }

	Cmd last{ 0 };
};

/// INIT_OP data: 0xFF, 0x81, AssignActivate, SYNC0, SYNC1, shift at 0x0C.
inline Cmd initOp(std::uint32_t sync0 = 1'000'000, std::uint16_t aa = 0, std::uint32_t sync1 = 0,
		  std::int32_t shift = 0)
{
	std::vector<std::uint8_t> d{ 0xFF, 0x81 };
	append16(d, aa);
	append32(d, sync0);
	append32(d, sync1);
	append32(d, static_cast<std::uint32_t>(shift));
	return Cmd(ECMXF_CMD_ECAT_INIT_OP).payload(d);
}

inline Cmd stateSet(std::uint8_t slave, std::uint8_t state)
{
	return Cmd(ECMXF_CMD_ECAT_STATE_SET, slave).d(state);
}

/// SDO_REQ: op 0 write / 1 read, slave, index, sub, length, timeout µs,
/// write data at 0x0C.
inline Cmd sdoReq(unsigned op, std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
		  std::vector<std::uint8_t> wdata = {}, std::uint16_t len = 0, std::uint32_t timeoutUs = 0)
{
	std::vector<std::uint8_t> d;
	d.push_back(static_cast<std::uint8_t>(op));
	d.push_back(slave);
	append16(d, index);
	d.push_back(sub);
	d.push_back(0);
	append16(d, op == 0 ? static_cast<std::uint16_t>(wdata.size()) : len);
	append32(d, timeoutUs);
	d.insert(d.end(), wdata.begin(), wdata.end());
	return Cmd(ECMXF_CMD_ECAT_SDO_REQ).payload(d);
}

using SlaveList = std::vector<std::unique_ptr<TestSlave>>;

/// A chip with test slaves and a raw host.
struct Rig {
	std::unique_ptr<ecmxf::sim::Chip> chip;
	Host host;

	static std::unique_ptr<ecmxf::sim::Chip> make(SlaveList slaves, ecmxf::sim::ChipConfig cfg)
	{
		ecmxf::sim::Network net;
		net.setName("chip test network");
		for (auto &s : slaves)
			net.add(std::move(s));
		return std::make_unique<ecmxf::sim::Chip>(std::move(net), std::move(cfg));
	}

	explicit Rig(SlaveList slaves, ecmxf::sim::ChipConfig cfg = {})
		: chip(make(std::move(slaves), std::move(cfg))), host(*chip)
	{
		host.sync();
	}

	/// @p n TestSlaves with the default configuration.
	explicit Rig(std::size_t n, SlaveConfig sc = {}, ecmxf::sim::ChipConfig cfg = {})
		: Rig(slaves(n, sc), std::move(cfg))
	{
	}

	static SlaveList slaves(std::size_t n, SlaveConfig sc = {})
	{
		SlaveList l;
		for (std::size_t i = 0; i < n; i++)
			l.push_back(std::make_unique<TestSlave>(sc));
		return l;
	}

	TestSlave &s(std::size_t i) { return dynamic_cast<TestSlave &>(chip->network().at(i)); }
	TestDrive &drive(std::size_t i) { return dynamic_cast<TestDrive &>(chip->network().at(i)); }

	/// INIT_OP to completion; the result must be success.
	Rsp init(std::uint32_t sync0 = 1'000'000, std::uint16_t aa = 0)
	{
		const Rsp r = host.async(initOp(sync0, aa));
		REQUIRE_FALSE(r.asyncError());
		return r;
	}

	/// STATE_SET for all slaves to completion; the result must be success.
	Rsp state(std::uint8_t st)
	{
		const Rsp r = host.async(stateSet(0xFF, st));
		REQUIRE_FALSE(r.asyncError());
		return r;
	}

	/// INIT_OP, then PRE-OP, SAFE-OP, OP.
	void toOp(std::uint32_t sync0 = 1'000'000)
	{
		init(sync0);
		state(ECMXF_ECAT_PREOP);
		state(ECMXF_ECAT_SAFEOP);
		const Rsp r = state(ECMXF_ECAT_OP);
		REQUIRE(r.h.ecat_state == ECMXF_ECAT_OP);
	}

	void run(std::chrono::nanoseconds dt) { chip->advance(dt); }
};

} // namespace simtest
