// SPDX-License-Identifier: MIT
/*
 * Watch a chip's events for a while: ECAT state changes (with the slaves'
 * AL status codes when the state went down), link, error and ECM status
 * bits, CRC and WKC errors, FIFO marks. ecmxf::EventDetector finds them in
 * the response headers this program polls (over /dev/ecmxfN the kernel
 * sends the same events: ecmxf::EventSubscriber).
 *
 *   ecmxf-example-watch-events [URI [MILLISECONDS]]   (default "sim:", 1000)
 */
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <ecmxf/ecmxf.hpp>

int main(int argc, char **argv)
{
	const char *uri = argc > 1 ? argv[1] : "sim:";
	char *end = nullptr;
	const unsigned long ms = argc > 2 ? std::strtoul(argv[2], &end, 10) : 1000;
	if (argc > 3 || (argc > 2 && (*argv[2] < '0' || *argv[2] > '9' || *end || ms < 1 || ms > 3'600'000))) {
		std::fprintf(stderr, "usage: %s [URI [MILLISECONDS]] (MILLISECONDS: 1..3600000)\n", argv[0]);
		return 2;
	}

	try {
		auto dev = ecmxf::Device::open(uri);
		ecmxf::Link &link = dev->link();
		ecmxf::EventDetector detector(*dev); // with the device: it reads the slaves' AL status
		const auto t0 = link.now();
		(void)detector.feed(dev->chip().infoUpdate(), link.now()); // the baseline

		// scan the bus and take it to PRE-OP, so that there is something to see
		dev->bus().initNetwork();
		dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);

		while (link.now() - t0 < std::chrono::milliseconds(ms)) {
			for (const ecmxf::Event &e : detector.feed(dev->chip().infoUpdate(), link.now())) {
				std::printf("%8.3f ms  %s", std::chrono::duration<double, std::milli>(e.time - t0).count(),
					    ecmxf::eventTypeName(e.type).c_str());
				if (e.type == ecmxf::EventType::State)
					std::printf(" %s -> %s", ecmxf::ecatStateName(static_cast<std::uint8_t>(e.oldValue)).c_str(),
						    ecmxf::ecatStateName(static_cast<std::uint8_t>(e.newValue)).c_str());
				for (const ecmxf::SlaveAlStatus &s : e.slaves)
					std::printf("; slave %u: AL status 0x%04x", unsigned{ s.position }, s.alStatus.value_or(0));
				std::printf("\n");
			}
			link.sleepFor(std::chrono::milliseconds(10)); // the poll interval
		}
	} catch (const std::exception &e) {
		std::fprintf(stderr, "watch-events: %s\n", e.what());
		return 1;
	}
	return 0;
}
