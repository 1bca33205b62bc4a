// SPDX-License-Identifier: MIT
// ecmxf::RecorderSnapshot and ecmxf::SnapshotExchange
// (include/ecmxf/scope/snapshot.hpp): the latest samples, the state and
// the count copied, bounded by the room and by what is asked; the triple
// buffer's hand-over in one thread (latest wins, pending until taken), and
// between a writer sampling a recorder and a reader checking every
// snapshot it takes is whole (run under -fsanitize=thread too:
// Documentation/scope.rst).

#include <catch2/catch.hpp>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <span>
#include <thread>
#include <vector>

#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/scope/snapshot.hpp>

#include "../common/thrown.hpp"

using ecmxftest::thrown;

namespace {

std::vector<double> list(std::span<const double> s)
{
	return { s.begin(), s.end() };
}

/// A recorder of two value signals: a = i, b = -i at sample i.
struct Two {
	std::int64_t a = 0, b = 0;
	ecmxf::Recorder rec;
	explicit Two(std::size_t capacity, ecmxf::RecorderTrigger t = {}) : rec(capacity)
	{
		rec.addValue("a", "inc", &a);
		rec.addValue("b", "", &b);
		rec.arm(t);
	}
	void sample(int n)
	{
		for (int i = 0; i < n; i++) {
			a = static_cast<std::int64_t>(rec.size());
			b = -a;
			(void)rec.sample(std::chrono::milliseconds(rec.size()));
		}
	}
};

} // namespace

TEST_CASE("scope snapshot: the latest samples of each signal, the state and the count")
{
	Two t(100);
	ecmxf::RecorderSnapshot s(2, 4);
	CHECK(s.signalRoom() == 2);
	CHECK(s.sampleRoom() == 4);
	CHECK(s.signals() == 0);
	CHECK(s.values(0).empty());
	s.take(t.rec, 4); // nothing sampled yet
	CHECK(s.state() == ecmxf::RecorderState::Armed);
	CHECK(s.size() == 0);
	CHECK(s.signals() == 2);
	CHECK(s.values(0).empty());
	t.sample(10);
	s.take(t.rec, 4);
	CHECK(s.state() == ecmxf::RecorderState::Recording);
	CHECK(s.triggered());
	CHECK(!s.done());
	CHECK(s.size() == 10);
	CHECK(list(s.values(0)) == std::vector<double>{ 6, 7, 8, 9 });
	CHECK(list(s.values(1)) == std::vector<double>{ -6, -7, -8, -9 });
	CHECK(s.values(2).empty());
	// more asked than the room: the room's
	s.take(t.rec, 1000);
	CHECK(s.values(0).size() == 4);
	// fewer samples and signals asked
	s.take(t.rec, 3, 1);
	CHECK(s.signals() == 1);
	CHECK(list(s.values(0)) == std::vector<double>{ 7, 8, 9 });
	CHECK(s.values(1).empty());
	t.rec.finish();
	s.take(t.rec, 2);
	CHECK(s.done());
	CHECK(list(s.values(1)) == std::vector<double>{ -8, -9 });
}

TEST_CASE("scope snapshot: fewer samples than asked, less room than signals, a bad room")
{
	Two t(100);
	t.sample(2);
	ecmxf::RecorderSnapshot s(1, 2000);
	s.take(t.rec, 2000);
	CHECK(s.signals() == 1); // the room: one signal
	CHECK(list(s.values(0)) == std::vector<double>{ 0, 1 });
	CHECK(s.values(1).empty());
	// a trigger not come: waiting, not triggered
	ecmxf::RecorderTrigger trig;
	trig.edge = ecmxf::TriggerEdge::Rising;
	trig.signal = "a";
	trig.level = 1000;
	trig.preSamples = 2;
	Two w(10, trig);
	w.sample(3);
	s.take(w.rec, 10);
	CHECK(s.state() == ecmxf::RecorderState::Armed);
	CHECK(!s.triggered());
	CHECK(s.size() == 2); // the pre-trigger samples kept
	CHECK(list(s.values(0)) == std::vector<double>{ 1, 2 });
	CHECK(thrown([] { ecmxf::RecorderSnapshot bad(1, 0); }).errnoValue() == EINVAL);
	CHECK(thrown([] { ecmxf::RecorderSnapshot bad(1, 1'000'001); }).errnoValue() == EINVAL);
	ecmxf::RecorderSnapshot none(0, 1); // no signal: only the state and the count
	none.take(t.rec, 1);
	CHECK(none.signals() == 0);
	CHECK(none.size() == 2);
}

TEST_CASE("scope snapshot exchange: the latest published is taken once, pending until then")
{
	Two t(100);
	ecmxf::SnapshotExchange x(2, 10);
	CHECK(x.take() == nullptr);
	CHECK(!x.pending());
	t.sample(1);
	x.back().take(t.rec, 10);
	x.publish();
	CHECK(x.pending());
	const ecmxf::RecorderSnapshot *s = x.take();
	REQUIRE(s != nullptr);
	CHECK(!x.pending());
	CHECK(s->size() == 1);
	CHECK(x.take() == nullptr); // nothing new
	// two published before a take: the second is taken, the first skipped
	for (int i = 0; i < 2; i++) {
		t.sample(1);
		x.back().take(t.rec, 10);
		x.publish();
	}
	s = x.take();
	REQUIRE(s != nullptr);
	CHECK(s->size() == 3);
	CHECK(list(s->values(0)) == std::vector<double>{ 0, 1, 2 });
	// the writer's buffer is never the one the reader holds
	for (int i = 0; i < 5; i++) {
		CHECK(&x.back() != s);
		x.back().take(t.rec, 10);
		x.publish();
	}
	CHECK(list(s->values(0)) == std::vector<double>{ 0, 1, 2 }); // still the reader's, untouched
	CHECK(x.take()->size() == 3);
}

TEST_CASE("scope snapshot exchange: a writer thread and a reader thread, every snapshot taken whole")
{
	// the writer samples a = i and publishes a copy of the latest 50 after
	// each sample; the reader checks each copy it takes: consecutive
	// values ending at size() - 1, the sizes growing
	constexpr int kSamples = 20000;
	Two t(kSamples);
	ecmxf::SnapshotExchange x(2, 50);
	std::atomic<bool> done{ false };
	int taken = 0, bad = 0;
	std::size_t lastSize = 0;
	std::thread reader([&] {
		for (;;) {
			const bool end = done.load(std::memory_order_acquire);
			if (const ecmxf::RecorderSnapshot *s = x.take()) {
				taken++;
				const auto v = s->values(0);
				const auto w = s->values(1);
				bad += s->size() < lastSize || v.size() != std::min<std::size_t>(50, s->size()) ||
				       w.size() != v.size();
				for (std::size_t i = 0; i < v.size(); i++)
					bad += v[i] != static_cast<double>(s->size() - v.size() + i) || w[i] != -v[i];
				lastSize = s->size();
			} else if (end) {
				break;
			}
		}
	});
	for (int i = 0; i < kSamples; i++) {
		t.sample(1);
		x.back().take(t.rec, 50);
		x.publish();
	}
	done.store(true, std::memory_order_release);
	reader.join();
	CHECK(bad == 0);
	CHECK(taken >= 1);
	CHECK(lastSize == static_cast<std::size_t>(kSamples)); // the last published is always taken
}
