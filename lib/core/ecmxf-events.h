/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmxf-events.h - events from successive response headers (sans-I/O)
 *
 * The rules that turn the response headers a host sees into events (state
 * changes, link up/down, WKC error bursts, FIFO marks, chip resets...),
 * written once for the kernel module (which multicasts them over generic
 * netlink) and for the userspace poller of `ecmxf-util monitor` (sim: and
 * spidev: devices), so that both report the same events for the same
 * headers.  No I/O, no allocation, no clock: the caller passes each valid
 * header with the time it arrived.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_EVENTS_H
#define ECMXF_EVENTS_H

#include "ecmxf-proto.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * enum ecmxf_det_type - kinds of events; the values are those of
 *	&enum ecmxf_nl_event in <linux/ecmxf_netlink.h>
 * @ECMXF_DET_RESET: the chip reset (NOP answer, "Ethernet initialised"
 *	cleared, or the ECAT state back to 0); the only event of its header
 * @ECMXF_DET_LINK: error status bit 0 (EtherCAT link) changed
 * @ECMXF_DET_STATE: the ECAT state changed
 * @ECMXF_DET_ERROR_STATUS: error status bits 1..7 changed
 * @ECMXF_DET_ECM_STATUS: ECM status bits 2, 3, 4 or 6 changed
 * @ECMXF_DET_CRC_ERRORS: the SPI CRC error count went up
 * @ECMXF_DET_WKC_BURST: the WKC error count went up, no burst running
 * @ECMXF_DET_WKC_BURST_END: a burst had no new errors for the quiet time
 * @ECMXF_DET_FIFO: a FIFO count crossed its mark
 */
enum ecmxf_det_type {
	ECMXF_DET_RESET = 2,
	ECMXF_DET_LINK = 3,
	ECMXF_DET_STATE = 4,
	ECMXF_DET_ERROR_STATUS = 5,
	ECMXF_DET_ECM_STATUS = 6,
	ECMXF_DET_CRC_ERRORS = 7,
	ECMXF_DET_WKC_BURST = 8,
	ECMXF_DET_WKC_BURST_END = 9,
	ECMXF_DET_FIFO = 10,
};

/* ECM status bits an %ECMXF_DET_ECM_STATUS event watches (2, 3, 4, 6) */
#define ECMXF_DET_ECM_WATCHED	(ECMXF_STS_DC_STABLE | ECMXF_STS_ETH_INIT | \
				 ECMXF_STS_PDO_CONFIGURED | ECMXF_STS_FIFO_EN)
/* error status bits an %ECMXF_DET_ERROR_STATUS event watches (1..7) */
#define ECMXF_DET_ERR_WATCHED	((u8)~ECMXF_ERR_LINK_HW)

/* &ecmxf_det_event.fifo */
#define ECMXF_DET_FIFO_TX	0u
#define ECMXF_DET_FIFO_RX	1u

/* the most events one call of ecmxf_det_feed() can return */
#define ECMXF_DET_MAX_EVENTS	10u

/* defaults of &struct ecmxf_det_cfg */
#define ECMXF_DET_TX_HIGH	10u
#define ECMXF_DET_RX_LOW	0u
#define ECMXF_DET_WKC_QUIET_NS	100000000ull	/* 100 ms */

/**
 * struct ecmxf_det_cfg - thresholds of a detector
 * @tx_high: TxFIFO high mark: an event when the count reaches it (>=) or
 *	falls below it
 * @rx_low: RxFIFO low mark: an event when the count falls to it (<=) or
 *	rises above it
 * @wkc_quiet_ns: a WKC burst ends when no header showed new errors for
 *	this long
 */
struct ecmxf_det_cfg {
	u8 tx_high;
	u8 rx_low;
	u64 wkc_quiet_ns;
};

/**
 * struct ecmxf_det_event - one event
 * @type: &enum ecmxf_det_type
 * @old_val: %ECMXF_DET_STATE: old state; %ECMXF_DET_ERROR_STATUS: old
 *	error status; %ECMXF_DET_ECM_STATUS: old watched bits
 * @new_val: new value, as @old_val; %ECMXF_DET_RESET: the ECAT state;
 *	%ECMXF_DET_LINK: 1 up, 0 down
 * @err_status: error status byte of the header
 * @ecm_status: ECM status byte of the header
 * @fifo: %ECMXF_DET_FIFO: %ECMXF_DET_FIFO_TX or %ECMXF_DET_FIFO_RX
 * @above: %ECMXF_DET_FIFO: the count is above the mark now (TxFIFO: at or
 *	above the high mark; RxFIFO: above the low mark)
 * @count: counter value (CRC, WKC) or FIFO count of the header
 * @increase: CRC/WKC: how much the counter went up
 * @errors: %ECMXF_DET_WKC_BURST_END: errors of the whole burst
 * @mark: %ECMXF_DET_FIFO: the mark crossed
 * @duration_ns: %ECMXF_DET_WKC_BURST_END: first to last header with new
 *	errors
 * @time_ns: when the event was seen (the caller's clock)
 */
struct ecmxf_det_event {
	u8 type;
	u8 old_val;
	u8 new_val;
	u8 err_status;
	u8 ecm_status;
	u8 fifo;
	bool above;
	u32 count;
	u32 increase;
	u32 errors;
	u32 mark;
	u64 duration_ns;
	u64 time_ns;
};

/**
 * struct ecmxf_det - detector state; private to ecmxf-events.c
 */
struct ecmxf_det {
	/* private: */
	struct ecmxf_det_cfg cfg;
	struct ecmxf_rsp_hdr prev;
	bool have_prev;
	bool burst;
	u32 burst_errors;
	u64 burst_start_ns;
	u64 burst_last_ns;
};

void ecmxf_det_init(struct ecmxf_det *d, const struct ecmxf_det_cfg *cfg);
unsigned int ecmxf_det_feed(struct ecmxf_det *d,
			    const struct ecmxf_rsp_hdr *h, u64 now_ns,
			    struct ecmxf_det_event *out);
unsigned int ecmxf_det_poll(struct ecmxf_det *d, u64 now_ns,
			    struct ecmxf_det_event *out);
unsigned int ecmxf_det_rebase(struct ecmxf_det *d, u64 now_ns,
			      struct ecmxf_det_event *out);
u64 ecmxf_det_deadline(const struct ecmxf_det *d);
bool ecmxf_det_have_baseline(const struct ecmxf_det *d);

#ifdef __cplusplus
}
#endif

#endif /* ECMXF_EVENTS_H */
