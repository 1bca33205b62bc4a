// SPDX-License-Identifier: MIT
//
// bench-sim: how much faster than real time the simulator runs a bus.
//
// One simulated second of an 8 kHz bus (125 us DC cycle) after bringing the
// network to OP: the host keeps the chip's RxFIFO fed with one
// PDO_DATA_FIFO_OP per bus cycle (write one RxPDO frame, read TxPDO frames),
// i.e. 8 full FIFO exchanges per millisecond at the largest packet size
// (1440 bytes, 96 Mbit/s). Reported: simulated time / CPU time of this
// thread (the target: >= 10x), plus the wall-clock ratio, bus
// cycles, frames and WKC errors so that a broken run cannot look fast.

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <time.h>

#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

#include "ecmxf-proto.h"

namespace {

using namespace std::chrono_literals;
namespace sim = ecmxf::sim;

double threadCpuSeconds()
{
	timespec ts{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

[[noreturn]] void die(const std::string &what)
{
	std::fprintf(stderr, "bench-sim: %s\n", what.c_str());
	std::exit(1);
}

// A raw host: packets built with the protocol core, one exchange at a time.
class Host
{
public:
	explicit Host(sim::Chip &chip) : chip_(chip) {}

	std::size_t dataSize = ECMXF_DATA_DEFAULT;
	ecmxf_rsp_hdr h{};
	std::vector<std::uint8_t> data;

	// One exchange with a fresh index (or a repeat of the last packet).
	void send(std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0,
		  const std::vector<std::uint8_t> &payload = {}, std::uint16_t len = 0xFFFF,
		  bool repeat = false)
	{
		if (!repeat) {
			hdr_ = {};
			hdr_.code = code;
			hdr_.param = param;
			hdr_.data[0] = d0;
			hdr_.len = len == 0xFFFF ? static_cast<std::uint16_t>(payload.size()) : len;
			hdr_.index = ++index_;
			payload_ = payload;
		}
		tx_.assign(ECMXF_PKT_SIZE(dataSize), 0);
		rx_.assign(tx_.size(), 0);
		if (ecmxf_encode_cmd(tx_.data(), tx_.size(), ECMXF_CHECK_FIXED, &hdr_, payload_.data(),
				     payload_.size()))
			die("encode failed");
		chip_.exchange(tx_, rx_);
		const std::uint8_t *d = nullptr;
		if (ecmxf_decode_rsp(rx_.data(), rx_.size(), ECMXF_CHECK_FIXED, &h, &d) !=
		    ECMXF_FAULT_NONE)
			die("bad response");
		data.assign(d, d + h.len);
	}

	// A command and its answer (the answer comes one exchange late).
	void cmd(std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0,
		 const std::vector<std::uint8_t> &payload = {}, std::uint16_t len = 0xFFFF)
	{
		send(code, param, d0, payload, len);
		for (int i = 0; i < 10; i++) {
			send(code, 0, 0, {}, 0, true);
			if (h.index == hdr_.index && h.code == code)
				return;
		}
		die("no answer to command " + std::to_string(code));
	}

	// An async command, then INFO_UPDATE polls every millisecond until idle.
	void async(std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0,
		   const std::vector<std::uint8_t> &payload = {})
	{
		cmd(code, param, d0, payload);
		for (int i = 0; i < 20000; i++) {
			if (!(h.ecm_status & ECMXF_STS_BUSY)) {
				if (h.err_status & ECMXF_ERR_ASYNC)
					die("async command " + std::to_string(code) + " failed");
				return;
			}
			chip_.advance(1ms);
			cmd(ECMXF_CMD_INFO_UPDATE_OP);
		}
		die("async command " + std::to_string(code) + " never finished");
	}

private:
	sim::Chip &chip_;
	ecmxf_cmd_hdr hdr_{};
	std::vector<std::uint8_t> payload_, tx_, rx_;
	std::uint8_t index_ = 0;
};

struct Result {
	std::size_t slaves = 0;
	double simulated = 0, cpu = 0, wall = 0;
	std::uint64_t cycles = 0, framesOut = 0, framesIn = 0, wkcErrors = 0;
	std::size_t rxSize = 0, txSize = 0;
};

Result run(sim::Network net)
{
	Result res;
	res.slaves = net.size();
	sim::ChipConfig cfg;
	cfg.spiClockHz = 96'000'000; // the chip's maximum
	sim::Chip chip(std::move(net), cfg);
	Host host(chip);

	host.send(ECMXF_CMD_INFO_UPDATE_OP); // the power-on NOP
	std::vector<std::uint8_t> init = { 0xFF, 0x81, 0, 0 };
	const std::uint32_t sync0 = 125'000;
	for (int i = 0; i < 4; i++)
		init.push_back(static_cast<std::uint8_t>(sync0 >> (8 * i)));
	init.resize(16, 0);
	host.async(ECMXF_CMD_ECAT_INIT_OP, 0, 0, init);
	for (unsigned st : { ECMXF_ECAT_PREOP, ECMXF_ECAT_SAFEOP, ECMXF_ECAT_OP })
		host.async(ECMXF_CMD_ECAT_STATE_SET, 0xFF, static_cast<std::uint8_t>(st));
	host.cmd(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	if (host.h.ret != ECMXF_ECAT_OP)
		die("network did not reach OP (state " + std::to_string(host.h.ret) + ")");

	// largest packets: SPI_RECONFIG_OP, 100 ms, then 1440-byte exchanges
	host.send(ECMXF_CMD_SPI_RECONFIG_OP, 0, 0, {}, ECMXF_DATA_MAX);
	chip.advance(100ms);
	host.dataSize = ECMXF_DATA_MAX;
	host.send(ECMXF_CMD_SPI_RECONFIG_OP, 0, 0, {}, ECMXF_DATA_MAX, true);
	host.cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0);
	res.rxSize = static_cast<std::size_t>(host.data.at(0) | host.data.at(1) << 8);
	host.cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1);
	res.txSize = static_cast<std::size_t>(host.data.at(0) | host.data.at(1) << 8);
	if (!res.rxSize || !res.txSize || res.rxSize > ECMXF_DATA_MAX)
		die("unexpected PDO sizes");
	host.cmd(ECMXF_CMD_FIFO_ENABLE, 1);
	host.cmd(ECMXF_CMD_INFO_UPDATE_OP);
	const unsigned wkc0 = host.h.wkc_err_cnt;

	const std::vector<std::uint8_t> frame(res.rxSize, 0);
	const auto sim0 = chip.now();
	const auto cycles0 = chip.stats().busCycles;
	const double cpu0 = threadCpuSeconds();
	const auto wall0 = std::chrono::steady_clock::now();
	for (int ms = 0; ms < 1000; ms++) {
		for (int k = 0; k < 8; k++) {
			// write one frame, read what is there: one exchange per cycle
			host.send(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, 1, 0x03, frame);
			res.framesOut++;
			if (host.h.code == ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP && (host.h.ret & 0x02))
				res.framesIn += host.h.len / res.txSize;
		}
		const auto next = sim0 + std::chrono::milliseconds(ms + 1);
		if (chip.now() < next)
			chip.advance(next - chip.now());
	}
	res.cpu = threadCpuSeconds() - cpu0;
	res.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
	res.simulated = std::chrono::duration<double>(chip.now() - sim0).count();
	res.cycles = chip.stats().busCycles - cycles0;
	host.cmd(ECMXF_CMD_INFO_UPDATE_OP);
	res.wkcErrors = host.h.wkc_err_cnt - wkc0;
	return res;
}

} // namespace

int main()
{
	struct Case {
		const char *name;
		sim::Network (*make)();
	};
	const Case cases[] = {
		{ "2x EST-584 + I/O (default)", [] { return sim::Network::defaultNetwork(); } },
		{ "16x EST-584", [] { return sim::Network::fromText("slave EST-584 count=16\n", "16"); } },
		{ "128 slaves (slaves128.net)",
		  [] { return sim::Network::fromFile(ECMXF_BENCH_NETWORK_DIR "/slaves128.net"); } },
	};

	std::printf("\nSimulator speed: 1 simulated second of an 8 kHz bus (125 us cycle), one\n"
		    "PDO_DATA_FIFO_OP of 1440 bytes per cycle (8 FIFO exchanges per ms)\n\n");
	std::printf("%-28s %6s %6s %8s %8s %8s %8s %9s %9s %5s\n", "network", "slaves", "rx/tx B",
		    "sim s", "cpu s", "wall s", "x real", "cycles", "frames in", "WKC e");
	bool ok = true;
	double ratio128 = 0;
	for (const Case &c : cases) {
		Result r;
		try {
			r = run(c.make());
		} catch (const std::exception &e) {
			die(std::string(c.name) + ": " + e.what());
		}
		const double ratio = r.simulated / r.cpu;
		std::printf("%-28s %6zu %3zu/%-3zu %8.3f %8.3f %8.3f %8.1f %9llu %9llu %5llu\n", c.name,
			    r.slaves, r.rxSize, r.txSize, r.simulated, r.cpu, r.wall, ratio,
			    static_cast<unsigned long long>(r.cycles),
			    static_cast<unsigned long long>(r.framesIn),
			    static_cast<unsigned long long>(r.wkcErrors));
		if (r.cycles < 7990 || r.wkcErrors != 0 || r.framesIn < 7900) {
			std::printf("  ^ run incomplete: expected ~8000 cycles, ~8000 frames, no WKC errors\n");
			ok = false;
		}
		if (r.slaves == 128)
			ratio128 = ratio;
	}
	std::printf("\ntarget: 128 slaves at >= 10x real time (simulated s / CPU s): %.1fx -> %s\n",
		    ratio128, ratio128 >= 10.0 ? "MET" : "MISSED");
	return ok ? 0 : 1;
}
