// SPDX-License-Identifier: MIT
// A Recorder's latest samples copied for a drawing thread, and the triple
// buffer that hands them over (include/ecmxf/scope/snapshot.hpp).

#include <ecmxf/scope/snapshot.hpp>

#include <algorithm>
#include <cerrno>
#include <string>

#include <ecmxf/error.hpp>

namespace ecmxf {

namespace {

constexpr std::size_t kMaxSamples = 1'000'000;

std::size_t checkedSamples(std::size_t samples)
{
	if (samples < 1 || samples > kMaxSamples)
		throw Error("scope snapshot: " + std::to_string(samples) + " samples a signal: 1.." +
				    std::to_string(kMaxSamples),
			    EINVAL);
	return samples;
}

} // namespace

RecorderSnapshot::RecorderSnapshot(std::size_t signals, std::size_t samples)
	: signalRoom_(signals), sampleRoom_(checkedSamples(samples)), values_(signals * samples, 0.0)
{
}

void RecorderSnapshot::take(const Recorder &rec, std::size_t samples, std::size_t signals) noexcept
{
	state_ = rec.state();
	triggered_ = rec.triggered();
	size_ = rec.size();
	signals_ = std::min({ signals, signalRoom_, rec.signals().size() });
	copied_ = std::min({ samples, sampleRoom_, size_ });
	const std::size_t first = size_ - copied_;
	for (std::size_t k = 0; k < signals_; k++) {
		double *to = &values_[k * sampleRoom_];
		for (std::size_t i = 0; i < copied_; i++)
			to[i] = rec.value(first + i, k);
	}
}

std::span<const double> RecorderSnapshot::values(std::size_t signal) const noexcept
{
	if (signal >= signals_)
		return {};
	return { values_.data() + signal * sampleRoom_, copied_ };
}

SnapshotExchange::SnapshotExchange(std::size_t signals, std::size_t samples)
	: buffers_{ RecorderSnapshot(signals, samples), RecorderSnapshot(signals, samples),
		    RecorderSnapshot(signals, samples) }
{
}

void SnapshotExchange::publish() noexcept
{
	// release: the reader that takes it sees what was written into it;
	// acquire: the buffer got back is one the reader has let go of
	const std::uint8_t old = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
	back_ = static_cast<std::uint8_t>(old & ~kFresh);
}

bool SnapshotExchange::pending() const noexcept
{
	return (middle_.load(std::memory_order_relaxed) & kFresh) != 0;
}

const RecorderSnapshot *SnapshotExchange::take() noexcept
{
	if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0)
		return nullptr;
	// acquire: the snapshot's contents; release: the buffer given back
	// (the one drawn last) is free for the writer
	const std::uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
	front_ = static_cast<std::uint8_t>(old & ~kFresh);
	return &buffers_[front_];
}

} // namespace ecmxf
