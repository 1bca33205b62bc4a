// SPDX-License-Identifier: MIT
// The userspace side of the kernel's PDO rings (lib/pdo_ring.hpp) against
// a fake kernel in another thread: the memory is laid out from reported
// offsets as ecmxf.ko reports them (Documentation/uapi.rst), the fake
// kernel follows the same acquire/release protocol. No frame may be lost,
// duplicated or reordered; a full ring refuses; the status block is read
// consistently while it is being written.

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "pdo_ring.hpp"

using ecmxf::detail::PdoRingView;

namespace {

/// One ring's memory as ecmxf-ring.c lays it out (the offsets are
/// reported, so the test uses others than the kernel's on purpose).
struct FakeRing {
	std::vector<std::uint64_t> mem; // 8-byte aligned
	ecmxf_ring_offsets off{};

	FakeRing(std::uint32_t entries, std::uint32_t frameSize, bool status)
	{
		off.head = 0;
		off.tail = 128;
		off.mask = 256;
		off.entries = 260;
		off.flags = 264;
		off.dropped = 268;
		off.status = status ? 320 : 0;
		off.frames = 512;
		off.frame_size = frameSize;
		off.frame_stride = (frameSize + 7) / 8 * 8;
		off.mmap_size = off.frames + entries * off.frame_stride;
		mem.assign(off.mmap_size / 8 + 1, 0);
		word(off.mask) = entries - 1;
		word(off.entries) = entries;
	}
	std::uint8_t *base() { return reinterpret_cast<std::uint8_t *>(mem.data()); }
	std::uint32_t &word(std::uint32_t o) { return *reinterpret_cast<std::uint32_t *>(base() + o); }
	std::atomic_ref<std::uint32_t> idx(std::uint32_t o) { return std::atomic_ref<std::uint32_t>(word(o)); }
	std::uint8_t *slot(std::uint32_t i)
	{
		return base() + off.frames + (i & word(off.mask)) * off.frame_stride;
	}
};

} // namespace

TEST_CASE("pdo ring: output frames reach a concurrent consumer in order, none lost or doubled", "[pdo][ring]")
{
	FakeRing r(8, 6, false);
	PdoRingView out(r.base(), r.off);
	REQUIRE(out.entries() == 8);
	constexpr std::uint32_t kFrames = 200000;
	std::atomic<bool> bad{ false };
	std::thread kernel([&] {
		// the fake kernel: consumes with acquire on tail, release on head
		std::uint32_t want = 0;
		while (want < kFrames) {
			const std::uint32_t tail = r.idx(r.off.tail).load(std::memory_order_acquire);
			std::uint32_t head = r.idx(r.off.head).load(std::memory_order_relaxed);
			if (tail - head > 8)
				bad = true;
			for (; head != tail; head++, want++) {
				std::uint32_t v;
				std::memcpy(&v, r.slot(head), 4);
				if (v != want || r.slot(head)[4] != static_cast<std::uint8_t>(want * 7))
					bad = true;
			}
			r.idx(r.off.head).store(head, std::memory_order_release);
		}
	});
	std::uint64_t refused = 0;
	for (std::uint32_t v = 0; v < kFrames;) {
		std::uint8_t f[6]{};
		std::memcpy(f, &v, 4);
		f[4] = static_cast<std::uint8_t>(v * 7);
		if (out.push(f))
			v++;
		else
			refused++;
	}
	kernel.join();
	CHECK_FALSE(bad);
	CHECK(out.count() == 0);
	INFO("pushes refused while the ring was full: " << refused);
}

TEST_CASE("pdo ring: a full output ring refuses and keeps what it has", "[pdo][ring]")
{
	FakeRing r(4, 3, false);
	PdoRingView out(r.base(), r.off);
	for (std::uint8_t i = 0; i < 4; i++) {
		const std::uint8_t f[3] = { i, i, i };
		CHECK(out.push(f));
	}
	const std::uint8_t f[3] = { 9, 9, 9 };
	CHECK_FALSE(out.push(f));
	CHECK(out.count() == 4);
	CHECK(r.word(r.off.tail) == 4);
	CHECK(r.slot(0)[0] == 0);
	CHECK(r.slot(3)[0] == 3);
	// the consumer frees two: two more fit, in slots 0 and 1 (wrapped)
	r.idx(r.off.head).store(2, std::memory_order_release);
	CHECK(out.push(f));
	CHECK(out.push(f));
	CHECK_FALSE(out.push(f));
	CHECK(r.slot(4)[0] == 9);
	CHECK(r.word(r.off.tail) == 6);
}

TEST_CASE("pdo ring: input frames from a concurrent producer, in order, across index wrap", "[pdo][ring]")
{
	FakeRing r(16, 5, true);
	// indices run freely: start just below 2^32
	r.word(r.off.head) = r.word(r.off.tail) = 0xFFFFFF00u;
	PdoRingView in(r.base(), r.off);
	constexpr std::uint32_t kFrames = 100000;
	std::thread kernel([&] {
		std::uint32_t v = 0;
		while (v < kFrames) {
			const std::uint32_t head = r.idx(r.off.head).load(std::memory_order_acquire);
			std::uint32_t tail = r.idx(r.off.tail).load(std::memory_order_relaxed);
			while (tail - head < 16 && v < kFrames) {
				std::memcpy(r.slot(tail), &v, 4);
				r.slot(tail)[4] = static_cast<std::uint8_t>(v ^ 0x5A);
				tail++;
				v++;
			}
			r.idx(r.off.tail).store(tail, std::memory_order_release);
		}
	});
	std::uint32_t want = 0;
	bool bad = false;
	while (want < kFrames) {
		in.consume([&](std::span<const std::uint8_t> f) {
			std::uint32_t v;
			std::memcpy(&v, f.data(), 4);
			if (f.size() != 5 || v != want || f[4] != static_cast<std::uint8_t>(want ^ 0x5A))
				bad = true;
			want++;
		});
	}
	kernel.join();
	CHECK_FALSE(bad);
	CHECK(want == kFrames);
	CHECK(r.word(r.off.head) == 0xFFFFFF00u + kFrames);
}

TEST_CASE("pdo ring: a producer index beyond the ring is never read past the ring", "[pdo][ring]")
{
	FakeRing r(4, 2, false);
	PdoRingView in(r.base(), r.off);
	r.word(r.off.tail) = 1000; // garbage
	std::uint32_t n = 0;
	CHECK(in.consume([&](std::span<const std::uint8_t>) { n++; }) == 4);
	CHECK(n == 4);
}

TEST_CASE("pdo ring: the status block is read whole while the kernel writes it", "[pdo][ring]")
{
	FakeRing r(4, 2, true);
	PdoRingView in(r.base(), r.off);
	auto *st = reinterpret_cast<ecmxf_ring_status *>(r.base() + r.off.status);
	std::atomic<bool> stop{ false };
	std::thread kernel([&] {
		// the seqcount protocol of ecmxf_status_update(): odd, fields, even
		for (std::uint32_t i = 1; !stop.load(std::memory_order_relaxed); i++) {
			std::atomic_ref<std::uint32_t> seq(st->seq);
			seq.store(seq.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
			std::atomic_thread_fence(std::memory_order_release);
			std::atomic_ref<std::uint32_t>(st->wkc).store(i, std::memory_order_relaxed);
			std::atomic_ref<std::uint32_t>(st->wkc_reads).store(i, std::memory_order_relaxed);
			std::atomic_ref<std::uint32_t>(st->pump_ops).store(i * 3, std::memory_order_relaxed);
			seq.store(seq.load(std::memory_order_relaxed) + 1, std::memory_order_release);
		}
	});
	unsigned good = 0, torn = 0;
	for (int k = 0; k < 200000; k++) {
		ecmxf_ring_status s{};
		if (!in.status(s))
			continue;
		good++;
		if (s.wkc != s.wkc_reads || s.pump_ops != s.wkc * 3)
			torn++;
	}
	stop = true;
	kernel.join();
	CHECK(good > 0);
	CHECK(torn == 0);
}
