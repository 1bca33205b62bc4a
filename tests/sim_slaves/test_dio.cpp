// SPDX-License-Identifier: MIT
// The digital I/O terminal: no mailbox, outputs applied only in OP, inputs
// in SAFE-OP and OP, WKC contributions, options.

#include "helpers.hpp"

using namespace th;
using ecmxf::sim::AlState;
using ecmxf::sim::DioModel;

TEST_CASE("DIO: no mailbox: SDO answers 0x08000023, no FoE, no BOOT (0x0015)")
{
	auto s = make("dio");
	CHECK(!s->hasCoE());
	CHECK(!s->hasFoE());
	CHECK(s->dcAssignActivate() == 0);
	reach(*s, AlState::PreOp);
	std::vector<std::uint8_t> out;
	CHECK(s->sdoUpload(0x1000, 0, false, out) == 0x08000023);
	CHECK(s->sdoDownload(0x1C12, 0, false, le(0, 1)) == 0x08000023);
	CHECK(s->foeRead("log.txt", out) != 0);
	CHECK(!s->popEmergency());
	s->alControl(0x01);
	s->alControl(0x03);
	CHECK(s->alStatus() == (0x01 | 0x10));
	CHECK(s->alStatusCode() == 0x0015);
}

TEST_CASE("DIO: 1 output byte and 1 input byte by default, as PDOs 0x1600/0x1A00")
{
	auto s = make("dio");
	CHECK(s->outputBytes() == 1);
	CHECK(s->inputBytes() == 1);
	const auto rx = s->rxPdos();
	REQUIRE(rx.size() == 1);
	CHECK(rx[0].index == 0x1600);
	REQUIRE(rx[0].entries.size() == 1);
	CHECK(rx[0].entries[0].index == 0x7000);
	CHECK(rx[0].entries[0].subindex == 1);
	CHECK(rx[0].entries[0].bits == 8);
	const auto tx = s->txPdos();
	REQUIRE(tx.size() == 1);
	CHECK(tx[0].index == 0x1A00);
	CHECK(tx[0].entries[0].index == 0x6000);

	// SII: no mailbox; SyncM category: SM0 outputs at 0x0F00, SM1 inputs at 0x1000
	const auto w = s->sii();
	CHECK(w[0x1C] == 0);
	std::size_t p = 0x40;
	bool found = false;
	while (w[p] != 0xFFFF) {
		if (w[p] == 41) {
			found = true;
			CHECK(w[p + 1] == 8);         // two SMs, 4 words each
			CHECK(w[p + 2] == 0x0F00);    // SM0 start
			CHECK(w[p + 3] == 1);         // length
			CHECK((w[p + 5] >> 8) == 3);  // type: outputs
			CHECK(w[p + 6] == 0x1000);    // SM1 start
			CHECK((w[p + 9] >> 8) == 4);  // type: inputs
		}
		p += 2u + w[p + 1];
	}
	CHECK(found);
}

TEST_CASE("DIO: outputs reach the terminals only in OP, inputs are read in SAFE-OP and OP")
{
	auto s = make("dio");
	auto *io = dynamic_cast<DioModel *>(s.get());
	REQUIRE(io);
	reach(*s, AlState::PreOp);
	io->setInput(3, true);
	io->setInput(7, true);
	std::vector<std::uint8_t> in{ 0x5A };
	CHECK(cycle(*s, { 0xA5 }, &in) == 0); // PRE-OP: no process data
	CHECK(in[0] == 0x5A);                 // untouched
	CHECK(io->outputs()[0] == 0);

	s->alControl(0x04);
	CHECK(cycle(*s, { 0xA5 }, &in) == 1); // SAFE-OP: inputs only
	CHECK(in[0] == 0x88);
	CHECK(io->outputs()[0] == 0);

	s->alControl(0x08);
	REQUIRE(s->alStatus() == 0x08);
	CHECK(cycle(*s, { 0xA5 }, &in) == 3);
	CHECK(io->outputs()[0] == 0xA5);
	CHECK(cycle(*s, { 0xA5 }, &in, 1ms, false) == 1); // no valid outputs: kept, no +2
	CHECK(io->outputs()[0] == 0xA5);

	io->setInput(3, false);
	const std::uint8_t bytes[] = { 0x01, 0xFF };
	io->setInputs(bytes); // the extra byte is ignored
	CHECK(io->inputs()[0] == 0x01);

	s->alControl(0x04);
	CHECK(io->outputs()[0] == 0); // safe state when OP is left
}

TEST_CASE("DIO options: sizes, loopback, WKC of one-directional terminals")
{
	auto s = make("dio", { { "outputs", "4" }, { "inputs", "2" }, { "loopback", "yes" } });
	auto *io = dynamic_cast<DioModel *>(s.get());
	CHECK(s->outputBytes() == 4);
	CHECK(s->inputBytes() == 2);
	reach(*s, AlState::Op);
	std::vector<std::uint8_t> in;
	CHECK(cycle(*s, { 0x11, 0x22, 0x33, 0x44 }, &in) == 3);
	CHECK(in == std::vector<std::uint8_t>{ 0x11, 0x22 });
	CHECK(io->outputs().size() == 4);
	CHECK(io->outputs()[3] == 0x44);

	auto o = make("dio", { { "inputs", "0" } });
	reach(*o, AlState::Op);
	CHECK(cycle(*o, { 1 }) == 2);
	auto i = make("dio", { { "outputs", "0" }, { "inputs", "3" } });
	reach(*i, AlState::Op);
	CHECK(cycle(*i) == 1);
	CHECK(i->rxPdos().empty());

	CHECK_THROWS_WITH(make("dio", { { "outputs", "200" } }), Catch::Contains("outputs"));
	CHECK_THROWS_WITH(make("dio", { { "loopback", "maybe" } }), Catch::Contains("loopback"));
	CHECK_THROWS_WITH(make("dio", { { "home_switch", "1" } }),
			  Catch::Contains("unknown option 'home_switch'"));
}
