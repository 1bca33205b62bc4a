// SPDX-License-Identifier: MIT
/*
 * fuzz_sim.cpp - arbitrary MOSI into the simulated chip
 *
 * The simulator must survive whatever a host sends: random bytes, valid
 * packets with arbitrary fields (every command code, parameter, length and
 * payload), wrong sizes, repeats, time passing and faults switched on and
 * off.  It must never crash, hang, read or write out of bounds, or answer
 * with a packet of another size than the one it was sent.
 *
 * Input: a sequence of records, each starting with an op byte:
 *   op%7 == 0  raw: the next bytes (up to a packet) as MOSI, zero-padded
 *   op%7 == 1  command: code, param, d0..d3, len(2), control, payload
 *              length n, n bytes -> a valid packet in the chip's check type
 *   op%7 == 2  repeat the previous MOSI
 *   op%7 == 3  advance time by u16 * 10 us (at most 2 s per input)
 *   op%7 == 4  fault: kind, value
 *   op%7 == 5  wrong size: u16 length (1..1600)
 *   op%7 == 6  valid command with a corrupted byte (index from the input)
 * At most 256 records run per input.
 */
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

#include "ecmxf-proto.h"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

class Reader
{
public:
	Reader(const std::uint8_t *d, std::size_t n) : d_(d), n_(n) {}
	bool empty() const { return pos_ >= n_; }
	std::uint8_t u8() { return pos_ < n_ ? d_[pos_++] : 0; }
	std::uint16_t u16()
	{
		const std::uint16_t lo = u8();
		return static_cast<std::uint16_t>(lo | (u8() << 8));
	}
	std::size_t take(std::uint8_t *out, std::size_t want)
	{
		std::size_t k = 0;
		while (k < want && pos_ < n_)
			out[k++] = d_[pos_++];
		return k;
	}

private:
	const std::uint8_t *d_;
	std::size_t n_;
	std::size_t pos_ = 0;
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	using namespace std::chrono;
	namespace sim = ecmxf::sim;

	if (!data || size == 0)
		return 0;
	Reader in(data, size);
	sim::Chip chip; // the default network: 2 x EST-584 + I/O
	ecmxf_check check = ECMXF_CHECK_FIXED;
	std::vector<std::uint8_t> prev;
	std::uint8_t index = 0;
	nanoseconds budget = seconds(2);

	auto exchange = [&](std::vector<std::uint8_t> mosi) {
		std::vector<std::uint8_t> miso(mosi.size(), 0xEE);
		chip.exchange(mosi, miso);
		FUZZ_ASSERT(miso.size() == mosi.size());
		FUZZ_ASSERT(ecmxf_data_size_valid(static_cast<unsigned>(chip.dataSize())));
		FUZZ_ASSERT(chip.packetSize() == ECMXF_PKT_SIZE(chip.dataSize()));
		// learn the check type the chip uses now from a readable answer
		ecmxf_rsp_hdr h{};
		for (ecmxf_check c : { check, ECMXF_CHECK_FIXED, ECMXF_CHECK_CRC32 }) {
			if (ecmxf_decode_rsp(miso.data(), miso.size(), c, &h, nullptr) ==
			    ECMXF_FAULT_NONE) {
				check = static_cast<ecmxf_check>(h.ecm_status & ECMXF_STS_CHECK_MASK);
				FUZZ_ASSERT(h.len <= miso.size() - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE);
				break;
			}
		}
		prev = std::move(mosi);
	};

	auto command = [&](bool corrupt) {
		ecmxf_cmd_hdr h{};
		h.code = in.u8();
		h.param = in.u8();
		for (auto &b : h.data)
			b = in.u8();
		h.len = in.u16();
		h.control = in.u8();
		h.reserved = static_cast<std::uint16_t>(in.u8() << 8);
		h.index = ++index;
		const std::size_t n = chip.dataSize();
		std::vector<std::uint8_t> payload(std::min<std::size_t>(in.u8() * 6u, n));
		payload.resize(in.take(payload.data(), payload.size()));
		std::vector<std::uint8_t> mosi(chip.packetSize());
		FUZZ_ASSERT(ecmxf_encode_cmd(mosi.data(), mosi.size(), check, &h, payload.data(),
					     payload.size()) == 0);
		if (corrupt)
			mosi[in.u16() % mosi.size()] ^= static_cast<std::uint8_t>(in.u8() | 1);
		exchange(std::move(mosi));
	};

	for (int step = 0; step < 256 && !in.empty(); step++) {
		const std::uint8_t op = in.u8();
		switch (op % 7) {
		case 0: {
			std::vector<std::uint8_t> mosi(chip.packetSize(), 0);
			in.take(mosi.data(), mosi.size());
			exchange(std::move(mosi));
			break;
		}
		case 1:
			command(false);
			break;
		case 2:
			if (prev.size() == chip.packetSize())
				exchange(prev);
			break;
		case 3: {
			const nanoseconds dt = microseconds(in.u16() * 10u);
			if (dt <= budget) {
				budget -= dt;
				chip.advance(dt);
			}
			break;
		}
		case 4: {
			auto &f = chip.faults();
			const std::uint8_t kind = in.u8(), v = in.u8();
			switch (kind % 8) {
			case 0:
				f.mosiBitErrors = v % 4;
				break;
			case 1:
				f.misoBitErrors = v % 4;
				break;
			case 2:
				f.notReady = v % 4;
				break;
			case 3:
				f.int0StuckBusy = v & 1;
				break;
			case 4:
				f.linkLost = v & 1;
				break;
			case 5:
				f.slaveDropped = v < 3 ? v : -1;
				break;
			case 6:
				f.forcedSdoAbort = (v & 1) ? 0x06020000u : 0;
				break;
			default:
				f.asyncStuckBusy = v & 1;
				break;
			}
			break;
		}
		case 5: {
			std::vector<std::uint8_t> mosi(in.u16() % 1600u + 1u, 0x5A);
			std::vector<std::uint8_t> miso(mosi.size());
			chip.exchange(mosi, miso);
			FUZZ_ASSERT(miso.size() == mosi.size());
			break;
		}
		default:
			command(true);
			break;
		}
		(void)chip.int0();
		(void)chip.int1();
		(void)chip.ready();
	}
	return 0;
}
