// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-crc.c - check words of the ECM-XF packet
 *
 * CRC-32 comes from the platform where it has one (crc32_le() in the
 * kernel) and from a slice-by-8 table here otherwise.  CRC-8 and
 * CRC-CCITT-FALSE exist only in firmware ver. 038 and use small tables.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-proto.h"
#include "ecmxf-crc-tables.h"
#include "ecmxf-crc-simd.h"

#ifdef __KERNEL__
#include <linux/crc32.h>
#endif

/**
 * ecmxf_crc8_update() - CRC-8, poly 0x07, not reflected, from @crc on
 * @crc: the CRC so far (the initial value for the first bytes)
 * @buf: bytes to check
 * @len: number of bytes
 *
 * Eight bytes per step.  Also the ECM-SK frame's CRC (initial value 0x5A,
 * ecmsk-frame.c).
 *
 * Return: the CRC after @buf.
 */
u8 ecmxf_crc8_update(u8 crc, const void *buf, size_t len)
{
	const u8 (*t)[256] = ecmxf_crc8_table;
	const u8 *p = buf;

	for (; len >= 8; len -= 8, p += 8)
		crc = t[7][crc ^ p[0]] ^ t[6][p[1]] ^ t[5][p[2]] ^ t[4][p[3]] ^
		      t[3][p[4]] ^ t[2][p[5]] ^ t[1][p[6]] ^ t[0][p[7]];
	while (len--)
		crc = t[0][crc ^ *p++];
	return crc;
}

/**
 * ecmxf_crc8() - CRC-8, poly 0x07, init 0, no reflection, no final xor
 * @buf: bytes to check
 * @len: number of bytes
 *
 * Return: the CRC ("123456789" gives 0xF4).
 */
u8 ecmxf_crc8(const void *buf, size_t len)
{
	return ecmxf_crc8_update(0, buf, len);
}

/**
 * ecmxf_crc_ccitt() - CRC-CCITT-FALSE, poly 0x1021, init 0xFFFF
 * @buf: bytes to check
 * @len: number of bytes
 *
 * Return: the CRC ("123456789" gives 0x29B1).
 */
u16 ecmxf_crc_ccitt(const void *buf, size_t len)
{
	const u8 *p = buf;
	u16 crc = 0xFFFF;

	while (len--)
		crc = (u16)((crc << 8) ^ ecmxf_ccitt_table[(crc >> 8) ^ *p++]);
	return crc;
}

/**
 * ecmxf_crc32() - CRC-32 as zlib and Ethernet compute it
 * @buf: bytes to check
 * @len: number of bytes
 *
 * Reflected poly 0x04C11DB7, init and final xor 0xFFFFFFFF.
 *
 * Return: the CRC ("123456789" gives 0xCBF43926).
 */
u32 ecmxf_crc32(const void *buf, size_t len)
{
#ifdef __KERNEL__
	return crc32_le(~0u, buf, len) ^ ~0u;
#else
	const u8 *p = buf;
	u32 crc = ~0u;

#ifdef ECMXF_HAVE_CRC32_CLMUL
	if (len >= 64 && ecmxf_crc32_clmul_usable()) {
		size_t block = len & ~(size_t)15;

		crc = ecmxf_crc32_clmul(crc, p, block);
		p += block;
		len -= block;
	}
#endif
	while (len && ((uintptr_t)p & 7)) {
		crc = (crc >> 8) ^ ecmxf_crc32_table[0][(crc ^ *p++) & 0xFF];
		len--;
	}
	while (len >= 8) {
		u32 lo = get_unaligned_le32(p) ^ crc;
		u32 hi = get_unaligned_le32(p + 4);

		crc = ecmxf_crc32_table[7][lo & 0xFF] ^
		      ecmxf_crc32_table[6][(lo >> 8) & 0xFF] ^
		      ecmxf_crc32_table[5][(lo >> 16) & 0xFF] ^
		      ecmxf_crc32_table[4][lo >> 24] ^
		      ecmxf_crc32_table[3][hi & 0xFF] ^
		      ecmxf_crc32_table[2][(hi >> 8) & 0xFF] ^
		      ecmxf_crc32_table[1][(hi >> 16) & 0xFF] ^
		      ecmxf_crc32_table[0][hi >> 24];
		p += 8;
		len -= 8;
	}
	while (len--)
		crc = (crc >> 8) ^ ecmxf_crc32_table[0][(crc ^ *p++) & 0xFF];
	return ~crc;
#endif
}

/**
 * ecmxf_check_word() - the check word for a packet's covered bytes
 * @check: check type (%ECMXF_CHECK_COVER_VALID is ignored: @len is the
 *	covered length, see ecmxf_check_span())
 * @buf: the covered bytes: header and data section
 * @len: their length
 *
 * Return: the 32-bit check word (CRC-8 and CRC-CCITT zero-extended).
 */
u32 ecmxf_check_word(enum ecmxf_check check, const void *buf, size_t len)
{
	switch ((unsigned int)check & ECMXF_CHECK_TYPE_MASK) {
	case ECMXF_CHECK_CRC8:
		return ecmxf_crc8(buf, len);
	case ECMXF_CHECK_CCITT:
		return ecmxf_crc_ccitt(buf, len);
	case ECMXF_CHECK_CRC32:
		return ecmxf_crc32(buf, len);
	case ECMXF_CHECK_FIXED:
	default:
		return ECMXF_FIXED_CHECK;
	}
}
