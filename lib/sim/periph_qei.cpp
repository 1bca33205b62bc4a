// SPDX-License-Identifier: MIT
//
// periph_qei.cpp - the quadrature encoder interface: a 32-bit up/down
// counter fed by the A/B phases (X4: every edge, X2: the A edges), with the
// index and over/underflow flags.

#include "periph_blocks.hpp"

namespace ecmxf::sim::periph {

namespace {

// Floor division by 2 (towards minus infinity).
constexpr std::int64_t half(std::int64_t v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); }

} // namespace

void Qei::reset()
{
	mode_ = QeiMode::X4Free;
	running_ = false;
	count_ = 0;
	flags_ = 0;
}

void Qei::open(QeiMode mode)
{
	mode_ = mode;
	running_ = false;
	count_ = 0;
	flags_ = 0;
}

void Qei::move(std::int64_t edges)
{
	const std::int64_t from = shaft_;
	shaft_ += edges;
	if (!running_ || edges == 0)
		return;
	std::int64_t delta = edges;
	if (mode_ == QeiMode::X2Free || mode_ == QeiMode::X2Compare) {
		// Edges alternate A, B, A, B...; the A edges sit between the
		// shaft positions 2k-1 and 2k.
		delta = half(shaft_) - half(from);
	}
	// No command sets CNTMAX, so compare-counting wraps at 2^32 as well.
	const std::int64_t next = static_cast<std::int64_t>(count_) + delta;
	constexpr std::int64_t kRange = std::int64_t{ 1 } << 32;
	if (next < 0 || next >= kRange)
		flags_ |= kFlagOverflow;
	count_ = static_cast<std::uint32_t>(((next % kRange) + kRange) % kRange);
}

void Qei::index()
{
	if (running_)
		flags_ |= kFlagIndex;
}

} // namespace ecmxf::sim::periph
