// SPDX-License-Identifier: MIT
/*
 * fuzz_sk_frame.cpp - libFuzzer target: the ECM-SK slot protocol core
 *
 * Everything an ECM-SK board (or a host program) can hand to
 * lib/core/ecmsk-*.c: command frames through ecmsk_link_prepare(),
 * response frames through ecmsk_link_complete() and every slot decoder.
 * The input is read as:
 *
 *   [0]   bit 0: 16-byte slots (else 12); bit 1: TX CRC; bit 2: RX CRC
 *   then per exchange (at most kMaxSteps):
 *   ctl   bits 2-0: patches to the command frame, bits 5-3: patches to
 *         the response frame (3 bytes each: offset le16 % frame size,
 *         value); bit 6: seal the response's CRC; bit 7: zero the command
 *         frame first
 *   dt    the clock moves by dt * 10 us before the exchange
 *   patches
 *
 * Invariants (abort() on violation): prepare() returns 0, -EINVAL or
 * -EBUSY and changes nothing on error; a prepared frame carries its CRC
 * (TX CRC) or 0 in byte 3; complete() returns 0, or -EBADMSG exactly when
 * RX CRC is on and the CRC is wrong; a completed long command is no longer
 * pending and its error is one the header documents; every slot decodes
 * and re-encodes to the same bytes (the CRC byte and the SDO slot's
 * reserved byte 5 aside).
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ecmsk-proto.h"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

constexpr unsigned kMaxSteps = 64;

[[noreturn]] void fail(const char *what)
{
	std::fprintf(stderr, "fuzz_sk_frame: invariant violated: %s (input %s)\n", what,
		     ecmxf_fuzz_context ? ecmxf_fuzz_context : "?");
	std::abort();
}

void require(bool ok, const char *what)
{
	if (!ok)
		fail(what);
}

bool errIn(int e, std::initializer_list<int> ok)
{
	for (int o : ok)
		if (e == o)
			return true;
	return false;
}

void roundTrip(const ecmsk_geom &g, const std::vector<std::uint8_t> &f)
{
	std::vector<std::uint8_t> out(g.frame_size, 0);
	ecmsk_ecm_rsp e{};
	ecmsk_get_ecm(&g, f.data(), &e);
	require(ecmsk_put_ecm_rsp(&g, out.data(), &e) == 0, "put_ecm_rsp");
	for (unsigned i = 0; i < g.slot_size; i++)
		if (i != ECMSK_CRC_OFFSET)
			require(out[i] == f[i], "ECM slot round trip");
	for (unsigned s = 1; s <= g.max_slaves; s++) {
		ecmsk_slave_rsp r{};
		require(ecmsk_get_slave(&g, f.data(), s, &r) == 0, "get_slave");
		require(ecmsk_put_slave_rsp(&g, out.data(), s, &r) == 0, "put_slave_rsp");
		if (g.slot_size == ECMSK_SLOT16) {
			ecmsk_hsp2 h{};
			require(ecmsk_get_hsp2(&g, f.data(), s, &h) == 0, "get_hsp2");
		}
		ecmsk_slave_cmd c{};
		require(ecmsk_get_slave_cmd(&g, f.data(), s, &c) == 0, "get_slave_cmd");
	}
	ecmsk_sdo sdo{};
	ecmsk_get_sdo(&g, f.data(), &sdo);
	require(ecmsk_put_sdo_rsp(&g, out.data(), &sdo) == 0, "put_sdo_rsp");
	const std::size_t base = static_cast<std::size_t>(g.sdo_slot) * g.slot_size;
	for (std::size_t i = g.slot_size; i < g.frame_size; i++) {
		if (i == base + 5)
			continue;
		if (i >= base + 12)
			continue; // bytes 12-15 of the SDO slot are reserved
		require(out[i] == f[i], "slot round trip");
	}
	ecmsk_slave_rsp none{};
	require(ecmsk_get_slave(&g, f.data(), 0, &none) == -ERANGE, "slot 0 is not a slave");
	require(ecmsk_get_slave(&g, f.data(), g.max_slaves + 1u, &none) == -ERANGE,
		"the SDO slot is not a slave");
}

void checkDone(const ecmsk_pending &p, bool done, int err, std::initializer_list<int> ok,
	       const char *what)
{
	if (!done)
		return;
	require(!p.active, what);
	require(errIn(err, ok), what);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const unsigned slot = (data[0] & 1) ? ECMSK_SLOT16 : ECMSK_SLOT12;
	const std::uint32_t flags = (data[0] >> 1) & 3;
	ecmsk_link l{};
	require(ecmsk_link_init(&l, slot, flags) == 0, "init");
	const ecmsk_geom g = l.g;
	std::vector<std::uint8_t> mosi(g.frame_size, 0), miso(g.frame_size, 0);
	std::uint64_t now = 0;
	size_t pos = 1;

	for (unsigned step = 0; step < kMaxSteps && pos + 2 <= size; step++) {
		const std::uint8_t ctl = data[pos++];
		now += std::uint64_t{ data[pos++] } * 10'000;
		if (ctl & 0x80)
			std::fill(mosi.begin(), mosi.end(), 0);
		auto patch = [&](std::vector<std::uint8_t> &f, unsigned n) {
			for (unsigned k = 0; k < n && pos + 3 <= size; k++, pos += 3) {
				const unsigned off = (data[pos] | (unsigned{ data[pos + 1] } << 8)) % g.frame_size;
				f[off] = data[pos + 2];
			}
		};
		patch(mosi, ctl & 7);
		patch(miso, (ctl >> 3) & 7);

		const ecmsk_link before = l;
		std::vector<std::uint8_t> sent = mosi;
		const int pr = ecmsk_link_prepare(&l, sent.data(), now, 500'000);
		require(errIn(pr, { 0, -EINVAL, -EBUSY }), "prepare's return");
		if (pr) {
			require(std::memcmp(&before, &l, sizeof(l)) == 0, "prepare failed but changed state");
			continue;
		}
		if (flags & ECMSK_LINK_TX_CRC)
			require(ecmsk_frame_crc_ok(sent.data(), sent.size()), "sent without its CRC");
		else
			require(sent[ECMSK_CRC_OFFSET] == 0, "CRC byte not 0 without TX CRC");
		mosi = sent;

		if (ctl & 0x40)
			ecmsk_frame_seal(miso.data(), miso.size());
		const std::uint64_t ex = l.exchanges;
		ecmsk_result r{};
		const int cr = ecmsk_link_complete(&l, miso.data(), now, &r);
		require(l.exchanges == ex + 1, "exchange not counted");
		const bool crcOk = ecmsk_frame_crc_ok(miso.data(), miso.size());
		if ((flags & ECMSK_LINK_RX_CRC) && !crcOk)
			require(cr == -EBADMSG, "bad response CRC accepted");
		else
			require(cr == 0, "good response refused");
		checkDone(l.ecm, r.state_done, r.state_err, { 0, -ETIMEDOUT, -EBADMSG }, "SET_STATE result");
		checkDone(l.sdo, r.sdo_done, r.sdo_err,
			  { 0, -EIO, -EPROTO, -EACCES, -EBADMSG, -ETIMEDOUT }, "SDO result");
		checkDone(l.home, r.home_done, r.home_err, { 0, -EIO, -EBADMSG, -ETIMEDOUT },
			  "GO_HOME result");
		if (cr == 0) {
			require(l.state == miso[2], "state not taken");
			for (unsigned s = 0; s <= g.slots; s++)
				(void)ecmsk_link_answered(&l, s, miso.data());
		}
		roundTrip(g, miso);
	}
	return 0;
}
