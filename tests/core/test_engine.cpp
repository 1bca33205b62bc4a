// SPDX-License-Identifier: MIT
// The exchange engine against a scripted fake chip (fake_chip.hpp).

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <set>
#include <vector>

#include "ecmxf-proto.h"
#include "fake_chip.hpp"

namespace {

using Link = fake::Link;

ecmxf_xfer command(std::uint8_t code, std::uint8_t param = 0)
{
	ecmxf_xfer x{};
	x.hdr.code = code;
	x.hdr.param = param;
	return x;
}

} // namespace

TEST_CASE("engine: the first packet is an INFO_UPDATE sync, and the answer arrives one exchange late",
	  "[engine]")
{
	Link l;
	std::uint8_t buf[16];
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	x.rx_buf = buf;
	x.rx_size = sizeof(buf);
	REQUIRE(l.submit(x) == 0);
	CHECK(x.status == -EINPROGRESS);

	// 1: sync INFO_UPDATE (answer: power-on NOP)
	CHECK(l.exchange() == ECMXF_EV_HEADER);
	REQUIRE(l.chip.cmdLog.size() == 1);
	CHECK(l.chip.cmdLog[0].code == ECMXF_CMD_INFO_UPDATE_OP);
	CHECK(x.status == -EINPROGRESS);

	// 2: the command goes out; the answer is the sync's
	l.exchange();
	CHECK(l.lastMosi().code == ECMXF_CMD_ECAT_STATE_GET);
	CHECK(l.lastMosi().param == 0xFF);
	CHECK(x.status == -EINPROGRESS);

	// 3: re-sent with the same (index, code); its answer arrives now
	const unsigned ev = l.exchange();
	CHECK(l.lastMosi().code == ECMXF_CMD_ECAT_STATE_GET);
	CHECK(l.chip.cmdLog[2].index == l.chip.cmdLog[1].index);
	CHECK((ev & ECMXF_EV_CMD_DONE) != 0);
	CHECK(x.status == 0);
	CHECK(x.rsp.code == ECMXF_CMD_ECAT_STATE_GET);
	CHECK(x.rsp.ret == ECMXF_CMD_ECAT_STATE_GET + 1);
	CHECK(x.rsp.index == x.hdr.index);
	// the chip executed the command once: the re-send ran as INFO_UPDATE
	CHECK(l.chip.executed.size() == 1);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("engine: response data is copied, clipped to the buffer with -EMSGSIZE", "[engine]")
{
	Link l;
	l.chip.handler = [](const ecmxf_cmd_hdr &, const std::uint8_t *) {
		return fake::Answer{ 0, { 1, 2, 3, 4, 5, 6 } };
	};
	std::uint8_t big[8] = {};
	ecmxf_xfer x = command(ECMXF_CMD_FW_VERSION_GET);
	x.rx_buf = big;
	x.rx_size = sizeof(big);
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK(x.status == 0);
	CHECK(x.rx_len == 6);
	CHECK(big[0] == 1);
	CHECK(big[5] == 6);
	CHECK(big[6] == 0);

	std::uint8_t small[4] = {};
	ecmxf_xfer y = command(ECMXF_CMD_FW_VERSION_GET);
	y.rx_buf = small;
	y.rx_size = sizeof(small);
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK(y.status == -EMSGSIZE);
	CHECK(y.rx_len == 4);
	CHECK(y.rsp.len == 6);
	CHECK(small[3] == 4);
}

TEST_CASE("engine: every new command gets a fresh index, wrapping after 255", "[engine]")
{
	Link l;
	std::vector<std::uint8_t> indices;
	for (int i = 0; i < 300; i++) {
		ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
		REQUIRE(l.submit(x) == 0);
		l.run(x);
		REQUIRE(x.status == 0);
		indices.push_back(x.hdr.index);
	}
	// consecutive commands differ in index (same code!), and the index wraps
	bool wrapped = false;
	for (std::size_t i = 1; i < indices.size(); i++) {
		CHECK(indices[i] != indices[i - 1]);
		CHECK(indices[i] == static_cast<std::uint8_t>(indices[i - 1] + 1));
		if (indices[i - 1] == 255 && indices[i] == 0)
			wrapped = true;
	}
	CHECK(wrapped);
	// every one of them was executed by the chip, none taken for a repeat
	CHECK(l.chip.executed.size() == 300);
}

TEST_CASE("engine: a late answer is polled by re-sending the same packet", "[engine]")
{
	Link l;
	l.chip.answerLag = 4;
	ecmxf_xfer x = command(ECMXF_CMD_402_STATE_GET, 1);
	REQUIRE(l.submit(x) == 0);
	const int n = l.run(x);
	CHECK(x.status == 0);
	CHECK(x.rsp.ret == ECMXF_CMD_402_STATE_GET + 1);
	CHECK(n == 3 + 4);
	CHECK(l.e.stats.polls >= 4);
	// all packets after the first send were identical re-sends
	std::size_t sends = 0;
	for (const auto &c : l.chip.cmdLog) {
		if (c.code != ECMXF_CMD_402_STATE_GET)
			continue;
		sends++;
		CHECK(c.index == x.hdr.index);
		CHECK(c.param == 1);
	}
	CHECK(sends == static_cast<std::size_t>(n - 1));
	CHECK(l.chip.executed.size() == 1);
}

TEST_CASE("engine: an async command is tracked through the busy bit to completion", "[engine]")
{
	Link l;
	l.chip.asyncBusyExchanges = 6;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_STATE_SET, 0xFF);
	x.hdr.data[0] = ECMXF_ECAT_PREOP;
	REQUIRE(l.submit(x) == 0);
	CHECK(x.async);

	// accepted: the slot frees while the chip is busy
	while (l.e.cur)
		l.exchange();
	CHECK(x.status == -EINPROGRESS);
	CHECK(l.e.async == &x);

	// an immediate command runs meanwhile
	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(ecmxf_engine_can_submit(&l.e, &y));
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK(y.status == 0);
	CHECK(x.status == -EINPROGRESS);

	// a second async command must wait its turn
	ecmxf_xfer z = command(ECMXF_CMD_ECAT_SDO_REQ);
	CHECK_FALSE(ecmxf_engine_can_submit(&l.e, &z));
	CHECK(l.submit(z) == -EBUSY);

	l.events = 0;
	l.run(x);
	CHECK(x.status == 0);
	CHECK((l.events & ECMXF_EV_ASYNC_DONE) != 0);
	CHECK((x.rsp.ecm_status & ECMXF_STS_BUSY) == 0);
	CHECK(ecmxf_engine_idle(&l.e));
	CHECK(l.submit(z) == 0);
}

TEST_CASE("engine: an async command that fails reports -EREMOTEIO and the error bit is cleared",
	  "[engine]")
{
	Link l;
	l.chip.asyncBusyExchanges = 3;
	l.chip.asyncFails = true;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SDO_REQ);
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK(x.status == -EREMOTEIO);
	CHECK((x.rsp.err_status & ECMXF_ERR_ASYNC) != 0);
	CHECK(l.e.stats.async_errors == 1);
	CHECK((l.events & ECMXF_EV_ERR_STATUS) != 0);

	// the next new packet carries "clear async-command error"
	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK((l.chip.cmdLog[l.chip.cmdLog.size() - 2].control & ECMXF_CTL_CLR_ASYNC_ERR) != 0);
	CHECK((l.chip.errStatus & ECMXF_ERR_ASYNC) == 0);

	// and a following async command succeeds
	l.chip.asyncFails = false;
	ecmxf_xfer z = command(ECMXF_CMD_ECAT_SDO_REQ);
	REQUIRE(l.submit(z) == 0);
	l.run(z);
	CHECK(z.status == 0);
}

TEST_CASE("engine: an async command refused because the chip is busy gives -EBUSY", "[engine]")
{
	Link l;
	// an async command the engine does not know about is running
	l.chip.busyLeft = 50;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_INIT_OP);
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK(x.status == -EBUSY);
	CHECK(l.e.stats.busy_rejects == 1);
	CHECK((x.rsp.err_status & ECMXF_ERR_CMD) != 0);

	// the command error bit is cleared with the next new packet
	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK((l.chip.errStatus & ECMXF_ERR_CMD) == 0);
}

TEST_CASE("engine: ECMXF_XF_NO_AUTO_CLEAR leaves the error bits for the caller", "[engine]")
{
	Link l;
	l.chip.asyncFails = true;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SDO_REQ);
	x.flags = ECMXF_XF_NO_AUTO_CLEAR;
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK(x.status == -EREMOTEIO);
	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK((l.chip.errStatus & ECMXF_ERR_ASYNC) != 0);

	// cleared when asked
	ecmxf_engine_clear_errors(&l.e, ECMXF_CTL_CLR_ASYNC_ERR);
	ecmxf_xfer z = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(z) == 0);
	l.run(z);
	CHECK((l.chip.errStatus & ECMXF_ERR_ASYNC) == 0);
}

TEST_CASE("engine: bad packets are retried and the command still succeeds", "[engine]")
{
	using fake::Fault;
	Link l;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(x) == 0);
	l.exchange(); // sync
	l.exchange(); // first send
	l.chip.faults = { Fault::CheckWord, Fault::StartWord, Fault::NotReady, Fault::EndWord };
	l.run(x);
	// the answer was destroyed by the first fault; the re-sends got INFO_UPDATE
	// answers with our index, so the (idempotent) command was re-issued
	CHECK(x.status == 0);
	CHECK(l.e.stats.faults[ECMXF_FAULT_CHECK] == 1);
	CHECK(l.e.stats.faults[ECMXF_FAULT_START] == 1);
	CHECK(l.e.stats.faults[ECMXF_FAULT_NOT_READY] == 1);
	CHECK(l.e.stats.faults[ECMXF_FAULT_END] == 1);
	CHECK(l.e.stats.retries >= 4);
}

TEST_CASE("engine: consecutive bad packets beyond the bound fail the command with the fault's errno",
	  "[engine]")
{
	using fake::Fault;
	struct Case {
		Fault fault;
		int err;
		ecmxf_fault why;
	};
	const Case cases[] = {
		{ Fault::CheckWord, -EBADMSG, ECMXF_FAULT_CHECK },
		{ Fault::DataByte, -EBADMSG, ECMXF_FAULT_CHECK },
		{ Fault::StartWord, -EPROTO, ECMXF_FAULT_START },
		{ Fault::EndWord, -EPROTO, ECMXF_FAULT_END },
		{ Fault::NotReady, -EIO, ECMXF_FAULT_NOT_READY },
	};
	for (const Case &c : cases) {
		Link l;
		l.chip.check = ECMXF_CHECK_CRC32;
		ecmxf_engine_init(&l.e, ECMXF_DATA_DEFAULT, ECMXF_CHECK_CRC32);
		ecmxf_engine_set_retries(&l.e, 5);
		ecmxf_xfer x = command(ECMXF_CMD_ECAT_STATE_GET);
		REQUIRE(l.submit(x) == 0);
		l.exchange(); // sync
		for (int i = 0; i < 10; i++)
			l.chip.faults.push_back(c.fault);
		const int n = l.run(x);
		INFO("fault " << static_cast<int>(c.fault));
		CHECK(x.status == c.err);
		CHECK(x.fault == c.why);
		CHECK(n == 6); // five tolerated, the sixth fails it
		CHECK(l.e.stats.exhausted == 1);
	}
}

TEST_CASE("engine: a new command gets the whole retry budget whatever a timed-out one used",
	  "[engine]")
{
	using fake::Fault;
	Link l;
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	a.timeout_us = 1000; // 5 exchanges of 200 us
	REQUIRE(l.submit(a) == 0);
	l.exchange(); // sync
	for (int i = 0; i < 20; i++)
		l.chip.faults.push_back(Fault::StartWord);
	l.run(a);
	REQUIRE(a.status == -ETIMEDOUT);
	const auto bad = l.e.stats.faults[ECMXF_FAULT_START];
	REQUIRE(bad >= 1);
	REQUIRE(bad < 8);
	l.chip.faults.clear();

	// eight bad packets in a row are tolerated (the ninth would fail it)
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(b) == 0);
	for (int i = 0; i < 8; i++)
		l.chip.faults.push_back(Fault::StartWord);
	l.run(b);
	CHECK(b.status == 0);
	CHECK(l.e.stats.faults[ECMXF_FAULT_START] == bad + 8);
	CHECK(l.e.stats.exhausted == 0);
}

TEST_CASE("engine: a command the chip never answers times out at its deadline", "[engine]")
{
	Link l;
	l.chip.silent = true;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_INFO_GET);
	x.timeout_us = 5000; // 5 ms = 25 exchanges of 200 us
	REQUIRE(l.submit(x) == 0);
	const std::uint64_t start = l.now;
	CHECK(ecmxf_engine_deadline(&l.e) == start + 5'000'000);
	l.run(x);
	CHECK(x.status == -ETIMEDOUT);
	CHECK(l.now >= start + 5'000'000);
	CHECK(l.now < start + 5'000'000 + 2 * l.stepNs);
	CHECK(l.e.stats.timeouts == 1);
	CHECK(ecmxf_engine_deadline(&l.e) == ~std::uint64_t{ 0 });
}

TEST_CASE("engine: deadlines apply without exchanges too (ecmxf_engine_poll_time)", "[engine]")
{
	Link l;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_INFO_GET);
	x.timeout_us = 1000;
	REQUIRE(l.submit(x) == 0);
	CHECK(ecmxf_engine_poll_time(&l.e, l.now + 999'999) == 0);
	CHECK(ecmxf_engine_poll_time(&l.e, l.now + 1'000'000) == ECMXF_EV_CMD_DONE);
	CHECK(x.status == -ETIMEDOUT);
}

TEST_CASE("engine: an async command that stays busy times out", "[engine]")
{
	Link l;
	l.chip.asyncBusyExchanges = 1000;
	ecmxf_xfer x = command(ECMXF_CMD_EEPROM_REQ);
	x.timeout_us = 10'000;
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK(x.status == -ETIMEDOUT);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("engine: a lost answer of a non-idempotent command is reported, not repeated",
	  "[engine]")
{
	using fake::Fault;
	Link l;
	ecmxf_xfer x = command(ECMXF_CMD_FIFO_ENABLE, 1);
	REQUIRE(l.submit(x) == 0);
	l.exchange(); // sync
	l.exchange(); // first send
	l.chip.faults = { Fault::CheckWord };
	l.run(x);
	CHECK(x.status == -EPROTO);
	CHECK(l.e.stats.lost_answers == 1);
	// executed exactly once
	std::size_t n = 0;
	for (const auto &c : l.chip.executed)
		n += c.code == ECMXF_CMD_FIFO_ENABLE;
	CHECK(n == 1);
}

TEST_CASE("engine: a NOP response after valid ones means the chip reset", "[engine]")
{
	Link l;
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(a) == 0);
	l.run(a);
	REQUIRE(a.status == 0);

	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(x) == 0);
	l.chip.resetPending = true;
	l.events = 0;
	l.run(x);
	CHECK(x.status == -ECONNRESET);
	CHECK((l.events & ECMXF_EV_CHIP_RESET) != 0);
	CHECK(l.e.stats.chip_resets == 1);
}

TEST_CASE("engine: SPI_RECONFIG_OP goes out with the fixed check word and switches the size",
	  "[engine]")
{
	Link l;
	l.chip.check = ECMXF_CHECK_CRC32;
	ecmxf_engine_init(&l.e, ECMXF_DATA_DEFAULT, ECMXF_CHECK_CRC32);

	ecmxf_xfer x = command(ECMXF_CMD_SPI_RECONFIG_OP);
	x.hdr.len = 1408;
	REQUIRE(l.submit(x) == 0);
	l.exchange(); // sync
	const std::uint64_t before = l.now;
	l.exchange(); // RECONFIG first send
	const auto &sent = l.chip.mosiLog.back();
	REQUIRE(sent.size() == ECMXF_PKT_SIZE(112));
	// the check word of that packet is the fixed value
	CHECK(sent[24 + 112] == 0x78);
	CHECK(sent[24 + 112 + 3] == 0x12);
	// the engine now speaks 1440-byte packets, after a 100 ms hold-off
	CHECK(ecmxf_engine_pkt_size(&l.e) == ECMXF_PKT_SIZE(1408));
	CHECK(ecmxf_engine_not_before(&l.e) == before + ECMXF_RECONFIG_HOLDOFF_NS);
	std::vector<std::uint8_t> tx(ECMXF_PKT_SIZE(1408));
	CHECK(ecmxf_engine_next(&l.e, before + 1000, tx.data(), tx.size()) == -EAGAIN);
	l.run(x);
	CHECK(x.status == 0);
	CHECK(l.chip.mosiLog.back().size() == ECMXF_PKT_SIZE(1408));

	// sizes are validated at submission
	ecmxf_xfer bad = command(ECMXF_CMD_SPI_RECONFIG_OP);
	bad.hdr.len = 31;
	CHECK(l.submit(bad) == -EINVAL);
	bad.hdr.len = 1409;
	CHECK(l.submit(bad) == -EINVAL);
}

TEST_CASE("engine: CRC_TYPE_SET switches the check word of both directions", "[engine]")
{
	Link l;
	ecmxf_xfer x = command(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32);
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK(x.status == 0);
	CHECK(l.e.check == ECMXF_CHECK_CRC32);

	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK(y.status == 0);
	const auto &p = l.chip.mosiLog.back();
	const std::size_t n = p.size() - 8;
	const std::uint32_t word = static_cast<std::uint32_t>(p[n]) |
				   static_cast<std::uint32_t>(p[n + 1]) << 8 |
				   static_cast<std::uint32_t>(p[n + 2]) << 16 |
				   static_cast<std::uint32_t>(p[n + 3]) << 24;
	CHECK(word == ecmxf_crc32(p.data(), n));
	CHECK(l.chip.mosiBad == 0);

	ecmxf_xfer bad = command(ECMXF_CMD_CRC_TYPE_SET, 4);
	CHECK(l.submit(bad) == -EINVAL);
}

TEST_CASE("engine: new error-status bits are surfaced once and cleared when asked", "[engine]")
{
	Link l;
	l.chip.errStatus = ECMXF_ERR_SPI_CRC | ECMXF_ERR_LINK_HW;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	CHECK((l.events & ECMXF_EV_ERR_STATUS) != 0);
	CHECK((l.e.last.err_status & ECMXF_ERR_SPI_CRC) != 0);

	// not reported again while it stays set
	l.events = 0;
	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(y) == 0);
	l.run(y);
	CHECK((l.events & ECMXF_EV_ERR_STATUS) == 0);

	ecmxf_engine_clear_errors(&l.e, ECMXF_CTL_CLR_SPI_CRC_ERR);
	ecmxf_xfer z = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(z) == 0);
	l.run(z);
	CHECK((l.chip.errStatus & ECMXF_ERR_SPI_CRC) == 0);
	// the control bit went out exactly once: re-sends do not repeat it
	int with = 0;
	for (const auto &c : l.chip.cmdLog)
		with += (c.control & ECMXF_CTL_CLR_SPI_CRC_ERR) != 0;
	CHECK(with == 1);
}

TEST_CASE("engine: interrupt clears go out once, in a new packet", "[engine]")
{
	Link l;
	ecmxf_engine_clear_ints(&l.e, ECMXF_INT_ECAT_PKT, 0x01, 0x80);
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(x) == 0);
	l.run(x);
	int with = 0;
	for (const auto &c : l.chip.cmdLog) {
		if (c.int_clear) {
			with++;
			CHECK(c.int_clear == ECMXF_INT_ECAT_PKT);
			CHECK(c.gpio_int_clear[0] == 0x01);
			CHECK(c.gpio_int_clear[1] == 0x80);
		}
	}
	CHECK(with == 1);
}

TEST_CASE("engine: submission checks its arguments", "[engine]")
{
	Link l;
	std::uint8_t data[200] = {};
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SDO_REQ);
	x.tx_data = data;
	x.tx_len = 113; // > 112-byte data section
	CHECK(l.submit(x) == -EMSGSIZE);
	x.tx_len = 4;
	x.tx_data = nullptr;
	CHECK(l.submit(x) == -EINVAL);
	x.tx_data = data;
	x.rx_size = 4; // without a buffer
	CHECK(l.submit(x) == -EINVAL);
	x.rx_size = 0;
	CHECK(l.submit(x) == 0);
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_STATE_SET);
	CHECK(l.submit(a) == -EBUSY); // one async command at a time
	ecmxf_xfer y = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(l.submit(y) == 0); // rides behind the first
	ecmxf_xfer z = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(l.submit(z) == -EBUSY); // two command slots
	std::vector<std::uint8_t> tx(ECMXF_PKT_SIZE(112) + 1);
	CHECK(ecmxf_engine_next(&l.e, l.now, tx.data(), tx.size()) == -EINVAL);
}

TEST_CASE("engine: cancel withdraws a command", "[engine]")
{
	Link l;
	ecmxf_xfer x = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	REQUIRE(l.submit(x) == 0);
	CHECK(ecmxf_engine_cancel(&l.e, &x) == 0);
	CHECK(x.status == -ECANCELED);
	CHECK(ecmxf_engine_cancel(&l.e, &x) == -ENOENT);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("engine: WARM_RESET switches to the power-on format and completes on the NOP",
	  "[engine]")
{
	Link l;
	l.chip.check = ECMXF_CHECK_CRC32;
	ecmxf_engine_init(&l.e, ECMXF_DATA_DEFAULT, ECMXF_CHECK_CRC32);
	ecmxf_xfer x = command(ECMXF_CMD_WARM_RESET);
	REQUIRE(l.submit(x) == 0);
	l.exchange(); // sync
	l.chip.resetPending = true; // the chip restarts on receiving it
	l.exchange(); // WARM_RESET
	CHECK(l.e.check == ECMXF_CHECK_FIXED);
	l.run(x);
	CHECK(x.status == 0);
	CHECK((l.events & ECMXF_EV_CHIP_RESET) != 0);
	// WARM_RESET went out once; the chip was polled with INFO_UPDATE after
	// it, since a restarted chip would run a repeated WARM_RESET again
	std::size_t resets = 0;
	for (const auto &c : l.chip.cmdLog)
		resets += c.code == ECMXF_CMD_WARM_RESET;
	CHECK(resets == 1);
	CHECK(l.chip.cmdLog.back().code == ECMXF_CMD_INFO_UPDATE_OP);
}

TEST_CASE("engine: WARM_RESET waits for the NOP through bad packets and late answers", "[engine]")
{
	Link l;
	ecmxf_xfer x = command(ECMXF_CMD_WARM_RESET);
	REQUIRE(l.submit(x) == 0);
	l.exchange(); // sync
	l.exchange(); // WARM_RESET; the chip takes it as any command
	// two polls get a bad packet and a stale header before the restart
	l.chip.faults.push_back(fake::Fault::CheckWord);
	l.exchange();
	l.exchange();
	CHECK(x.status == -EINPROGRESS);
	l.chip.resetPending = true; // the chip restarts now
	l.run(x);
	CHECK(x.status == 0);
	CHECK((l.events & ECMXF_EV_CHIP_RESET) != 0);
	std::size_t resets = 0;
	for (const auto &c : l.chip.cmdLog)
		resets += c.code == ECMXF_CMD_WARM_RESET;
	CHECK(resets == 1);
}

TEST_CASE("engine: data that would not fit the format a command switches to is refused",
	  "[engine]")
{
	Link l;
	ecmxf_engine_init(&l.e, 300, ECMXF_CHECK_FIXED);
	std::uint8_t data[300] = {};
	ecmxf_xfer x = command(ECMXF_CMD_SPI_RECONFIG_OP);
	x.hdr.len = 64;
	x.tx_data = data;
	x.tx_len = 65; // fits 300 now, not the 64 it switches to
	CHECK(l.submit(x) == -EMSGSIZE);
	x.tx_len = 64;
	CHECK(l.submit(x) == 0);
	CHECK(ecmxf_engine_cancel(&l.e, &x) == 0);

	ecmxf_xfer w = command(ECMXF_CMD_WARM_RESET);
	w.tx_data = data;
	w.tx_len = 113; // the power-on data section is 112 bytes
	CHECK(l.submit(w) == -EMSGSIZE);
}

// ---------------------------------------------------------------------------
// Pipelining: the second command rides in the exchange that fetches the
// first one's answer; an async command's fetch is its poll.
// ---------------------------------------------------------------------------

namespace {

// Exchanges until every command given is final.
int runAll(Link &l, std::initializer_list<ecmxf_xfer *> xs, int max = 1000)
{
	int n = 0;
	auto busy = [&] {
		for (ecmxf_xfer *x : xs)
			if (x->status == -EINPROGRESS)
				return true;
		return false;
	};
	while (busy() && n < max) {
		l.exchange();
		n++;
	}
	return n;
}

// SDO_REQ with SDO_GET as its fetch, which brings 4 bytes back.
struct SdoUpload {
	std::uint8_t buf[4] = {};
	ecmxf_xfer req = command(ECMXF_CMD_ECAT_SDO_REQ);
	ecmxf_xfer get = command(ECMXF_CMD_ECAT_SDO_GET);
	SdoUpload()
	{
		get.rx_buf = buf;
		get.rx_size = sizeof(buf);
		req.fetch = &get;
	}
	SdoUpload(const SdoUpload &) = delete;
	SdoUpload &operator=(const SdoUpload &) = delete;
};

} // namespace

TEST_CASE("pipelining: the second command rides in the exchange that fetches the first answer",
	  "[engine][pipeline]")
{
	Link l;
	l.exchange(); // sync
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	REQUIRE(l.submit(a) == 0);
	REQUIRE(l.submit(b) == 0);
	CHECK(runAll(l, { &a, &b }) == 3); // a, b (fetches a), refresh (fetches b)
	CHECK(a.status == 0);
	CHECK(b.status == 0);
	CHECK(a.rsp.ret == ECMXF_CMD_ECAT_SLV_CNT_GET + 1);
	CHECK(b.rsp.ret == ECMXF_CMD_ECAT_STATE_GET + 1);
	REQUIRE(l.chip.cmdLog.size() == 4);
	CHECK(l.chip.cmdLog[1].code == ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(l.chip.cmdLog[2].code == ECMXF_CMD_ECAT_STATE_GET);
	// the last packet fetches b's answer: b's (index, code) again
	CHECK(l.chip.cmdLog[3].code == ECMXF_CMD_ECAT_STATE_GET);
	CHECK(l.chip.cmdLog[3].index == l.chip.cmdLog[2].index);
	CHECK(l.chip.executed.size() == 2);
	CHECK(ecmxf_engine_get_stats(&l.e)->pipelined == 1);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: a command whose answer waits for the next exchange, alone or not (waits_only)",
	  "[engine][pipeline]")
{
	Link l;
	l.exchange(); // sync
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	ecmxf_xfer w = command(ECMXF_CMD_ECAT_PDO_WC_GET, 3);
	CHECK_FALSE(ecmxf_engine_waits_only(&l.e, nullptr));
	REQUIRE(l.submit(a) == 0);
	REQUIRE(l.submit(w) == 0);
	CHECK_FALSE(ecmxf_engine_waits_only(&l.e, &w)); // not sent
	l.exchange();                                     // a goes out
	CHECK_FALSE(ecmxf_engine_waits_only(&l.e, &w));
	CHECK_FALSE(ecmxf_engine_waits_only(&l.e, &a)); // w still to send
	l.exchange(); // w rides, fetching a's answer
	CHECK(a.status == 0);
	CHECK(w.status == -EINPROGRESS);
	CHECK(ecmxf_engine_waits_only(&l.e, &w));
	CHECK_FALSE(ecmxf_engine_idle(&l.e));
	// the next command takes the answer along: no exchange for w alone
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	REQUIRE(l.submit(b) == 0);
	CHECK_FALSE(ecmxf_engine_waits_only(&l.e, &w)); // b is to send
	l.exchange();
	CHECK(w.status == 0);
	CHECK(w.rsp.code == ECMXF_CMD_ECAT_PDO_WC_GET);
	CHECK(ecmxf_engine_waits_only(&l.e, &b));
	l.exchange();
	CHECK(b.status == 0);
	CHECK(l.chip.executed.size() == 3);
	CHECK(ecmxf_engine_idle(&l.e));

	// an async command running beside it: not alone
	SdoUpload u;
	ecmxf_xfer w2 = command(ECMXF_CMD_ECAT_PDO_WC_GET, 3);
	l.chip.asyncBusyExchanges = 6;
	REQUIRE(l.submit(u.req) == 0);
	while (l.e.async != &u.req)
		l.exchange();
	REQUIRE(l.submit(w2) == 0);
	for (int i = 0; i < 3 && !ecmxf_engine_sent(&l.e, &w2); i++)
		l.exchange();
	REQUIRE(ecmxf_engine_sent(&l.e, &w2));
	CHECK_FALSE(ecmxf_engine_waits_only(&l.e, &w2));
	runAll(l, { &u.req, &u.get, &w2 });
	CHECK(u.get.status == 0);
	CHECK(w2.status == 0);
}

TEST_CASE("pipelining: off, the second command waits for the first answer", "[engine][pipeline]")
{
	Link l;
	ecmxf_engine_set_pipeline(&l.e, false);
	l.exchange();
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	REQUIRE(l.submit(a) == 0);
	CHECK(l.submit(b) == -EBUSY);
	CHECK(l.run(a) == 2);
	REQUIRE(l.submit(b) == 0);
	CHECK(l.run(b) == 2);
	CHECK(ecmxf_engine_get_stats(&l.e)->pipelined == 0);
}

TEST_CASE("pipelining: commands that change the packet format travel alone", "[engine][pipeline]")
{
	Link l;
	l.exchange();
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	ecmxf_xfer crc = command(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32);
	REQUIRE(l.submit(a) == 0);
	CHECK(l.submit(crc) == -EBUSY);
	CHECK(!ecmxf_engine_can_submit(&l.e, &crc));
	l.run(a);
	REQUIRE(l.submit(crc) == 0);
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(l.submit(b) == -EBUSY);
	l.run(crc);
	CHECK(crc.status == 0);
}

TEST_CASE("pipelining: a lost answer of the first command, with the second in flight",
	  "[engine][pipeline]")
{
	Link l;
	l.exchange();
	const bool idempotent = GENERATE(true, false);
	// SLV_CNT_GET may run again; PDO_DATA_FIFO_OP (frames) must not
	ecmxf_xfer a = command(idempotent ? ECMXF_CMD_ECAT_SLV_CNT_GET : ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP);
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	REQUIRE(l.submit(a) == 0);
	REQUIRE(l.submit(b) == 0);
	l.exchange(); // a goes out
	l.chip.faults.push_back(fake::Fault::CheckWord);
	l.exchange(); // b goes out; a's answer arrives broken
	runAll(l, { &a, &b });
	CHECK(b.status == 0);
	CHECK(b.rsp.code == ECMXF_CMD_ECAT_STATE_GET);
	int runsOfA = 0;
	for (const ecmxf_cmd_hdr &h : l.chip.executed)
		runsOfA += h.code == a.hdr.code;
	if (idempotent) {
		CHECK(a.status == 0);
		CHECK(runsOfA == 2); // again, after b
		CHECK(ecmxf_engine_get_stats(&l.e)->reordered == 1);
	} else {
		CHECK(a.status == -EPROTO); // may have run: never a second time
		CHECK(runsOfA == 1);
	}
	CHECK(ecmxf_engine_get_stats(&l.e)->lost_answers == 1);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: a not-ready answer leaves both commands to run exactly once",
	  "[engine][pipeline]")
{
	Link l;
	l.exchange();
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP);
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_STATE_GET, 0xFF);
	REQUIRE(l.submit(a) == 0);
	REQUIRE(l.submit(b) == 0);
	l.exchange();
	l.chip.faults.push_back(fake::Fault::NotReady);
	l.exchange();
	runAll(l, { &a, &b });
	// the fake takes the packet in; the engine re-sends b (a repeat) and
	// a's answer is lost: a fails, nothing runs twice
	CHECK(a.status == -EPROTO);
	CHECK(b.status == 0);
	CHECK(l.chip.executed.size() == 2);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: a late chip is polled by re-sending the newest command only",
	  "[engine][pipeline]")
{
	Link l;
	l.exchange();
	l.chip.answerLag = 2;
	ecmxf_xfer a = command(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP);
	ecmxf_xfer b = command(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP);
	REQUIRE(l.submit(a) == 0);
	REQUIRE(l.submit(b) == 0);
	runAll(l, { &a, &b });
	CHECK(a.status == 0);
	CHECK(b.status == 0);
	// a went out once; every later packet was b (first send or repeat)
	CHECK(l.chip.executed.size() == 2);
	CHECK(ecmxf_engine_get_stats(&l.e)->polls > 0);
}

TEST_CASE("pipelining: an async command's fetch is its poll, and completes with it",
	  "[engine][pipeline]")
{
	const bool pipeline = GENERATE(true, false);
	Link l;
	ecmxf_engine_set_pipeline(&l.e, pipeline);
	l.chip.asyncBusyExchanges = 3;
	l.chip.handler = [](const ecmxf_cmd_hdr &h, const std::uint8_t *) {
		return fake::Answer{ static_cast<std::uint8_t>(h.code + 1), { 0x50, 0xC3, 0, 0 } };
	};
	l.exchange();
	SdoUpload up;
	ecmxf_xfer &req = up.req, &get = up.get;
	const std::uint8_t *buf = up.buf;
	REQUIRE(l.submit(req) == 0);
	const int n = runAll(l, { &req, &get });
	CHECK(req.status == 0);
	CHECK(get.status == 0);
	CHECK(get.rx_len == 4);
	CHECK(buf[0] == 0x50);
	CHECK((get.rsp.ecm_status & ECMXF_STS_BUSY) == 0);
	int infos = 0;
	for (std::size_t i = 1; i < l.chip.cmdLog.size(); i++)
		infos += l.chip.cmdLog[i].code == ECMXF_CMD_INFO_UPDATE_OP;
	int reqs = 0;
	for (const ecmxf_cmd_hdr &h : l.chip.executed)
		reqs += h.code == ECMXF_CMD_ECAT_SDO_REQ;
	CHECK(reqs == 1);
	int gets = 0;
	for (const ecmxf_cmd_hdr &h : l.chip.executed)
		gets += h.code == ECMXF_CMD_ECAT_SDO_GET;
	if (pipeline) {
		// By hand, the chip busy for the 3 exchanges after the one that
		// took REQ: 1 REQ; 2 REQ repeated (its answer: accepted, busy);
		// 3 GET (runs busy); 4 GET again, sent ahead while the answer
		// to 3 (busy) comes back; it runs after the busy phase; 5 GET
		// again, while the answer to 4 brings the result: 5 exchanges,
		// a fresh GET in each from the third on, none repeated
		CHECK(infos == 0);
		CHECK(n == 5);
		CHECK(gets == 3);
		CHECK(ecmxf_engine_get_stats(&l.e)->fetch_polls == 1);
	} else {
		CHECK(infos > 0);
		CHECK(n > 6);
	}
}

TEST_CASE("pipelining: a fetch sent ahead polls through lost answers and a packet the chip dropped",
	  "[engine][pipeline]")
{
	Link l;
	l.chip.asyncBusyExchanges = 6;
	l.chip.handler = [](const ecmxf_cmd_hdr &h, const std::uint8_t *) {
		return fake::Answer{ static_cast<std::uint8_t>(h.code + 1), { 1, 2, 3, 4 } };
	};
	int getsSeen = 0;
	l.chip.dropCmd = [&](const ecmxf_cmd_hdr &h) {
		return h.code == ECMXF_CMD_ECAT_SDO_GET && ++getsSeen == 2;
	};
	l.exchange();
	SdoUpload up;
	ecmxf_xfer &req = up.req, &get = up.get;
	const std::uint8_t *buf = up.buf;
	REQUIRE(l.submit(req) == 0);
	// the answers of the 4th and 6th exchange are garbled on the wire
	l.chip.faults = { fake::Fault::None, fake::Fault::None, fake::Fault::None, fake::Fault::CheckWord,
			  fake::Fault::None, fake::Fault::CheckWord };
	runAll(l, { &req, &get });
	CHECK(req.status == 0);
	CHECK(get.status == 0);
	REQUIRE(get.rx_len == 4);
	CHECK(buf[3] == 4);
	CHECK((get.rsp.ecm_status & ECMXF_STS_BUSY) == 0);
	int reqs = 0;
	for (const ecmxf_cmd_hdr &h : l.chip.executed)
		reqs += h.code == ECMXF_CMD_ECAT_SDO_REQ;
	CHECK(reqs == 1);
	// never a repeat while the fetch polls: every GET packet is fresh
	std::set<std::uint8_t> seen;
	for (const ecmxf_cmd_hdr &h : l.chip.cmdLog)
		if (h.code == ECMXF_CMD_ECAT_SDO_GET)
			CHECK(seen.insert(h.index).second);
	CHECK(seen.size() >= 4);
	CHECK(getsSeen >= 2); // the drop happened
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: a fetch does not go ahead of a late chip's answers", "[engine][pipeline]")
{
	// answers come 2 exchanges late: a fetch sent anew in every exchange
	// would never meet the answer to its previous send; it waits for them
	const int lag = GENERATE(1, 2, 4);
	Link l;
	l.exchange();
	l.chip.answerLag = lag;
	l.chip.asyncBusyExchanges = 6;
	l.chip.handler = [](const ecmxf_cmd_hdr &h, const std::uint8_t *) {
		return fake::Answer{ static_cast<std::uint8_t>(h.code + 1), { 9, 8, 7, 6 } };
	};
	SdoUpload up;
	REQUIRE(l.submit(up.req) == 0);
	const int n = runAll(l, { &up.req, &up.get });
	CHECK(up.req.status == 0);
	CHECK(up.get.status == 0);
	CHECK(up.buf[0] == 9);
	CHECK(n < 100);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: the fetch of an async command the chip refuses is withdrawn",
	  "[engine][pipeline]")
{
	Link l;
	l.exchange();
	l.chip.busyLeft = 50; // another async command runs
	ecmxf_xfer req = command(ECMXF_CMD_ECAT_SDO_REQ);
	ecmxf_xfer get = command(ECMXF_CMD_ECAT_SDO_GET);
	req.fetch = &get;
	REQUIRE(l.submit(req) == 0);
	runAll(l, { &req, &get });
	CHECK(req.status == -EBUSY);
	CHECK(get.status == -ECANCELED);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: an async command that fails reports it, its fetch still ran",
	  "[engine][pipeline]")
{
	Link l;
	l.chip.asyncFails = true;
	l.exchange();
	ecmxf_xfer req = command(ECMXF_CMD_ECAT_SDO_REQ);
	ecmxf_xfer get = command(ECMXF_CMD_ECAT_SDO_GET);
	req.fetch = &get;
	REQUIRE(l.submit(req) == 0);
	runAll(l, { &req, &get });
	CHECK(req.status == -EREMOTEIO);
	CHECK(get.status != -EINPROGRESS);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: bad fetch pairs are refused", "[engine][pipeline]")
{
	Link l;
	ecmxf_xfer imm = command(ECMXF_CMD_ECAT_SLV_CNT_GET);
	ecmxf_xfer get = command(ECMXF_CMD_ECAT_SDO_GET);
	imm.fetch = &get; // not async
	CHECK(l.submit(imm) == -EINVAL);
	ecmxf_xfer req = command(ECMXF_CMD_ECAT_SDO_REQ);
	ecmxf_xfer req2 = command(ECMXF_CMD_ECAT_SDO_REQ);
	req.fetch = &req2; // an async fetch
	CHECK(l.submit(req) == -EINVAL);
	req.fetch = &req; // itself
	CHECK(l.submit(req) == -EINVAL);
	ecmxf_xfer warm = command(ECMXF_CMD_WARM_RESET);
	req.fetch = &warm;
	CHECK(l.submit(req) == -EINVAL);
	CHECK(ecmxf_engine_idle(&l.e));
}

TEST_CASE("pipelining: cancelling an async command withdraws its fetch", "[engine][pipeline]")
{
	Link l;
	l.exchange();
	ecmxf_xfer req = command(ECMXF_CMD_ECAT_SDO_REQ);
	ecmxf_xfer get = command(ECMXF_CMD_ECAT_SDO_GET);
	req.fetch = &get;
	REQUIRE(l.submit(req) == 0);
	l.exchange();
	l.exchange(); // accepted: the fetch polls
	CHECK(ecmxf_engine_running(&l.e, &req));
	CHECK(ecmxf_engine_cancel(&l.e, &req) == 0);
	CHECK(req.status == -ECANCELED);
	CHECK(get.status == -ECANCELED);
	CHECK(ecmxf_engine_idle(&l.e));
}
