// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-bits.c - the names of the header's bits (ECM-XF manual ver. 050,
 * the packet header tables; ver. 038 where it agrees)
 *
 * One table per header field that holds flags: the command's control byte
 * (0x0A) and reserved word (0x08), the response's error status (0x09) and
 * ECM status (0x0A; bits 1-0 are the check type, not flags), and the
 * interrupt word (0x10: the command's clear bits, the response's flags).
 * The trace decoder (lib/trace/trace.cpp) names set bits with them and
 * the Wireshark dissector's bit fields are generated from them
 * (utils/wireshark/ecmxf-lua-gen.cpp). Userspace only: the module names
 * no bits.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-proto.h"

static const struct ecmxf_bit_name ecmxf_control_bits[] = {
	{ 0, "refresh state" },    { 1, "clear CRC count" },
	{ 3, "clear async error" }, { 4, "clear SPI error" },
	{ 5, "clear FIFO error" },  { 6, "clear SPI CRC error" },
	{ 7, "clear command error" },
};

static const struct ecmxf_bit_name ecmxf_reserved_bits[] = {
	{ 11, "LRW" }, { 12, "bus shift" }, { 15, "GPIO out valid" },
};

static const struct ecmxf_bit_name ecmxf_err_bits[] = {
	{ 0, "link" },       { 1, "link at INIT_OP" }, { 3, "async error" },
	{ 4, "SPI error" },  { 5, "FIFO error" },      { 6, "SPI CRC error" },
	{ 7, "command error" },
};

static const struct ecmxf_bit_name ecmxf_ecm_bits[] = {
	{ 2, "DC stable" },      { 3, "Ethernet initialised" },
	{ 4, "PDO configured" }, { 5, "NOP" },
	{ 6, "FIFO enabled" },   { 7, "busy" },
};

static const struct ecmxf_bit_name ecmxf_int_bits[] = {
	{ 22, "WKC error" },  { 23, "CRC error" }, { 24, "TxFIFO high" },
	{ 25, "RxFIFO low" }, { 29, "encoder" },   { 31, "EtherCAT packet" },
};

#define ECMXF_BITS(t) { t, sizeof(t) / sizeof((t)[0]) }

static const struct {
	const struct ecmxf_bit_name *names;
	size_t count;
} ecmxf_bit_tables[ECMXF_BITS_FIELDS] = {
	[ECMXF_BITS_CONTROL] = ECMXF_BITS(ecmxf_control_bits),
	[ECMXF_BITS_RESERVED] = ECMXF_BITS(ecmxf_reserved_bits),
	[ECMXF_BITS_ERR_STATUS] = ECMXF_BITS(ecmxf_err_bits),
	[ECMXF_BITS_ECM_STATUS] = ECMXF_BITS(ecmxf_ecm_bits),
	[ECMXF_BITS_INT] = ECMXF_BITS(ecmxf_int_bits),
};

const struct ecmxf_bit_name *ecmxf_bit_names(enum ecmxf_bits_field field,
					     size_t *count)
{
	if ((unsigned int)field >= ECMXF_BITS_FIELDS) {
		*count = 0;
		return NULL;
	}
	*count = ecmxf_bit_tables[field].count;
	return ecmxf_bit_tables[field].names;
}
