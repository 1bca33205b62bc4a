// SPDX-License-Identifier: MIT
/**
 * @file recorder.hpp
 * @brief The scope's recorder: chosen signals sampled every cycle into a
 *        buffer sized up front, with a trigger and a stop.
 *
 * Signals are added before arm(), by a text (the same for the library,
 * `ecmxf-util scope` and `cia402 move --plot`):
 *
 *   - `N:NAME`        process-data entry NAME of slave N (an input, else an
 *                     output; case, spaces, '_' and '-' ignored:
 *                     `1:position_actual_value`), over a ProcessImage;
 *   - `N:INDEX:SUB`   the entry mapped as INDEX:SUB (hex: `1:0x6064:0`);
 *   - a cycle figure of the ECM-XF's CycleResult (`wkc`, `wkc_expected`,
 *     `wkc_errors`, `rx_fifo`, `tx_fifo`, `pushed`, `popped`, `error`) or
 *     of the ECM-SK's (`fifo_remaining`, `fifo_full`, `dropped`, `staged`);
 *   - over an ECM-SK board, `N:position`, `N:statusword`, `N:torque`,
 *     `N:error_code`: the feedback slot of bus position N (0-based).
 *
 * Any other value of the application (a computed set-point) joins with
 * addValue(). A text that names nothing throws ecmxf::Error (EINVAL)
 * naming the text and what is wrong (the entries the slave has, the slaves
 * the bus has, the figures there are).
 *
 * arm() allocates the buffer (capacity x signals values) and sets the
 * trigger (at once, or a rising / falling crossing of a numeric signal's
 * level, with pre-trigger samples kept) and the stop (after cycles, after
 * a time, or the buffer full). sample() then reads every signal once per
 * cycle: it allocates nothing and throws nothing.
 *
 * @code
 *   ecmxf::Recorder rec(10000);
 *   rec.add(image, "0:position_actual_value");
 *   rec.add(image, "wkc");
 *   rec.arm({}, { .cycles = 2000 });
 *   while (!rec.done()) { const auto &r = cyc.cycle(); rec.sample(dev.link().now(), r); cyc.waitNextCycle(); }
 *   ecmxf::writeSvg(rec, "move.svg");                  // <ecmxf/scope/plot.hpp>
 * @endcode
 *
 * Thread safety: none; the thread that runs the cycles samples.
 */
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/pdo/process_image.hpp>

namespace ecmxf {

struct CycleResult;

namespace sk {
class Board;
struct CycleResult;
} // namespace sk

/// When recording starts.
enum class TriggerEdge : std::uint8_t {
	Now,     ///< the first sample after arm()
	Rising,  ///< the signal goes from below level to level or above
	Falling, ///< the signal goes from above level to level or below
};

struct RecorderTrigger {
	TriggerEdge edge = TriggerEdge::Now;
	/// The signal's text as given to add() (Rising / Falling only); it
	/// must be numeric (not a word of bits or a code).
	std::string signal;
	double level = 0;
	/// Samples before the trigger kept (less than the capacity).
	std::size_t preSamples = 0;
};

/// When recording stops, whichever comes first; both zero: the buffer
/// full. The buffer full always stops it.
struct RecorderStop {
	std::uint64_t cycles = 0;            ///< samples from the trigger on (it included)
	std::chrono::nanoseconds time{ 0 };  ///< time from the trigger on
};

/// One recorded signal.
struct RecordedSignal {
	std::string name;    ///< the text it was added by
	std::string label;   ///< what a legend shows ("slave 0 Position actual value")
	std::string unit;    ///< "inc", "inc/s", ... empty: none
	bool numeric = true; ///< false: a word of bits or a code (no trigger on it)
};

enum class RecorderState : std::uint8_t {
	Idle,      ///< before arm()
	Armed,     ///< waiting for the trigger
	Recording, ///< triggered
	Done,      ///< stopped
};

class ECMXF_EXPORT Recorder
{
public:
	/// A recorder of at most @p capacity samples (1..10^7, else EINVAL).
	explicit Recorder(std::size_t capacity);
	~Recorder();
	Recorder(const Recorder &) = delete;
	Recorder &operator=(const Recorder &) = delete;

	/// Adds the signal @p text names (file comment) over @p image (which
	/// must outlive the recorder); returns its number. Throws
	/// ecmxf::Error (EINVAL) naming what is wrong; EBUSY after arm().
	std::size_t add(ProcessImage &image, std::string_view text);
	/// The same over an ECM-SK board of @p slaves slaves (feedback slots
	/// and the ECM-SK's cycle figures).
	std::size_t add(sk::Board &board, unsigned slaves, std::string_view text);
	/// A value of the application, read at each sample through @p source
	/// (which must outlive the recorder).
	std::size_t addValue(std::string name, std::string unit, const std::int64_t *source, bool numeric = true);

	/// Allocates the buffer, sets the trigger and the stop, and forgets
	/// the samples of before. EINVAL: no signal, a trigger signal not
	/// added or not numeric, preSamples not below the capacity.
	void arm(const RecorderTrigger &trigger = {}, const RecorderStop &stop = {});

	/// One sample at @p now (any clock; the link's): every signal read.
	/// The overloads take the cycle figures from the cycle's result.
	/// Allocate nothing, throw nothing; return the state after it.
	RecorderState sample(std::chrono::nanoseconds now) noexcept;
	RecorderState sample(std::chrono::nanoseconds now, const CycleResult &cycle) noexcept;
	RecorderState sample(std::chrono::nanoseconds now, const sk::CycleResult &cycle) noexcept;

	/// Stops recording (a user's quit): what was recorded stays.
	void finish() noexcept;

	[[nodiscard]] RecorderState state() const noexcept { return state_; }
	[[nodiscard]] bool done() const noexcept { return state_ == RecorderState::Done; }
	[[nodiscard]] bool triggered() const noexcept { return triggerSample_ != kNone; }
	[[nodiscard]] std::size_t capacity() const noexcept { return capacity_; }
	[[nodiscard]] const std::vector<RecordedSignal> &signals() const noexcept { return signals_; }
	/// Samples held (oldest first).
	[[nodiscard]] std::size_t size() const noexcept { return count_; }
	/// Sample @p i's time relative to the trigger (negative before it;
	/// relative to the first sample when never triggered).
	[[nodiscard]] std::chrono::nanoseconds time(std::size_t i) const noexcept;
	/// Signal @p signal's value in sample @p i.
	[[nodiscard]] double value(std::size_t i, std::size_t signal) const noexcept;
	/// The sample that triggered (its index), or size() when none did.
	[[nodiscard]] std::size_t triggerIndex() const noexcept;

	struct Source;

private:
	std::size_t push(Source s, RecordedSignal sig);
	void checkIdle() const;
	[[nodiscard]] std::size_t slot(std::size_t i) const noexcept { return (head_ + i) % capacity_; }
	RecorderState record(std::chrono::nanoseconds now, const CycleResult *xf, const sk::CycleResult *sk) noexcept;

	static constexpr std::size_t kNone = ~std::size_t{ 0 };

	std::size_t capacity_;
	std::vector<RecordedSignal> signals_;
	std::vector<Source> sources_;
	std::vector<double> values_;               // capacity x signals
	std::vector<std::int64_t> times_;          // ns
	RecorderTrigger trigger_;
	RecorderStop stop_;
	std::size_t triggerSignal_ = 0;
	RecorderState state_ = RecorderState::Idle;
	std::size_t head_ = 0, count_ = 0;
	std::size_t triggerSample_ = kNone;        // counted from head_
	std::int64_t triggerTime_ = 0;
	std::uint64_t sinceTrigger_ = 0;
	double previous_ = 0;
	bool havePrevious_ = false;
};

} // namespace ecmxf
