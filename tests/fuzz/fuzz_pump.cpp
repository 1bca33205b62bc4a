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
 *
 * The same records then drive the schedule (lib/core/ecmxf-pump-sched.c)
 * as the kernel's pump does, with two FIFO commands in flight and the
 * working counter read: byte 0 advances the clock, byte 3 bits 2..3 are
 * INT1 and "the newest command went out", byte 8 bit 6 the FIFOs on,
 * byte 11 bits 2..4 which command finishes and how (answer, no answer,
 * chip reset); the schedule's flags, periods and the bus cycle come from
 * the setup bytes.  Invariants: a pick never takes a slot in flight (at
 * most two FIFO commands, one without FIFO_NEXT) and only a read that is
 * due; the deadline is 0 exactly while the FIFOs are off; every output
 * frame leaves the modelled ring once (skipped, freed when sent, or freed
 * by its answer or its loss; a command error leaves it there), never more
 * than were ready; the counts are 0 or 1 and agree with the answer; work
 * is left only by a command that moved frames.  And as the library's
 * synchronous cycle: the RxFIFO estimate never exceeds the count plus
 * the frames in flight, a cycle ends within 1 + ecmxf_pump_max_reads() +
 * the writes of its room, pushes at most its room (one frame at or above
 * the fill level) and reads at most ecmxf_pump_max_reads() times.
 */
#include <algorithm>
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

/// A response header from a record's bytes 4..10.
ecmxf_rsp_hdr recordHeader(const uint8_t *r)
{
	ecmxf_rsp_hdr h{};
	h.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
	h.ret = r[4];
	h.rx_fifo_cnt = r[5];
	h.tx_fifo_cnt = r[6];
	h.err_status = r[7];
	h.ecm_status = r[8];
	h.len = static_cast<u16>(r[9] | r[10] << 8);
	return h;
}

/// The counts of an account are 0 or 1 each, and the frames add up.
void checkAcct(const ecmxf_pump_acct &a, u32 push, bool released)
{
	require(a.ops <= 1 && a.refusals <= 1 && a.tx_overruns <= 1 && a.rx_underruns <= 1 &&
			a.out_underruns <= a.rx_underruns && a.failures <= 1,
		"counts are 0 or 1");
	require(a.free <= push && a.dropped <= push, "free, dropped <= push");
	require(!released || !a.free, "frames freed when sent are not freed again");
	require(a.wake_out == (a.free != 0), "wake exactly when frames left the ring");
}

/// The kernel's pump over the records: picks, slots, plans, answers.
void fuzzSchedule(ecmxf_pump &p, unsigned flags, u64 pollNs, u64 wkcNs, const uint8_t *data, size_t size)
{
	ecmxf_pump_sched s;
	ecmxf_pump_sched_init(&s, flags, pollNs, wkcNs);
	ecmxf_pump_flight f{};
	ecmxf_rsp_hdr last{};
	u64 now = 0;
	u64 ring = 0;	// frames the application has put in the modelled ring
	for (; size >= 12; data += 12, size -= 12) {
		now += data[0] * 37ULL;
		ring += data[1] % 16;
		last.ecm_status = (data[8] & ECMXF_STS_FIFO_EN) ? ECMXF_STS_FIFO_EN : 0;
		last.rx_fifo_cnt = data[5];
		const bool kick = data[3] & 4;
		const bool sent = data[3] & 8;
		const u64 dl = ecmxf_pump_sched_deadline(&s, &last);
		require((dl == 0) == !(last.ecm_status & ECMXF_STS_FIFO_EN), "deadline 0 iff FIFOs off");
		const int pick = ecmxf_pump_sched_pick(&s, &f, &last, now, kick, sent);
		require(pick == ECMXF_PUMP_PICK_NONE || pick == ECMXF_PUMP_PICK_FIFO || pick == ECMXF_PUMP_PICK_WKC,
			"pick");
		require(pick == ECMXF_PUMP_PICK_NONE || (last.ecm_status & ECMXF_STS_FIFO_EN), "no pick while off");
		if (pick == ECMXF_PUMP_PICK_WKC) {
			require(!f.busy[ECMXF_PUMP_SLOT_WKC] && wkcNs && now >= s.next_wkc_ns, "read due and free");
			ecmxf_pump_sched_wkc(&s, now);
			require(s.next_wkc_ns > now, "next read after now");
			ecmxf_pump_sched_sent(&f, ECMXF_PUMP_SLOT_WKC, s.next_tick_ns);
		} else if (pick == ECMXF_PUMP_PICK_FIFO) {
			require(!f.busy[0] || !f.busy[1], "two FIFO commands at most");
			require((flags & ECMXF_PUMP_S_FIFO_NEXT) || !f.busy[f.newest], "one without FIFO_NEXT");
			const unsigned i = ecmxf_pump_sched_fifo(&s, &f, now);
			require(i < 2 && !f.busy[i] && f.newest == i, "a free slot, the newest");
			require(s.next_tick_ns == now + pollNs && !s.again, "the timer restarts");
			const u32 level = ecmxf_pump_sched_level(&p, &f, &last);
			require(level >= ecmxf_pump_flight_pushed(&f), "level counts the frames in flight");
			const u32 avail = static_cast<u32>(std::min<u64>(ring, 0xffff));
			const bool send = ecmxf_pump_sched_plan(&p, &f, i, level, avail, ECMXF_PUMP_F_READ);
			const ecmxf_pump_plan &pl = f.plan[i];
			require(f.skipped[i] == pl.skip && pl.skip + pl.push <= avail, "plan within the ring");
			ring -= pl.skip;
			if (!send || (data[11] & 0x20)) {
				const u32 sk = ecmxf_pump_sched_unsent(&f, i);
				require(sk == pl.skip && ecmxf_pump_sched_unsent(&f, i) == 0, "skipped counted once");
			} else {
				const u32 freed = ecmxf_pump_sched_sent(&f, i, s.next_tick_ns);
				require(freed == (f.released[i] ? pl.push : 0), "freed when sent");
				ring -= freed;
			}
		}
		for (unsigned w = 0; w < ECMXF_PUMP_SLOTS; w++)
			require(!ecmxf_pump_sched_waits(&s, &f, w, data[2] * 1000ULL, now) ||
					(f.busy[w] && now < f.answer_by_ns[w] && 2 * pollNs <= data[2] * 1000ULL),
				"an answer waits only while the next command is sure to come");
		// one command finishes: the oldest FIFO command, or the read
		unsigned i = f.newest ^ 1U;
		if (!f.busy[i])
			i = f.newest;
		if (!f.busy[i] || (data[11] & 0x10))
			i = ECMXF_PUMP_SLOT_WKC;
		if (!f.busy[i] || !(data[11] & 0x08))
			continue;
		const int status = data[11] & 4 ? (data[11] & 1 ? -ECONNRESET : -ETIMEDOUT) : 0;
		u32 skipped = 0;
		const u32 planSkip = i < 2 ? f.skipped[i] : 0;
		const int done = ecmxf_pump_sched_finish(&f, i, status, &skipped);
		require(!f.busy[i] && skipped == planSkip, "finish frees the slot, counts the skipped");
		require(done == (status == -ECONNRESET ? ECMXF_PUMP_DONE_STOP
				 : status		  ? ECMXF_PUMP_DONE_FAILED
							  : ECMXF_PUMP_DONE_ANSWER),
			"finish outcome");
		const u32 push = i < 2 ? f.plan[i].push : 0;
		const bool released = i < 2 && f.released[i];
		ecmxf_pump_acct a;
		if (done == ECMXF_PUMP_DONE_FAILED) {
			ecmxf_pump_sched_failed(&p, &f, i, &a);
			require(a.failures == 1 && a.dropped == push && a.free == (released ? 0 : push), "lost");
			checkAcct(a, push, released);
			require(a.free <= ring, "lost frames were in the ring");
			ring -= a.free;
			continue;
		}
		if (done != ECMXF_PUMP_DONE_ANSWER || i == ECMXF_PUMP_SLOT_WKC)
			continue;
		const ecmxf_rsp_hdr h = recordHeader(data);
		const int err = ecmxf_pump_sched_answer(&p, &f, i, &h, h.len, &a);
		require(err == 0 || err == -EREMOTEIO || err == -EPROTO, "answer errno");
		require(a.ops == 1 && a.answered == (err == 0), "answered");
		require(err != -EREMOTEIO || (!a.free && a.dropped == (released ? push : 0)), "command error");
		require(err == -EREMOTEIO || released || a.free == push, "taken frames leave the ring");
		require(err == 0 || !a.store, "no input from a bad answer");
		require(a.store <= ecmxf_pump_per_read(&p), "store <= per read");
		require(a.free <= ring, "answered frames were in the ring");
		ring -= a.free;
		const bool againBefore = s.again;
		ecmxf_pump_sched_left(&s, &f, i, &h, static_cast<int>(std::min<u64>(ring, 0xffff)), &a);
		require(!s.again || againBefore || (a.moved && a.answered), "work left by a command that moved");
		checkAcct(a, push, released);
	}
}

/// The library's synchronous cycles (and the estimate) over the records.
void fuzzCycles(ecmxf_pump &p, u64 busNs, const uint8_t *data, size_t size)
{
	ecmxf_pump_est e;
	ecmxf_pump_est_start(&e, busNs, 0);
	const u32 maxReads = ecmxf_pump_max_reads(&p);
	const u32 perWrite = ecmxf_pump_per_write(&p);
	u64 now = 0;
	for (; size >= 12; data += 12, size -= 12) {
		now += data[0] * 53ULL;
		const u32 inFlight = data[2] % 8;
		const u64 have = u64{ e.rx_level } + inFlight;
		const u32 level = ecmxf_pump_est_cycle(&e, &p, inFlight, now);
		require(level <= have && (p.out_size || !level), "estimate <= count + in flight");
		ecmxf_pump_cycle c;
		ecmxf_pump_cycle_start(&c, level, data[3] & 1);
		const u32 room = p.rx_fill > level ? p.rx_fill - level : 0;
		const u32 maxCmds = 1 + maxReads + (perWrite ? room / perWrite + 1 : 0) + 1;
		u32 rng = static_cast<u32>(data[4] | data[5] << 8 | data[6] << 16) | static_cast<u32>(data[7]) << 24;
		u32 cmds = 0;
		ecmxf_pump_plan pl;
		bool withWkc = false;
		while (ecmxf_pump_cycle_next(&p, &c, &pl, &withWkc)) {
			require(++cmds <= maxCmds, "a cycle ends");
			require(!withWkc || cmds == 1, "the read rides with the first command");
			rng = rng * 1103515245U + 12345U;
			ecmxf_pump_result res{};
			res.taken = pl.push;
			res.refused = (rng >> 8) % 7 == 0 ? pl.push : 0;
			res.popped = pl.read && ecmxf_pump_per_read(&p) ? (rng >> 12) % (ecmxf_pump_per_read(&p) + 1) : 0;
			res.tx_overrun = (rng >> 20) & 1;
			const u32 txCnt = (rng >> 24) % 16;
			ecmxf_pump_est_pushed(&e, &pl, (rng >> 4) & 15, now, e.cycles);
			u32 dropped = 0;
			ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &res, txCnt, now, &dropped);
		}
		require(c.state == ECMXF_PUMP_C_DONE, "done");
		require(c.pushed <= std::max<u32>(room, 1), "a cycle pushes at most its room, or one frame");
		require(c.reads <= maxReads, "reads bounded");
		require(ecmxf_pump_cycle_wkc_alone(&c) == (c.wkc && !c.wkc_carried), "read alone");
	}
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
	const uint8_t *const records = data;
	const size_t recordBytes = size;
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
		const ecmxf_rsp_hdr h = recordHeader(data);
		const u32 rxLen = h.len;
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
	const unsigned schedFlags = (outSize ^ inSize) & 3;
	const u64 pollNs = 1 + txDepth * 100ULL;
	const u64 wkcNs = (rxDepth & 3) * 250ULL;
	ecmxf_pump_init(&p, outSize, inSize, dataSize, rxDepth, rxFill, txDepth);
	fuzzSchedule(p, schedFlags, pollNs, wkcNs, records, recordBytes);
	ecmxf_pump_init(&p, outSize, inSize, dataSize, rxDepth, rxFill, txDepth);
	fuzzCycles(p, pollNs & 1 ? 0 : pollNs, records, recordBytes);
	return 0;
}
