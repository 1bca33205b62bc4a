// SPDX-License-Identifier: MIT
/*
 * fuzz_pump.cpp - libFuzzer target: the PDO pump's answer interpreter
 *
 * The protocol core's pump (lib/core/ecmxf-pump.c) is set up from the
 * first bytes, then each further record plans a FIFO command and feeds it
 * an arbitrary answer, as the kernel's pump and the library's FIFO path
 * do with whatever the chip sends:
 *
 *   [0]     RxPDO frame bytes (0: none)
 *   [1]     TxPDO frame bytes (0: none)
 *   [2..3]  le16: data size = 32 + v % 1377
 *   [4]     RxFIFO depth
 *   [5]     fill level (v % (depth + 2): also out of range)
 *   [6]     TxFIFO depth
 *   then records of 12 bytes: level, avail (le16), flags, the answer's
 *   ret, rx_fifo_cnt, tx_fifo_cnt, err_status, ecm_status, rx_len (le16),
 *   and a byte whose bit 0 makes the command fail with no answer.
 *
 * Invariants (abort() on violation): ecmxf_pump_check() agrees with the
 * rules it documents; a plan never skips more than was ready, never
 * pushes more than fits the room (or the one frame of F_ONE), the data
 * section or the byte parameter, and reads only with TxPDO frames; the
 * command's data bytes are what the plan pushes; an answer returns 0,
 * -EREMOTEIO exactly on a command error, or -EPROTO; popped frames fill
 * exactly rx_len and fit the data section; refused <= taken <= pushed;
 * the level is the header's count plus what the last command pushed.
 */
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "ecmxf-pump.h"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

[[noreturn]] void fail(const char *what)
{
	std::fprintf(stderr, "fuzz_pump: invariant violated: %s (input %s)\n", what,
		     ecmxf_fuzz_context ? ecmxf_fuzz_context : "?");
	std::abort();
}

void require(bool ok, const char *what)
{
	if (!ok)
		fail(what);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 7)
		return 0;
	const u32 outSize = data[0];
	const u32 inSize = data[1];
	const u32 dataSize = 32 + (static_cast<u32>(data[2] | data[3] << 8) % 1377);
	const u32 rxDepth = data[4];
	const u32 rxFill = data[5] % (rxDepth + 2);
	const u32 txDepth = data[6];
	data += 7;
	size -= 7;

	const u32 maxFill = ecmxf_pump_max_fill(rxDepth);
	require(maxFill >= 1 && (rxDepth <= 2 || maxFill == rxDepth - 2), "max fill");
	const int chk = ecmxf_pump_check(outSize, inSize, dataSize, rxDepth, rxFill);
	int want = 0;
	if (rxFill > maxFill)
		want = -EINVAL;
	else if (!outSize && !inSize)
		want = -ENODATA;
	else if (outSize > dataSize || inSize > dataSize)
		want = -EMSGSIZE;
	require(chk == want, "ecmxf_pump_check");
	if (chk)
		return 0;

	ecmxf_pump p;
	ecmxf_pump_init(&p, outSize, inSize, dataSize, rxDepth, rxFill, txDepth);
	require(p.rx_fill == (rxFill ? rxFill : maxFill), "fill level");
	const u32 perWrite = ecmxf_pump_per_write(&p);
	const u32 perRead = ecmxf_pump_per_read(&p);
	require(perWrite <= ECMXF_PUMP_MAX_PUSH && perWrite * outSize <= dataSize, "per write");
	require(perRead * inSize <= dataSize, "per read");

	ecmxf_rsp_hdr last{};
	bool haveLast = false;
	for (; size >= 12; data += 12, size -= 12) {
		const ecmxf_rsp_hdr *prev = haveLast ? &last : nullptr;
		const u32 level = data[0] % 2 ? ecmxf_pump_level(&p, prev) : data[0];
		const u32 avail = static_cast<u32>(data[1] | data[2] << 8);
		const unsigned flags = data[3] & (ECMXF_PUMP_F_READ | ECMXF_PUMP_F_ONE);

		ecmxf_pump_plan pl;
		const bool send = ecmxf_pump_next(&p, level, avail, flags, &pl);
		const u32 room = p.rx_fill > level ? p.rx_fill - level : 0;
		require(pl.skip <= avail, "skip <= avail");
		require(pl.push <= avail - pl.skip, "push <= what is left");
		require(pl.push <= perWrite, "push <= per write");
		require(pl.push <= room || ((flags & ECMXF_PUMP_F_ONE) && !room && pl.push == 1),
			"push <= room");
		require(!pl.read || (inSize && (flags & ECMXF_PUMP_F_READ)), "read only with inputs");
		require(send == (pl.push || pl.read), "send");
		require(!pl.skip || avail - pl.skip == (room ? room : (flags & ECMXF_PUMP_F_ONE ? 1 : 0)) + p.rx_fill,
			"skip leaves room + fill");
		if (!send)
			continue;

		ecmxf_cmd_hdr c;
		const u32 len = ecmxf_pump_fifo_cmd(&p, &pl, data[11] & 2, &c);
		require(len == pl.push * outSize && len <= dataSize, "command length");
		require(c.code == ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP && c.param == pl.push, "command code");
		require(((c.data[0] & ECMXF_PUMP_OP_WRITE) != 0) == (pl.push != 0) &&
				((c.data[0] & ECMXF_PUMP_OP_READ) != 0) == pl.read,
			"command bits");

		if (data[11] & 1) {
			require(ecmxf_pump_lost(&p, &pl) == pl.push && p.unconfirmed == pl.push, "lost");
			continue;
		}
		ecmxf_rsp_hdr h{};
		h.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
		h.ret = data[4];
		h.rx_fifo_cnt = data[5];
		h.tx_fifo_cnt = data[6];
		h.err_status = data[7];
		h.ecm_status = data[8];
		const u32 rxLen = static_cast<u32>(data[9] | data[10] << 8);
		h.len = static_cast<u16>(rxLen);
		const u32 before = p.unconfirmed;
		ecmxf_pump_result res;
		const int err = ecmxf_pump_answer(&p, &pl, &h, rxLen, &res);
		require(err == 0 || err == -EREMOTEIO || err == -EPROTO, "answer errno");
		require((err == -EREMOTEIO) == ((h.err_status & ECMXF_ERR_CMD) != 0), "EREMOTEIO iff command error");
		require(res.refused <= res.taken && res.taken <= pl.push, "refused <= taken <= push");
		if (err == -EREMOTEIO) {
			require(!res.taken && !res.popped && p.unconfirmed == before, "nothing taken");
			continue;
		}
		require(res.taken == pl.push && p.unconfirmed == pl.push, "taken");
		require(res.refused == ((h.ret & ECMXF_PUMP_RET_TAKEN) ? 0 : pl.push), "refused");
		if (err == -EPROTO) {
			require(pl.read && (rxLen % inSize || rxLen / inSize > perRead), "EPROTO only for a bad read");
			require(!res.popped, "nothing popped on EPROTO");
		} else if (pl.read) {
			require(res.popped * inSize == rxLen && res.popped <= perRead, "popped fills rx_len");
			require(res.tx_overrun == (txDepth && res.popped + h.tx_fifo_cnt >= txDepth), "tx overrun");
		} else {
			require(!res.popped && !res.tx_overrun, "no read, nothing popped");
		}
		if (!err)
			require(!res.rx_underrun || (outSize && p.pushed_any && !h.rx_fifo_cnt &&
						      (h.ecm_status & ECMXF_STS_FIFO_EN)),
				"rx underrun");
		require(ecmxf_pump_level(&p, &h) == h.rx_fifo_cnt + pl.push, "level");
		last = h;
		haveLast = true;
	}
	return 0;
}
