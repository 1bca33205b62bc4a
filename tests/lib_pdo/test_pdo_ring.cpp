// SPDX-License-Identifier: MIT
// The userspace side of the kernel's PDO rings (lib/link/pdo_ring.hpp) against
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

#include "link/pdo_ring.hpp"

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
		off.status = status ? 320 : 0; // the block is 192 bytes
		static_assert(sizeof(ecmxf_ring_status_block) == 192);
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
			if (head == tail) {
				// nothing yet: let the producer run (one core: at once,
				// not at the end of a time slice)
				std::this_thread::yield();
				continue;
			}
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
		if (out.push(f)) {
			v++;
		} else {
			refused++;
			std::this_thread::yield();
		}
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
			if (tail - head >= 16) {
				std::this_thread::yield(); // full: let the consumer run
				continue;
			}
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
		const std::uint32_t got = in.consume([&](std::span<const std::uint8_t> f) {
			std::uint32_t v;
			std::memcpy(&v, f.data(), 4);
			if (f.size() != 5 || v != want || f[4] != static_cast<std::uint8_t>(want ^ 0x5A))
				bad = true;
			want++;
		});
		if (!got)
			std::this_thread::yield(); // empty: let the producer run
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

namespace {

/// The kernel's writer of the status block (ecmxf_status_publish() in
/// kmod/ecmxf-ring.c), split into its single stores so that a test can
/// stop it anywhere: the latch count, copy 0 word by word, the count,
/// copy 1 word by word.
struct LatchWriter {
	ecmxf_ring_status_block *b;
	std::uint32_t seq = 0;

	static constexpr std::size_t kWords = sizeof(ecmxf_ring_status) / 4;
	static constexpr std::size_t kSteps = 2 + 2 * kWords;

	/// Store number @p step (0 .. kSteps-1) of publishing @p next.
	void step(std::size_t k, const ecmxf_ring_status &next)
	{
		std::atomic_ref<std::uint32_t> count(b->seq);
		const std::size_t copy = k <= kWords ? 0 : 1;
		const std::size_t first = copy ? kWords + 1 : 0; // the count's store
		if (k == first) {
			count.store(++seq, std::memory_order_release);
			return;
		}
		std::uint32_t w;
		std::memcpy(&w, reinterpret_cast<const std::uint8_t *>(&next) + (k - first - 1) * 4, 4);
		std::atomic_ref<std::uint32_t>(reinterpret_cast<std::uint32_t *>(&b->copy[copy])[k - first - 1])
			.store(w, std::memory_order_release);
	}
	void publish(const ecmxf_ring_status &next)
	{
		for (std::size_t k = 0; k < kSteps; k++)
			step(k, next);
	}
};

/// A status whose every field derives from @p g: a mixed copy shows.
ecmxf_ring_status statusOf(std::uint32_t g)
{
	ecmxf_ring_status s{};
	s.generation = g;
	s.wkc = g * 3;
	s.wkc_reads = g;
	s.int_flags = ~g;
	s.crc_err_cnt = static_cast<std::uint8_t>(g);
	s.ecat_state = static_cast<std::uint8_t>(g >> 8);
	s.pump_ops = g * 7;
	s.error = g ^ 0x5A5A5A5Au;
	s.out_skipped = g + 1;
	s.pump_failures = g + 2;
	return s;
}

bool sameStatus(const ecmxf_ring_status &a, const ecmxf_ring_status &b)
{
	return std::memcmp(&a, &b, sizeof(a)) == 0;
}

} // namespace

TEST_CASE("pdo ring: a reader that preempted the status writer anywhere reads a whole status at once",
	  "[pdo][ring]")
{
	// What an RT reader of higher priority on the writer's CPU sees: the
	// writer stopped after any of its stores. The reader must succeed
	// first time with the old status until the writer switched copies,
	// the new one after, never a mix.
	const ecmxf_ring_status old = statusOf(41), next = statusOf(42);
	for (std::size_t stop = 0; stop <= LatchWriter::kSteps; stop++) {
		FakeRing r(4, 2, true);
		PdoRingView in(r.base(), r.off);
		LatchWriter w{ reinterpret_cast<ecmxf_ring_status_block *>(r.base() + r.off.status) };
		w.publish(statusOf(40));
		w.publish(old);
		for (std::size_t k = 0; k < stop; k++)
			w.step(k, next);
		ecmxf_ring_status got{};
		INFO("writer stopped after " << stop << " of " << LatchWriter::kSteps << " stores");
		REQUIRE(in.status(got));
		// the second count store (step kWords + 1) sends readers to copy 0
		CHECK(sameStatus(got, stop >= LatchWriter::kWords + 2 ? next : old));
	}
}

TEST_CASE("pdo ring: the status block is read whole while the kernel writes it", "[pdo][ring]")
{
	FakeRing r(4, 2, true);
	PdoRingView in(r.base(), r.off);
	LatchWriter w{ reinterpret_cast<ecmxf_ring_status_block *>(r.base() + r.off.status) };
	w.publish(statusOf(0)); // as the kernel's block is valid from setup on
	std::atomic<bool> stop{ false };
	std::atomic<std::uint32_t> last{ 0 };
	std::thread kernel([&] {
		for (std::uint32_t g = 1; !stop.load(std::memory_order_relaxed); g++) {
			w.publish(statusOf(g));
			last.store(g, std::memory_order_relaxed);
		}
	});
	unsigned torn = 0, backwards = 0;
	std::uint32_t seen = 0;
	for (int k = 0; k < 200000; k++) {
		ecmxf_ring_status s{};
		if (!in.status(s))
			continue; // the writer finished 64 updates during the reads
		if (!sameStatus(s, statusOf(s.generation)))
			torn++;
		if (s.generation < seen)
			backwards++;
		seen = s.generation;
	}
	stop = true;
	kernel.join();
	CHECK(torn == 0);
	CHECK(backwards == 0);
	// with the writer at rest, a read gives exactly its last status
	ecmxf_ring_status s{};
	REQUIRE(in.status(s));
	CHECK(sameStatus(s, statusOf(last.load())));
}
