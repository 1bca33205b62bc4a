// SPDX-License-Identifier: MIT
/**
 * @file snapshot.hpp
 * @brief What a live view's frame needs from a Recorder, copied on the
 *        cycling thread without allocating, and handed to a drawing
 *        thread without waiting.
 *
 * A Recorder is not thread-safe: the thread that runs the cycles samples
 * into it. A live view that draws in a thread of its own (as
 * `ecmxf-util scope --live` does, Documentation/scope.rst) must not read
 * it there. Instead the cycling thread, between cycles, copies what a frame
 * needs into a RecorderSnapshot: the recorder's state and sample count and,
 * of each drawn signal, its latest samples (2 per terminal cell:
 * terminalText() draws them). The snapshot's room is allocated once, by its
 * constructor; take() allocates nothing, throws nothing, locks nothing.
 *
 * SnapshotExchange hands snapshots from the cycling thread (one writer) to
 * the drawing thread (one reader) through three of them (a triple buffer):
 * the writer fills back() and publish()es it, the reader take()s the latest
 * one published. The two swap buffers with one atomic exchange each: neither
 * ever waits for the other, and a snapshot published while the reader is
 * still drawing an older one replaces the one it had not taken yet. The
 * writer can see that the reader has not taken the last one (pending()) and
 * skip copying the next: a drawer stuck on a slow terminal costs the cycles
 * nothing.
 *
 * @code
 *   ecmxf::SnapshotExchange frames(rec.signals().size(), 2000); // before the cycles
 *   // the cycling thread, every 100 ms between cycles:
 *   if (!frames.pending()) { frames.back().take(rec, 2 * width); frames.publish(); }
 *   // the drawing thread:
 *   if (const ecmxf::RecorderSnapshot *s = frames.take())
 *       rows = ecmxf::terminalText(s->values(0), width, height);
 * @endcode
 */
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/scope/recorder.hpp>

namespace ecmxf {

/// A copy of a Recorder's latest samples, its state and its sample count.
class ECMXF_EXPORT RecorderSnapshot
{
public:
	/// Room for @p signals signals of @p samples samples each (allocates
	/// them). EINVAL: @p samples not 1..10^6.
	RecorderSnapshot(std::size_t signals, std::size_t samples);

	/// Copies the recorder's state and size and, of its first
	/// min(@p signals, room, recorder's) signals, the latest
	/// min(@p samples, room, size()) samples. Allocates nothing, throws
	/// nothing: for the cycling thread, between cycles.
	void take(const Recorder &rec, std::size_t samples, std::size_t signals = ~std::size_t{ 0 }) noexcept;

	/// Signal @p signal's copied samples, oldest first (empty: not copied).
	[[nodiscard]] std::span<const double> values(std::size_t signal) const noexcept;
	/// The signals copied by the last take().
	[[nodiscard]] std::size_t signals() const noexcept { return signals_; }
	/// The recorder's state, triggered() and size() at the last take().
	[[nodiscard]] RecorderState state() const noexcept { return state_; }
	[[nodiscard]] bool done() const noexcept { return state_ == RecorderState::Done; }
	[[nodiscard]] bool triggered() const noexcept { return triggered_; }
	[[nodiscard]] std::size_t size() const noexcept { return size_; }
	/// The room: signals and samples per signal.
	[[nodiscard]] std::size_t signalRoom() const noexcept { return signalRoom_; }
	[[nodiscard]] std::size_t sampleRoom() const noexcept { return sampleRoom_; }

private:
	std::size_t signalRoom_, sampleRoom_;
	std::vector<double> values_; // signalRoom_ x sampleRoom_
	std::size_t signals_ = 0, copied_ = 0, size_ = 0;
	RecorderState state_ = RecorderState::Idle;
	bool triggered_ = false;
};

/// Three RecorderSnapshots passed from one writer thread to one reader
/// thread without a lock (file comment).
class ECMXF_EXPORT SnapshotExchange
{
public:
	/// Three snapshots of RecorderSnapshot(@p signals, @p samples).
	SnapshotExchange(std::size_t signals, std::size_t samples);
	SnapshotExchange(const SnapshotExchange &) = delete;
	SnapshotExchange &operator=(const SnapshotExchange &) = delete;

	/// The writer's snapshot, to fill before publish().
	[[nodiscard]] RecorderSnapshot &back() noexcept { return buffers_[back_]; }
	/// Makes back() the latest for the reader; back() is then another one.
	void publish() noexcept;
	/// True while the last snapshot published has not been taken.
	[[nodiscard]] bool pending() const noexcept;

	/// The reader's: the latest snapshot published since the last take(),
	/// nullptr when none was. It stays the reader's until its next take().
	[[nodiscard]] const RecorderSnapshot *take() noexcept;

private:
	static constexpr std::uint8_t kFresh = 4; // beside the index 0..2
	RecorderSnapshot buffers_[3];
	std::uint8_t back_ = 0;             // the writer's
	std::uint8_t front_ = 2;            // the reader's
	std::atomic<std::uint8_t> middle_{ 1 }; // the one between them, kFresh when published and not taken
};

} // namespace ecmxf
