// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - command-line tool for the ECM-XF.
 *
 * This first version knows the protocol's static parts; the commands that
 * talk to a chip (slaves, upload, download, states, cia402, monitor...)
 * arrive with the library and the simulator.
 */
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>

#include <ecmxf/protocol.hpp>

namespace {

void usage(std::FILE *out)
{
	std::fprintf(out,
		     "Usage: ecmxf-util [-h] [-V] COMMAND [ARGS]\n"
		     "\n"
		     "Commands:\n"
		     "  commands [--json]   list the ECM-XF command codes (ver. 038 and 050)\n"
		     "  version             print the version\n"
		     "\n"
		     "Options:\n"
		     "  -h, --help          show this help\n"
		     "  -V, --version       print the version\n");
}

std::string partnerName(const ecmxf::CommandInfo &ci)
{
	if (!ci.partner)
		return "-";
	auto p = ecmxf::commandInfo(*ci.partner);
	return p ? std::string(p->name) : std::to_string(*ci.partner);
}

int cmdCommands(bool json)
{
	const std::size_t n = ecmxf::commandCount();

	if (json) {
		std::printf("[");
		for (std::size_t i = 0; i < n; i++) {
			const auto ci = ecmxf::commandAt(i);
			std::printf("%s\n  {\"code\": %u, \"name\": \"%.*s\", \"async\": %s, "
				    "\"v038\": %s, \"v050\": %s, \"partner\": %s, \"timeout_ms\": %u}",
				    i ? "," : "", ci.code, static_cast<int>(ci.name.size()),
				    ci.name.data(), ci.async ? "true" : "false",
				    ci.inV038 ? "true" : "false", ci.inV050 ? "true" : "false",
				    ci.partner ? std::to_string(*ci.partner).c_str() : "null",
				    ci.timeoutMs);
		}
		std::printf("\n]\n");
		return 0;
	}
	std::printf("%-4s  %-28s %-6s %-8s %-26s %s\n", "CODE", "NAME", "KIND", "MANUALS",
		    "RESULT / READ-BACK", "TIMEOUT");
	for (std::size_t i = 0; i < n; i++) {
		const auto ci = ecmxf::commandAt(i);
		std::string kind = ci.async ? (ci.asyncOnlyParam0 ? "async*" : "async") : "immed";
		std::string manuals = std::string(ci.inV038 ? "038" : "") +
				      (ci.inV038 && ci.inV050 ? "+" : "") + (ci.inV050 ? "050" : "");
		std::printf("%4u  %-28.*s %-6s %-8s %-26s %u ms\n", ci.code,
			    static_cast<int>(ci.name.size()), ci.name.data(), kind.c_str(),
			    manuals.c_str(), partnerName(ci).c_str(), ci.timeoutMs);
	}
	std::printf("\n%zu commands; async* = async only with command parameter 0\n", n);
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return 2;
	}
	const std::string_view cmd = argv[1];
	if (cmd == "-h" || cmd == "--help" || cmd == "help") {
		usage(stdout);
		return 0;
	}
	if (cmd == "-V" || cmd == "--version" || cmd == "version") {
		std::printf("ecmxf-util %.*s\n", static_cast<int>(ecmxf::version().size()),
			    ecmxf::version().data());
		return 0;
	}
	if (std::string_view("commands").starts_with(cmd)) {
		bool json = false;
		for (int i = 2; i < argc; i++) {
			if (std::strcmp(argv[i], "--json") == 0) {
				json = true;
			} else {
				std::fprintf(stderr, "ecmxf-util commands: unknown argument '%s'\n",
					     argv[i]);
				return 2;
			}
		}
		return cmdCommands(json);
	}
	std::fprintf(stderr, "ecmxf-util: unknown command '%s' (try --help)\n", argv[1]);
	return 2;
}
