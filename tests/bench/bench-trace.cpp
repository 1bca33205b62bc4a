// SPDX-License-Identifier: MIT
/*
 * bench-trace - `ecmxf-util decode --pcapng` (ecmxf::traceToPcapng()) of a
 * text trace of 10^6 exchanges (a MOSI and a MISO packet of 144 bytes
 * each, as the library's trace writer writes them), in exchanges per
 * second; the target is 10^6/s (`make bench`, Documentation/trace.rst).
 * The text trace is flushed to the disk before the conversion starts (its
 * write-back does not compete with the conversion), and the conversion's
 * CPU time (user: the reader and the writer; system: the kernel's copies
 * into and out of the page cache) is printed beside the wall time.
 *
 * bench-trace [EXCHANGES] (default 1000000); the files go to $TMPDIR.
 */
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <ecmxf/trace/trace.hpp>

#include "ecmxf-proto.h"
#include "link/trace_writer.hpp"

namespace {

/// The process's user and system CPU time so far, in seconds.
struct Cpu {
	double user = 0, sys = 0;
};
Cpu cpuSeconds()
{
	rusage u{};
	::getrusage(RUSAGE_SELF, &u);
	auto sec = [](const timeval &t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6; };
	return { sec(u.ru_utime), sec(u.ru_stime) };
}

} // namespace

int main(int argc, char **argv)
{
	const unsigned long exchanges = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 1'000'000ul;
	const char *tmp = std::getenv("TMPDIR");
	const std::filesystem::path dir = tmp && *tmp ? tmp : "/tmp";
	const std::string text = (dir / "ecmxf-bench-trace.trace").string();
	const std::string pcap = (dir / "ecmxf-bench-trace.pcapng").string();

	// the trace: command and answer packets with a varying header and data
	{
		ecmxf::detail::TraceWriter w(text);
		w.format(ECMXF_DATA_DEFAULT, ECMXF_CHECK_FIXED);
		std::vector<std::uint8_t> cmd(ECMXF_PKT_SIZE(ECMXF_DATA_DEFAULT)), rsp(cmd.size());
		ecmxf_cmd_hdr ch{};
		ecmxf_rsp_hdr rh{};
		std::uint8_t data[ECMXF_DATA_DEFAULT];
		for (unsigned long i = 0; i < exchanges; i++) {
			ch.code = ECMXF_CMD_ECAT_PDO_DATA_OP;
			ch.index = static_cast<std::uint8_t>(i);
			ch.len = 64;
			for (unsigned k = 0; k < sizeof(data); k++)
				data[k] = static_cast<std::uint8_t>(i * 7 + k);
			ecmxf_encode_cmd(cmd.data(), cmd.size(), ECMXF_CHECK_FIXED, &ch, data, 64);
			rh.code = ch.code;
			rh.index = ch.index;
			rh.len = 64;
			ecmxf_encode_rsp(rsp.data(), rsp.size(), ECMXF_CHECK_FIXED, &rh, data, 64);
			w.packet(i * 100'000u, '>', cmd);
			w.packet(i * 100'000u + 30'000u, '<', rsp);
		}
		w.close();
	}
	const auto textSize = std::filesystem::file_size(text);
	::sync();

	std::ifstream in(text, std::ios::binary);
	const Cpu c0 = cpuSeconds();
	const auto t0 = std::chrono::steady_clock::now();
	const ecmxf::TraceSummary s = ecmxf::traceToPcapng(in, pcap);
	const auto t1 = std::chrono::steady_clock::now();
	const Cpu c1 = cpuSeconds();
	const double user = c1.user - c0.user, sys = c1.sys - c0.sys, cpu = user + sys;
	const double sec = std::chrono::duration<double>(t1 - t0).count();
	const auto pcapSize = std::filesystem::file_size(pcap);
	std::filesystem::remove(text);
	std::filesystem::remove(pcap);
	const double rate = static_cast<double>(s.packets) / 2.0 / sec;
	const double cpuRate = static_cast<double>(s.packets) / 2.0 / cpu;
	std::printf("bench-trace: decode --pcapng of %lu exchanges (%zu packets, %.0f MB text -> %.0f MB pcapng): "
		    "%.3f s, %.0f exchanges/s (%.0f MB/s of text); target 1000000/s: %s\n"
		    "bench-trace: CPU time %.3f s (user %.3f s, system %.3f s), %.0f exchanges per CPU second\n",
		    exchanges, s.packets, static_cast<double>(textSize) / 1e6, static_cast<double>(pcapSize) / 1e6, sec,
		    rate, static_cast<double>(textSize) / 1e6 / sec, rate >= 1e6 ? "met" : "NOT met", cpu, user, sys, cpuRate);
	return 0;
}
