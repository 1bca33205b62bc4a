// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-codec.c - framing of ECM-XF command and response packets
 *
 * A packet is header (24) | data (N) | check word (4) | end word (4),
 * N = 32..1408, every field little-endian.  Both directions use the same
 * length.  Decoding never trusts the chip: every length it reports is
 * checked against the packet before anything is read through it.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-proto.h"

/**
 * ecmxf_data_size_valid() - is @data_size a legal data section size
 * @data_size: data section size in bytes
 *
 * Return: true for 32..1408.
 */
bool ecmxf_data_size_valid(unsigned int data_size)
{
	return data_size >= ECMXF_DATA_MIN && data_size <= ECMXF_DATA_MAX;
}

static bool ecmxf_check_valid(enum ecmxf_check check)
{
	return !((unsigned int)check &
		 ~(ECMXF_CHECK_TYPE_MASK | ECMXF_CHECK_COVER_VALID));
}

/**
 * ecmxf_check_span() - how many bytes from the start the check word covers
 * @pkt: a whole packet whose header is in place
 * @pkt_len: its size, ECMXF_PKT_SIZE(N) with N in 32..1408
 * @check: check type, with %ECMXF_CHECK_COVER_VALID for the example host
 *	code's coverage
 *
 * Manual ver. 050: every byte before the check word (header and the whole
 * data section).  With %ECMXF_CHECK_COVER_VALID: the header plus the data
 * length field (0x0E) rounded up to a multiple of 4, at most the data
 * section, so a length field of N or more gives the same span as the
 * manual's rule.
 *
 * Return: the number of bytes, or 0 for a @pkt_len out of range.
 */
size_t ecmxf_check_span(const u8 *pkt, size_t pkt_len, enum ecmxf_check check)
{
	size_t n, len;

	if (!pkt || pkt_len < ECMXF_PKT_SIZE(ECMXF_DATA_MIN) ||
	    pkt_len > ECMXF_PKT_MAX)
		return 0;
	n = pkt_len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	if (!((unsigned int)check & ECMXF_CHECK_COVER_VALID))
		return ECMXF_HDR_SIZE + n;
	len = get_unaligned_le16(pkt + 0x0E);
	len = (len + 3) & ~(size_t)3;
	return ECMXF_HDR_SIZE + (len < n ? len : n);
}

/**
 * ecmxf_cover_name() - a short text for a CRC coverage
 * @cover: the coverage
 *
 * Return: "frame", "valid" or "unknown" (the words of the simulator's
 * crc32-coverage option and of sysfs).
 */
const char *ecmxf_cover_name(enum ecmxf_cover cover)
{
	switch (cover) {
	case ECMXF_COVER_FRAME:
		return "frame";
	case ECMXF_COVER_VALID:
		return "valid";
	case ECMXF_COVER_UNKNOWN:
	default:
		return "unknown";
	}
}

/* Fill in start word, data section, check word and end word. */
static int ecmxf_frame(u8 *pkt, size_t pkt_len, enum ecmxf_check check,
		       const void *data, size_t data_len)
{
	size_t n;

	if (!pkt || pkt_len < ECMXF_PKT_SIZE(ECMXF_DATA_MIN) ||
	    pkt_len > ECMXF_PKT_MAX || !ecmxf_check_valid(check))
		return -EINVAL;
	n = pkt_len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	if (data_len > n || (data_len && !data))
		return -EMSGSIZE;

	put_unaligned_le32(ECMXF_START_WORD, pkt);
	if (data_len)
		memcpy(pkt + ECMXF_HDR_SIZE, data, data_len);
	memset(pkt + ECMXF_HDR_SIZE + data_len, 0, n - data_len);
	put_unaligned_le32(ecmxf_check_word(check, pkt,
					    ecmxf_check_span(pkt, pkt_len, check)),
			   pkt + ECMXF_HDR_SIZE + n);
	put_unaligned_le32(ECMXF_END_WORD, pkt + ECMXF_HDR_SIZE + n + 4);
	return 0;
}

/* Validate the frame of a received packet; *n gets the data size. */
static enum ecmxf_fault ecmxf_unframe(const u8 *pkt, size_t pkt_len,
				      enum ecmxf_check check, size_t *n)
{
	u32 word;

	if (!pkt || pkt_len < ECMXF_PKT_SIZE(ECMXF_DATA_MIN) ||
	    pkt_len > ECMXF_PKT_MAX || !ecmxf_check_valid(check))
		return ECMXF_FAULT_SIZE;
	*n = pkt_len - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;

	word = get_unaligned_le32(pkt + ECMXF_HDR_SIZE + *n);
	if (word == ECMXF_NOT_READY_WORD)
		return ECMXF_FAULT_NOT_READY;
	if (get_unaligned_le32(pkt) != ECMXF_START_WORD)
		return ECMXF_FAULT_START;
	if (get_unaligned_le32(pkt + ECMXF_HDR_SIZE + *n + 4) != ECMXF_END_WORD)
		return ECMXF_FAULT_END;
	if (word != ecmxf_check_word(check, pkt,
				     ecmxf_check_span(pkt, pkt_len, check)))
		return ECMXF_FAULT_CHECK;
	return ECMXF_FAULT_NONE;
}

/**
 * ecmxf_encode_cmd() - build a command packet
 * @pkt: output buffer of exactly one packet
 * @pkt_len: packet size, ECMXF_PKT_SIZE(N) with N in 32..1408
 * @check: check word type (%ECMXF_CHECK_COVER_VALID: the example host
 *	code's CRC coverage)
 * @hdr: header fields
 * @data: bytes for the data section (the rest is zero-filled)
 * @data_len: number of bytes at @data, at most N
 *
 * Return: 0, -EINVAL for a bad size or check type, -EMSGSIZE when
 * @data_len does not fit.
 */
int ecmxf_encode_cmd(u8 *pkt, size_t pkt_len, enum ecmxf_check check,
		     const struct ecmxf_cmd_hdr *hdr,
		     const void *data, size_t data_len)
{
	int ret;

	if (!hdr || !pkt)
		return -EINVAL;
	/* header before framing: the check word covers it */
	if (pkt_len >= ECMXF_HDR_SIZE) {
		memcpy(pkt + 4, hdr->data, 4);
		put_unaligned_le16(hdr->reserved, pkt + 0x08);
		pkt[0x0A] = hdr->control;
		pkt[0x0B] = hdr->index;
		pkt[0x0C] = hdr->code;
		pkt[0x0D] = hdr->param;
		put_unaligned_le16(hdr->len, pkt + 0x0E);
		put_unaligned_le32(hdr->int_clear, pkt + 0x10);
		pkt[0x14] = hdr->gpio_int_clear[0];
		pkt[0x15] = hdr->gpio_int_clear[1];
		pkt[0x16] = hdr->gpio_out[0];
		pkt[0x17] = hdr->gpio_out[1];
	}
	ret = ecmxf_frame(pkt, pkt_len, check, data, data_len);
	return ret;
}

/**
 * ecmxf_decode_rsp() - validate a response packet and read its header
 * @pkt: the received packet
 * @pkt_len: its size, ECMXF_PKT_SIZE(N)
 * @check: the check type in force (with %ECMXF_CHECK_COVER_VALID: the
 *	example host code's CRC coverage)
 * @hdr: filled in when the packet is valid
 * @data: set to the data section when the packet is valid (may be NULL)
 *
 * The data length field is checked against N; a valid packet's
 * @hdr->len is therefore always safe to use as a length into @data.
 *
 * Return: %ECMXF_FAULT_NONE or why the packet was rejected.
 */
enum ecmxf_fault ecmxf_decode_rsp(const u8 *pkt, size_t pkt_len,
				  enum ecmxf_check check,
				  struct ecmxf_rsp_hdr *hdr,
				  const u8 **data)
{
	enum ecmxf_fault fault;
	size_t n;
	u16 len;

	fault = ecmxf_unframe(pkt, pkt_len, check, &n);
	if (fault != ECMXF_FAULT_NONE)
		return fault;
	len = get_unaligned_le16(pkt + 0x0E);
	if (len > n)
		return ECMXF_FAULT_LENGTH;
	if (hdr) {
		hdr->crc_err_cnt = pkt[0x04];
		hdr->wkc_err_cnt = pkt[0x05];
		hdr->tx_fifo_cnt = pkt[0x06];
		hdr->rx_fifo_cnt = pkt[0x07];
		hdr->ecat_state = pkt[0x08];
		hdr->err_status = pkt[0x09];
		hdr->ecm_status = pkt[0x0A];
		hdr->index = pkt[0x0B];
		hdr->code = pkt[0x0C];
		hdr->ret = pkt[0x0D];
		hdr->len = len;
		hdr->int_flags = get_unaligned_le32(pkt + 0x10);
		hdr->gpio_int_flag[0] = pkt[0x14];
		hdr->gpio_int_flag[1] = pkt[0x15];
		hdr->gpio_in[0] = pkt[0x16];
		hdr->gpio_in[1] = pkt[0x17];
	}
	if (data)
		*data = pkt + ECMXF_HDR_SIZE;
	return ECMXF_FAULT_NONE;
}

/**
 * ecmxf_encode_rsp() - build a response packet (the chip's side)
 * @pkt: output buffer of exactly one packet
 * @pkt_len: packet size
 * @check: check word type
 * @hdr: header fields; @hdr->len is written as given
 * @data: bytes for the data section
 * @data_len: number of bytes at @data
 *
 * Used by the simulator and by tests that play the chip.
 *
 * Return: 0, -EINVAL or -EMSGSIZE as for ecmxf_encode_cmd().
 */
int ecmxf_encode_rsp(u8 *pkt, size_t pkt_len, enum ecmxf_check check,
		     const struct ecmxf_rsp_hdr *hdr,
		     const void *data, size_t data_len)
{
	if (!hdr || !pkt)
		return -EINVAL;
	if (pkt_len >= ECMXF_HDR_SIZE) {
		pkt[0x04] = hdr->crc_err_cnt;
		pkt[0x05] = hdr->wkc_err_cnt;
		pkt[0x06] = hdr->tx_fifo_cnt;
		pkt[0x07] = hdr->rx_fifo_cnt;
		pkt[0x08] = hdr->ecat_state;
		pkt[0x09] = hdr->err_status;
		pkt[0x0A] = hdr->ecm_status;
		pkt[0x0B] = hdr->index;
		pkt[0x0C] = hdr->code;
		pkt[0x0D] = hdr->ret;
		put_unaligned_le16(hdr->len, pkt + 0x0E);
		put_unaligned_le32(hdr->int_flags, pkt + 0x10);
		pkt[0x14] = hdr->gpio_int_flag[0];
		pkt[0x15] = hdr->gpio_int_flag[1];
		pkt[0x16] = hdr->gpio_in[0];
		pkt[0x17] = hdr->gpio_in[1];
	}
	return ecmxf_frame(pkt, pkt_len, check, data, data_len);
}

/**
 * ecmxf_decode_cmd() - validate a command packet and read its header
 * @pkt: the received packet
 * @pkt_len: its size
 * @check: the check type in force
 * @hdr: filled in when the packet is valid
 * @data: set to the data section when valid (may be NULL)
 *
 * The chip's side of ecmxf_decode_rsp().  The data length field of a
 * command can be a parameter (SPI_RECONFIG_OP), so it is not checked
 * against the data section here; the command's handler does that.
 *
 * Return: %ECMXF_FAULT_NONE or why the packet was rejected.
 */
enum ecmxf_fault ecmxf_decode_cmd(const u8 *pkt, size_t pkt_len,
				  enum ecmxf_check check,
				  struct ecmxf_cmd_hdr *hdr,
				  const u8 **data)
{
	enum ecmxf_fault fault;
	size_t n;

	fault = ecmxf_unframe(pkt, pkt_len, check, &n);
	if (fault != ECMXF_FAULT_NONE)
		return fault;
	if (hdr) {
		memcpy(hdr->data, pkt + 4, 4);
		hdr->reserved = get_unaligned_le16(pkt + 0x08);
		hdr->control = pkt[0x0A];
		hdr->index = pkt[0x0B];
		hdr->code = pkt[0x0C];
		hdr->param = pkt[0x0D];
		hdr->len = get_unaligned_le16(pkt + 0x0E);
		hdr->int_clear = get_unaligned_le32(pkt + 0x10);
		hdr->gpio_int_clear[0] = pkt[0x14];
		hdr->gpio_int_clear[1] = pkt[0x15];
		hdr->gpio_out[0] = pkt[0x16];
		hdr->gpio_out[1] = pkt[0x17];
	}
	if (data)
		*data = pkt + ECMXF_HDR_SIZE;
	return ECMXF_FAULT_NONE;
}

/**
 * ecmxf_fault_errno() - the errno that reports a packet fault
 * @fault: the fault
 *
 * Return: 0, -EIO (not ready), -EPROTO (start/end word, length field),
 * -EBADMSG (check word) or -EINVAL (caller's buffer size).
 */
int ecmxf_fault_errno(enum ecmxf_fault fault)
{
	switch (fault) {
	case ECMXF_FAULT_NONE:
		return 0;
	case ECMXF_FAULT_NOT_READY:
		return -EIO;
	case ECMXF_FAULT_CHECK:
		return -EBADMSG;
	case ECMXF_FAULT_START:
	case ECMXF_FAULT_END:
	case ECMXF_FAULT_LENGTH:
		return -EPROTO;
	case ECMXF_FAULT_SIZE:
	default:
		return -EINVAL;
	}
}

/**
 * ecmxf_fault_name() - a short text for a packet fault
 * @fault: the fault
 *
 * Return: a static string, never NULL.
 */
const char *ecmxf_fault_name(enum ecmxf_fault fault)
{
	switch (fault) {
	case ECMXF_FAULT_NONE:
		return "valid packet";
	case ECMXF_FAULT_NOT_READY:
		return "chip not ready (check word 0x87654321)";
	case ECMXF_FAULT_START:
		return "wrong start word";
	case ECMXF_FAULT_END:
		return "wrong end word";
	case ECMXF_FAULT_CHECK:
		return "check word mismatch";
	case ECMXF_FAULT_LENGTH:
		return "data length beyond the data section";
	case ECMXF_FAULT_SIZE:
		return "packet size not 56..1440 bytes";
	default:
		return "unknown fault";
	}
}
