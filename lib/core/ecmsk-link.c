// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmsk-link.c - the host's bookkeeping of ECM-SK exchanges
 *
 * The result of a command comes back in the next exchange (quick start
 * 2.1); SET_STATE, SDO_RD/SDO_WR and GO_HOME take several cycles and
 * their outcome is read later with GET_STATUS in the same slot.  The
 * board counts the commands it refused for a bad CRC in byte 1 of slot 0.
 * This file checks what the host sends, remembers what each slot is
 * waiting for and decides, response by response, when a long command is
 * done.  Documentation/ecm-sk.rst, "Exchanges".
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmsk-proto.h"

/**
 * ecmsk_link_init() - start tracking a board
 * @l: the link state
 * @slot_size: 12 or 16 (the board's CONFIG2)
 * @flags: %ECMSK_LINK_TX_CRC and/or %ECMSK_LINK_RX_CRC (the board's
 *	SET_EX setting in force)
 *
 * Return: 0, or -EINVAL for a bad slot size or unknown flags.
 */
int ecmsk_link_init(struct ecmsk_link *l, unsigned int slot_size, u32 flags)
{
	int ret;

	memset(l, 0, sizeof(*l));
	if (flags & ~(ECMSK_LINK_TX_CRC | ECMSK_LINK_RX_CRC))
		return -EINVAL;
	ret = ecmsk_geom_init(&l->g, slot_size);
	if (ret)
		return ret;
	l->flags = flags;
	return 0;
}

/**
 * ecmsk_link_reset() - forget every exchange (after SW_RESET or a power
 *	cycle of the board); the geometry and flags stay
 * @l: the link state
 */
void ecmsk_link_reset(struct ecmsk_link *l)
{
	struct ecmsk_geom g = l->g;
	u32 flags = l->flags;

	memset(l, 0, sizeof(*l));
	l->g = g;
	l->flags = flags;
}

static bool ecm_slot_cmd(u16 cmd)
{
	switch (cmd) {
	case ECMSK_CMD_GET_STATUS:
	case ECMSK_CMD_SET_STATE:
	case ECMSK_CMD_SET_AXIS:
	case ECMSK_CMD_SET_DC:
	case ECMSK_CMD_SET_EX:
	case ECMSK_CMD_SET_FIFO:
	case ECMSK_CMD_LIO_RD:
	case ECMSK_CMD_LIO_WR:
	case ECMSK_CMD_SW_RESET:
		return true;
	default:
		return false;
	}
}

static void pend(struct ecmsk_pending *p, u16 cmd, u8 slave, u32 target,
		 u64 seq, u64 now, u64 timeout_ns)
{
	p->active = true;
	p->cmd = cmd;
	p->slave = slave;
	p->target = target;
	p->seq = seq;
	p->started = false;
	p->deadline = timeout_ns ? now + timeout_ns : 0;
}

/**
 * ecmsk_link_prepare() - check a command frame and send it next
 * @l: the link state
 * @mosi: the frame the host filled with ecmsk_put_*(); its CRC byte is
 *	set here (0 unless %ECMSK_LINK_TX_CRC)
 * @now: the caller's clock (ns)
 * @timeout_ns: deadline for the long commands in this frame (0: none)
 *
 * Checks that each slot carries a command that belongs there, that a
 * SET_STATE names a state and that no second SDO or GO_HOME starts while
 * one is running, then registers the long commands as pending.  Must be
 * followed by ecmsk_link_complete() with the frame received in the same
 * transfer.
 *
 * Return: 0; -EINVAL for a command in the wrong slot, an unknown command
 * or a bad SET_STATE state; -EBUSY for an SDO or a GO_HOME while one is
 * pending.  On error nothing is registered and @mosi must not be sent.
 */
int ecmsk_link_prepare(struct ecmsk_link *l, u8 *mosi, u64 now,
		       u64 timeout_ns)
{
	const struct ecmsk_geom *g = &l->g;
	struct ecmsk_ecm_cmd ecm;
	struct ecmsk_sdo sdo;
	unsigned int s, home = 0;
	u64 seq = l->exchanges + 1;

	ecmsk_get_ecm_cmd(g, mosi, &ecm);
	if (!ecm_slot_cmd(ecm.cmd))
		return -EINVAL;
	if (ecm.cmd == ECMSK_CMD_SET_STATE && !ecmsk_state_valid(ecm.data1))
		return -EINVAL;
	for (s = 1; s <= g->max_slaves; s++) {
		u8 c = mosi[(size_t)s * g->slot_size];

		if (c != ECMSK_CMD_GET_STATUS && !ecmsk_cmd_is_slave(c))
			return -EINVAL;
		if (c == ECMSK_CMD_GO_HOME) {
			if (home || l->home.active)
				return -EBUSY;
			home = s;
		}
	}
	ecmsk_get_sdo(g, mosi, &sdo);
	if (sdo.cmd != ECMSK_CMD_GET_STATUS && sdo.cmd != ECMSK_CMD_SDO_RD &&
	    sdo.cmd != ECMSK_CMD_SDO_WR)
		return -EINVAL;
	if (sdo.cmd != ECMSK_CMD_GET_STATUS && l->sdo.active)
		return -EBUSY;

	memcpy(l->answering, l->sent, sizeof(l->sent));
	memcpy(l->answering_index, l->sent_index, sizeof(l->sent_index));
	for (s = 0; s < g->slots; s++) {
		l->sent[s] = mosi[(size_t)s * g->slot_size];
		l->sent_index[s] = s && s <= g->max_slaves ?
				   mosi[(size_t)s * g->slot_size + 1] : 0;
	}

	if (ecm.cmd == ECMSK_CMD_SW_RESET) {
		memset(&l->ecm, 0, sizeof(l->ecm));
		memset(&l->sdo, 0, sizeof(l->sdo));
		memset(&l->home, 0, sizeof(l->home));
	} else if (ecm.cmd == ECMSK_CMD_SET_STATE) {
		pend(&l->ecm, ecm.cmd, 0, ecm.data1, seq, now, timeout_ns);
	}
	if (sdo.cmd != ECMSK_CMD_GET_STATUS)
		pend(&l->sdo, sdo.cmd, sdo.slave,
		     (u32)sdo.index << 8 | sdo.subindex, seq, now, timeout_ns);
	if (home)
		pend(&l->home, ECMSK_CMD_GO_HOME, (u8)home, 0, seq, now,
		     timeout_ns);
	for (s = 1; s <= g->max_slaves; s++)
		if (l->sent[s] == ECMSK_CMD_ABORT_HOME)
			memset(&l->home, 0, sizeof(l->home));

	if (l->flags & ECMSK_LINK_TX_CRC)
		ecmsk_frame_seal(mosi, g->frame_size);
	else
		mosi[ECMSK_CRC_OFFSET] = 0;
	return 0;
}

/* the response of the current exchange answers the pending command */
static bool answers(const struct ecmsk_link *l, const struct ecmsk_pending *p)
{
	return p->active && l->exchanges >= p->seq + 1;
}

/* the current response answers exactly the exchange that sent @p */
static bool answers_first(const struct ecmsk_link *l,
			  const struct ecmsk_pending *p)
{
	return p->active && l->exchanges == p->seq + 1;
}

static bool expired(const struct ecmsk_pending *p, u64 now)
{
	return p->active && p->deadline && now >= p->deadline;
}

static void finish(struct ecmsk_pending *p, bool *done, int *err, int e)
{
	p->active = false;
	*done = true;
	*err = e;
}

static void check_timeouts(struct ecmsk_link *l, u64 now,
			   struct ecmsk_result *res)
{
	if (expired(&l->ecm, now))
		finish(&l->ecm, &res->state_done, &res->state_err, -ETIMEDOUT);
	if (expired(&l->sdo, now))
		finish(&l->sdo, &res->sdo_done, &res->sdo_err, -ETIMEDOUT);
	if (expired(&l->home, now))
		finish(&l->home, &res->home_done, &res->home_err, -ETIMEDOUT);
}

static void check_sdo(struct ecmsk_link *l, struct ecmsk_result *res)
{
	struct ecmsk_pending *p = &l->sdo;
	const struct ecmsk_sdo *r = &res->sdo;

	if (!answers(l, p))
		return;
	if (r->cmd != p->cmd || r->slave != p->slave) {
		if (answers_first(l, p))
			finish(p, &res->sdo_done, &res->sdo_err, -EACCES);
		return;
	}
	if (r->status == ECMSK_SDO_BUSY)
		return;
	if (((u32)r->index << 8 | r->subindex) != p->target)
		finish(p, &res->sdo_done, &res->sdo_err, -EPROTO);
	else if (r->status == ECMSK_SDO_DONE)
		finish(p, &res->sdo_done, &res->sdo_err, 0);
	else
		finish(p, &res->sdo_done, &res->sdo_err, -EIO);
}

static void check_home(struct ecmsk_link *l, const u8 *miso,
		       struct ecmsk_result *res)
{
	struct ecmsk_pending *p = &l->home;
	struct ecmsk_slave_rsp r;

	if (!answers(l, p) || ecmsk_get_slave(&l->g, miso, p->slave, &r))
		return;
	if (r.statusword & ECMSK_SW_HOMING_ERROR)
		finish(p, &res->home_done, &res->home_err, -EIO);
	else if ((r.statusword & ECMSK_SW_HOMED) != ECMSK_SW_HOMED)
		p->started = true;
	else if (p->started)
		finish(p, &res->home_done, &res->home_err, 0);
}

/**
 * ecmsk_link_complete() - take in the frame received by the exchange
 * @l: the link state
 * @miso: the response frame (@l->g.frame_size bytes)
 * @now: the caller's clock (ns)
 * @res: filled in: slot 0, the SDO slot, commands refused for a bad CRC,
 *	and the long commands that completed with this response
 *
 * The response answers the frame sent by the exchange before this one.
 * A SET_STATE is done when Current State equals the state requested; an
 * SDO when the SDO slot echoes its command, slave and object with a
 * status other than busy; a GO_HOME when its slave's statusword, having
 * shown homing in progress, has bits 10 and 12 both set (bit 13: error).
 * A rise of the board's CRC-error counter fails the long command of the
 * frame it answers with -EBADMSG.  Deadlines are checked even when the
 * response itself is bad.
 *
 * Return: 0, or -EBADMSG when response CRCs are checked and this one is
 * wrong (then only @res's timeouts are meaningful).
 */
int ecmsk_link_complete(struct ecmsk_link *l, const u8 *miso, u64 now,
			struct ecmsk_result *res)
{
	const struct ecmsk_geom *g = &l->g;

	memset(res, 0, sizeof(*res));
	l->exchanges++;
	if ((l->flags & ECMSK_LINK_RX_CRC) &&
	    !ecmsk_frame_crc_ok(miso, g->frame_size)) {
		l->rx_crc_bad++;
		check_timeouts(l, now, res);
		return -EBADMSG;
	}
	ecmsk_get_ecm(g, miso, &res->ecm);
	ecmsk_get_sdo(g, miso, &res->sdo);
	if (l->have_rsp)
		res->refused = (u8)(res->ecm.crc_errors - l->crc_errors);
	l->refused += res->refused;
	l->crc_errors = res->ecm.crc_errors;
	l->state = res->ecm.state;
	l->have_rsp = true;

	if (res->refused) {
		if (answers_first(l, &l->ecm))
			finish(&l->ecm, &res->state_done, &res->state_err,
			       -EBADMSG);
		if (answers_first(l, &l->sdo))
			finish(&l->sdo, &res->sdo_done, &res->sdo_err,
			       -EBADMSG);
		if (answers_first(l, &l->home))
			finish(&l->home, &res->home_done, &res->home_err,
			       -EBADMSG);
	}
	if (answers(l, &l->ecm) && res->ecm.state == l->ecm.target)
		finish(&l->ecm, &res->state_done, &res->state_err, 0);
	check_sdo(l, res);
	check_home(l, miso, res);
	check_timeouts(l, now, res);
	return 0;
}

/**
 * ecmsk_link_answered() - does a slot of the response answer the command
 *	sent in that slot by the exchange before?
 * @l: the link state, after ecmsk_link_complete() of this response
 * @slot: slot number (0: the ECM)
 * @miso: the response frame
 *
 * The ECM slot answers with its Cmd ID, or 0xBF in OP; a slave slot with
 * its Cmd ID and Command Index.  A command the board did not carry out
 * (not allowed in the state or for the slave type) is answered as
 * GET_STATUS (Documentation/ecm-sk.rst, "Refused commands").
 *
 * Return: true when it does.
 */
bool ecmsk_link_answered(const struct ecmsk_link *l, unsigned int slot,
			 const u8 *miso)
{
	const u8 *s;

	if (slot >= l->g.slots)
		return false;
	s = miso + (size_t)slot * l->g.slot_size;
	if (slot == 0)
		return s[0] == l->answering[0] ||
		       (s[2] == ECMSK_STATE_OP && s[0] == ECMSK_RSP_OP);
	if (slot == l->g.sdo_slot)
		return s[0] == l->answering[slot];
	return s[0] == l->answering[slot] &&
	       s[1] == l->answering_index[slot];
}
