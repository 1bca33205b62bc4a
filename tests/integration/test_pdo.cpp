// SPDX-License-Identifier: MIT
// Process data: the PDO configuration commands, the FIFO commands, the
// direct image access and the cyclic FIFO exchange through Cyclic and
// ProcessImage, on the device of ECMXF_TEST_URI.
//
// Expected values: the EST-584's default mapping (manual 5.4.1: RxPDO
// 0x1600 = 0x6040/16, 0x607A/32, 0x60B0/32, 0x60B8/16), the frame sizes
// 25/35 of the test network, the good working counter 3 + 2 x 3 = 9 (both
// manuals under ECAT_PDO_WC_GET), the FIFO budget RxCount x 25 + TxCount x
// 35 <= 0x4000, and the dio's loopback (est584x2-io-loopback.net: its
// input byte is its output byte).

#include <catch2/catch.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <set>
#include <vector>

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "integration.hpp"

using namespace std::chrono_literals;
using ecmxf::kAllSlaves;
using ecmxf::State;
using integ::Rig;

TEST_CASE("PDO: the mapping read back, the FIFO set up, the image read and written directly", "[pdo]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	integ::initBus(d);
	d.bus().stateSet(kAllSlaves, State::PreOp);

	const ecmxf::PdoConfig rx = d.bus().pdoConfigRead(0, 0x1C12);
	CHECK(rx.slave == 0);
	CHECK(rx.assignIndex == 0x1C12);
	CHECK(rx.pdoCount == 1);
	CHECK(rx.complete());
	REQUIRE(rx.pdos.size() == 1);
	CHECK(rx.pdos[0].index == 0x1600);
	const std::vector<ecmxf::PdoMapEntry> want{
		{ 0x6040, 0, 16 }, { 0x607A, 0, 32 }, { 0x60B0, 0, 32 }, { 0x60B8, 0, 16 }
	};
	CHECK(rx.pdos[0].entries == want);
	const ecmxf::PdoConfig tx = d.bus().pdoConfigRead(1, 0x1C13);
	REQUIRE(tx.pdos.size() == 1);
	CHECK(tx.pdos[0].index == 0x1A00);
	CHECK(tx.pdos[0].entries.size() == 6);
	CHECK(tx.pdos[0].entries[0] == ecmxf::PdoMapEntry{ 0x6041, 0, 16 });
	CHECK(d.bus().pdoConfigGet().assignIndex == 0x1C13);

	d.bus().stateSet(kAllSlaves, State::SafeOp);
	const ecmxf::FifoPackSizes ps = d.pdo().fifoPackSizes();
	CHECK(ps.rxPdoBytes == 25);
	CHECK(ps.txPdoBytes == 35);
	// depths within the budget (25 x 100 + 35 x 150 <= 0x4000), read back
	d.pdo().fifoSetCounts(100, 150);
	CHECK(d.pdo().fifoRxCount() == 100);
	CHECK(d.pdo().fifoTxCount() == 150);
	d.pdo().fifoSetCounts(64, 64);
	CHECK(d.pdo().fifoRxCount() == 64);
	CHECK(d.pdo().fifoTxCount() == 64);
	const ecmxf::Error e = integ::thrown([&] { d.pdo().fifoSetRxCount(0); });
	CHECK(e.errnoValue() == EINVAL);
	ecmxf::FifoThresholds th;
	th.txHighEnabled = true;
	th.txHigh = 32;
	d.pdo().fifoSetThresholds(th);
	d.pdo().fifoSetThresholds({});
	d.pdo().fifoInit();
	d.pdo().fifoClear(ecmxf::FifoSelect::Both);

	// the direct image (FIFO off): outputs pre-loaded, inputs read
	d.pdo().fifoEnable(false);
	std::vector<std::uint8_t> out(25, 0);
	out[24] = 0x5A; // the dio's output byte
	d.pdo().write(out);
	d.bus().stateSet(kAllSlaves, State::Op);
	// the dio copies its outputs to its inputs every bus cycle in OP
	std::vector<std::uint8_t> in;
	for (int i = 0; i < 200; i++) {
		in = d.pdo().writeRead(out);
		if (in.size() == 35 && in[34] == 0x5A)
			break;
		d.link().sleepFor(1ms);
	}
	REQUIRE(in.size() == 35);
	CHECK(in[34] == 0x5A);
	CHECK(d.pdo().read().size() == 35);
	// and the FIFO path by hand: one RxPDO frame in, TxPDO frames out
	d.pdo().fifoClear();
	d.pdo().fifoEnable(true);
	out[24] = 0xC3;
	const ecmxf::PdoFifoResult w = d.pdo().fifoExchange(out, 1, false);
	CHECK(w.allWritten);
	CHECK(w.framesRead == 0);
	ecmxf::PdoFifoResult got;
	for (int i = 0; i < 200; i++) {
		d.link().sleepFor(2ms);
		got = d.pdo().fifoExchange({}, 0, true);
		if (got.framesRead && got.inputs[(got.framesRead - 1) * 35 + 34] == 0xC3)
			break;
	}
	REQUIRE(got.framesRead > 0);
	CHECK(got.inputs.size() == got.framesRead * 35);
	CHECK(got.inputs[(got.framesRead - 1) * 35 + 34] == 0xC3);
	d.pdo().fifoEnable(false);
	CHECK(d.pdo().workingCounter() == 9);
}

TEST_CASE("cyclic: a few hundred FIFO cycles, the WKC right, the dio's inputs follow its outputs", "[pdo][cyclic]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	ecmxf::Master m(d);
	m.bringUp(integ::masterConfig(d));
	ecmxf::ProcessImage image(m.pdos());
	auto dout = image.output<std::uint8_t>(2, 0x7000, 1);
	auto din = image.input<std::uint8_t>(2, 0x6000, 1);
	auto sw0 = image.input<std::uint16_t>(0, 0x6041, 0);
	ecmxf::CyclicConfig cc = integ::cyclicConfig(r.u);
	cc.wkcEvery = 10;
	ecmxf::Cyclic cyc(d, image, cc);
	CHECK(cyc.packSizes().rxPdoBytes == 25);
	CHECK(cyc.packSizes().txPdoBytes == 35);
	CHECK(cyc.expectedWkc() == 9);
	CHECK(cyc.rxFill() == 2);
	const auto t0 = d.link().now();
	cyc.start();

	// outputs 1, 2, 3... (never 0); every input seen must be an output
	// written before it, or the 0 from before the first frame
	constexpr unsigned kCycles = 200;
	std::set<std::uint8_t> written;
	std::vector<std::uint8_t> seen;
	unsigned errors = 0, wkcReads = 0, wkcBad = 0;
	for (unsigned k = 0; k < kCycles; k++) {
		const auto v = static_cast<std::uint8_t>(k % 250 + 1);
		dout.set(v);
		written.insert(v);
		const ecmxf::CycleResult &res = cyc.cycle();
		if (res.error) {
			errors++;
			UNSCOPED_INFO("cycle " << k << ": " << res.message);
		}
		if (res.wkcRead) {
			wkcReads++;
			wkcBad += res.wkc != 9;
		}
		if (res.inputsUpdated) {
			const std::uint8_t in = din.get();
			if (in != 0 && !written.count(in)) {
				FAIL_CHECK("cycle " << k << ": dio input " << unsigned{ in } << " was never written");
			}
			if (seen.empty() || seen.back() != in)
				seen.push_back(in);
		}
		(void)cyc.waitNextCycle();
	}
	// then hold one value until it comes back
	dout.set(0xA5);
	bool back = false;
	for (unsigned k = 0; k < 300 && !back; k++) {
		const ecmxf::CycleResult &res = cyc.cycle();
		errors += res.error != 0;
		back = res.inputsUpdated && din.get() == 0xA5;
		(void)cyc.waitNextCycle();
	}
	const ecmxf::CyclicStats st = cyc.stats();
	const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(d.link().now() - t0).count();
	cyc.stop();
	std::printf("note: cyclic: %llu cycles, %llu commands, %lld ms, %llu late, %llu rx refusals, %llu tx "
		    "overflows\n",
		    static_cast<unsigned long long>(st.cycles), static_cast<unsigned long long>(st.commands),
		    static_cast<long long>(ms), static_cast<unsigned long long>(st.lateCycles),
		    static_cast<unsigned long long>(st.rxRefusals), static_cast<unsigned long long>(st.txOverflows));
	CHECK(errors == 0);
	CHECK(back);
	CHECK(st.failedCycles == 0);
	CHECK(st.wkcMismatches == 0);
	CHECK(wkcReads >= kCycles / 10);
	CHECK(wkcBad == 0);
	CHECK(st.framesPopped > 0);
	CHECK(st.framesPushed >= kCycles);
	// the inputs moved along with the outputs: many distinct values came back
	CHECK(seen.size() > 10);
	// the drives answered too: statusword SWITCH ON DISABLED (0x40 | bit 4
	// voltage | bit 9 remote = 0x0250, sim-slaves.rst)
	CHECK(sw0.get() == 0x0250);
	INFO("cycles " << st.cycles << ", late " << st.lateCycles << ", rx refusals " << st.rxRefusals
		       << ", tx overflows " << st.txOverflows);
	CHECK(st.cycles >= kCycles);
}
