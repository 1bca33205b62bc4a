// SPDX-License-Identifier: MIT
/*
 * ecmxf-sim --board ecm-sk: serve a simulated ECM-SK over the wire
 * protocol of ecmxf-sim (Documentation/sim-wire-protocol.rst), on
 * standard input/output or a Unix socket, one client at a time. The wire
 * loop is the server's (ecmxf-sim-server.cpp, as for the ECM-XF); here is
 * what is the ECM-SK's: its options and its Target.
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
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <optional>
#include <string_view>
#include <span>
#include <vector>


#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/sim_channel.hpp>

#include "ecmxf-sim-server.hpp"
#include "ecmxf-sim-sk.hpp"

namespace {

// The simulated ECM-SK behind the server's wire loop: its frame size,
// Busy as the line, no fault injection.
class SkTarget final : public ecmxfsim::Target
{
public:
	explicit SkTarget(ecmxf::sk::SimBoard &b) : b_(b) {}

	std::string badExchange(std::size_t n) const override
	{
		if (n == b_.frameSize())
			return {};
		return "this ECM-SK's frame is " + std::to_string(b_.frameSize()) + " bytes (slot=" +
		       std::to_string(b_.config().slotSize) + ")";
	}
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		b_.exchange(mosi, miso);
	}
	std::uint8_t lines() const override { return static_cast<std::uint8_t>(b_.busy() ? 1 : 4); }
	void advance(std::chrono::nanoseconds d) override { b_.advance(d); }
	std::chrono::nanoseconds now() const override { return b_.now(); }
	std::string fault(std::uint8_t, std::uint32_t) override
	{
		return "no fault injection on the simulated ECM-SK";
	}

private:
	ecmxf::sk::SimBoard &b_;
};

void usage(std::FILE *out)
{
	std::fprintf(out,
		     "Usage: ecmxf-sim --board ecm-sk [--network FILE] [--settings KEY=VALUE&...]\n"
		     "                 [--paced] [--socket PATH]\n"
		     "\n"
		     "Serve a simulated ECM-SK starter kit (Documentation/ecm-sk.rst) over standard\n"
		     "input/output or a Unix socket; reach it with sk-unix:PATH?slot=12|16&ex=0..3.\n"
		     "\n"
		     "  -n, --network FILE   slaves (default: servo (Drive) + EST-584 (STEP) + dio (IO))\n"
		     "  -o, --settings S     board settings: slot=12|16, test=0|1, abandon=0|1,\n"
		     "                       ex=0..3, fifo=160..4096, busy_us=, spi_hz=, lio=0..63,\n"
		     "                       paced=0|1\n"
		     "  -p, --paced          follow the wall clock (paced=1): cycles at the board's rate\n"
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
	std::string settings;
	bool paced = false;
	const std::optional<ecmxfsim::Options> o = ecmxfsim::parseOptions(
		argc, argv,
		[&](std::string_view a, const ecmxfsim::OptionValue &value) {
			if (a == "-p" || a == "--paced") {
				paced = true;
				return true;
			}
			if (a != "-o" && a != "--settings")
				return false;
			settings = value("--settings");
			return true;
		},
		" for --board ecm-sk (try --board ecm-sk --help)", usage);
	if (!o)
		return 0; // --help
	const std::string &network = o->network;
	ecmxf::sk::SimBoard board(network.empty()
					  ? ecmxf::sim::Network::fromText(ecmxf::sk::defaultSkNetwork(), "ecm-sk")
					  : ecmxf::sim::Network::fromFile(network),
				  ecmxf::sk::BoardConfig::parse(settings + (paced ? "&paced=1" : "")));
	SkTarget target(board);
	return ecmxfsim::serve(target, o->socketPath);
}
