// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-events.c - events from successive response headers, sans I/O
 *
 * Feed every valid response header with the time it arrived:
 *
 *	n = ecmxf_det_feed(d, hdr, now, ev);	(ev holds ECMXF_DET_MAX_EVENTS)
 *
 * The first header is the baseline and gives no event; each later one is
 * compared with the one before:
 *
 * - a chip reset (the NOP bit, "Ethernet initialised" going away, or the
 *   ECAT state back to 0) is the only event of its header: everything
 *   else that changed follows from it;
 * - otherwise, in this order: the ECAT state, the link (error status bit
 *   0), the other error status bits, the watched ECM status bits, the SPI
 *   CRC error count going up, the WKC error count going up (only the
 *   first increase of a burst is an event), the end of a WKC burst, and
 *   the two FIFO counts crossing their marks.
 *
 * A WKC burst ends when no header showed new errors for the quiet time;
 * since that is a matter of time, not of headers, ecmxf_det_poll() ends it
 * too, and ecmxf_det_deadline() says when to call it.  Counts that go down
 * (cleared by INIT_OP or CRC_ERR_CNT_CLR) are no events.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-events.h"

#define ECMXF_DET_U64_MAX	(~(u64)0)

/**
 * ecmxf_det_init() - start a detector with no baseline
 * @d: detector
 * @cfg: thresholds, or NULL for the defaults (%ECMXF_DET_TX_HIGH,
 *	%ECMXF_DET_RX_LOW, %ECMXF_DET_WKC_QUIET_NS)
 */
void ecmxf_det_init(struct ecmxf_det *d, const struct ecmxf_det_cfg *cfg)
{
	memset(d, 0, sizeof(*d));
	if (cfg) {
		d->cfg = *cfg;
	} else {
		d->cfg.tx_high = ECMXF_DET_TX_HIGH;
		d->cfg.rx_low = ECMXF_DET_RX_LOW;
		d->cfg.wkc_quiet_ns = ECMXF_DET_WKC_QUIET_NS;
	}
}

static struct ecmxf_det_event *ecmxf_det_new(struct ecmxf_det_event *out,
					     unsigned int *n, u8 type,
					     const struct ecmxf_rsp_hdr *h,
					     u64 now_ns)
{
	struct ecmxf_det_event *e = &out[(*n)++];

	memset(e, 0, sizeof(*e));
	e->type = type;
	e->time_ns = now_ns;
	if (h) {
		e->err_status = h->err_status;
		e->ecm_status = h->ecm_status;
	}
	return e;
}

/* The burst ends: its event, from the last header seen. */
static void ecmxf_det_end_burst(struct ecmxf_det *d, u64 now_ns,
				struct ecmxf_det_event *out, unsigned int *n)
{
	struct ecmxf_det_event *e;

	e = ecmxf_det_new(out, n, ECMXF_DET_WKC_BURST_END,
			  d->have_prev ? &d->prev : NULL, now_ns);
	e->errors = d->burst_errors;
	e->duration_ns = d->burst_last_ns - d->burst_start_ns;
	e->count = d->have_prev ? d->prev.wkc_err_cnt : 0;
	d->burst = false;
	d->burst_errors = 0;
}

static bool ecmxf_det_is_reset(const struct ecmxf_rsp_hdr *p,
			       const struct ecmxf_rsp_hdr *h)
{
	if (h->ecm_status & ECMXF_STS_NOP)
		return true;
	if ((p->ecm_status & ECMXF_STS_ETH_INIT) &&
	    !(h->ecm_status & ECMXF_STS_ETH_INIT))
		return true;
	return p->ecat_state != ECMXF_ECAT_NONE &&
	       h->ecat_state == ECMXF_ECAT_NONE;
}

static void ecmxf_det_fifo(const struct ecmxf_det *d,
			   const struct ecmxf_rsp_hdr *prev,
			   const struct ecmxf_rsp_hdr *h, u64 now_ns,
			   struct ecmxf_det_event *out, unsigned int *n, bool tx)
{
	unsigned int p = tx ? prev->tx_fifo_cnt : prev->rx_fifo_cnt;
	unsigned int c = tx ? h->tx_fifo_cnt : h->rx_fifo_cnt;
	unsigned int mark = tx ? d->cfg.tx_high : d->cfg.rx_low;
	/* TxFIFO: "above" is at or above the high mark; RxFIFO: above the low */
	bool was = tx ? p >= mark : p > mark;
	bool is = tx ? c >= mark : c > mark;
	struct ecmxf_det_event *e;

	if (was == is)
		return;
	e = ecmxf_det_new(out, n, ECMXF_DET_FIFO, h, now_ns);
	e->fifo = (u8)(tx ? ECMXF_DET_FIFO_TX : ECMXF_DET_FIFO_RX);
	e->count = c;
	e->mark = mark;
	e->above = is;
}

/**
 * ecmxf_det_feed() - the events of one more response header
 * @d: detector
 * @h: a valid response header
 * @now_ns: when it arrived
 * @out: room for %ECMXF_DET_MAX_EVENTS events
 *
 * Return: the number of events written to @out.
 */
unsigned int ecmxf_det_feed(struct ecmxf_det *d,
			    const struct ecmxf_rsp_hdr *h, u64 now_ns,
			    struct ecmxf_det_event *out)
{
	const struct ecmxf_rsp_hdr old = d->prev;
	const struct ecmxf_rsp_hdr *p = &old;
	struct ecmxf_det_event *e;
	unsigned int n = 0;
	u8 pw, cw;

	if (!d->have_prev) {
		d->prev = *h;
		d->have_prev = true;
		return 0;
	}

	if (ecmxf_det_is_reset(p, h)) {
		if (d->burst)
			ecmxf_det_end_burst(d, now_ns, out, &n);
		e = ecmxf_det_new(out, &n, ECMXF_DET_RESET, h, now_ns);
		e->new_val = h->ecat_state;
		d->prev = *h;
		return n;
	}

	if (h->ecat_state != p->ecat_state) {
		e = ecmxf_det_new(out, &n, ECMXF_DET_STATE, h, now_ns);
		e->old_val = p->ecat_state;
		e->new_val = h->ecat_state;
	}
	if ((h->err_status ^ p->err_status) & ECMXF_ERR_LINK_HW) {
		e = ecmxf_det_new(out, &n, ECMXF_DET_LINK, h, now_ns);
		e->new_val = (h->err_status & ECMXF_ERR_LINK_HW) ? 1 : 0;
	}
	if ((h->err_status ^ p->err_status) & ECMXF_DET_ERR_WATCHED) {
		e = ecmxf_det_new(out, &n, ECMXF_DET_ERROR_STATUS, h, now_ns);
		e->old_val = p->err_status;
		e->new_val = h->err_status;
	}
	pw = p->ecm_status & ECMXF_DET_ECM_WATCHED;
	cw = h->ecm_status & ECMXF_DET_ECM_WATCHED;
	if (pw != cw) {
		e = ecmxf_det_new(out, &n, ECMXF_DET_ECM_STATUS, h, now_ns);
		e->old_val = pw;
		e->new_val = cw;
	}
	if (h->crc_err_cnt > p->crc_err_cnt) {
		e = ecmxf_det_new(out, &n, ECMXF_DET_CRC_ERRORS, h, now_ns);
		e->increase = (u32)(h->crc_err_cnt - p->crc_err_cnt);
		e->count = h->crc_err_cnt;
	}
	if (h->wkc_err_cnt > p->wkc_err_cnt) {
		u32 inc = (u32)(h->wkc_err_cnt - p->wkc_err_cnt);

		if (!d->burst) {
			e = ecmxf_det_new(out, &n, ECMXF_DET_WKC_BURST, h,
					  now_ns);
			e->increase = inc;
			e->count = h->wkc_err_cnt;
			d->burst = true;
			d->burst_errors = 0;
			d->burst_start_ns = now_ns;
		}
		d->burst_errors += inc;
		d->burst_last_ns = now_ns;
	}
	d->prev = *h;
	if (d->burst && now_ns - d->burst_last_ns >= d->cfg.wkc_quiet_ns)
		ecmxf_det_end_burst(d, now_ns, out, &n);
	ecmxf_det_fifo(d, &old, h, now_ns, out, &n, true);
	ecmxf_det_fifo(d, &old, h, now_ns, out, &n, false);
	return n;
}

/**
 * ecmxf_det_poll() - end a WKC burst whose quiet time has passed
 * @d: detector
 * @now_ns: current time
 * @out: room for one event
 *
 * Return: 1 when the burst ended (%ECMXF_DET_WKC_BURST_END in @out), else 0.
 */
unsigned int ecmxf_det_poll(struct ecmxf_det *d, u64 now_ns,
			    struct ecmxf_det_event *out)
{
	unsigned int n = 0;

	if (d->burst && now_ns >= d->burst_last_ns &&
	    now_ns - d->burst_last_ns >= d->cfg.wkc_quiet_ns)
		ecmxf_det_end_burst(d, now_ns, out, &n);
	return n;
}

/**
 * ecmxf_det_rebase() - forget the baseline (the link was resynchronised)
 * @d: detector
 * @now_ns: current time
 * @out: room for one event
 *
 * The next header fed is a baseline again.  A running WKC burst ends now
 * rather than vanish.
 *
 * Return: 1 when a burst ended (its event in @out), else 0.
 */
unsigned int ecmxf_det_rebase(struct ecmxf_det *d, u64 now_ns,
			      struct ecmxf_det_event *out)
{
	unsigned int n = 0;

	if (d->burst)
		ecmxf_det_end_burst(d, now_ns, out, &n);
	d->have_prev = false;
	return n;
}

/**
 * ecmxf_det_deadline() - when ecmxf_det_poll() may have an event
 * @d: detector
 *
 * Return: a time on the caller's clock, or U64_MAX when no burst runs.
 */
u64 ecmxf_det_deadline(const struct ecmxf_det *d)
{
	if (!d->burst)
		return ECMXF_DET_U64_MAX;
	return d->burst_last_ns + d->cfg.wkc_quiet_ns;
}

/**
 * ecmxf_det_have_baseline() - has a header been fed since init or rebase
 * @d: detector
 *
 * Return: true when the next header is compared with a previous one.
 */
bool ecmxf_det_have_baseline(const struct ecmxf_det *d)
{
	return d->have_prev;
}
