// SPDX-License-Identifier: MIT
/*
 * ecmxf-util decode - a packet trace (Documentation/trace.rst) as a
 * readable protocol log, or as JSON.
 */
#include "ecmxf-util.hpp"

#include <ecmxf/error.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <ecmxf/trace/trace.hpp>

namespace ecmxf_util {

const char *const kDecodeHelp =
	"Usage: ecmxf-util [global options] decode TRACEFILE [--json | --pcapng OUT]\n"
	"\n"
	"Decode a packet trace written with the global option --trace FILE (or the\n"
	"device URI option trace=FILE) like a protocol analyzer: per packet the time,\n"
	"the direction, the header fields by name, the data bytes and the check word\n"
	"verdict (OK, BAD with expected and received value, NOT READY); each answer\n"
	"is paired with the command it answers. Needs no device. TRACEFILE '-' reads\n"
	"standard input.\n"
	"\n"
	"Options:\n"
	"  --json      a JSON array of packet objects instead of the log\n"
	"  --pcapng OUT  convert the trace to the pcapng file OUT (for Wireshark\n"
	"              with ecmxf.lua, Documentation/trace.rst); OUT appears only\n"
	"              when the whole trace converted\n"
	"  -h, --help  show this help\n";

int cmdDecode(Globals &g, const Args &args)
{
	std::string file;
	std::string pcapng;
	bool haveFile = false;
	for (std::size_t i = 0; i < args.size(); i++) {
		const std::string_view a = args[i];
		if (a == "-h" || a == "--help") {
			std::fputs(kDecodeHelp, stdout);
			return 0;
		}
		if (a == "--json") {
			g.json = true;
		} else if (a == "--pcapng") {
			if (i + 1 >= args.size() || args[i + 1].empty())
				throw UsageError("decode: option '--pcapng' needs an output file name");
			pcapng = std::string(args[++i]);
		} else if (a.size() > 1 && a.starts_with("-")) {
			throw UsageError("decode: unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util decode --help')");
		} else if (haveFile) {
			throw UsageError("decode: one trace file only ('" + file + "' and '" + std::string(a) + "')");
		} else {
			file = std::string(a);
			haveFile = true;
		}
	}
	if (!haveFile)
		throw UsageError("decode: which trace file? (ecmxf-util decode TRACEFILE)");
	if (!pcapng.empty() && g.json)
		throw UsageError("decode: --json and --pcapng exclude each other");

	ecmxf::TraceDecodeOptions o;
	o.json = g.json;
	std::ifstream f;
	std::istream *in = &std::cin;
	if (file != "-") {
		std::error_code ec;
		if (std::filesystem::is_directory(file, ec))
			throw ecmxf::Error("decode: \"" + file + "\" is a directory, not a trace file", EISDIR);
		f.open(file);
		if (!f)
			throw std::runtime_error("cannot open the trace file \"" + file + "\": " + std::strerror(errno));
		in = &f;
	}
	if (!pcapng.empty()) {
		const ecmxf::TraceSummary s = ecmxf::traceToPcapng(*in, pcapng);
		std::cerr << "decode: " << s.packets << " packets (" << s.commands << " to the chip, " << s.responses
			  << " from it) written to " << pcapng << '\n';
		return 0;
	}
	// decoded in full before anything is printed: a bad line gives an
	// error, not half a log
	std::ostringstream out;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(*in, out, o);
	std::cout << out.str();
	if (!g.json)
		std::cout << s.packets << " packets: " << s.commands << " commands, " << s.responses << " responses, "
			  << s.bad << " bad (" << s.notReady << " not ready)"
			  << (s.skFrames ? ", " + std::to_string(s.skFrames) + " of them ECM-SK frames" : std::string())
			  << '\n';
	std::cout.flush();
	return 0;
}

} // namespace ecmxf_util
