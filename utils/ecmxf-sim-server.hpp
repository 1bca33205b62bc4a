// SPDX-License-Identifier: MIT
/*
 * ecmxf-sim's server, the same for every board it simulates (the ECM-XF in
 * ecmxf-sim.cpp, the ECM-SK in ecmxf-sim-sk.cpp): the byte pipe of the wire
 * protocol (Documentation/sim-wire-protocol.rst) and the loop that serves
 * standard input/output or a Unix socket, one client at a time.
 */
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace ecmxfsim {

/// A file descriptor, closed with the object.
struct Fd {
	int fd = -1;
	Fd() = default;
	explicit Fd(int f) : fd(f) {}
	Fd(Fd &&o) noexcept : fd(o.fd) { o.fd = -1; }
	Fd &operator=(Fd &&o) noexcept;
	Fd(const Fd &) = delete;
	Fd &operator=(const Fd &) = delete;
	~Fd() { reset(); }
	void reset();
};

/// Whole reads and writes on a descriptor pair; throws std::runtime_error.
class Pipe
{
public:
	Pipe(int in, int out) : in_(in), out_(out) {}
	/// Reads exactly @p n bytes; false at a clean end of input.
	bool read(void *buf, std::size_t n);
	void write(const void *buf, std::size_t n);
	void u8(std::uint8_t v) { write(&v, 1); }
	void u16(std::uint16_t v);
	void u64(std::uint64_t v);
	/// @p type ('E' error, 'B' busy), u16 length, the text.
	void message(char type, const std::string &m);

private:
	int in_, out_;
};

/// @p n little-endian bytes at @p b.
std::uint64_t le(const std::uint8_t *b, int n);

/// What one request leaves behind.
enum class Served {
	More,	// answered; the client may send another
	Closed, // the client went away (or must be dropped)
	Quit,	// 'Q': the server ends
};
using ServeOne = std::function<Served(Pipe &)>;

/// Serves standard input/output until the client ends or quits.
int serveStdio(const ServeOne &serve);
/// Serves the Unix socket @p path: one client at a time (a second one gets
/// 'B' and is closed), the board outliving them; until 'Q' or SIGTERM /
/// SIGINT, which remove the socket.
int serveSocket(const std::string &path, const ServeOne &serve);

} // namespace ecmxfsim
