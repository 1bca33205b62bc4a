// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-pump.c - NEXTW ECM-XF: the PDO pump
 *
 * The pump runs in the link worker (ecmxf-worker.c): while the chip
 * reports its FIFO enabled it sends ECAT_PDO_DATA_FIFO_OP commands that
 * move output frames from the output ring into the chip's RxFIFO and pop
 * the TxFIFO into the input ring (the rings: ecmxf-ring.c); now and then
 * it reads the working counter.  It is woken by INT1 (the FIFO threshold
 * flags), by its own timer and by the work a previous command left.  Its
 * commands take turns with the files' commands.  The working counter read
 * has a command of its own beside the FIFO command's, so that it rides in
 * the exchange that fetches the FIFO command's answer (pipelining: three
 * exchanges for a cycle that reads it, not four).  With
 * %ECMXF_RING_F_FIFO_NEXT the FIFO command's answer is left to the next
 * FIFO command's exchange: two of them are then in flight (&struct
 * ecmxf_pump_slot.fifo), one exchange per pump cycle.
 *
 * What a command carries and what its answer means (the fill level, the
 * skipped frames, the refusals and losses, the EPROTO rules) is the
 * protocol core's pump (lib/core/ecmxf-pump.c), which the library's FIFO
 * path runs too; this file does the kernel's part: when to send, the
 * ring indices, the counters, the status block and the wake-ups.
 *
 * Locking: as ecmxf-ring.c.  The worker builds and submits the command
 * without &ecmxf_dev.lock and finishes it with the lock held.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/minmax.h>
#include <linux/module.h>
#include <linux/poll.h>

#include "ecmxf.h"

/*
 * time allowed for each pump command (module parameter pump_timeout_ms,
 * 10..60000): longer than the table's 100 ms, since a frame whose command
 * failed is dropped, never sent again
 */
static unsigned int ecmxf_param_pump_timeout_ms = 500;
module_param_named(pump_timeout_ms, ecmxf_param_pump_timeout_ms, uint, 0644);
MODULE_PARM_DESC(pump_timeout_ms,
		 "time allowed for each PDO pump command, ms (10..60000, default 500)");

/**
 * ecmxf_pump_busy() - is one of the pump's commands in the engine?
 * @edev: the device, lock held
 *
 * Return: true while the FIFO command or the working counter read is in
 * flight.
 */
bool ecmxf_pump_busy(const struct ecmxf_dev *edev)
{
	const struct ecmxf_pump_slot *p = &edev->pump;

	return p->fifo[0].busy || p->fifo[1].busy || p->wkc.busy;
}

/* the time allowed for each pump command, in microseconds */
static u32 ecmxf_pump_timeout_us(void)
{
	return clamp(READ_ONCE(ecmxf_param_pump_timeout_ms), 10U, 60000U) *
	       USEC_PER_MSEC;
}

/**
 * ecmxf_pump_answer_waits() - may the worker sleep with a command in flight?
 * @edev: the device; called by the worker without the lock
 *
 * With %ECMXF_RING_F_WKC_NEXT the working counter read's answer, with
 * %ECMXF_RING_F_FIFO_NEXT the FIFO command's, is left to the exchange of
 * the next FIFO command: the worker need not exchange for it alone while
 * that command is coming (the pump's timer runs, well within the time
 * the command is allowed, and its next tick, which may find nothing to
 * send, has not passed yet) and no reset waits.  The engine is the
 * worker's: whether the command is all it has in flight (no other pump
 * command, no file's request) is asked without the lock, which is taken
 * only then.
 *
 * Return: true when one of the pump's commands, sent, is all the engine
 * has in flight and may wait for the pump's next command.
 */
bool ecmxf_pump_answer_waits(struct ecmxf_dev *edev)
{
	struct ecmxf_pump_slot *p = &edev->pump;
	struct ecmxf_pump_cmd *c = &p->fifo[p->newest];
	u32 flag = ECMXF_RING_F_FIFO_NEXT;
	struct ecmxf_rings *r;
	bool waits;

	if (!ecmxf_engine_waits_only(&edev->e, &c->x)) {
		c = &p->wkc;
		flag = ECMXF_RING_F_WKC_NEXT;
		if (!ecmxf_engine_waits_only(&edev->e, &c->x))
			return false;
	}
	mutex_lock(&edev->lock);
	r = edev->rings;
	waits = c->busy && r && (r->setup_flags & flag) &&
		r->poll_ns * 2 <= (u64)c->x.timeout_us * NSEC_PER_USEC &&
		ktime_get_ns() < c->answer_by_ns &&
		list_empty(&edev->resets) && ecmxf_pump_deadline(edev);
	mutex_unlock(&edev->lock);
	return waits;
}

/**
 * ecmxf_pump_take() - should the pump send a command now?
 * @edev: the device, lock held
 * @now: ktime_get_ns()
 *
 * Due when rings exist, the pump has not stopped and the chip's FIFO is
 * on (ECM status bit 6 in the last header); then the FIFO command, when
 * it is not in flight (with %ECMXF_RING_F_FIFO_NEXT: when the one in
 * flight has gone out and waits for its answer, which the new one will
 * fetch) and its timer expired, INT1 fired (the FIFO threshold flags) or
 * the last one left work; else the working counter read, when it is not
 * in flight and due.  The FIFO command goes first: it carries the process
 * data, and the read rides behind it (while one is in flight, the read
 * goes next).  The choice is kept for ecmxf_pump_submit().
 *
 * Return: the rings with a reference for the command, or NULL.
 */
struct ecmxf_rings *ecmxf_pump_take(struct ecmxf_dev *edev, u64 now)
{
	struct ecmxf_rings *r = edev->rings;
	struct ecmxf_pump_slot *p = &edev->pump;
	struct ecmxf_pump_cmd *f = &p->fifo[p->newest];
	bool fifo, wkc;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped)
		return NULL;
	if (!(edev->last.ecm_status & ECMXF_STS_FIFO_EN))
		return NULL;
	fifo = !f->busy ||
	       ((r->setup_flags & ECMXF_RING_F_FIFO_NEXT) &&
		!p->fifo[!p->newest].busy && ecmxf_engine_sent(&edev->e, &f->x));
	fifo = fifo && (r->again || now >= r->next_tick_ns ||
			atomic_read(&edev->int1_flag));
	wkc = !p->wkc.busy && r->wkc_ns && now >= r->next_wkc_ns;
	if (!fifo && !wkc)
		return NULL;
	/*
	 * the read rides in the exchange that fetches the answer of the FIFO
	 * command in flight; a FIFO command that could go in its place
	 * (%ECMXF_RING_F_FIFO_NEXT) waits for that one exchange, else a
	 * busy pump would never read
	 */
	p->take_wkc = wkc && (!fifo || f->busy);
	/* this command is the exchange that INT1 asks for */
	if (!p->take_wkc)
		atomic_set(&edev->int1_flag, 0);
	kref_get(&r->ref);
	return r;
}

/**
 * ecmxf_pump_deadline() - when the pump wants to run next by its timers
 * @edev: the device, lock held
 *
 * Return: a ktime_get_ns() time, or 0 when the pump has no timer running.
 */
u64 ecmxf_pump_deadline(struct ecmxf_dev *edev)
{
	struct ecmxf_rings *r = edev->rings;
	u64 t;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped || !(edev->last.ecm_status & ECMXF_STS_FIFO_EN))
		return 0;
	t = r->next_tick_ns;
	if (r->wkc_ns && r->next_wkc_ns < t)
		t = r->next_wkc_ns;
	return t ? t : 1;
}

/* Build the working counter read in @edev->pump.wkc.x. */
static void ecmxf_pump_prepare_wkc(struct ecmxf_dev *edev,
				   struct ecmxf_rings *r, u64 now)
{
	struct ecmxf_xfer *x = &edev->pump.wkc.x;

	memset(x, 0, sizeof(*x));
	x->rx_buf = r->wkc_buf;
	x->rx_size = ECMXF_DATA_MAX;
	x->status = -EINPROGRESS;
	ecmxf_pump_wkc_cmd(&x->hdr);
	/*
	 * every wkc_ns from the first read on, not from whenever the worker
	 * woke: late wake-ups must not stretch the period (a reader counting
	 * reads over N periods sees N / period); after a gap of more than a
	 * period, one read, no burst
	 */
	r->next_wkc_ns += r->wkc_ns;
	if (r->next_wkc_ns <= now)
		r->next_wkc_ns = now + r->wkc_ns;
}

/*
 * Build the FIFO command @i of @edev->pump.fifo: what the protocol core
 * plans from what the output ring holds (up to the RxFIFO fill level and
 * the data section), popping TxPDO frames.  The frames of the other one,
 * when it is in flight, are in the RxFIFO for the plan, though no header
 * shows them yet.  Return: false when there is nothing to send.
 */
static bool ecmxf_pump_prepare(struct ecmxf_dev *edev, struct ecmxf_rings *r,
			       unsigned int i)
{
	struct ecmxf_pump_slot *p = &edev->pump;
	struct ecmxf_pump_cmd *c = &p->fifo[i];
	const struct ecmxf_pump_cmd *o = &p->fifo[!i];
	struct ecmxf_pump_plan *pl = &c->plan;
	struct ecmxf_xfer *x = &c->x;
	const struct ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&edev->e);
	u32 level;
	bool send;
	int avail;

	memset(x, 0, sizeof(*x));
	memset(pl, 0, sizeof(*pl));
	x->rx_buf = r->rx_buf[i];
	x->rx_size = ECMXF_DATA_MAX;
	x->tx_data = r->tx_buf[i];
	x->status = -EINPROGRESS;
	c->skipped = 0;
	c->released = r->setup_flags & ECMXF_RING_F_FIFO_NEXT;

	avail = ecmxf_ring_out_avail(r);
	if (avail < 0)
		return false;	/* ecmxf_pump_submit() stops the rings */
	r->pump.data_size = ecmxf_engine_data_size(&edev->e);
	level = ecmxf_pump_level(&r->pump, h) + (o->busy ? o->plan.push : 0);
	send = ecmxf_pump_next(&r->pump, level, (u32)avail, ECMXF_PUMP_F_READ,
			       pl);
	/*
	 * Fallen behind (the application produces faster than the chip
	 * takes): the oldest frames are skipped.  Counted, never silent.
	 */
	if (pl->skip) {
		ecmxf_ring_out_release(r, pl->skip, pl->skip);
		c->skipped = pl->skip;
	}
	if (!send)
		return false;
	ecmxf_ring_out_copy(r, r->tx_buf[i], pl->push);
	/* re-arm the threshold flags that woke us (INT1 is edge-triggered) */
	x->tx_len = (u16)ecmxf_pump_fifo_cmd(&r->pump, pl, true, &x->hdr);
	return true;
}

/**
 * ecmxf_pump_submit() - hand the pump's next command to the engine
 * @edev: the device; called by the worker without the lock
 * @r: the rings, with the reference ecmxf_pump_take() took
 * @now: ktime_get_ns()
 *
 * On success the reference travels with the command; otherwise it is
 * dropped here.
 *
 * Return: 0 when a command is in the engine, else a negative errno.
 */
int ecmxf_pump_submit(struct ecmxf_dev *edev, struct ecmxf_rings *r, u64 now)
{
	struct ecmxf_pump_slot *p = &edev->pump;
	bool wkc = p->take_wkc;
	struct ecmxf_pump_cmd *c = &p->wkc;
	int ret;

	if (wkc) {
		ecmxf_pump_prepare_wkc(edev, r, now);
	} else {
		/* the one in flight, if any, is the older */
		if (p->fifo[p->newest].busy)
			p->newest = !p->newest;
		c = &p->fifo[p->newest];
		r->again = false;
		r->next_tick_ns = now + r->poll_ns;
		if (!ecmxf_pump_prepare(edev, r, p->newest)) {
			ret = -ENODATA;
			if (ecmxf_ring_out_avail(r) < 0)
				ret = -EFAULT;
			goto drop;
		}
	}
	c->x.timeout_us = ecmxf_pump_timeout_us();
	c->answer_by_ns = r->next_tick_ns;
	if (!ecmxf_engine_can_submit(&edev->e, &c->x)) {
		ret = -EBUSY;
		goto drop;
	}
	ret = ecmxf_engine_submit(&edev->e, &c->x, now);
	if (ret)
		goto drop;
	mutex_lock(&edev->lock);
	c->rings = r;
	c->busy = true;
	p->turn = false;
	/* the command has its copy: the slots are the application's again */
	if (!wkc && c->released && c->plan.push) {
		ecmxf_ring_out_release(r, c->plan.push, 0);
		ecmxf_rings_wake(edev, EPOLLOUT | EPOLLWRNORM);
	}
	mutex_unlock(&edev->lock);
	return 0;
drop:
	mutex_lock(&edev->lock);
	/* frames skipped for a command that did not go: counted all the same */
	if (!wkc && c->skipped) {
		edev->out_ring_skipped += c->skipped;
		if (edev->rings == r && !r->stopped) {
			r->cur.out_skipped += c->skipped;
			ecmxf_rings_publish(r);
		}
		c->skipped = 0;
	}
	if (ret == -EFAULT && edev->rings == r)
		ecmxf_rings_stop(edev, -EFAULT);
	mutex_unlock(&edev->lock);
	ecmxf_rings_put(r);
	return ret;
}

/* Publish the header and the counters in the status block; lock held. */
static void ecmxf_status_update(struct ecmxf_rings *r,
				const struct ecmxf_rsp_hdr *h, int err,
				const u32 deltas[7])
{
	struct ecmxf_ring_status *st = &r->cur;

	st->int_flags = h->int_flags;
	st->crc_err_cnt = h->crc_err_cnt;
	st->wkc_err_cnt = h->wkc_err_cnt;
	st->tx_fifo_cnt = h->tx_fifo_cnt;
	st->rx_fifo_cnt = h->rx_fifo_cnt;
	st->ecat_state = h->ecat_state;
	st->err_status = h->err_status;
	st->ecm_status = h->ecm_status;
	st->error = (u32)-err;
	st->pump_ops += deltas[0];
	st->rx_refusals += deltas[1];
	st->tx_overflows += deltas[2];
	st->rx_underruns += deltas[3];
	st->out_underruns += deltas[4];
	st->out_skipped += deltas[5];
	st->pump_failures += deltas[6];
	ecmxf_rings_publish(r);
}

/* The working counter arrived (a bad answer is not published); lock held. */
static void ecmxf_pump_wkc_done(struct ecmxf_rings *r,
				const struct ecmxf_xfer *x)
{
	u32 wkc;

	if (ecmxf_pump_wkc_answer(&x->rsp, r->wkc_buf, x->rx_len, &wkc))
		return;
	r->cur.wkc = wkc;
	r->cur.wkc_reads++;
	ecmxf_rings_publish(r);
}

/*
 * The FIFO command @c answered: move the frames, count; lock held.  Its
 * output frames leave the ring now, or left it when it was built
 * (@c->released): then only the refused ones are counted here.
 */
static void ecmxf_pump_fifo_done(struct ecmxf_dev *edev,
				 struct ecmxf_rings *r,
				 const struct ecmxf_pump_cmd *c)
{
	const struct ecmxf_xfer *x = &c->x;
	const struct ecmxf_rsp_hdr *h = &x->rsp;
	u32 deltas[7] = { 1, 0, 0, 0, 0, c->skipped, 0 };
	struct ecmxf_pump_result res;
	__poll_t wake = 0;
	bool successor;
	u32 stored;
	int avail, err;

	err = ecmxf_pump_answer(&r->pump, &c->plan, h, x->rx_len, &res);
	if (err == -EREMOTEIO) {
		/*
		 * nothing was taken: the frames stay in the ring, or, gone
		 * from it already, are dropped (newer ones have been sent)
		 */
		if (c->released && c->plan.push)
			ecmxf_ring_out_release(r, 0, c->plan.push);
		ecmxf_status_update(r, h, err, deltas);
		return;
	}
	if (res.taken) {
		ecmxf_ring_out_release(r, c->released ? 0 : res.taken,
				       res.refused);
		if (res.refused) {
			/* the RxFIFO was full: some of them were refused */
			edev->rx_fifo_overruns++;
			deltas[1]++;
		}
		if (!c->released)
			wake |= EPOLLOUT | EPOLLWRNORM;
	}
	if (err) {
		/* -EPROTO: the input frames of the answer are lost */
		ecmxf_status_update(r, h, err, deltas);
		return;
	}
	if (res.popped) {
		stored = ecmxf_ring_in_store(r, x->rx_buf, res.popped);
		edev->in_ring_overruns += res.popped - stored;
		wake |= EPOLLRDBAND;
	}
	if (res.tx_overrun) {
		edev->tx_fifo_overruns++;
		deltas[2]++;
	}
	avail = ecmxf_ring_out_avail(r);
	if (res.rx_underrun) {
		edev->rx_fifo_underruns++;
		deltas[3]++;
		if (!avail) {
			edev->out_ring_underruns++;
			deltas[4]++;
		}
	}
	ecmxf_status_update(r, h, 0, deltas);
	/*
	 * more queued either way: again at once (if this one moved any).
	 * The TxPDO frames queued then are for the command that went out
	 * after this one, if it is still in flight (%ECMXF_RING_F_FIFO_NEXT):
	 * it pops them.
	 */
	successor = edev->pump.fifo[c == &edev->pump.fifo[0]].busy;
	if ((res.taken || res.popped) &&
	    ((h->tx_fifo_cnt && !successor) || avail > 0))
		r->again = true;
	if (wake)
		ecmxf_rings_wake(edev, wake);
}

/*
 * The command failed after it may have reached the chip (no answer, bad
 * packets): its output frames are dropped and counted, never sent again,
 * because a second copy would reach the bus after newer frames; the input
 * frames its answer carried are lost.  Counted as a pump failure, not as
 * a refusal (the chip may well have taken the frames); lock held.
 */
static void ecmxf_pump_failed(struct ecmxf_dev *edev, struct ecmxf_rings *r,
			      const struct ecmxf_pump_cmd *c)
{
	bool fifo = c != &edev->pump.wkc;
	u32 deltas[7] = { 0, 0, 0, 0, 0, fifo ? c->skipped : 0, 1 };
	u32 lost = fifo ? ecmxf_pump_lost(&r->pump, &c->plan) : 0;

	edev->pump_failures++;
	if (lost) {
		ecmxf_ring_out_release(r, c->released ? 0 : lost, lost);
		if (!c->released)
			ecmxf_rings_wake(edev, EPOLLOUT | EPOLLWRNORM);
	}
	ecmxf_status_update(r, &c->x.rsp, c->x.status, deltas);
}

/* Finish @c if the engine finished it; lock held.  Return: its reference. */
static struct ecmxf_rings *ecmxf_pump_finish(struct ecmxf_dev *edev,
					     struct ecmxf_pump_cmd *c)
{
	struct ecmxf_rings *r = c->rings;
	const struct ecmxf_xfer *x = &c->x;
	bool fifo = c != &edev->pump.wkc;

	if (!c->busy || x->status == -EINPROGRESS)
		return NULL;
	c->busy = false;
	c->rings = NULL;
	/* counted here; the status block's delta below reads it too */
	if (fifo)
		edev->out_ring_skipped += c->skipped;
	if (r == edev->rings && !r->stopped) {
		if (x->status == -ECONNRESET)
			ecmxf_rings_stop(edev, x->status);
		else if (x->status)
			ecmxf_pump_failed(edev, r, c);
		else if (!fifo)
			ecmxf_pump_wkc_done(r, x);
		else
			ecmxf_pump_fifo_done(edev, r, c);
	}
	return r;
}

/**
 * ecmxf_pump_collect() - finish the pump's commands that left the engine
 * @edev: the device, lock held (called by ecmxf_collect())
 * @put: the commands' references to the rings, set for those finished,
 *	else NULL; the caller drops them with ecmxf_rings_put() after
 *	unlocking (several may finish in one exchange: a chip reset, the
 *	retries run out)
 *
 * The FIFO commands are finished oldest first: their frames are moved in
 * the order the chip took and gave them.
 */
void ecmxf_pump_collect(struct ecmxf_dev *edev,
			struct ecmxf_rings *put[ECMXF_PUMP_CMDS])
{
	struct ecmxf_pump_slot *p = &edev->pump;

	lockdep_assert_held(&edev->lock);
	put[0] = ecmxf_pump_finish(edev, &p->fifo[!p->newest]);
	put[1] = ecmxf_pump_finish(edev, &p->fifo[p->newest]);
	put[2] = ecmxf_pump_finish(edev, &p->wkc);
}

/* Withdraw @c from the engine; lock held.  Return: its reference. */
static struct ecmxf_rings *ecmxf_pump_withdraw(struct ecmxf_dev *edev,
					       struct ecmxf_pump_cmd *c)
{
	struct ecmxf_rings *r = c->rings;

	if (!c->busy)
		return NULL;
	ecmxf_engine_cancel(&edev->e, &c->x);
	c->busy = false;
	c->rings = NULL;
	return r;
}

/**
 * ecmxf_pump_cancel() - the worker stops: withdraw the pump's commands
 * @edev: the device, lock held
 * @put: the commands' references to the rings, NULL where none was in
 *	the engine; the caller drops them with ecmxf_rings_put() after
 *	unlocking
 */
void ecmxf_pump_cancel(struct ecmxf_dev *edev,
		       struct ecmxf_rings *put[ECMXF_PUMP_CMDS])
{
	struct ecmxf_pump_slot *p = &edev->pump;

	lockdep_assert_held(&edev->lock);
	put[0] = ecmxf_pump_withdraw(edev, &p->fifo[0]);
	put[1] = ecmxf_pump_withdraw(edev, &p->fifo[1]);
	put[2] = ecmxf_pump_withdraw(edev, &p->wkc);
}
