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
 * Every decision is the protocol core's (lib/core/ecmxf-pump.c and
 * ecmxf-pump-sched.c, which the library's FIFO path runs too): which
 * command goes next and when, the slot of a FIFO command and the frames
 * in flight, what a command carries, which answer belongs to which
 * command, what it frees, stores, drops and counts, whether to go again.
 * This file is the adapter: the engine, the ring indices, the counters,
 * the status block, the lock, the clock and the wake-ups.
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

/**
 * ecmxf_pump_busy() - is one of the pump's commands in the engine?
 * @edev: the device, lock held
 *
 * Return: true while a FIFO command or the working counter read is in
 * flight.
 */
bool ecmxf_pump_busy(const struct ecmxf_dev *edev)
{
	return ecmxf_pump_flight_busy(&edev->pdo.pump.flight);
}

/*
 * the time allowed for each pump command, in microseconds
 * (&ecmxf_dev_cfg.pump_timeout_ms, 10..60000): longer than the table's
 * 100 ms, since a frame whose command failed is dropped, never sent again
 */
static u32 ecmxf_pump_timeout_us(const struct ecmxf_dev *edev)
{
	return edev->cfg.pump_timeout_ms * USEC_PER_MSEC;
}

/**
 * ecmxf_pump_answer_waits() - may the worker sleep with a command in flight?
 * @edev: the device; called by the worker without the lock
 *
 * The protocol core decides (ecmxf_pump_sched_waits()) for the command
 * that, sent, is all the engine has in flight (the newest FIFO command,
 * else the working counter read), when no reset waits and the pump's
 * timer runs.  The engine is the worker's: whether the command is all it
 * has in flight is asked without the lock, which is taken only then.
 *
 * Return: true when one of the pump's commands, sent, is all the engine
 * has in flight and may wait for the pump's next command.
 */
bool ecmxf_pump_answer_waits(struct ecmxf_dev *edev)
{
	struct ecmxf_pump_slot *p = &edev->pdo.pump;
	unsigned int i = p->flight.newest;
	struct ecmxf_rings *r;
	bool waits;

	if (!ecmxf_engine_waits_only(&edev->link.e, &p->cmd[i].x)) {
		i = ECMXF_PUMP_SLOT_WKC;
		if (!ecmxf_engine_waits_only(&edev->link.e, &p->cmd[i].x))
			return false;
	}
	mutex_lock(&edev->lock);
	r = edev->pdo.rings;
	waits = r && ecmxf_pump_sched_waits(&r->sched, &p->flight, i,
					    (u64)p->cmd[i].x.timeout_us *
					    NSEC_PER_USEC, ktime_get_ns()) &&
		list_empty(&edev->resets) && ecmxf_pump_deadline(edev);
	mutex_unlock(&edev->lock);
	return waits;
}

/**
 * ecmxf_pump_take() - should the pump send a command now?
 * @edev: the device, lock held
 * @now: ktime_get_ns()
 *
 * While rings exist and the pump has not stopped, the protocol core picks
 * (ecmxf_pump_sched_pick()) from the last header, the timers, INT1 (the
 * FIFO threshold flags; at most one INT1-driven command per period) and
 * the commands in flight.  A FIFO command is
 * the exchange INT1 asks for.  The choice is kept for ecmxf_pump_submit().
 *
 * Return: the rings with a reference for the command, or NULL.
 */
struct ecmxf_rings *ecmxf_pump_take(struct ecmxf_dev *edev, u64 now)
{
	struct ecmxf_rings *r = edev->pdo.rings;
	struct ecmxf_pump_slot *p = &edev->pdo.pump;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped)
		return NULL;
	/*
	 * INT1 while the schedule holds it (one INT1-driven command per
	 * period): seen, and asking for nothing the timer will not do; left
	 * set it would make the worker spin or refresh the header at the
	 * rate a level INT1 that nobody clears fires again
	 */
	if (ecmxf_pump_sched_kick_held(&r->sched, now))
		atomic_set(&edev->irq.int1_flag, 0);
	p->pick = ecmxf_pump_sched_pick(&r->sched, &p->flight, &edev->chip.last,
					now, atomic_read(&edev->irq.int1_flag),
					ecmxf_engine_sent(&edev->link.e,
							  &p->cmd[p->flight.newest].x));
	if (p->pick == ECMXF_PUMP_PICK_NONE)
		return NULL;
	if (p->pick == ECMXF_PUMP_PICK_FIFO)
		atomic_set(&edev->irq.int1_flag, 0);
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
	struct ecmxf_rings *r = edev->pdo.rings;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped)
		return 0;
	return ecmxf_pump_sched_deadline(&r->sched, &edev->chip.last);
}

/* Build the working counter read in its slot; its timer moves on. */
static void ecmxf_pump_prepare_wkc(struct ecmxf_dev *edev,
				   struct ecmxf_rings *r, u64 now)
{
	struct ecmxf_xfer *x = &edev->pdo.pump.cmd[ECMXF_PUMP_SLOT_WKC].x;

	memset(x, 0, sizeof(*x));
	x->rx_buf = r->wkc_buf;
	x->rx_size = ECMXF_DATA_MAX;
	x->status = -EINPROGRESS;
	ecmxf_pump_wkc_cmd(&x->hdr);
	ecmxf_pump_sched_wkc(&r->sched, now);
}

/*
 * Build the FIFO command of slot @i as the protocol core plans it from
 * what the output ring holds (the level counts the frames in flight):
 * the skipped frames leave the ring (counted when the command finishes),
 * the pushed ones are copied.  Return: false when there is nothing to
 * send.
 */
static bool ecmxf_pump_prepare(struct ecmxf_dev *edev, struct ecmxf_rings *r,
			       unsigned int i)
{
	struct ecmxf_pump_slot *p = &edev->pdo.pump;
	const struct ecmxf_pump_plan *pl = &p->flight.plan[i];
	struct ecmxf_xfer *x = &p->cmd[i].x;
	u32 level;
	bool send;
	int avail;

	memset(x, 0, sizeof(*x));
	x->rx_buf = r->rx_buf[i];
	x->rx_size = ECMXF_DATA_MAX;
	x->tx_data = r->tx_buf[i];
	x->status = -EINPROGRESS;

	avail = ecmxf_ring_out_avail(r);
	if (avail < 0)
		return false;	/* ecmxf_pump_submit() stops the rings */
	r->pump.data_size = ecmxf_engine_data_size(&edev->link.e);
	level = ecmxf_pump_sched_level(&r->pump, &p->flight,
				       ecmxf_engine_last_header(&edev->link.e));
	send = ecmxf_pump_sched_plan(&r->pump, &p->flight, i, level,
				     (u32)avail, ECMXF_PUMP_F_READ);
	ecmxf_ring_out_release(r, pl->skip, pl->skip);
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
	struct ecmxf_pump_slot *p = &edev->pdo.pump;
	unsigned int i = ECMXF_PUMP_SLOT_WKC;
	struct ecmxf_pump_cmd *c;
	u32 freed, skipped;
	int ret;

	if (p->pick == ECMXF_PUMP_PICK_WKC) {
		ecmxf_pump_prepare_wkc(edev, r, now);
	} else {
		i = ecmxf_pump_sched_fifo(&r->sched, &p->flight, now);
		if (!ecmxf_pump_prepare(edev, r, i)) {
			ret = ecmxf_ring_out_avail(r) < 0 ? -EFAULT : -ENODATA;
			goto drop;
		}
	}
	c = &p->cmd[i];
	c->x.timeout_us = ecmxf_pump_timeout_us(edev);
	if (!ecmxf_engine_can_submit(&edev->link.e, &c->x)) {
		ret = -EBUSY;
		goto drop;
	}
	ret = ecmxf_engine_submit(&edev->link.e, &c->x, now);
	if (ret)
		goto drop;
	mutex_lock(&edev->lock);
	c->rings = r;
	freed = ecmxf_pump_sched_sent(&p->flight, i, r->sched.next_tick_ns);
	p->turn = false;
	/* the command has its copy: the slots are the application's again */
	if (freed)
		ecmxf_ring_out_release(r, freed, 0);
	/* and so are those of frames skipped (ecmxf_pump_prepare()) */
	if (freed || (i != ECMXF_PUMP_SLOT_WKC && p->flight.plan[i].skip))
		ecmxf_rings_wake(edev, EPOLLOUT | EPOLLWRNORM);
	mutex_unlock(&edev->lock);
	return 0;
drop:
	mutex_lock(&edev->lock);
	/* frames skipped for a command that did not go: counted all the same */
	skipped = ecmxf_pump_sched_unsent(&p->flight, i);
	edev->cnt.out_ring_skipped += skipped;
	if (skipped && edev->pdo.rings == r && !r->stopped) {
		r->cur.out_skipped += skipped;
		ecmxf_rings_publish(r);
		/* their slots are free (ecmxf_pump_prepare()) */
		ecmxf_rings_wake(edev, EPOLLOUT | EPOLLWRNORM);
	}
	if (ret == -EFAULT && edev->pdo.rings == r)
		ecmxf_rings_stop(edev, -EFAULT);
	mutex_unlock(&edev->lock);
	ecmxf_rings_put(r);
	return ret;
}

/* Publish the header and the counts in the status block; lock held. */
static void ecmxf_status_update(struct ecmxf_rings *r,
				const struct ecmxf_rsp_hdr *h, int err,
				const struct ecmxf_pump_acct *a)
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
	st->pump_ops += a->ops;
	st->rx_refusals += a->refusals;
	st->tx_overflows += a->tx_overruns;
	st->rx_underruns += a->rx_underruns;
	st->out_underruns += a->out_underruns;
	st->out_skipped += a->skipped;
	st->pump_failures += a->failures;
	ecmxf_rings_publish(r);
}

/* Add the counts the core gave, wake the readers of the rings; lock held. */
static void ecmxf_pump_count(struct ecmxf_dev *edev,
			     const struct ecmxf_pump_acct *a, __poll_t wake)
{
	edev->cnt.rx_fifo_overruns += a->refusals;
	edev->cnt.tx_fifo_overruns += a->tx_overruns;
	edev->cnt.rx_fifo_underruns += a->rx_underruns;
	edev->cnt.out_ring_underruns += a->out_underruns;
	edev->cnt.pump_failures += a->failures;
	if (a->wake_out)
		wake |= EPOLLOUT | EPOLLWRNORM;
	if (wake)
		ecmxf_rings_wake(edev, wake);
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
 * The FIFO command of slot @i answered: the core says what its answer
 * frees, drops, stores and counts, and whether work is left; lock held.
 */
static void ecmxf_pump_fifo_done(struct ecmxf_dev *edev,
				 struct ecmxf_rings *r, unsigned int i,
				 u32 skipped)
{
	struct ecmxf_pump_slot *p = &edev->pdo.pump;
	const struct ecmxf_xfer *x = &p->cmd[i].x;
	const struct ecmxf_rsp_hdr *h = &x->rsp;
	struct ecmxf_pump_acct a;
	u32 stored;
	int err;

	err = ecmxf_pump_sched_answer(&r->pump, &p->flight, i, h, x->rx_len,
				      &a);
	a.skipped = skipped;
	ecmxf_ring_out_release(r, a.free, a.dropped);
	stored = ecmxf_ring_in_store(r, x->rx_buf, a.store);
	edev->cnt.in_ring_overruns += a.store - stored;
	ecmxf_pump_sched_left(&r->sched, &p->flight, i, h,
			      ecmxf_ring_out_avail(r), &a);
	ecmxf_status_update(r, h, err, &a);
	ecmxf_pump_count(edev, &a, a.store ? EPOLLRDBAND : 0);
}

/*
 * The command of slot @i failed after it may have reached the chip (no
 * answer, bad packets): the core counts the failure and the FIFO
 * command's frames as lost; lock held.
 */
static void ecmxf_pump_failed(struct ecmxf_dev *edev, struct ecmxf_rings *r,
			      unsigned int i, u32 skipped)
{
	struct ecmxf_pump_acct a;

	ecmxf_pump_sched_failed(&r->pump, &edev->pdo.pump.flight, i, &a);
	a.skipped = skipped;
	ecmxf_ring_out_release(r, a.free, a.dropped);
	ecmxf_pump_count(edev, &a, 0);
	ecmxf_status_update(r, &edev->pdo.pump.cmd[i].x.rsp,
			    edev->pdo.pump.cmd[i].x.status, &a);
}

/* Finish slot @i if the engine finished it; lock held.  Return: its ref. */
static struct ecmxf_rings *ecmxf_pump_finish(struct ecmxf_dev *edev,
					     unsigned int i)
{
	struct ecmxf_pump_slot *p = &edev->pdo.pump;
	struct ecmxf_pump_cmd *c = &p->cmd[i];
	struct ecmxf_rings *r = c->rings;
	u32 skipped;
	int done;

	if (!p->flight.busy[i] || c->x.status == -EINPROGRESS)
		return NULL;
	done = ecmxf_pump_sched_finish(&p->flight, i, c->x.status, &skipped);
	c->rings = NULL;
	edev->cnt.out_ring_skipped += skipped;
	if (r != edev->pdo.rings || r->stopped)
		return r;
	if (done == ECMXF_PUMP_DONE_STOP)
		ecmxf_rings_stop(edev, c->x.status);
	else if (done == ECMXF_PUMP_DONE_FAILED)
		ecmxf_pump_failed(edev, r, i, skipped);
	else if (i == ECMXF_PUMP_SLOT_WKC)
		ecmxf_pump_wkc_done(r, &c->x);
	else
		ecmxf_pump_fifo_done(edev, r, i, skipped);
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
	unsigned int newest = edev->pdo.pump.flight.newest;

	lockdep_assert_held(&edev->lock);
	put[0] = ecmxf_pump_finish(edev, newest ^ 1U);
	put[1] = ecmxf_pump_finish(edev, newest);
	put[2] = ecmxf_pump_finish(edev, ECMXF_PUMP_SLOT_WKC);
}

/* Withdraw slot @i from the engine; lock held.  Return: its reference. */
static struct ecmxf_rings *ecmxf_pump_withdraw(struct ecmxf_dev *edev,
					       unsigned int i)
{
	struct ecmxf_pump_cmd *c = &edev->pdo.pump.cmd[i];
	struct ecmxf_rings *r = c->rings;

	if (!edev->pdo.pump.flight.busy[i])
		return NULL;
	ecmxf_engine_cancel(&edev->link.e, &c->x);
	ecmxf_pump_sched_cancel(&edev->pdo.pump.flight, i);
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
	unsigned int i;

	lockdep_assert_held(&edev->lock);
	for (i = 0; i < ECMXF_PUMP_CMDS; i++)
		put[i] = ecmxf_pump_withdraw(edev, i);
}
