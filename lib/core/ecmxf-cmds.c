// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-cmds.c - the command table of ECM-XF manual ver. 038 and ver. 050
 *
 * Names, immediate/async kind, the partner that fetches the result or
 * reads back a setting, the default time the engine allows, and what a
 * command does to the chip (the permission class, ecmxf_cmd_perm()).  The async
 * set is the one fixed in Documentation/protocol-core.rst;
 * RECV_MAILBOX is async only with command parameter 0.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-proto.h"

#define ECMXF_CMD_ROW(c, n, f, p, t) \
	{ .code = (c), .flags = (f), .partner = (p), .timeout_ms = (t), \
	  .name = (n) }

static const struct ecmxf_cmd_info ecmxf_cmds[] = {
	ECMXF_CMD_ROW(0, "INFO_UPDATE_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(1, "ECAT_INIT_OP",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 10000),
	ECMXF_CMD_ROW(2, "ECAT_RECONFIG_OP",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 5000),
	ECMXF_CMD_ROW(3, "ECAT_INIT_DC_OP",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 5000),
	ECMXF_CMD_ROW(4, "ECAT_PDO_WC_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(5, "ECAT_PDO_DATA_FIFO_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      -1, 100),
	ECMXF_CMD_ROW(6, "ECAT_PDO_DATA_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      -1, 100),
	ECMXF_CMD_ROW(7, "ECAT_PDO_CONFIG_SET",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      9, 3000),
	ECMXF_CMD_ROW(8, "ECAT_PDO_CONFIG_REQ",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      9, 3000),
	ECMXF_CMD_ROW(9, "ECAT_PDO_CONFIG_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(10, "ECAT_SDO_REQ",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      11, 5000),
	ECMXF_CMD_ROW(11, "ECAT_SDO_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(12, "ECAT_STATE_SET",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      13, 10000),
	ECMXF_CMD_ROW(13, "ECAT_STATE_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(15, "ECAT_SLV_INFO_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(16, "ECAT_SLV_CNT_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(18, "FIFO_ENABLE",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      -1, 100),
	ECMXF_CMD_ROW(19, "FIFO_PACK_SIZE_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(20, "SPI_PACK_SIZE_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(23, "SPI_RECONFIG_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_DESTRUCTIVE,
		      20, 1000),
	ECMXF_CMD_ROW(24, "CRC_ERR_CNT_CLR",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(25, "CRC_TYPE_SET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_DESTRUCTIVE,
		      -1, 100),
	ECMXF_CMD_ROW(26, "402_CONFIG_SET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(27, "402_STATE_SET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      28, 100),
	ECMXF_CMD_ROW(28, "402_STATE_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(29, "402_CTL_SET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      30, 100),
	ECMXF_CMD_ROW(30, "402_CTL_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(31, "GPIO_CONFIG_SET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(32, "GPIO_FUNC_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(33, "QEI_FUNC_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(34, "DAC_FUNC_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(35, "ADC_FUNC_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(38, "EEPROM_REQ",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_DESTRUCTIVE,
		      39, 3000),
	ECMXF_CMD_ROW(39, "EEPROM_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(41, "ECAT_STATE_CHECK",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      13, 10000),
	ECMXF_CMD_ROW(50, "ECAT_DCSYNC",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 3000),
	ECMXF_CMD_ROW(51, "FIFO_CLR_OP",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      -1, 100),
	ECMXF_CMD_ROW(52, "FIFO_SET_TX_CNT",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      53, 100),
	ECMXF_CMD_ROW(53, "FIFO_GET_TX_CNT",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(54, "FIFO_SET_RX_CNT",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      55, 100),
	ECMXF_CMD_ROW(55, "FIFO_GET_RX_CNT",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(56, "FW_VERSION_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(57, "ECAT_STATE_UPDATE",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      13, 3000),
	ECMXF_CMD_ROW(58, "ECAT_INT_SET_ENABLE",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      59, 100),
	ECMXF_CMD_ROW(59, "ECAT_INT_GET_ENABLE",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(66, "FIFO_INIT",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      -1, 100),
	ECMXF_CMD_ROW(69, "ECAT_SDO_ABORTCODE_GET",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(70, "ECAT_SET_FIFO_TH",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_PROCESS,
		      -1, 100),
	ECMXF_CMD_ROW(71, "ECAT_CONFIG_SM",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(72, "ECAT_CONFIG_FMMU",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_BUS | ECMXF_CMDF_OBSOLETE,
		      -1, 100),
	ECMXF_CMD_ROW(73, "ECAT_CONFIG_MAP",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 5000),
	ECMXF_CMD_ROW(74, "402_GET_STATUSWORD",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(75, "ASYNCCMD_RESET",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(81, "MDIO",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(82, "DIRECT_ASSIGN",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(83, "COE_EMERGENCY",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(127, "WARM_RESET",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V050 | ECMXF_CMDF_DESTRUCTIVE,
		      -1, 5000),
	ECMXF_CMD_ROW(130, "ECAT_WKC_CONTI_ERR_CNT_GET",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(131, "ECAT_WKC_CONTI_ERR_MAX_GET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(132, "ECAT_WKC_CONTI_ERR_MAX_SET",
		      ECMXF_CMDF_V038 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      131, 100),
	ECMXF_CMD_ROW(137, "RAW_ECAT_FUNC_REQ",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V050 | ECMXF_CMDF_DESTRUCTIVE,
		      138, 1000),
	ECMXF_CMD_ROW(138, "RAW_ECAT_FUNC_GET",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
	ECMXF_CMD_ROW(139, "FOE_FUNC_REQ",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_V050 | ECMXF_CMDF_DESTRUCTIVE,
		      140, 30000),
	ECMXF_CMD_ROW(140, "FOE_FUNC_GET",
		      ECMXF_CMDF_V050,
		      -1, 100),
	ECMXF_CMD_ROW(142, "ENABLE_LRW",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 100),
	ECMXF_CMD_ROW(143, "RECV_MAILBOX",
		      ECMXF_CMDF_ASYNC | ECMXF_CMDF_ASYNC_PARAM0 | ECMXF_CMDF_V050 | ECMXF_CMDF_BUS,
		      -1, 3000),
	ECMXF_CMD_ROW(144, "MBX_STAT",
		      ECMXF_CMDF_V050 | ECMXF_CMDF_IDEMPOTENT,
		      -1, 100),
};

#define ECMXF_NCMDS ARRAY_SIZE(ecmxf_cmds)

/**
 * ecmxf_cmd_lookup() - find a command's row
 * @code: command code
 *
 * Return: the row, or NULL for a code neither manual documents.
 */
const struct ecmxf_cmd_info *ecmxf_cmd_lookup(unsigned int code)
{
	size_t lo = 0, hi = ECMXF_NCMDS;

	/* the table is sorted by code */
	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;

		if (ecmxf_cmds[mid].code == code)
			return &ecmxf_cmds[mid];
		if (ecmxf_cmds[mid].code < code)
			lo = mid + 1;
		else
			hi = mid;
	}
	return NULL;
}

/**
 * ecmxf_cmd_table() - the whole table, sorted by code
 * @count: set to the number of rows
 *
 * Return: the first row.
 */
const struct ecmxf_cmd_info *ecmxf_cmd_table(size_t *count)
{
	if (count)
		*count = ECMXF_NCMDS;
	return ecmxf_cmds;
}

/**
 * ecmxf_cmd_is_async() - does the chip run this command asynchronously
 * @code: command code
 * @param: command parameter (RECV_MAILBOX is async only with 0)
 *
 * Return: true when the chip answers at once but stays busy until done.
 */
bool ecmxf_cmd_is_async(unsigned int code, unsigned int param)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(code);

	if (!ci || !(ci->flags & ECMXF_CMDF_ASYNC))
		return false;
	if (ci->flags & ECMXF_CMDF_ASYNC_PARAM0)
		return param == 0;
	return true;
}

/* EEPROM_REQ and RAW_ECAT_FUNC_REQ that only read (data byte 0) */
static bool ecmxf_cmd_only_reads(unsigned int code, const u8 *data, size_t len)
{
	if (!len)
		return false;
	switch (code) {
	case ECMXF_CMD_EEPROM_REQ:
		/* operation word: 0 read */
		return len >= 2 && data[0] == 0 && data[1] == 0;
	case ECMXF_CMD_RAW_ECAT_FUNC_REQ:
		/* datagram command: APRD, FPRD, BRD, LRD */
		return data[0] == 1 || data[0] == 4 || data[0] == 7 ||
		       data[0] == 10;
	default:
		return false;
	}
}

/**
 * ecmxf_cmd_perm() - the permission class of a command
 * @code: command code
 * @param: command parameter
 * @data: the data section the command carries
 * @len: bytes at @data
 *
 * The class of the table's row, refined where the parameter or the data
 * choose between reading and writing: the read sub-operations of
 * GPIO_FUNC_OP (get value, get interrupt flag) and QEI_FUNC_OP (get count)
 * are queries; an EEPROM_REQ read and a RAW_ECAT_FUNC_REQ read datagram
 * change no more than any bus command.  A code neither manual documents is
 * treated as destructive.
 *
 * Return: %ECMXF_PERM_QUERY, %ECMXF_PERM_CHIP, %ECMXF_PERM_PROCESS or
 * %ECMXF_PERM_ADMIN.
 */
enum ecmxf_perm ecmxf_cmd_perm(unsigned int code, unsigned int param,
			       const u8 *data, size_t len)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(code);

	if (!ci)
		return ECMXF_PERM_ADMIN;
	if (ci->flags & ECMXF_CMDF_DESTRUCTIVE)
		return ecmxf_cmd_only_reads(code, data, len) ?
		       ECMXF_PERM_CHIP : ECMXF_PERM_ADMIN;
	if (ci->flags & ECMXF_CMDF_PROCESS)
		return ECMXF_PERM_PROCESS;
	if (!(ci->flags & ECMXF_CMDF_BUS))
		return ECMXF_PERM_QUERY;
	if (code == ECMXF_CMD_GPIO_FUNC_OP &&
	    (param == 1 || param == 3 || param == 5 || param == 7))
		return ECMXF_PERM_QUERY;
	if (code == ECMXF_CMD_QEI_FUNC_OP && param == 21)
		return ECMXF_PERM_QUERY;
	return ECMXF_PERM_CHIP;
}

/**
 * ecmxf_rsv_valid() - are the bits of a header's reserved word allowed?
 * @code: command code
 * @rsv: the 16-bit word at packet offset 0x08 (%ECMXF_RSV_*)
 *
 * The manuals give the word three meanings: bit 15 marks the GPIO
 * outputs of the header valid (any command), bits 11 (LRW) and 12 (bus
 * shift mode) are options of ECAT_INIT_OP.  Every other bit, and bits 11
 * and 12 with another command, is reserved and must be zero
 * (Documentation/uapi.rst, "Commands").
 *
 * Return: true when @rsv sets no reserved bit.
 */
bool ecmxf_rsv_valid(unsigned int code, unsigned int rsv)
{
	unsigned int allowed = ECMXF_RSV_GPIO_OUT;

	if (code == ECMXF_CMD_ECAT_INIT_OP)
		allowed |= ECMXF_RSV_LRW | ECMXF_RSV_BUS_SHIFT;
	return !(rsv & ~allowed);
}
