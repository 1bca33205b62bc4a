// SPDX-License-Identifier: MIT
/*
 * bench-core.cpp - CPU cost of the protocol core per SPI packet
 *
 * For each check type and for the default (N=112, 144 B) and the largest
 * legal packet (N=1408, 1440 B):
 *   encode+decode  ecmxf_encode_cmd() with a full data section (check
 *                  word included) + ecmxf_decode_rsp() of a valid
 *                  response of the same size (check word verified);
 *   encode, decode the two halves alone;
 * and, with CRC-32:
 *   crc32 raw      ecmxf_crc32() over the 1432 bytes a 1440-byte packet
 *                  covers;
 *   engine round   ecmxf_engine_submit() + ecmxf_engine_next() +
 *                  ecmxf_engine_input() of one PDO_DATA_FIFO_OP with a
 *                  full data section each way, the response prepared.
 *
 * Each figure is set against the packet's wire time on SPI at 96 Mbit/s
 * (bytes * 8 / 96e6 s): the counters wire_us and cpu_pct_of_wire, and a
 * summary table at the end.  The target (issue: "CRC-32 at the largest
 * packet under 1 us of CPU, under 1 % of the wire time") is checked there.
 * The issue says "1448 bytes", which is no legal packet (N would be 1416 >
 * 1408); the largest packet is 24 + 1408 + 8 = 1440 bytes.
 */
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <unistd.h>

#include <benchmark/benchmark.h>

#include "ecmxf-proto.h"

namespace {

constexpr double kSpiBitsPerSec = 96e6;

double wire_us(size_t bytes)
{
	return static_cast<double>(bytes) * 8.0 / kSpiBitsPerSec * 1e6;
}

struct CheckType {
	ecmxf_check check;
	const char *name;
};

const CheckType kChecks[] = {
	{ ECMXF_CHECK_FIXED, "fixed" },
	{ ECMXF_CHECK_CRC8, "crc8" },
	{ ECMXF_CHECK_CCITT, "ccitt" },
	{ ECMXF_CHECK_CRC32, "crc32" },
};

const unsigned kDataSizes[] = { ECMXF_DATA_DEFAULT, ECMXF_DATA_MAX };

/* What the summary table needs to know about each benchmark. */
struct Info {
	std::string what;
	std::string check;
	size_t pkt_bytes;
	size_t wire_bytes;	/* the packet the cost is compared with */
};

std::vector<std::string> g_order;
std::map<std::string, Info> g_info;
std::map<std::string, double> g_cpu_ns;

std::vector<u8> pattern(size_t n, unsigned seed)
{
	std::vector<u8> v(n);

	for (size_t i = 0; i < n; i++)
		v[i] = static_cast<u8>(i * 31u + seed);
	return v;
}

/* A valid response packet: N bytes of data, length field N. */
std::vector<u8> make_rsp(unsigned n, ecmxf_check check, u8 index, u8 code)
{
	std::vector<u8> pkt(ECMXF_PKT_SIZE(n));
	std::vector<u8> data = pattern(n, index);
	ecmxf_rsp_hdr h{};

	h.ecat_state = ECMXF_ECAT_OP;
	h.ecm_status = static_cast<u8>(ECMXF_STS_FIFO_EN |
				       static_cast<unsigned>(check));
	h.index = index;
	h.code = code;
	h.ret = 2;
	h.len = static_cast<u16>(n);
	if (ecmxf_encode_rsp(pkt.data(), pkt.size(), check, &h, data.data(),
			     data.size()))
		std::abort();
	if (ecmxf_decode_rsp(pkt.data(), pkt.size(), check, nullptr,
			     nullptr) != ECMXF_FAULT_NONE)
		std::abort();
	return pkt;
}

ecmxf_cmd_hdr pdo_cmd_hdr(unsigned n)
{
	ecmxf_cmd_hdr h{};

	h.data[0] = 3;			/* write + read */
	h.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
	h.param = 1;
	h.len = static_cast<u16>(n);
	return h;
}

/*
 * The counter shown next to each figure; SummaryReporter adds
 * cpu_pct_of_wire from the measured CPU time.
 */
void set_counters(benchmark::State &state, size_t bytes)
{
	state.counters["wire_us"] = wire_us(bytes);
	state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
				static_cast<int64_t>(bytes));
}

void bm_encode_decode(benchmark::State &state, ecmxf_check check,
		      unsigned n, bool do_encode, bool do_decode)
{
	const size_t len = ECMXF_PKT_SIZE(n);
	std::vector<u8> cmd(len);
	std::vector<u8> tx = pattern(n, 7);
	std::vector<u8> rsp = make_rsp(n, check, 42, 5);
	ecmxf_cmd_hdr ch = pdo_cmd_hdr(n);

	for (auto _ : state) {
		if (do_encode) {
			int r = ecmxf_encode_cmd(cmd.data(), len, check, &ch,
						 tx.data(), n);
			benchmark::DoNotOptimize(r);
			benchmark::ClobberMemory();
		}
		if (do_decode) {
			ecmxf_rsp_hdr h;
			const u8 *data;
			ecmxf_fault f = ecmxf_decode_rsp(rsp.data(), len, check,
							 &h, &data);
			benchmark::DoNotOptimize(f);
			benchmark::DoNotOptimize(h);
			benchmark::DoNotOptimize(data);
		}
		ch.index++;
	}
	set_counters(state, len);
}

void bm_crc32_raw(benchmark::State &state, size_t n)
{
	std::vector<u8> buf = pattern(n, 1);

	for (auto _ : state) {
		u32 crc = ecmxf_crc32(buf.data(), buf.size());
		benchmark::DoNotOptimize(crc);
		benchmark::ClobberMemory();
	}
	/* compared with the wire time of the packet it covers */
	set_counters(state, n + ECMXF_TRAILER_SIZE);
}

/*
 * One engine round: submit a PDO_DATA_FIFO_OP, build its packet, feed the
 * answer.  The answers are prepared for every index (the engine numbers
 * its commands 1, 2, ... 255, 0, 1, ...), so the response always matches
 * the packet just built and the command completes every round.
 */
void bm_engine_round(benchmark::State &state, unsigned n)
{
	const ecmxf_check check = ECMXF_CHECK_CRC32;
	const size_t len = ECMXF_PKT_SIZE(n);
	std::vector<std::vector<u8>> rsp;
	std::vector<u8> tx = pattern(n, 9), rx(n), pkt(len);
	ecmxf_engine e;
	ecmxf_xfer x{};
	u64 now = 1000000;

	for (unsigned i = 0; i < 256; i++)
		rsp.push_back(make_rsp(n, check, static_cast<u8>(i),
				       ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP));

	ecmxf_engine_init(&e, n, check);
	/* the sync exchange of a fresh engine */
	if (ecmxf_engine_next(&e, now, pkt.data(), len))
		std::abort();
	ecmxf_engine_input(&e, now, rsp[pkt[0x0B]].data(), len);

	x.hdr = pdo_cmd_hdr(n);
	x.tx_data = tx.data();
	x.tx_len = static_cast<u16>(n);
	x.rx_buf = rx.data();
	x.rx_size = static_cast<u16>(n);

	for (auto _ : state) {
		now += 20000;
		if (ecmxf_engine_submit(&e, &x, now))
			state.SkipWithError("submit failed");
		if (ecmxf_engine_next(&e, now, pkt.data(), len))
			state.SkipWithError("next failed");
		unsigned ev = ecmxf_engine_input(&e, now, rsp[pkt[0x0B]].data(),
						 len);
		if (!(ev & ECMXF_EV_CMD_DONE) || x.status != 0 ||
		    x.rx_len != n)
			state.SkipWithError("command did not complete");
		benchmark::DoNotOptimize(ev);
		benchmark::ClobberMemory();
	}
	set_counters(state, len);
}

void add(const std::string &name, const Info &info,
	 benchmark::internal::Benchmark *b)
{
	b->Unit(benchmark::kNanosecond);
	g_order.push_back(name);
	g_info[name] = info;
}

void register_all()
{
	for (const CheckType &c : kChecks) {
		for (unsigned n : kDataSizes) {
			const size_t len = ECMXF_PKT_SIZE(n);
			const std::string sfx = std::string(c.name) + "/" +
						std::to_string(len);
			const ecmxf_check ck = c.check;
			std::string name;

			name = "encode+decode/" + sfx;
			add(name, { "encode+decode", c.name, len, len },
			    benchmark::RegisterBenchmark(
				    name.c_str(), bm_encode_decode, ck, n,
				    true, true));
			name = "encode/" + sfx;
			add(name, { "  encode", c.name, len, len },
			    benchmark::RegisterBenchmark(
				    name.c_str(), bm_encode_decode, ck, n,
				    true, false));
			name = "decode/" + sfx;
			add(name, { "  decode", c.name, len, len },
			    benchmark::RegisterBenchmark(
				    name.c_str(), bm_encode_decode, ck, n,
				    false, true));
		}
	}

	const size_t covered = ECMXF_PKT_MAX - ECMXF_TRAILER_SIZE;	/* 1432 */
	std::string name = "crc32-raw/" + std::to_string(covered);
	add(name, { "raw CRC-32 of " + std::to_string(covered) + " B", "crc32",
		    covered, ECMXF_PKT_MAX },
	    benchmark::RegisterBenchmark(name.c_str(), bm_crc32_raw, covered));

	for (unsigned n : kDataSizes) {
		const size_t len = ECMXF_PKT_SIZE(n);

		name = "engine-round/crc32/" + std::to_string(len);
		add(name, { "engine round", "crc32", len, len },
		    benchmark::RegisterBenchmark(name.c_str(), bm_engine_round,
						 n));
	}
}

/*
 * The console output as usual, with cpu_pct_of_wire = 100 * CPU time per
 * packet / wire time added to each run, and the CPU time of each run kept
 * for the summary.
 */
class SummaryReporter : public benchmark::ConsoleReporter {
public:
	/* colour only on a terminal (a custom reporter ignores
	 * --benchmark_color) */
	SummaryReporter()
		: ConsoleReporter(isatty(STDOUT_FILENO) && !std::getenv("NO_COLOR") ?
				  OO_ColorTabular : OO_Tabular)
	{
	}

	void ReportRuns(const std::vector<Run> &runs) override
	{
		std::vector<Run> out(runs);

		for (Run &r : out) {
			auto w = r.counters.find("wire_us");

			if (r.error_occurred || w == r.counters.end())
				continue;
			/* every benchmark here reports in ns */
			r.counters["cpu_pct_of_wire"] = benchmark::Counter(
				r.GetAdjustedCPUTime() /
				(w->second.value * 1000.0) * 100.0);
			if (r.run_type == Run::RT_Iteration)
				g_cpu_ns[r.run_name.str()] =
					r.GetAdjustedCPUTime();
		}
		ConsoleReporter::ReportRuns(out);
	}
};

int print_summary()
{
	const std::string target = "encode+decode/crc32/" +
				   std::to_string(ECMXF_PKT_MAX);
	int missing = 0;

	std::printf("\nECM-XF protocol core: CPU per packet against SPI wire time at 96 Mbit/s\n"
		    "(packet = 24 header + N data + 8 check/end; 144 B is N=112, the default;\n"
		    " 1440 B is N=1408, the largest legal packet: the issue's \"1448 bytes\"\n"
		    " would need N=1416 > 1408)\n\n");
	std::printf("%-30s %-6s %8s %10s %9s %13s\n", "operation", "check",
		    "packet", "cpu ns", "wire us", "cpu % of wire");
	std::printf("%-30s %-6s %8s %10s %9s %13s\n", "---------", "-----",
		    "------", "------", "-------", "-------------");
	for (const std::string &name : g_order) {
		const Info &in = g_info[name];
		auto it = g_cpu_ns.find(name);
		const double w = wire_us(in.wire_bytes);

		if (it == g_cpu_ns.end()) {	/* filtered out or failed */
			missing++;
			continue;
		}
		std::printf("%-30s %-6s %6zu B %10.1f %9.1f %12.3f%%\n",
			    in.what.c_str(), in.check.c_str(), in.pkt_bytes,
			    it->second, w, it->second / (w * 1000.0) * 100.0);
	}

	auto it = g_cpu_ns.find(target);
	if (it != g_cpu_ns.end()) {
		const double w = wire_us(ECMXF_PKT_MAX);
		const bool ok = it->second < 1000.0;

		std::printf("\ntarget: CRC-32 encode+decode of a %u-byte packet under 1 us "
			    "(1%% of %.1f us wire time): %.1f ns = %.3f%% -> %s\n",
			    ECMXF_PKT_MAX, w, it->second,
			    it->second / (w * 1000.0) * 100.0,
			    ok ? "MET" : "MISSED");
	} else {
		std::printf("\n(target benchmark %s did not run)\n",
			    target.c_str());
	}
	if (missing)
		std::printf("(%d benchmarks not run)\n", missing);
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	register_all();
	benchmark::Initialize(&argc, argv);
	if (benchmark::ReportUnrecognizedArguments(argc, argv))
		return 1;
	SummaryReporter reporter;
	benchmark::RunSpecifiedBenchmarks(&reporter);
	benchmark::Shutdown();
	return print_summary();
}
