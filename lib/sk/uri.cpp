// SPDX-License-Identifier: MIT
// The ECM-SK device URIs (include/ecmxf/sk/uri.hpp).

#include <ecmxf/sk/uri.hpp>

#include <cerrno>
#include <charconv>
#include <stdexcept>
#include <vector>

#include <ecmxf/error.hpp>

namespace ecmxf::sk {

namespace {

[[noreturn]] void bad(std::string_view uri, const std::string &why)
{
	throw Error("device URI \"" + std::string(uri) + "\": " + why + "; the ECM-SK forms are " +
			    std::string(kSkUriForms),
		    EINVAL);
}

std::uint64_t num(std::string_view uri, const std::string &key, const std::string &v, std::uint64_t lo,
		  std::uint64_t hi)
{
	std::uint64_t n = 0;
	auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
	if (v.empty() || ec != std::errc() || p != v.data() + v.size() || n < lo || n > hi)
		bad(uri, key + "=" + v + " is not a number in " + std::to_string(lo) + ".." + std::to_string(hi));
	return n;
}

std::vector<std::pair<std::string, std::string>> options(std::string_view uri, std::string_view q)
{
	std::vector<std::pair<std::string, std::string>> out;
	std::size_t pos = 0;
	while (pos <= q.size()) {
		std::size_t end = q.find('&', pos);
		if (end == std::string_view::npos)
			end = q.size();
		const std::string item(q.substr(pos, end - pos));
		pos = end + 1;
		if (item.empty())
			continue;
		const auto eq = item.find('=');
		if (eq == std::string::npos || eq == 0)
			bad(uri, "option \"" + item + "\" is not key=value");
		out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
	}
	return out;
}

void hostOption(std::string_view uri, SkUri &u, const std::string &k, const std::string &v)
{
	if (k == "slot") {
		const auto s = num(uri, k, v, 12, 16);
		if (s != 12 && s != 16)
			bad(uri, "slot=" + v + ": the slot size is 12 or 16 (the board's CONFIG2)");
		u.slotSize = static_cast<unsigned>(s);
	} else if (k == "ex") {
		u.extensions = static_cast<std::uint32_t>(num(uri, k, v, 0, 3));
	} else {
		bad(uri, "unknown option \"" + k + "\"");
	}
}

} // namespace

SkUri parseSkUri(std::string_view uri)
{
	SkUri u;
	const auto colon = uri.find(':');
	if (colon == std::string_view::npos)
		bad(uri, "no scheme");
	const std::string_view scheme = uri.substr(0, colon);
	std::string_view rest = uri.substr(colon + 1);
	std::string_view query;
	if (const auto q = rest.find('?'); q != std::string_view::npos) {
		query = rest.substr(q + 1);
		rest = rest.substr(0, q);
	}
	u.path = std::string(rest);
	const auto opts = options(uri, query);

	if (scheme == "sk-sim") {
		u.kind = SkUri::Kind::Sim;
		for (const auto &[k, v] : opts) {
			try {
				u.board.set(k, v);
			} catch (const std::invalid_argument &e) {
				bad(uri, e.what());
			}
		}
		u.slotSize = u.board.slotSize;
		u.extensions = u.board.extensions;
		return u;
	}
	if (scheme == "sk-unix") {
		u.kind = SkUri::Kind::Unix;
		if (u.path.empty())
			bad(uri, "no socket path");
		for (const auto &[k, v] : opts)
			hostOption(uri, u, k, v);
		return u;
	}
	if (scheme == "sk-spidev") {
		u.kind = SkUri::Kind::Spidev;
		if (u.path.empty() || u.path[0] != '/')
			bad(uri, "the spidev node must be an absolute path (/dev/spidevB.C)");
		u.spidev.device = u.path;
		u.spidev.speedHz = kSkMaxSpeedHz;
		u.spidev.mode = 0;
		u.spidev.readyHigh = false; // Busy: low = ready
		for (const auto &[k, v] : opts) {
			if (k == "busy") {
				const auto c = v.rfind(':');
				if (c == std::string::npos || c == 0)
					bad(uri, "busy=" + v + " is not <chip>:<line>");
				u.spidev.int0 = GpioLineSpec{ v.substr(0, c),
							      static_cast<unsigned>(num(uri, "busy line", v.substr(c + 1), 0, 65535)) };
			} else if (k == "speed") {
				u.spidev.speedHz = static_cast<std::uint32_t>(num(uri, k, v, 1, kSkMaxSpeedHz));
			} else if (k == "mode") {
				u.spidev.mode = static_cast<std::uint8_t>(num(uri, k, v, 0, 3));
			} else {
				hostOption(uri, u, k, v);
			}
		}
		if (!u.spidev.int0)
			bad(uri, "busy=<chip>:<line> is required: the host may start an exchange only while Busy is low");
		return u;
	}
	bad(uri, "unknown scheme \"" + std::string(scheme) + "\"");
}

} // namespace ecmxf::sk
