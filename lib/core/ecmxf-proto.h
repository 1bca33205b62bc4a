/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmxf-proto.h - the ECM-XF host protocol core (sans-I/O)
 *
 * One C module, compiled into the kernel module (kmod/) and into the
 * userspace library (lib/): packet framing, check words, response
 * validation, the command table and the exchange engine.  It performs no
 * I/O, allocates nothing, never sleeps and reads no clock: the caller
 * passes buffers in and the current time (in nanoseconds, any monotonic
 * origin) where time matters.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_PROTO_H
#define ECMXF_PROTO_H

#include "ecmxf-compat.h"
#include <linux/ecmxf.h>	/* include/uapi: protocol numbers */

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------- */
/* Packet geometry                                                        */
/* ---------------------------------------------------------------------- */

#define ECMXF_HDR_SIZE		24u
#define ECMXF_TRAILER_SIZE	8u	/* check word + end word */
#define ECMXF_DATA_MIN		32u
#define ECMXF_DATA_MAX		1408u
#define ECMXF_DATA_DEFAULT	112u
#define ECMXF_PKT_SIZE(n)	(ECMXF_HDR_SIZE + (n) + ECMXF_TRAILER_SIZE)
#define ECMXF_PKT_MAX		ECMXF_PKT_SIZE(ECMXF_DATA_MAX)

#define ECMXF_START_WORD	0xA1A2A3A4u
#define ECMXF_END_WORD		0x56575859u
#define ECMXF_FIXED_CHECK	0x12345678u
#define ECMXF_NOT_READY_WORD	0x87654321u

/**
 * enum ecmxf_check - check word type (ECM status bits 1-0, CRC_TYPE_SET)
 * @ECMXF_CHECK_FIXED: the constant 0x12345678
 * @ECMXF_CHECK_CRC8: CRC-8, poly 0x07, init 0 (ver. 038 only)
 * @ECMXF_CHECK_CCITT: CRC-CCITT-FALSE, poly 0x1021, init 0xFFFF (038 only)
 * @ECMXF_CHECK_CRC32: CRC-32 (zlib/Ethernet)
 * @ECMXF_CHECK_COVER_VALID: a flag OR-ed into a check type passed to the
 *	codec: the CRC covers the header plus the valid data length (header
 *	field 0x0E) rounded up to 4 bytes, at most the data section, as
 *	NEXTW's example host code computes it; without the flag it covers
 *	every byte before the check word (manual ver. 050)
 *
 * CRC values are stored zero-extended in the 32-bit little-endian check
 * word and cover every byte before it (header and data section), or with
 * %ECMXF_CHECK_COVER_VALID the header and the valid data only.  The fixed
 * word ignores the flag.
 */
enum ecmxf_check {
	ECMXF_CHECK_FIXED = 0,
	ECMXF_CHECK_CRC8 = 1,
	ECMXF_CHECK_CCITT = 2,
	ECMXF_CHECK_CRC32 = 3,
	ECMXF_CHECK_COVER_VALID = 0x10,
};

#define ECMXF_CHECK_TYPE_MASK	0x03u

/**
 * enum ecmxf_cover - which bytes a chip's CRC check word covers
 * @ECMXF_COVER_UNKNOWN: not known yet (no CRC in force, or no response
 *	that tells the two rules apart)
 * @ECMXF_COVER_FRAME: header and the whole data section (manual ver. 050)
 * @ECMXF_COVER_VALID: header and the valid data length rounded up to 4
 *	bytes (NEXTW's example host code)
 */
enum ecmxf_cover {
	ECMXF_COVER_UNKNOWN = 0,
	ECMXF_COVER_FRAME = 1,
	ECMXF_COVER_VALID = 2,
};

/*
 * The header's bits (ECMXF_RSV_*, ECMXF_CTL_*, ECMXF_ERR_*, ECMXF_STS_*,
 * ECMXF_INT_*), the EtherCAT states (ECMXF_ECAT_*) and the command codes
 * (ECMXF_CMD_*) are the uAPI's: <linux/ecmxf.h>.
 */

/**
 * struct ecmxf_cmd_hdr - command header fields (host to chip)
 * @data: parametric data 0..3 (0x04..0x07)
 * @reserved: the 16-bit word at 0x08 (%ECMXF_RSV_*)
 * @control: control byte at 0x0A (%ECMXF_CTL_*)
 * @index: host-chosen tag at 0x0B
 * @code: command code at 0x0C
 * @param: command parameter at 0x0D
 * @len: data length field at 0x0E; for some commands a parameter
 * @int_clear: interrupt clear at 0x10 (%ECMXF_INT_*)
 * @gpio_int_clear: GPIO interrupt clear low/high (0x14, 0x15)
 * @gpio_out: GPIO outputs low/high (0x16, 0x17)
 */
struct ecmxf_cmd_hdr {
	u8 data[4];
	u16 reserved;
	u8 control;
	u8 index;
	u8 code;
	u8 param;
	u16 len;
	u32 int_clear;
	u8 gpio_int_clear[2];
	u8 gpio_out[2];
};

/**
 * struct ecmxf_rsp_hdr - response header fields (chip to host)
 * @crc_err_cnt: SPI CRC error count (0x04)
 * @wkc_err_cnt: WKC error count (0x05)
 * @tx_fifo_cnt: TxPDOs in the chip's TxFIFO not yet read (0x06)
 * @rx_fifo_cnt: RxPDOs in the chip's RxFIFO not yet sent (0x07)
 * @ecat_state: EtherCAT state (0x08, %ECMXF_ECAT_*)
 * @err_status: error status (0x09, %ECMXF_ERR_*)
 * @ecm_status: ECM status (0x0A, %ECMXF_STS_*)
 * @index: index of the command answered (0x0B)
 * @code: command code answered (0x0C)
 * @ret: return value (0x0D)
 * @len: valid data length (0x0E); never more than the data section
 * @int_flags: interrupt flags (0x10)
 * @gpio_int_flag: GPIO interrupt flags low/high (0x14, 0x15)
 * @gpio_in: GPIO inputs low/high (0x16, 0x17)
 */
struct ecmxf_rsp_hdr {
	u8 crc_err_cnt;
	u8 wkc_err_cnt;
	u8 tx_fifo_cnt;
	u8 rx_fifo_cnt;
	u8 ecat_state;
	u8 err_status;
	u8 ecm_status;
	u8 index;
	u8 code;
	u8 ret;
	u16 len;
	u32 int_flags;
	u8 gpio_int_flag[2];
	u8 gpio_in[2];
};

/**
 * enum ecmxf_fault - why a received packet was rejected
 * @ECMXF_FAULT_NONE: the packet is valid
 * @ECMXF_FAULT_NOT_READY: check word reads 0x87654321 (chip not ready)
 * @ECMXF_FAULT_START: wrong start word
 * @ECMXF_FAULT_END: wrong end word
 * @ECMXF_FAULT_CHECK: check word does not match
 * @ECMXF_FAULT_LENGTH: data length field exceeds the data section
 * @ECMXF_FAULT_SIZE: buffer length is not the configured packet size
 *	(a caller error, not a chip error)
 * @ECMXF_FAULT_COUNT: number of fault kinds (array size, not a fault)
 */
enum ecmxf_fault {
	ECMXF_FAULT_NONE = 0,
	ECMXF_FAULT_NOT_READY,
	ECMXF_FAULT_START,
	ECMXF_FAULT_END,
	ECMXF_FAULT_CHECK,
	ECMXF_FAULT_LENGTH,
	ECMXF_FAULT_SIZE,
	ECMXF_FAULT_COUNT
};

/* ---------------------------------------------------------------------- */
/* Check words                                                            */
/* ---------------------------------------------------------------------- */

u8 ecmxf_crc8_update(u8 crc, const void *buf, size_t len);
u8 ecmxf_crc8(const void *buf, size_t len);
u16 ecmxf_crc_ccitt(const void *buf, size_t len);
u32 ecmxf_crc32(const void *buf, size_t len);
u32 ecmxf_check_word(enum ecmxf_check check, const void *buf, size_t len);
size_t ecmxf_check_span(const u8 *pkt, size_t pkt_len, enum ecmxf_check check);
const char *ecmxf_cover_name(enum ecmxf_cover cover);

/* ---------------------------------------------------------------------- */
/* Codec                                                                  */
/* ---------------------------------------------------------------------- */

bool ecmxf_data_size_valid(unsigned int data_size);
int ecmxf_encode_cmd(u8 *pkt, size_t pkt_len, enum ecmxf_check check,
		     const struct ecmxf_cmd_hdr *hdr,
		     const void *data, size_t data_len);
enum ecmxf_fault ecmxf_decode_rsp(const u8 *pkt, size_t pkt_len,
				  enum ecmxf_check check,
				  struct ecmxf_rsp_hdr *hdr,
				  const u8 **data);
int ecmxf_encode_rsp(u8 *pkt, size_t pkt_len, enum ecmxf_check check,
		     const struct ecmxf_rsp_hdr *hdr,
		     const void *data, size_t data_len);
enum ecmxf_fault ecmxf_decode_cmd(const u8 *pkt, size_t pkt_len,
				  enum ecmxf_check check,
				  struct ecmxf_cmd_hdr *hdr,
				  const u8 **data);
int ecmxf_fault_errno(enum ecmxf_fault fault);
const char *ecmxf_fault_name(enum ecmxf_fault fault);

/* ---------------------------------------------------------------------- */
/* Command table                                                          */
/* ---------------------------------------------------------------------- */

/* struct ecmxf_cmd_info flags */
#define ECMXF_CMDF_ASYNC	(1u << 0)	/* async ("blocking") command */
#define ECMXF_CMDF_ASYNC_PARAM0	(1u << 1)	/* async only when param == 0 */
#define ECMXF_CMDF_V038		(1u << 2)	/* documented in ver. 038 */
#define ECMXF_CMDF_V050		(1u << 3)	/* documented in ver. 050 */
#define ECMXF_CMDF_IDEMPOTENT	(1u << 4)	/* a pure read: safe to re-issue */
#define ECMXF_CMDF_OBSOLETE	(1u << 5)	/* kept for old firmware only */
#define ECMXF_CMDF_DESTRUCTIVE	(1u << 6)	/* resets, reflashes, changes the link */
#define ECMXF_CMDF_BUS		(1u << 7)	/* changes the chip, the bus or its slaves */
#define ECMXF_CMDF_PROCESS	(1u << 8)	/* process data or the PDO FIFOs */

/*
 * Permission classes: what /dev/ecmxfN asks of the file that sends a
 * command (Documentation/uapi.rst, "Permissions"); ecmxf_cmd_perm() gives
 * a command's class.
 */
enum ecmxf_perm {
	ECMXF_PERM_QUERY = 0,	/* no side effect: any open file */
	ECMXF_PERM_CHIP,	/* changes the chip or the bus: open for writing */
	ECMXF_PERM_PROCESS,	/* process data, FIFOs: writing, the holder's */
	ECMXF_PERM_ADMIN,	/* resets, reflashes: writing and CAP_SYS_ADMIN */
};

/**
 * struct ecmxf_cmd_info - one row of the command table
 * @code: command code
 * @flags: %ECMXF_CMDF_* bits
 * @partner: the command that fetches this one's result or reads back
 *	what it set (*_REQ -> *_GET, *_SET -> *_GET), or -1 for none
 * @timeout_ms: default time the engine allows for the command, including
 *	async completion
 * @name: the manual's name without the ECM_CMD_ prefix
 */
struct ecmxf_cmd_info {
	u8 code;
	u16 flags;
	s16 partner;
	u32 timeout_ms;
	const char *name;
};

/**
 * enum ecmxf_bits_field - a header field whose bits have names
 * @ECMXF_BITS_CONTROL: the command's control byte (0x0A)
 * @ECMXF_BITS_RESERVED: the command's reserved word (0x08)
 * @ECMXF_BITS_ERR_STATUS: the response's error status (0x09)
 * @ECMXF_BITS_ECM_STATUS: the response's ECM status (0x0A; bits 1-0 are
 *	the check type, not named here)
 * @ECMXF_BITS_INT: the interrupt word (0x10): clear bits, flags
 * @ECMXF_BITS_FIELDS: the number of fields
 */
enum ecmxf_bits_field {
	ECMXF_BITS_CONTROL,
	ECMXF_BITS_RESERVED,
	ECMXF_BITS_ERR_STATUS,
	ECMXF_BITS_ECM_STATUS,
	ECMXF_BITS_INT,
	ECMXF_BITS_FIELDS,
};

/**
 * struct ecmxf_bit_name - the name of one bit of a header field
 * @bit: the bit number (0 = least significant)
 * @name: its name as the decoder prints it
 */
struct ecmxf_bit_name {
	u8 bit;
	const char *name;
};

/*
 * ecmxf_bit_names() - the named bits of @field, in bit order, and their
 * number in @count (NULL and 0 for an unknown field); lib/core/ecmxf-bits.c,
 * userspace only.
 */
const struct ecmxf_bit_name *ecmxf_bit_names(enum ecmxf_bits_field field,
					     size_t *count);

const struct ecmxf_cmd_info *ecmxf_cmd_lookup(unsigned int code);
const struct ecmxf_cmd_info *ecmxf_cmd_table(size_t *count);
bool ecmxf_cmd_is_async(unsigned int code, unsigned int param);
enum ecmxf_perm ecmxf_cmd_perm(unsigned int code, unsigned int param,
			       const u8 *data, size_t len);
bool ecmxf_rsv_valid(unsigned int code, unsigned int rsv);

/* ---------------------------------------------------------------------- */
/* Exchange engine                                                        */
/* ---------------------------------------------------------------------- */

/* struct ecmxf_xfer flags */
#define ECMXF_XF_NO_AUTO_CLEAR	(1u << 0) /* leave ERR_ASYNC/ERR_CMD set */

/**
 * struct ecmxf_xfer - one command travelling through the engine
 * @hdr: command header; @hdr.index and the engine's own control bits are
 *	filled in by the engine, everything else is sent as given
 * @tx_data: bytes for the data section (may be NULL when @tx_len is 0)
 * @tx_len: number of bytes at @tx_data, at most the data section size
 * @rx_buf: where the response data is copied (may be NULL)
 * @rx_size: capacity of @rx_buf
 * @timeout_us: time allowed from submission to completion (async: to
 *	the end of the chip's busy phase); 0 selects the table default
 * @flags: %ECMXF_XF_* bits
 * @fetch: for an async command, its result fetch (the *_GET partner, an
 *	immediate command) or NULL.  The engine sends @fetch as the poll of
 *	the running command and finishes both when an answer to @fetch shows
 *	the chip no longer busy: completion costs no extra exchange.  @fetch
 *	must stay valid until its own status is final; it is finished with
 *	-ECANCELED when the async command fails before it could be sent.
 * @rsp: the answering response header (valid once @status is final)
 * @rx_len: response data bytes copied to @rx_buf
 * @status: -EINPROGRESS until done, then 0 or a negative errno:
 *	-ETIMEDOUT (no answer or no completion in time), -EBADMSG / -EPROTO /
 *	-EIO (transport retries exhausted; see @fault), -EBUSY (the chip
 *	refused an async command because another one runs), -EREMOTEIO
 *	(async command finished with the error bit set), -ECONNRESET (the
 *	chip reset), -EMSGSIZE (answer longer than @rx_size; @rx_len bytes
 *	were copied), -ECANCELED (withdrawn by ecmxf_engine_cancel())
 * @fault: for transport failures, the last packet fault seen
 * @async: set by the engine when the command runs asynchronously
 * @started_ns: private: submission time
 * @deadline_ns: private: time at which the command times out
 * @state: private: where the command is in the engine
 * @sent_seq: private: exchange of the first send
 * @last_seq: private: exchange of the latest send (first or re-send)
 * @owner: private: the async command this one is the fetch of
 * @prev_index: private: the index of @owner's fetch before its latest send
 * @ahead: private: the latest send was a fetch sent ahead (a fresh send
 *	while the answer to @prev_index was still due)
 */
struct ecmxf_xfer {
	struct ecmxf_cmd_hdr hdr;
	const void *tx_data;
	u16 tx_len;
	void *rx_buf;
	u16 rx_size;
	u32 timeout_us;
	u32 flags;
	struct ecmxf_xfer *fetch;

	struct ecmxf_rsp_hdr rsp;
	u16 rx_len;
	int status;
	enum ecmxf_fault fault;
	bool async;

	u64 started_ns;
	u64 deadline_ns;
	u8 state;
	u32 sent_seq;
	u32 last_seq;
	struct ecmxf_xfer *owner;
	u8 prev_index;
	bool ahead;
};

/**
 * struct ecmxf_engine_stats - counters kept by the engine
 * @exchanges: packets handed to ecmxf_engine_input()
 * @faults: rejected packets, by &enum ecmxf_fault
 * @retries: packets re-sent because the previous answer was unusable
 * @polls: re-sends because the answer had not arrived yet
 * @exhausted: commands failed because retries ran out
 * @timeouts: commands failed by timeout
 * @async_errors: async commands that finished with the error bit
 * @busy_rejects: async commands the chip refused as busy
 * @lost_answers: answers overwritten by INFO_UPDATE (re-issued or failed)
 * @chip_resets: NOP responses after valid ones (the chip restarted)
 * @pipelined: commands sent in the exchange that fetched the previous
 *	command's answer
 * @reordered: idempotent commands whose answer was lost and that went
 *	again after the command riding behind them
 * @fetch_polls: result fetches sent again because the answer showed the
 *	async command still busy
 */
struct ecmxf_engine_stats {
	u64 exchanges;
	u64 faults[ECMXF_FAULT_COUNT];
	u64 retries;
	u64 polls;
	u64 exhausted;
	u64 timeouts;
	u64 async_errors;
	u64 busy_rejects;
	u64 lost_answers;
	u64 chip_resets;
	u64 pipelined;
	u64 reordered;
	u64 fetch_polls;
};

/* events returned by ecmxf_engine_input() and ecmxf_engine_poll_time() */
#define ECMXF_EV_CMD_DONE	(1u << 0) /* the current command finished */
#define ECMXF_EV_ASYNC_DONE	(1u << 1) /* the running async command finished */
#define ECMXF_EV_ERR_STATUS	(1u << 2) /* new bits in the error status */
#define ECMXF_EV_CHIP_RESET	(1u << 3) /* NOP response after valid ones */
#define ECMXF_EV_BAD_PACKET	(1u << 4) /* a packet was rejected */
#define ECMXF_EV_HEADER		(1u << 5) /* a valid header arrived */

/**
 * struct ecmxf_engine - exchange state of one link to one chip
 *
 * All fields are private to ecmxf-engine.c except where a function says
 * otherwise; the caller allocates the structure and calls
 * ecmxf_engine_init() on it.
 */
struct ecmxf_engine {
	/* private: */
	u16 data_size;
	u8 check;
	u8 prev_check;		/* accepted until a response uses the new one */
	u8 max_retries;
	u8 next_index;
	u8 last_index;		/* (index, code) of the last packet sent */
	u8 last_code;
	bool last_valid;
	bool seen_valid;	/* a non-NOP response has been seen */
	bool pipeline;		/* a second command may ride (default on) */
	u8 bad_in_row;
	enum ecmxf_fault last_fault;
	u8 control_pending;	/* control bits for the next packet */
	u8 err_seen;		/* fault bits of the last valid header */
	u16 pending_size;	/* SPI_RECONFIG_OP in flight: the new size */
	u64 not_before_ns;	/* next exchange not before (reconfig hold-off) */
	u32 int_clear_pending;
	u8 gpio_int_clear_pending[2];
	u32 seq;		/* exchanges built by ecmxf_engine_next() */
	struct ecmxf_xfer *cur;	/* the older command awaiting its answer */
	struct ecmxf_xfer *nxt;	/* the younger one, riding behind @cur */
	struct ecmxf_xfer *async; /* accepted async command, chip busy */
	struct ecmxf_rsp_hdr last;	/* last valid response header */
	bool have_last;
	struct ecmxf_engine_stats stats;
	/* firmware variants (Documentation/protocol-core.rst) */
	u8 cover;		/* enum ecmxf_cover: the chip's CRC coverage */
	u8 cover_probes;	/* INFO_UPDATE probes sent while unknown */
	u8 crcset_tries;	/* CRC_TYPE_SET sends the chip did not take */
	u8 switch_age;		/* responses since a check type switch went out */
};

#define ECMXF_ENGINE_DEFAULT_RETRIES	8u
#define ECMXF_COVER_MAX_PROBES		4u
#define ECMXF_RECONFIG_HOLDOFF_NS	100000000ull	/* 100 ms */

void ecmxf_engine_init(struct ecmxf_engine *e, unsigned int data_size,
		       enum ecmxf_check check);
int ecmxf_engine_set_format(struct ecmxf_engine *e, unsigned int data_size,
			    enum ecmxf_check check);
void ecmxf_engine_set_retries(struct ecmxf_engine *e, unsigned int max);
void ecmxf_engine_set_pipeline(struct ecmxf_engine *e, bool on);
size_t ecmxf_engine_pkt_size(const struct ecmxf_engine *e);
bool ecmxf_engine_can_submit(const struct ecmxf_engine *e,
			     const struct ecmxf_xfer *x);
int ecmxf_engine_submit(struct ecmxf_engine *e, struct ecmxf_xfer *x,
			u64 now_ns);
int ecmxf_engine_cancel(struct ecmxf_engine *e, struct ecmxf_xfer *x);
void ecmxf_engine_clear_errors(struct ecmxf_engine *e, u8 control_bits);
void ecmxf_engine_clear_ints(struct ecmxf_engine *e, u32 int_clear,
			     u8 gpio_clear_lo, u8 gpio_clear_hi);
int ecmxf_engine_next(struct ecmxf_engine *e, u64 now_ns,
		      u8 *pkt, size_t pkt_len);
unsigned int ecmxf_engine_input(struct ecmxf_engine *e, u64 now_ns,
				const u8 *pkt, size_t pkt_len);
unsigned int ecmxf_engine_poll_time(struct ecmxf_engine *e, u64 now_ns);
u64 ecmxf_engine_deadline(const struct ecmxf_engine *e);
u64 ecmxf_engine_not_before(const struct ecmxf_engine *e);
bool ecmxf_engine_idle(const struct ecmxf_engine *e);
bool ecmxf_engine_running(const struct ecmxf_engine *e,
			  const struct ecmxf_xfer *x);
bool ecmxf_engine_sent(const struct ecmxf_engine *e,
		       const struct ecmxf_xfer *x);
bool ecmxf_engine_waits_only(const struct ecmxf_engine *e,
			     const struct ecmxf_xfer *x);
const struct ecmxf_rsp_hdr *
ecmxf_engine_last_header(const struct ecmxf_engine *e);
const struct ecmxf_engine_stats *
ecmxf_engine_get_stats(const struct ecmxf_engine *e);
unsigned int ecmxf_engine_data_size(const struct ecmxf_engine *e);
unsigned int ecmxf_engine_retries(const struct ecmxf_engine *e);
enum ecmxf_check ecmxf_engine_check(const struct ecmxf_engine *e);
enum ecmxf_cover ecmxf_engine_cover(const struct ecmxf_engine *e);

#ifdef __cplusplus
}
#endif

#endif /* ECMXF_PROTO_H */
