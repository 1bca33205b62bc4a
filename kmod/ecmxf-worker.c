// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-worker.c - NEXTW ECM-XF: the kthread that owns the SPI link
 *
 * One SCHED_FIFO kthread per chip drives the shared protocol engine
 * (lib/core/ecmxf-engine.c) exactly as Documentation/protocol-core.rst
 * describes: wait for INT0 "ready" (or 150 us without INT0), submit the
 * next command when the engine allows, exchange one packet each way with
 * spi_sync(), feed the answer back, finish the commands that are done.
 *
 * Commands come from the files' queues, taken round-robin across the open
 * files (a file's own commands stay in order), so one busy opener cannot
 * starve the others; the engine itself allows one async command on the
 * chip at a time and immediate commands meanwhile.  Resets have their own
 * queue and go first.  While PDO rings exist, the PDO pump's commands
 * (ecmxf-pump.c) take turns with the files' commands: when both are due,
 * one of each.  The netlink unit's AL status query is one more client of
 * the queue (%ECMXF_REQ_KERNEL); the unit learns what the worker sees
 * through the &struct ecmxf_watch_ops it registered.
 *
 * Locking: &ecmxf_dev.lock (a mutex, so sleeping and PREEMPT_RT-safe) is
 * taken around queue and state changes only; spi_sync() and every wait
 * happen without it.  The engine and the packet buffers belong to this
 * thread alone.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/delay.h>
#include <linux/hrtimer.h>
#include <linux/interrupt.h>
#include <linux/kthread.h>
#include <linux/ktime.h>
#include <linux/poll.h>
#include <linux/sched.h>
#include <linux/sched/task.h>
#include <linux/slab.h>

#include "ecmxf.h"	/* get_unaligned_le32(): core/ecmxf-compat.h */
#include "ecmxf-latch.h"

/* the watcher's callbacks (ecmxf-netlink.c), set at module load */
static const struct ecmxf_watch_ops *ecmxf_watch __read_mostly;

/**
 * ecmxf_worker_watch() - set the watcher of every device's worker
 * @ops: the callbacks (every one set), or NULL
 *
 * Module init and exit only: no worker runs then.
 */
void ecmxf_worker_watch(const struct ecmxf_watch_ops *ops)
{
	ecmxf_watch = ops;
}

/* The watcher's callbacks, each a no-op without a watcher. */
static void ecmxf_watch_start(struct ecmxf_dev *edev)
{
	if (ecmxf_watch)
		ecmxf_watch->start(edev);
}

static void ecmxf_watch_stop(struct ecmxf_dev *edev)
{
	if (ecmxf_watch)
		ecmxf_watch->stop(edev);
}

static void ecmxf_watch_flush(struct ecmxf_dev *edev)
{
	if (ecmxf_watch)
		ecmxf_watch->flush(edev);
}

static void ecmxf_watch_header(struct ecmxf_dev *edev, u64 now)
{
	if (ecmxf_watch)
		ecmxf_watch->header(edev, now);
}

static void ecmxf_watch_req_sent(struct ecmxf_dev *edev,
				 const struct ecmxf_xfer *x)
{
	if (ecmxf_watch)
		ecmxf_watch->req_sent(edev, x);
}

static void ecmxf_watch_req_done(struct ecmxf_dev *edev,
				 const struct ecmxf_xfer *x)
{
	if (ecmxf_watch)
		ecmxf_watch->req_done(edev, x);
}

static void ecmxf_watch_link_reset(struct ecmxf_dev *edev)
{
	if (ecmxf_watch)
		ecmxf_watch->link_reset(edev);
}

static bool ecmxf_watch_poll_due(struct ecmxf_dev *edev, u64 now)
{
	return ecmxf_watch && ecmxf_watch->poll_due(edev, now);
}

static u64 ecmxf_watch_wake_at(struct ecmxf_dev *edev, u64 now)
{
	return ecmxf_watch ? ecmxf_watch->wake_at(edev, now) : U64_MAX;
}

/**
 * ecmxf_check_name() - name of a check word type
 * @check: 0..3
 *
 * Return: "fixed", "crc8", "crc-ccitt", "crc32" or "unknown".
 */
const char *ecmxf_check_name(unsigned int check)
{
	static const char * const names[] = {
		[ECMXF_CHECK_FIXED] = "fixed",
		[ECMXF_CHECK_CRC8] = "crc8",
		[ECMXF_CHECK_CCITT] = "crc-ccitt",
		[ECMXF_CHECK_CRC32] = "crc32",
	};

	return check < ARRAY_SIZE(names) ? names[check] : "unknown";
}

/**
 * ecmxf_worker_kick() - wake the task that owns the link
 * @edev: the device
 *
 * Called by the IRQ threads, by the file operations after they queued work
 * and dropped &ecmxf_dev.lock (the worker, at a higher priority, would
 * otherwise wake only to block on the lock its waker holds), and by the
 * worker's own watcher.
 */
void ecmxf_worker_kick(struct ecmxf_dev *edev)
{
	atomic_set(&edev->link.kick, 1);
	ecmxf_wake_owner(edev);
}

/**
 * ecmxf_wake_owner() - wake the task that owns the link, nothing more
 * @edev: the device
 *
 * For the INT0/INT1 handlers (hard IRQ or threaded), which record their
 * own flag first.
 */
void ecmxf_wake_owner(struct ecmxf_dev *edev)
{
	struct task_struct *t = READ_ONCE(edev->link.owner);

	if (t)
		wake_up_process(t);
}

/* Sleep until @until_ns (ktime_get_ns() clock) unless kicked. */
static void ecmxf_sleep_until(struct ecmxf_dev *edev, u64 until_ns)
{
	ktime_t t = ns_to_ktime(until_ns);

	set_current_state(TASK_IDLE);
	if (!atomic_read(&edev->link.kick) && !kthread_should_stop())
		schedule_hrtimeout(&t, HRTIMER_MODE_ABS);
	__set_current_state(TASK_RUNNING);
}

/*
 * Before an exchange: wait until the chip is ready for it, counted from
 * the end of the previous one.  Without INT0 the chip needs up to 150 us.
 * With INT0, wait for its level (GPIO form), its interrupt since the
 * previous exchange began (&ecmxf_dev.irq.int0_flag; a level-triggered one is
 * unmasked here and fires at once while the line is "ready"), but never
 * longer than ECMXF_READY_TIMEOUT_US after that exchange: a chip that
 * stays busy then answers "not ready", which the engine counts and
 * retries.
 *
 * Waiting here rather than right after the exchange lets the worker hand
 * an answer to its caller first: the chip's processing time after the
 * exchange that brought the answer overlaps with the caller's wake-up,
 * and the next command usually finds the chip ready.
 */
static void ecmxf_wait_ready(struct ecmxf_dev *edev)
{
	u64 ready_ns = edev->link.xfer_end_ns + ECMXF_READY_WAIT_US * NSEC_PER_USEC;
	ktime_t deadline;

	if (!edev->link.xfer_end_ns)
		return;		/* nothing exchanged yet */
	if (!edev->irq.int0_irq) {
		/* as usleep_range(): a wake-up does not end the wait */
		deadline = ns_to_ktime(ready_ns);
		while (ktime_get_ns() < ready_ns) {
			set_current_state(TASK_IDLE);
			schedule_hrtimeout_range(&deadline, 50 * NSEC_PER_USEC,
						 HRTIMER_MODE_ABS);
		}
		__set_current_state(TASK_RUNNING);
		return;
	}
	deadline = ns_to_ktime(edev->link.xfer_end_ns +
			       ECMXF_READY_TIMEOUT_US * NSEC_PER_USEC);
	ecmxf_irq_unmask(edev, edev->irq.int0_irq, &edev->irq.int0_masked);
	for (;;) {
		if (edev->irq.int0 && gpiod_get_value_cansleep(edev->irq.int0) > 0)
			return;
		set_current_state(TASK_IDLE);
		if (atomic_read(&edev->irq.int0_flag)) {
			__set_current_state(TASK_RUNNING);
			return;
		}
		if (!schedule_hrtimeout(&deadline, HRTIMER_MODE_ABS))
			return;		/* timed out */
		/* woken: by INT0, or by other work; look at the line again */
	}
}

/*
 * A level-triggered INT1 that its handler masked: unmask it once a packet
 * with interrupt clear bits reached the chip (@cleared: the worker saw
 * "ready" after it), else ECMXF_INT1_HOLDOFF_NS after the worker first
 * found it masked.  Still asserted then (flags the application does not
 * clear), it fires once more: one header refresh per hold-off, no storm.
 *
 * Return: when to look again (ktime_get_ns() clock), or U64_MAX.
 */
static u64 ecmxf_int1_rearm(struct ecmxf_dev *edev, u64 now, bool cleared)
{
	if (!edev->irq.int1_level || !atomic_read(&edev->irq.int1_masked)) {
		edev->link.int1_rearm_ns = 0;
		return U64_MAX;
	}
	if (!edev->link.int1_rearm_ns)
		edev->link.int1_rearm_ns = now + ECMXF_INT1_HOLDOFF_NS;
	if (!cleared && now < edev->link.int1_rearm_ns)
		return edev->link.int1_rearm_ns;
	edev->link.int1_rearm_ns = 0;
	ecmxf_irq_unmask(edev, edev->irq.int1_irq, &edev->irq.int1_masked);
	return U64_MAX;
}

/* After "ready": a clear sent in the last packet has reached the chip. */
static void ecmxf_int1_cleared(struct ecmxf_dev *edev)
{
	if (!edev->link.int1_cleared)
		return;
	edev->link.int1_cleared = false;
	ecmxf_int1_rearm(edev, ktime_get_ns(), true);
}

/* The packet in @pkt clears interrupt flags (int_clear, gpio_int_clear). */
static bool ecmxf_pkt_clears(const u8 *pkt)
{
	return get_unaligned_le32(pkt + 0x10) || pkt[0x14] || pkt[0x15];
}

/*
 * One SPI exchange: the engine's next packet out, the chip's packet in.
 * Before the hold-off after SPI_RECONFIG_OP / WARM_RESET ends, sleep
 * instead and only apply the deadlines.
 *
 * Return: the engine's %ECMXF_EV_* bits.
 */
static unsigned int ecmxf_exchange(struct ecmxf_dev *edev)
{
	size_t n = ecmxf_engine_pkt_size(&edev->link.e);
	struct spi_transfer t = {
		.tx_buf = edev->link.txbuf,
		.rx_buf = edev->link.rxbuf,
		.len = n,
	};
	unsigned int ev;
	u64 now;
	int ret;

	ecmxf_wait_ready(edev);
	ecmxf_int1_cleared(edev);
	now = ktime_get_ns();
	ret = ecmxf_engine_next(&edev->link.e, now, edev->link.txbuf, n);
	if (ret == -EAGAIN) {
		ecmxf_sleep_until(edev, ecmxf_engine_not_before(&edev->link.e));
		return ecmxf_engine_poll_time(&edev->link.e, ktime_get_ns());
	}
	if (WARN_ON_ONCE(ret))
		return ecmxf_engine_poll_time(&edev->link.e, now);

	atomic_set(&edev->irq.int0_flag, 0);
	if (edev->irq.int1_level)
		edev->link.int1_cleared = ecmxf_pkt_clears(edev->link.txbuf);
	ret = spi_sync_transfer(edev->spi, &t, 1);
	if (ret) {
		/* nothing usable came back: the engine retries, then fails */
		dev_err_ratelimited(&edev->spi->dev, "SPI transfer failed: %d\n",
				    ret);
		memset(edev->link.rxbuf, 0, n);
	}
	now = ktime_get_ns();
	edev->link.xfer_end_ns = now;
	ev = ecmxf_engine_input(&edev->link.e, now, edev->link.rxbuf, n);
	if (ev & ECMXF_EV_HEADER)
		ecmxf_watch_header(edev, now);	/* events (ecmxf-netlink.c) */
	return ev;
}

static void ecmxf_snapshot(struct ecmxf_dev *edev);

/*
 * The worker is asked to stop (unbind): a link reset's format search
 * gives up.  Probe runs before the worker exists (not in a kthread).
 */
static bool ecmxf_stopping(struct ecmxf_dev *edev)
{
	return current == edev->link.worker && kthread_should_stop();
}

/*
 * Run one command on an otherwise idle engine and exchange until it is
 * done (probe and link reset).  @x->timeout_us bounds the loop; a stop of
 * the worker (unbind) ends it at the next exchange (-ENODEV, as for
 * everything in flight then).
 */
static int ecmxf_run_xfer(struct ecmxf_dev *edev, struct ecmxf_xfer *x)
{
	int ret = ecmxf_engine_submit(&edev->link.e, x, ktime_get_ns());

	if (ret)
		return ret;
	while (x->status == -EINPROGRESS) {
		if (ecmxf_stopping(edev)) {
			ecmxf_engine_cancel(&edev->link.e, x);
			return -ENODEV;
		}
		ecmxf_exchange(edev);
		/* the counters move during a reset's search too */
		mutex_lock(&edev->lock);
		ecmxf_snapshot(edev);
		mutex_unlock(&edev->lock);
	}
	return x->status;
}

static int ecmxf_simple_cmd(struct ecmxf_dev *edev, u8 code, u8 param,
			    u16 len, u8 *rx, u16 rx_size,
			    struct ecmxf_rsp_hdr *rsp)
{
	struct ecmxf_xfer x;
	int ret;

	memset(&x, 0, sizeof(x));
	x.hdr.code = code;
	x.hdr.param = param;
	x.hdr.len = len;
	x.rx_buf = rx;
	x.rx_size = rx_size;
	x.timeout_us = ECMXF_PROBE_TIMEOUT_US;
	if (code == ECMXF_CMD_SPI_RECONFIG_OP)
		x.timeout_us += ECMXF_RECONFIG_HOLDOFF_NS / NSEC_PER_USEC;
	ret = ecmxf_run_xfer(edev, &x);
	if (rsp)
		*rsp = x.rsp;
	return ret;
}

/* @sum = @a + @b, counter by counter (the structure holds only u64s) */
static void ecmxf_stats_add(struct ecmxf_engine_stats *sum,
			    const struct ecmxf_engine_stats *a,
			    const struct ecmxf_engine_stats *b)
{
	const u64 *pa = (const u64 *)a, *pb = (const u64 *)b;
	u64 *ps = (u64 *)sum;
	size_t i;

	BUILD_BUG_ON(sizeof(*sum) % sizeof(u64));
	for (i = 0; i < sizeof(*sum) / sizeof(u64); i++)
		ps[i] = pa[i] + pb[i];
}

/*
 * Re-initialise the engine (its counters start at zero) without losing
 * the counts since probe: they move to &ecmxf_dev.cnt.stats_base.
 */
static void ecmxf_engine_reinit(struct ecmxf_dev *edev, unsigned int size,
				enum ecmxf_check check)
{
	mutex_lock(&edev->lock);
	ecmxf_stats_add(&edev->cnt.stats_base, &edev->cnt.stats_base,
			ecmxf_engine_get_stats(&edev->link.e));
	mutex_unlock(&edev->lock);
	ecmxf_engine_init(&edev->link.e, size, check);
}

/*
 * Publish the counters and the format for the lock-free readers
 * (&ecmxf_dev.cnt.snap); call with the lock held (the one writer).
 */
static void ecmxf_publish(struct ecmxf_dev *edev)
{
	const struct ecmxf_engine_stats *s = &edev->cnt.stats;
	struct ecmxf_snap v;
	struct ecmxf_counters *k = &v.k;

	lockdep_assert_held(&edev->lock);
	memset(&v, 0, sizeof(v));
	k->exchanges = s->exchanges;
	k->bad_not_ready = s->faults[ECMXF_FAULT_NOT_READY];
	k->bad_start = s->faults[ECMXF_FAULT_START];
	k->bad_end = s->faults[ECMXF_FAULT_END];
	k->bad_check = s->faults[ECMXF_FAULT_CHECK];
	k->bad_length = s->faults[ECMXF_FAULT_LENGTH];
	k->retries = s->retries;
	k->polls = s->polls;
	k->exhausted = s->exhausted;
	k->timeouts = s->timeouts + edev->cnt.queue_timeouts;
	k->async_errors = s->async_errors;
	k->busy_rejects = s->busy_rejects;
	k->lost_answers = s->lost_answers;
	k->chip_resets = s->chip_resets;
	k->wkc_errors = edev->cnt.wkc_errors;
	k->out_ring_underruns = edev->cnt.out_ring_underruns;
	k->in_ring_overruns = edev->cnt.in_ring_overruns;
	k->rx_fifo_underruns = edev->cnt.rx_fifo_underruns;
	k->rx_fifo_overruns = edev->cnt.rx_fifo_overruns;
	k->tx_fifo_overruns = edev->cnt.tx_fifo_overruns;
	v.ring_skipped = edev->cnt.out_ring_skipped;
	v.ring_failures = edev->cnt.pump_failures;
	v.data_size = edev->chip.data_size;
	v.check = edev->chip.check;
	v.cover = edev->chip.cover;
	v.fw_valid = edev->chip.fw_valid;
	v.fw_version = edev->chip.fw_version;
	memcpy(v.fw_info, edev->chip.fw_info, sizeof(v.fw_info));
	ecmxf_latch_write(&edev->cnt.snap_seq, &edev->cnt.snap_kseq, &edev->cnt.snap[0],
			  &edev->cnt.snap[1], &v, sizeof(v));
}

/* Copy what the file operations and sysfs show; call with the lock held. */
static void ecmxf_snapshot(struct ecmxf_dev *edev)
{
	const struct ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&edev->link.e);

	lockdep_assert_held(&edev->lock);
	ecmxf_stats_add(&edev->cnt.stats, &edev->cnt.stats_base,
			ecmxf_engine_get_stats(&edev->link.e));
	edev->chip.data_size = (u16)ecmxf_engine_data_size(&edev->link.e);
	/* no getter for the check type: read the field the engine keeps */
	edev->chip.check = edev->link.e.check;
	edev->chip.cover = ecmxf_engine_cover(&edev->link.e);
	if (h) {
		edev->chip.last = *h;
		if (edev->link.wkc_valid && h->wkc_err_cnt != edev->link.wkc_last)
			edev->cnt.wkc_errors += (u8)(h->wkc_err_cnt -
						 edev->link.wkc_last);
		edev->link.wkc_last = h->wkc_err_cnt;
		edev->link.wkc_valid = true;
	}
	ecmxf_publish(edev);
}

static int ecmxf_read_fw_version(struct ecmxf_dev *edev)
{
	struct ecmxf_rsp_hdr rsp;
	u8 info[sizeof(edev->chip.fw_info)];
	int ret;

	memset(info, 0, sizeof(info));
	ret = ecmxf_simple_cmd(edev, ECMXF_CMD_FW_VERSION_GET, 0, 0,
			       info, sizeof(info), &rsp);
	if (ret == -EMSGSIZE)
		ret = 0;	/* more than the 20 bytes we know: keep those */
	if (ret)
		return ret;
	mutex_lock(&edev->lock);
	edev->chip.fw_version = rsp.ret;
	memcpy(edev->chip.fw_info, info, sizeof(info));
	edev->chip.fw_valid = true;
	ecmxf_snapshot(edev);
	mutex_unlock(&edev->lock);
	return 0;
}

/*
 * Find the packet format the chip speaks: the wanted one (the chip may
 * keep it from an earlier load of the module; an ECM-XFU's fixed size
 * when nothing is wanted), then the power-on formats (112 bytes, or 992
 * on the ECM-XFU, fixed check word).  Each try is a
 * FW_VERSION_GET; a wrong format fails it within the retry bound.
 */
static int ecmxf_find_format(struct ecmxf_dev *edev)
{
	const unsigned int fixed = edev->cfg.variant->fixed_size;
	const unsigned int sizes[] = {
		edev->link.want_size ? edev->link.want_size :
		fixed ? fixed : ECMXF_DATA_DEFAULT,
		ECMXF_DATA_DEFAULT, 992,
	};
	const unsigned int checks[] = { edev->link.want_check, ECMXF_CHECK_FIXED };
	unsigned int i, j, k;
	int ret = -ENODEV;

	for (i = 0; i < ARRAY_SIZE(sizes); i++) {
		if (i && sizes[i] == sizes[0])
			continue;
		for (j = 0; j < ARRAY_SIZE(checks); j++) {
			if (j && checks[j] == checks[0])
				continue;
			ecmxf_engine_reinit(edev, sizes[i], checks[j]);
			/*
			 * A timeout is no evidence of a wrong format (that
			 * fails with bad packets): the link was too slow
			 * to be scheduled.  Ask again in the same format.
			 */
			for (k = 0; k < ECMXF_PROBE_TRIES; k++) {
				if (ecmxf_stopping(edev))
					return -ENODEV;
				ret = ecmxf_read_fw_version(edev);
				dev_dbg(&edev->spi->dev,
					"FW_VERSION_GET with %u bytes and the %s check word: %d\n",
					sizes[i], ecmxf_check_name(checks[j]), ret);
				if (ret != -ETIMEDOUT)
					break;
			}
			if (!ret)
				return 0;
		}
	}
	return ret;
}

/* Bring the link up; on failure log why and return the errno. */
static int ecmxf_link_up(struct ecmxf_dev *edev)
{
	struct device *dev = &edev->spi->dev;
	const struct ecmxf_engine_stats *st;
	int ret;

	ret = ecmxf_find_format(edev);
	if (ret) {
		mutex_lock(&edev->lock);
		ecmxf_snapshot(edev);
		mutex_unlock(&edev->lock);
		st = &edev->cnt.stats;
		return dev_err_probe(dev, ret,
				     "the chip does not answer FW_VERSION_GET in any known packet format (%llu exchanges; bad packets: %llu not ready, %llu start word, %llu end word, %llu check word)\n",
				     st->exchanges,
				     st->faults[ECMXF_FAULT_NOT_READY],
				     st->faults[ECMXF_FAULT_START],
				     st->faults[ECMXF_FAULT_END],
				     st->faults[ECMXF_FAULT_CHECK]);
	}
	if (edev->link.want_size &&
	    edev->link.want_size != ecmxf_engine_data_size(&edev->link.e)) {
		ret = ecmxf_simple_cmd(edev, ECMXF_CMD_SPI_RECONFIG_OP, 0,
				       (u16)edev->link.want_size, NULL, 0, NULL);
		if (ret)
			return dev_err_probe(dev, ret,
					     "SPI_RECONFIG_OP to a %u-byte data section failed (an ECM-XFU has a fixed 992)\n",
					     edev->link.want_size);
	}
	if (edev->link.want_check != edev->link.e.check) {
		ret = ecmxf_simple_cmd(edev, ECMXF_CMD_CRC_TYPE_SET,
				       (u8)edev->link.want_check, 0, NULL, 0, NULL);
		if (ret)
			return dev_err_probe(dev, ret,
					     "CRC_TYPE_SET to the %s check word failed\n",
					     ecmxf_check_name(edev->link.want_check));
	}
	/* the new format works both ways */
	ret = ecmxf_read_fw_version(edev);
	if (ret)
		return dev_err_probe(dev, ret,
				     "FW_VERSION_GET failed after switching to %u bytes with the %s check word\n",
				     ecmxf_engine_data_size(&edev->link.e),
				     ecmxf_check_name(edev->link.e.check));
	return 0;
}

/**
 * ecmxf_link_bringup() - probe: find the chip's format, set the wanted one
 * @edev: the device, worker not started yet
 *
 * Reads the firmware version in whatever format the chip speaks, then
 * sets the wanted data section size and check type and reads the version
 * again in the new format.
 *
 * Return: 0, or a negative errno after dev_err_probe() said why.
 */
int ecmxf_link_bringup(struct ecmxf_dev *edev)
{
	int ret;

	WRITE_ONCE(edev->link.owner, current);
	ret = ecmxf_link_up(edev);
	WRITE_ONCE(edev->link.owner, NULL);
	/* no IRQ thread still holds this task to wake it after it leaves */
	if (edev->irq.int0_irq)
		synchronize_irq(edev->irq.int0_irq);
	if (edev->irq.int1_irq)
		synchronize_irq(edev->irq.int1_irq);
	return ret;
}

/**
 * ecmxf_req_finish() - a request is done: hand it to whoever waits
 * @edev: the device
 * @req: the request, no longer queued nor in the engine
 * @status: its outcome (0 or a negative errno)
 *
 * Sync and reset requests wake their ioctl (or are freed when it left);
 * submitted ones go to their file's completion list (or are freed when
 * the file was closed); a kernel client's have their callback called.
 * Call with &ecmxf_dev.lock held.
 */
void ecmxf_req_finish(struct ecmxf_dev *edev, struct ecmxf_req *req,
		      int status)
{
	struct ecmxf_client *c = req->client;

	lockdep_assert_held(&edev->lock);
	req->x.status = status;
	req->state = ECMXF_RS_DONE;
	if (req->kind == ECMXF_REQ_KERNEL) {
		req->complete(edev, req);
		return;
	}
	if (req->kind == ECMXF_REQ_SUBMIT) {
		if (!c) {
			kfree(req);
			return;
		}
		list_add_tail(&req->node, &c->done);
		wake_up_interruptible_poll(&c->wq, EPOLLIN | EPOLLRDNORM);
		return;
	}
	if (req->abandoned) {
		kfree(req);
		return;
	}
	complete(&req->done);
}

/**
 * ecmxf_claim_allows() - may a file send something while the claim is held?
 * @edev: the device, lock held
 * @c: the file (NULL: a client inside the module, which is never refused)
 * @exclusive: the request is of a class above query, or a reset
 *
 * While a file holds the claim, the machine is its own: every other file
 * may send queries only (Documentation/uapi.rst, "Permissions").  Checked
 * when a request is queued and again when the worker takes it, so that a
 * request queued before the claim was taken does not run beside it.
 *
 * Return: true when @c may send it now.
 */
bool ecmxf_claim_allows(struct ecmxf_dev *edev, const struct ecmxf_client *c,
			bool exclusive)
{
	lockdep_assert_held(&edev->lock);
	return !c || !exclusive || !edev->claim.holder || edev->claim.holder == c;
}

/**
 * ecmxf_req_refused() - does the claim or the rings refuse @req now?
 * @edev: the device, lock held
 * @req: a request of a file (a kernel client's is never refused)
 *
 * The one rule for both moments it is asked: when the file queues @req,
 * and when the worker takes it, since the claim may have been taken and
 * the rings set up (the pump then owns the FIFO exchange) in between.
 *
 * Return: true when @req must end with -EBUSY, unsent.
 */
bool ecmxf_req_refused(struct ecmxf_dev *edev, const struct ecmxf_req *req)
{
	if (req->kind == ECMXF_REQ_KERNEL)
		return false;
	if (!ecmxf_claim_allows(edev, req->client, req->exclusive))
		return true;
	return req->x.hdr.code == ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP &&
	       req->kind != ECMXF_REQ_RESET && edev->pdo.rings;
}

/* Finish @req, taken off its queue, as refused (-EBUSY); lock held. */
static void ecmxf_req_refuse(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	req->refused = true;
	ecmxf_req_finish(edev, req, -EBUSY);
}

/* Fail the requests queued on every file; call with the lock held. */
static void ecmxf_fail_queued(struct ecmxf_dev *edev, int status)
{
	struct ecmxf_req *req, *tmp;
	struct ecmxf_client *c;

	list_for_each_entry(c, &edev->clients, node) {
		list_for_each_entry_safe(req, tmp, &c->queue, node) {
			list_del_init(&req->node);
			ecmxf_req_finish(edev, req, status);
		}
	}
}

/* Time out queued requests whose deadline passed; lock held. */
static void ecmxf_expire_queued(struct ecmxf_dev *edev, u64 now)
{
	struct ecmxf_req *req, *tmp;
	struct ecmxf_client *c;

	list_for_each_entry(c, &edev->clients, node) {
		list_for_each_entry_safe(req, tmp, &c->queue, node) {
			if (now < req->deadline_ns)
				continue;
			list_del_init(&req->node);
			edev->cnt.queue_timeouts++;
			ecmxf_req_finish(edev, req, -ETIMEDOUT);
		}
	}
}

/*
 * The next request the engine accepts, round-robin over the files: the
 * first file (in &ecmxf_dev.clients order) whose oldest queued request
 * can be submitted now; that file then goes to the back.  Lock held.
 */
static struct ecmxf_req *ecmxf_pick(struct ecmxf_dev *edev)
{
	struct ecmxf_client *c;
	struct ecmxf_req *req;

	list_for_each_entry(c, &edev->clients, node) {
		req = list_first_entry_or_null(&c->queue, struct ecmxf_req,
					       node);
		/* refused ones end here, whatever the engine could take */
		while (req && ecmxf_req_refused(edev, req)) {
			list_del_init(&req->node);
			ecmxf_req_refuse(edev, req);
			req = list_first_entry_or_null(&c->queue,
						       struct ecmxf_req, node);
		}
		if (!req || !ecmxf_engine_can_submit(&edev->link.e, &req->x))
			continue;
		/* an ended async command's fetch still holds async_req */
		if (edev->async_req &&
		    ecmxf_cmd_is_async(req->x.hdr.code, req->x.hdr.param))
			continue;
		list_del_init(&req->node);
		list_move_tail(&c->node, &edev->clients);
		return req;
	}
	return NULL;
}

/* Hand @req to the engine with the time left of its deadline. */
static int ecmxf_submit(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	u64 now = ktime_get_ns();
	u64 left;

	if (now >= req->deadline_ns)
		return -ETIMEDOUT;
	left = div_u64(req->deadline_ns - now, NSEC_PER_USEC);
	req->x.timeout_us = (u32)clamp_t(u64, left, 1, U32_MAX);
	req->fx.timeout_us = req->x.timeout_us;
	ecmxf_watch_req_sent(edev, &req->x);
	return ecmxf_engine_submit(&edev->link.e, &req->x, now);
}

/*
 * Take @req's command and its result fetch out of the engine; the fetch
 * may be there alone, after its command ended.
 */
static void ecmxf_req_cancel(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	if (ecmxf_engine_cancel(&edev->link.e, &req->x) && req->x.fetch)
		ecmxf_engine_cancel(&edev->link.e, req->x.fetch);
}

/* Both @req's command and its result fetch (if any) are done. */
static bool ecmxf_req_ended(const struct ecmxf_req *req)
{
	return req->x.status != -EINPROGRESS &&
	       (!req->x.fetch || req->fx.status != -EINPROGRESS);
}

/* Withdraw the running async command with @status; lock held. */
static void ecmxf_cancel_async(struct ecmxf_dev *edev, int status)
{
	struct ecmxf_req *req = edev->async_req;

	if (!req)
		return;
	ecmxf_req_cancel(edev, req);
	edev->async_req = NULL;
	ecmxf_req_finish(edev, req, status);
}

/* A reset request finished in the engine: apply its consequences. */
static void ecmxf_reset_done(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	if (req->x.status)
		return;
	if (req->reset_flags == ECMXF_RESET_F_ASYNC_CMD &&
	    (req->reset_param & ECMXF_RESET_ASYNC_ABANDON))
		ecmxf_cancel_async(edev, -ECANCELED);
	if (req->reset_flags == ECMXF_RESET_F_WARM) {
		ecmxf_fail_queued(edev, -ECONNRESET);
		/* a warm reset forgets the bus: the count is unknown again */
		edev->chip.slave_count = 0;
		/* and the FIFOs: the rings cannot go on */
		ecmxf_rings_stop(edev, -ECONNRESET);
	}
}

/* @req left the engine: note what it tells, then finish it; lock held. */
static void ecmxf_done(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	int status = req->x.status;

	/* the command ended well: the outcome is its result fetch's */
	if (!status && req->x.fetch) {
		status = req->fx.status;
		req->fetched = true;
	}

	if (req->x.hdr.code == ECMXF_CMD_FW_VERSION_GET &&
	    (!status || status == -EMSGSIZE) &&
	    req->x.rx_len >= sizeof(edev->chip.fw_info)) {
		edev->chip.fw_version = req->x.rsp.ret;
		memcpy(edev->chip.fw_info, req->rx, sizeof(edev->chip.fw_info));
		edev->chip.fw_valid = true;
	}
	/* the slave count, when the chip answered it without a command error */
	if (req->x.hdr.code == ECMXF_CMD_ECAT_SLV_CNT_GET && !status &&
	    req->x.rsp.code == ECMXF_CMD_ECAT_SLV_CNT_GET &&
	    !(req->x.rsp.err_status & ECMXF_ERR_CMD))
		edev->chip.slave_count = req->x.rsp.ret;
	if (req->x.hdr.code == ECMXF_CMD_WARM_RESET && !status)
		edev->chip.slave_count = 0;
	if (req->kind == ECMXF_REQ_RESET)
		ecmxf_reset_done(edev, req);
	ecmxf_watch_req_done(edev, &req->x);
	ecmxf_req_finish(edev, req, status);
}

/*
 * Finish what the engine finished; lock held.  The engine moves an
 * accepted async command out of its command slot: follow it.  @put: the
 * rings references of finished pump commands (or NULL), for the caller
 * to drop after unlocking.
 */
static void ecmxf_collect(struct ecmxf_dev *edev,
			  struct ecmxf_rings *put[ECMXF_PUMP_CMDS])
{
	struct ecmxf_req *req = edev->cur_req;

	lockdep_assert_held(&edev->lock);
	ecmxf_snapshot(edev);
	if (req && ecmxf_req_ended(req)) {
		edev->cur_req = NULL;
		ecmxf_done(edev, req);
	} else if (req && (ecmxf_engine_running(&edev->link.e, &req->x) ||
			   req->x.status != -EINPROGRESS)) {
		/* running, or ended with its result fetch still to come */
		edev->cur_req = NULL;
		edev->async_req = req;
	}
	req = edev->async_req;
	if (req && ecmxf_req_ended(req)) {
		edev->async_req = NULL;
		ecmxf_done(edev, req);
	}
	ecmxf_pump_collect(edev, put);
	/* the pump's counts too */
	ecmxf_publish(edev);
}

/* Drop the pump's references to the rings; the lock not held. */
static void ecmxf_rings_put_all(struct ecmxf_rings *put[ECMXF_PUMP_CMDS])
{
	unsigned int i;

	for (i = 0; i < ECMXF_PUMP_CMDS; i++)
		ecmxf_rings_put(put[i]);
}

/*
 * ECMXF_RESET_F_LINK: forget the link state and find the chip again, in
 * the worker (the only owner of the engine).  Everything in flight fails
 * with -ECONNRESET.
 */
static int ecmxf_reset_link(struct ecmxf_dev *edev)
{
	unsigned int size = ecmxf_engine_data_size(&edev->link.e);
	enum ecmxf_check check = edev->link.e.check;
	struct ecmxf_rings *pumped[ECMXF_PUMP_CMDS];
	int ret;

	mutex_lock(&edev->lock);
	ecmxf_cancel_async(edev, -ECONNRESET);
	ecmxf_pump_cancel(edev, pumped);
	ecmxf_rings_stop(edev, -ECONNRESET);
	mutex_unlock(&edev->lock);
	ecmxf_rings_put_all(pumped);

	ecmxf_engine_reinit(edev, size, check);
	ecmxf_watch_link_reset(edev);
	ret = ecmxf_read_fw_version(edev);
	if (ret)
		ret = ecmxf_find_format(edev);
	mutex_lock(&edev->lock);
	ecmxf_snapshot(edev);
	mutex_unlock(&edev->lock);
	return ret;
}

/*
 * Start a reset request.  ASYNC_CMD and WARM are commands through the
 * engine (finished by ecmxf_collect()); LINK is done here.  Called when
 * the engine's command slot is free; the lock is not held.
 */
static void ecmxf_start_reset(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	int ret;

	if (req->reset_flags == ECMXF_RESET_F_LINK) {
		ret = ecmxf_reset_link(edev);
		mutex_lock(&edev->lock);
		ecmxf_req_finish(edev, req, ret);
		mutex_unlock(&edev->lock);
		return;
	}
	if (req->reset_flags == ECMXF_RESET_F_WARM) {
		/* the restart ends whatever the chip runs */
		mutex_lock(&edev->lock);
		ecmxf_cancel_async(edev, -ECONNRESET);
		mutex_unlock(&edev->lock);
	}
	ret = ecmxf_submit(edev, req);
	mutex_lock(&edev->lock);
	if (ret)
		ecmxf_req_finish(edev, req, ret);
	else
		edev->cur_req = req;
	mutex_unlock(&edev->lock);
}

/*
 * Sleep until there is work: a kick, INT1, kthread_stop(), @until_ns
 * (ktime_get_ns() clock; U64_MAX: no timeout) for the events' poll or a
 * masked level INT1, or the PDO pump's next timer deadline.  A wake-up by
 * INT0 alone ("ready" after the last exchange of a command) only puts it
 * back to sleep, without a turn of the owner loop; its flag stays for the
 * next wait for "ready".
 */
static void ecmxf_idle(struct ecmxf_dev *edev, u64 until_ns)
{
	s64 int0_seen;
	ktime_t t;
	u64 pump;

	if (edev->link.int1_cleared) {
		/* the clear must reach the chip before INT1 is unmasked */
		ecmxf_wait_ready(edev);
		ecmxf_int1_cleared(edev);
	}
	mutex_lock(&edev->lock);
	pump = ecmxf_pump_deadline(edev);
	mutex_unlock(&edev->lock);
	if (pump && pump < until_ns)
		until_ns = pump;
	t = ns_to_ktime(until_ns);

	int0_seen = atomic64_read(&edev->irq.int0_irqs);
	for (;;) {
		set_current_state(TASK_IDLE);
		if (atomic_read(&edev->link.kick) || atomic_read(&edev->irq.int1_flag) ||
		    kthread_should_stop())
			break;
		if (until_ns == U64_MAX)
			schedule();
		else if (!schedule_hrtimeout(&t, HRTIMER_MODE_ABS))
			break;		/* @until_ns reached */
		/*
		 * an INT0 interrupt ("ready" after the last exchange) is no
		 * work: sleep on (the next wait for "ready" sees its flag)
		 */
		if (atomic64_read(&edev->irq.int0_irqs) == int0_seen)
			break;
		int0_seen = atomic64_read(&edev->irq.int0_irqs);
	}
	__set_current_state(TASK_RUNNING);
}

static int ecmxf_worker_fn(void *data)
{
	struct ecmxf_dev *edev = data;
	struct ecmxf_req *reset, *req;
	struct ecmxf_rings *pump, *finished[ECMXF_PUMP_CMDS];
	u64 now, int1_at;
	bool slot_free, pump_ok, waits;
	int ret;

	ecmxf_watch_start(edev);
	while (!kthread_should_stop()) {
		/* the events found since, no lock held */
		ecmxf_watch_flush(edev);
		atomic_set(&edev->link.kick, 0);
		now = ktime_get_ns();
		int1_at = ecmxf_int1_rearm(edev, now, false);
		reset = NULL;
		req = NULL;
		pump = NULL;

		mutex_lock(&edev->lock);
		/* a reset needs the engine to itself */
		slot_free = !edev->cur_req && !ecmxf_pump_busy(edev);
		if (slot_free) {
			reset = list_first_entry_or_null(&edev->resets,
							 struct ecmxf_req,
							 node);
			if (reset) {
				list_del_init(&reset->node);
				reset->state = ECMXF_RS_ACTIVE;
			}
			if (reset && ecmxf_req_refused(edev, reset)) {
				ecmxf_req_refuse(edev, reset);
				reset = NULL;
			}
		}
		if (!reset && now >= edev->link.next_expire_ns) {
			ecmxf_expire_queued(edev, now);
			edev->link.next_expire_ns = now + ECMXF_EXPIRE_PERIOD_NS;
			ecmxf_publish(edev);
		}
		/*
		 * The pump and the files take turns.  One new command per
		 * turn of the loop: while the one before waits for its answer
		 * the engine sends it in the exchange that fetches that answer
		 * (pipelining), so the pump and a file's request share
		 * exchanges.
		 */
		pump_ok = ecmxf_engine_can_submit(&edev->link.e, NULL);
		/* a waiting reset lets the engine drain first */
		if (!reset && list_empty(&edev->resets) &&
		    (pump_ok || !edev->cur_req)) {
			if (edev->pdo.pump.turn && pump_ok)
				pump = ecmxf_pump_take(edev, now);
			if (!pump && !edev->cur_req)
				req = ecmxf_pick(edev);
			if (req) {
				req->state = ECMXF_RS_ACTIVE;
				edev->cur_req = req;
				edev->pdo.pump.turn = true;
			} else if (!pump && pump_ok) {
				pump = ecmxf_pump_take(edev, now);
			}
		}
		mutex_unlock(&edev->lock);

		if (reset) {
			ecmxf_start_reset(edev, reset);
			continue;
		}
		if (pump)
			ecmxf_pump_submit(edev, pump, now);
		if (req) {
			ret = ecmxf_submit(edev, req);
			if (ret) {
				mutex_lock(&edev->lock);
				edev->cur_req = NULL;
				ecmxf_req_finish(edev, req, ret);
				mutex_unlock(&edev->lock);
				continue;
			}
		}

		/*
		 * A pump command's answer left to the next FIFO command needs
		 * no exchange of its own; INT1 meanwhile is for that command
		 * (the pump's turn at the top of the loop), not a refresh.
		 */
		waits = ecmxf_pump_answer_waits(edev);
		if (waits && atomic_read(&edev->irq.int1_flag))
			continue;
		/*
		 * INT1, or a poll for the events' listeners: refresh the
		 * header (flags, state) with one exchange
		 */
		if ((waits || (ecmxf_engine_idle(&edev->link.e) &&
			       !atomic_xchg(&edev->irq.int1_flag, 0))) &&
		    !ecmxf_watch_poll_due(edev, now)) {
			/* a burst that just ended */
			ecmxf_watch_flush(edev);
			ecmxf_idle(edev, min(ecmxf_watch_wake_at(edev, now),
					     int1_at));
			continue;
		}
		ecmxf_exchange(edev);
		mutex_lock(&edev->lock);
		ecmxf_collect(edev, finished);
		mutex_unlock(&edev->lock);
		/* the pump's references, after the lock (see &ecmxf_dev.lock) */
		ecmxf_rings_put_all(finished);
	}

	/* the device is going away: nothing in flight survives */
	mutex_lock(&edev->lock);
	if (edev->cur_req) {
		req = edev->cur_req;
		ecmxf_req_cancel(edev, req);
		edev->cur_req = NULL;
		ecmxf_req_finish(edev, req, -ENODEV);
	}
	ecmxf_cancel_async(edev, -ENODEV);
	ecmxf_pump_cancel(edev, finished);
	mutex_unlock(&edev->lock);
	ecmxf_rings_put_all(finished);
	/* the last events, after every command of the watcher ended */
	ecmxf_watch_stop(edev);
	return 0;
}

/**
 * ecmxf_worker_start() - create the link worker, SCHED_FIFO
 * @edev: the device, link up
 *
 * The worker gets sched_set_fifo(): the middle real-time priority that
 * the kernel gives its own real-time kthreads (50).  Which priority it
 * needs depends on the machine (above the application's cyclic thread
 * or below it, above or below the SPI controller's and the GPIO IRQ
 * threads): the machine builder sets it with chrt(1) on the thread
 * "ecmxfN", as for any kernel thread, not through the driver.
 *
 * Return: 0 or a negative errno.
 */
int ecmxf_worker_start(struct ecmxf_dev *edev)
{
	struct task_struct *t;

	t = kthread_create(ecmxf_worker_fn, edev, "ecmxf%d", edev->id);
	if (IS_ERR(t))
		return PTR_ERR(t);
	sched_set_fifo(t);
	get_task_struct(t);
	edev->link.worker = t;
	WRITE_ONCE(edev->link.owner, t);
	wake_up_process(t);
	return 0;
}

/**
 * ecmxf_worker_stop() - stop the link worker
 * @edev: the device; its IRQs are already freed
 *
 * Requests in the engine fail with -ENODEV; queued ones stay queued for
 * ecmxf_chrdev_fail_all().
 */
void ecmxf_worker_stop(struct ecmxf_dev *edev)
{
	struct task_struct *t = edev->link.worker;

	if (!t)
		return;
	kthread_stop(t);
	mutex_lock(&edev->lock);
	WRITE_ONCE(edev->link.owner, NULL);
	edev->link.worker = NULL;
	mutex_unlock(&edev->lock);
	put_task_struct(t);
}

/**
 * ecmxf_get_counters() - the link statistics since probe, without a lock
 * @edev: the device
 * @k: filled in, reserved fields zero
 */
void ecmxf_get_counters(struct ecmxf_dev *edev, struct ecmxf_counters *k)
{
	struct ecmxf_snap v;

	ecmxf_get_snap(edev, &v);
	*k = v.k;
	k->int0_irqs = atomic64_read(&edev->irq.int0_irqs);
	k->int1_irqs = atomic64_read(&edev->irq.int1_irqs);
}

/**
 * ecmxf_get_snap() - what the worker published last, without a lock
 * @edev: the device
 * @snap: filled in (&struct ecmxf_snap; its interrupt counts 0)
 *
 * Never waits for the worker, nor makes it wait (ecmxf-latch.h).
 */
void ecmxf_get_snap(struct ecmxf_dev *edev, struct ecmxf_snap *snap)
{
	ecmxf_latch_read(&edev->cnt.snap_seq, &edev->cnt.snap[0], &edev->cnt.snap[1], snap,
			 sizeof(*snap));
}
