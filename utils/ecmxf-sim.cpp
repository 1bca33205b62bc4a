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
#include <string_view>
#include <utility>
#include <vector>

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

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

// A socket descriptor, closed with the object.
struct Socket {
	int fd = -1;
	Socket() = default;
	explicit Socket(int f) : fd(f) {}
	Socket(Socket &&o) noexcept : fd(o.fd) { o.fd = -1; }
	Socket &operator=(Socket &&o) noexcept
	{
		if (this != &o) {
			reset();
			fd = o.fd;
			o.fd = -1;
		}
		return *this;
	}
	Socket(const Socket &) = delete;
	Socket &operator=(const Socket &) = delete;
	~Socket() { reset(); }
	void reset()
	{
		if (fd >= 0)
			::close(fd);
		fd = -1;
	}
};

class Pipe
{
public:
	Pipe(int in, int out) : in_(in), out_(out) {}

	// Read exactly n bytes; false at a clean end of input.
	bool read(void *buf, std::size_t n)
	{
		auto *p = static_cast<std::uint8_t *>(buf);
		while (n) {
			const ssize_t r = ::read(in_, p, n);
			if (r == 0)
				return false;
			if (r < 0) {
				if (errno == EINTR)
					continue;
				throw std::runtime_error(std::string("read: ") + std::strerror(errno));
			}
			p += r;
			n -= static_cast<std::size_t>(r);
		}
		return true;
	}

	void write(const void *buf, std::size_t n)
	{
		const auto *p = static_cast<const std::uint8_t *>(buf);
		while (n) {
			const ssize_t r = ::write(out_, p, n);
			if (r < 0) {
				if (errno == EINTR)
					continue;
				throw std::runtime_error(std::string("write: ") + std::strerror(errno));
			}
			p += r;
			n -= static_cast<std::size_t>(r);
		}
	}

	void writeU8(std::uint8_t v) { write(&v, 1); }
	void writeU16(std::uint16_t v)
	{
		const std::uint8_t b[2] = { static_cast<std::uint8_t>(v),
					    static_cast<std::uint8_t>(v >> 8) };
		write(b, 2);
	}
	void writeU64(std::uint64_t v)
	{
		std::uint8_t b[8];
		for (int i = 0; i < 8; i++)
			b[i] = static_cast<std::uint8_t>(v >> (8 * i));
		write(b, 8);
	}

private:
	int in_;
	int out_;
};

std::uint64_t le(const std::uint8_t *b, int n)
{
	std::uint64_t v = 0;
	for (int i = n - 1; i >= 0; i--)
		v = (v << 8) | b[i];
	return v;
}

void refuse(Pipe &p, char type, const std::string &msg)
{
	p.writeU8(static_cast<std::uint8_t>(type));
	p.writeU16(static_cast<std::uint16_t>(msg.size()));
	p.write(msg.data(), msg.size());
}

void error(Pipe &p, const std::string &msg)
{
	refuse(p, 'E', msg);
}

// What serveOne() leaves behind.
enum class Served {
	More,	// the request was answered; the client may send another
	Closed, // the client went away (or must be dropped)
	Quit,	// 'Q': the server ends
};

// Read one request and answer it.
Served serveOne(ecmxf::sim::Chip &chip, Pipe &p)
{
	std::vector<std::uint8_t> mosi, miso;
	std::uint8_t type;

	if (!p.read(&type, 1))
		return Served::Closed;

	switch (type) {
	case 'X': {
		std::uint8_t b[2];
		if (!p.read(b, 2))
			return Served::Closed;
		const std::size_t n = le(b, 2);
		mosi.resize(n);
		miso.assign(n, 0);
		if (!p.read(mosi.data(), n))
			return Served::Closed;
		if (n < ecmxf::packetSize(ecmxf::kDataMin) ||
		    n > ecmxf::packetSize(ecmxf::kDataMax)) {
			error(p, "exchange of " + std::to_string(n) +
					 " bytes: packets are 56..1440 bytes");
			break;
		}
		chip.exchange(mosi, miso);
		p.writeU8('X');
		p.writeU16(static_cast<std::uint16_t>(n));
		p.write(miso.data(), n);
		break;
	}
	case 'L':
		p.writeU8('L');
		p.writeU8(static_cast<std::uint8_t>((chip.int0() ? 1 : 0) |
						    (chip.int1() ? 2 : 0) |
						    (chip.ready() ? 4 : 0)));
		break;
	case 'A': {
		std::uint8_t b[8];
		if (!p.read(b, 8))
			return Served::Closed;
		const std::uint64_t ns = le(b, 8);
		if (ns > 3'600'000'000'000ULL) {
			error(p, "advance of more than one hour refused");
			break;
		}
		chip.advance(std::chrono::nanoseconds(static_cast<std::int64_t>(ns)));
		p.writeU8('A');
		p.writeU64(static_cast<std::uint64_t>(chip.now().count()));
		break;
	}
	case 'T':
		p.writeU8('T');
		p.writeU64(static_cast<std::uint64_t>(chip.now().count()));
		break;
	case 'F': {
		std::uint8_t b[5];
		if (!p.read(b, 5))
			return Served::Closed;
		const auto v = static_cast<std::uint32_t>(le(b + 1, 4));
		auto &f = chip.faults();
		switch (b[0]) {
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
			error(p, "unknown fault id " + std::to_string(b[0]));
			return Served::More;
		}
		p.writeU8('F');
		p.writeU8(0);
		break;
	}
	case 'Q':
		p.writeU8('Q');
		return Served::Quit;
	case 'H': {
		const auto magic = ecmxf::UnixChannel::kHelloMagic;
		p.writeU8('H');
		p.write(magic.data(), magic.size());
		p.writeU16(ecmxf::UnixChannel::kProtocolVersion);
		break;
	}
	default: {
		char hex[8];
		std::snprintf(hex, sizeof(hex), "0x%02x", type);
		error(p, std::string("unknown request type ") + hex);
		return Served::Closed; // the stream is out of step: drop it
	}
	}
	return Served::More;
}

// The socket of --socket, for removeSocketAndExit().
char gSocketPath[sizeof(sockaddr_un::sun_path)];

extern "C" void removeSocketAndExit(int)
{
	::unlink(gSocketPath); // async-signal-safe, as _exit()
	::_exit(0);
}

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
		     "                      crc-type-set-fixed=drop|accept (firmware variants,\n"
		     "                      Documentation/simulator.rst)\n"
		     "  -p, --paced         follow the wall clock instead of virtual time\n"
		     "  -s, --socket PATH   listen on a Unix socket at PATH\n"
		     "  -b, --board BOARD   ecm-xf (default) or ecm-sk (--board ecm-sk --help)\n"
		     "  -h, --help          show this help\n");
}

int run(int argc, char **argv)
{
	std::string network, socketPath;
	ecmxf::sim::ChipConfig cfg;
	std::vector<std::pair<std::string, std::string>> chipOptions;

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
		} else if (a == "-n" || a == "--network") {
			network = value("--network");
		} else if (a == "-c" || a == "--chip") {
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
		} else if (a == "-p" || a == "--paced") {
			cfg.timeMode = ecmxf::sim::TimeMode::Paced;
		} else if (a == "-s" || a == "--socket") {
			socketPath = value("--socket");
		} else if (a == "-b" || a == "--board") {
			if (value("--board") != "ecm-xf") // ecm-sk: ecmxfSimSkMain()
				throw std::invalid_argument("--board: ecm-xf or ecm-sk");
		} else {
			throw std::invalid_argument("unknown option '" + std::string(a) +
						    "' (try --help)");
		}
	}

	ecmxf::sim::Network net =
		network.empty() ? ecmxf::sim::Network::defaultNetwork() : ecmxf::sim::Network::fromFile(network);
	for (const auto &[key, val] : chipOptions)
		net.setChipOption(key, val); // over the file's chip lines
	ecmxf::sim::Chip chip(std::move(net), cfg);

	if (socketPath.empty()) {
		Pipe p(STDIN_FILENO, STDOUT_FILENO);
		while (serveOne(chip, p) == Served::More) {
		}
		return 0;
	}

	const Socket listener(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
	if (listener.fd < 0)
		throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
	sockaddr_un addr{};
	addr.sun_family = AF_UNIX;
	if (socketPath.size() >= sizeof(addr.sun_path))
		throw std::invalid_argument("socket path too long (at most " +
					    std::to_string(sizeof(addr.sun_path) - 1) + " bytes): " + socketPath);
	std::memcpy(addr.sun_path, socketPath.c_str(), socketPath.size() + 1);
	::unlink(socketPath.c_str());
	if (::bind(listener.fd, reinterpret_cast<sockaddr *>(&addr), sizeof(addr)) < 0 ||
	    ::listen(listener.fd, 4) < 0)
		throw std::runtime_error("listen on " + socketPath + ": " + std::strerror(errno));
	// SIGTERM/SIGINT remove the socket: no stale one is left behind
	std::memcpy(gSocketPath, addr.sun_path, sizeof(addr.sun_path));
	std::signal(SIGTERM, removeSocketAndExit);
	std::signal(SIGINT, removeSocketAndExit);

	// One client at a time; the chip is the server's and outlives them.
	// The client's requests are served before new connections are looked
	// at, so a client that closes and reconnects is never refused.
	Socket client;
	for (;;) {
		pollfd fds[2] = { { listener.fd, POLLIN, 0 }, { client.fd, POLLIN, 0 } };
		if (::poll(fds, client.fd >= 0 ? 2 : 1, -1) < 0) {
			if (errno == EINTR)
				continue;
			throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
		}
		if (client.fd >= 0 && fds[1].revents != 0) {
			Pipe p(client.fd, client.fd);
			Served s = Served::Closed;
			try {
				s = serveOne(chip, p);
			} catch (const std::exception &ex) {
				std::fprintf(stderr, "ecmxf-sim: client dropped: %s\n", ex.what());
			}
			if (s == Served::Quit)
				break;
			if (s == Served::Closed)
				client.reset();
		}
		if (fds[0].revents & POLLIN) {
			Socket c(::accept4(listener.fd, nullptr, nullptr, SOCK_CLOEXEC));
			if (c.fd < 0) {
				if (errno == EINTR || errno == ECONNABORTED || errno == EAGAIN)
					continue;
				throw std::runtime_error(std::string("accept: ") + std::strerror(errno));
			}
			if (client.fd < 0) {
				client = std::move(c);
				continue;
			}
			Pipe p(c.fd, c.fd);
			try {
				refuse(p, 'B',
				       "busy: ecmxf-sim serves one client at a time and another one is connected");
			} catch (const std::exception &) {
				// the refused client is gone already
			}
		}
	}
	::unlink(socketPath.c_str());
	return 0;
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
