// SPDX-License-Identifier: MIT
/*
 * ecmxf-util monitor - events as lines and JSON objects, apart from the
 * loops that get them (netlink or polling) so that tests can drive them.
 *
 * Both sources give typed ecmxf::Event values: the kernel module over
 * generic netlink, or ecmxf::EventDetector (the protocol core's detector,
 * the very rules the kernel applies) over polled response headers.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/events/events.hpp>

namespace ecmxf_util::monitor {

/// FIFO levels that make an event when a count crosses them (polled
/// devices; the kernel uses the defaults).
struct Thresholds {
	unsigned txHigh = 10; ///< TxFIFO high mark: count rises to >= it, or falls below it
	unsigned rxLow = 0;   ///< RxFIFO low mark: count falls to <= it, or rises above it
};

/// One event as printed: a type, a line for people and the members of its
/// JSON object (values already JSON text).
struct Event {
	/// device, reset, link, state, error_status, ecm_status, crc_errors,
	/// wkc_burst, wkc_burst_end, fifo, async_error
	std::string type;
	std::string text;
	std::vector<std::pair<std::string, std::string>> fields;
};

/// The line and the JSON members of @p e (whatever its source):
///  - state: "ECAT state OP -> ERROR", then per slave the kernel or the
///    poller read: "; slave 1: not answering" or "; slave 0: PREOP +
///    error, AL status 0x001b (Sync manager watchdog)";
///  - link: "EtherCAT link down (error status 0x40)";
///  - error_status / ecm_status: the bits set / cleared, by name (bit 0 of
///    the error status is the link event's);
///  - crc_errors, wkc_burst, wkc_burst_end, fifo, reset, device,
///    async_error: see the help text.
/// Netlink events also get "device", "seq" and, when the kernel's rate
/// limit held some back, "suppressed" (and " [N suppressed]" in the line).
Event describe(const ecmxf::Event &e);

/// Does a state event ask for the slaves' states and AL status codes: the
/// state went down or into ERROR (the kernel's rule, ecmxf::stateWentDown()).
bool wantsSlaves(const ecmxf::Event &e);

/// The polled detector: ecmxf::EventDetector with @p th, and a WKC burst
/// that ends after @p wkcQuiet without new errors; with a @p device, its
/// state events that went down carry the slaves' AL status codes
/// (ecmxf::readSlaveStatus(), read in update()).
class Detector
{
public:
	explicit Detector(Thresholds th = {},
			  std::chrono::nanoseconds wkcQuiet = std::chrono::milliseconds(100),
			  ecmxf::Device *device = nullptr);
	/// The events of @p cur, polled at @p now (any monotonic origin); the
	/// first header is the baseline.
	std::vector<ecmxf::Event> update(const ecmxf::ResponseHeader &cur, std::chrono::nanoseconds now);
	/// Forget the previous header (after a chip reset): the next update is
	/// a baseline again; a running burst ends (its event is returned).
	std::vector<ecmxf::Event> rebase(std::chrono::nanoseconds now);

private:
	ecmxf::EventDetector det_;
};

/// Names of the set bits of the error status (0x09) and of ECM status
/// bits 2, 3, 4, 6 (0x0A).
std::vector<std::string> errorBitNames(std::uint8_t v);
std::vector<std::string> ecmBitNames(std::uint8_t v);

/// The counters of the kernel's counters command: "name value" lines, or
/// one JSON object.
std::string countersText(const ecmxf::NetlinkCounters &c);
std::string countersJson(const ecmxf::NetlinkCounters &c);

} // namespace ecmxf_util::monitor
