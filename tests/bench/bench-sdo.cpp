// SPDX-License-Identifier: MIT
//
// bench-sdo: the SDO round trip of libecmxf against a host that waits for
// async completion the way NEXTW's example driver does.
//
// The transfer: a 4-byte upload (0x6064:00, position actual value) from an
// EST-584 in PRE-OP on the default network (2 x EST-584 + dio), with the
// EST-584s' mailbox latency (the chip's SDO time) at 100 us .. 1.2 ms; the
// model's default is 1 ms. Counted per transfer: SPI exchanges, and two
// simulated times: the period of back-to-back transfers (the total over
// the rounds, INT0 waits included), and one transfer's own time, from the
// start of the exchange that carries ECAT_SDO_REQ to the end of the one
// that brings the answer of ECAT_SDO_GET.
//
//  - ours:     Sdo::read<int32_t>() (the protocol engine polls the
//              running command back to back, each poll gated by INT0 only);
//  - baseline: NEXTW's example host driver as it runs (its sequence and
//              delays, modelled; no code of it): raw exchanges on a second
//              chip, a lenient firmware (chip option init-op=lenient: the
//              driver sends ECAT_INIT_OP with data byte 1 = 0), a 200 us
//              delay after every exchange, an INFO_UPDATE poll before
//              SDO_REQ (is the chip idle?), SDO_REQ, then INFO_UPDATE polls
//              1 ms apart until the busy bit clears -- the first poll reads
//              SDO_REQ's own answer (the chip answers a packet in the next
//              exchange), and each poll's header is the chip's state when
//              it took the packet before -- then SDO_GET and its answer.
//
// Both wait for INT0 (ready) before every exchange. Printed: both figures
// and the ratio of simulated times (baseline / ours) per latency.

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/model/types_bus.hpp>

#include "ecmxf-proto.h"

namespace {

using namespace std::chrono_literals;
namespace sim = ecmxf::sim;

constexpr int kRounds = 200;
constexpr std::uint8_t kSlave = 0;
constexpr std::uint16_t kIndex = 0x6064;

[[noreturn]] void die(const std::string &what)
{
	std::fprintf(stderr, "bench-sdo: %s\n", what.c_str());
	std::exit(1);
}

struct Figures {
	double exchanges = 0; // per transfer
	double micros = 0;    // simulated µs per transfer, back to back
	double transferUs = 0; // one transfer, first exchange to the answer
};

using Nanos = std::chrono::nanoseconds;

/// One transfer's time: from the start of its first exchange since
/// start() to the end of its last.
class TransferTimer
{
public:
	void start() { started_ = false; }
	/// Around each exchange: @p now before it, then after it.
	void before(Nanos now)
	{
		if (!started_) {
			started_ = true;
			first_ = now;
		}
	}
	void after(Nanos now) { last_ = now; }
	[[nodiscard]] double micros() const { return std::chrono::duration<double, std::micro>(last_ - first_).count(); }

private:
	bool started_ = false;
	Nanos first_{}, last_{};
};

/// The simulator's channel, timing transfers (TransferTimer).
class TimedChannel : public ecmxf::ByteChannel, public TransferTimer
{
public:
	explicit TimedChannel(std::unique_ptr<ecmxf::SimChannel> c) : c_(std::move(c)) {}
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		before(c_->now());
		c_->exchange(mosi, miso);
		after(c_->now());
	}
	bool waitReady(Nanos timeout) override { return c_->waitReady(timeout); }
	Nanos now() const override { return c_->now(); }
	void sleepFor(Nanos d) override { c_->sleepFor(d); }
	std::string name() const override { return c_->name(); }
private:
	std::unique_ptr<ecmxf::SimChannel> c_;
};

// A raw host: one packet per exchange, waiting for INT0 in 10 µs steps.
class RawHost
{
public:
	explicit RawHost(sim::Chip &chip) : chip_(chip) {}

	/// NEXTW's example driver waits this long after every exchange.
	static constexpr Nanos kExchangeDelay = 200us;

	ecmxf_rsp_hdr h{};
	std::vector<std::uint8_t> data;

	void send(std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0,
		  const std::vector<std::uint8_t> &payload = {}, bool repeat = false)
	{
		if (!repeat) {
			hdr_ = {};
			hdr_.code = code;
			hdr_.param = param;
			hdr_.data[0] = d0;
			hdr_.len = static_cast<std::uint16_t>(payload.size());
			hdr_.index = ++index_;
			payload_ = payload;
		}
		std::vector<std::uint8_t> tx(ECMXF_PKT_SIZE(ECMXF_DATA_DEFAULT)), rx(tx.size());
		if (ecmxf_encode_cmd(tx.data(), tx.size(), ECMXF_CHECK_FIXED, &hdr_, payload_.data(), payload_.size()))
			die("encode failed");
		while (!chip_.ready())
			chip_.advance(10us);
		timer.before(chip_.now());
		chip_.exchange(tx, rx);
		timer.after(chip_.now());
		chip_.advance(kExchangeDelay);
		const std::uint8_t *d = nullptr;
		if (ecmxf_decode_rsp(rx.data(), rx.size(), ECMXF_CHECK_FIXED, &h, &d) != ECMXF_FAULT_NONE)
			die("bad response");
		data.assign(d, d + h.len);
	}
	// a command and its answer: the same packet again
	void cmd(std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0,
		 const std::vector<std::uint8_t> &payload = {})
	{
		send(code, param, d0, payload);
		send(code, 0, 0, {}, true);
		if (h.index != hdr_.index)
			die("no answer to command " + std::to_string(code));
	}
	// the example driver's wait: INFO_UPDATE polls 1 ms apart until busy
	// clears; the first poll's response is the answer to the packet before
	void waitIdle1ms()
	{
		for (;;) {
			send(ECMXF_CMD_INFO_UPDATE_OP);
			if (!(h.ecm_status & ECMXF_STS_BUSY))
				break;
			chip_.advance(1ms);
		}
		if (h.err_status & ECMXF_ERR_ASYNC)
			die("async command failed");
	}
	/// The index of the last command sent (its answer carries it).
	[[nodiscard]] std::uint8_t lastIndex() const { return hdr_.index; }

	TransferTimer timer; ///< one transfer's time

private:
	sim::Chip &chip_;
	ecmxf_cmd_hdr hdr_{};
	std::vector<std::uint8_t> payload_;
	std::uint8_t index_ = 0;
};

std::vector<std::uint8_t> sdoReadPayload()
{
	std::vector<std::uint8_t> d{ 1, kSlave, static_cast<std::uint8_t>(kIndex), static_cast<std::uint8_t>(kIndex >> 8),
				     0, 0, 4, 0, 0, 0, 0, 0 };
	return d;
}

/// The default network with the EST-584s' mailbox latency set to @p us.
sim::Network network(unsigned us)
{
	const std::string est = "slave EST-584 mailbox_latency_us=" + std::to_string(us) + "\n";
	return sim::Network::fromText(est + est + "slave dio\n", "bench-sdo");
}

Figures ours(unsigned latencyUs, bool pipeline)
{
	auto sc = std::make_unique<ecmxf::SimChannel>(network(latencyUs));
	sim::Chip &chip = sc->chip();
	auto owned = std::make_unique<TimedChannel>(std::move(sc));
	TimedChannel &timed = *owned;
	ecmxf::Device dev(std::unique_ptr<ecmxf::ByteChannel>(std::move(owned)));
	dev.link().setPipelining(pipeline);
	dev.bus().initNetwork();
	dev.bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);
	const auto x0 = chip.stats().exchanges;
	const auto t0 = chip.now();
	double transfers = 0;
	for (int i = 0; i < kRounds; i++) {
		timed.start();
		(void)dev.sdo().read<std::int32_t>(kSlave, kIndex, 0);
		transfers += timed.micros();
	}
	Figures f;
	f.exchanges = static_cast<double>(chip.stats().exchanges - x0) / kRounds;
	f.micros = std::chrono::duration<double, std::micro>(chip.now() - t0).count() / kRounds;
	f.transferUs = transfers / kRounds;
	return f;
}

Figures baseline(unsigned latencyUs)
{
	sim::Network net = network(latencyUs);
	net.setChipOption("init-op", "lenient"); // byte 1 = 0, as the driver sends it
	sim::Chip chip(std::move(net));
	RawHost host(chip);
	host.send(ECMXF_CMD_INFO_UPDATE_OP); // the power-on NOP
	std::vector<std::uint8_t> init = { 0xFF, 0x00, 0x00, 0x03 };
	for (std::uint32_t v : { 1'000'000u, 0u, 0u })
		for (int i = 0; i < 4; i++)
			init.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
	host.send(ECMXF_CMD_ECAT_INIT_OP, 0, 0, init);
	host.waitIdle1ms();
	host.send(ECMXF_CMD_ECAT_STATE_SET, 0xFF, ECMXF_ECAT_PREOP);
	host.waitIdle1ms();

	const auto x0 = chip.stats().exchanges;
	const auto t0 = chip.now();
	double transfers = 0;
	for (int i = 0; i < kRounds; i++) {
		host.timer.start();
		host.send(ECMXF_CMD_INFO_UPDATE_OP); // the poll before SDO_REQ
		if (host.h.ecm_status & ECMXF_STS_BUSY)
			die("the chip is busy before SDO_REQ");
		host.send(ECMXF_CMD_ECAT_SDO_REQ, 0, 0, sdoReadPayload());
		const std::uint8_t req = host.lastIndex();
		host.send(ECMXF_CMD_INFO_UPDATE_OP); // the first poll: SDO_REQ's own answer
		if (host.h.index != req || host.h.code != ECMXF_CMD_ECAT_SDO_REQ)
			die("the first poll did not read SDO_REQ's answer");
		if (host.h.ecm_status & ECMXF_STS_BUSY) {
			chip.advance(1ms);
			host.waitIdle1ms();
		}
		host.cmd(ECMXF_CMD_ECAT_SDO_GET);
		if (host.data.size() != 4)
			die("SDO_GET returned " + std::to_string(host.data.size()) + " bytes");
		transfers += host.timer.micros();
	}
	Figures f;
	f.exchanges = static_cast<double>(chip.stats().exchanges - x0) / kRounds;
	f.micros = std::chrono::duration<double, std::micro>(chip.now() - t0).count() / kRounds;
	f.transferUs = transfers / kRounds;
	return f;
}

} // namespace

int main()
{
	// one exchange: a 144-byte packet at the default 48 MHz SPI clock plus
	// the chip's default processing time (INT0 busy), sim::ChipConfig
	const sim::ChipConfig cfg;
	const double exchangeUs = static_cast<double>(ECMXF_PKT_SIZE(ECMXF_DATA_DEFAULT)) * 8.0 * 1e6 /
					  static_cast<double>(cfg.spiClockHz) +
				  std::chrono::duration<double, std::micro>(cfg.processingTime).count();
	std::printf("bench-sdo: 4-byte SDO upload (0x6064:00) from an EST-584 in PRE-OP, %d rounds, simulated "
		    "time;\n"
		    "overhead = time - the slave's mailbox latency, in exchange times (one exchange = %.1f us:\n"
		    "144 bytes at %u Hz + %.0f us chip processing). per transfer = back to back (the total over the\n"
		    "rounds); one transfer = from the start of the exchange that carries SDO_REQ to the end of the\n"
		    "one that brings SDO_GET's answer. engine off = before pipelining (INFO_UPDATE polls, SDO_GET\n"
		    "after the completion), on = pipelined (SDO_GET is the poll, sent ahead); same run.\n",
		    kRounds, exchangeUs, cfg.spiClockHz, std::chrono::duration<double, std::micro>(cfg.processingTime).count());
	std::printf("  %-10s | %-28s | %-45s | %-28s | %s\n", "latency", "engine off: xfers, per transfer",
		    "engine on: xfers, per transfer, one transfer", "NEXTW example (200 us, 1 ms polls)",
		    "baseline/on");
	auto ex = [&](double us, unsigned lat) { return (us - lat) / exchangeUs; };
	// 1000 us is the EST-584 model's default mailbox latency
	for (unsigned lat : { 100u, 250u, 500u, 1000u, 1200u }) {
		const Figures a = ours(lat, false);
		const Figures p = ours(lat, true);
		const Figures b = baseline(lat);
		std::printf("  %7u us | %4.1f %7.1f us +%4.2f ex | %4.1f %7.1f us +%4.2f ex, %7.1f us +%4.2f ex | "
			    "%4.1f %7.1f us +%5.2f ex | %5.2fx\n",
			    lat, a.exchanges, a.micros, ex(a.micros, lat), p.exchanges, p.micros, ex(p.micros, lat),
			    p.transferUs, ex(p.transferUs, lat), b.exchanges, b.micros, ex(b.micros, lat),
			    b.micros / p.micros);
	}
	std::printf("  (the slave's mailbox latency bounds all; a 1 ms poller is at its best when the\n"
		    "   latency is just under 1 ms, at its worst just over it. The physical limit is one\n"
		    "   exchange to send the request and one to fetch the result, plus the wait for the\n"
		    "   first fetch that runs after the slave answered: under one exchange, since the\n"
		    "   fetch goes out in every exchange)\n");
	return 0;
}
