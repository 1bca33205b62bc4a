// SPDX-License-Identifier: MIT
// ecmxf-sim's server for every board (ecmxf-sim-server.hpp).

#include "ecmxf-sim-server.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <vector>

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <ecmxf/link/unix_channel.hpp>

namespace ecmxfsim {

Fd &Fd::operator=(Fd &&o) noexcept
{
	if (this != &o) {
		reset();
		fd = o.fd;
		o.fd = -1;
	}
	return *this;
}

void Fd::reset()
{
	if (fd >= 0)
		::close(fd);
	fd = -1;
}

bool Pipe::read(void *buf, std::size_t n)
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

void Pipe::write(const void *buf, std::size_t n)
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

void Pipe::u16(std::uint16_t v)
{
	const std::uint8_t b[2] = { static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8) };
	write(b, 2);
}

void Pipe::u64(std::uint64_t v)
{
	std::uint8_t b[8];
	for (int i = 0; i < 8; i++)
		b[i] = static_cast<std::uint8_t>(v >> (8 * i));
	write(b, 8);
}

void Pipe::message(char type, const std::string &m)
{
	u8(static_cast<std::uint8_t>(type));
	u16(static_cast<std::uint16_t>(m.size()));
	write(m.data(), m.size());
}

std::uint64_t le(const std::uint8_t *b, int n)
{
	std::uint64_t v = 0;
	for (int i = n - 1; i >= 0; i--)
		v = (v << 8) | b[i];
	return v;
}

Served serveOne(Target &t, Pipe &p)
{
	std::uint8_t type = 0;
	if (!p.read(&type, 1))
		return Served::Closed;
	switch (type) {
	case 'X': {
		std::uint8_t h[2];
		if (!p.read(h, 2))
			return Served::Closed;
		const auto n = static_cast<std::size_t>(le(h, 2));
		std::vector<std::uint8_t> mosi(n), miso(n, 0);
		if (!p.read(mosi.data(), n))
			return Served::Closed;
		if (const std::string why = t.badExchange(n); !why.empty()) {
			p.message('E', "exchange of " + std::to_string(n) + " bytes: " + why);
			break;
		}
		t.exchange(mosi, miso);
		p.u8('X');
		p.u16(static_cast<std::uint16_t>(n));
		p.write(miso.data(), n);
		break;
	}
	case 'L':
		p.u8('L');
		p.u8(t.lines());
		break;
	case 'A': {
		std::uint8_t v[8];
		if (!p.read(v, 8))
			return Served::Closed;
		const std::uint64_t ns = le(v, 8);
		if (ns > 3'600'000'000'000ULL) {
			p.message('E', "advance of more than one hour refused");
			break;
		}
		t.advance(std::chrono::nanoseconds(static_cast<std::int64_t>(ns)));
		p.u8('A');
		p.u64(static_cast<std::uint64_t>(t.now().count()));
		break;
	}
	case 'T':
		p.u8('T');
		p.u64(static_cast<std::uint64_t>(t.now().count()));
		break;
	case 'F': {
		std::uint8_t v[5];
		if (!p.read(v, 5))
			return Served::Closed;
		if (const std::string why = t.fault(v[0], static_cast<std::uint32_t>(le(v + 1, 4))); !why.empty()) {
			p.message('E', why);
			break;
		}
		p.u8('F');
		p.u8(0);
		break;
	}
	case 'H': {
		const auto magic = ecmxf::UnixChannel::kHelloMagic;
		p.u8('H');
		p.write(magic.data(), magic.size());
		p.u16(ecmxf::UnixChannel::kProtocolVersion);
		break;
	}
	case 'Q':
		p.u8('Q');
		return Served::Quit;
	default: {
		char hex[8];
		std::snprintf(hex, sizeof(hex), "0x%02x", type);
		p.message('E', std::string("unknown request type ") + hex);
		return Served::Closed; // the stream is out of step: drop it
	}
	}
	return Served::More;
}

std::optional<Options> parseOptions(int argc, char **argv, const BoardOption &board, const std::string &unknownHint,
				    void (*usage)(std::FILE *))
{
	Options o;
	for (int i = 1; i < argc; i++) {
		const std::string_view a = argv[i];
		const OptionValue value = [&](const char *what) -> std::string {
			if (i + 1 >= argc)
				throw std::invalid_argument(std::string(what) + " needs a value");
			return argv[++i];
		};
		if (a == "-h" || a == "--help") {
			usage(stdout);
			return std::nullopt;
		} else if (a == "-n" || a == "--network") {
			o.network = value("--network");
		} else if (a == "-s" || a == "--socket") {
			o.socketPath = value("--socket");
		} else if (a == "-b" || a == "--board") {
			(void)value("--board"); // which board: main's ecmxfSimWantsSk()
		} else if (!board(a, value)) {
			throw std::invalid_argument("unknown option '" + std::string(a) + "'" + unknownHint);
		}
	}
	return o;
}

int serve(Target &t, const std::string &path)
{
	const ServeOne one = [&t](Pipe &p) { return serveOne(t, p); };
	return path.empty() ? serveStdio(one) : serveSocket(path, one);
}

int serveStdio(const ServeOne &serve)
{
	Pipe p(STDIN_FILENO, STDOUT_FILENO);
	while (serve(p) == Served::More) {
	}
	return 0;
}

namespace {

// The socket being served, for removeSocketAndExit().
char gSocketPath[sizeof(sockaddr_un::sun_path)];

extern "C" void removeSocketAndExit(int)
{
	::unlink(gSocketPath); // async-signal-safe, as _exit()
	::_exit(0);
}

} // namespace

int serveSocket(const std::string &path, const ServeOne &serve)
{
	const Fd listener(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
	if (listener.fd < 0)
		throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
	sockaddr_un addr{};
	addr.sun_family = AF_UNIX;
	if (path.size() >= sizeof(addr.sun_path))
		throw std::invalid_argument("socket path too long (at most " +
					    std::to_string(sizeof(addr.sun_path) - 1) + " bytes): " + path);
	std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
	::unlink(path.c_str());
	if (::bind(listener.fd, reinterpret_cast<sockaddr *>(&addr), sizeof(addr)) < 0 ||
	    ::listen(listener.fd, 4) < 0)
		throw std::runtime_error("listen on " + path + ": " + std::strerror(errno));
	// SIGTERM/SIGINT remove the socket: no stale one is left behind
	std::memcpy(gSocketPath, addr.sun_path, sizeof(addr.sun_path));
	std::signal(SIGTERM, removeSocketAndExit);
	std::signal(SIGINT, removeSocketAndExit);

	// One client at a time; the board is the server's and outlives them.
	// The client's requests are served before new connections are looked
	// at, so a client that closes and reconnects is never refused.
	Fd client;
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
				s = serve(p);
			} catch (const std::exception &ex) {
				std::fprintf(stderr, "ecmxf-sim: client dropped: %s\n", ex.what());
			}
			if (s == Served::Quit)
				break;
			if (s == Served::Closed)
				client.reset();
		}
		if (fds[0].revents & POLLIN) {
			Fd c(::accept4(listener.fd, nullptr, nullptr, SOCK_CLOEXEC));
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
				p.message('B', "busy: ecmxf-sim serves one client at a time and another one is connected");
			} catch (const std::exception &) {
				// the refused client is gone already
			}
		}
	}
	::unlink(path.c_str());
	return 0;
}

} // namespace ecmxfsim
