// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-pump-sched.c - the PDO pump's schedule, sans I/O
 *
 * ecmxf-pump.c plans one FIFO command and reads its answer; this file
 * decides everything around it, once for the kernel's pump and the
 * library's FIFO path: which of the pump's commands goes next (the FIFO
 * command, or the working counter read that rides in the exchange that
 * fetches its answer), two FIFO commands in flight (the answer of one
 * taken by the exchange of the next), which answer belongs to which
 * command, the frames counted in flight, the RxFIFO estimate of a host
 * that keeps time, and what is skipped, lost and counted where.  The
 * callers move the frames, take their locks and read their clocks; they
 * hand the times in (nanoseconds of any one clock).
 *
 * The kernel's pump (kmod/ecmxf-pump.c), one command per turn of its
 * worker:
 *
 *	ecmxf_pump_sched_pick()		the FIFO command or the read, or none
 *	ecmxf_pump_sched_fifo()		the FIFO slot, the timer
 *	ecmxf_pump_sched_level()	the level with the frames in flight
 *	ecmxf_pump_sched_plan()		ecmxf_pump_next() into the slot
 *	ecmxf_pump_sched_sent()		in flight (or _unsent(): not sent)
 *	ecmxf_pump_sched_finish()	answered, failed, or the chip reset
 *	ecmxf_pump_sched_answer()	what to free, store and count
 *	ecmxf_pump_sched_left()		the underruns, whether to go again
 *
 * The library's synchronous cycle: ecmxf_pump_est_cycle(), then
 * ecmxf_pump_cycle_next() and ecmxf_pump_cycle_answer() until there is
 * nothing more to send; with the FIFO answer left to the next cycle,
 * ecmxf_pump_cycle_ahead() plans the one command of a cycle in a slot of
 * &struct ecmxf_pump_flight.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-pump.h"

#ifdef __KERNEL__
#include <linux/math64.h>
#else
static inline u64 div64_u64(u64 dividend, u64 divisor)
{
	return dividend / divisor;
}
#endif

/**
 * ecmxf_pump_max_reads() - read-only commands one cycle may add
 * @p: the pump
 *
 * A TxFIFO backlog after a late cycle is popped by read-only commands
 * while the answers' TxFIFO count says frames are left, at most what the
 * TxFIFO holds in answers plus two (the count lags by up to two
 * exchanges).
 *
 * Return: the TxFIFO depth divided by ecmxf_pump_per_read(), plus 2; 0
 * without inputs.
 */
u32 ecmxf_pump_max_reads(const struct ecmxf_pump *p)
{
	u32 per_read = ecmxf_pump_per_read(p);

	return per_read ? p->tx_depth / per_read + 2 : 0;
}

/**
 * ecmxf_pump_sched_init() - set the timers up
 * @s: the schedule
 * @flags: %ECMXF_PUMP_S_FIFO_NEXT, %ECMXF_PUMP_S_WKC_NEXT
 * @poll_ns: the FIFO command period
 * @wkc_ns: the working counter read period, 0 never
 *
 * Both commands are due at once.
 */
void ecmxf_pump_sched_init(struct ecmxf_pump_sched *s, unsigned int flags,
			   u64 poll_ns, u64 wkc_ns)
{
	memset(s, 0, sizeof(*s));
	s->flags = flags;
	s->poll_ns = poll_ns;
	s->wkc_ns = wkc_ns;
}

/* the chip runs its FIFOs (ECM status bit 6 in the last header) */
static bool ecmxf_pump_fifo_on(const struct ecmxf_rsp_hdr *h)
{
	return h && (h->ecm_status & ECMXF_STS_FIFO_EN);
}

/**
 * ecmxf_pump_sched_pick() - which of the pump's commands goes next
 * @s: the schedule
 * @f: the commands in flight
 * @h: the last response header (NULL: none yet)
 * @now: the time
 * @kick: INT1 fired (a FIFO threshold flag)
 * @newest_sent: the newest FIFO command has gone out and waits for its
 *	answer (only asked when it is in flight)
 *
 * Nothing while the chip's FIFOs are off.  The FIFO command may go when
 * none is in flight, or, with %ECMXF_PUMP_S_FIFO_NEXT, when the one in
 * flight has gone out and the older slot is free (the new one fetches its
 * answer); it is due when its timer expired, the last answer left work,
 * or @kick unless ecmxf_pump_sched_kick_held(): INT1 brings at most one
 * FIFO command forward per timer period, so a level INT1 held by a source
 * the pump does not clear (a frame, WKC or encoder flag) at most doubles
 * the pump's rate instead of running it at the link's.  The working
 * counter read is due when it is not in flight and its timer expired.
 * The FIFO command goes first: it carries the process data, and the read
 * rides behind it.  While one is in flight, the read goes next: it rides
 * in the exchange that fetches its answer, and a busy pump would
 * otherwise never read.
 *
 * Return: %ECMXF_PUMP_PICK_NONE, %ECMXF_PUMP_PICK_FIFO or
 * %ECMXF_PUMP_PICK_WKC.
 */
int ecmxf_pump_sched_pick(const struct ecmxf_pump_sched *s,
			  const struct ecmxf_pump_flight *f,
			  const struct ecmxf_rsp_hdr *h, u64 now, bool kick,
			  bool newest_sent)
{
	bool newest = f->busy[f->newest];
	bool older = f->busy[!f->newest];
	bool fifo, wkc;

	if (!ecmxf_pump_fifo_on(h))
		return ECMXF_PUMP_PICK_NONE;
	fifo = !newest || ((s->flags & ECMXF_PUMP_S_FIFO_NEXT) && !older &&
			   newest_sent);
	kick = kick && !ecmxf_pump_sched_kick_held(s, now);
	fifo = fifo && (s->again || now >= s->next_tick_ns || kick);
	wkc = !f->busy[ECMXF_PUMP_SLOT_WKC] && s->wkc_ns &&
	      now >= s->next_wkc_ns;
	if (wkc && (!fifo || newest))
		return ECMXF_PUMP_PICK_WKC;
	return fifo ? ECMXF_PUMP_PICK_FIFO : ECMXF_PUMP_PICK_NONE;
}

/**
 * ecmxf_pump_sched_kick_held() - does the schedule ignore INT1 now?
 * @s: the schedule
 * @now: the time
 *
 * The last FIFO command was brought forward by INT1, its timer has not
 * expired since and its answer left no work: INT1 cannot bring the next
 * one forward.  The caller may consume the INT1 it saw (it asks for
 * nothing the timer-driven command will not do).
 *
 * Return: true while INT1 is held.
 */
bool ecmxf_pump_sched_kick_held(const struct ecmxf_pump_sched *s, u64 now)
{
	return s->kicked && !s->again && now < s->next_tick_ns;
}

/**
 * ecmxf_pump_sched_deadline() - when the pump's timers want it next
 * @s: the schedule
 * @h: the last response header (NULL: none yet)
 *
 * Return: the earlier of the two timers (1 for a timer at 0), or 0 while
 * the chip's FIFOs are off.
 */
u64 ecmxf_pump_sched_deadline(const struct ecmxf_pump_sched *s,
			      const struct ecmxf_rsp_hdr *h)
{
	u64 t;

	if (!ecmxf_pump_fifo_on(h))
		return 0;
	t = s->next_tick_ns;
	if (s->wkc_ns && s->next_wkc_ns < t)
		t = s->next_wkc_ns;
	return t ? t : 1;
}

/**
 * ecmxf_pump_sched_fifo() - a FIFO command is being built
 * @s: the schedule: the FIFO timer restarts from @now, the work left is
 *	being done
 * @f: the commands in flight
 * @now: the time
 *
 * The slot is the newest one when it is free, else the other one (the
 * one in flight is then the older).  Its plan and skip count are cleared
 * for ecmxf_pump_sched_plan(); with %ECMXF_PUMP_S_FIFO_NEXT its frames
 * leave the ring when it is sent (the answer waits for the next command).
 * A command before its timer with no work left was brought forward by
 * INT1 (&ecmxf_pump_sched.kicked).
 *
 * Return: the slot, 0 or 1.
 */
unsigned int ecmxf_pump_sched_fifo(struct ecmxf_pump_sched *s,
				   struct ecmxf_pump_flight *f, u64 now)
{
	unsigned int i;

	if (f->busy[f->newest])
		f->newest ^= 1U;
	i = f->newest;
	memset(&f->plan[i], 0, sizeof(f->plan[i]));
	f->skipped[i] = 0;
	f->released[i] = s->flags & ECMXF_PUMP_S_FIFO_NEXT;
	s->kicked = !s->again && now < s->next_tick_ns;
	s->again = false;
	s->next_tick_ns = now + s->poll_ns;
	return i;
}

/**
 * ecmxf_pump_sched_wkc() - a working counter read is being built
 * @s: the schedule
 * @now: the time
 *
 * The next read is due a period after the last one was due, not after
 * @now: late wake-ups do not stretch the period (a reader counting reads
 * over N periods sees N); after a gap of more than a period, one read
 * and no burst (a period after @now).
 */
void ecmxf_pump_sched_wkc(struct ecmxf_pump_sched *s, u64 now)
{
	s->next_wkc_ns += s->wkc_ns;
	if (s->next_wkc_ns <= now)
		s->next_wkc_ns = now + s->wkc_ns;
}

/**
 * ecmxf_pump_flight_pushed() - output frames in flight
 * @f: the commands in flight
 *
 * Return: the frames the FIFO commands in flight push, which no header
 * shows yet.
 */
u32 ecmxf_pump_flight_pushed(const struct ecmxf_pump_flight *f)
{
	return (f->busy[0] ? f->plan[0].push : 0) +
	       (f->busy[1] ? f->plan[1].push : 0);
}

/**
 * ecmxf_pump_flight_busy() - is any of the pump's commands in flight?
 * @f: the commands in flight
 *
 * Return: true while a FIFO command or the working counter read is.
 */
bool ecmxf_pump_flight_busy(const struct ecmxf_pump_flight *f)
{
	return f->busy[0] || f->busy[1] || f->busy[ECMXF_PUMP_SLOT_WKC];
}

/**
 * ecmxf_pump_sched_level() - the RxFIFO level a new FIFO command plans with
 * @p: the pump
 * @f: the commands in flight
 * @h: the latest response header, or NULL before the first
 *
 * Return: ecmxf_pump_level() plus the frames in flight
 * (ecmxf_pump_flight_pushed()).
 */
u32 ecmxf_pump_sched_level(const struct ecmxf_pump *p,
			   const struct ecmxf_pump_flight *f,
			   const struct ecmxf_rsp_hdr *h)
{
	return ecmxf_pump_level(p, h) + ecmxf_pump_flight_pushed(f);
}

/**
 * ecmxf_pump_sched_plan() - plan the FIFO command of a slot
 * @p: the pump
 * @f: the commands in flight; the slot's plan and skip count are set
 * @slot: from ecmxf_pump_sched_fifo()
 * @level: the RxFIFO level (ecmxf_pump_sched_level())
 * @avail: output frames ready
 * @flags: ecmxf_pump_next()'s
 *
 * The frames skipped (&ecmxf_pump_plan.skip) are the caller's to drop
 * now; they are counted when the command finishes, or when it is not
 * sent (ecmxf_pump_sched_unsent()).
 *
 * Return: true when there is a command to send.
 */
bool ecmxf_pump_sched_plan(const struct ecmxf_pump *p,
			   struct ecmxf_pump_flight *f, unsigned int slot,
			   u32 level, u32 avail, unsigned int flags)
{
	bool send = ecmxf_pump_next(p, level, avail, flags, &f->plan[slot]);

	f->skipped[slot] = f->plan[slot].skip;
	return send;
}

/**
 * ecmxf_pump_sched_sent() - a command went into the engine
 * @f: the commands in flight
 * @slot: the FIFO slot or %ECMXF_PUMP_SLOT_WKC
 * @answer_by_ns: until when its answer may wait for the next FIFO
 *	command (ecmxf_pump_sched_waits())
 *
 * Return: output frames that leave the ring now (a FIFO command whose
 * answer waits for the next one: the engine has its copy), else 0.
 */
u32 ecmxf_pump_sched_sent(struct ecmxf_pump_flight *f, unsigned int slot,
			  u64 answer_by_ns)
{
	f->busy[slot] = true;
	f->answer_by_ns[slot] = answer_by_ns;
	if (slot == ECMXF_PUMP_SLOT_WKC || !f->released[slot])
		return 0;
	return f->plan[slot].push;
}

/**
 * ecmxf_pump_sched_unsent() - a planned command did not go out
 * @f: the commands in flight
 * @slot: the FIFO slot or %ECMXF_PUMP_SLOT_WKC
 *
 * Return: the frames its plan skipped, to be counted now (skipped frames
 * are counted whether or not a command went).
 */
u32 ecmxf_pump_sched_unsent(struct ecmxf_pump_flight *f, unsigned int slot)
{
	u32 n;

	if (slot == ECMXF_PUMP_SLOT_WKC)
		return 0;
	n = f->skipped[slot];
	f->skipped[slot] = 0;
	return n;
}

/**
 * ecmxf_pump_sched_waits() - may a command's answer wait for the next one?
 * @s: the schedule
 * @f: the commands in flight
 * @slot: the command the engine holds alone (sent, waiting)
 * @timeout_ns: the time it is allowed
 * @now: the time
 *
 * With %ECMXF_PUMP_S_FIFO_NEXT the FIFO command's answer, with
 * %ECMXF_PUMP_S_WKC_NEXT the read's, is fetched by the exchange of the
 * next FIFO command: nothing need be exchanged for it alone while that
 * command is sure to come, i.e. before the timer tick that was next when
 * the command was sent (a later tick may find nothing to send), and with
 * two periods well within the time the command is allowed.
 *
 * Return: true when the answer may wait.
 */
bool ecmxf_pump_sched_waits(const struct ecmxf_pump_sched *s,
			    const struct ecmxf_pump_flight *f,
			    unsigned int slot, u64 timeout_ns, u64 now)
{
	unsigned int flag = slot == ECMXF_PUMP_SLOT_WKC ?
			    ECMXF_PUMP_S_WKC_NEXT : ECMXF_PUMP_S_FIFO_NEXT;

	return f->busy[slot] && (s->flags & flag) &&
	       s->poll_ns * 2 <= timeout_ns && now < f->answer_by_ns[slot];
}

/**
 * ecmxf_pump_sched_finish() - a command left the engine
 * @f: the commands in flight; the slot is free again
 * @slot: the FIFO slot or %ECMXF_PUMP_SLOT_WKC
 * @status: its outcome, 0 or a negative errno
 * @skipped: set to the frames its plan skipped, counted now
 *
 * Return: %ECMXF_PUMP_DONE_ANSWER (read the answer:
 * ecmxf_pump_sched_answer() or ecmxf_pump_wkc_answer()),
 * %ECMXF_PUMP_DONE_FAILED (ecmxf_pump_sched_failed()) or
 * %ECMXF_PUMP_DONE_STOP (-ECONNRESET: the chip reset, its FIFOs are gone;
 * the pump stops).
 */
int ecmxf_pump_sched_finish(struct ecmxf_pump_flight *f, unsigned int slot,
			    int status, u32 *skipped)
{
	f->busy[slot] = false;
	*skipped = ecmxf_pump_sched_unsent(f, slot);
	if (status == -ECONNRESET)
		return ECMXF_PUMP_DONE_STOP;
	return status ? ECMXF_PUMP_DONE_FAILED : ECMXF_PUMP_DONE_ANSWER;
}

/**
 * ecmxf_pump_sched_cancel() - a command was withdrawn from the engine
 * @f: the commands in flight; the slot is free again
 * @slot: the FIFO slot or %ECMXF_PUMP_SLOT_WKC
 *
 * The pump stops (its worker does): nothing is counted.
 */
void ecmxf_pump_sched_cancel(struct ecmxf_pump_flight *f, unsigned int slot)
{
	f->busy[slot] = false;
	if (slot != ECMXF_PUMP_SLOT_WKC)
		f->skipped[slot] = 0;
}

/**
 * ecmxf_pump_sched_answer() - what a FIFO command's answer moves and counts
 * @p: the pump (ecmxf_pump_answer() keeps its bookkeeping)
 * @f: the commands in flight
 * @slot: the FIFO slot, finished (ecmxf_pump_sched_finish())
 * @h: the answer's header
 * @rx_len: the answer's data bytes
 * @a: set: one command answered; the frames to free, drop and store and
 *	the losses to count
 *
 * Frames still in the ring leave it when taken; those freed when the
 * command was sent are only counted when refused.  A command error takes
 * nothing: frames still in the ring go again, those that left it are
 * dropped (newer ones went since).  With -EPROTO the pushed frames are
 * taken and the answer's input frames are lost.
 *
 * Return: ecmxf_pump_answer()'s: 0, -EREMOTEIO or -EPROTO.
 */
int ecmxf_pump_sched_answer(struct ecmxf_pump *p,
			    const struct ecmxf_pump_flight *f,
			    unsigned int slot, const struct ecmxf_rsp_hdr *h,
			    u32 rx_len, struct ecmxf_pump_acct *a)
{
	const struct ecmxf_pump_plan *pl = &f->plan[slot];
	bool released = f->released[slot];
	struct ecmxf_pump_result res;
	int err;

	memset(a, 0, sizeof(*a));
	a->ops = 1;
	err = ecmxf_pump_answer(p, pl, h, rx_len, &res);
	if (err == -EREMOTEIO) {
		if (released)
			a->dropped = pl->push;
		return err;
	}
	if (res.taken) {
		a->free = released ? 0 : res.taken;
		a->dropped = res.refused;
		a->refusals = res.refused ? 1 : 0;
		a->wake_out = !released;
	}
	a->moved = res.taken || res.popped;
	if (err)
		return err;
	a->answered = true;
	a->store = res.popped;
	a->tx_overruns = res.tx_overrun;
	a->rx_underruns = res.rx_underrun;
	return 0;
}

/**
 * ecmxf_pump_sched_left() - after an answer: underruns, and work left
 * @s: the schedule: &ecmxf_pump_sched.again is set when work is left
 * @f: the commands in flight
 * @slot: the FIFO slot answered
 * @h: its answer's header
 * @avail: output frames ready now, after the answer's were freed
 *	(negative: the ring is broken)
 * @a: from ecmxf_pump_sched_answer() (nothing changes unless the answer
 *	was read whole: &ecmxf_pump_acct.answered)
 *
 * An RxFIFO underrun with no output frame ready is the application's
 * (an output ring underrun).  A command that moved frames leaves work
 * when output frames are ready, or TxPDO frames are queued and no later
 * FIFO command is in flight (that one pops them).
 */
void ecmxf_pump_sched_left(struct ecmxf_pump_sched *s,
			   const struct ecmxf_pump_flight *f,
			   unsigned int slot, const struct ecmxf_rsp_hdr *h,
			   int avail, struct ecmxf_pump_acct *a)
{
	bool successor = f->busy[!slot];

	if (!a->answered)
		return;
	if (a->rx_underruns && !avail)
		a->out_underruns = 1;
	if (a->moved && ((h->tx_fifo_cnt && !successor) || avail > 0))
		s->again = true;
}

/**
 * ecmxf_pump_sched_failed() - a command failed after it may have reached
 *	the chip (no answer, bad packets)
 * @p: the pump (ecmxf_pump_lost() keeps its bookkeeping)
 * @f: the commands in flight
 * @slot: the slot, finished (ecmxf_pump_sched_finish())
 * @a: set: one failure; a FIFO command's frames are lost (dropped, never
 *	sent again: a second copy would reach the bus after newer frames)
 *	and leave the ring if still in it
 */
void ecmxf_pump_sched_failed(struct ecmxf_pump *p,
			     const struct ecmxf_pump_flight *f,
			     unsigned int slot, struct ecmxf_pump_acct *a)
{
	u32 lost;

	memset(a, 0, sizeof(*a));
	a->failures = 1;
	if (slot == ECMXF_PUMP_SLOT_WKC)
		return;
	lost = ecmxf_pump_lost(p, &f->plan[slot]);
	if (!lost)
		return;
	a->free = f->released[slot] ? 0 : lost;
	a->dropped = lost;
	a->wake_out = !f->released[slot];
}

/**
 * ecmxf_pump_est_start() - start estimating (a cyclic exchange starts)
 * @e: the estimate
 * @bus_ns: the bus cycle, 0 unknown
 * @now: the time: the FIFOs were cleared, both counts are 0
 */
void ecmxf_pump_est_start(struct ecmxf_pump_est *e, u64 bus_ns, u64 now)
{
	memset(e, 0, sizeof(*e));
	e->bus_ns = bus_ns;
	e->rx_ns = now;
	e->tx_ns = now;
}

/**
 * ecmxf_pump_est_cycle() - a cycle starts: the RxFIFO level to plan with
 * @e: the estimate (counts the cycle)
 * @p: the pump
 * @in_flight: frames pushed by commands whose answer is not taken yet
 *	(ecmxf_pump_flight_pushed())
 * @now: the time
 *
 * The count of the last write's answer plus @in_flight, less the frames
 * the bus took since the chip ran that write: one per bus cycle, or one
 * per cycle when the bus cycle is unknown.
 *
 * Return: the level, at least 0; 0 without outputs.
 */
u32 ecmxf_pump_est_cycle(struct ecmxf_pump_est *e,
			 const struct ecmxf_pump *p, u32 in_flight, u64 now)
{
	u64 gone, have;

	e->cycles++;
	if (!p->out_size)
		return 0;
	gone = e->cycles - e->rx_cycle;
	if (e->bus_ns)
		gone = now > e->rx_ns ? div64_u64(now - e->rx_ns, e->bus_ns) : 0;
	have = (u64)e->rx_level + in_flight;
	return gone >= have ? 0 : (u32)(have - gone);
}

/**
 * ecmxf_pump_est_pushed() - a write's answer was taken
 * @e: the estimate
 * @pl: the command's plan (nothing changes without a push)
 * @rx_cnt: the answer's RxFIFO count
 * @at: when the chip ran the command
 * @cycle: in which cycle (&ecmxf_pump_est.cycles then)
 */
void ecmxf_pump_est_pushed(struct ecmxf_pump_est *e,
			   const struct ecmxf_pump_plan *pl, u32 rx_cnt,
			   u64 at, u64 cycle)
{
	if (!pl->push)
		return;
	e->rx_level = rx_cnt;
	e->rx_ns = at;
	e->rx_cycle = cycle;
}

/**
 * ecmxf_pump_est_popped() - the first read's answer of a cycle was taken
 * @e: the estimate
 * @pl: the command's plan (nothing changes without a read)
 * @res: ecmxf_pump_answer()'s result
 * @tx_cnt: the answer's TxFIFO count
 * @at: when the chip ran the command
 * @dropped: set to the TxPDO frames the full TxFIFO dropped, estimated
 *	with a known bus cycle: the count left by the last read plus one
 *	frame per bus cycle since, less the frames queued (popped plus
 *	left); else 0
 *
 * Return: the TxFIFO was full (&ecmxf_pump_result.tx_overrun).
 */
bool ecmxf_pump_est_popped(struct ecmxf_pump_est *e,
			   const struct ecmxf_pump_plan *pl,
			   const struct ecmxf_pump_result *res, u32 tx_cnt,
			   u64 at, u32 *dropped)
{
	u64 made, expected, queued;

	*dropped = 0;
	if (!pl->read)
		return false;
	if (res->tx_overrun && e->bus_ns) {
		queued = (u64)res->popped + tx_cnt;
		made = at > e->tx_ns ? div64_u64(at - e->tx_ns, e->bus_ns) : 0;
		expected = e->tx_level + made;
		if (expected > queued)
			*dropped = expected - queued > 0xffffffffU ?
				   0xffffffffU : (u32)(expected - queued);
	}
	ecmxf_pump_est_read(e, tx_cnt, at);
	return res->tx_overrun;
}

/**
 * ecmxf_pump_est_read() - a read-only command's answer was taken
 * @e: the estimate
 * @tx_cnt: the answer's TxFIFO count
 * @at: when the chip ran the command
 */
void ecmxf_pump_est_read(struct ecmxf_pump_est *e, u32 tx_cnt, u64 at)
{
	e->tx_level = tx_cnt;
	e->tx_ns = at;
}

/**
 * ecmxf_pump_cycle_start() - a cycle of synchronous FIFO commands starts
 * @c: the cycle
 * @level: the RxFIFO level (ecmxf_pump_est_cycle())
 * @wkc: the cycle reads the working counter
 */
void ecmxf_pump_cycle_start(struct ecmxf_pump_cycle *c, u32 level,
			    bool wkc)
{
	memset(c, 0, sizeof(*c));
	c->level = level;
	c->wkc = wkc;
}

/* the frames a cycle can offer: copies of the one output frame, any number */
static u32 ecmxf_pump_cycle_avail(const struct ecmxf_pump *p)
{
	return p->out_size ? p->rx_fill : 0;
}

/**
 * ecmxf_pump_cycle_next() - the cycle's next FIFO command
 * @p: the pump
 * @c: the cycle
 * @pl: the plan
 * @with_wkc: set when the working counter read rides with this command
 *	(in the exchange that fetches its answer)
 *
 * The first command pushes at least one copy of the outputs and up to
 * the fill level, and reads; read-only commands follow while frames are
 * left in the TxFIFO; then writes top the RxFIFO up to the fill level,
 * unless it refused frames.
 *
 * Return: false when the cycle has nothing more to send.
 */
bool ecmxf_pump_cycle_next(const struct ecmxf_pump *p,
			   struct ecmxf_pump_cycle *c,
			   struct ecmxf_pump_plan *pl, bool *with_wkc)
{
	*with_wkc = false;
	switch (c->state) {
	case ECMXF_PUMP_C_FIRST:
		if (!ecmxf_pump_next(p, c->level, ecmxf_pump_cycle_avail(p),
				     ECMXF_PUMP_F_READ | ECMXF_PUMP_F_ONE, pl))
			break;
		*with_wkc = c->wkc;
		c->wkc_carried = c->wkc;
		return true;
	case ECMXF_PUMP_C_READ:
		ecmxf_pump_next(p, 0, 0, ECMXF_PUMP_F_READ, pl);
		return true;
	case ECMXF_PUMP_C_WRITE:
		if (ecmxf_pump_next(p, c->level + c->pushed,
				    ecmxf_pump_cycle_avail(p), 0, pl))
			return true;
		break;
	default:
		memset(pl, 0, sizeof(*pl));
		return false;
	}
	c->state = ECMXF_PUMP_C_DONE;
	return false;
}

/**
 * ecmxf_pump_cycle_answer() - the answer to the cycle's last command
 * @p: the pump
 * @c: the cycle
 * @e: the estimate: the answer's TxFIFO count (a read's)
 * @pl: the command's plan
 * @res: ecmxf_pump_answer()'s result (it returned 0)
 * @tx_cnt: the answer's TxFIFO count
 * @at: when the chip ran the command
 * @dropped: set to the TxPDO frames a full TxFIFO dropped (estimated
 *	from the cycle's first read: ecmxf_pump_est_popped()), else 0
 *
 * A refusal (the RxFIFO was full) ends the writes; a read that popped
 * nothing, or whose answer shows the TxFIFO empty, ends the reads, as
 * does ecmxf_pump_max_reads().
 *
 * Return: the cycle's first read found the TxFIFO full.
 */
bool ecmxf_pump_cycle_answer(const struct ecmxf_pump *p,
			     struct ecmxf_pump_cycle *c,
			     struct ecmxf_pump_est *e,
			     const struct ecmxf_pump_plan *pl,
			     const struct ecmxf_pump_result *res, u32 tx_cnt,
			     u64 at, u32 *dropped)
{
	u32 max_reads = ecmxf_pump_max_reads(p);
	bool overrun = false;

	*dropped = 0;
	if (c->state == ECMXF_PUMP_C_READ) {
		ecmxf_pump_est_read(e, tx_cnt, at);
		c->reads++;
		if (res->popped && tx_cnt && c->reads < max_reads)
			return false;
	} else {
		overrun = ecmxf_pump_est_popped(e, pl, res, tx_cnt, at,
						dropped);
		c->pushed += pl->push;
		if (res->refused)
			c->refused = true;
		if (c->state == ECMXF_PUMP_C_FIRST && pl->read && tx_cnt &&
		    max_reads) {
			c->state = ECMXF_PUMP_C_READ;
			return overrun;
		}
	}
	c->state = c->refused ? ECMXF_PUMP_C_DONE : ECMXF_PUMP_C_WRITE;
	return overrun;
}

/**
 * ecmxf_pump_cycle_wkc_alone() - does the read go on its own?
 * @c: the cycle, done
 *
 * Return: true when the cycle wants a working counter read and no FIFO
 * command carried it.
 */
bool ecmxf_pump_cycle_wkc_alone(const struct ecmxf_pump_cycle *c)
{
	return c->wkc && !c->wkc_carried;
}

/**
 * ecmxf_pump_cycle_ahead() - plan a cycle's one FIFO command whose answer
 *	the next cycle takes
 * @p: the pump
 * @f: the commands in flight
 * @slot: from ecmxf_pump_sched_fifo()
 * @level: ecmxf_pump_est_cycle() with the frames in flight
 *
 * As the first command of ecmxf_pump_cycle_next(): the extra reads and
 * writes would need its answer, so a backlog is left to the next cycles.
 *
 * Return: true (the command always goes: it offers this cycle's outputs
 * or reads).
 */
bool ecmxf_pump_cycle_ahead(const struct ecmxf_pump *p,
			    struct ecmxf_pump_flight *f, unsigned int slot,
			    u32 level)
{
	return ecmxf_pump_sched_plan(p, f, slot, level,
				     ecmxf_pump_cycle_avail(p),
				     ECMXF_PUMP_F_READ | ECMXF_PUMP_F_ONE);
}
