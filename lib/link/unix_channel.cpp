// SPDX-License-Identifier: MIT
// UnixChannel: an ecmxf-sim server over its Unix stream socket
// (include/ecmxf/link/unix_channel.hpp, Documentation/sim-wire-protocol.rst).

#include <ecmxf/error.hpp>
#include <ecmxf/link/unix_channel.hpp>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "base/text.hpp"
#include "base/os.hpp"

namespace ecmxf {

namespace {

std::uint64_t le(std::span<const std::uint8_t> b) noexcept
{
	std::uint64_t v = 0;
	for (std::size_t i = b.size(); i-- > 0;)
		v = (v << 8) | b[i];
	return v;
}

/// @p bytes as text for a message: printable ASCII as is, the rest as
/// \xNN, in double quotes; at most 32 bytes, then "...".
std::string shown(std::span<const std::uint8_t> bytes)
{
	static constexpr char kHex[] = "0123456789abcdef";
	std::string s;
	for (std::size_t i = 0; i < bytes.size() && i < 32; i++) {
		const std::uint8_t c = bytes[i];
		if (c >= 0x20 && c < 0x7F && c != '\\' && c != '"') {
			s.push_back(static_cast<char>(c));
		} else {
			s.append("\\x");
			s.push_back(kHex[c >> 4]);
			s.push_back(kHex[c & 15]);
		}
	}
	if (bytes.size() > 32)
		s.append("...");
	return detail::quoted(s);
}

/// "'X'" for a request or reply type.
std::string typeName(char t)
{
	return std::string{ '\'', t, '\'' };
}

} // namespace

SimReply parseSimReply(std::span<const std::uint8_t> bytes) noexcept
{
	SimReply r;
	if (bytes.empty())
		return r; // NeedMore, size 1
	r.type = static_cast<char>(bytes[0]);

	// fixed part after the type byte; kVariable: u16 length + payload
	constexpr std::size_t kVariable = SIZE_MAX;
	std::size_t fixed = 0;
	switch (r.type) {
	case 'L':
	case 'F':
		fixed = 1;
		break;
	case 'A':
	case 'T':
		fixed = 8;
		break;
	case 'Q':
		fixed = 0;
		break;
	case 'H':
		fixed = UnixChannel::kHelloMagic.size() + 2;
		break;
	case 'X':
	case 'E':
	case 'B':
		fixed = kVariable;
		break;
	default:
		r.status = SimReply::Status::Malformed;
		r.size = 1;
		return r;
	}

	if (fixed == kVariable) {
		if (bytes.size() < 3) {
			r.size = 3;
			return r;
		}
		const std::size_t n = static_cast<std::size_t>(le(bytes.subspan(1, 2)));
		r.size = 3 + n;
		if (bytes.size() < r.size)
			return r;
		r.value = n;
		r.payload = bytes.subspan(3, n);
	} else {
		r.size = 1 + fixed;
		if (bytes.size() < r.size)
			return r;
		if (r.type == 'H') {
			r.payload = bytes.subspan(1, UnixChannel::kHelloMagic.size());
			r.value = le(bytes.subspan(1 + UnixChannel::kHelloMagic.size(), 2));
		} else {
			r.value = le(bytes.subspan(1, fixed));
		}
	}
	r.status = SimReply::Status::Complete;
	return r;
}

class UnixChannel::Impl
{
public:
	explicit Impl(const std::string &path) : path_(path), name_("unix:" + path) {}

	void connect();
	void hello();

	/// Sends the request @p type + @p args, reads the reply and checks
	/// it is of @p type (an 'E' reply throws with the server's message).
	SimReply request(char type, std::span<const std::uint8_t> args = {});

	[[noreturn]] void fail(const std::string &what, int err) const
	{
		throw Error(name_ + ": " + what, err);
	}

	std::string path_;
	std::string name_;
	detail::FileDescriptor fd_;
	std::vector<std::uint8_t> out_;
	std::vector<std::uint8_t> in_;
	bool inHello_ = false;

private:
	void sendAll(char type);
	SimReply readReply(char type);
	/// After a reply that is not one: what else the peer sent at once.
	void drainForMessage();
};

void UnixChannel::Impl::connect()
{
	sockaddr_un addr{};
	addr.sun_family = AF_UNIX;
	if (path_.empty())
		fail("no socket path (unix:PATH names an ecmxf-sim --socket PATH server)", EINVAL);
	if (path_.size() >= sizeof(addr.sun_path))
		fail("socket path is " + std::to_string(path_.size()) + " bytes long; a Unix socket address holds at most " +
			     std::to_string(sizeof(addr.sun_path) - 1),
		     ENAMETOOLONG);
	std::memcpy(addr.sun_path, path_.c_str(), path_.size() + 1);

	fd_.reset(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
	if (!fd_.valid())
		detail::throwErrno(name_ + ": socket", errno);
	if (::connect(fd_.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof(addr)) == 0)
		return;
	const int err = errno;
	struct stat st {};
	if (::stat(path_.c_str(), &st) == 0 && !S_ISSOCK(st.st_mode))
		fail(std::string("not a socket (") + (S_ISDIR(st.st_mode) ? "a directory" : "not a Unix socket") +
			     "; unix:PATH names an ecmxf-sim --socket PATH server)",
		     ENOTSOCK);
	if (err == ENOENT || err == ECONNREFUSED)
		detail::throwErrno(name_ + ": no ecmxf-sim listening there (start one with `ecmxf-sim --socket " +
					   path_ + "`)",
				   err);
	detail::throwErrno(name_ + ": cannot connect", err);
}

void UnixChannel::Impl::hello()
{
	// the hello has a time limit: a peer that is not ecmxf-sim may never
	// answer it
	timeval tv{};
	tv.tv_sec = static_cast<time_t>(kHelloTimeout.count());
	if (::setsockopt(fd_.get(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv)) < 0)
		detail::throwErrno(name_ + ": setsockopt(SO_RCVTIMEO)", errno);
	inHello_ = true;
	const SimReply r = request('H');
	const auto magic = UnixChannel::kHelloMagic;
	if (!std::equal(r.payload.begin(), r.payload.end(), magic.begin(), magic.end())) {
		in_.resize(r.size);
		drainForMessage();
		fail("not an ecmxf-sim server: its answer to the hello was " +
			     shown(in_),
		     EPROTO);
	}
	if (r.value != UnixChannel::kProtocolVersion)
		fail("ecmxf-sim speaks wire protocol version " + std::to_string(r.value) + ", this library version " +
			     std::to_string(UnixChannel::kProtocolVersion),
		     EPROTO);
	inHello_ = false;
	tv = {};
	if (::setsockopt(fd_.get(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv)) < 0)
		detail::throwErrno(name_ + ": setsockopt(SO_RCVTIMEO)", errno);
}

SimReply UnixChannel::Impl::request(char type, std::span<const std::uint8_t> args)
{
	out_.assign(1, static_cast<std::uint8_t>(type));
	out_.insert(out_.end(), args.begin(), args.end());
	sendAll(type);
	return readReply(type);
}

void UnixChannel::Impl::sendAll(char type)
{
	std::size_t done = 0;
	while (done < out_.size()) {
		const ssize_t n = ::send(fd_.get(), out_.data() + done, out_.size() - done, MSG_NOSIGNAL);
		if (n < 0) {
			if (errno == EINTR)
				continue;
			// the server may have refused us and closed: its reason
			// is still to be read
			if ((errno == EPIPE || errno == ECONNRESET) && done == 0)
				break;
			detail::throwErrno(name_ + ": sending the " + typeName(type) + " request", errno);
		}
		done += static_cast<std::size_t>(n);
	}
}

SimReply UnixChannel::Impl::readReply(char type)
{
	in_.clear();
	for (;;) {
		const SimReply r = parseSimReply(in_);
		if (r.status == SimReply::Status::Malformed) {
			drainForMessage();
			if (inHello_)
				fail("not an ecmxf-sim server: its answer to the hello was " + shown(in_), EPROTO);
			fail("ecmxf-sim answered the " + typeName(type) + " request with " + shown(in_) +
				     ", which is no reply of the wire protocol",
			     EPROTO);
		}
		if (r.status == SimReply::Status::Complete) {
			const std::string msg(r.payload.begin(), r.payload.end());
			if (r.type == 'B')
				fail("ecmxf-sim refused the connection: " + msg, EBUSY);
			if (r.type == 'E') {
				if (inHello_)
					fail("the peer answered the hello with an error (an ecmxf-sim of an older "
					     "wire protocol, without 'H'?): " +
						     msg,
					     EPROTO);
				fail("ecmxf-sim refused the " + typeName(type) + " request: " + msg, EPROTO);
			}
			if (r.type != type) {
				if (inHello_)
					fail("not an ecmxf-sim server: its answer to the hello was " + shown(in_),
					     EPROTO);
				fail("ecmxf-sim answered the " + typeName(type) + " request with a " +
					     typeName(r.type) + " reply",
				     EPROTO);
			}
			return r;
		}
		const std::size_t have = in_.size();
		in_.resize(r.size);
		const ssize_t n = ::recv(fd_.get(), in_.data() + have, r.size - have, 0);
		if (n > 0) {
			in_.resize(have + static_cast<std::size_t>(n));
			continue;
		}
		const int err = errno;
		in_.resize(have);
		if (n < 0 && err == EINTR)
			continue;
		if (n < 0 && (err == EAGAIN || err == EWOULDBLOCK) && inHello_)
			fail("no answer to the hello within " + std::to_string(kHelloTimeout.count()) + " s" +
				     (have ? " (got " + shown(in_) + ")" : std::string()) +
				     ": not an ecmxf-sim server?",
			     ETIMEDOUT);
		if (n < 0 && err != ECONNRESET)
			detail::throwErrno(name_ + ": reading the reply to the " + typeName(type) + " request", err);
		if (inHello_)
			fail("the peer closed the connection " +
				     (have ? "after " + shown(in_) : std::string("without answering")) +
				     " the hello: not an ecmxf-sim server?",
			     EPROTO);
		fail("ecmxf-sim closed the connection in the middle of the " + typeName(type) + " request" +
			     (have ? " (after " + std::to_string(have) + " bytes of its reply)" : std::string()),
		     ECONNRESET);
	}
}

void UnixChannel::Impl::drainForMessage()
{
	std::array<std::uint8_t, 32> more{};
	const ssize_t n = ::recv(fd_.get(), more.data(), more.size(), MSG_DONTWAIT);
	if (n > 0)
		in_.insert(in_.end(), more.begin(), more.begin() + n);
}

UnixChannel::UnixChannel(const std::string &path) : impl_(std::make_unique<Impl>(path))
{
	impl_->connect();
	impl_->hello();
}

UnixChannel::~UnixChannel() = default;

std::string UnixChannel::name() const
{
	return impl_->name_;
}

void UnixChannel::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	if (mosi.size() != miso.size() || mosi.size() > 0xFFFF)
		impl_->fail("exchange of " + std::to_string(mosi.size()) + " bytes out, " +
				    std::to_string(miso.size()) + " in",
			    EINVAL);
	std::vector<std::uint8_t> args(2 + mosi.size());
	args[0] = static_cast<std::uint8_t>(mosi.size());
	args[1] = static_cast<std::uint8_t>(mosi.size() >> 8);
	std::copy(mosi.begin(), mosi.end(), args.begin() + 2);
	const SimReply r = impl_->request('X', args);
	if (r.payload.size() != miso.size())
		impl_->fail("ecmxf-sim answered an exchange of " + std::to_string(mosi.size()) + " bytes with " +
				    std::to_string(r.payload.size()),
			    EPROTO);
	std::copy(r.payload.begin(), r.payload.end(), miso.begin());
}

namespace {

std::array<std::uint8_t, 8> u64le(std::uint64_t v) noexcept
{
	std::array<std::uint8_t, 8> b{};
	for (std::size_t i = 0; i < b.size(); i++)
		b[i] = static_cast<std::uint8_t>(v >> (8 * i));
	return b;
}

constexpr std::uint8_t kLineReady = 4;

} // namespace

bool UnixChannel::waitReady(std::chrono::nanoseconds timeout)
{
	using std::chrono::nanoseconds;
	nanoseconds t = now();
	const nanoseconds end = t + std::max(timeout, nanoseconds::zero());

	for (;;) {
		if (impl_->request('L').value & kLineReady)
			return true;
		if (t >= end)
			return false;
		const auto step = std::min(readyStep(), end - t);
		t = nanoseconds(static_cast<std::int64_t>(
			impl_->request('A', u64le(static_cast<std::uint64_t>(step.count()))).value));
	}
}

std::chrono::nanoseconds UnixChannel::now() const
{
	return std::chrono::nanoseconds(static_cast<std::int64_t>(impl_->request('T').value));
}

void UnixChannel::sleepFor(std::chrono::nanoseconds duration)
{
	// the server refuses more than an hour per request
	constexpr std::chrono::nanoseconds kMaxStep = std::chrono::minutes(60);
	while (duration > std::chrono::nanoseconds::zero()) {
		const auto step = std::min(duration, kMaxStep);
		(void)impl_->request('A', u64le(static_cast<std::uint64_t>(step.count())));
		duration -= step;
	}
}

} // namespace ecmxf
