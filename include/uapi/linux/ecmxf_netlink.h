/* SPDX-License-Identifier: GPL-2.0-only WITH Linux-syscall-note */
/*
 * <linux/ecmxf_netlink.h> - generic netlink interface of the NEXTW ECM-XF
 * SPI EtherCAT master (ecmxf.ko)
 *
 * The family %ECMXF_GENL_NAME ("ecmxf") has one multicast group,
 * %ECMXF_GENL_MCGRP_EVENTS ("events"), on which the kernel sends one
 * %ECMXF_NL_CMD_EVENT message per event of any chip: link up/down,
 * EtherCAT state changes (with the slaves' AL status codes), WKC error
 * bursts, failed async commands, FIFO marks, chip resets, devices coming
 * and going.  Joining the group needs no privilege.  The command
 * %ECMXF_NL_CMD_GET_COUNTERS reads the link statistics of one device (do,
 * with %ECMXF_NL_A_DEV_MINOR) or of every device (dump).
 *
 * Every message carries %ECMXF_NL_A_DEV_MINOR and %ECMXF_NL_A_DEV_NAME;
 * every event also %ECMXF_NL_A_EVENT_TYPE, %ECMXF_NL_A_TIMESTAMP_NS and
 * %ECMXF_NL_A_SEQ, then the attributes its &enum ecmxf_nl_event value
 * lists.  Receivers must ignore attributes and event types they do not
 * know: later versions add some (never renumber or retype one).
 * 64-bit attributes are aligned with %ECMXF_NL_A_PAD (nla_put_u64_64bit).
 *
 * The family exists in the initial network namespace only.  See
 * Documentation/driver.rst, "Events (generic netlink)".
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef _UAPI_LINUX_ECMXF_NETLINK_H
#define _UAPI_LINUX_ECMXF_NETLINK_H

/**
 * ECMXF_GENL_NAME - name of the generic netlink family
 */
#define ECMXF_GENL_NAME			"ecmxf"
/**
 * ECMXF_GENL_VERSION - version of the family (genlmsghdr.version)
 *
 * Raised when an attribute or event type gains a meaning that an older
 * receiver could misread; adding new ones does not raise it.
 */
#define ECMXF_GENL_VERSION		1
/**
 * ECMXF_GENL_MCGRP_EVENTS - name of the multicast group of the events
 */
#define ECMXF_GENL_MCGRP_EVENTS		"events"

/**
 * enum ecmxf_nl_cmd - generic netlink commands of the family
 * @ECMXF_NL_CMD_UNSPEC: unused
 * @ECMXF_NL_CMD_EVENT: kernel to userspace, on the "events" group: one
 *	event (&enum ecmxf_nl_event)
 * @ECMXF_NL_CMD_GET_COUNTERS: userspace asks for the link statistics: as
 *	a request with %ECMXF_NL_A_DEV_MINOR, of that device (-ENODEV if it
 *	does not exist); as a dump (NLM_F_DUMP), one message per device.
 *	Each answer has %ECMXF_NL_A_DEV_MINOR, %ECMXF_NL_A_DEV_NAME and the
 *	nest %ECMXF_NL_A_COUNTERS
 * @__ECMXF_NL_CMD_MAX: number of commands (not a command)
 */
enum ecmxf_nl_cmd {
	ECMXF_NL_CMD_UNSPEC,
	ECMXF_NL_CMD_EVENT,
	ECMXF_NL_CMD_GET_COUNTERS,
	__ECMXF_NL_CMD_MAX
};
#define ECMXF_NL_CMD_MAX	(__ECMXF_NL_CMD_MAX - 1)

/**
 * enum ecmxf_nl_attr - top-level attributes
 * @ECMXF_NL_A_UNSPEC: unused
 * @ECMXF_NL_A_PAD: padding for 64-bit attributes (no value)
 * @ECMXF_NL_A_DEV_MINOR: u32, N of /dev/ecmxfN
 * @ECMXF_NL_A_DEV_NAME: string, "ecmxfN"
 * @ECMXF_NL_A_EVENT_TYPE: u32, &enum ecmxf_nl_event
 * @ECMXF_NL_A_TIMESTAMP_NS: u64, CLOCK_MONOTONIC time in nanoseconds at
 *	which the kernel saw the event
 * @ECMXF_NL_A_SEQ: u32, per-device event number, counting from 0 at probe
 *	and including suppressed events: a gap that
 *	%ECMXF_NL_A_SUPPRESSED does not explain is a message lost on the
 *	way (a full socket buffer)
 * @ECMXF_NL_A_SUPPRESSED: u32, events of this device not sent because of
 *	the rate limit since the previous one sent; absent when zero
 * @ECMXF_NL_A_OLD: u32, previous value (%ECMXF_NL_EV_STATE: ECAT state;
 *	%ECMXF_NL_EV_ERROR_STATUS: error status byte;
 *	%ECMXF_NL_EV_ECM_STATUS: the watched ECM status bits)
 * @ECMXF_NL_A_NEW: u32, new value, as @ECMXF_NL_A_OLD; for
 *	%ECMXF_NL_EV_RESET and %ECMXF_NL_EV_DEVICE the ECAT state after it
 * @ECMXF_NL_A_LINK_UP: u8, 1 when the EtherCAT link is up (error status
 *	bit 0), 0 when it is down
 * @ECMXF_NL_A_ERR_STATUS: u8, the error status byte of the response header
 *	that showed the event
 * @ECMXF_NL_A_ECM_STATUS: u8, the ECM status byte of that header
 * @ECMXF_NL_A_COUNT: u32, the counter or FIFO count the header shows
 * @ECMXF_NL_A_INCREASE: u32, how much a counter went up since the header
 *	before
 * @ECMXF_NL_A_ERRORS: u32, WKC errors of a whole burst
 * @ECMXF_NL_A_DURATION_NS: u64, time from the first to the last header
 *	that showed new WKC errors of the burst
 * @ECMXF_NL_A_FIFO: u8, &enum ecmxf_nl_fifo
 * @ECMXF_NL_A_MARK: u32, the FIFO mark that was crossed
 * @ECMXF_NL_A_ABOVE: u8, 1 when the count is now above the mark (TxFIFO:
 *	at or above its high mark; RxFIFO: above its low mark), 0 when below
 * @ECMXF_NL_A_RESET_REASON: u32, &enum ecmxf_nl_reset_reason
 * @ECMXF_NL_A_CMD_CODE: u8, the chip command code (ECM_CMD_*)
 * @ECMXF_NL_A_STATUS: s32, negative errno of the failed command, as
 *	&struct ecmxf_cmd.status
 * @ECMXF_NL_A_SLAVE_COUNT: u32, slaves on the bus (ECAT_SLV_CNT_GET)
 * @ECMXF_NL_A_SLAVES: nest of %ECMXF_NL_A_SLAVE, one per slave not in OP
 * @ECMXF_NL_A_SLAVE: nest of &enum ecmxf_nl_slave_attr
 * @ECMXF_NL_A_AL_STATUS: u16, the first non-zero AL status code among
 *	@ECMXF_NL_A_SLAVES (absent when every answering slave reports 0)
 * @ECMXF_NL_A_AL_SLAVE: u16, position of the slave of @ECMXF_NL_A_AL_STATUS
 * @ECMXF_NL_A_SLAVES_INCOMPLETE: flag: the slaves could not all be read
 *	(a command failed, a reset came, or more than 64 slaves)
 * @ECMXF_NL_A_ACTION: u32, &enum ecmxf_nl_device_action
 * @ECMXF_NL_A_COUNTERS: nest of &enum ecmxf_nl_counter
 * @ECMXF_NL_A_LOSS: u8, &enum ecmxf_nl_loss
 * @ECMXF_NL_A_TOTAL: u64, the &struct ecmxf_counters field of that kind
 *	since probe (the sum of every @ECMXF_NL_A_INCREASE, suppressed
 *	events included)
 * @__ECMXF_NL_A_MAX: number of attributes (not an attribute)
 */
enum ecmxf_nl_attr {
	ECMXF_NL_A_UNSPEC,
	ECMXF_NL_A_PAD,
	ECMXF_NL_A_DEV_MINOR,
	ECMXF_NL_A_DEV_NAME,
	ECMXF_NL_A_EVENT_TYPE,
	ECMXF_NL_A_TIMESTAMP_NS,
	ECMXF_NL_A_SEQ,
	ECMXF_NL_A_SUPPRESSED,
	ECMXF_NL_A_OLD,
	ECMXF_NL_A_NEW,
	ECMXF_NL_A_LINK_UP,
	ECMXF_NL_A_ERR_STATUS,
	ECMXF_NL_A_ECM_STATUS,
	ECMXF_NL_A_COUNT,
	ECMXF_NL_A_INCREASE,
	ECMXF_NL_A_ERRORS,
	ECMXF_NL_A_DURATION_NS,
	ECMXF_NL_A_FIFO,
	ECMXF_NL_A_MARK,
	ECMXF_NL_A_ABOVE,
	ECMXF_NL_A_RESET_REASON,
	ECMXF_NL_A_CMD_CODE,
	ECMXF_NL_A_STATUS,
	ECMXF_NL_A_SLAVE_COUNT,
	ECMXF_NL_A_SLAVES,
	ECMXF_NL_A_SLAVE,
	ECMXF_NL_A_AL_STATUS,
	ECMXF_NL_A_AL_SLAVE,
	ECMXF_NL_A_SLAVES_INCOMPLETE,
	ECMXF_NL_A_ACTION,
	ECMXF_NL_A_COUNTERS,
	ECMXF_NL_A_LOSS,
	ECMXF_NL_A_TOTAL,
	__ECMXF_NL_A_MAX
};
#define ECMXF_NL_A_MAX		(__ECMXF_NL_A_MAX - 1)

/**
 * enum ecmxf_nl_slave_attr - attributes inside %ECMXF_NL_A_SLAVE
 * @ECMXF_NL_SA_UNSPEC: unused
 * @ECMXF_NL_SA_POSITION: u16, position on the bus (0 = first)
 * @ECMXF_NL_SA_STATE: u8, ECAT_STATE_GET of the slave: 1 INIT, 2 PRE-OP,
 *	3 BOOT, 4 SAFE-OP, 8 OP, bit 4 (0x10) error; 0x10 alone means the
 *	slave does not answer
 * @ECMXF_NL_SA_AL_STATUS: u16, the slave's AL status code
 *	(ECAT_SLV_INFO_GET code 7); absent for a slave that does not answer
 * @__ECMXF_NL_SA_MAX: number of attributes (not an attribute)
 */
enum ecmxf_nl_slave_attr {
	ECMXF_NL_SA_UNSPEC,
	ECMXF_NL_SA_POSITION,
	ECMXF_NL_SA_STATE,
	ECMXF_NL_SA_AL_STATUS,
	__ECMXF_NL_SA_MAX
};
#define ECMXF_NL_SA_MAX		(__ECMXF_NL_SA_MAX - 1)

/**
 * enum ecmxf_nl_event - %ECMXF_NL_A_EVENT_TYPE values, with the attributes
 *	each event has besides the common ones
 * @ECMXF_NL_EV_UNSPEC: unused
 * @ECMXF_NL_EV_DEVICE: a device was probed (its worker started; the link
 *	to the chip is up) or is being removed: %ECMXF_NL_A_ACTION; added:
 *	also %ECMXF_NL_A_NEW (ECAT state), %ECMXF_NL_A_LINK_UP,
 *	%ECMXF_NL_A_ERR_STATUS, %ECMXF_NL_A_ECM_STATUS
 * @ECMXF_NL_EV_RESET: the chip reset (a NOP answer, "Ethernet initialised"
 *	cleared, or the ECAT state back to 0), or the kernel resynchronised
 *	the link: %ECMXF_NL_A_RESET_REASON, %ECMXF_NL_A_NEW,
 *	%ECMXF_NL_A_ECM_STATUS.  Other changes in that header are no events:
 *	they follow from the reset
 * @ECMXF_NL_EV_LINK: the EtherCAT link went up or down (error status bit
 *	0): %ECMXF_NL_A_LINK_UP, %ECMXF_NL_A_ERR_STATUS
 * @ECMXF_NL_EV_STATE: the ECAT state in the response header changed:
 *	%ECMXF_NL_A_OLD, %ECMXF_NL_A_NEW.  When the state went down or to
 *	ERROR, the kernel first reads the slaves' states and AL status codes
 *	(see Documentation/driver.rst) and adds %ECMXF_NL_A_SLAVE_COUNT,
 *	%ECMXF_NL_A_SLAVES, and %ECMXF_NL_A_AL_STATUS + %ECMXF_NL_A_AL_SLAVE
 *	or %ECMXF_NL_A_SLAVES_INCOMPLETE as they apply
 * @ECMXF_NL_EV_ERROR_STATUS: bits 1..7 of the error status changed:
 *	%ECMXF_NL_A_OLD, %ECMXF_NL_A_NEW (whole bytes; bit 0 is
 *	%ECMXF_NL_EV_LINK's)
 * @ECMXF_NL_EV_ECM_STATUS: ECM status bits 2 (DC stable), 3 (Ethernet
 *	initialised), 4 (PDO configured) or 6 (FIFO enabled) changed:
 *	%ECMXF_NL_A_OLD, %ECMXF_NL_A_NEW (those bits only)
 * @ECMXF_NL_EV_CRC_ERRORS: the chip's SPI CRC error count went up:
 *	%ECMXF_NL_A_INCREASE, %ECMXF_NL_A_COUNT
 * @ECMXF_NL_EV_WKC_BURST: the WKC error count went up after a quiet
 *	period: a burst starts; %ECMXF_NL_A_INCREASE, %ECMXF_NL_A_COUNT.  No
 *	event per error follows
 * @ECMXF_NL_EV_WKC_BURST_END: no new WKC errors for 100 ms (or a reset):
 *	the burst is over; %ECMXF_NL_A_ERRORS, %ECMXF_NL_A_DURATION_NS,
 *	%ECMXF_NL_A_COUNT (255: the chip's count saturated)
 * @ECMXF_NL_EV_FIFO: a FIFO count crossed its mark (TxFIFO: reached or
 *	left 10 or more frames waiting, an overrun coming; RxFIFO: ran dry
 *	or got frames again, an underrun): %ECMXF_NL_A_FIFO,
 *	%ECMXF_NL_A_COUNT, %ECMXF_NL_A_MARK, %ECMXF_NL_A_ABOVE
 * @ECMXF_NL_EV_ASYNC_ERROR: an async command failed: it ended with the
 *	async-error bit (-EREMOTEIO), the chip refused it as busy (-EBUSY),
 *	or it timed out (-ETIMEDOUT): %ECMXF_NL_A_CMD_CODE,
 *	%ECMXF_NL_A_STATUS, %ECMXF_NL_A_ERR_STATUS
 * @ECMXF_NL_EV_PDO_LOSS: the cyclic path (the PDO rings and the pump)
 *	lost, refused or repeated frames, or found a FIFO or ring
 *	empty or full: %ECMXF_NL_A_LOSS (which counter), %ECMXF_NL_A_INCREASE
 *	(how much it went up since the previous event of that kind),
 *	%ECMXF_NL_A_TOTAL.  The kernel looks at the counters at most every
 *	10 ms and sends one event per counter that went up; when the rate
 *	limit holds one back, the increase carries over into the next one
 *	(never suppressed)
 * @__ECMXF_NL_EV_MAX: number of event types (not an event)
 */
enum ecmxf_nl_event {
	ECMXF_NL_EV_UNSPEC,
	ECMXF_NL_EV_DEVICE,
	ECMXF_NL_EV_RESET,
	ECMXF_NL_EV_LINK,
	ECMXF_NL_EV_STATE,
	ECMXF_NL_EV_ERROR_STATUS,
	ECMXF_NL_EV_ECM_STATUS,
	ECMXF_NL_EV_CRC_ERRORS,
	ECMXF_NL_EV_WKC_BURST,
	ECMXF_NL_EV_WKC_BURST_END,
	ECMXF_NL_EV_FIFO,
	ECMXF_NL_EV_ASYNC_ERROR,
	ECMXF_NL_EV_PDO_LOSS,
	__ECMXF_NL_EV_MAX
};
#define ECMXF_NL_EV_MAX		(__ECMXF_NL_EV_MAX - 1)

/**
 * enum ecmxf_nl_fifo - %ECMXF_NL_A_FIFO values
 * @ECMXF_NL_FIFO_TX: the chip's TxFIFO (inputs from the slaves, waiting
 *	for the host)
 * @ECMXF_NL_FIFO_RX: the chip's RxFIFO (outputs from the host, waiting
 *	for the bus)
 */
enum ecmxf_nl_fifo {
	ECMXF_NL_FIFO_TX,
	ECMXF_NL_FIFO_RX
};

/**
 * enum ecmxf_nl_loss - %ECMXF_NL_A_LOSS values: which counter of
 *	&struct ecmxf_counters went up
 * @ECMXF_NL_LOSS_OUT_RING_UNDERRUN: out_ring_underruns: the output ring
 *	was empty when the chip's RxFIFO wanted a frame
 * @ECMXF_NL_LOSS_IN_RING_OVERRUN: in_ring_overruns: input frames dropped,
 *	the input ring was full
 * @ECMXF_NL_LOSS_RX_FIFO_UNDERRUN: rx_fifo_underruns: the chip's RxFIFO
 *	ran empty (the bus repeats the last outputs)
 * @ECMXF_NL_LOSS_RX_FIFO_OVERRUN: rx_fifo_overruns: the chip refused
 *	output frames, its RxFIFO was full
 * @ECMXF_NL_LOSS_TX_FIFO_OVERRUN: tx_fifo_overruns: the chip's TxFIFO was
 *	full, it dropped its oldest input frames
 * @ECMXF_NL_LOSS_OUT_RING_SKIPPED: output frames the pump skipped when it
 *	had fallen behind (sysfs ring_skipped)
 * @ECMXF_NL_LOSS_PUMP_FAILURE: pump commands that failed after they may
 *	have reached the chip (sysfs ring_failures): their output frames are
 *	not sent again, the input frames of the lost answer are lost
 */
enum ecmxf_nl_loss {
	ECMXF_NL_LOSS_OUT_RING_UNDERRUN,
	ECMXF_NL_LOSS_IN_RING_OVERRUN,
	ECMXF_NL_LOSS_RX_FIFO_UNDERRUN,
	ECMXF_NL_LOSS_RX_FIFO_OVERRUN,
	ECMXF_NL_LOSS_TX_FIFO_OVERRUN,
	ECMXF_NL_LOSS_OUT_RING_SKIPPED,
	ECMXF_NL_LOSS_PUMP_FAILURE
};

/**
 * enum ecmxf_nl_reset_reason - %ECMXF_NL_A_RESET_REASON values
 * @ECMXF_NL_RESET_CHIP: the chip restarted on its own (or someone else
 *	reset it), seen in a response header
 * @ECMXF_NL_RESET_WARM: the chip restarted after a WARM_RESET the kernel
 *	sent (%ECMXF_IOC_RESET with %ECMXF_RESET_F_WARM, or the command)
 * @ECMXF_NL_RESET_LINK: the kernel resynchronised the link
 *	(%ECMXF_RESET_F_LINK); the chip itself did not restart
 */
enum ecmxf_nl_reset_reason {
	ECMXF_NL_RESET_CHIP = 1,
	ECMXF_NL_RESET_WARM,
	ECMXF_NL_RESET_LINK
};

/**
 * enum ecmxf_nl_device_action - %ECMXF_NL_A_ACTION values
 * @ECMXF_NL_DEV_ADDED: the device was probed and its link is up
 * @ECMXF_NL_DEV_REMOVED: the device is going away
 */
enum ecmxf_nl_device_action {
	ECMXF_NL_DEV_ADDED = 1,
	ECMXF_NL_DEV_REMOVED
};

/**
 * enum ecmxf_nl_counter - attributes inside %ECMXF_NL_A_COUNTERS, each a
 *	u64 (64-bit aligned, padded with %ECMXF_NL_C_PAD)
 * @ECMXF_NL_C_UNSPEC: unused
 * @ECMXF_NL_C_PAD: padding
 * @ECMXF_NL_C_EXCHANGES: &struct ecmxf_counters.exchanges
 * @ECMXF_NL_C_BAD_NOT_READY: &struct ecmxf_counters.bad_not_ready
 * @ECMXF_NL_C_BAD_START: &struct ecmxf_counters.bad_start
 * @ECMXF_NL_C_BAD_END: &struct ecmxf_counters.bad_end
 * @ECMXF_NL_C_BAD_CHECK: &struct ecmxf_counters.bad_check
 * @ECMXF_NL_C_BAD_LENGTH: &struct ecmxf_counters.bad_length
 * @ECMXF_NL_C_RETRIES: &struct ecmxf_counters.retries
 * @ECMXF_NL_C_POLLS: &struct ecmxf_counters.polls
 * @ECMXF_NL_C_EXHAUSTED: &struct ecmxf_counters.exhausted
 * @ECMXF_NL_C_TIMEOUTS: &struct ecmxf_counters.timeouts
 * @ECMXF_NL_C_ASYNC_ERRORS: &struct ecmxf_counters.async_errors
 * @ECMXF_NL_C_BUSY_REJECTS: &struct ecmxf_counters.busy_rejects
 * @ECMXF_NL_C_LOST_ANSWERS: &struct ecmxf_counters.lost_answers
 * @ECMXF_NL_C_CHIP_RESETS: &struct ecmxf_counters.chip_resets
 * @ECMXF_NL_C_WKC_ERRORS: &struct ecmxf_counters.wkc_errors
 * @ECMXF_NL_C_OUT_RING_UNDERRUNS: &struct ecmxf_counters.out_ring_underruns
 * @ECMXF_NL_C_IN_RING_OVERRUNS: &struct ecmxf_counters.in_ring_overruns
 * @ECMXF_NL_C_RX_FIFO_UNDERRUNS: &struct ecmxf_counters.rx_fifo_underruns
 * @ECMXF_NL_C_RX_FIFO_OVERRUNS: &struct ecmxf_counters.rx_fifo_overruns
 * @ECMXF_NL_C_TX_FIFO_OVERRUNS: &struct ecmxf_counters.tx_fifo_overruns
 * @ECMXF_NL_C_INT0_IRQS: &struct ecmxf_counters.int0_irqs
 * @ECMXF_NL_C_INT1_IRQS: &struct ecmxf_counters.int1_irqs
 * @ECMXF_NL_C_EVENTS: events detected (sent or not)
 * @ECMXF_NL_C_EVENTS_SUPPRESSED: events not sent because of the rate limit
 * @ECMXF_NL_C_EVENTS_FAILED: events that could not be sent (no memory, or
 *	every listener's socket buffer full); "no listener" is not counted
 * @__ECMXF_NL_C_MAX: number of attributes (not an attribute)
 *
 * @ECMXF_NL_C_EXCHANGES .. @ECMXF_NL_C_INT1_IRQS are the fields of &struct
 * ecmxf_counters in order: attribute ECMXF_NL_C_EXCHANGES + i is field i.
 */
enum ecmxf_nl_counter {
	ECMXF_NL_C_UNSPEC,
	ECMXF_NL_C_PAD,
	ECMXF_NL_C_EXCHANGES,
	ECMXF_NL_C_BAD_NOT_READY,
	ECMXF_NL_C_BAD_START,
	ECMXF_NL_C_BAD_END,
	ECMXF_NL_C_BAD_CHECK,
	ECMXF_NL_C_BAD_LENGTH,
	ECMXF_NL_C_RETRIES,
	ECMXF_NL_C_POLLS,
	ECMXF_NL_C_EXHAUSTED,
	ECMXF_NL_C_TIMEOUTS,
	ECMXF_NL_C_ASYNC_ERRORS,
	ECMXF_NL_C_BUSY_REJECTS,
	ECMXF_NL_C_LOST_ANSWERS,
	ECMXF_NL_C_CHIP_RESETS,
	ECMXF_NL_C_WKC_ERRORS,
	ECMXF_NL_C_OUT_RING_UNDERRUNS,
	ECMXF_NL_C_IN_RING_OVERRUNS,
	ECMXF_NL_C_RX_FIFO_UNDERRUNS,
	ECMXF_NL_C_RX_FIFO_OVERRUNS,
	ECMXF_NL_C_TX_FIFO_OVERRUNS,
	ECMXF_NL_C_INT0_IRQS,
	ECMXF_NL_C_INT1_IRQS,
	ECMXF_NL_C_EVENTS,
	ECMXF_NL_C_EVENTS_SUPPRESSED,
	ECMXF_NL_C_EVENTS_FAILED,
	__ECMXF_NL_C_MAX
};
#define ECMXF_NL_C_MAX		(__ECMXF_NL_C_MAX - 1)

#endif /* _UAPI_LINUX_ECMXF_NETLINK_H */
