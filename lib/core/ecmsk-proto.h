/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmsk-proto.h - the ECM-SK slot protocol core (sans-I/O)
 *
 * The ECM-SK starter kit exchanges one whole frame per SPI transfer: 42
 * slots of 12 bytes (504 bytes) or 32 slots of 16 bytes (512 bytes).
 * Slot 0 is the ECM itself, slots 1..N the slaves in bus order, the last
 * slot is the SDO slot.  This module encodes and decodes the slots of
 * every command of the quick start's table 1.3, computes the frame's
 * CRC-8 and tracks the exchanges: the answer to a command comes back in
 * the next exchange, and the long commands (SET_STATE, SDO_RD/SDO_WR,
 * GO_HOME) complete later, observed with GET_STATUS in the same slot.
 *
 * Like the ECM-XF core (ecmxf-proto.h) it performs no I/O, allocates
 * nothing, never sleeps and reads no clock.  Documentation/ecm-sk.rst.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMSK_PROTO_H
#define ECMSK_PROTO_H

#include "ecmxf-compat.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------- */
/* Frame geometry                                                         */
/* ---------------------------------------------------------------------- */

#define ECMSK_SLOT12		12u	/* CONFIG2 low (default) */
#define ECMSK_SLOT16		16u	/* CONFIG2 high */
#define ECMSK_SLOTS12		42u	/* ECM + 40 slaves + SDO */
#define ECMSK_SLOTS16		32u	/* ECM + 30 slaves + SDO */
#define ECMSK_FRAME12		(ECMSK_SLOT12 * ECMSK_SLOTS12)	/* 504 */
#define ECMSK_FRAME16		(ECMSK_SLOT16 * ECMSK_SLOTS16)	/* 512 */
#define ECMSK_FRAME_MAX		ECMSK_FRAME16
#define ECMSK_SLOTS_MAX		ECMSK_SLOTS12
#define ECMSK_SLAVES_MAX	40u
#define ECMSK_CRC_OFFSET	3u	/* byte 3 of slot 0 */
#define ECMSK_CRC_INIT		0x5Au

/**
 * struct ecmsk_geom - the frame layout for one slot size
 * @slot_size: bytes per slot (12 or 16)
 * @slots: slots per frame (42 or 32)
 * @max_slaves: slave slots (40 or 30), numbered 1..@max_slaves
 * @sdo_slot: index of the SDO slot (the last one)
 * @frame_size: bytes per frame (504 or 512)
 */
struct ecmsk_geom {
	u8 slot_size;
	u8 slots;
	u8 max_slaves;
	u8 sdo_slot;
	u16 frame_size;
};

int ecmsk_geom_init(struct ecmsk_geom *g, unsigned int slot_size);

/* ---------------------------------------------------------------------- */
/* Commands (table 1.3)                                                   */
/* ---------------------------------------------------------------------- */

#define ECMSK_CMD_GET_STATUS	0x00
#define ECMSK_CMD_SET_STATE	0x01
#define ECMSK_CMD_SET_AXIS	0x02
#define ECMSK_CMD_SET_DC	0x03
#define ECMSK_CMD_SET_EX	0x04
#define ECMSK_CMD_SET_FIFO	0x05
#define ECMSK_CMD_DRIVE_MODE	0x06
#define ECMSK_CMD_SDO_RD	0x07
#define ECMSK_CMD_SDO_WR	0x08
#define ECMSK_CMD_ALM_CLR	0x10
#define ECMSK_CMD_SV_ON		0x11
#define ECMSK_CMD_SV_OFF	0x12
#define ECMSK_CMD_IO_RD		0x13
#define ECMSK_CMD_IO_WR		0x14
#define ECMSK_CMD_CSP		0x15
#define ECMSK_CMD_CSV		0x16
#define ECMSK_CMD_CST		0x17
#define ECMSK_CMD_GO_HOME	0x18
#define ECMSK_CMD_ABORT_HOME	0x19
#define ECMSK_CMD_LIO_RD	0x21
#define ECMSK_CMD_LIO_WR	0x22
#define ECMSK_CMD_SW_RESET	0xBB
/* byte 0 of the ECM slot's response in OP */
#define ECMSK_RSP_OP		0xBF

/* EtherCAT states (Current State, SET_STATE's Requested STATE) */
#define ECMSK_STATE_INIT	0x01
#define ECMSK_STATE_PREOP	0x02
#define ECMSK_STATE_SAFEOP	0x04
#define ECMSK_STATE_OP		0x08

/* Slave types of SET_AXIS (4 bits per slave) */
#define ECMSK_AXIS_DRIVE	0x0
#define ECMSK_AXIS_IO		0x1
#define ECMSK_AXIS_HSP		0x2
#define ECMSK_AXIS_STEP		0x3
#define ECMSK_AXIS_NONE		0xF
#define ECMSK_AXIS_GROUPS	5u	/* groups 0..4, 8 slaves each */

/* SET_DC */
#define ECMSK_DC_MIN_US		250u
#define ECMSK_DC_DEFAULT_US	1000u
#define ECMSK_DC_FIX		0x0000FFFFu

/* SET_EX bits (effective from the next power-on) */
#define ECMSK_EX_CMD_CRC	0x1u	/* check command CRCs */
#define ECMSK_EX_RSP_CRC	0x2u	/* send response CRCs */

/* SET_FIFO actions */
#define ECMSK_FIFO_CLEAR	1u
#define ECMSK_FIFO_THRESHOLD	2u
#define ECMSK_FIFO_THRESHOLD_DEFAULT 160u
#define ECMSK_FIFO_ABANDON_CYCLES 100u	/* CONFIG3: a queued command older than this is abandoned */

/* DRIVE_MODE */
#define ECMSK_MODE_CSP		8u
#define ECMSK_MODE_CSV		9u
#define ECMSK_MODE_CST		10u
#define ECMSK_SYNC_FREERUN	0u
#define ECMSK_SYNC_DCSYNC	1u

/* Statusword bits 10 (target reached) and 12 (homing attained) */
#define ECMSK_SW_HOMED		0x1400u
#define ECMSK_SW_HOMING_ERROR	0x2000u

/*
 * SDO slot status (byte 1 of the SDO slot's response; a decision of
 * Documentation/ecm-sk.rst: the quick start does not say how a failed or
 * a still running SDO shows).
 */
#define ECMSK_SDO_DONE		0x00
#define ECMSK_SDO_BUSY		0x01
#define ECMSK_SDO_FAILED	0x02

/* ---------------------------------------------------------------------- */
/* CRC-8                                                                  */
/* ---------------------------------------------------------------------- */

u8 ecmsk_crc8(const u8 *frame, size_t len);
void ecmsk_frame_seal(u8 *frame, size_t len);
bool ecmsk_frame_crc_ok(const u8 *frame, size_t len);

/* ---------------------------------------------------------------------- */
/* Slot encode / decode                                                   */
/* ---------------------------------------------------------------------- */

/**
 * struct ecmsk_ecm_cmd - a command in slot 0 (the ECM)
 * @cmd: Cmd ID (bytes 0-1)
 * @param: byte 2: SET_AXIS group, SET_FIFO action
 * @data1: bytes 4-7 (state, topology, cycle time, extensions, value)
 * @data2: bytes 8-11 (SET_DC's FIX value)
 * @data3: bytes 12-15 (16-byte slots only)
 */
struct ecmsk_ecm_cmd {
	u16 cmd;
	u8 param;
	u32 data1;
	u32 data2;
	u32 data3;
};

/**
 * struct ecmsk_ecm_rsp - slot 0 of a response
 * @cmd: byte 0: the Cmd ID answered, or %ECMSK_RSP_OP in OP
 * @crc_errors: byte 1: commands refused for a CRC error (wraps at 256)
 * @state: byte 2: the current EtherCAT state (%ECMSK_STATE_*)
 * @crc: byte 3: the frame's CRC-8 (when response CRCs are enabled)
 * @data1: bytes 4-7 (SET_AXIS: slaves detected; LIO_RD: inputs)
 * @data2: bytes 8-11
 * @data3: bytes 12-15 (16-byte slots only, else 0)
 * @fifo_remaining: bytes 8-9, meaningful in OP
 * @fifo_full: bytes 10-11, meaningful in OP
 */
struct ecmsk_ecm_rsp {
	u8 cmd;
	u8 crc_errors;
	u8 state;
	u8 crc;
	u32 data1;
	u32 data2;
	u32 data3;
	u16 fifo_remaining;
	u16 fifo_full;
};

/**
 * struct ecmsk_slave_cmd - a command in a slave slot
 * @cmd: byte 0
 * @index: byte 1, the host's Command Index, echoed in the answer
 * @target: bytes 4-7: position, velocity, torque or IO output; DRIVE_MODE:
 *	the mode of operation; 2-channel HSP: target 1
 * @value: bytes 8-11: CSP/CSV output value; DRIVE_MODE: the sync type;
 *	2-channel HSP: bytes 8-9 output 1, 10-11 the low half of target 2
 * @value3: bytes 12-15 (16-byte slots only)
 */
struct ecmsk_slave_cmd {
	u8 cmd;
	u8 index;
	u32 target;
	u32 value;
	u32 value3;
};

/**
 * struct ecmsk_slave_rsp - a slave slot of a response
 * @cmd: byte 0: the Cmd ID answered
 * @index: byte 1: its Command Index
 * @statusword: bytes 2-3 (0x6041)
 * @position: bytes 4-7: current position (0x6064); IO_RD: the inputs
 * @torque: bytes 8-9: current torque (0x6077); HSP: input status
 * @error_code: bytes 10-11: error code (0x603F)
 * @extra: bytes 12-15 (16-byte slots only, else 0)
 */
struct ecmsk_slave_rsp {
	u8 cmd;
	u8 index;
	u16 statusword;
	u32 position;
	u16 torque;
	u16 error_code;
	u32 extra;
};

/**
 * struct ecmsk_hsp2 - the 16-byte layout of a 2-channel HSP (tables 2.16
 * and 2.18): two targets/positions and two output/input words
 * @cmd: byte 0
 * @index: byte 1
 * @statusword: bytes 2-3 (responses only)
 * @pos1: bytes 4-7: target 1 (command) or current position 1 (response)
 * @io1: bytes 8-9: output value 1 (command) or input status 1 (response)
 * @pos2: bytes 10-13: target 2 or current position 2
 * @io2: bytes 14-15: output value 2 or input status 2
 */
struct ecmsk_hsp2 {
	u8 cmd;
	u8 index;
	u16 statusword;
	u32 pos1;
	u16 io1;
	u32 pos2;
	u16 io2;
};

/**
 * struct ecmsk_sdo - the SDO slot, command and response alike
 * @cmd: bytes 0-1: SDO_RD, SDO_WR (or GET_STATUS to fetch the result)
 * @status: byte 1 of a response: %ECMSK_SDO_DONE, %ECMSK_SDO_BUSY or
 *	%ECMSK_SDO_FAILED (then @value is the abort code); 0 in a command
 * @slave: byte 2: slave position 1..40
 * @size: byte 3: object size for SDO_WR (1, 2 or 4)
 * @subindex: byte 4
 * @index: bytes 6-7
 * @value: bytes 8-11: the value written or read, or the abort code
 */
struct ecmsk_sdo {
	u8 cmd;
	u8 status;
	u8 slave;
	u8 size;
	u8 subindex;
	u16 index;
	u32 value;
};

int ecmsk_put_ecm(const struct ecmsk_geom *g, u8 *frame,
		  const struct ecmsk_ecm_cmd *c);
int ecmsk_put_slave(const struct ecmsk_geom *g, u8 *frame, unsigned int slave,
		    const struct ecmsk_slave_cmd *c);
int ecmsk_put_hsp2(const struct ecmsk_geom *g, u8 *frame, unsigned int slave,
		   const struct ecmsk_hsp2 *c);
int ecmsk_put_sdo(const struct ecmsk_geom *g, u8 *frame,
		  const struct ecmsk_sdo *c);

void ecmsk_get_ecm(const struct ecmsk_geom *g, const u8 *frame,
		   struct ecmsk_ecm_rsp *r);
int ecmsk_get_slave(const struct ecmsk_geom *g, const u8 *frame,
		    unsigned int slave, struct ecmsk_slave_rsp *r);
int ecmsk_get_hsp2(const struct ecmsk_geom *g, const u8 *frame,
		   unsigned int slave, struct ecmsk_hsp2 *r);
void ecmsk_get_sdo(const struct ecmsk_geom *g, const u8 *frame,
		   struct ecmsk_sdo *r);

/* the firmware's side: decode commands, encode responses */
void ecmsk_get_ecm_cmd(const struct ecmsk_geom *g, const u8 *frame,
		       struct ecmsk_ecm_cmd *c);
int ecmsk_get_slave_cmd(const struct ecmsk_geom *g, const u8 *frame,
			unsigned int slave, struct ecmsk_slave_cmd *c);
int ecmsk_put_ecm_rsp(const struct ecmsk_geom *g, u8 *frame,
		      const struct ecmsk_ecm_rsp *r);
int ecmsk_put_slave_rsp(const struct ecmsk_geom *g, u8 *frame,
			unsigned int slave, const struct ecmsk_slave_rsp *r);
int ecmsk_put_hsp2_rsp(const struct ecmsk_geom *g, u8 *frame,
		       unsigned int slave, const struct ecmsk_hsp2 *r);
int ecmsk_put_sdo_rsp(const struct ecmsk_geom *g, u8 *frame,
		      const struct ecmsk_sdo *r);

/* command-specific helpers */
int ecmsk_axis_topology(const u8 *types, unsigned int count, unsigned int group,
			u32 *topology);
bool ecmsk_dc_cycle_valid(u32 cycle_us);
bool ecmsk_state_valid(u32 state);
bool ecmsk_cmd_known(u16 cmd);
bool ecmsk_cmd_is_slave(u8 cmd);
bool ecmsk_cmd_is_cyclic(u8 cmd);
unsigned int ecmsk_cmd_states(u16 cmd);
const char *ecmsk_cmd_name(u16 cmd);

/* ---------------------------------------------------------------------- */
/* Exchange tracking                                                      */
/* ---------------------------------------------------------------------- */

/* ecmsk_link.flags */
#define ECMSK_LINK_TX_CRC	0x1u	/* seal command frames with the CRC */
#define ECMSK_LINK_RX_CRC	0x2u	/* check the CRC of response frames */

/**
 * struct ecmsk_pending - a long command waiting for its completion
 * @active: a command is in flight
 * @cmd: its Cmd ID
 * @slave: its slave (SDO, GO_HOME) or 0
 * @target: SET_STATE: the requested state; SDO: the index << 8 | sub-index
 * @deadline: give up at this time (ns, the caller's clock; 0: never)
 * @seq: the exchange that sent it (1-based); responses of exchange
 *	@seq + 1 and later answer it
 * @started: GO_HOME: a statusword without "homing attained" was seen
 */
struct ecmsk_pending {
	bool active;
	u16 cmd;
	u8 slave;
	u32 target;
	u64 deadline;
	u64 seq;
	bool started;
};

/**
 * struct ecmsk_link - the state of a host's exchanges with one ECM-SK
 * @g: the frame geometry
 * @flags: %ECMSK_LINK_TX_CRC, %ECMSK_LINK_RX_CRC
 * @sent: the command (byte 0) sent in each slot by the last exchange,
 *	answered by the next one
 * @sent_index: the Command Index sent in each slave slot
 * @answering: what the response being decoded answers (the exchange
 *	before the last)
 * @answering_index: its Command Index per slot
 * @state: the last Current State seen
 * @crc_errors: the last Error Code seen (the board's counter, byte 1)
 * @refused: commands the board refused for a bad CRC (sum of the counter's
 *	increments seen)
 * @rx_crc_bad: responses whose CRC did not match
 * @exchanges: completed exchanges
 * @have_rsp: a response was decoded (the board's counters are known)
 * @ecm: the pending SET_STATE
 * @sdo: the pending SDO_RD/SDO_WR
 * @home: the slave whose GO_HOME is pending (one at a time on the bus)
 */
struct ecmsk_link {
	struct ecmsk_geom g;
	u32 flags;
	u8 sent[ECMSK_SLOTS_MAX];
	u8 sent_index[ECMSK_SLOTS_MAX];
	u8 answering[ECMSK_SLOTS_MAX];
	u8 answering_index[ECMSK_SLOTS_MAX];
	u8 state;
	u8 crc_errors;
	u32 refused;
	u32 rx_crc_bad;
	u64 exchanges;
	bool have_rsp;
	struct ecmsk_pending ecm;
	struct ecmsk_pending sdo;
	struct ecmsk_pending home;
};

/*
 * Completion of a pending command (ecmsk_link_poll()): still running,
 * done, or failed (reason in the result).
 */
#define ECMSK_POLL_NONE		0
#define ECMSK_POLL_RUNNING	1
#define ECMSK_POLL_DONE		2

/**
 * struct ecmsk_result - what one response says about the last exchange
 * @ecm: slot 0
 * @refused: commands refused for a bad CRC since the previous response
 * @state_done: the pending SET_STATE completed (or failed: @state_err)
 * @state_err: 0, -ETIMEDOUT when its deadline passed, -EBADMSG when the
 *	board refused it for a bad CRC
 * @sdo_done: the pending SDO completed (or failed: @sdo_err)
 * @sdo_err: 0, -EIO (aborted: @sdo.value is the abort code), -EPROTO
 *	(the answer names another object), -EACCES (not taken: the answer
 *	is not an SDO one, e.g. in INIT), -EBADMSG, -ETIMEDOUT
 * @sdo: the SDO slot
 * @home_done: the pending GO_HOME completed (or failed: @home_err)
 * @home_err: 0, -EIO (statusword bit 13, homing error), -EBADMSG,
 *	-ETIMEDOUT
 */
struct ecmsk_result {
	struct ecmsk_ecm_rsp ecm;
	u32 refused;
	bool state_done;
	int state_err;
	bool sdo_done;
	int sdo_err;
	struct ecmsk_sdo sdo;
	bool home_done;
	int home_err;
};

int ecmsk_link_init(struct ecmsk_link *l, unsigned int slot_size, u32 flags);
void ecmsk_link_reset(struct ecmsk_link *l);
int ecmsk_link_prepare(struct ecmsk_link *l, u8 *mosi, u64 now,
		       u64 timeout_ns);
int ecmsk_link_complete(struct ecmsk_link *l, const u8 *miso, u64 now,
			struct ecmsk_result *res);
bool ecmsk_link_answered(const struct ecmsk_link *l, unsigned int slot,
			 const u8 *miso);

#ifdef __cplusplus
}
#endif

#endif /* ECMSK_PROTO_H */
