// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-selftest.c - load-time self-test of the protocol core
 *
 * The protocol core (lib/core, shared with userspace through the
 * kmod/core symlink) is checked at module load to compute in kernel space
 * what it computes in userspace: the three CRC check values and one
 * encode/decode round trip per check type.  A mismatch fails the load
 * with -EINVAL (see ecmxf_init()).
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/init.h>
#include <linux/kernel.h>
#include <linux/printk.h>
#include <linux/string.h>

#include "ecmxf.h"

/* The catalogue check input of every CRC ("123456789", no NUL) */
static const char ecmxf_check_input[] __initconst = "123456789";
#define ECMXF_CHECK_INPUT_LEN	(sizeof(ecmxf_check_input) - 1)

static int __init ecmxf_selftest_crc(void)
{
	const void *in = ecmxf_check_input;
	size_t len = ECMXF_CHECK_INPUT_LEN;
	u32 crc32 = ecmxf_crc32(in, len);
	u16 ccitt = ecmxf_crc_ccitt(in, len);
	u8 crc8 = ecmxf_crc8(in, len);
	int ret = 0;

	if (crc32 != 0xCBF43926) {
		pr_err("self-test: CRC-32 of \"123456789\" is 0x%08x, expected 0xcbf43926\n",
		       crc32);
		ret = -EINVAL;
	}
	if (crc8 != 0xF4) {
		pr_err("self-test: CRC-8 of \"123456789\" is 0x%02x, expected 0xf4\n",
		       crc8);
		ret = -EINVAL;
	}
	if (ccitt != 0x29B1) {
		pr_err("self-test: CRC-CCITT of \"123456789\" is 0x%04x, expected 0x29b1\n",
		       ccitt);
		ret = -EINVAL;
	}
	return ret;
}

/*
 * Encode one command packet, decode it again and compare; then corrupt
 * one data byte and require the decoder to reject the packet (for the
 * fixed check word, which covers nothing, the end word is corrupted).
 */
static int __init ecmxf_selftest_codec(enum ecmxf_check check)
{
	static const u8 payload[] = { 0xde, 0xad, 0xbe, 0xef, 0x01, 0x02 };
	u8 pkt[ECMXF_PKT_SIZE(ECMXF_DATA_MIN)];
	struct ecmxf_cmd_hdr tx, rx;
	enum ecmxf_fault fault;
	const u8 *data = NULL;
	int ret;

	memset(&tx, 0, sizeof(tx));
	memset(&rx, 0, sizeof(rx));
	tx.data[0] = 0x01;
	tx.data[1] = 0x02;
	tx.data[2] = 0x03;
	tx.data[3] = 0x04;
	tx.reserved = ECMXF_RSV_LRW;
	tx.control = ECMXF_CTL_REFRESH_STATE;
	tx.index = 0x5a;
	tx.code = ECMXF_CMD_FW_VERSION_GET;
	tx.param = 0x07;
	tx.len = sizeof(payload);
	tx.int_clear = ECMXF_INT_WKC_ERR | ECMXF_INT_ECAT_PKT;
	tx.gpio_int_clear[0] = 0x11;
	tx.gpio_int_clear[1] = 0x22;
	tx.gpio_out[0] = 0x33;
	tx.gpio_out[1] = 0x44;

	ret = ecmxf_encode_cmd(pkt, sizeof(pkt), check, &tx,
			       payload, sizeof(payload));
	if (ret) {
		pr_err("self-test: encode (check %d) failed: %d\n", check, ret);
		return -EINVAL;
	}
	fault = ecmxf_decode_cmd(pkt, sizeof(pkt), check, &rx, &data);
	if (fault != ECMXF_FAULT_NONE) {
		pr_err("self-test: decode (check %d) rejected the packet: %s\n",
		       check, ecmxf_fault_name(fault));
		return -EINVAL;
	}
	if (memcmp(&rx, &tx, sizeof(rx)) ||
	    memcmp(data, payload, sizeof(payload)) ||
	    memchr_inv(data + sizeof(payload), 0,
		       ECMXF_DATA_MIN - sizeof(payload))) {
		pr_err("self-test: round trip (check %d) changed the packet\n",
		       check);
		return -EINVAL;
	}

	if (check == ECMXF_CHECK_FIXED)
		pkt[sizeof(pkt) - 1] ^= 0x01;
	else
		pkt[ECMXF_HDR_SIZE] ^= 0x01;
	fault = ecmxf_decode_cmd(pkt, sizeof(pkt), check, &rx, &data);
	if (fault != (check == ECMXF_CHECK_FIXED ? ECMXF_FAULT_END :
		      ECMXF_FAULT_CHECK)) {
		pr_err("self-test: corrupted packet (check %d) gave: %s\n",
		       check, ecmxf_fault_name(fault));
		return -EINVAL;
	}
	return 0;
}

/**
 * ecmxf_selftest() - check the protocol core as the kernel compiled it
 *
 * Return: 0 when the catalogue CRC values match and, for each check
 * type, one encode/decode round trip gives the packet back and one
 * corrupted packet is rejected; -EINVAL after logging what differed.
 */
int __init ecmxf_selftest(void)
{
	static const enum ecmxf_check checks[] __initconst = {
		ECMXF_CHECK_FIXED, ECMXF_CHECK_CRC8,
		ECMXF_CHECK_CCITT, ECMXF_CHECK_CRC32,
	};
	int ret = ecmxf_selftest_crc();
	unsigned int i;

	for (i = 0; i < ARRAY_SIZE(checks); i++)
		if (ecmxf_selftest_codec(checks[i]))
			ret = -EINVAL;
	return ret;
}
