// SPDX-License-Identifier: MIT
//
// A scripted stand-in for the ECM-XF, just enough to exercise the exchange
// rules of the protocol core's engine: responses one exchange late, a
// repeated (index, code) runs as INFO_UPDATE, async commands busy for a
// number of exchanges, and faults injected on the MISO side.  The full
// simulator is lib/sim; this one is small enough to reason about in a test.

#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include <catch2/catch.hpp>

#include "ecmxf-proto.h"

namespace fake {

enum class Fault {
	None,
	CheckWord,	// flip a byte of the check word
	StartWord,	// wrong start word
	EndWord,	// wrong end word
	NotReady,	// check word 0x87654321
	DataByte,	// flip a byte inside the data section
};

struct Answer {
	std::uint8_t ret = 0;
	std::vector<std::uint8_t> data;
};

class Chip
{
public:
	unsigned dataSize = ECMXF_DATA_DEFAULT;
	ecmxf_check check = ECMXF_CHECK_FIXED;

	// How the chip answers an immediate command.
	std::function<Answer(const ecmxf_cmd_hdr &, const std::uint8_t *)> handler =
		[](const ecmxf_cmd_hdr &h, const std::uint8_t *) {
			return Answer{ static_cast<std::uint8_t>(h.code + 1), {} };
		};

	// Async behaviour: exchanges the chip stays busy, and whether it fails.
	int asyncBusyExchanges = 3;
	bool asyncFails = false;
	int busyLeft = 0;		// > 0: an async command is running

	// Hold every answer back for this many extra exchanges (stale headers).
	int answerLag = 0;
	// Never answer at all (the chip seems silent; headers stay stale).
	bool silent = false;

	std::deque<Fault> faults;	// applied to the next responses, in order
	std::vector<std::vector<std::uint8_t>> mosiLog;
	std::vector<ecmxf_cmd_hdr> cmdLog;	// decoded valid command packets
	std::vector<ecmxf_cmd_hdr> executed;	// commands actually executed
	std::uint8_t errStatus = 0;
	std::uint8_t ecatState = ECMXF_ECAT_INIT;
	int mosiBad = 0;

	bool resetPending = false;	// next response is a NOP (chip restarted)

	// Firmware variants: the CRC covers the header and the valid data only
	// (NEXTW's example host code); the fixed word is taken in while a CRC
	// is in force for every command (false: SPI_RECONFIG_OP only, and
	// CRC_TYPE_SET when crcSetFixed); check types the chip refuses
	// (bit per type: command error, no switch); valid packets dropped as if
	// their check word were bad.
	bool validCover = false;
	bool fixedForAll = true;
	bool crcSetFixed = false;
	unsigned refuseTypes = 0;
	std::function<bool(const ecmxf_cmd_hdr &)> dropCmd;

	std::size_t pktSize() const { return ECMXF_PKT_SIZE(dataSize); }

	// The codec's check argument for the chip's type and coverage.
	ecmxf_check codecCheck() const
	{
		unsigned c = check;
		if (validCover && check != ECMXF_CHECK_FIXED)
			c |= ECMXF_CHECK_COVER_VALID;
		return static_cast<ecmxf_check>(c);
	}

	// One full-duplex exchange.
	std::vector<std::uint8_t> exchange(const std::vector<std::uint8_t> &mosi)
	{
		mosiLog.push_back(mosi);
		std::vector<std::uint8_t> miso = powerOn_ ? initialNop() : pending_;
		powerOn_ = false;

		// time passes for the running async command
		if (busyLeft > 0 && --busyLeft == 0 && asyncFails)
			errStatus |= ECMXF_ERR_ASYNC;

		process(mosi);
		return applyFault(miso);
	}

	// Encode a response now (used to build the next pending packet).
	std::vector<std::uint8_t> encode(ecmxf_rsp_hdr h, const std::vector<std::uint8_t> &data) const
	{
		std::vector<std::uint8_t> p(pktSize());
		h.ecm_status = static_cast<std::uint8_t>((h.ecm_status & ~ECMXF_STS_CHECK_MASK) |
						  static_cast<unsigned>(check));
		ecmxf_encode_rsp(p.data(), p.size(), codecCheck(), &h, data.data(), data.size());
		return p;
	}

private:
	bool powerOn_ = true;		// the first response is the power-on NOP
	std::vector<std::uint8_t> pending_;
	bool havePrev_ = false;
	std::uint8_t prevIndex_ = 0;
	std::uint8_t prevCode_ = 0;
	std::deque<std::vector<std::uint8_t>> lagged_;

	std::vector<std::uint8_t> initialNop() const
	{
		ecmxf_rsp_hdr h{};
		h.ecm_status = ECMXF_STS_NOP;
		return encode(h, {});
	}

	ecmxf_rsp_hdr header() const
	{
		ecmxf_rsp_hdr h{};
		h.ecat_state = ecatState;
		h.err_status = errStatus;
		if (busyLeft > 0)
			h.ecm_status |= ECMXF_STS_BUSY;
		return h;
	}

	void process(const std::vector<std::uint8_t> &mosi)
	{
		ecmxf_cmd_hdr c{};
		const std::uint8_t *data = nullptr;
		// SPI_RECONFIG_OP is sent with the fixed check word
		ecmxf_fault f = ecmxf_decode_cmd(mosi.data(), mosi.size(), codecCheck(), &c, &data);
		if (f == ECMXF_FAULT_CHECK) {
			f = ecmxf_decode_cmd(mosi.data(), mosi.size(), ECMXF_CHECK_FIXED, &c, &data);
			const bool taken = fixedForAll || c.code == ECMXF_CMD_SPI_RECONFIG_OP ||
					   (crcSetFixed && c.code == ECMXF_CMD_CRC_TYPE_SET);
			if (f == ECMXF_FAULT_NONE && !taken)
				f = ECMXF_FAULT_CHECK;
		}
		if (f == ECMXF_FAULT_NONE && dropCmd && dropCmd(c))
			f = ECMXF_FAULT_CHECK;

		ecmxf_rsp_hdr h = header();
		std::vector<std::uint8_t> out;

		if (f != ECMXF_FAULT_NONE) {
			mosiBad++;
			errStatus |= ECMXF_ERR_SPI_CRC;
			h.err_status = errStatus;
			h.index = prevIndex_;
			queue(encode(h, {}));
			return;
		}
		cmdLog.push_back(c);

		// control byte clears
		if (c.control & ECMXF_CTL_CLR_ASYNC_ERR)
			errStatus &= static_cast<std::uint8_t>(~ECMXF_ERR_ASYNC);
		if (c.control & ECMXF_CTL_CLR_CMD_ERR)
			errStatus &= static_cast<std::uint8_t>(~ECMXF_ERR_CMD);
		if (c.control & ECMXF_CTL_CLR_SPI_CRC_ERR)
			errStatus &= static_cast<std::uint8_t>(~ECMXF_ERR_SPI_CRC);

		if (resetPending) {
			// restart: power-on format, and the next response is a NOP
			resetPending = false;
			havePrev_ = false;
			dataSize = ECMXF_DATA_DEFAULT;
			check = ECMXF_CHECK_FIXED;
			ecmxf_rsp_hdr n{};
			n.ecm_status = ECMXF_STS_NOP;
			pending_ = encode(n, {});
			lagged_.clear();
			return;
		}

		const bool repeat = havePrev_ && c.index == prevIndex_ && c.code == prevCode_;
		havePrev_ = true;
		prevIndex_ = c.index;
		prevCode_ = c.code;

		if (repeat || c.code == ECMXF_CMD_INFO_UPDATE_OP) {
			h = header();
			h.index = c.index;
			h.code = ECMXF_CMD_INFO_UPDATE_OP;
			queue(encode(h, {}));
			return;
		}

		executed.push_back(c);
		h = header();
		h.index = c.index;
		h.code = c.code;
		if (ecmxf_cmd_is_async(c.code, c.param)) {
			if (busyLeft > 0) {
				errStatus |= ECMXF_ERR_CMD;
			} else {
				busyLeft = asyncBusyExchanges;
				if (busyLeft == 0 && asyncFails)
					errStatus |= ECMXF_ERR_ASYNC;
			}
			h = header();
			h.index = c.index;
			h.code = c.code;
			queue(encode(h, {}));
		} else {
			if (c.code == ECMXF_CMD_SPI_RECONFIG_OP)
				dataSize = c.len;	// answer at the new size
			Answer a = handler(c, data);
			h.ret = a.ret;
			h.len = static_cast<std::uint16_t>(a.data.size());
			queue(encode(h, a.data));
		}
		// the chip's own format changes take effect after answering
		if (c.code == ECMXF_CMD_CRC_TYPE_SET) {
			if (c.param > ECMXF_CHECK_CRC32 || (refuseTypes & (1u << c.param)))
				errStatus |= ECMXF_ERR_CMD;
			else
				check = static_cast<ecmxf_check>(c.param);
		}
	}

	void queue(std::vector<std::uint8_t> answer)
	{
		if (silent) {
			// a stale refresh that answers nothing new
			ecmxf_rsp_hdr h = header();
			h.index = static_cast<std::uint8_t>(prevIndex_ + 128);
			h.code = ECMXF_CMD_INFO_UPDATE_OP;
			pending_ = encode(h, {});
			return;
		}
		if (answerLag <= 0) {
			pending_ = std::move(answer);
			return;
		}
		// stale header now; the answer after answerLag more exchanges
		lagged_.push_back(std::move(answer));
		ecmxf_rsp_hdr h = header();
		// an index no command in flight has (two may be: a pipelined pair)
		h.index = static_cast<std::uint8_t>(prevIndex_ + 128);
		h.code = 99;
		pending_ = encode(h, {});
		if (static_cast<int>(lagged_.size()) > answerLag) {
			pending_ = lagged_.front();
			lagged_.pop_front();
		}
	}

	std::vector<std::uint8_t> applyFault(std::vector<std::uint8_t> p)
	{
		if (faults.empty())
			return p;
		Fault f = faults.front();
		faults.pop_front();
		const std::size_t n = p.size() - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
		switch (f) {
		case Fault::None:
			break;
		case Fault::CheckWord:
			p[ECMXF_HDR_SIZE + n] ^= 0x01;
			break;
		case Fault::StartWord:
			p[0] ^= 0xFF;
			break;
		case Fault::EndWord:
			p[p.size() - 1] ^= 0xFF;
			break;
		case Fault::NotReady:
			p[ECMXF_HDR_SIZE + n + 0] = 0x21;
			p[ECMXF_HDR_SIZE + n + 1] = 0x43;
			p[ECMXF_HDR_SIZE + n + 2] = 0x65;
			p[ECMXF_HDR_SIZE + n + 3] = 0x87;
			break;
		case Fault::DataByte:
			p[ECMXF_HDR_SIZE + 3] ^= 0x10;
			break;
		}
		return p;
	}
};


// The engine of the protocol core wired to a fake Chip: the owner loop of
// Documentation/protocol-core.rst in a few lines, for the engine's tests.
struct Link {
	ecmxf_engine e{};
	Chip chip;
	std::uint64_t now = 1'000'000;
	std::uint64_t stepNs;	// virtual time per exchange
	unsigned events = 0;	// every event seen so far

	explicit Link(std::uint64_t step = 200'000) : stepNs(step)
	{
		ecmxf_engine_init(&e, ECMXF_DATA_DEFAULT, ECMXF_CHECK_FIXED);
	}

	// One exchange; returns the events of this exchange.
	unsigned exchange()
	{
		if (now < ecmxf_engine_not_before(&e))
			now = ecmxf_engine_not_before(&e);
		const std::size_t n = ecmxf_engine_pkt_size(&e);
		std::vector<std::uint8_t> tx(n);
		REQUIRE(ecmxf_engine_next(&e, now, tx.data(), n) == 0);
		std::vector<std::uint8_t> rx = chip.exchange(tx);
		REQUIRE(rx.size() == n);
		now += stepNs;
		const unsigned ev = ecmxf_engine_input(&e, now, rx.data(), rx.size());
		events |= ev;
		return ev;
	}

	// Exchanges until @x is final; returns the number of exchanges.
	int run(ecmxf_xfer &x, int max = 100000)
	{
		int n = 0;
		while (x.status == -EINPROGRESS && n < max) {
			exchange();
			n++;
		}
		return n;
	}

	int submit(ecmxf_xfer &x) { return ecmxf_engine_submit(&e, &x, now); }

	// Runs one command to its end; returns its status.
	int cmd(std::uint8_t code, std::uint8_t param = 0, const std::vector<std::uint8_t> &tx = {})
	{
		ecmxf_xfer x{};
		x.hdr.code = code;
		x.hdr.param = param;
		x.hdr.len = static_cast<std::uint16_t>(tx.size());
		x.tx_data = tx.empty() ? nullptr : tx.data();
		x.tx_len = static_cast<std::uint16_t>(tx.size());
		REQUIRE(submit(x) == 0);
		run(x);
		return x.status;
	}

	const ecmxf_cmd_hdr &lastMosi() const { return chip.cmdLog.back(); }
};

} // namespace fake
