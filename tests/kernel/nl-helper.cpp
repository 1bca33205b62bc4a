// SPDX-License-Identifier: MIT
// ecmxf-nl-helper: the parts of the netlink guest step
// (tests/kernel/steps/check/70-netlink.sh) that need the device node:
//
//   ecmxf-nl-helper op [/dev/ecmxfN]        ECAT_INIT_OP, then PRE-OP,
//                                           SAFE-OP, OP for all slaves
//   ecmxf-nl-helper refused [/dev/ecmxfN]   slave 0 to INIT, then straight
//                                           to OP: the slave refuses (AL
//                                           status 0x0011, error bit), the
//                                           STATE_SET ends with the async
//                                           error; exit 0 when it did fail
//   ecmxf-nl-helper as UID PROG ARGS...     run PROG as user UID (group
//                                           UID, no supplementary groups,
//                                           no capabilities)
//   ecmxf-nl-helper counters [/dev/ecmxfN]  ECMXF_IOC_COUNTERS as "name
//                                           value" lines, in the order and
//                                           with the names of
//                                           `ecmxf-util monitor --counters`
//
// (ecmxf-util itself is the netlink side: it links libmnl, which Debian
// ships without a static library, so it is the one dynamically linked
// guest program.)

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>

#include <grp.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <string_view>
#include <utility>

namespace {
// time limits are not what the step checks: a loaded TCG guest (the debug
// kernel above all) can stall a command beyond the table's 100 ms
constexpr std::chrono::seconds kPatience{ 5 };
} // namespace

int main(int argc, char **argv)
{
	const std::string_view what = argc > 1 ? argv[1] : "";
	if (what == "as" && argc > 3) {
		const auto id = static_cast<uid_t>(std::stoul(argv[2]));
		if (::setgroups(0, nullptr) < 0 || ::setgid(id) < 0 || ::setuid(id) < 0) {
			std::perror("ecmxf-nl-helper as: dropping privileges");
			return 1;
		}
		::execv(argv[3], argv + 3);
		std::perror(argv[3]);
		return 1;
	}
	const std::string path = argc > 2 ? argv[2] : "/dev/ecmxf0";
	try {
		if (what == "op") {
			auto dev = ecmxf::Device::open(path);
			dev->setMinimumTimeout(kPatience);
			dev->bus().initNetwork();
			dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);
			dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::SafeOp);
			dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::Op);
			std::printf("guest-test: ok   %s: bus in OP (%u slaves)\n", path.c_str(), static_cast<unsigned>(dev->bus().slaveCount()));
			return 0;
		}
		if (what == "refused") {
			auto dev = ecmxf::Device::open(path);
			dev->setMinimumTimeout(kPatience);
			dev->bus().stateSet(0, ecmxf::State::Init);
			try {
				dev->bus().stateSet(0, ecmxf::State::Op); // INIT -> OP: not allowed
			} catch (const ecmxf::Error &e) {
				std::printf("guest-test: ok   %s: slave 0 INIT -> OP refused: %s\n", path.c_str(),
					    e.what());
				return 0;
			}
			std::printf("guest-test: FAIL %s: slave 0 INIT -> OP was not refused\n", path.c_str());
			return 1;
		}
		if (what == "counters") {
			// the transport alone: opening it sends no command
			const ecmxf::KernelLink kt(path);
			const ecmxf::LinkCounters k = kt.counters();
			for (const auto &[name, value] : ecmxf::counterFields(k))
				std::printf("%s %llu\n", name, static_cast<unsigned long long>(value));
			return 0;
		}
		std::fprintf(stderr, "usage: ecmxf-nl-helper op|refused|counters [/dev/ecmxfN] | as UID PROG ARGS...\n");
		return 2;
	} catch (const std::exception &e) {
		std::printf("guest-test: FAIL %s %s: %s\n", std::string(what).c_str(), path.c_str(), e.what());
		return 1;
	}
}
