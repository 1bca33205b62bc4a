// SPDX-License-Identifier: MIT
/*
 * ecmxf-sim - serve the simulated ECM-XF over a byte pipe.
 *
 * Standard input/output by default, or a Unix stream socket (--socket),
 * with the framing of Documentation/simulator.rst ("ecmxf-sim wire
 * protocol"): one request, one reply, in order.
 *
 *   request                              reply
 *   'X' u16 n, n bytes MOSI              'X' u16 n, n bytes MISO
 *   'L'                                  'L' u8 lines (bit0 INT0, bit1 INT1,
 *                                            bit2 ready)
 *   'A' u64 ns                           'A' u64 now_ns   (advance time)
 *   'T'                                  'T' u64 now_ns   (read time)
 *   'F' u8 fault, u32 value              'F' u8 0
 *   'Q'                                  'Q'              (then exit/close)
 *   'H'                                  'H' "ECMXFSIM" u16 version (hello;
 *                                            version 1 = this protocol)
 *   anything malformed                   'E' u16 n, n bytes of message
 *   (a second client on --socket)        'B' u16 n, n bytes of message,
 *                                            then the connection is closed
 *
 * All integers are little-endian. Over --socket the chip lives as long as
 * the server: its state survives between clients. One client is served at
 * a time; a client that connects while another is served is refused at
 * once with 'B' ("busy").
 */
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <optional>
#include <string_view>
#include <utility>
#include <span>
#include <vector>


#include <ecmxf/protocol.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

#include "ecmxf-sim-server.hpp"
#include "ecmxf-sim-sk.hpp"

namespace {

// Fault identifiers of the 'F' request.
enum FaultId : std::uint8_t {
	kFaultMosiBitErrors = 1,
	kFaultMisoBitErrors = 2,
	kFaultNotReady = 3,
	kFaultInt0StuckBusy = 4,
	kFaultLinkLost = 5,
	kFaultSlaveDropped = 6,
	kFaultSdoAbort = 7,
	kFaultAsyncStuck = 8,
};

// The simulated ECM-XF behind the server's wire loop.
class ChipTarget final : public ecmxfsim::Target
{
public:
	explicit ChipTarget(ecmxf::sim::Chip &chip) : chip_(chip) {}

	std::string badExchange(std::size_t n) const override
	{
		if (n < ecmxf::packetSize(ecmxf::kDataMin) || n > ecmxf::packetSize(ecmxf::kDataMax))
			return "packets are 56..1440 bytes";
		return {};
	}
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		chip_.exchange(mosi, miso);
	}
	std::uint8_t lines() const override
	{
		return static_cast<std::uint8_t>((chip_.int0() ? 1 : 0) | (chip_.int1() ? 2 : 0) |
						 (chip_.ready() ? 4 : 0));
	}
	void advance(std::chrono::nanoseconds d) override { chip_.advance(d); }
	std::chrono::nanoseconds now() const override { return chip_.now(); }
	std::string fault(std::uint8_t id, std::uint32_t v) override
	{
		auto &f = chip_.faults();
		switch (id) {
		case kFaultMosiBitErrors:
			f.mosiBitErrors = v;
			break;
		case kFaultMisoBitErrors:
			f.misoBitErrors = v;
			break;
		case kFaultNotReady:
			f.notReady = v;
			break;
		case kFaultInt0StuckBusy:
			f.int0StuckBusy = v != 0;
			break;
		case kFaultLinkLost:
			f.linkLost = v != 0;
			break;
		case kFaultSlaveDropped:
			f.slaveDropped = static_cast<int>(v == 0xFFFFFFFFu ? -1 : static_cast<int>(v));
			break;
		case kFaultSdoAbort:
			f.forcedSdoAbort = v;
			break;
		case kFaultAsyncStuck:
			f.asyncStuckBusy = v != 0;
			break;
		default:
			return "unknown fault id " + std::to_string(id);
		}
		return {};
	}

private:
	ecmxf::sim::Chip &chip_;
};

void usage(std::FILE *out)
{
	std::fprintf(out,
		     "Usage: ecmxf-sim [--network FILE] [--chip KEY=VALUE]... [--paced] [--socket PATH]\n"
		     "\n"
		     "Serve a simulated ECM-XF over standard input/output, or over a Unix\n"
		     "stream socket (one client at a time: another one is refused as busy; the\n"
		     "chip keeps its state between clients, reach it with the device URI\n"
		     "unix:PATH). The wire protocol is described in\n"
		     "Documentation/sim-wire-protocol.rst.\n"
		     "\n"
		     "  -n, --network FILE  network description (default: 2x EST-584 + I/O)\n"
		     "  -c, --chip KEY=VALUE  a chip option, over the network file's `chip`\n"
		     "                      lines (may be repeated): crc32-coverage=frame|valid,\n"
		     "                      crc-type-set-fixed=drop|accept, init-op=strict|lenient\n"
		     "                      (firmware variants, Documentation/simulator.rst)\n"
		     "  -p, --paced         follow the wall clock instead of virtual time\n"
		     "  -s, --socket PATH   listen on a Unix socket at PATH\n"
		     "  -b, --board BOARD   ecm-xf (default) or ecm-sk (--board ecm-sk --help)\n"
		     "  -h, --help          show this help\n");
}

int run(int argc, char **argv)
{
	ecmxf::sim::ChipConfig cfg;
	std::vector<std::pair<std::string, std::string>> chipOptions;
	const std::optional<ecmxfsim::Options> o = ecmxfsim::parseOptions(
		argc, argv,
		[&](std::string_view a, const ecmxfsim::OptionValue &value) {
			if (a == "-c" || a == "--chip") {
				const std::string kv = value("--chip");
				const auto eq = kv.find('=');
				if (eq == std::string::npos || eq == 0)
					throw std::invalid_argument("--chip '" + kv + "' is not KEY=VALUE (" +
								    std::string(ecmxf::sim::kChipOptions) + ")");
				chipOptions.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
				try {
					ecmxf::sim::ChipConfig check;
					ecmxf::sim::applyChipOption(check, chipOptions.back().first,
								    chipOptions.back().second);
				} catch (const std::invalid_argument &e) {
					throw std::invalid_argument(std::string("--chip: ") + e.what());
				}
				return true;
			}
			if (a == "-p" || a == "--paced") {
				cfg.timeMode = ecmxf::sim::TimeMode::Paced;
				return true;
			}
			return false;
		},
		" (try --help)", usage);
	if (!o)
		return 0; // --help
	const std::string &network = o->network;

	ecmxf::sim::Network net =
		network.empty() ? ecmxf::sim::Network::defaultNetwork() : ecmxf::sim::Network::fromFile(network);
	for (const auto &[key, val] : chipOptions)
		net.setChipOption(key, val); // over the file's chip lines
	ecmxf::sim::Chip chip(std::move(net), cfg);

	ChipTarget target(chip);
	return ecmxfsim::serve(target, o->socketPath);
}

} // namespace

int main(int argc, char **argv)
{
	std::signal(SIGPIPE, SIG_IGN);
	try {
		if (ecmxfSimWantsSk(argc, argv)) // --board ecm-sk: utils/ecmxf-sim-sk.cpp
			return ecmxfSimSkMain(argc, argv);
		return run(argc, argv);
	} catch (const std::exception &e) {
		std::fprintf(stderr, "ecmxf-sim: %s\n", e.what());
		return 1;
	}
}
