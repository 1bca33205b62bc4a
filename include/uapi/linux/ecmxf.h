/* SPDX-License-Identifier: GPL-2.0-only WITH Linux-syscall-note */
/*
 * <linux/ecmxf.h> - userspace ABI of the NEXTW ECM-XF SPI EtherCAT master
 *
 * One character device per chip, /dev/ecmxfN.  Commands go to the chip
 * synchronously (%ECMXF_IOC_CMD) or asynchronously (%ECMXF_IOC_SUBMIT, with
 * completions read() from the file descriptor); process data travels through
 * two mmap()ed single-producer/single-consumer rings whose layout the kernel
 * reports as offsets (%ECMXF_IOC_RING_SETUP), in the style of io_uring.
 *
 * Rules that hold for every structure in this file:
 *  - sizes are multiples of 8 and identical on 32- and 64-bit ABIs; there
 *    are no implicit holes, every byte is a named field;
 *  - 64-bit fields and user pointers are __aligned_u64;
 *  - fields named padding or reserved must be zero on input (the kernel
 *    returns -EINVAL otherwise) and are zeroed by the kernel on output, so
 *    that later versions can give them a meaning.
 *
 * ABI version 4 (%ECMXF_UAPI_VERSION).  See Documentation/uapi.rst, which
 * also gives the compatibility policy.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef _UAPI_LINUX_ECMXF_H
#define _UAPI_LINUX_ECMXF_H

#include <linux/ioctl.h>
#include <linux/types.h>

/**
 * ECMXF_UAPI_VERSION - version of the ABI described by this header
 *
 * Reported by %ECMXF_IOC_GET_VERSION and in &struct ecmxf_devinfo.uapi_version.
 * Raised when a reserved field or flag gains a meaning or a layout changes.
 * Version 2 (from version 1): completion records carry the answer's data
 * inline (&struct ecmxf_completion.data; &struct ecmxf_submit.reserved_ptr
 * was rx_ptr and must now be zero) and the ring status block is a latch of
 * two copies (&struct ecmxf_ring_status_block).  Version 3: an async
 * command may carry its result fetch (%ECMXF_CMD_F_FETCH, &struct
 * ecmxf_cmd.fetch in what were its reserved words), and the rings' working
 * counter read may leave its answer to the next pump cycle
 * (%ECMXF_RING_F_WKC_NEXT).  Version 4: the pump's FIFO command may leave
 * its answer to the next pump cycle (%ECMXF_RING_F_FIFO_NEXT), and
 * %ECMXF_IOC_SUBMIT takes a result fetch too (&struct ecmxf_submit.fetch,
 * &struct ecmxf_completion.flags in what were reserved words).  Userspace
 * built against another version must refuse to run: compare the value
 * first.
 */
#define ECMXF_UAPI_VERSION		4

/**
 * ECMXF_DATA_SIZE_MAX - the largest packet data section (bytes), and the
 * most response data a command can return
 */
#define ECMXF_DATA_SIZE_MAX		1408

/*
 * ECMXF_IOC_MAGIC - ioctl type byte of /dev/ecmxfN, sequence numbers 0x00-0x1F.
 *
 * Not listed in Documentation/userspace-api/ioctl/ioctl-number.rst as far as
 * we know (0xE5 is linux/fuse.h, 0xEC is cros_ec_dev.h; 0xE9 is free there).
 */
#define ECMXF_IOC_MAGIC			0xE9

/**
 * struct ecmxf_cmd_header - command header fields that userspace chooses
 * @data: parametric data 0..3 (packet offsets 0x04..0x07)
 * @rsv_word: the 16-bit word at 0x08 that the manual calls "reserved":
 *	bit 15 marks @gpio_out valid, bits 11 (enable LRW) and 12 (bus shift
 *	mode) are options of ECAT_INIT_OP; any other bit, or 11 and 12 with
 *	another command, is -EINVAL
 * @control: control byte at 0x0A (manual ver. 050: refresh state, clear
 *	error bits); the kernel may OR in clear bits of its own
 * @padding: the index byte at 0x0B, which the kernel allocates; must be zero
 * @code: command code at 0x0C
 * @param: command parameter at 0x0D
 * @len: data length field at 0x0E, sent as given (for most commands the
 *	number of data bytes, for some a parameter)
 * @int_clear: interrupt clear bits at 0x10
 * @gpio_int_clear: GPIO interrupt clear low/high (0x14, 0x15)
 * @gpio_out: GPIO outputs low/high (0x16, 0x17), valid when @rsv_word bit 15
 *	is set
 * @reserved: must be zero
 *
 * The field at offset n is the packet byte at n + 4: the structure mirrors
 * packet bytes 0x04..0x17; start word, data, check word and end word are the
 * kernel's.
 */
struct ecmxf_cmd_header {
	__u8 data[4];
	__u16 rsv_word;
	__u8 control;
	__u8 padding;
	__u8 code;
	__u8 param;
	__u16 len;
	__u32 int_clear;
	__u8 gpio_int_clear[2];
	__u8 gpio_out[2];
	__u32 reserved;
};

/**
 * struct ecmxf_rsp_header - the response header that answered a command
 * @crc_err_cnt: SPI CRC error count (0x04)
 * @wkc_err_cnt: WKC error count (0x05)
 * @tx_fifo_cnt: TxPDO frames waiting in the chip's TxFIFO (0x06)
 * @rx_fifo_cnt: RxPDO frames waiting in the chip's RxFIFO (0x07)
 * @ecat_state: EtherCAT state (0x08): 0 none, 1 INIT, 2 PRE_OP, 3 BOOT,
 *	4 SAFE_OP, 8 OP, 0x10 ERROR
 * @err_status: error status bits (0x09)
 * @ecm_status: ECM status bits (0x0A); bit 7 async command busy
 * @index: index of the command answered (0x0B), the kernel's
 * @code: command code answered (0x0C)
 * @ret: return value (0x0D)
 * @len: valid data length (0x0E)
 * @int_flags: interrupt flags (0x10)
 * @gpio_int_flag: GPIO interrupt flags low/high (0x14, 0x15)
 * @gpio_in: GPIO inputs low/high (0x16, 0x17)
 * @padding: zeroed by the kernel
 *
 * Like &struct ecmxf_cmd_header, field offset n is packet byte n + 4.
 * For an async command it is the header that reported the end of the busy
 * phase, not the one that accepted the command.
 */
struct ecmxf_rsp_header {
	__u8 crc_err_cnt;
	__u8 wkc_err_cnt;
	__u8 tx_fifo_cnt;
	__u8 rx_fifo_cnt;
	__u8 ecat_state;
	__u8 err_status;
	__u8 ecm_status;
	__u8 index;
	__u8 code;
	__u8 ret;
	__u16 len;
	__u32 int_flags;
	__u8 gpio_int_flag[2];
	__u8 gpio_in[2];
	__u32 padding;
};

/*
 * &struct ecmxf_cmd.flags and &struct ecmxf_submit.flags
 *
 * ECMXF_CMD_F_NO_AUTO_CLEAR: when the command fails with the chip's
 * async-command error or command error bit, leave the bit set instead of
 * clearing it with the next packet's control byte.
 *
 * ECMXF_CMD_F_FETCH: the command is async and &struct ecmxf_cmd.fetch
 * (&struct ecmxf_submit.fetch) is the header of the command that fetches its
 * result, its *_GET partner (ECAT_SDO_GET for ECAT_SDO_REQ, ...; no data).
 * The kernel sends the fetch as the poll of the running command, so the
 * exchange that sees the command end also brings the result: no separate
 * fetch after it.  The fetch has a permission class of its own (its code
 * and its header's fields), checked with the command's.
 *
 * ECMXF_CMD_F_FETCHED (output only; rejected as input): set by the kernel
 * (in &struct ecmxf_cmd.flags, &struct ecmxf_completion.flags) when the
 * fetch ran: @rsp, @rx_len, @status and the data are the fetch's.
 * Clear after a %ECMXF_CMD_F_FETCH command: the command itself failed
 * (@status, @rsp are its own) and the fetch was not sent.
 */
#define ECMXF_CMD_F_NO_AUTO_CLEAR	(1U << 0)
#define ECMXF_CMD_F_FETCH		(1U << 1)
#define ECMXF_CMD_F_FETCHED		(1U << 2)

/**
 * struct ecmxf_cmd - one synchronous command (%ECMXF_IOC_CMD)
 * @hdr: command header; the kernel allocates the index
 * @tx_ptr: user pointer to the data section bytes to send (may be 0 when
 *	@tx_len is 0)
 * @rx_ptr: user pointer to a buffer for the response data (may be 0 when
 *	@rx_size is 0)
 * @tx_len: bytes at @tx_ptr, at most &struct ecmxf_devinfo.data_size; the
 *	rest of the data section is sent as zeros
 * @rx_size: capacity of @rx_ptr in bytes
 * @timeout_us: time allowed from the ioctl until the answer (for async
 *	commands: until the chip's busy phase ends), in microseconds; 0 selects
 *	the command's default
 * @flags: %ECMXF_CMD_F_* bits; unknown bits are rejected; output:
 *	%ECMXF_CMD_F_FETCHED
 * @rsp: output: the response header that answered the command
 * @rx_len: output: response data bytes copied to @rx_ptr
 * @status: output: 0, or the negative errno of the command: -ETIMEDOUT,
 *	-EBUSY (the chip refused an async command while another ran),
 *	-EREMOTEIO (async command ended with the error bit), -EBADMSG,
 *	-EPROTO or -EIO (transport retries exhausted), -ECONNRESET (the chip
 *	reset), -EMSGSIZE (answer longer than @rx_size, @rx_len bytes copied),
 *	-ECANCELED (abandoned by %ECMXF_IOC_RESET)
 * @fetch: with %ECMXF_CMD_F_FETCH, the result fetch's header, as @hdr
 *	(the kernel allocates its index; len, padding and reserved zero);
 *	without, all zero (version 2 called these 24 bytes reserved)
 *
 * The ioctl returns 0 whenever the command reached the link; the outcome of
 * the command itself is in @status.  With %ECMXF_CMD_F_FETCH the outputs
 * are the fetch's when %ECMXF_CMD_F_FETCHED is set (the data is the
 * result, @status 0 or the fetch's errno), else the command's own.
 */
struct ecmxf_cmd {
	struct ecmxf_cmd_header hdr;
	__aligned_u64 tx_ptr;
	__aligned_u64 rx_ptr;
	__u32 tx_len;
	__u32 rx_size;
	__u32 timeout_us;
	__u32 flags;
	struct ecmxf_rsp_header rsp;
	__u32 rx_len;
	__s32 status;
	struct ecmxf_cmd_header fetch;
};

/**
 * struct ecmxf_submit - one asynchronous command (%ECMXF_IOC_SUBMIT)
 * @hdr: command header; the kernel allocates the index
 * @tx_ptr: user pointer to the data section bytes; copied during the ioctl
 * @reserved_ptr: must be zero (version 1 had a reply pointer here: the
 *	answer now travels inside the completion record, so that read() never
 *	writes to an address the submitter chose)
 * @tx_len: bytes at @tx_ptr, at most &struct ecmxf_devinfo.data_size
 * @rx_size: response data bytes wanted in the completion record
 *	(0..%ECMXF_DATA_SIZE_MAX); a longer answer completes with -EMSGSIZE and
 *	its first @rx_size bytes
 * @timeout_us: as &struct ecmxf_cmd.timeout_us, counted from the submit
 * @flags: %ECMXF_CMD_F_* input bits (%ECMXF_CMD_F_NO_AUTO_CLEAR,
 *	%ECMXF_CMD_F_FETCH)
 * @cookie: any value; returned in &struct ecmxf_completion.cookie
 * @fetch: with %ECMXF_CMD_F_FETCH, the header of the async command's
 *	result fetch, as &struct ecmxf_cmd.fetch (the completion record then
 *	carries the fetch's outcome, &struct ecmxf_completion.flags); else
 *	must be zero
 *
 * The first 56 bytes are laid out as in &struct ecmxf_cmd.
 */
struct ecmxf_submit {
	struct ecmxf_cmd_header hdr;
	__aligned_u64 tx_ptr;
	__aligned_u64 reserved_ptr;
	__u32 tx_len;
	__u32 rx_size;
	__u32 timeout_us;
	__u32 flags;
	__aligned_u64 cookie;
	struct ecmxf_cmd_header fetch;
};

/**
 * struct ecmxf_completion - record read() from /dev/ecmxfN
 * @cookie: &struct ecmxf_submit.cookie of the finished command
 * @status: 0 or negative errno, as &struct ecmxf_cmd.status
 * @rx_len: response data bytes in @data (at most the submit's rx_size)
 * @rsp: the response header that answered the command
 * @flags: %ECMXF_CMD_F_FETCHED when the submit's result fetch ran: @rsp,
 *	@rx_len, @data and @status are then the fetch's; else 0
 * @reserved: zeroed by the kernel
 * @data: the response data; bytes past @rx_len are zero
 *
 * read() returns whole records only; a buffer shorter than one record gives
 * -EINVAL.  Completions of one file descriptor are read in completion order.
 * read() writes nothing but the buffer it is given.
 */
struct ecmxf_completion {
	__aligned_u64 cookie;
	__s32 status;
	__u32 rx_len;
	struct ecmxf_rsp_header rsp;
	__u32 flags;
	__u32 reserved[5];
	__u8 data[ECMXF_DATA_SIZE_MAX];
};

/* &struct ecmxf_devinfo.flags */
#define ECMXF_DEVINFO_F_INT0		(1U << 0)	/* INT0 (ready) line wired */
#define ECMXF_DEVINFO_F_INT1		(1U << 1)	/* INT1 (event) line wired */
#define ECMXF_DEVINFO_F_FW_VERSION	(1U << 2)	/* fw_version, fw_info valid */
#define ECMXF_DEVINFO_F_CLAIMED		(1U << 3)	/* someone holds the claim */
#define ECMXF_DEVINFO_F_CLAIM_MINE	(1U << 4)	/* this fd holds the claim */
#define ECMXF_DEVINFO_F_RINGS		(1U << 5)	/* PDO rings are set up */
/*
 * the claim reserves every class above query to its holder, checked when a
 * command is queued and when it is sent, reserved header bits are refused,
 * and %ECMXF_IOC_CLAIM_BREAK exists (Documentation/uapi.rst, "Permissions")
 */
#define ECMXF_DEVINFO_F_CLAIM_EXCLUSIVE	(1U << 6)

/**
 * struct ecmxf_devinfo - the chip and the link (%ECMXF_IOC_DEVINFO)
 * @uapi_version: %ECMXF_UAPI_VERSION of the running kernel module
 * @flags: %ECMXF_DEVINFO_F_* bits
 * @data_size: packet data section size in bytes (32..1408)
 * @check_type: check word type: 0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32
 * @fw_version: return value of ECM_CMD_FW_VERSION_GET
 * @fw_info: the 20 data bytes of ECM_CMD_FW_VERSION_GET: byte 1 extended
 *	version, byte 3 master series (XF, XFL, XFU, XM), bytes 4..19 build
 *	identifier
 * @slave_count: return value of the last ECM_CMD_ECAT_SLV_CNT_GET that the
 *	kernel passed on and that the chip answered without a command error;
 *	0 if unknown (none yet, or a warm reset since)
 * @max_open: how many file descriptors may have the device open at once
 * @open_count: how many have it open now
 * @claim_pid: process that holds the cyclic claim (%ECMXF_IOC_CLAIM), in the
 *	caller's pid namespace; 0 if none or not visible there
 * @queue_depth: submitted commands a file descriptor may have in flight
 * @spi_speed_hz: SPI clock of the link
 * @reserved: zeroed by the kernel
 */
struct ecmxf_devinfo {
	__u32 uapi_version;
	__u32 flags;
	__u16 data_size;
	__u8 check_type;
	__u8 fw_version;
	__u8 fw_info[20];
	__u32 slave_count;
	__u32 max_open;
	__u32 open_count;
	__u32 claim_pid;
	__u32 queue_depth;
	__u32 spi_speed_hz;
	__u32 reserved[10];
};

/**
 * struct ecmxf_counters - link statistics since probe (%ECMXF_IOC_COUNTERS)
 * @exchanges: SPI exchanges (one packet each way)
 * @bad_not_ready: received packets whose check word read 0x87654321
 * @bad_start: received packets with a wrong start word
 * @bad_end: received packets with a wrong end word
 * @bad_check: received packets whose check word did not match
 * @bad_length: received packets whose data length exceeded the data section
 * @retries: packets re-sent because the answer was unusable
 * @polls: packets re-sent because the answer had not arrived yet
 * @exhausted: commands failed because retries ran out
 * @timeouts: commands failed with -ETIMEDOUT
 * @async_errors: async commands that ended with the error bit (-EREMOTEIO)
 * @busy_rejects: async commands the chip refused as busy (-EBUSY)
 * @lost_answers: answers overwritten before they were read (re-issued or
 *	failed)
 * @chip_resets: times the chip was seen to restart
 * @wkc_errors: increments of the chip's WKC error count
 * @out_ring_underruns: pump cycles that found the output ring empty while
 *	the chip's RxFIFO wanted a frame
 * @in_ring_overruns: input frames dropped because the input ring was full
 * @rx_fifo_underruns: responses in which the chip's RxFIFO (outputs) was
 *	empty while the pump was running
 * @rx_fifo_overruns: output frames the chip refused because its RxFIFO was
 *	full
 * @tx_fifo_overruns: times the chip's TxFIFO (inputs) was seen full, so the
 *	chip dropped its oldest frames
 * @int0_irqs: INT0 (ready) interrupts handled
 * @int1_irqs: INT1 (event) interrupts handled
 * @reserved: zeroed by the kernel
 */
struct ecmxf_counters {
	__aligned_u64 exchanges;
	__aligned_u64 bad_not_ready;
	__aligned_u64 bad_start;
	__aligned_u64 bad_end;
	__aligned_u64 bad_check;
	__aligned_u64 bad_length;
	__aligned_u64 retries;
	__aligned_u64 polls;
	__aligned_u64 exhausted;
	__aligned_u64 timeouts;
	__aligned_u64 async_errors;
	__aligned_u64 busy_rejects;
	__aligned_u64 lost_answers;
	__aligned_u64 chip_resets;
	__aligned_u64 wkc_errors;
	__aligned_u64 out_ring_underruns;
	__aligned_u64 in_ring_overruns;
	__aligned_u64 rx_fifo_underruns;
	__aligned_u64 rx_fifo_overruns;
	__aligned_u64 tx_fifo_overruns;
	__aligned_u64 int0_irqs;
	__aligned_u64 int1_irqs;
	__aligned_u64 reserved[10];
};

/*
 * &struct ecmxf_reset.flags: exactly one must be set.
 *
 * ECMXF_RESET_F_ASYNC_CMD: send ECM_CMD_ASYNCCMD_RESET with parameter
 *	&struct ecmxf_reset.param (%ECMXF_RESET_ASYNC_*).
 * ECMXF_RESET_F_WARM: send ECM_CMD_WARM_RESET; the chip restarts, the kernel
 *	returns to the default packet format, fails every pending command with
 *	-ECONNRESET and stops the rings.
 * ECMXF_RESET_F_LINK: send nothing special; forget the link state (index,
 *	pending answer, packet format) and resynchronise with the chip.
 */
#define ECMXF_RESET_F_ASYNC_CMD		(1U << 0)
#define ECMXF_RESET_F_WARM		(1U << 1)
#define ECMXF_RESET_F_LINK		(1U << 2)

/* &struct ecmxf_reset.param for %ECMXF_RESET_F_ASYNC_CMD (ASYNCCMD_RESET) */
#define ECMXF_RESET_ASYNC_CLEAR_BUSY	(1U << 0)	/* clear a stuck busy bit */
#define ECMXF_RESET_ASYNC_SKIP_LINK	(1U << 1)	/* skip the link wait */
#define ECMXF_RESET_ASYNC_ABANDON	(1U << 2)	/* abandon the async command */

/**
 * struct ecmxf_reset - recover the chip or the link (%ECMXF_IOC_RESET)
 * @flags: one %ECMXF_RESET_F_* value
 * @param: for %ECMXF_RESET_F_ASYNC_CMD, %ECMXF_RESET_ASYNC_* bits (the
 *	command parameter); must be zero otherwise
 * @timeout_us: time allowed for the reset, in microseconds; 0 selects the
 *	default
 * @reserved: must be zero
 */
struct ecmxf_reset {
	__u32 flags;
	__u32 param;
	__u32 timeout_us;
	__u32 reserved[5];
};

/*
 * mmap() offsets of the two rings (the offset argument; length is
 * &struct ecmxf_ring_offsets.mmap_size).  ECMXF_RING_OFF_OUT maps the output
 * ring (host to chip, RxPDO frames), ECMXF_RING_OFF_IN the input ring (chip
 * to host, TxPDO frames).
 */
#define ECMXF_RING_OFF_OUT		0x00000000ULL
#define ECMXF_RING_OFF_IN		0x10000000ULL

/* &struct ecmxf_ring_setup.flags */
/*
 * poll() on /dev/ecmxfN: EPOLLIN | EPOLLRDNORM means a completion record is
 * readable and nothing else.  The rings of the claim holder have bits of
 * their own: EPOLLRDBAND while the input ring holds frames (with
 * ECMXF_RING_F_POLL_IN), EPOLLOUT | EPOLLWRNORM while the output ring has
 * room (with ECMXF_RING_F_POLL_OUT; the file has no write()), EPOLLERR once
 * the pump stopped, EPOLLERR | EPOLLHUP when the device is gone.
 */
#define ECMXF_RING_F_POLL_OUT	(1U << 0)	/* EPOLLOUT: output ring has room */
#define ECMXF_RING_F_POLL_IN	(1U << 1)	/* EPOLLRDBAND: input ring has frames */
/*
 * ECMXF_RING_F_WKC_NEXT: the working counter read (@wkc_us) rides in the
 * exchange that fetches the FIFO command's answer, and its own answer is
 * left to the next exchange the pump makes anyway (the next FIFO command):
 * two SPI exchanges per pump cycle with a read instead of three.
 * &struct ecmxf_ring_status.wkc then shows the read about one @poll_us
 * later.
 */
#define ECMXF_RING_F_WKC_NEXT	(1U << 2)
/*
 * ECMXF_RING_F_FIFO_NEXT: the pump's FIFO command leaves its answer to the
 * exchange of the next FIFO command, which it rides in: one SPI exchange
 * per pump cycle instead of two.  The input frames a command pops reach
 * the input ring one pump cycle (@poll_us, or the next INT1) later, and
 * its output frames leave the output ring when it is built: a command
 * the chip refuses (command error) or whose answer is lost drops them
 * (the ring's dropped count), never sends them again after newer ones.
 */
#define ECMXF_RING_F_FIFO_NEXT	(1U << 3)

/* bits of the ring's flags word (in ring memory, written by the kernel) */
#define ECMXF_RING_S_ACTIVE	(1U << 0)	/* the pump is moving frames */
#define ECMXF_RING_S_ERROR	(1U << 1)	/* the pump stopped on an error */

/**
 * struct ecmxf_ring_offsets - where a ring's parts are in its mapping
 * @head: offset of the __u32 consumer index
 * @tail: offset of the __u32 producer index
 * @mask: offset of the __u32 index mask (entries - 1)
 * @entries: offset of the __u32 number of frame slots
 * @flags: offset of the __u32 %ECMXF_RING_S_* word
 * @dropped: offset of the __u32 count of frames dropped at this ring
 * @frames: offset of the first frame slot
 * @frame_size: value: bytes of process data in a frame (the chip's RxPDO
 *	size for the output ring, TxPDO size for the input ring)
 * @frame_stride: value: bytes from one frame slot to the next, a multiple
 *	of 8 and at least @frame_size
 * @mmap_size: value: length to pass to mmap(), a multiple of the page size
 * @status: offset of the &struct ecmxf_ring_status_block that the kernel
 *	keeps (input ring only; 0 in the output ring)
 * @reserved: zeroed by the kernel
 *
 * Slot i is at @frames + (i & mask) * @frame_stride.  Indices run freely
 * and wrap at 2^32; the ring is empty when head == tail and full when
 * tail - head == entries.  Each index has one writer: the producer stores
 * tail with release after writing the frame, the consumer loads it with
 * acquire; the consumer stores head with release after reading the frame,
 * the producer loads it with acquire.  Userspace produces the output ring
 * and consumes the input ring.
 *
 * The dropped counters are the kernel's: in the output ring, frames the
 * chip refused (RxFIFO full); in the input ring, frames the kernel could
 * not store because the ring was full (the newest frame is dropped, the
 * consumer's head is never moved by the kernel).
 */
struct ecmxf_ring_offsets {
	__u32 head;
	__u32 tail;
	__u32 mask;
	__u32 entries;
	__u32 flags;
	__u32 dropped;
	__u32 frames;
	__u32 frame_size;
	__u32 frame_stride;
	__u32 mmap_size;
	__u32 status;
	__u32 reserved;
};

/**
 * struct ecmxf_ring_status - what the PDO pump saw last (in the input ring)
 * @generation: how many times the kernel has published the status (wraps);
 *	this copy's number
 * @wkc: the working counter of the last ECAT_PDO_WC_GET 3 the pump read
 * @wkc_reads: how many times the pump has read it (wraps)
 * @int_flags: interrupt flags (0x10) of the pump's last answer
 * @crc_err_cnt: header byte 0x04 of the pump's last answer
 * @wkc_err_cnt: header byte 0x05
 * @tx_fifo_cnt: header byte 0x06, TxPDO frames left in the chip
 * @rx_fifo_cnt: header byte 0x07, RxPDO frames waiting in the chip
 * @ecat_state: header byte 0x08
 * @err_status: header byte 0x09
 * @ecm_status: header byte 0x0A
 * @padding: zero
 * @pump_ops: ECAT_PDO_DATA_FIFO_OP commands the pump completed (wraps)
 * @rx_refusals: pump commands whose output frames the chip refused
 * @tx_overflows: answers that showed the chip's TxFIFO full
 * @rx_underruns: answers that showed the chip's RxFIFO empty
 * @out_underruns: of those, the ones that found the output ring empty too
 * @error: 0, or the positive errno of the pump's last failed command
 * @out_skipped: output frames skipped because the pump had fallen behind
 * @pump_failures: pump commands that failed after they may have reached
 *	the chip (no answer in time, bad packets): their output frames are
 *	not sent again (counted in the output ring's dropped count; they may
 *	have reached the bus) and the input frames of the lost answer are
 *	lost (at most what the command asked for); @error says why
 * @reserved: zero
 *
 * Written by the kernel only.  The counters wrap at 2^32 and count since
 * %ECMXF_IOC_RING_SETUP; &struct ecmxf_counters has the totals since probe.
 */
struct ecmxf_ring_status {
	__u32 generation;
	__u32 wkc;
	__u32 wkc_reads;
	__u32 int_flags;
	__u8 crc_err_cnt;
	__u8 wkc_err_cnt;
	__u8 tx_fifo_cnt;
	__u8 rx_fifo_cnt;
	__u8 ecat_state;
	__u8 err_status;
	__u8 ecm_status;
	__u8 padding;
	__u32 pump_ops;
	__u32 rx_refusals;
	__u32 tx_overflows;
	__u32 rx_underruns;
	__u32 out_underruns;
	__u32 error;
	__u32 out_skipped;
	__u32 pump_failures;
	__u32 reserved[2];
};

/**
 * struct ecmxf_ring_status_block - the status block (a latch of two copies)
 * @seq: latch count, written by the kernel only: it increments @seq (store
 *	release) before it rewrites a copy, so that @copy[@seq & 1] is never
 *	the one being written
 * @reserved: zero
 * @copy: the two copies of the status; read @copy[@seq & 1]
 *
 * Reading: load @seq with acquire, copy @copy[@seq & 1], issue a read
 * barrier (acquire fence), load @seq again and retry when it changed.  A
 * retry is needed only when the kernel finished rewriting a copy during the
 * read, so a reader never waits for the writer: a reader that preempted the
 * kernel's writer (an RT thread of higher priority on the same CPU) reads
 * the other copy and succeeds at once.  The copies differ at most by the
 * last update.
 */
struct ecmxf_ring_status_block {
	__u32 seq;
	__u32 reserved[15];
	struct ecmxf_ring_status copy[2];
};

/**
 * struct ecmxf_ring_setup - create the PDO rings (%ECMXF_IOC_RING_SETUP)
 * @out_entries: frame slots of the output ring, a power of two 2..4096
 * @in_entries: frame slots of the input ring, a power of two 2..4096
 * @flags: %ECMXF_RING_F_* bits
 * @poll_us: period of the pump's timer in microseconds (50..100000; 0
 *	selects 1000): the longest time an output frame waits in the ring
 *	when no interrupt wakes the pump earlier
 * @rx_fill: RxFIFO level (frames) the pump fills the chip's RxFIFO up to;
 *	0 selects the depth minus two, at most the depth minus two
 * @wkc_us: read the working counter (ECAT_PDO_WC_GET 3) into
 *	&struct ecmxf_ring_status every this many microseconds; 0: never
 * @out: output: layout of the output ring (mmap at %ECMXF_RING_OFF_OUT)
 * @in: output: layout of the input ring (mmap at %ECMXF_RING_OFF_IN)
 * @reserved: must be zero
 *
 * Needs the cyclic claim.  Frame sizes come from the chip's PDO
 * configuration at the time of the call (FIFO_PACK_SIZE_GET), the RxFIFO
 * and TxFIFO depths from FIFO_GET_RX_CNT and FIFO_GET_TX_CNT.
 */
struct ecmxf_ring_setup {
	__u32 out_entries;
	__u32 in_entries;
	__u32 flags;
	__u32 poll_us;
	struct ecmxf_ring_offsets out;
	struct ecmxf_ring_offsets in;
	__u32 rx_fill;
	__u32 wkc_us;
	__u32 reserved[2];
};

/**
 * ECMXF_IOC_GET_VERSION - read %ECMXF_UAPI_VERSION of the module (a __u32);
 * its number never changes, so it also works across versions
 */
#define ECMXF_IOC_GET_VERSION	_IOR(ECMXF_IOC_MAGIC, 0x00, __u32)
/**
 * ECMXF_IOC_DEVINFO - fill &struct ecmxf_devinfo
 */
#define ECMXF_IOC_DEVINFO	_IOR(ECMXF_IOC_MAGIC, 0x01, struct ecmxf_devinfo)
/**
 * ECMXF_IOC_CMD - run one command and wait for its answer (for async
 * commands, for the end of the busy phase); &struct ecmxf_cmd
 */
#define ECMXF_IOC_CMD		_IOWR(ECMXF_IOC_MAGIC, 0x02, struct ecmxf_cmd)
/**
 * ECMXF_IOC_SUBMIT - queue one command; its &struct ecmxf_completion is
 * read() later; &struct ecmxf_submit
 */
#define ECMXF_IOC_SUBMIT	_IOW(ECMXF_IOC_MAGIC, 0x03, struct ecmxf_submit)
/**
 * ECMXF_IOC_COUNTERS - fill &struct ecmxf_counters
 */
#define ECMXF_IOC_COUNTERS	_IOR(ECMXF_IOC_MAGIC, 0x04, struct ecmxf_counters)
/**
 * ECMXF_IOC_RESET - recover the chip or the link; &struct ecmxf_reset
 */
#define ECMXF_IOC_RESET		_IOW(ECMXF_IOC_MAGIC, 0x05, struct ecmxf_reset)
/**
 * ECMXF_IOC_CLAIM - take the exclusive cyclic-path claim for this file
 * descriptor (no argument); -EBUSY if another one holds it, -EPERM if the
 * file is not open for writing
 */
#define ECMXF_IOC_CLAIM		_IO(ECMXF_IOC_MAGIC, 0x06)
/**
 * ECMXF_IOC_RELEASE - give the claim back and tear the rings down (no
 * argument); closing the file descriptor does the same
 */
#define ECMXF_IOC_RELEASE	_IO(ECMXF_IOC_MAGIC, 0x07)
/**
 * ECMXF_IOC_RING_SETUP - create the two PDO rings; &struct ecmxf_ring_setup
 */
#define ECMXF_IOC_RING_SETUP	_IOWR(ECMXF_IOC_MAGIC, 0x08, struct ecmxf_ring_setup)
/**
 * ECMXF_IOC_CLAIM_BREAK - take the claim from its holder (no argument), to
 * stop a machine whose claim holder hangs: its rings stop with
 * -ECONNABORTED and go, and this file descriptor holds the claim until it
 * releases it; -ENOENT when no claim is held, -EPERM without a file open
 * for writing and CAP_SYS_ADMIN
 */
#define ECMXF_IOC_CLAIM_BREAK	_IO(ECMXF_IOC_MAGIC, 0x09)

/*
 * The chip's protocol numbers
 *
 * Everything below is what the ECM-XF user manuals (ver. 038 and ver. 050;
 * ver. 050 wins where they differ) define for the packet header: command
 * codes for &struct ecmxf_cmd_header.code, the bits of its rsv_word and
 * control fields, and the bits of &struct ecmxf_rsp_header (err_status,
 * ecm_status, ecat_state, int_flags).  The protocol core of the driver
 * (lib/core) uses these very definitions; a program needs nothing else to
 * talk to the chip through %ECMXF_IOC_CMD.
 */

/*
 * Command codes (&struct ecmxf_cmd_header.code, &struct
 * ecmxf_rsp_header.code): the manuals' ECM_CMD_* names without the ECM_
 * prefix.  Async ("blocking" in ver. 038) commands are marked; %ECMXF_IOC_CMD
 * waits for the end of their busy phase, and a *_REQ's result is then read
 * with its *_GET partner.  %ECMXF_CMD_ASYNCCMD_RESET and %ECMXF_CMD_WARM_RESET
 * are sent by %ECMXF_IOC_RESET only.
 */
#define ECMXF_CMD_INFO_UPDATE_OP		0	/* no-op, refreshes the header */
#define ECMXF_CMD_ECAT_INIT_OP			1	/* async: scan and initialise the bus */
#define ECMXF_CMD_ECAT_RECONFIG_OP		2	/* async */
#define ECMXF_CMD_ECAT_INIT_DC_OP		3	/* async */
#define ECMXF_CMD_ECAT_PDO_WC_GET		4
#define ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP		5
#define ECMXF_CMD_ECAT_PDO_DATA_OP		6
#define ECMXF_CMD_ECAT_PDO_CONFIG_SET		7	/* async */
#define ECMXF_CMD_ECAT_PDO_CONFIG_REQ		8	/* async, then PDO_CONFIG_GET */
#define ECMXF_CMD_ECAT_PDO_CONFIG_GET		9
#define ECMXF_CMD_ECAT_SDO_REQ			10	/* async, then SDO_GET */
#define ECMXF_CMD_ECAT_SDO_GET			11
#define ECMXF_CMD_ECAT_STATE_SET		12	/* async */
#define ECMXF_CMD_ECAT_STATE_GET		13
#define ECMXF_CMD_ECAT_SLV_INFO_GET		15
#define ECMXF_CMD_ECAT_SLV_CNT_GET		16	/* return value: slave count */
#define ECMXF_CMD_FIFO_ENABLE			18
#define ECMXF_CMD_FIFO_PACK_SIZE_GET		19
#define ECMXF_CMD_SPI_PACK_SIZE_GET		20
#define ECMXF_CMD_SPI_RECONFIG_OP		23
#define ECMXF_CMD_CRC_ERR_CNT_CLR		24
#define ECMXF_CMD_CRC_TYPE_SET			25
#define ECMXF_CMD_402_CONFIG_SET		26
#define ECMXF_CMD_402_STATE_SET			27
#define ECMXF_CMD_402_STATE_GET			28
#define ECMXF_CMD_402_CTL_SET			29
#define ECMXF_CMD_402_CTL_GET			30
#define ECMXF_CMD_GPIO_CONFIG_SET		31
#define ECMXF_CMD_GPIO_FUNC_OP			32
#define ECMXF_CMD_QEI_FUNC_OP			33
#define ECMXF_CMD_DAC_FUNC_OP			34
#define ECMXF_CMD_ADC_FUNC_OP			35
#define ECMXF_CMD_EEPROM_REQ			38	/* async, then EEPROM_GET */
#define ECMXF_CMD_EEPROM_GET			39
#define ECMXF_CMD_ECAT_STATE_CHECK		41	/* async */
#define ECMXF_CMD_ECAT_DCSYNC			50	/* async */
#define ECMXF_CMD_FIFO_CLR_OP			51
#define ECMXF_CMD_FIFO_SET_TX_CNT		52
#define ECMXF_CMD_FIFO_GET_TX_CNT		53
#define ECMXF_CMD_FIFO_SET_RX_CNT		54
#define ECMXF_CMD_FIFO_GET_RX_CNT		55
#define ECMXF_CMD_FW_VERSION_GET		56
#define ECMXF_CMD_ECAT_STATE_UPDATE		57	/* async */
#define ECMXF_CMD_ECAT_INT_SET_ENABLE		58
#define ECMXF_CMD_ECAT_INT_GET_ENABLE		59
#define ECMXF_CMD_FIFO_INIT			66
#define ECMXF_CMD_ECAT_SDO_ABORTCODE_GET	69	/* data: __le32 abort code */
#define ECMXF_CMD_ECAT_SET_FIFO_TH		70
#define ECMXF_CMD_ECAT_CONFIG_SM		71
#define ECMXF_CMD_ECAT_CONFIG_FMMU		72	/* obsolete */
#define ECMXF_CMD_ECAT_CONFIG_MAP		73	/* async */
#define ECMXF_CMD_402_GET_STATUSWORD		74
#define ECMXF_CMD_ASYNCCMD_RESET		75	/* %ECMXF_IOC_RESET only */
#define ECMXF_CMD_MDIO				81
#define ECMXF_CMD_DIRECT_ASSIGN			82
#define ECMXF_CMD_COE_EMERGENCY			83
#define ECMXF_CMD_WARM_RESET			127	/* %ECMXF_IOC_RESET only */
#define ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET	130
#define ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET	131
#define ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET	132
#define ECMXF_CMD_RAW_ECAT_FUNC_REQ		137	/* async, then RAW_ECAT_FUNC_GET */
#define ECMXF_CMD_RAW_ECAT_FUNC_GET		138
#define ECMXF_CMD_FOE_FUNC_REQ			139	/* async, then FOE_FUNC_GET */
#define ECMXF_CMD_FOE_FUNC_GET			140
#define ECMXF_CMD_ENABLE_LRW			142
#define ECMXF_CMD_RECV_MAILBOX			143	/* async with param 0 */
#define ECMXF_CMD_MBX_STAT			144

/* &struct ecmxf_cmd_header.rsv_word (packet word 0x08) */
#define ECMXF_RSV_LRW			(1U << 11)	/* ECAT_INIT_OP: enable LRW */
#define ECMXF_RSV_BUS_SHIFT		(1U << 12)	/* ECAT_INIT_OP: bus shift mode */
#define ECMXF_RSV_GPIO_OUT		(1U << 15)	/* gpio_out is valid */

/*
 * &struct ecmxf_cmd_header.control (packet byte 0x0A, ver. 050): refresh the
 * EtherCAT state, or clear a counter or an error status bit (each
 * ECMXF_CTL_CLR_*_ERR clears the %ECMXF_ERR_* bit of the same number).
 */
#define ECMXF_CTL_REFRESH_STATE		(1U << 0)	/* read the state from the slaves */
#define ECMXF_CTL_CLR_CRC_CNT		(1U << 1)	/* clear crc_err_cnt */
#define ECMXF_CTL_CLR_ASYNC_ERR		(1U << 3)
#define ECMXF_CTL_CLR_SPI_ERR		(1U << 4)
#define ECMXF_CTL_CLR_FIFO_ERR		(1U << 5)
#define ECMXF_CTL_CLR_SPI_CRC_ERR	(1U << 6)
#define ECMXF_CTL_CLR_CMD_ERR		(1U << 7)

/* &struct ecmxf_rsp_header.err_status (packet byte 0x09, ver. 050) */
#define ECMXF_ERR_LINK_HW		(1U << 0)	/* Ethernet link up (hardware) */
#define ECMXF_ERR_LINK_SW		(1U << 1)	/* link seen at bus initialisation */
#define ECMXF_ERR_ASYNC			(1U << 3)	/* the async command failed */
#define ECMXF_ERR_SPI			(1U << 4)
#define ECMXF_ERR_FIFO			(1U << 5)
#define ECMXF_ERR_SPI_CRC		(1U << 6)
#define ECMXF_ERR_CMD			(1U << 7)	/* refused: bad parameter or busy */
#define ECMXF_ERR_FAULT_MASK		0xF8U		/* the bits that report a fault */

/* &struct ecmxf_rsp_header.ecm_status (packet byte 0x0A) */
#define ECMXF_STS_CHECK_MASK		0x03U		/* check word type, as devinfo.check_type */
#define ECMXF_STS_DC_STABLE		(1U << 2)
#define ECMXF_STS_ETH_INIT		(1U << 3)	/* Ethernet initialised */
#define ECMXF_STS_PDO_CONFIGURED	(1U << 4)
#define ECMXF_STS_NOP			(1U << 5)	/* this response answers no command */
#define ECMXF_STS_FIFO_EN		(1U << 6)	/* PDO FIFO enabled (the ring pump runs) */
#define ECMXF_STS_BUSY			(1U << 7)	/* an async command runs */

/*
 * &struct ecmxf_rsp_header.ecat_state (packet byte 0x08), also the state
 * byte of ECAT_STATE_SET (data[0]) and ECAT_STATE_GET (return value)
 */
#define ECMXF_ECAT_NONE			0x00U
#define ECMXF_ECAT_INIT			0x01U
#define ECMXF_ECAT_PREOP		0x02U
#define ECMXF_ECAT_BOOT			0x03U
#define ECMXF_ECAT_SAFEOP		0x04U
#define ECMXF_ECAT_OP			0x08U
#define ECMXF_ECAT_ERROR		0x10U

/*
 * INT1 interrupt flags: &struct ecmxf_rsp_header.int_flags and
 * &struct ecmxf_ring_status.int_flags (packet 0x10..0x13, read),
 * &struct ecmxf_cmd_header.int_clear (write 1 to clear), and the enable
 * mask of ECAT_INT_SET_ENABLE.  INT1 is asserted while a flag is set and
 * enabled; the PDO pump clears %ECMXF_INT_RXFIFO_LOW and
 * %ECMXF_INT_TXFIFO_HIGH with each of its commands.
 */
#define ECMXF_INT_WKC_ERR		(1U << 22)	/* working counter error */
#define ECMXF_INT_CRC_ERR		(1U << 23)	/* SPI CRC error */
#define ECMXF_INT_TXFIFO_HIGH		(1U << 24)	/* TxFIFO reached its high mark */
#define ECMXF_INT_RXFIFO_LOW		(1U << 25)	/* RxFIFO fell to its low mark */
#define ECMXF_INT_ENCODER		(1U << 29)	/* encoder (QEI) */
#define ECMXF_INT_ECAT_PKT		(1U << 31)	/* EtherCAT frame received (bus cycle) */

#endif /* _UAPI_LINUX_ECMXF_H */
