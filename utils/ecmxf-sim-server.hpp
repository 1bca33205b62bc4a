// SPDX-License-Identifier: MIT
/*
 * ecmxf-sim's server, the same for every board it simulates (the ECM-XF in
 * ecmxf-sim.cpp, the ECM-SK in ecmxf-sim-sk.cpp): the byte pipe of the wire
 * protocol (Documentation/sim-wire-protocol.rst), the one loop that reads
 * its requests and answers them from a Target, and the serving of standard
 * input/output or a Unix socket, one client at a time.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

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

/// The simulated board behind the wire protocol: what differs between the
/// boards; the requests, their framing and errors are the server's.
class Target
{
public:
	virtual ~Target() = default;
	/// Why an 'X' exchange of @p n bytes is refused; empty: it is not.
	[[nodiscard]] virtual std::string badExchange(std::size_t n) const = 0;
	virtual void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) = 0;
	/// 'L': bit 0 INT0 (ECM-SK: Busy high), bit 1 INT1, bit 2 ready.
	[[nodiscard]] virtual std::uint8_t lines() const = 0;
	virtual void advance(std::chrono::nanoseconds d) = 0;
	[[nodiscard]] virtual std::chrono::nanoseconds now() const = 0;
	/// 'F': fault @p id set to @p value; why it is refused, or empty.
	virtual std::string fault(std::uint8_t id, std::uint32_t value) = 0;
};

/// What one request leaves behind.
enum class Served {
	More,	// answered; the client may send another
	Closed, // the client went away (or must be dropped)
	Quit,	// 'Q': the server ends
};
using ServeOne = std::function<Served(Pipe &)>;

/// The options of every board: -n/--network FILE, -s/--socket PATH,
/// -b/--board (read by main), -h/--help.
struct Options {
	std::string network;
	std::string socketPath;
};
/// The value of the option being read ("<what> needs a value" when none).
using OptionValue = std::function<std::string(const char *what)>;
/// A board's own option @p a: true when it took it.
using BoardOption = std::function<bool(std::string_view a, const OptionValue &value)>;
/// Parses argv: the common options, @p board's own; another is
/// std::invalid_argument "unknown option '<a>'<unknownHint>". -h/--help
/// prints @p usage to stdout: std::nullopt (the server exits 0).
std::optional<Options> parseOptions(int argc, char **argv, const BoardOption &board, const std::string &unknownHint,
				    void (*usage)(std::FILE *));

/// Reads one request from @p p and answers it from @p t (the one wire
/// loop of every board).
Served serveOne(Target &t, Pipe &p);
/// Serves @p t on standard input/output, or on the Unix socket @p path
/// when it is not empty.
int serve(Target &t, const std::string &path);

/// Serves standard input/output until the client ends or quits.
int serveStdio(const ServeOne &serve);
/// Serves the Unix socket @p path: one client at a time (a second one gets
/// 'B' and is closed), the board outliving them; until 'Q' or SIGTERM /
/// SIGINT, which remove the socket.
int serveSocket(const std::string &path, const ServeOne &serve);

} // namespace ecmxfsim
