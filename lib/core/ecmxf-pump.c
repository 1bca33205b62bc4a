// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-pump.c - the PDO pump's policy over the chip's FIFOs, sans I/O
 *
 * One exchange of process data is one ECAT_PDO_DATA_FIFO_OP (command 5):
 * its parameter is the number of RxPDO frames in the data section, data
 * byte 0 bit 0 pushes them into the RxFIFO, bit 1 pops TxPDO frames into
 * the answer, whose data length is a whole number of TxPDO frames.  The
 * RxFIFO refuses the newest frames when full (return value bit 0 clear),
 * the TxFIFO drops its oldest; the chip takes one RxPDO frame and makes
 * one TxPDO frame per bus cycle.  The header's FIFO counts lag by up to
 * two exchanges, so the pump fills the RxFIFO to at most its depth minus
 * two.
 *
 * A caller:
 *
 *	ecmxf_pump_init(&p, ...);			once, at setup
 *	if (ecmxf_pump_next(&p, level, avail, flags, &pl)) {
 *		drop pl.skip frames, copy pl.push frames
 *		len = ecmxf_pump_fifo_cmd(&p, &pl, rearm, &hdr);
 *		run the command
 *		err = ecmxf_pump_answer(&p, &pl, &rsp, rx_len, &res);
 *		free res.taken frames, store res.popped frames
 *	}
 *
 * The kernel's pump gives the level as ecmxf_pump_level() computes it
 * from the last header; the library's FIFO path estimates it from the
 * time since its last write.  The working counter (ECAT_PDO_WC_GET 3)
 * has its own pair: ecmxf_pump_wkc_cmd() and ecmxf_pump_wkc_answer().
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-pump.h"

/**
 * ecmxf_pump_max_fill() - the highest RxFIFO fill level for a depth
 * @rx_depth: the RxFIFO depth (FIFO_GET_RX_CNT)
 *
 * Return: @rx_depth minus %ECMXF_PUMP_RX_MARGIN, at least 1.
 */
u32 ecmxf_pump_max_fill(u32 rx_depth)
{
	return rx_depth > ECMXF_PUMP_RX_MARGIN ?
	       rx_depth - ECMXF_PUMP_RX_MARGIN : 1;
}

/**
 * ecmxf_pump_check() - can the pump run with these frames and FIFOs?
 * @out_size: RxPDO frame bytes (0: no outputs)
 * @in_size: TxPDO frame bytes (0: no inputs)
 * @data_size: the data section size in force
 * @rx_depth: the RxFIFO depth
 * @rx_fill: the wanted fill level, 0 for ecmxf_pump_max_fill()
 *
 * Return: 0, -EINVAL when @rx_fill is above ecmxf_pump_max_fill(),
 * -ENODATA without frames either way, -EMSGSIZE when a frame does not
 * fit the data section (checked in this order).
 */
int ecmxf_pump_check(u32 out_size, u32 in_size, u32 data_size,
		     u32 rx_depth, u32 rx_fill)
{
	if (rx_fill > ecmxf_pump_max_fill(rx_depth))
		return -EINVAL;
	if (!out_size && !in_size)
		return -ENODATA;
	if (out_size > data_size || in_size > data_size)
		return -EMSGSIZE;
	return 0;
}

/**
 * ecmxf_pump_init() - set the pump up for a claim (or a Cyclic start)
 * @p: the pump
 * @out_size: RxPDO frame bytes (0: no outputs)
 * @in_size: TxPDO frame bytes (0: no inputs)
 * @data_size: the data section size in force (the caller may update
 *	&ecmxf_pump.data_size when it changes)
 * @rx_depth: the RxFIFO depth
 * @rx_fill: the fill level, 0 for ecmxf_pump_max_fill()
 * @tx_depth: the TxFIFO depth, 0 when unknown (no overrun detection)
 *
 * No checks: ecmxf_pump_check() first.
 */
void ecmxf_pump_init(struct ecmxf_pump *p, u32 out_size, u32 in_size,
		     u32 data_size, u32 rx_depth, u32 rx_fill, u32 tx_depth)
{
	memset(p, 0, sizeof(*p));
	p->out_size = out_size;
	p->in_size = in_size;
	p->data_size = data_size;
	p->rx_fill = rx_fill ? rx_fill : ecmxf_pump_max_fill(rx_depth);
	p->tx_depth = tx_depth;
}

/**
 * ecmxf_pump_per_write() - RxPDO frames one command can push
 * @p: the pump
 *
 * Return: what fits the data section, at most %ECMXF_PUMP_MAX_PUSH; 0
 * without outputs.
 */
u32 ecmxf_pump_per_write(const struct ecmxf_pump *p)
{
	u32 n;

	if (!p->out_size)
		return 0;
	n = p->data_size / p->out_size;
	return n < ECMXF_PUMP_MAX_PUSH ? n : ECMXF_PUMP_MAX_PUSH;
}

/**
 * ecmxf_pump_per_read() - TxPDO frames one answer can carry
 * @p: the pump
 *
 * Return: what fits the data section; 0 without inputs.
 */
u32 ecmxf_pump_per_read(const struct ecmxf_pump *p)
{
	return p->in_size ? p->data_size / p->in_size : 0;
}

/**
 * ecmxf_pump_level() - the RxFIFO level to plan with, from a header
 * @p: the pump
 * @h: the latest response header, or NULL before the first
 *
 * The header's count may not show the frames of the previous command
 * yet: they are added (a level too high costs a frame's delay, one too
 * low an overrun).
 *
 * Return: the frames taken to be in the RxFIFO.
 */
u32 ecmxf_pump_level(const struct ecmxf_pump *p,
		     const struct ecmxf_rsp_hdr *h)
{
	return (h ? h->rx_fifo_cnt : 0) + p->unconfirmed;
}

/**
 * ecmxf_pump_next() - plan the next FIFO command
 * @p: the pump
 * @level: frames taken to be in the RxFIFO (ecmxf_pump_level(), or the
 *	caller's estimate)
 * @avail: output frames ready, oldest first
 * @flags: %ECMXF_PUMP_F_READ to pop TxPDO frames, %ECMXF_PUMP_F_ONE to
 *	push a frame even when the RxFIFO is at its fill level (the chip
 *	refuses it if full, and the answer says so)
 * @pl: the plan
 *
 * The RxFIFO has room for the fill level minus @level frames; one command
 * pushes at most ecmxf_pump_per_write().  A caller that holds more frames
 * than that room plus the fill level has fallen behind: the oldest ones
 * beyond it are skipped (@pl->skip), so that the newest outputs reach the
 * bus within about twice the fill level.
 *
 * Return: true when the command has anything to do (frames to push, or
 * a read); false: send nothing (@pl->skip may still be set).
 */
bool ecmxf_pump_next(const struct ecmxf_pump *p, u32 level, u32 avail,
		     unsigned int flags, struct ecmxf_pump_plan *pl)
{
	u32 space = p->rx_fill > level ? p->rx_fill - level : 0;
	u32 per_write = ecmxf_pump_per_write(p);
	u32 k;

	memset(pl, 0, sizeof(*pl));
	if (!space && (flags & ECMXF_PUMP_F_ONE))
		space = 1;
	if ((u64)avail > (u64)space + p->rx_fill) {
		pl->skip = avail - space - p->rx_fill;
		avail -= pl->skip;
	}
	k = avail < space ? avail : space;
	pl->push = k < per_write ? k : per_write;
	pl->read = (flags & ECMXF_PUMP_F_READ) && p->in_size;
	return pl->push || pl->read;
}

/**
 * ecmxf_pump_fifo_cmd() - the header of a planned FIFO command
 * @p: the pump
 * @pl: the plan
 * @rearm: clear the FIFO threshold interrupt flags (INT1 is edge
 *	triggered: the flags that woke the caller must be re-armed)
 * @hdr: the command header; every field is set (the length field is 0:
 *	the caller sends the data length)
 *
 * The command also clears error status bits 5 and 7, which then belong
 * to this command alone.
 *
 * Return: the data bytes to send (@pl->push frames of
 * &ecmxf_pump.out_size bytes).
 */
u32 ecmxf_pump_fifo_cmd(const struct ecmxf_pump *p,
			const struct ecmxf_pump_plan *pl, bool rearm,
			struct ecmxf_cmd_hdr *hdr)
{
	memset(hdr, 0, sizeof(*hdr));
	hdr->code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
	hdr->param = (u8)pl->push;
	hdr->data[0] = (u8)((pl->push ? ECMXF_PUMP_OP_WRITE : 0) |
			    (pl->read ? ECMXF_PUMP_OP_READ : 0));
	hdr->control = ECMXF_CTL_CLR_CMD_ERR | ECMXF_CTL_CLR_FIFO_ERR;
	if (rearm)
		hdr->int_clear = ECMXF_INT_RXFIFO_LOW | ECMXF_INT_TXFIFO_HIGH;
	return pl->push * p->out_size;
}

/**
 * ecmxf_pump_answer() - what the answer to a FIFO command says
 * @p: the pump (its bookkeeping of the pushed frames is updated)
 * @pl: the plan the command was built from
 * @h: the answer's header
 * @rx_len: the answer's data bytes (TxPDO frames when @pl->read)
 * @res: filled in, also on an error (with what is known)
 *
 * Data in the answer to a command that asked for no read is ignored.
 *
 * Return: 0; -EREMOTEIO when the chip refused the command (error status
 * bit 7): nothing was taken, the frames may be pushed again; -EPROTO when
 * the read data is not a whole number of TxPDO frames, or more frames
 * than one answer can hold (the pushed frames are taken: @res->taken).
 */
int ecmxf_pump_answer(struct ecmxf_pump *p, const struct ecmxf_pump_plan *pl,
		      const struct ecmxf_rsp_hdr *h, u32 rx_len,
		      struct ecmxf_pump_result *res)
{
	u32 n;

	memset(res, 0, sizeof(*res));
	if (h->err_status & ECMXF_ERR_CMD)
		return -EREMOTEIO;
	res->taken = pl->push;
	if (pl->push) {
		p->pushed_any = true;
		if (!(h->ret & ECMXF_PUMP_RET_TAKEN))
			res->refused = pl->push;
	}
	p->unconfirmed = pl->push;
	if (pl->read && p->in_size) {
		if (rx_len % p->in_size)
			return -EPROTO;
		n = rx_len / p->in_size;
		if (n > ecmxf_pump_per_read(p))
			return -EPROTO;
		res->popped = n;
		/* popped plus left is what was queued; a full FIFO dropped */
		if (p->tx_depth && n + h->tx_fifo_cnt >= p->tx_depth)
			res->tx_overrun = true;
	}
	if (p->pushed_any && p->out_size && !h->rx_fifo_cnt &&
	    (h->ecm_status & ECMXF_STS_FIFO_EN))
		res->rx_underrun = true;
	return 0;
}

/**
 * ecmxf_pump_lost() - a FIFO command failed with no answer
 * @p: the pump
 * @pl: the plan the command was built from
 *
 * The command may have reached the chip: its frames are not sent again
 * (a second copy would reach the bus after newer frames), and the level
 * counts them as possibly in the RxFIFO.
 *
 * Return: the output frames lost (the caller frees and counts them).
 */
u32 ecmxf_pump_lost(struct ecmxf_pump *p, const struct ecmxf_pump_plan *pl)
{
	p->unconfirmed = pl->push;
	return pl->push;
}

/**
 * ecmxf_pump_wkc_cmd() - the header of ECAT_PDO_WC_GET 3
 * @hdr: the command header; every field is set
 */
void ecmxf_pump_wkc_cmd(struct ecmxf_cmd_hdr *hdr)
{
	memset(hdr, 0, sizeof(*hdr));
	hdr->code = ECMXF_CMD_ECAT_PDO_WC_GET;
	hdr->param = 3;
	hdr->control = ECMXF_CTL_CLR_CMD_ERR;
}

/**
 * ecmxf_pump_wkc_answer() - the working counter in an answer
 * @h: the answer's header
 * @data: its data
 * @len: the data bytes
 * @wkc: the working counter (little-endian u32), set on success
 *
 * Return: 0, -EREMOTEIO (command error) or -EPROTO (under 4 bytes).
 */
int ecmxf_pump_wkc_answer(const struct ecmxf_rsp_hdr *h, const u8 *data,
			  u32 len, u32 *wkc)
{
	if (h->err_status & ECMXF_ERR_CMD)
		return -EREMOTEIO;
	if (len < 4)
		return -EPROTO;
	*wkc = get_unaligned_le32(data);
	return 0;
}
