// SPDX-License-Identifier: MIT
// The AL state machine of every model against the AKD2G document (003_...):
// every state x every request, with and without acknowledge, with and
// without a pending error; SM watchdog; SM configuration checks; ESC
// registers and the SII image.

#include "helpers.hpp"

#include <array>

using namespace th;
using ecmxf::sim::AlState;

namespace {

constexpr std::uint8_t I = 0x01, P = 0x02, B = 0x03, S = 0x04, O = 0x08, E = 0x10;

struct Expect {
	std::uint8_t status; // AL status register 0x0130
	std::uint16_t code;  // AL status code 0x0134
};

// The document's table, request by request (AL control bits 3..0 = 0..15),
// for a slave without an error pending:
//  - up only I->P->S->O (and I->B), down to any lower state;
//  - 0x0011 "I->S, I->O, P->O, O->B, S->B, P->B": current status + E
//    (B->P/S/O likewise: BOOT leads only to INIT);
//  - 0x0012 unknown state (0, 5..7, 9..15): I+E, P+E, S+E (an OP slave
//    drops to SAFE-OP, a BOOT slave stays in BOOT);
//  - 0x0015 I->B without bootstrap mailbox: I+E.
// kBootI is the I->B entry of slaves that have a bootstrap mailbox.
constexpr Expect kBootI{ B, 0 };
constexpr std::array<Expect, 16> kFromI{ {
	{ I | E, 0x12 }, { I, 0 }, { P, 0 }, { I | E, 0x15 }, { I | E, 0x11 }, { I | E, 0x12 },
	{ I | E, 0x12 }, { I | E, 0x12 }, { I | E, 0x11 }, { I | E, 0x12 }, { I | E, 0x12 },
	{ I | E, 0x12 }, { I | E, 0x12 }, { I | E, 0x12 }, { I | E, 0x12 }, { I | E, 0x12 },
} };
constexpr std::array<Expect, 16> kFromP{ {
	{ P | E, 0x12 }, { I, 0 }, { P, 0 }, { P | E, 0x11 }, { S, 0 }, { P | E, 0x12 },
	{ P | E, 0x12 }, { P | E, 0x12 }, { P | E, 0x11 }, { P | E, 0x12 }, { P | E, 0x12 },
	{ P | E, 0x12 }, { P | E, 0x12 }, { P | E, 0x12 }, { P | E, 0x12 }, { P | E, 0x12 },
} };
constexpr std::array<Expect, 16> kFromB{ {
	{ B | E, 0x12 }, { I, 0 }, { B | E, 0x11 }, { B, 0 }, { B | E, 0x11 }, { B | E, 0x12 },
	{ B | E, 0x12 }, { B | E, 0x12 }, { B | E, 0x11 }, { B | E, 0x12 }, { B | E, 0x12 },
	{ B | E, 0x12 }, { B | E, 0x12 }, { B | E, 0x12 }, { B | E, 0x12 }, { B | E, 0x12 },
} };
constexpr std::array<Expect, 16> kFromS{ {
	{ S | E, 0x12 }, { I, 0 }, { P, 0 }, { S | E, 0x11 }, { S, 0 }, { S | E, 0x12 },
	{ S | E, 0x12 }, { S | E, 0x12 }, { O, 0 }, { S | E, 0x12 }, { S | E, 0x12 },
	{ S | E, 0x12 }, { S | E, 0x12 }, { S | E, 0x12 }, { S | E, 0x12 }, { S | E, 0x12 },
} };
constexpr std::array<Expect, 16> kFromO{ {
	{ S | E, 0x12 }, { I, 0 }, { P, 0 }, { O | E, 0x11 }, { S, 0 }, { S | E, 0x12 },
	{ S | E, 0x12 }, { S | E, 0x12 }, { O, 0 }, { S | E, 0x12 }, { S | E, 0x12 },
	{ S | E, 0x12 }, { S | E, 0x12 }, { S | E, 0x12 }, { S | E, 0x12 }, { S | E, 0x12 },
} };

Expect expected(std::uint8_t from, unsigned req, bool hasBoot)
{
	switch (from) {
	case I:
		return req == 3 && hasBoot ? kBootI : kFromI[req];
	case P:
		return kFromP[req];
	case B:
		return kFromB[req];
	case S:
		return kFromS[req];
	default:
		return kFromO[req];
	}
}

// A request that makes a slave in state s set the error flag (0x0011).
std::uint8_t invalidRequest(std::uint8_t s)
{
	switch (s) {
	case I:
		return S;
	case P:
		return O;
	case B:
		return P;
	default:
		return B; // S->B, O->B
	}
}

struct Model {
	const char *type;
	bool boot;
};
constexpr Model kModels[] = { { "EST-584", false }, { "servo", true }, { "dio", false } };

void checkStatus(const Slave &s, Expect e)
{
	CHECK(unsigned(s.alStatus()) == e.status);
	CHECK(s.alStatusCode() == e.code);
	// the registers say the same
	CHECK(unsigned(s.escRead8(0x0130)) == e.status);
	CHECK(unsigned(s.escRead8(0x0134)) == (e.code & 0xFFu));
	CHECK(unsigned(s.escRead8(0x0135)) == unsigned(e.code >> 8));
}

} // namespace

TEST_CASE("AL state machine: every state x every request follows the AKD2G table")
{
	for (const Model &m : kModels) {
		auto s = make(m.type);
		for (std::uint8_t from : { I, P, B, S, O }) {
			if (from == B && !m.boot)
				continue;
			for (unsigned req = 0; req < 16; req++) {
				for (bool ack : { false, true }) {
					INFO(m.type << " from 0x" << std::hex << unsigned(from) << " request 0x"
						    << req << (ack ? " +ack" : ""));
					reach(*s, static_cast<AlState>(from));
					if (from == S)
						cycle(*s); // outputs arriving: S->O completes at once
					s->alControl(static_cast<std::uint8_t>(req | (ack ? 0x10 : 0)));
					checkStatus(*s, expected(from, req, m.boot));
				}
			}
		}
	}
}

TEST_CASE("AL state machine: a pending error blocks higher requests until acknowledged")
{
	// Rule (documented in sim-slaves.rst, as the EtherCAT slave stack does
	// it): with the error flag set, a request without the acknowledge bit
	// for a higher state is ignored; the current or a lower state is
	// processed and the error flag and code stay; with the acknowledge
	// bit, error and code are cleared and the request is processed.
	for (const Model &m : kModels) {
		auto s = make(m.type);
		for (std::uint8_t from : { I, P, B, S, O }) {
			if (from == B && !m.boot)
				continue;
			for (unsigned req = 0; req < 16; req++) {
				for (bool ack : { false, true }) {
					INFO(m.type << " from 0x" << std::hex << unsigned(from)
						    << "+E request 0x" << req << (ack ? " +ack" : ""));
					reach(*s, static_cast<AlState>(from));
					if (from == S)
						cycle(*s);
					s->alControl(invalidRequest(from));
					const Expect err{ static_cast<std::uint8_t>(from | E), 0x11 };
					checkStatus(*s, err);
					s->alControl(static_cast<std::uint8_t>(req | (ack ? 0x10 : 0)));
					Expect want = expected(from, req, m.boot);
					if (!ack) {
						if (req > from)
							want = err; // ignored
						else if (!(want.status & E))
							want = { static_cast<std::uint8_t>(want.status | E), 0x11 };
					}
					checkStatus(*s, want);
				}
			}
		}
	}
}

TEST_CASE("AL state machine: acknowledging in the current state clears the error")
{
	auto s = make("EST-584");
	reach(*s, AlState::PreOp);
	s->alControl(O); // P->O invalid
	CHECK(s->alStatus() == (P | E));
	s->alControl(S); // higher without ack: ignored
	CHECK(s->alStatus() == (P | E));
	CHECK(s->alStatusCode() == 0x0011);
	s->alControl(P | 0x10);
	CHECK(s->alStatus() == P);
	CHECK(s->alStatusCode() == 0);
	s->alControl(S);
	CHECK(s->alStatus() == S);
}

TEST_CASE("SM watchdog: OP without outputs for longer than 100 ms drops to SAFE-OP+E 0x001B")
{
	for (const char *type : { "EST-584", "servo", "dio" }) {
		INFO(type);
		auto s = make(type);
		reach(*s, AlState::Op);
		// default watchdog: divider 0x09C2 (100 us) x 1000
		CHECK(s->escRead8(0x0400) == 0xC2);
		CHECK(s->escRead8(0x0401) == 0x09);
		CHECK(s->escRead8(0x0420) == 0xE8);
		CHECK(s->escRead8(0x0421) == 0x03);
		for (int i = 0; i < 100; i++)
			cycle(*s, {}, nullptr, 1ms, false); // frames without valid outputs
		CHECK(s->alStatus() == O); // exactly 100 ms: not longer yet
		CHECK((s->escRead8(0x0440) & 1) == 1);
		cycle(*s, {}, nullptr, 1ms, false);
		CHECK(s->alStatus() == (S | E));
		CHECK(s->alStatusCode() == 0x001B);
		CHECK((s->escRead8(0x0440) & 1) == 0);
	}
}

TEST_CASE("SM watchdog: idle time counts, valid outputs retrigger, 0x0420 sets the time")
{
	auto s = make("EST-584");
	reach(*s, AlState::Op);
	idle(*s, 90ms);
	cycle(*s); // retrigger
	idle(*s, 90ms);
	CHECK(s->alStatus() == O);
	// 50 ms watchdog
	s->escWrite8(0x0420, 500 & 0xFF);
	s->escWrite8(0x0421, 500 >> 8);
	cycle(*s);
	idle(*s, 51ms);
	CHECK(s->alStatus() == (S | E));
	CHECK(s->alStatusCode() == 0x001B);
	// disabled watchdog
	reach(*s, AlState::Op);
	s->escWrite8(0x0420, 0);
	s->escWrite8(0x0421, 0);
	idle(*s, 1000ms, 10ms);
	CHECK(s->alStatus() == O);
}

TEST_CASE("SAFE-OP to OP waits for the first valid outputs, and times out with 0x001B")
{
	auto s = make("EST-584");
	reach(*s, AlState::SafeOp);
	s->alControl(O);
	CHECK(s->alStatus() == S); // pending, no error
	CHECK(cycle(*s) == 3);     // the first outputs: OP, applied, WKC 2 + 1
	CHECK(s->alStatus() == O);

	reach(*s, AlState::SafeOp);
	s->alControl(O);
	idle(*s, 100ms);
	CHECK(s->alStatus() == S);
	idle(*s, 1ms);
	CHECK(s->alStatus() == (S | E));
	CHECK(s->alStatusCode() == 0x001B);

	// outputs that stopped long ago do not count
	reach(*s, AlState::SafeOp);
	cycle(*s);
	idle(*s, 150ms);
	s->alControl(O);
	CHECK(s->alStatus() == S);
	cycle(*s);
	CHECK(s->alStatus() == O);
}

TEST_CASE("A slave without outputs goes to OP at once and has no SM watchdog")
{
	auto s = make("dio", { { "outputs", "0" } });
	REQUIRE(s->outputBytes() == 0);
	reach(*s, AlState::SafeOp);
	s->alControl(O);
	CHECK(s->alStatus() == O);
	idle(*s, 500ms, 10ms);
	CHECK(s->alStatus() == O);
}

TEST_CASE("I->P checks a configured mailbox SM0/SM1 (0x0016), P->S the SM2/SM3 lengths (0x001D/0x001E)")
{
	auto s = make("EST-584");
	s->reset();
	auto sm = [&](unsigned n, std::uint16_t start, std::uint16_t len) {
		const auto base = static_cast<std::uint16_t>(0x0800 + 8 * n);
		s->escWrite8(base, static_cast<std::uint8_t>(start));
		s->escWrite8(static_cast<std::uint16_t>(base + 1), static_cast<std::uint8_t>(start >> 8));
		s->escWrite8(static_cast<std::uint16_t>(base + 2), static_cast<std::uint8_t>(len));
		s->escWrite8(static_cast<std::uint16_t>(base + 3), static_cast<std::uint8_t>(len >> 8));
		s->escWrite8(static_cast<std::uint16_t>(base + 6), 1);
	};
	sm(0, 0x1800, 128); // not where the SII says
	sm(1, 0x1080, 128);
	s->alControl(P);
	CHECK(s->alStatus() == (I | E));
	CHECK(s->alStatusCode() == 0x0016);
	sm(0, 0x1000, 128);
	s->alControl(P | 0x10);
	CHECK(s->alStatus() == P);

	sm(2, 0x1100, 11); // default RxPDO is 12 bytes
	sm(3, 0x1400, 17);
	s->alControl(S);
	CHECK(s->alStatus() == (P | E));
	CHECK(s->alStatusCode() == 0x001D);
	sm(2, 0x1100, 12);
	sm(3, 0x1400, 16);
	s->alControl(S | 0x10);
	CHECK(s->alStatus() == (P | E));
	CHECK(s->alStatusCode() == 0x001E);
	sm(3, 0x1400, 17);
	s->alControl(S | 0x10);
	CHECK(s->alStatus() == S);
}

TEST_CASE("ESC registers: station address, alias, DL status, type")
{
	auto s = make("EST-584", { { "alias", "7" } });
	s->reset();
	CHECK(s->escRead8(0x0000) == 0x11);
	CHECK(s->escRead8(0x0012) == 7);
	CHECK(s->escRead8(0x0013) == 0);
	s->escWrite8(0x0012, 9); // read-only for the master
	CHECK(s->escRead8(0x0012) == 7);
	s->escWrite8(0x0010, 0x01);
	s->escWrite8(0x0011, 0x10);
	CHECK(s->escRead8(0x0010) == 0x01);
	CHECK(s->escRead8(0x0011) == 0x10);
	CHECK((s->escRead8(0x0110) & 0x01) == 0x01); // PDI operational: EEPROM loaded
	CHECK((s->escRead8(0x0110) & 0x10) == 0x10); // link on port 0
	s->escWrite8(0x0130, 0x08);                  // AL status is read-only
	CHECK(s->escRead8(0x0130) == I);
	s->escWrite8(0x0120, P); // AL control through the register
	CHECK(s->escRead8(0x0130) == P);
	// DC system time runs with the cycles
	s->idle(1234ns);
	CHECK(s->escRead8(0x0910) == (1234 & 0xFF));
	CHECK(s->escRead8(0x0911) == (1234 >> 8));
}

namespace {

// ETG.2010 SII checksum: CRC-8, polynomial x^8+x^2+x+1, initial 0xFF, over
// the 14 bytes of words 0..6 (written here independently of the model).
std::uint8_t crc8(const std::vector<std::uint16_t> &w)
{
	unsigned crc = 0xFF;
	for (unsigned i = 0; i < 14; i++) {
		crc ^= (unsigned{ w[i / 2] } >> (8 * (i % 2))) & 0xFFu;
		for (int b = 0; b < 8; b++)
			crc = (crc & 0x80) ? ((crc << 1) ^ 0x07) & 0xFF : (crc << 1) & 0xFF;
	}
	return static_cast<std::uint8_t>(crc);
}

std::uint32_t dword(const std::vector<std::uint16_t> &w, std::size_t at)
{
	return w[at] | std::uint32_t{ w[at + 1] } << 16;
}

// The strings of the SII strings category (type 10).
std::vector<std::string> siiStrings(const std::vector<std::uint16_t> &w)
{
	std::size_t p = 0x40;
	while (p + 1 < w.size() && w[p] != 0xFFFF) {
		const std::size_t len = w[p + 1];
		if (w[p] == 10) {
			std::vector<std::uint8_t> b;
			for (std::size_t i = 0; i < len; i++) {
				b.push_back(static_cast<std::uint8_t>(w[p + 2 + i]));
				b.push_back(static_cast<std::uint8_t>(w[p + 2 + i] >> 8));
			}
			std::vector<std::string> out;
			std::size_t q = 1;
			for (unsigned n = 0; n < b[0]; n++) {
				out.emplace_back(b.begin() + static_cast<long>(q + 1),
						 b.begin() + static_cast<long>(q + 1 + b[q]));
				q += 1u + b[q];
			}
			return out;
		}
		p += 2 + len;
	}
	return {};
}

} // namespace

TEST_CASE("SII image: identity at words 0x08..0x0F, alias at 0x04, checksum, mailbox, name")
{
	using namespace ecmxf::sim::model;
	struct Case {
		const char *type;
		std::uint32_t product, revision;
		std::uint16_t protocols;
		bool mbx, boot;
		const char *name;
	};
	for (const Case &c : { Case{ "EST-584", kEst584Product, kEst584Revision, 0x0004, true, false,
				     "EST-584" },
			       Case{ "servo", kServoProduct, kServoRevision, 0x000C, true, true,
				     "AKD2G-like servo" },
			       Case{ "dio", kDioProduct, kDioRevision, 0x0000, false, false,
				     "Digital I/O 8 out / 8 in" } }) {
		INFO(c.type);
		auto s = make(c.type, { { "alias", "0x1234" }, { "serial", "4711" } });
		const auto w = s->sii();
		REQUIRE(w.size() >= 64);
		CHECK(w[0x04] == 0x1234);
		CHECK((w[0x07] & 0xFF) == crc8(w));
		CHECK(dword(w, 0x08) == kVendorId);
		CHECK(dword(w, 0x0A) == c.product);
		CHECK(dword(w, 0x0C) == c.revision);
		CHECK(dword(w, 0x0E) == 4711);
		CHECK(w[0x1C] == c.protocols);
		if (c.mbx) {
			CHECK(w[0x18] == 0x1000);
			CHECK(w[0x19] == 128);
			CHECK(w[0x1A] == 0x1080);
			CHECK(w[0x1B] == 128);
		} else {
			CHECK(w[0x18] == 0);
			CHECK(w[0x19] == 0);
		}
		CHECK((w[0x14] != 0) == c.boot);
		CHECK((w[0x15] != 0) == c.boot);
		const auto strings = siiStrings(w);
		CHECK(std::find(strings.begin(), strings.end(), std::string(c.name)) != strings.end());
		CHECK(s->identity().name == c.name);
		CHECK(s->identity().serial == 4711);
		CHECK(s->identity().vendorId == kVendorId);
	}
}

TEST_CASE("SII EEPROM interface: read 4 words, write needs enable, alias from EEPROM at power-on")
{
	auto s = make("EST-584", { { "alias", "5" } });
	s->reset();
	auto cmd = [&](std::uint16_t word, std::uint8_t command) {
		s->escWrite8(0x0504, static_cast<std::uint8_t>(word));
		s->escWrite8(0x0505, static_cast<std::uint8_t>(word >> 8));
		s->escWrite8(0x0503, command);
	};
	auto data16 = [&](unsigned i) {
		return static_cast<std::uint16_t>(s->escRead8(static_cast<std::uint16_t>(0x0508 + 2 * i)) |
						  s->escRead8(static_cast<std::uint16_t>(0x0509 + 2 * i)) << 8);
	};
	cmd(0x08, 0x01); // read vendor id and product code
	CHECK(data16(0) == (ecmxf::sim::model::kVendorId & 0xFFFF));
	CHECK(data16(1) == (ecmxf::sim::model::kVendorId >> 16));
	CHECK(data16(2) == (ecmxf::sim::model::kEst584Product & 0xFFFF));
	CHECK((s->escRead8(0x0503) & 0x80) == 0); // never busy

	// write word 4 without the write-enable bit: error, nothing written
	s->escWrite8(0x0508, 42);
	s->escWrite8(0x0509, 0);
	cmd(0x04, 0x02);
	CHECK((s->escRead8(0x0503) & 0x40) != 0);
	CHECK(s->sii()[0x04] == 5);

	// with write enable; then a matching checksum; alias applies at power-on
	s->escWrite8(0x0502, 0x01);
	cmd(0x04, 0x02);
	CHECK(s->sii()[0x04] == 42);
	auto w = s->sii();
	const std::uint16_t sum = crc8(w);
	s->escWrite8(0x0508, static_cast<std::uint8_t>(sum));
	s->escWrite8(0x0509, 0);
	s->escWrite8(0x0502, 0x01);
	cmd(0x07, 0x02);
	CHECK(s->escRead8(0x0012) == 5); // not yet
	s->reset();
	CHECK(s->escRead8(0x0012) == 42);
	CHECK((s->escRead8(0x0110) & 0x01) == 0x01);

	// a broken checksum: the ESC does not load the configuration
	s->escWrite8(0x0508, static_cast<std::uint8_t>(sum ^ 0xFF));
	s->escWrite8(0x0502, 0x01);
	cmd(0x07, 0x02);
	s->reset();
	CHECK(s->escRead8(0x0012) == 0);
	CHECK((s->escRead8(0x0110) & 0x01) == 0x00);
}
