// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmsk-frame.c - ECM-SK frame geometry, CRC-8 and slot encode/decode
 *
 * Every multi-byte field is little-endian (quick start 2.1).  The CRC-8
 * (x^8 + x^2 + x + 1, initial value 0x5A, not reflected, no final xor)
 * covers the whole frame with byte 3 of slot 0 counted as zero (2.2).
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmsk-proto.h"
#include "ecmxf-proto.h"

/**
 * ecmsk_geom_init() - the frame layout for a slot size
 * @g: filled in
 * @slot_size: %ECMSK_SLOT12 or %ECMSK_SLOT16 (the board's CONFIG2)
 *
 * Return: 0, or -EINVAL for any other slot size (@g is then zeroed).
 */
int ecmsk_geom_init(struct ecmsk_geom *g, unsigned int slot_size)
{
	memset(g, 0, sizeof(*g));
	if (slot_size == ECMSK_SLOT12)
		g->slots = ECMSK_SLOTS12;
	else if (slot_size == ECMSK_SLOT16)
		g->slots = ECMSK_SLOTS16;
	else
		return -EINVAL;
	g->slot_size = (u8)slot_size;
	g->max_slaves = (u8)(g->slots - 2);
	g->sdo_slot = (u8)(g->slots - 1);
	g->frame_size = (u16)(g->slots * slot_size);
	return 0;
}

/**
 * ecmsk_crc8() - the CRC-8 of a frame, byte 3 counted as zero
 * @frame: the frame
 * @len: its length (504 or 512; any length >= 4 is computed)
 *
 * Return: the CRC, or the CRC of the bytes given when @len < 4.
 */
u8 ecmsk_crc8(const u8 *frame, size_t len)
{
	static const u8 zero;
	u8 crc;

	if (len <= ECMSK_CRC_OFFSET)
		return ecmxf_crc8_update(ECMSK_CRC_INIT, frame, len);
	crc = ecmxf_crc8_update(ECMSK_CRC_INIT, frame, ECMSK_CRC_OFFSET);
	crc = ecmxf_crc8_update(crc, &zero, 1);	/* byte 3 counted as 0 */
	return ecmxf_crc8_update(crc, frame + ECMSK_CRC_OFFSET + 1,
				 len - ECMSK_CRC_OFFSET - 1);
}

/**
 * ecmsk_frame_seal() - store the frame's CRC-8 in byte 3
 * @frame: the frame
 * @len: its length (at least 4)
 */
void ecmsk_frame_seal(u8 *frame, size_t len)
{
	if (len > ECMSK_CRC_OFFSET)
		frame[ECMSK_CRC_OFFSET] = ecmsk_crc8(frame, len);
}

/**
 * ecmsk_frame_crc_ok() - does byte 3 hold the frame's CRC-8?
 * @frame: the frame
 * @len: its length
 *
 * Return: true when it does (false for a frame shorter than 4 bytes).
 */
bool ecmsk_frame_crc_ok(const u8 *frame, size_t len)
{
	return len > ECMSK_CRC_OFFSET &&
	       frame[ECMSK_CRC_OFFSET] == ecmsk_crc8(frame, len);
}

static u8 *slot_ptr(const struct ecmsk_geom *g, u8 *frame, unsigned int slot)
{
	return frame + (size_t)slot * g->slot_size;
}

static const u8 *slot_cptr(const struct ecmsk_geom *g, const u8 *frame,
			   unsigned int slot)
{
	return frame + (size_t)slot * g->slot_size;
}

static bool slave_ok(const struct ecmsk_geom *g, unsigned int slave)
{
	return slave >= 1 && slave <= g->max_slaves;
}

/**
 * ecmsk_put_ecm() - encode a command into slot 0
 * @g: the geometry
 * @frame: the frame (@g->frame_size bytes)
 * @c: the command
 *
 * Byte 3 (the CRC) is left as it is: ecmsk_frame_seal() sets it last.
 * @c->data3 is written only with 16-byte slots.
 *
 * Return: 0, or -EINVAL when @c->data3 is not 0 with 12-byte slots.
 */
int ecmsk_put_ecm(const struct ecmsk_geom *g, u8 *frame,
		  const struct ecmsk_ecm_cmd *c)
{
	u8 *s = frame;

	if (g->slot_size == ECMSK_SLOT12 && c->data3)
		return -EINVAL;
	put_unaligned_le16(c->cmd, s);
	s[2] = c->param;
	put_unaligned_le32(c->data1, s + 4);
	put_unaligned_le32(c->data2, s + 8);
	if (g->slot_size == ECMSK_SLOT16)
		put_unaligned_le32(c->data3, s + 12);
	return 0;
}

/**
 * ecmsk_put_slave() - encode a command into a slave slot
 * @g: the geometry
 * @frame: the frame
 * @slave: slave position, 1..@g->max_slaves
 * @c: the command
 *
 * Return: 0, -ERANGE for a slave outside the frame, -EINVAL when
 * @c->value3 is not 0 with 12-byte slots.
 */
int ecmsk_put_slave(const struct ecmsk_geom *g, u8 *frame, unsigned int slave,
		    const struct ecmsk_slave_cmd *c)
{
	u8 *s;

	if (!slave_ok(g, slave))
		return -ERANGE;
	if (g->slot_size == ECMSK_SLOT12 && c->value3)
		return -EINVAL;
	s = slot_ptr(g, frame, slave);
	s[0] = c->cmd;
	s[1] = c->index;
	s[2] = 0;
	s[3] = 0;
	put_unaligned_le32(c->target, s + 4);
	put_unaligned_le32(c->value, s + 8);
	if (g->slot_size == ECMSK_SLOT16)
		put_unaligned_le32(c->value3, s + 12);
	return 0;
}

static void hsp2_put(u8 *s, const struct ecmsk_hsp2 *c, bool rsp)
{
	s[0] = c->cmd;
	s[1] = c->index;
	put_unaligned_le16(rsp ? c->statusword : 0, s + 2);
	put_unaligned_le32(c->pos1, s + 4);
	put_unaligned_le16(c->io1, s + 8);
	put_unaligned_le32(c->pos2, s + 10);
	put_unaligned_le16(c->io2, s + 14);
}

static void hsp2_get(const u8 *s, struct ecmsk_hsp2 *r)
{
	r->cmd = s[0];
	r->index = s[1];
	r->statusword = get_unaligned_le16(s + 2);
	r->pos1 = get_unaligned_le32(s + 4);
	r->io1 = get_unaligned_le16(s + 8);
	r->pos2 = get_unaligned_le32(s + 10);
	r->io2 = get_unaligned_le16(s + 14);
}

/**
 * ecmsk_put_hsp2() - encode a 2-channel HSP command (16-byte slots only)
 * @g: the geometry
 * @frame: the frame
 * @slave: slave position
 * @c: the command (@c->statusword is not sent)
 *
 * Return: 0, -ERANGE for a slave outside the frame, -EINVAL with 12-byte
 * slots (a 2-channel HSP needs CONFIG2 high).
 */
int ecmsk_put_hsp2(const struct ecmsk_geom *g, u8 *frame, unsigned int slave,
		   const struct ecmsk_hsp2 *c)
{
	if (g->slot_size != ECMSK_SLOT16)
		return -EINVAL;
	if (!slave_ok(g, slave))
		return -ERANGE;
	hsp2_put(slot_ptr(g, frame, slave), c, false);
	return 0;
}

/**
 * ecmsk_put_hsp2_rsp() - encode a 2-channel HSP slot of a response
 * @g: the geometry (16-byte slots)
 * @frame: the response frame
 * @slave: slave position
 * @r: the response, statusword included
 *
 * Return: 0, -ERANGE for a slave outside the frame, -EINVAL with 12-byte
 * slots.
 */
int ecmsk_put_hsp2_rsp(const struct ecmsk_geom *g, u8 *frame,
		       unsigned int slave, const struct ecmsk_hsp2 *r)
{
	if (g->slot_size != ECMSK_SLOT16)
		return -EINVAL;
	if (!slave_ok(g, slave))
		return -ERANGE;
	hsp2_put(slot_ptr(g, frame, slave), r, true);
	return 0;
}

static void sdo_put(u8 *s, const struct ecmsk_sdo *c, bool rsp)
{
	s[0] = c->cmd;
	s[1] = rsp ? c->status : 0;
	s[2] = c->slave;
	s[3] = c->size;
	s[4] = c->subindex;
	s[5] = 0;
	put_unaligned_le16(c->index, s + 6);
	put_unaligned_le32(c->value, s + 8);
}

/**
 * ecmsk_put_sdo() - encode a command into the SDO slot
 * @g: the geometry
 * @frame: the frame
 * @c: the command (@c->status is not sent)
 *
 * Return: 0, -EINVAL for an SDO_WR whose size is not 1, 2 or 4 or whose
 * value does not fit that size, -ERANGE for a slave outside 1..max.
 */
int ecmsk_put_sdo(const struct ecmsk_geom *g, u8 *frame,
		  const struct ecmsk_sdo *c)
{
	if (c->cmd == ECMSK_CMD_SDO_RD || c->cmd == ECMSK_CMD_SDO_WR) {
		if (!slave_ok(g, c->slave))
			return -ERANGE;
	}
	if (c->cmd == ECMSK_CMD_SDO_WR) {
		if (c->size != 1 && c->size != 2 && c->size != 4)
			return -EINVAL;
		if (c->size < 4 && (c->value >> (8 * c->size)))
			return -EINVAL;
	}
	sdo_put(slot_ptr(g, frame, g->sdo_slot), c, false);
	return 0;
}

/**
 * ecmsk_get_ecm() - decode slot 0 of a response
 * @g: the geometry
 * @frame: the response frame
 * @r: filled in; the FIFO counts are bytes 8-11 read as two halves
 */
void ecmsk_get_ecm(const struct ecmsk_geom *g, const u8 *frame,
		   struct ecmsk_ecm_rsp *r)
{
	r->cmd = frame[0];
	r->crc_errors = frame[1];
	r->state = frame[2];
	r->crc = frame[3];
	r->data1 = get_unaligned_le32(frame + 4);
	r->data2 = get_unaligned_le32(frame + 8);
	r->data3 = g->slot_size == ECMSK_SLOT16 ?
		   get_unaligned_le32(frame + 12) : 0;
	r->fifo_remaining = get_unaligned_le16(frame + 8);
	r->fifo_full = get_unaligned_le16(frame + 10);
}

/**
 * ecmsk_get_slave() - decode a slave slot of a response
 * @g: the geometry
 * @frame: the response frame
 * @slave: slave position
 * @r: filled in
 *
 * Return: 0, or -ERANGE for a slave outside the frame.
 */
int ecmsk_get_slave(const struct ecmsk_geom *g, const u8 *frame,
		    unsigned int slave, struct ecmsk_slave_rsp *r)
{
	const u8 *s;

	if (!slave_ok(g, slave))
		return -ERANGE;
	s = slot_cptr(g, frame, slave);
	r->cmd = s[0];
	r->index = s[1];
	r->statusword = get_unaligned_le16(s + 2);
	r->position = get_unaligned_le32(s + 4);
	r->torque = get_unaligned_le16(s + 8);
	r->error_code = get_unaligned_le16(s + 10);
	r->extra = g->slot_size == ECMSK_SLOT16 ?
		   get_unaligned_le32(s + 12) : 0;
	return 0;
}

/**
 * ecmsk_get_hsp2() - decode a 2-channel HSP slot of a response
 * @g: the geometry (16-byte slots)
 * @frame: the response frame
 * @slave: slave position
 * @r: filled in
 *
 * Return: 0, -ERANGE for a slave outside the frame, -EINVAL with 12-byte
 * slots.
 */
int ecmsk_get_hsp2(const struct ecmsk_geom *g, const u8 *frame,
		   unsigned int slave, struct ecmsk_hsp2 *r)
{
	if (g->slot_size != ECMSK_SLOT16)
		return -EINVAL;
	if (!slave_ok(g, slave))
		return -ERANGE;
	hsp2_get(slot_cptr(g, frame, slave), r);
	return 0;
}

static void sdo_get(const u8 *s, struct ecmsk_sdo *r)
{
	r->cmd = s[0];
	r->status = s[1];
	r->slave = s[2];
	r->size = s[3];
	r->subindex = s[4];
	r->index = get_unaligned_le16(s + 6);
	r->value = get_unaligned_le32(s + 8);
}

/**
 * ecmsk_get_sdo() - decode the SDO slot (of a response or a command)
 * @g: the geometry
 * @frame: the frame
 * @r: filled in
 */
void ecmsk_get_sdo(const struct ecmsk_geom *g, const u8 *frame,
		   struct ecmsk_sdo *r)
{
	sdo_get(slot_cptr(g, frame, g->sdo_slot), r);
}

/**
 * ecmsk_get_ecm_cmd() - decode slot 0 of a command frame (firmware side)
 * @g: the geometry
 * @frame: the command frame
 * @c: filled in
 */
void ecmsk_get_ecm_cmd(const struct ecmsk_geom *g, const u8 *frame,
		       struct ecmsk_ecm_cmd *c)
{
	c->cmd = get_unaligned_le16(frame);
	c->param = frame[2];
	c->data1 = get_unaligned_le32(frame + 4);
	c->data2 = get_unaligned_le32(frame + 8);
	c->data3 = g->slot_size == ECMSK_SLOT16 ?
		   get_unaligned_le32(frame + 12) : 0;
}

/**
 * ecmsk_get_slave_cmd() - decode a slave slot of a command frame
 * @g: the geometry
 * @frame: the command frame
 * @slave: slave position
 * @c: filled in
 *
 * Return: 0, or -ERANGE for a slave outside the frame.
 */
int ecmsk_get_slave_cmd(const struct ecmsk_geom *g, const u8 *frame,
			unsigned int slave, struct ecmsk_slave_cmd *c)
{
	const u8 *s;

	if (!slave_ok(g, slave))
		return -ERANGE;
	s = slot_cptr(g, frame, slave);
	c->cmd = s[0];
	c->index = s[1];
	c->target = get_unaligned_le32(s + 4);
	c->value = get_unaligned_le32(s + 8);
	c->value3 = g->slot_size == ECMSK_SLOT16 ?
		    get_unaligned_le32(s + 12) : 0;
	return 0;
}

/**
 * ecmsk_put_ecm_rsp() - encode slot 0 of a response (firmware side)
 * @g: the geometry
 * @frame: the response frame
 * @r: the response; in OP its FIFO counts replace @r->data2 (bytes 8-11)
 *
 * Byte 3 is left to ecmsk_frame_seal().
 *
 * Return: 0.
 */
int ecmsk_put_ecm_rsp(const struct ecmsk_geom *g, u8 *frame,
		      const struct ecmsk_ecm_rsp *r)
{
	frame[0] = r->cmd;
	frame[1] = r->crc_errors;
	frame[2] = r->state;
	put_unaligned_le32(r->data1, frame + 4);
	if (r->state == ECMSK_STATE_OP) {
		put_unaligned_le16(r->fifo_remaining, frame + 8);
		put_unaligned_le16(r->fifo_full, frame + 10);
	} else {
		put_unaligned_le32(r->data2, frame + 8);
	}
	if (g->slot_size == ECMSK_SLOT16)
		put_unaligned_le32(r->data3, frame + 12);
	return 0;
}

/**
 * ecmsk_put_slave_rsp() - encode a slave slot of a response
 * @g: the geometry
 * @frame: the response frame
 * @slave: slave position
 * @r: the response
 *
 * Return: 0, or -ERANGE for a slave outside the frame.
 */
int ecmsk_put_slave_rsp(const struct ecmsk_geom *g, u8 *frame,
			unsigned int slave, const struct ecmsk_slave_rsp *r)
{
	u8 *s;

	if (!slave_ok(g, slave))
		return -ERANGE;
	s = slot_ptr(g, frame, slave);
	s[0] = r->cmd;
	s[1] = r->index;
	put_unaligned_le16(r->statusword, s + 2);
	put_unaligned_le32(r->position, s + 4);
	put_unaligned_le16(r->torque, s + 8);
	put_unaligned_le16(r->error_code, s + 10);
	if (g->slot_size == ECMSK_SLOT16)
		put_unaligned_le32(r->extra, s + 12);
	return 0;
}

/**
 * ecmsk_put_sdo_rsp() - encode the SDO slot of a response
 * @g: the geometry
 * @frame: the response frame
 * @r: the response (with its status)
 *
 * Return: 0.
 */
int ecmsk_put_sdo_rsp(const struct ecmsk_geom *g, u8 *frame,
		      const struct ecmsk_sdo *r)
{
	sdo_put(slot_ptr(g, frame, g->sdo_slot), r, true);
	return 0;
}

/**
 * ecmsk_axis_topology() - SET_AXIS's topology word for one group
 * @types: slave types (%ECMSK_AXIS_*) of slaves 1..@count
 * @count: number of entries in @types (at most 40)
 * @group: the group, 0..4: slaves 8 * @group + 1 .. 8 * @group + 8
 * @topology: filled in: 4 bits per slave, slave n + 1 in bits 3..0;
 *	slaves beyond @count are %ECMSK_AXIS_NONE
 *
 * Return: 0, -EINVAL for a group outside 0..4, a count above 40 or a type
 * other than Drive, IO, HSP or STEP.
 */
int ecmsk_axis_topology(const u8 *types, unsigned int count, unsigned int group,
			u32 *topology)
{
	unsigned int i;
	u32 t = 0;

	if (group >= ECMSK_AXIS_GROUPS || count > ECMSK_SLAVES_MAX)
		return -EINVAL;
	for (i = 0; i < 8; i++) {
		unsigned int n = group * 8 + i;
		u32 v = ECMSK_AXIS_NONE;

		if (n < count) {
			if (types[n] > ECMSK_AXIS_STEP)
				return -EINVAL;
			v = types[n];
		}
		t |= v << (4 * i);
	}
	*topology = t;
	return 0;
}

/**
 * ecmsk_dc_cycle_valid() - is a SET_DC cycle time 250 * 2^n us?
 * @cycle_us: the cycle time in microseconds
 *
 * Return: true for 250, 500, 1000, ... (up to 250 * 2^20).
 */
bool ecmsk_dc_cycle_valid(u32 cycle_us)
{
	u32 q;

	if (cycle_us < ECMSK_DC_MIN_US || cycle_us % ECMSK_DC_MIN_US)
		return false;
	q = cycle_us / ECMSK_DC_MIN_US;
	return q <= (1u << 20) && !(q & (q - 1));
}

/**
 * ecmsk_state_valid() - is a value one of the four EtherCAT states?
 * @state: the value
 *
 * Return: true for INIT, PRE-OP, SAFE-OP and OP.
 */
bool ecmsk_state_valid(u32 state)
{
	return state == ECMSK_STATE_INIT || state == ECMSK_STATE_PREOP ||
	       state == ECMSK_STATE_SAFEOP || state == ECMSK_STATE_OP;
}

#define ST_ALL	(ECMSK_STATE_INIT | ECMSK_STATE_PREOP | ECMSK_STATE_SAFEOP | \
		 ECMSK_STATE_OP)

/*
 * Table 1.3.  SET_AXIS, SET_DC and DRIVE_MODE are marked for INIT and
 * PRE-OP in the table; their sections say PRE-OP only, and the digest
 * keeps the table (SET_AXIS answers 0 slaves in INIT).
 */
static const struct {
	u16 cmd;
	u8 states;
	const char *name;
} ecmsk_cmds[] = {
	{ ECMSK_CMD_GET_STATUS, ST_ALL, "GET_STATUS" },
	{ ECMSK_CMD_SET_STATE, ST_ALL, "SET_STATE" },
	{ ECMSK_CMD_SET_AXIS, ECMSK_STATE_INIT | ECMSK_STATE_PREOP, "SET_AXIS" },
	{ ECMSK_CMD_SET_DC, ECMSK_STATE_INIT | ECMSK_STATE_PREOP, "SET_DC" },
	{ ECMSK_CMD_SET_EX, ECMSK_STATE_INIT | ECMSK_STATE_PREOP |
	  ECMSK_STATE_SAFEOP, "SET_EX" },
	{ ECMSK_CMD_SET_FIFO, ECMSK_STATE_OP, "SET_FIFO" },
	{ ECMSK_CMD_DRIVE_MODE, ECMSK_STATE_INIT | ECMSK_STATE_PREOP,
	  "DRIVE_MODE" },
	{ ECMSK_CMD_SDO_RD, ECMSK_STATE_PREOP | ECMSK_STATE_SAFEOP |
	  ECMSK_STATE_OP, "SDO_RD" },
	{ ECMSK_CMD_SDO_WR, ECMSK_STATE_PREOP | ECMSK_STATE_SAFEOP |
	  ECMSK_STATE_OP, "SDO_WR" },
	{ ECMSK_CMD_ALM_CLR, ECMSK_STATE_OP, "ALM_CLR" },
	{ ECMSK_CMD_SV_ON, ECMSK_STATE_OP, "SV_ON" },
	{ ECMSK_CMD_SV_OFF, ECMSK_STATE_OP, "SV_OFF" },
	{ ECMSK_CMD_IO_RD, ECMSK_STATE_OP, "IO_RD" },
	{ ECMSK_CMD_IO_WR, ECMSK_STATE_OP, "IO_WR" },
	{ ECMSK_CMD_CSP, ECMSK_STATE_OP, "CSP" },
	{ ECMSK_CMD_CSV, ECMSK_STATE_OP, "CSV" },
	{ ECMSK_CMD_CST, ECMSK_STATE_OP, "CST" },
	{ ECMSK_CMD_GO_HOME, ECMSK_STATE_OP, "GO_HOME" },
	{ ECMSK_CMD_ABORT_HOME, ECMSK_STATE_OP, "ABORT_HOME" },
	{ ECMSK_CMD_LIO_RD, ST_ALL, "LIO_RD" },
	{ ECMSK_CMD_LIO_WR, ST_ALL, "LIO_WR" },
	{ ECMSK_CMD_SW_RESET, ST_ALL, "SW_RESET" },
};

static int cmd_find(u16 cmd)
{
	unsigned int i;

	for (i = 0; i < ARRAY_SIZE(ecmsk_cmds); i++)
		if (ecmsk_cmds[i].cmd == cmd)
			return (int)i;
	return -1;
}

/**
 * ecmsk_cmd_known() - is @cmd a command of table 1.3?
 * @cmd: Cmd ID
 *
 * Return: true when it is.
 */
bool ecmsk_cmd_known(u16 cmd)
{
	return cmd_find(cmd) >= 0;
}

/**
 * ecmsk_cmd_states() - the states a command is allowed in (table 1.3)
 * @cmd: Cmd ID
 *
 * Return: a mask of %ECMSK_STATE_* bits, 0 for an unknown command.
 */
unsigned int ecmsk_cmd_states(u16 cmd)
{
	int i = cmd_find(cmd);

	return i < 0 ? 0 : ecmsk_cmds[i].states;
}

/**
 * ecmsk_cmd_name() - the manual's name of a command
 * @cmd: Cmd ID
 *
 * Return: e.g. "SET_STATE", or "?" for an unknown command.
 */
const char *ecmsk_cmd_name(u16 cmd)
{
	int i = cmd_find(cmd);

	return i < 0 ? "?" : ecmsk_cmds[i].name;
}

/**
 * ecmsk_cmd_is_slave() - does a command go into a slave slot?
 * @cmd: Cmd ID
 *
 * Return: true for DRIVE_MODE and 0x10..0x19.
 */
bool ecmsk_cmd_is_slave(u8 cmd)
{
	return cmd == ECMSK_CMD_DRIVE_MODE ||
	       (cmd >= ECMSK_CMD_ALM_CLR && cmd <= ECMSK_CMD_ABORT_HOME);
}

/**
 * ecmsk_cmd_is_cyclic() - is a command queued in the ECM's FIFO?
 * @cmd: Cmd ID
 *
 * Return: true for CSP, CSV and CST.
 */
bool ecmsk_cmd_is_cyclic(u8 cmd)
{
	return cmd == ECMSK_CMD_CSP || cmd == ECMSK_CMD_CSV ||
	       cmd == ECMSK_CMD_CST;
}
