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
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sk/sim_board.hpp>
#include <ecmxf/sk/sim_channel.hpp>

#include "ecmxf-sim-sk.hpp"

namespace {

struct Fd {
	int fd = -1;
	explicit Fd(int f = -1) : fd(f) {}
	Fd(const Fd &) = delete;
	Fd &operator=(const Fd &) = delete;
	~Fd() { reset(); }
	void reset(int f = -1)
	{
		if (fd >= 0)
			::close(fd);
		fd = f;
	}
};

class Stream
{
public:
	Stream(int in, int out) : in_(in), out_(out) {}
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
	void u8(std::uint8_t v) { write(&v, 1); }
	void u16(std::uint16_t v)
	{
		const std::uint8_t b[2] = { static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8) };
		write(b, 2);
	}
	void u64(std::uint64_t v)
	{
		std::uint8_t b[8];
		for (int i = 0; i < 8; i++)
			b[i] = static_cast<std::uint8_t>(v >> (8 * i));
		write(b, 8);
	}
	void message(char type, const std::string &m)
	{
		u8(static_cast<std::uint8_t>(type));
		u16(static_cast<std::uint16_t>(m.size()));
		write(m.data(), m.size());
	}

private:
	int in_, out_;
};

std::uint64_t le(const std::uint8_t *b, int n)
{
	std::uint64_t v = 0;
	for (int i = n - 1; i >= 0; i--)
		v = (v << 8) | b[i];
	return v;
}

enum class Served { More, Closed, Quit };

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

char gPath[sizeof(sockaddr_un::sun_path)];

extern "C" void removeAndExit(int)
{
	::unlink(gPath);
	::_exit(0);
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
	if (socketPath.empty()) {
		Stream s(STDIN_FILENO, STDOUT_FILENO);
		while (serveOne(board, s) == Served::More) {
		}
		return 0;
	}
	Fd listener(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
	if (listener.fd < 0)
		throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
	sockaddr_un addr{};
	addr.sun_family = AF_UNIX;
	if (socketPath.size() >= sizeof(addr.sun_path))
		throw std::invalid_argument("socket path too long: " + socketPath);
	std::memcpy(addr.sun_path, socketPath.c_str(), socketPath.size() + 1);
	::unlink(socketPath.c_str());
	if (::bind(listener.fd, reinterpret_cast<sockaddr *>(&addr), sizeof(addr)) < 0 ||
	    ::listen(listener.fd, 4) < 0)
		throw std::runtime_error("listen on " + socketPath + ": " + std::strerror(errno));
	std::memcpy(gPath, addr.sun_path, sizeof(addr.sun_path));
	std::signal(SIGTERM, removeAndExit);
	std::signal(SIGINT, removeAndExit);
	Fd client;
	for (;;) {
		pollfd fds[2] = { { listener.fd, POLLIN, 0 }, { client.fd, POLLIN, 0 } };
		if (::poll(fds, client.fd >= 0 ? 2 : 1, -1) < 0) {
			if (errno == EINTR)
				continue;
			throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
		}
		if (client.fd >= 0 && fds[1].revents) {
			Stream s(client.fd, client.fd);
			Served r = Served::Closed;
			try {
				r = serveOne(board, s);
			} catch (const std::exception &e) {
				std::fprintf(stderr, "ecmxf-sim: client dropped: %s\n", e.what());
			}
			if (r == Served::Quit)
				break;
			if (r == Served::Closed)
				client.reset();
		}
		if (fds[0].revents & POLLIN) {
			const int c = ::accept4(listener.fd, nullptr, nullptr, SOCK_CLOEXEC);
			if (c < 0)
				continue;
			if (client.fd < 0) {
				client.reset(c);
				continue;
			}
			Fd other(c);
			Stream s(c, c);
			try {
				s.message('B', "busy: ecmxf-sim serves one client at a time and another one is connected");
			} catch (const std::exception &) {
			}
		}
	}
	::unlink(socketPath.c_str());
	return 0;
}
