// SPDX-License-Identifier: MIT
/*
 * ecmxf-sim --board ecm-sk: serve a simulated ECM-SK over the wire
 * protocol of ecmxf-sim (Documentation/sim-wire-protocol.rst), on
 * standard input/output or a Unix socket, one client at a time.
 *
 *   'X' u16 n, n bytes MOSI   'X' u16 n, n bytes MISO (n = 504 or 512, the
 *                             board's frame; other sizes: 'E')
 *   'L'                       'L' u8: bit 0 Busy high, bit 2 ready (Busy low)
 *   'A' u64 ns / 'T'          'A'/'T' u64 now_ns
 *   'H'                       'H' "ECMXFSIM" u16 version
 *   'Q'                       'Q', then the server ends
 *   'F'                       'E' (no fault injection on this board)
 *
 * The library reaches it with "sk-unix:PATH?slot=...&ex=..."
 * (UnixChannel); Documentation/ecm-sk.rst, "The simulator".
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>


#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/sim_channel.hpp>

#include "ecmxf-sim-server.hpp"
#include "ecmxf-sim-sk.hpp"

namespace {

using ecmxfsim::le;
using ecmxfsim::Served;
using Stream = ecmxfsim::Pipe;

Served serveOne(ecmxf::sk::SimBoard &b, Stream &s)
{
	std::uint8_t type = 0;
	if (!s.read(&type, 1))
		return Served::Closed;
	switch (type) {
	case 'X': {
		std::uint8_t h[2];
		if (!s.read(h, 2))
			return Served::Closed;
		const auto n = static_cast<std::size_t>(le(h, 2));
		std::vector<std::uint8_t> mosi(n), miso(n, 0);
		if (!s.read(mosi.data(), n))
			return Served::Closed;
		if (n != b.frameSize()) {
			s.message('E', "exchange of " + std::to_string(n) + " bytes: this ECM-SK's frame is " +
					       std::to_string(b.frameSize()) + " bytes (slot=" +
					       std::to_string(b.config().slotSize) + ")");
			break;
		}
		b.exchange(mosi, miso);
		s.u8('X');
		s.u16(static_cast<std::uint16_t>(n));
		s.write(miso.data(), n);
		break;
	}
	case 'L':
		s.u8('L');
		s.u8(static_cast<std::uint8_t>(b.busy() ? 1 : 4));
		break;
	case 'A': {
		std::uint8_t v[8];
		if (!s.read(v, 8))
			return Served::Closed;
		const std::uint64_t ns = le(v, 8);
		if (ns > 3'600'000'000'000ULL) {
			s.message('E', "advance of more than one hour refused");
			break;
		}
		b.advance(std::chrono::nanoseconds(static_cast<std::int64_t>(ns)));
		s.u8('A');
		s.u64(static_cast<std::uint64_t>(b.now().count()));
		break;
	}
	case 'T':
		s.u8('T');
		s.u64(static_cast<std::uint64_t>(b.now().count()));
		break;
	case 'F': {
		std::uint8_t v[5];
		if (!s.read(v, 5))
			return Served::Closed;
		s.message('E', "no fault injection on the simulated ECM-SK");
		break;
	}
	case 'H': {
		const auto magic = ecmxf::UnixChannel::kHelloMagic;
		s.u8('H');
		s.write(magic.data(), magic.size());
		s.u16(ecmxf::UnixChannel::kProtocolVersion);
		break;
	}
	case 'Q':
		s.u8('Q');
		return Served::Quit;
	default: {
		char hex[8];
		std::snprintf(hex, sizeof(hex), "0x%02x", type);
		s.message('E', std::string("unknown request type ") + hex);
		return Served::Closed;
	}
	}
	return Served::More;
}

void usage(std::FILE *out)
{
	std::fprintf(out,
		     "Usage: ecmxf-sim --board ecm-sk [--network FILE] [--settings KEY=VALUE&...]\n"
		     "                 [--socket PATH]\n"
		     "\n"
		     "Serve a simulated ECM-SK starter kit (Documentation/ecm-sk.rst) over standard\n"
		     "input/output or a Unix socket; reach it with sk-unix:PATH?slot=12|16&ex=0..3.\n"
		     "\n"
		     "  -n, --network FILE   slaves (default: servo (Drive) + EST-584 (STEP) + dio (IO))\n"
		     "  -o, --settings S     board settings: slot=12|16, test=0|1, abandon=0|1,\n"
		     "                       ex=0..3, fifo=161..4096, busy_us=, spi_hz=, lio=0..63\n"
		     "  -s, --socket PATH    listen on a Unix socket at PATH\n"
		     "  -h, --help           show this help\n");
}

} // namespace

bool ecmxfSimWantsSk(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		const std::string_view a = argv[i];
		if (a != "--board" && a != "-b")
			continue;
		if (i + 1 >= argc)
			throw std::invalid_argument("--board needs a value: ecm-xf or ecm-sk");
		const std::string_view v = argv[i + 1];
		if (v != "ecm-xf" && v != "ecm-sk")
			throw std::invalid_argument("--board " + std::string(v) + ": ecm-xf or ecm-sk");
		return v == "ecm-sk";
	}
	return false;
}

int ecmxfSimSkMain(int argc, char **argv)
{
	std::string network, settings, socketPath;
	for (int i = 1; i < argc; i++) {
		const std::string_view a = argv[i];
		auto value = [&](const char *what) -> std::string {
			if (i + 1 >= argc)
				throw std::invalid_argument(std::string(what) + " needs a value");
			return argv[++i];
		};
		if (a == "-h" || a == "--help") {
			usage(stdout);
			return 0;
		} else if (a == "-b" || a == "--board") {
			(void)value("--board");
		} else if (a == "-n" || a == "--network") {
			network = value("--network");
		} else if (a == "-o" || a == "--settings") {
			settings = value("--settings");
		} else if (a == "-s" || a == "--socket") {
			socketPath = value("--socket");
		} else {
			throw std::invalid_argument("unknown option '" + std::string(a) +
						    "' for --board ecm-sk (try --board ecm-sk --help)");
		}
	}
	ecmxf::sk::SimBoard board(network.empty()
					  ? ecmxf::sim::Network::fromText(ecmxf::sk::defaultSkNetwork(), "ecm-sk")
					  : ecmxf::sim::Network::fromFile(network),
				  ecmxf::sk::BoardConfig::parse(settings));
	const ecmxfsim::ServeOne serve = [&board](Stream &s) { return serveOne(board, s); };
	if (socketPath.empty())
		return ecmxfsim::serveStdio(serve);
	return ecmxfsim::serveSocket(socketPath, serve);
}
