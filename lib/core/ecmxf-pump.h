/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmxf-pump.h - the PDO pump's policy over the chip's FIFOs (sans-I/O)
 *
 * What an ECAT_PDO_DATA_FIFO_OP should carry and what its answer means,
 * written once for the kernel's pump (kmod/ecmxf-pump.c, frames from the
 * mmap()ed rings) and for the library's FIFO-command path (frames from
 * the process image): how many RxPDO frames the RxFIFO has room for, the
 * command's header fields, and from the answer the frames popped, the
 * frames refused and the FIFO losses.  No I/O, no allocation, no clock:
 * the caller moves the frames and runs the commands.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_PUMP_H
#define ECMXF_PUMP_H

#include "ecmxf-proto.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * frames kept free in the RxFIFO: the header's FIFO counts lag by up to
 * two exchanges (spec, "PDO exchange details")
 */
#define ECMXF_PUMP_RX_MARGIN	2U
/* RxPDO frames one command can carry: the command parameter is a byte */
#define ECMXF_PUMP_MAX_PUSH	255U

/* data byte 0 of ECAT_PDO_DATA_FIFO_OP */
#define ECMXF_PUMP_OP_WRITE	0x01U	/* push the frames into the RxFIFO */
#define ECMXF_PUMP_OP_READ	0x02U	/* pop TxPDO frames */
/* return value bit 0: the RxFIFO took the frames (clear: full, refused) */
#define ECMXF_PUMP_RET_TAKEN	0x01U

/* ecmxf_pump_next() flags */
#define ECMXF_PUMP_F_READ	0x01U	/* pop TxPDO frames (if there are any) */
#define ECMXF_PUMP_F_ONE	0x02U	/* offer one frame even to a full FIFO */

/**
 * struct ecmxf_pump - what the pump knows about the chip's FIFOs
 * @out_size: RxPDO frame bytes (FIFO_PACK_SIZE_GET 0), 0 without outputs
 * @in_size: TxPDO frame bytes (FIFO_PACK_SIZE_GET 1), 0 without inputs
 * @data_size: the data section size in force
 * @rx_fill: RxFIFO level the pump fills up to
 * @tx_depth: TxFIFO depth (FIFO_GET_TX_CNT), 0 unknown
 * @unconfirmed: frames of the previous command that the header's RxFIFO
 *	count may not show yet
 * @pushed_any: a frame has been pushed (an empty RxFIFO is an underrun
 *	only after that)
 *
 * Set up with ecmxf_pump_init(); ecmxf_pump_answer() keeps the last two.
 */
struct ecmxf_pump {
	u32 out_size;
	u32 in_size;
	u32 data_size;
	u32 rx_fill;
	u32 tx_depth;
	u32 unconfirmed;
	bool pushed_any;
};

/**
 * struct ecmxf_pump_plan - one planned ECAT_PDO_DATA_FIFO_OP
 * @skip: the oldest ready output frames to drop before pushing (the
 *	caller fell behind); counted by the caller, never sent
 * @push: output frames the command carries (after the skipped ones)
 * @read: the command pops TxPDO frames
 */
struct ecmxf_pump_plan {
	u32 skip;
	u32 push;
	bool read;
};

/**
 * struct ecmxf_pump_result - what an answer to the FIFO command says
 * @taken: output frames gone for good (the caller frees them): the pushed
 *	ones, unless the chip refused the whole command (command error)
 * @refused: of @taken, frames the full RxFIFO refused (RxFIFO overrun)
 * @popped: TxPDO frames in the answer's data
 * @tx_overrun: the TxFIFO was full: the chip dropped its oldest frames
 * @rx_underrun: the RxFIFO ran empty while the FIFOs were enabled
 */
struct ecmxf_pump_result {
	u32 taken;
	u32 refused;
	u32 popped;
	bool tx_overrun;
	bool rx_underrun;
};

u32 ecmxf_pump_max_fill(u32 rx_depth);
int ecmxf_pump_check(u32 out_size, u32 in_size, u32 data_size,
		     u32 rx_depth, u32 rx_fill);
void ecmxf_pump_init(struct ecmxf_pump *p, u32 out_size, u32 in_size,
		     u32 data_size, u32 rx_depth, u32 rx_fill, u32 tx_depth);
u32 ecmxf_pump_per_write(const struct ecmxf_pump *p);
u32 ecmxf_pump_per_read(const struct ecmxf_pump *p);
u32 ecmxf_pump_level(const struct ecmxf_pump *p,
		     const struct ecmxf_rsp_hdr *h);
bool ecmxf_pump_next(const struct ecmxf_pump *p, u32 level, u32 avail,
		     unsigned int flags, struct ecmxf_pump_plan *pl);
u32 ecmxf_pump_fifo_cmd(const struct ecmxf_pump *p,
			const struct ecmxf_pump_plan *pl, bool rearm,
			struct ecmxf_cmd_hdr *hdr);
int ecmxf_pump_answer(struct ecmxf_pump *p, const struct ecmxf_pump_plan *pl,
		      const struct ecmxf_rsp_hdr *h, u32 rx_len,
		      struct ecmxf_pump_result *res);
u32 ecmxf_pump_lost(struct ecmxf_pump *p, const struct ecmxf_pump_plan *pl);
void ecmxf_pump_wkc_cmd(struct ecmxf_cmd_hdr *hdr);
int ecmxf_pump_wkc_answer(const struct ecmxf_rsp_hdr *h, const u8 *data,
			  u32 len, u32 *wkc);

#ifdef __cplusplus
}
#endif

#endif /* ECMXF_PUMP_H */
