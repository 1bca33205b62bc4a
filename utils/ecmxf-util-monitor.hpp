// SPDX-License-Identifier: MIT
/*
 * ecmxf-util monitor - event detection from successive response headers,
 * apart from the polling loop so that tests can drive it directly.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/device.hpp>

namespace ecmxf_util::monitor {

/// FIFO levels that make an event when a count crosses them.
struct Thresholds {
	unsigned txHigh = 10; ///< TxFIFO high mark: count rises to >= it, or falls below it
	unsigned rxLow = 0;   ///< RxFIFO low mark: count falls to <= it, or rises above it
};

/// One event: a type, a line for people and the members of its JSON
/// object (values already JSON text).
struct Event {
	std::string type; ///< state, reset, error_status, ecm_status, crc_errors, wkc_burst, wkc_burst_end, fifo
	std::string text;
	std::vector<std::pair<std::string, std::string>> fields;
};

/// The events between two response headers @p prev and @p cur (pure):
///  - reset: the NOP bit (ECM status bit 5) in @p cur, or "Ethernet
///    initialised" (bit 3) cleared, or the ECAT state back to 0 (NONE):
///    only this event, the other differences follow from it;
///  - state: the ECAT state changed;
///  - error_status: bits of the error status set / cleared, by name;
///  - ecm_status: ECM status bits 2, 3, 4, 6 set / cleared (not the check
///    type, NOP or busy);
///  - crc_errors: the SPI CRC error count went up;
///  - wkc: the WKC error count went up (fields increase, total) - the
///    Detector turns these into bursts;
///  - fifo: a FIFO count crossed its threshold.
std::vector<Event> diffHeaders(const ecmxf::ResponseHeader &prev, const ecmxf::ResponseHeader &cur,
			       const Thresholds &th);

/// Stateful wrapper: the first header is the baseline (no events); WKC
/// increments in consecutive polls are one burst, reported when it starts
/// (wkc_burst) and when a poll shows no increment (wkc_burst_end, with the
/// errors of the whole burst and its duration).
class Detector
{
public:
	explicit Detector(Thresholds th = {}) : th_(th) {}
	/// The events of @p cur, polled at @p now (any monotonic origin).
	std::vector<Event> update(const ecmxf::ResponseHeader &cur, std::chrono::nanoseconds now);
	/// Forget the previous header (after a chip reset): the next update
	/// is a baseline again.
	void rebase() { prev_.reset(); burst_ = false; }

private:
	Thresholds th_;
	std::optional<ecmxf::ResponseHeader> prev_;
	bool burst_ = false;
	unsigned burstErrors_ = 0;
	std::chrono::nanoseconds burstStart_{ 0 };
};

/// Names of the set bits of the error status (0x09) and of ECM status
/// bits 2, 3, 4, 6 (0x0A).
std::vector<std::string> errorBitNames(std::uint8_t v);
std::vector<std::string> ecmBitNames(std::uint8_t v);


} // namespace ecmxf_util::monitor
