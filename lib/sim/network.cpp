// SPDX-License-Identifier: MIT
//
// network.cpp - a bus of slave models, and its text file format:
//
//   # comment
//   name 2x EST-584 + digital I/O
//   slave EST-584 alias=1
//   slave EST-584
//   slave dio count=126
//   chip crc32-coverage=valid
//
// One "slave" line per slave (or per "count" equal slaves), in bus order;
// "chip" lines set options of the simulated chip (ChipConfig).
// Options are key=value words; values may be double-quoted. The format is
// documented in Documentation/simulator.rst.

#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/chip.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "base/text.hpp"
#if __has_include("ecmxf_network_dir.h")
#include "ecmxf_network_dir.h" // ECMXF_NETWORK_DIR: the configured prefix's networks
#endif
#include "slaves/factory.hpp"

namespace ecmxf::sim {

namespace {

constexpr std::size_t kMaxSlaves = 128; // the chip's limit

std::string lower(std::string s)
{
	std::transform(s.begin(), s.end(), s.begin(),
		       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
	return s;
}

// Split a line into words; "quoted words" keep their spaces.
std::vector<std::string> words(const std::string &line, const std::string &where)
{
	std::vector<std::string> out;
	std::string cur;
	bool quoted = false, have = false;
	for (char c : line) {
		if (c == '"') {
			quoted = !quoted;
			have = true;
		} else if (!quoted && std::isspace(static_cast<unsigned char>(c))) {
			if (have)
				out.push_back(cur);
			cur.clear();
			have = false;
		} else {
			cur += c;
			have = true;
		}
	}
	if (quoted)
		throw std::invalid_argument(where + ": unterminated quote");
	if (have)
		out.push_back(cur);
	return out;
}

const char *const kDefaultNetwork = "name 2x EST-584 + digital I/O\n"
				    "slave EST-584\n"
				    "slave EST-584\n"
				    "slave dio\n";

/// The KEY=VALUE word @p w of a line at @p where: its key lower-cased and its
/// value; "<where>: <what> '<w>' is not <form>" where it is not one.
std::pair<std::string, std::string> keyValue(const std::string &w, const std::string &where,
					     const char *what, const char *form)
{
	const auto eq = w.find('=');
	if (eq == std::string::npos || eq == 0)
		throw std::invalid_argument(where + ": " + what + " '" + w + "' is not " + form);
	return { lower(w.substr(0, eq)), w.substr(eq + 1) };
}

} // namespace

Network::Network() = default;
Network::~Network() = default;
Network::Network(Network &&) noexcept = default;
Network &Network::operator=(Network &&) noexcept = default;

std::unique_ptr<Slave> Network::makeSlave(const std::string &type, unsigned position,
					  const std::map<std::string, std::string> &options)
{
	const std::string t = lower(type);
	if (t == "est-584" || t == "est584")
		return makeEst584(position, options);
	if (t == "servo" || t == "akd2g")
		return makeServo(position, options);
	if (t == "dio" || t == "io")
		return makeDio(position, options);
	if (t == "hsp") // NEXTW HSP, for the ECM-SK (lib/sim/slaves/hsp.cpp)
		return makeHsp(position, options);
	throw std::invalid_argument("unknown slave type '" + type +
				    "' (known: EST-584, servo, dio, hsp)");
}

Network Network::fromText(const std::string &text, const std::string &origin)
{
	// what a message quotes of the file (a word, a key, a value) may be any
	// bytes: never raw to a terminal
	try {
		return parseText(text, origin);
	} catch (const std::invalid_argument &e) {
		throw std::invalid_argument(detail::printable(e.what()));
	}
}

Network Network::parseText(const std::string &text, const std::string &origin)
{
	Network net;
	std::istringstream in(text);
	std::string line;
	unsigned lineNo = 0;
	while (std::getline(in, line)) {
		lineNo++;
		const std::string where = origin + ":" + std::to_string(lineNo);
		const auto hash = line.find('#');
		if (hash != std::string::npos)
			line.erase(hash);
		const auto w = words(line, where);
		if (w.empty())
			continue;
		const std::string kw = lower(w[0]);
		if (kw == "name") {
			std::string name;
			for (std::size_t i = 1; i < w.size(); i++)
				name += (i > 1 ? " " : "") + w[i];
			net.setName(name);
			continue;
		}
		if (kw == "chip") {
			if (w.size() < 2)
				throw std::invalid_argument(where + ": 'chip' needs KEY=VALUE options (" +
							    std::string(kChipOptions) + ")");
			for (std::size_t i = 1; i < w.size(); i++) {
				const auto [key, value] = keyValue(w[i], where, "chip option", "KEY=VALUE");
				for (const auto &kv : net.chipOptions())
					if (kv.first == key)
						throw std::invalid_argument(where + ": chip option '" + key +
									    "' given twice");
				try {
					net.setChipOption(key, value);
				} catch (const std::invalid_argument &e) {
					throw std::invalid_argument(where + ": " + e.what());
				}
			}
			continue;
		}
		if (kw != "slave")
			throw std::invalid_argument(where + ": unknown keyword '" + w[0] +
						    "' (expected 'slave', 'chip' or 'name')");
		if (w.size() < 2)
			throw std::invalid_argument(where + ": 'slave' needs a type");
		std::map<std::string, std::string> opts;
		unsigned long count = 1;
		for (std::size_t i = 2; i < w.size(); i++) {
			const auto [key, value] = keyValue(w[i], where, "option", "key=value");
			if (key == "count") {
				std::size_t used = 0;
				try {
					count = std::stoul(value, &used, 0);
				} catch (const std::exception &) {
					used = 0;
				}
				if (used != value.size() || count == 0 || count > kMaxSlaves)
					throw std::invalid_argument(where + ": count '" + value +
								    "' is not 1.." +
								    std::to_string(kMaxSlaves));
				continue;
			}
			if (!opts.emplace(key, value).second)
				throw std::invalid_argument(where + ": option '" + key +
							    "' given twice");
		}
		for (unsigned long n = 0; n < count; n++) {
			if (net.size() >= kMaxSlaves)
				throw std::invalid_argument(where + ": more than " +
							    std::to_string(kMaxSlaves) +
							    " slaves (the chip's limit)");
			try {
				net.add(makeSlave(w[1], static_cast<unsigned>(net.size()), opts));
			} catch (const std::invalid_argument &e) {
				throw std::invalid_argument(where + ": " + e.what());
			}
		}
	}
	if (net.name().empty())
		net.setName(origin);
	return net;
}

std::string Network::findFile(const std::string &name)
{
	std::error_code ec;
	if (name.empty() || name.find('/') != std::string::npos || std::filesystem::exists(name, ec))
		return name;
	std::vector<std::string> dirs;
	if (const char *p = std::getenv("ECMXF_NETWORK_PATH")) {
		std::string_view rest = p;
		while (!rest.empty()) {
			const auto colon = rest.find(':');
			const std::string_view d = rest.substr(0, colon);
			if (!d.empty())
				dirs.emplace_back(d);
			rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
		}
	}
	// relocatable: the prefix the program runs from (bin/../share), then
	// the one the library was configured for
	const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
	if (!ec)
		dirs.push_back((exe.parent_path().parent_path() / "share/ecmxf/networks").string());
#ifdef ECMXF_NETWORK_DIR
	dirs.emplace_back(ECMXF_NETWORK_DIR);
#endif
	std::string looked;
	for (const std::string &d : dirs) {
		for (const std::string &file : { name, name + ".net" }) {
			const std::filesystem::path f = std::filesystem::path(d) / file;
			if (std::filesystem::is_regular_file(f, ec))
				return f.string();
		}
		if (looked.find(d) == std::string::npos)
			looked += (looked.empty() ? "" : ", ") + d;
	}
	throw std::runtime_error("cannot open network file '" + name + "': not in the working directory, nor in " +
				 looked + " (the installed networks; ECMXF_NETWORK_PATH adds directories)");
}

Network Network::fromFile(const std::string &given)
{
	const std::string path = findFile(given);
	// a directory opens as an ifstream on Linux and reads as nothing
	std::error_code ec;
	if (std::filesystem::is_directory(path, ec))
		throw std::runtime_error("network file '" + path + "' is a directory");
	std::ifstream f(path);
	if (!f)
		throw std::runtime_error("cannot open network file '" + path + "'");
	std::ostringstream ss;
	ss << f.rdbuf();
	Network net = fromText(ss.str(), path);
	// the chip's ECAT_INIT_OP fails on an empty bus with no word why
	if (net.size() == 0)
		throw std::runtime_error("network file '" + path + "': the network has no slaves (no 'slave' line)");
	return net;
}

Network Network::defaultNetwork()
{
	return fromText(kDefaultNetwork, "default network");
}

std::size_t Network::size() const
{
	return slaves_.size();
}

Slave &Network::at(std::size_t position)
{
	return *slaves_.at(position);
}

const Slave &Network::at(std::size_t position) const
{
	return *slaves_.at(position);
}

void Network::add(std::unique_ptr<Slave> slave)
{
	if (!slave)
		throw std::invalid_argument("Network::add: null slave");
	if (slaves_.size() >= kMaxSlaves)
		throw std::invalid_argument("Network::add: more than 128 slaves");
	slaves_.push_back(std::move(slave));
}

void Network::setChipOption(const std::string &key, const std::string &value)
{
	ChipConfig check;
	applyChipOption(check, key, value); // throws for a bad key or value
	for (auto &kv : chipOptions_) {
		if (kv.first == key) {
			kv.second = value;
			return;
		}
	}
	chipOptions_.emplace_back(key, value);
}

const std::string &Network::name() const
{
	return name_;
}

void Network::setName(std::string name)
{
	name_ = std::move(name);
}

} // namespace ecmxf::sim
