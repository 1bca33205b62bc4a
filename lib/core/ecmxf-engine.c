// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-engine.c - the exchange rules of the ECM-XF link, sans I/O
 *
 * The owner of the link calls, for every SPI exchange:
 *
 *	ecmxf_engine_next(e, now, tx, ecmxf_engine_pkt_size(e));
 *	... clock tx out and rx in, in one full-duplex transfer ...
 *	events = ecmxf_engine_input(e, now, rx, same size);
 *
 * and submits commands with ecmxf_engine_submit() whenever
 * ecmxf_engine_can_submit() allows.  The engine applies the rules of
 * the manuals (see Documentation/protocol-core.rst):
 *
 * - every response answers the packet sent one exchange earlier;
 * - each new command gets a fresh index, so its (index, code) differs
 *   from the previous packet's, and a command is polled by re-sending
 *   the identical (index, code), which the chip runs as INFO_UPDATE;
 * - the first packet of a fresh engine is an INFO_UPDATE "sync", so a
 *   first command can never repeat whatever the chip saw last;
 * - async commands are answered at once and then tracked through the
 *   busy bit of every header; one runs at a time, immediate commands
 *   may run meanwhile; the error bit decides their outcome;
 * - bad packets (start/end word, check word, "not ready") are retried up
 *   to a bound, then whatever waits fails with the fault's errno;
 * - every command has a deadline.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-proto.h"

enum {
	ECMXF_XS_IDLE = 0,
	ECMXF_XS_QUEUED,	/* in e->cur, not yet sent */
	ECMXF_XS_SENT,		/* in e->cur, sent, awaiting its answer */
	ECMXF_XS_RUNNING,	/* in e->async, chip busy */
	ECMXF_XS_DONE,
};

#define ECMXF_U64_MAX	(~(u64)0)

/**
 * ecmxf_engine_init() - reset an engine to its power-on state
 * @e: engine
 * @data_size: data section size in force on the chip (32..1408)
 * @check: check type in force on the chip
 *
 * An invalid @data_size is replaced by the default 112.
 */
void ecmxf_engine_init(struct ecmxf_engine *e, unsigned int data_size,
		       enum ecmxf_check check)
{
	memset(e, 0, sizeof(*e));
	e->data_size = (u16)(ecmxf_data_size_valid(data_size) ?
			     data_size : ECMXF_DATA_DEFAULT);
	e->check = (u8)((unsigned int)check <= ECMXF_CHECK_CRC32 ?
			check : ECMXF_CHECK_FIXED);
	e->prev_check = e->check;
	e->pipeline = true;
	e->max_retries = ECMXF_ENGINE_DEFAULT_RETRIES;
	e->last_fault = ECMXF_FAULT_NONE;
}

/**
 * ecmxf_engine_set_format() - tell the engine the chip's packet format
 * @e: engine
 * @data_size: data section size (32..1408)
 * @check: check type
 *
 * The engine follows SPI_RECONFIG_OP, CRC_TYPE_SET and WARM_RESET by
 * itself; this is for an owner that changed the chip some other way.
 *
 * Return: 0 or -EINVAL.
 */
int ecmxf_engine_set_format(struct ecmxf_engine *e, unsigned int data_size,
			    enum ecmxf_check check)
{
	if (!ecmxf_data_size_valid(data_size) ||
	    (unsigned int)check > ECMXF_CHECK_CRC32)
		return -EINVAL;
	e->data_size = (u16)data_size;
	e->prev_check = e->check;
	e->check = (u8)check;
	return 0;
}

/**
 * ecmxf_engine_set_retries() - bound on consecutive bad packets
 * @e: engine
 * @max: bad packets tolerated in a row (1..255) before failing
 */
void ecmxf_engine_set_retries(struct ecmxf_engine *e, unsigned int max)
{
	if (max < 1)
		max = 1;
	if (max > 255)
		max = 255;
	e->max_retries = (u8)max;
}

/**
 * ecmxf_engine_pkt_size() - size of the next exchange
 * @e: engine
 *
 * Call before every exchange: SPI_RECONFIG_OP and WARM_RESET change it.
 *
 * Return: packet size in bytes.
 */
size_t ecmxf_engine_pkt_size(const struct ecmxf_engine *e)
{
	return ECMXF_PKT_SIZE(e->data_size);
}

static bool ecmxf_xfer_async(const struct ecmxf_xfer *x)
{
	return ecmxf_cmd_is_async(x->hdr.code, x->hdr.param);
}

/* commands that change the next packet's format: nothing rides with them */
static bool ecmxf_cmd_solo(unsigned int code)
{
	return code == ECMXF_CMD_SPI_RECONFIG_OP ||
	       code == ECMXF_CMD_CRC_TYPE_SET || code == ECMXF_CMD_WARM_RESET;
}

/* an async command is accepted, running or about to be sent */
static bool ecmxf_async_pending(const struct ecmxf_engine *e)
{
	const struct ecmxf_xfer *s[2] = { e->cur, e->nxt };
	unsigned int i;

	if (e->async)
		return true;
	for (i = 0; i < 2; i++)
		if (s[i] && (ecmxf_xfer_async(s[i]) || s[i]->owner))
			return true;
	return false;
}

/**
 * ecmxf_engine_set_pipeline() - let a second command ride
 * @e: engine
 * @on: true (the default): a second command is sent in the exchange that
 *	fetches the first one's answer, and an async command's result fetch
 *	is its poll; false: one command per two exchanges, INFO_UPDATE polls
 *	and the fetch after completion (for comparison and for tests)
 */
void ecmxf_engine_set_pipeline(struct ecmxf_engine *e, bool on)
{
	e->pipeline = on;
}

/**
 * ecmxf_engine_can_submit() - may @x be submitted now
 * @e: engine
 * @x: the command
 *
 * Return: true when a command slot is free: the first, or the second one
 * behind a command that changes no packet format (pipelining on).  An
 * async command also needs no other async command accepted, running or
 * queued.
 */
bool ecmxf_engine_can_submit(const struct ecmxf_engine *e,
			     const struct ecmxf_xfer *x)
{
	bool async = x && ecmxf_xfer_async(x);

	if (e->cur) {
		if (e->nxt || !e->pipeline || ecmxf_cmd_solo(e->cur->hdr.code))
			return false;
		if (x && ecmxf_cmd_solo(x->hdr.code))
			return false;
	}
	return !(async && ecmxf_async_pending(e));
}

static u64 ecmxf_deadline_of(const struct ecmxf_xfer *x, u64 now_ns)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(x->hdr.code);
	u64 timeout_ns = x->timeout_us ? (u64)x->timeout_us * 1000u :
			 (u64)(ci ? ci->timeout_ms : 100u) * 1000000u;

	return now_ns + timeout_ns;
}

static void ecmxf_xfer_start(struct ecmxf_xfer *x, u64 now_ns)
{
	x->async = ecmxf_xfer_async(x);
	x->status = -EINPROGRESS;
	x->fault = ECMXF_FAULT_NONE;
	x->rx_len = 0;
	memset(&x->rsp, 0, sizeof(x->rsp));
	x->started_ns = now_ns;
	x->deadline_ns = ecmxf_deadline_of(x, now_ns);
	x->state = ECMXF_XS_QUEUED;
	x->sent_seq = 0;
	x->last_seq = 0;
}

static int ecmxf_xfer_check(const struct ecmxf_engine *e,
			    const struct ecmxf_xfer *x)
{
	if (!x || (x->tx_len && !x->tx_data) || (x->rx_size && !x->rx_buf))
		return -EINVAL;
	if (x->tx_len > e->data_size)
		return -EMSGSIZE;
	if (x->hdr.code == ECMXF_CMD_SPI_RECONFIG_OP &&
	    !ecmxf_data_size_valid(x->hdr.len))
		return -EINVAL;
	/* re-sends go out in the format these commands switch to */
	if (x->hdr.code == ECMXF_CMD_SPI_RECONFIG_OP && x->tx_len > x->hdr.len)
		return -EMSGSIZE;
	if (x->hdr.code == ECMXF_CMD_WARM_RESET &&
	    x->tx_len > ECMXF_DATA_DEFAULT)
		return -EMSGSIZE;
	if (x->hdr.code == ECMXF_CMD_CRC_TYPE_SET &&
	    x->hdr.param > ECMXF_CHECK_CRC32)
		return -EINVAL;
	return 0;
}

/* put @x in the first free slot */
static void ecmxf_slot_add(struct ecmxf_engine *e, struct ecmxf_xfer *x)
{
	if (!e->cur)
		e->cur = x;
	else
		e->nxt = x;
}

/* take @x out of its slot; the younger command moves up */
static void ecmxf_slot_del(struct ecmxf_engine *e, struct ecmxf_xfer *x)
{
	if (e->cur == x) {
		e->cur = e->nxt;
		e->nxt = NULL;
	} else if (e->nxt == x) {
		e->nxt = NULL;
	}
}

/**
 * ecmxf_engine_submit() - hand a command to the engine
 * @e: engine
 * @x: the command; it must stay valid until its status is final (and
 *	@x->fetch until its own is)
 * @now_ns: current time
 *
 * Return: 0; -EBUSY when ecmxf_engine_can_submit() says no; -EINVAL for
 * a bad argument (also a @x->fetch on a command that is not async, or a
 * fetch that is async or has a fetch itself); -EMSGSIZE when a data
 * length exceeds the data section.
 */
int ecmxf_engine_submit(struct ecmxf_engine *e, struct ecmxf_xfer *x,
			u64 now_ns)
{
	struct ecmxf_xfer *f = x ? x->fetch : NULL;
	int ret;

	ret = ecmxf_xfer_check(e, x);
	if (ret)
		return ret;
	if (f) {
		ret = ecmxf_xfer_check(e, f);
		if (ret)
			return ret;
		if (f == x || !ecmxf_xfer_async(x) || ecmxf_xfer_async(f) ||
		    f->fetch || ecmxf_cmd_solo(f->hdr.code))
			return -EINVAL;
	}
	if (!ecmxf_engine_can_submit(e, x))
		return -EBUSY;

	ecmxf_xfer_start(x, now_ns);
	x->owner = NULL;
	if (f) {
		ecmxf_xfer_start(f, now_ns);
		f->state = ECMXF_XS_IDLE;	/* queued when @x is accepted */
		f->owner = x;
	}
	/*
	 * The retry bound is per command: bad packets that a command which
	 * ended meanwhile (by its deadline) or an idle refresh saw must not
	 * use up the budget of this one.  Commands in flight keep counting.
	 */
	if (!e->async && !e->cur)
		e->bad_in_row = 0;
	ecmxf_slot_add(e, x);
	return 0;
}

static void ecmxf_finish(struct ecmxf_xfer *x, int status)
{
	x->status = status;
	x->state = ECMXF_XS_DONE;
}

/* A fetch whose async command failed before the fetch was queued. */
static unsigned int ecmxf_drop_fetch(struct ecmxf_xfer *x)
{
	struct ecmxf_xfer *f = x->fetch;

	if (!f || f->owner != x || f->state != ECMXF_XS_IDLE)
		return 0;
	ecmxf_finish(f, -ECANCELED);
	return ECMXF_EV_CMD_DONE;
}

/* Finish a command in a slot; returns the event to report. */
static unsigned int ecmxf_finish_slot(struct ecmxf_engine *e,
				      struct ecmxf_xfer *x, int status)
{
	unsigned int ev = ECMXF_EV_CMD_DONE;

	ecmxf_slot_del(e, x);
	ecmxf_finish(x, status);
	if (status)
		ev |= ecmxf_drop_fetch(x);
	return ev;
}

static unsigned int ecmxf_finish_async(struct ecmxf_engine *e, int status)
{
	struct ecmxf_xfer *x = e->async;

	ecmxf_finish(x, status);
	e->async = NULL;
	if (status)
		return ECMXF_EV_ASYNC_DONE | ecmxf_drop_fetch(x);
	return ECMXF_EV_ASYNC_DONE;
}

/* Queue the fetch of @x (accepted, or done at once) in a free slot. */
static void ecmxf_queue_fetch(struct ecmxf_engine *e, struct ecmxf_xfer *x,
			      u64 now_ns)
{
	struct ecmxf_xfer *f = x->fetch;
	u64 d;

	if (!f || f->owner != x || f->state != ECMXF_XS_IDLE)
		return;
	f->state = ECMXF_XS_QUEUED;
	/* it polls until @x ends: it may take as long as @x */
	d = ecmxf_deadline_of(f, now_ns);
	f->deadline_ns = d > x->deadline_ns ? d : x->deadline_ns;
	ecmxf_slot_add(e, f);
}

/**
 * ecmxf_engine_cancel() - withdraw a command
 * @e: engine
 * @x: a command submitted to @e
 *
 * The command finishes with -ECANCELED, and so does its fetch if it has
 * not finished yet.  An async command may still run on the chip; its
 * busy bit then delays the next async command.
 *
 * Return: 0, or -ENOENT when @x is not in the engine.
 */
int ecmxf_engine_cancel(struct ecmxf_engine *e, struct ecmxf_xfer *x)
{
	struct ecmxf_xfer *f;

	if (!x || (x != e->cur && x != e->nxt && x != e->async))
		return -ENOENT;
	f = x->fetch;
	if (x == e->async) {
		ecmxf_finish_async(e, -ECANCELED);
	} else {
		ecmxf_slot_del(e, x);
		ecmxf_finish(x, -ECANCELED);
	}
	if (f && f->owner == x && f->status == -EINPROGRESS) {
		ecmxf_slot_del(e, f);
		ecmxf_finish(f, -ECANCELED);
	}
	return 0;
}

/**
 * ecmxf_engine_clear_errors() - clear error-status bits on the chip
 * @e: engine
 * @control_bits: %ECMXF_CTL_* bits, sent in the control byte of the
 *	next new packet
 */
void ecmxf_engine_clear_errors(struct ecmxf_engine *e, u8 control_bits)
{
	e->control_pending |= control_bits;
}

/**
 * ecmxf_engine_clear_ints() - clear interrupt flags on the chip
 * @e: engine
 * @int_clear: %ECMXF_INT_* bits
 * @gpio_clear_lo: GPIO 0-7 interrupt flags to clear
 * @gpio_clear_hi: GPIO 8-15 interrupt flags to clear
 *
 * The bits go out in the next new packet.
 */
void ecmxf_engine_clear_ints(struct ecmxf_engine *e, u32 int_clear,
			     u8 gpio_clear_lo, u8 gpio_clear_hi)
{
	e->int_clear_pending |= int_clear;
	e->gpio_int_clear_pending[0] |= gpio_clear_lo;
	e->gpio_int_clear_pending[1] |= gpio_clear_hi;
}

/* Move the pending clears into a header that is sent for the first time. */
static void ecmxf_take_pending(struct ecmxf_engine *e,
			       struct ecmxf_cmd_hdr *h)
{
	h->control |= e->control_pending;
	h->int_clear |= e->int_clear_pending;
	h->gpio_int_clear[0] |= e->gpio_int_clear_pending[0];
	h->gpio_int_clear[1] |= e->gpio_int_clear_pending[1];
	e->control_pending = 0;
	e->int_clear_pending = 0;
	e->gpio_int_clear_pending[0] = 0;
	e->gpio_int_clear_pending[1] = 0;
}

static u8 ecmxf_fresh_index(struct ecmxf_engine *e)
{
	u8 idx = e->next_index;

	if (e->last_valid && idx == e->last_index)
		idx++;
	e->next_index = (u8)(idx + 1);
	return idx;
}

/* After a chip reset the chip is back in its power-on format. */
static void ecmxf_power_on_format(struct ecmxf_engine *e, u64 now_ns)
{
	e->data_size = ECMXF_DATA_DEFAULT;
	e->prev_check = e->check;
	e->check = ECMXF_CHECK_FIXED;
	e->switch_age = 0;
	e->not_before_ns = now_ns + ECMXF_RECONFIG_HOLDOFF_NS;
}

/*
 * Firmware variants (Documentation/protocol-core.rst, "Firmware
 * variants"): which bytes the chip's CRC covers, found from its answers,
 * and a CRC_TYPE_SET the chip did not take.
 */

/* The codec's check argument: @check with the coverage found. */
static enum ecmxf_check ecmxf_with_cover(const struct ecmxf_engine *e,
					 unsigned int check)
{
	if (check != ECMXF_CHECK_FIXED && e->cover == ECMXF_COVER_VALID)
		check |= ECMXF_CHECK_COVER_VALID;
	return (enum ecmxf_check)check;
}

/* A CRC is in force and no answer told the two coverages apart yet. */
static bool ecmxf_cover_unknown(const struct ecmxf_engine *e)
{
	return e->check != ECMXF_CHECK_FIXED &&
	       e->cover == ECMXF_COVER_UNKNOWN;
}

/*
 * While the coverage is unknown a new command waits and INFO_UPDATE
 * probes go out instead (at most ECMXF_COVER_MAX_PROBES; then commands go
 * out with the manual's coverage).
 */
static bool ecmxf_cover_probe(const struct ecmxf_engine *e)
{
	return ecmxf_cover_unknown(e) &&
	       e->cover_probes < ECMXF_COVER_MAX_PROBES;
}

/*
 * Data length field of an INFO_UPDATE the engine sends: while the
 * coverage is unknown the whole data section, so that both rules cover
 * the same bytes and any chip takes the packet; 0 otherwise.
 */
static u16 ecmxf_probe_len(struct ecmxf_engine *e)
{
	if (!ecmxf_cover_unknown(e))
		return 0;
	if (e->cover_probes < 255)
		e->cover_probes++;
	return e->data_size;
}

/*
 * CRC_TYPE_SET goes out in the check type in force; after a send the chip
 * did not take (ecmxf_chip_kept_check()) the next one carries the fixed
 * word, as NEXTW's example host code sends it, the one after that the
 * type in force again, and so on.  Its re-sends, which the chip runs as
 * INFO_UPDATE, are in the new type: while that type's coverage is unknown
 * they carry the whole data section as length (see ecmxf_probe_len()).
 */
static enum ecmxf_check ecmxf_crcset_format(struct ecmxf_engine *e,
					    struct ecmxf_cmd_hdr *h,
					    enum ecmxf_check check, bool first)
{
	if (!first) {
		if (ecmxf_cover_unknown(e))
			h->len = e->data_size;
		return check;
	}
	e->cover_probes = 0;
	e->switch_age = 0;
	return (e->crcset_tries & 1) ? ECMXF_CHECK_FIXED : check;
}

static bool ecmxf_sent(const struct ecmxf_xfer *x)
{
	return x && x->state == ECMXF_XS_SENT;
}

/* @x, in one of the two command slots, has the slots to itself. */
static bool ecmxf_alone(const struct ecmxf_engine *e,
			const struct ecmxf_xfer *x)
{
	return x == e->cur ? !e->nxt : !e->cur;
}

static unsigned int ecmxf_answer_lost(struct ecmxf_engine *e,
				      struct ecmxf_xfer *x,
				      const struct ecmxf_rsp_hdr *h,
				      u8 new_err, u64 now_ns);

/*
 * A result fetch polling its running async command goes out anew, with a
 * fresh index, in every exchange rather than being repeated to collect
 * its answer: the answer to its previous send comes back in the same
 * exchange (ecmxf_match()), so the chip is polled once per exchange, not
 * once per two.  Only an idempotent fetch (a *_GET that runs again
 * harmlessly) alone in the slots, with pipelining on.  The answer to the
 * send that goes out after the one showing the end is never read: the
 * chip answers it, and the next packet repeats it as INFO_UPDATE or
 * overwrites it.
 */
static bool ecmxf_fetch_ahead(const struct ecmxf_engine *e,
			      const struct ecmxf_xfer *x)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(x->hdr.code);

	return e->pipeline && x->owner && x->owner == e->async &&
	       x->owner->state == ECMXF_XS_RUNNING && ecmxf_alone(e, x) &&
	       ci && (ci->flags & ECMXF_CMDF_IDEMPOTENT);
}

/*
 * What the next packet carries: a first send (*first set), a re-send of
 * the newest command sent, or NULL for an INFO_UPDATE.  Only the packet
 * sent last may be repeated: the chip runs a repeat of the previous
 * packet as INFO_UPDATE, but anything older would run again.  A command
 * whose answer is still due although a younger one went out after it and
 * left unanswered (cancelled, timed out) can no longer be polled: its
 * answer counts as lost.
 */
static struct ecmxf_xfer *ecmxf_pick(struct ecmxf_engine *e, bool *first,
				     u64 now_ns)
{
	struct ecmxf_xfer *newest;

	for (;;) {
		/* no first send while the CRC coverage is being found */
		bool hold = ecmxf_cover_probe(e);

		newest = NULL;
		if (ecmxf_sent(e->cur))
			newest = e->cur;
		if (ecmxf_sent(e->nxt) &&
		    (!newest || e->nxt->sent_seq > newest->sent_seq))
			newest = e->nxt;
		*first = true;
		/* held with nothing in flight: ecmxf_engine_next() probes */
		if (e->cur && e->cur->state == ECMXF_XS_QUEUED &&
		    (!hold || !newest))
			return e->cur;
		if (e->nxt && e->nxt->state == ECMXF_XS_QUEUED &&
		    e->pipeline && !hold)
			return e->nxt;
		if (newest && newest->last_seq == e->seq && !hold &&
		    ecmxf_fetch_ahead(e, newest))
			return newest;	/* sent ahead: a first send again */
		*first = false;
		if (!newest || newest->last_seq == e->seq)
			return newest;
		if (newest->async) {
			/* accepted or refused: nothing tells which any more */
			e->stats.lost_answers++;
			newest->fault = e->last_fault;
			ecmxf_finish_slot(e, newest, -EPROTO);
			continue;
		}
		ecmxf_answer_lost(e, newest, &e->last, 0, now_ns);
	}
}

/**
 * ecmxf_engine_next() - the packet for the next exchange
 * @e: engine
 * @now_ns: current time
 * @pkt: output buffer
 * @pkt_len: must equal ecmxf_engine_pkt_size()
 *
 * Always produces a packet: a command's first send (the second command
 * rides in the exchange that fetches the first one's answer), a re-send
 * of the newest command to poll for its answer, or an INFO_UPDATE that
 * refreshes the header and polls a running async command.  A command
 * that can no longer be polled (see ecmxf_pick()) is finished here with
 * -EPROTO unless it is safe to send again: owners look at the status of
 * their commands after every exchange, not only at the events.
 *
 * Return: 0; -EINVAL for a wrong @pkt_len; -EAGAIN before
 * ecmxf_engine_not_before().
 */
int ecmxf_engine_next(struct ecmxf_engine *e, u64 now_ns,
		      u8 *pkt, size_t pkt_len)
{
	struct ecmxf_cmd_hdr h;
	struct ecmxf_xfer *x = NULL, *polled = NULL;
	enum ecmxf_check check = ecmxf_with_cover(e, e->check);
	const void *data = NULL;
	size_t data_len = 0;
	bool first = false;
	int ret;

	if (!pkt || pkt_len != ecmxf_engine_pkt_size(e))
		return -EINVAL;
	if (now_ns < e->not_before_ns)
		return -EAGAIN;

	if (e->last_valid)
		x = ecmxf_pick(e, &first, now_ns);
	/* a new command waits for the CRC coverage to be found */
	if (x && first && ecmxf_cover_probe(e))
		x = NULL;
	/*
	 * WARM_RESET is never re-sent: a chip that has just restarted
	 * remembers no previous packet and would run it again.  It is polled
	 * with INFO_UPDATE until the NOP, and stays pollable so.
	 */
	if (x && !first && x->hdr.code == ECMXF_CMD_WARM_RESET) {
		polled = x;
		x = NULL;
	}

	if (!x) {
		/* sync packet, INFO_UPDATE poll / probe / header refresh */
		memset(&h, 0, sizeof(h));
		h.code = ECMXF_CMD_INFO_UPDATE_OP;
		h.index = e->last_valid ? e->last_index : ecmxf_fresh_index(e);
		h.len = ecmxf_probe_len(e);
		ecmxf_take_pending(e, &h);
	} else {
		h = x->hdr;
		data = x->tx_data;
		data_len = x->tx_len;
		if (first) {
			/* a fetch already sent goes ahead (ecmxf_pick()) */
			x->ahead = x->state == ECMXF_XS_SENT;
			x->prev_index = x->hdr.index;
			h.index = ecmxf_fresh_index(e);
			x->hdr.index = h.index;
			ecmxf_take_pending(e, &h);
		} else {
			/*
			 * A re-send: same (index, code), so the chip runs it
			 * as INFO_UPDATE.  One-shot bits are not repeated:
			 * a second interrupt clear could swallow a new event.
			 */
			h.control = 0;
			h.int_clear = 0;
			h.gpio_int_clear[0] = 0;
			h.gpio_int_clear[1] = 0;
		}
		if (h.code == ECMXF_CMD_SPI_RECONFIG_OP && first)
			check = ECMXF_CHECK_FIXED;	/* as the manual asks */
		else if (h.code == ECMXF_CMD_CRC_TYPE_SET)
			check = ecmxf_crcset_format(e, &h, check, first);
	}

	ret = ecmxf_encode_cmd(pkt, pkt_len, check, &h, data, data_len);
	if (ret)
		return ret;

	e->seq++;
	if (polled)
		polled->last_seq = e->seq;
	if (x) {
		x->last_seq = e->seq;
		if (first) {
			x->sent_seq = e->seq;
			x->state = ECMXF_XS_SENT;
			if (ecmxf_sent(x == e->cur ? e->nxt : e->cur))
				e->stats.pipelined++;
		}
	}
	if (x && first) {
		switch (h.code) {
		case ECMXF_CMD_SPI_RECONFIG_OP:
			/* the next exchange is at the new size, 100 ms on */
			e->data_size = h.len;
			e->not_before_ns = now_ns + ECMXF_RECONFIG_HOLDOFF_NS;
			break;
		case ECMXF_CMD_CRC_TYPE_SET:
			e->prev_check = e->check;
			e->check = h.param;
			break;
		case ECMXF_CMD_WARM_RESET:
			ecmxf_power_on_format(e, now_ns);
			break;
		default:
			break;
		}
	}
	e->last_index = h.index;
	e->last_code = h.code;
	e->last_valid = true;
	return 0;
}

/* Fail whatever waits, after the retry bound ran out. */
static unsigned int ecmxf_exhausted(struct ecmxf_engine *e)
{
	int err = ecmxf_fault_errno(e->last_fault);
	unsigned int ev = 0;

	while (e->cur) {
		e->cur->fault = e->last_fault;
		ev |= ecmxf_finish_slot(e, e->cur, err);
		e->stats.exhausted++;
	}
	if (e->async) {
		e->async->fault = e->last_fault;
		ev |= ecmxf_finish_async(e, err);
		e->stats.exhausted++;
	}
	e->bad_in_row = 0;
	return ev;
}

/* An async command ended (busy clear): its outcome is the error bit. */
static int ecmxf_async_outcome(struct ecmxf_engine *e, struct ecmxf_xfer *x,
			       const struct ecmxf_rsp_hdr *h)
{
	if (!(h->err_status & ECMXF_ERR_ASYNC))
		return 0;
	e->stats.async_errors++;
	if (!(x->flags & ECMXF_XF_NO_AUTO_CLEAR))
		e->control_pending |= ECMXF_CTL_CLR_ASYNC_ERR;
	return -EREMOTEIO;
}

/* The answer to an async command @x in a slot arrived (or was lost). */
static unsigned int ecmxf_async_answered(struct ecmxf_engine *e,
					 struct ecmxf_xfer *x,
					 const struct ecmxf_rsp_hdr *h,
					 u8 new_err, u64 now_ns)
{
	unsigned int ev;

	if (new_err & ECMXF_ERR_CMD) {
		/* refused: another async command is running on the chip */
		e->stats.busy_rejects++;
		if (!(x->flags & ECMXF_XF_NO_AUTO_CLEAR))
			e->control_pending |= ECMXF_CTL_CLR_CMD_ERR;
		return ecmxf_finish_slot(e, x, -EBUSY);
	}
	if (h->ecm_status & ECMXF_STS_BUSY) {
		ecmxf_slot_del(e, x);
		e->async = x;
		x->state = ECMXF_XS_RUNNING;
		/* with pipelining, the fetch is the poll */
		if (e->pipeline)
			ecmxf_queue_fetch(e, x, now_ns);
		return 0;
	}
	ev = ecmxf_finish_slot(e, x, ecmxf_async_outcome(e, x, h));
	if (!x->status)
		ecmxf_queue_fetch(e, x, now_ns);
	return ev;
}

/*
 * The answer of @x is gone: overwritten on the chip or lost on the wire.
 * An idempotent command goes again; anything else may have run, so it
 * fails rather than run twice.
 */
static unsigned int ecmxf_answer_lost(struct ecmxf_engine *e,
				      struct ecmxf_xfer *x,
				      const struct ecmxf_rsp_hdr *h,
				      u8 new_err, u64 now_ns)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(x->hdr.code);

	e->stats.lost_answers++;
	x->rsp = *h;
	if (x->async)
		return ecmxf_async_answered(e, x, h, new_err, now_ns);
	if (x->owner || (ci && (ci->flags & ECMXF_CMDF_IDEMPOTENT))) {
		e->stats.retries++;
		if (ecmxf_sent(x == e->cur ? e->nxt : e->cur))
			e->stats.reordered++;	/* it goes after the younger */
		x->state = ECMXF_XS_QUEUED;	/* again, with a fresh index */
		return 0;
	}
	x->fault = e->last_fault;
	return ecmxf_finish_slot(e, x, -EPROTO);
}

/* @x's own answer arrived: copy it and decide. */
static unsigned int ecmxf_answered(struct ecmxf_engine *e,
				   struct ecmxf_xfer *x,
				   const struct ecmxf_rsp_hdr *h,
				   const u8 *data, u8 new_err, u64 now_ns)
{
	u16 n = h->len;			/* <= data section: decode checked it */

	if (x->owner && (h->ecm_status & ECMXF_STS_BUSY)) {
		/*
		 * a fetch that ran while the chip was busy: poll again, unless
		 * this answers the send before the one already out ahead
		 */
		e->stats.fetch_polls++;
		if (!x->ahead || h->index != x->prev_index)
			x->state = ECMXF_XS_QUEUED;
		return 0;
	}
	x->rsp = *h;
	if (x->rx_buf) {
		if (n > x->rx_size)
			n = x->rx_size;
		memcpy(x->rx_buf, data, n);
		x->rx_len = n;
	}
	if (x->async)
		return ecmxf_async_answered(e, x, h, new_err, now_ns);
	if (x->rx_buf && h->len > x->rx_size)
		return ecmxf_finish_slot(e, x, -EMSGSIZE);
	return ecmxf_finish_slot(e, x, 0);
}

/* Match a valid response to the commands waiting for their answer. */
static unsigned int ecmxf_match(struct ecmxf_engine *e,
				const struct ecmxf_rsp_hdr *h,
				const u8 *data, u8 new_err, u64 now_ns)
{
	struct ecmxf_xfer *x = NULL, *other;
	unsigned int ev = 0;

	if (ecmxf_sent(e->cur) && h->index == e->cur->hdr.index)
		x = e->cur;
	else if (ecmxf_sent(e->nxt) && h->index == e->nxt->hdr.index)
		x = e->nxt;
	else if (ecmxf_sent(e->cur) && e->cur->ahead &&
		 h->index == e->cur->prev_index)
		x = e->cur;	/* a fetch sent ahead: its previous send */
	else if (ecmxf_sent(e->nxt) && e->nxt->ahead &&
		 h->index == e->nxt->prev_index)
		x = e->nxt;

	if (!x) {
		/*
		 * Not answered yet (the chip is late, or rejected a packet):
		 * the newest command is re-sent with its (index, code), which
		 * the chip runs as INFO_UPDATE if it has it and as the command
		 * if it has not.
		 */
		if (ecmxf_sent(e->cur) || ecmxf_sent(e->nxt))
			e->stats.polls++;
		return 0;
	}

	/* an older command still waiting lost its answer before this one */
	other = x == e->cur ? e->nxt : e->cur;
	if (ecmxf_sent(other) && other->sent_seq < x->sent_seq)
		ev |= ecmxf_answer_lost(e, other, h, new_err, now_ns);

	if (h->code != x->hdr.code)
		/*
		 * Our index with another code: the chip answered a re-send
		 * as INFO_UPDATE, so the real answer was lost (on the wire
		 * or overwritten after a rejected packet).  It did run.
		 */
		return ev | ecmxf_answer_lost(e, x, h, new_err, now_ns);
	return ev | ecmxf_answered(e, x, h, data, new_err, now_ns);
}

static unsigned int ecmxf_chip_reset(struct ecmxf_engine *e)
{
	struct ecmxf_xfer *s[2] = { e->cur, e->nxt };
	unsigned int ev = ECMXF_EV_CHIP_RESET;
	unsigned int i;

	e->stats.chip_resets++;
	e->seen_valid = false;
	e->err_seen = 0;
	for (i = 0; i < 2; i++)
		if (ecmxf_sent(s[i]))
			ev |= ecmxf_finish_slot(e, s[i], s[i]->hdr.code ==
						ECMXF_CMD_WARM_RESET ?
						0 : -ECONNRESET);
	if (e->async)
		ev |= ecmxf_finish_async(e, e->async->hdr.code ==
					 ECMXF_CMD_WARM_RESET ? 0 : -ECONNRESET);
	/*
	 * The NOP was readable in the format in force, so the chip speaks
	 * it: the format is left alone (WARM_RESET switched it when sent).
	 */
	return ev;
}

/* Decode under @check with the coverage found, or find it. */
static enum ecmxf_fault ecmxf_decode_cover(struct ecmxf_engine *e,
					   unsigned int check,
					   const u8 *pkt, size_t pkt_len,
					   struct ecmxf_rsp_hdr *h,
					   const u8 **data)
{
	enum ecmxf_fault frame, valid;

	if (check == ECMXF_CHECK_FIXED || e->cover != ECMXF_COVER_UNKNOWN)
		return ecmxf_decode_rsp(pkt, pkt_len, ecmxf_with_cover(e, check),
					h, data);
	frame = ecmxf_decode_rsp(pkt, pkt_len, (enum ecmxf_check)check,
				 h, data);
	if (frame != ECMXF_FAULT_NONE && frame != ECMXF_FAULT_CHECK)
		return frame;
	valid = ecmxf_decode_rsp(pkt, pkt_len, (enum ecmxf_check)
				 (check | ECMXF_CHECK_COVER_VALID), h, data);
	/* both verify when the rules cover the same bytes: decide later */
	if (frame == ECMXF_FAULT_NONE && valid != ECMXF_FAULT_NONE)
		e->cover = ECMXF_COVER_FRAME;
	else if (frame != ECMXF_FAULT_NONE && valid == ECMXF_FAULT_NONE)
		e->cover = ECMXF_COVER_VALID;
	return frame == ECMXF_FAULT_NONE ? frame : valid;
}

/*
 * A response in the previous check type.  The first one after the switch
 * answers the packet before it, the second one may be CRC_TYPE_SET's own
 * answer: both are old by right.  Any other means the chip did not switch
 * (it dropped the command, or refused the type): speak its type again; an
 * unanswered CRC_TYPE_SET goes out anew with a fresh index
 * (ecmxf_crcset_format() picks its check word).
 */
static void ecmxf_chip_kept_check(struct ecmxf_engine *e,
				  const struct ecmxf_rsp_hdr *h)
{
	struct ecmxf_xfer *x = e->cur;

	if (e->switch_age < 2 || h->code == ECMXF_CMD_CRC_TYPE_SET)
		return;
	e->check = e->prev_check;
	if (ecmxf_sent(x) && x->hdr.code == ECMXF_CMD_CRC_TYPE_SET &&
	    h->index != x->hdr.index) {
		x->state = ECMXF_XS_QUEUED;
		/* not the index the chip saw last: that would be a repeat */
		if (e->next_index == h->index)
			e->next_index++;
		if (e->crcset_tries < 255)
			e->crcset_tries++;
		e->stats.retries++;
	}
}

/*
 * Validate a response: in the check type in force or, until a response
 * proves the switch, the previous one (answers prepared before a
 * CRC_TYPE_SET took effect, or a chip that did not switch).
 */
static enum ecmxf_fault ecmxf_decode_checked(struct ecmxf_engine *e,
					     const u8 *pkt, size_t pkt_len,
					     struct ecmxf_rsp_hdr *h,
					     const u8 **data)
{
	enum ecmxf_fault fault;
	bool kept = false;

	if (e->switch_age < 255)
		e->switch_age++;
	fault = ecmxf_decode_cover(e, e->check, pkt, pkt_len, h, data);
	if (fault == ECMXF_FAULT_NONE) {
		/* the chip speaks the new check type: forget the old one */
		e->prev_check = e->check;
	} else if (fault == ECMXF_FAULT_CHECK && e->prev_check != e->check) {
		fault = ecmxf_decode_cover(e, e->prev_check, pkt, pkt_len,
					   h, data);
		kept = fault == ECMXF_FAULT_NONE;
	}
	if (fault != ECMXF_FAULT_NONE)
		return fault;
	/* CRC_TYPE_SET answered, or none waits: its fallback starts over */
	if (h->code == ECMXF_CMD_CRC_TYPE_SET || !e->cur ||
	    e->cur->hdr.code != ECMXF_CMD_CRC_TYPE_SET)
		e->crcset_tries = 0;
	if (kept)
		ecmxf_chip_kept_check(e, h);
	return fault;
}

/**
 * ecmxf_engine_input() - feed the packet received in an exchange
 * @e: engine
 * @now_ns: current time
 * @pkt: received bytes
 * @pkt_len: their number: the size the exchange had
 *
 * Validates the packet, updates the header snapshot, matches it to the
 * commands waiting for it, tracks the running async command and applies
 * the deadlines.
 *
 * Return: %ECMXF_EV_* bits.
 */
unsigned int ecmxf_engine_input(struct ecmxf_engine *e, u64 now_ns,
				const u8 *pkt, size_t pkt_len)
{
	struct ecmxf_rsp_hdr h;
	enum ecmxf_fault fault;
	const u8 *data = NULL;
	unsigned int ev = 0;
	u8 new_err;

	e->stats.exchanges++;
	fault = ecmxf_decode_checked(e, pkt, pkt_len, &h, &data);
	if (fault != ECMXF_FAULT_NONE) {
		e->stats.faults[fault]++;
		e->last_fault = fault;
		ev |= ECMXF_EV_BAD_PACKET;
		if (ecmxf_sent(e->cur) || ecmxf_sent(e->nxt) || e->async)
			e->stats.retries++;
		if (++e->bad_in_row > e->max_retries)
			ev |= ecmxf_exhausted(e);
		return ev | ecmxf_engine_poll_time(e, now_ns);
	}

	e->bad_in_row = 0;
	e->last = h;
	e->have_last = true;
	ev |= ECMXF_EV_HEADER;

	new_err = (u8)(h.err_status & ECMXF_ERR_FAULT_MASK & ~e->err_seen);
	e->err_seen = h.err_status & ECMXF_ERR_FAULT_MASK;
	if (new_err)
		ev |= ECMXF_EV_ERR_STATUS;

	if (h.ecm_status & ECMXF_STS_NOP) {
		if (e->seen_valid)
			ev |= ecmxf_chip_reset(e);
		return ev | ecmxf_engine_poll_time(e, now_ns);
	}
	e->seen_valid = true;

	if (e->async) {
		/* running async command: done when busy clears */
		if (!(h.ecm_status & ECMXF_STS_BUSY)) {
			struct ecmxf_xfer *a = e->async;

			a->rsp = h;
			ev |= ecmxf_finish_async(e, ecmxf_async_outcome(e, a,
									&h));
			/* without pipelining the fetch follows the end */
			if (!a->status)
				ecmxf_queue_fetch(e, a, now_ns);
		}
	}
	ev |= ecmxf_match(e, &h, data, new_err, now_ns);

	return ev | ecmxf_engine_poll_time(e, now_ns);
}

/**
 * ecmxf_engine_poll_time() - apply deadlines
 * @e: engine
 * @now_ns: current time
 *
 * Called by ecmxf_engine_input(); call it also when a wait for the
 * chip (INT0) ends without an exchange.
 *
 * Return: %ECMXF_EV_CMD_DONE and/or %ECMXF_EV_ASYNC_DONE for commands
 * that timed out (-ETIMEDOUT).
 */
unsigned int ecmxf_engine_poll_time(struct ecmxf_engine *e, u64 now_ns)
{
	struct ecmxf_xfer *s[2] = { e->cur, e->nxt };
	unsigned int ev = 0;
	unsigned int i;

	for (i = 0; i < 2; i++) {
		if (!s[i] || now_ns < s[i]->deadline_ns)
			continue;
		e->stats.timeouts++;
		s[i]->fault = e->last_fault;
		ev |= ecmxf_finish_slot(e, s[i], -ETIMEDOUT);
	}
	if (e->async && now_ns >= e->async->deadline_ns) {
		e->stats.timeouts++;
		ev |= ecmxf_finish_async(e, -ETIMEDOUT);
	}
	return ev;
}

/**
 * ecmxf_engine_deadline() - the earliest deadline of a waiting command
 * @e: engine
 *
 * Return: a time in ns, or U64_MAX when nothing waits.
 */
u64 ecmxf_engine_deadline(const struct ecmxf_engine *e)
{
	u64 d = ECMXF_U64_MAX;

	if (e->cur)
		d = e->cur->deadline_ns;
	if (e->nxt && e->nxt->deadline_ns < d)
		d = e->nxt->deadline_ns;
	if (e->async && e->async->deadline_ns < d)
		d = e->async->deadline_ns;
	return d;
}

/**
 * ecmxf_engine_not_before() - earliest time for the next exchange
 * @e: engine
 *
 * Non-zero for 100 ms after SPI_RECONFIG_OP and WARM_RESET.
 *
 * Return: a time in ns (0 when there is no hold-off).
 */
u64 ecmxf_engine_not_before(const struct ecmxf_engine *e)
{
	return e->not_before_ns;
}

/**
 * ecmxf_engine_idle() - nothing submitted is waiting
 * @e: engine
 *
 * Return: true when no command waits for an answer or a completion.
 */
bool ecmxf_engine_idle(const struct ecmxf_engine *e)
{
	return !e->cur && !e->nxt && !e->async;
}

/**
 * ecmxf_engine_running() - is @x an accepted async command the chip runs
 * @e: engine
 * @x: a command submitted to @e
 *
 * Return: true from the answer that accepted @x until its completion; the
 * engine's command slot is free meanwhile.
 */
bool ecmxf_engine_running(const struct ecmxf_engine *e,
			  const struct ecmxf_xfer *x)
{
	return x && e->async == x;
}

/**
 * ecmxf_engine_sent() - has @x gone out and waits for its answer
 * @e: engine
 * @x: a command submitted to @e
 *
 * Return: true from @x's first packet until its answer (or until it is
 * queued to go again); the next exchange on the link fetches the answer.
 */
bool ecmxf_engine_sent(const struct ecmxf_engine *e,
		       const struct ecmxf_xfer *x)
{
	return x && (x == e->cur || x == e->nxt) && ecmxf_sent(x);
}

/**
 * ecmxf_engine_waits_only() - is @x, sent, all the engine has in flight
 * @e: engine
 * @x: a command submitted to @e
 *
 * An owner loop that may leave @x's answer to the next exchange it makes
 * for another reason (the kernel's PDO pump: the working counter read's
 * answer to the next cycle's FIFO command) need not exchange now.
 *
 * Return: true when @x has gone out and waits for its answer, and no
 * other command is in the engine (nothing to send, no async command).
 */
bool ecmxf_engine_waits_only(const struct ecmxf_engine *e,
			     const struct ecmxf_xfer *x)
{
	return ecmxf_engine_sent(e, x) && !e->async && ecmxf_alone(e, x);
}

/**
 * ecmxf_engine_last_header() - the latest valid response header
 * @e: engine
 *
 * Return: the header, or NULL before the first valid response.
 */
const struct ecmxf_rsp_hdr *
ecmxf_engine_last_header(const struct ecmxf_engine *e)
{
	return e->have_last ? &e->last : NULL;
}

/**
 * ecmxf_engine_get_stats() - the engine's counters
 * @e: engine
 *
 * Return: the counters, valid as long as @e.
 */
const struct ecmxf_engine_stats *
ecmxf_engine_get_stats(const struct ecmxf_engine *e)
{
	return &e->stats;
}

/**
 * ecmxf_engine_data_size() - data section size of the next exchange
 * @e: engine
 *
 * Return: 32..1408.
 */
unsigned int ecmxf_engine_data_size(const struct ecmxf_engine *e)
{
	return e->data_size;
}

/**
 * ecmxf_engine_retries() - bad packets tolerated in a row
 * @e: engine
 *
 * Return: the bound set by ecmxf_engine_set_retries() (default 8).
 */
unsigned int ecmxf_engine_retries(const struct ecmxf_engine *e)
{
	return e->max_retries;
}

/**
 * ecmxf_engine_check() - the check type of the next exchange
 * @e: engine
 *
 * Return: %ECMXF_CHECK_FIXED .. %ECMXF_CHECK_CRC32 (without the coverage
 * flag; see ecmxf_engine_cover()).
 */
enum ecmxf_check ecmxf_engine_check(const struct ecmxf_engine *e)
{
	return (enum ecmxf_check)e->check;
}

/**
 * ecmxf_engine_cover() - which bytes the chip's CRC covers
 * @e: engine
 *
 * Found from the first answer in a CRC type that verifies under one rule
 * only, and kept for the life of the engine (a firmware property).
 *
 * Return: %ECMXF_COVER_UNKNOWN until then, %ECMXF_COVER_FRAME (manual
 * ver. 050) or %ECMXF_COVER_VALID (NEXTW's example host code).
 */
enum ecmxf_cover ecmxf_engine_cover(const struct ecmxf_engine *e)
{
	return (enum ecmxf_cover)e->cover;
}
