// SPDX-License-Identifier: MIT
// The userspace side of the kernel's mmap()ed PDO rings (<linux/ecmxf.h>,
// Documentation/uapi.rst "The cyclic path"): a view over one mapped ring,
// laid out by the offsets the kernel reported, with the acquire/release
// protocol on the two indices. Internal to the library; header-only so
// that the host tests can run it against a fake kernel.

#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "uapi/linux/ecmxf.h"

namespace ecmxf::detail {

/// One ring: the application is the producer of the output ring and the
/// consumer of the input ring. Nothing here allocates, throws or calls the
/// kernel.
class PdoRingView
{
public:
	PdoRingView() = default;
	/// @p base: the mapping of @p off.mmap_size bytes.
	PdoRingView(void *base, const ecmxf_ring_offsets &off) noexcept
		: base_(static_cast<std::uint8_t *>(base)), off_(off), entries_(off.mmap_size ? word(off.entries) : 0)
	{
	}

	[[nodiscard]] bool valid() const noexcept { return base_ != nullptr; }
	[[nodiscard]] std::uint32_t entries() const noexcept { return entries_; }
	[[nodiscard]] std::uint32_t frameSize() const noexcept { return off_.frame_size; }

	/// Producer: copies @p frame (frame_size bytes) into the next slot and
	/// publishes it. False when the ring is full (nothing written).
	bool push(std::span<const std::uint8_t> frame) noexcept
	{
		const std::uint32_t tail = ref(off_.tail).load(std::memory_order_relaxed);
		const std::uint32_t head = ref(off_.head).load(std::memory_order_acquire);
		if (tail - head >= entries_)
			return false;
		std::memcpy(slot(tail), frame.data(), std::min<std::size_t>(frame.size(), off_.frame_size));
		ref(off_.tail).store(tail + 1, std::memory_order_release);
		return true;
	}

	/// Consumer: hands every frame there is to @p fn (oldest first, a span
	/// valid during the call), then frees the slots. Returns how many.
	template <typename Fn> std::uint32_t consume(Fn &&fn) noexcept
	{
		const std::uint32_t head = ref(off_.head).load(std::memory_order_relaxed);
		const std::uint32_t tail = ref(off_.tail).load(std::memory_order_acquire);
		std::uint32_t n = tail - head;
		if (n > entries_)
			n = entries_; // a producer gone wrong: never read beyond the ring
		for (std::uint32_t i = 0; i < n; i++)
			fn(std::span<const std::uint8_t>(slot(head + i), off_.frame_size));
		ref(off_.head).store(head + n, std::memory_order_release);
		return n;
	}

	/// Frames waiting (producer's view for the output ring, consumer's
	/// for the input ring).
	[[nodiscard]] std::uint32_t count() const noexcept
	{
		return ref(off_.tail).load(std::memory_order_acquire) - ref(off_.head).load(std::memory_order_acquire);
	}

	/// The kernel's ECMXF_RING_S_* word and dropped-frames count.
	[[nodiscard]] std::uint32_t flags() const noexcept { return ref(off_.flags).load(std::memory_order_acquire); }
	[[nodiscard]] std::uint32_t dropped() const noexcept
	{
		return ref(off_.dropped).load(std::memory_order_relaxed);
	}

	/// A consistent copy of the status (input ring); false when the ring
	/// has none. The block is a latch of two copies
	/// (ecmxf_ring_status_block): the copy read is never the one the kernel
	/// is writing, so a read retries only when the kernel finished a whole
	/// update meanwhile, and never waits for a writer it preempted. The
	/// bound on retries only guards against a count gone wrong (false).
	bool status(ecmxf_ring_status &out) const noexcept
	{
		if (!off_.status)
			return false;
		auto *b = reinterpret_cast<ecmxf_ring_status_block *>(base_ + off_.status);
		std::atomic_ref<std::uint32_t> seq(b->seq);
		for (int tries = 0; tries < 64; tries++) {
			const std::uint32_t s1 = seq.load(std::memory_order_acquire);
			copyStatus(b->copy[s1 & 1u], out);
			std::atomic_thread_fence(std::memory_order_acquire);
			if (seq.load(std::memory_order_relaxed) == s1)
				return true;
		}
		return false;
	}

private:
	[[nodiscard]] std::uint32_t word(std::uint32_t offset) const noexcept
	{
		std::uint32_t v;
		std::memcpy(&v, base_ + offset, sizeof(v));
		return v;
	}
	[[nodiscard]] std::atomic_ref<std::uint32_t> ref(std::uint32_t offset) const noexcept
	{
		return std::atomic_ref<std::uint32_t>(*reinterpret_cast<std::uint32_t *>(base_ + offset));
	}
	[[nodiscard]] std::uint8_t *slot(std::uint32_t index) const noexcept
	{
		return base_ + off_.frames + static_cast<std::size_t>(index & (entries_ - 1)) * off_.frame_stride;
	}
	static void copyStatus(ecmxf_ring_status &st, ecmxf_ring_status &out) noexcept
	{
		// field by field with relaxed atomic loads: the kernel may be
		// writing them (the latch count tells)
		auto ld = [](std::uint32_t &w) { return std::atomic_ref<std::uint32_t>(w).load(std::memory_order_relaxed); };
		auto ld8 = [](std::uint8_t &b) { return std::atomic_ref<std::uint8_t>(b).load(std::memory_order_relaxed); };
		out.generation = ld(st.generation);
		out.wkc = ld(st.wkc);
		out.wkc_reads = ld(st.wkc_reads);
		out.int_flags = ld(st.int_flags);
		out.crc_err_cnt = ld8(st.crc_err_cnt);
		out.wkc_err_cnt = ld8(st.wkc_err_cnt);
		out.tx_fifo_cnt = ld8(st.tx_fifo_cnt);
		out.rx_fifo_cnt = ld8(st.rx_fifo_cnt);
		out.ecat_state = ld8(st.ecat_state);
		out.err_status = ld8(st.err_status);
		out.ecm_status = ld8(st.ecm_status);
		out.padding = 0;
		out.pump_ops = ld(st.pump_ops);
		out.rx_refusals = ld(st.rx_refusals);
		out.tx_overflows = ld(st.tx_overflows);
		out.rx_underruns = ld(st.rx_underruns);
		out.out_underruns = ld(st.out_underruns);
		out.error = ld(st.error);
		out.out_skipped = ld(st.out_skipped);
		out.pump_failures = ld(st.pump_failures);
		out.reserved[0] = out.reserved[1] = 0;
	}

	std::uint8_t *base_ = nullptr;
	ecmxf_ring_offsets off_{};
	std::uint32_t entries_ = 0;
};

} // namespace ecmxf::detail
