// SPDX-License-Identifier: MIT
/*
 * ecmxf-sdo-read - bring the EtherCAT bus up to OP and read one SDO, with
 * nothing but open(), ioctl() and <linux/ecmxf.h> (no ecmxf library).
 *
 *   ecmxf-sdo-read DEVICE INDEX:SUB [SLAVE]
 *
 *   ecmxf-sdo-read /dev/ecmxf0 0x2001:0        slave 0 (the default)
 *   ecmxf-sdo-read /dev/ecmxf0 0x1018:1 1      vendor id of slave 1
 *
 * The value goes to stdout as one line, e.g.
 *
 *   0x2001:00 of slave 0 = 50000 (0xc350, 2 bytes)
 *
 * progress to stderr.  Exit status: 0 read, 1 a step failed (the message
 * names it), 2 bad arguments.
 *
 * The steps are those of the manuals' bring-up (Documentation/master.rst,
 * "Steps"), each one ECMXF_IOC_CMD:
 *
 *   ECAT_INIT_OP            scan the network (async)
 *   ECAT_SLV_CNT_GET        slave count (return value)
 *   ECAT_STATE_SET x 3      all slaves PRE-OP, SAFE-OP, OP (async)
 *   ECAT_STATE_GET          the slave's state (return value)
 *   ECAT_SDO_REQ            the upload (async), with ECAT_SDO_GET, its
 *                           data, as its result fetch (ECMXF_CMD_F_FETCH:
 *                           the kernel polls the running upload with it)
 *   ECAT_SDO_ABORTCODE_GET  why, when the upload failed
 *
 * An async command's ECMXF_IOC_CMD returns when the chip's busy phase has
 * ended; struct ecmxf_cmd.status then says how it went (-EREMOTEIO: the
 * chip's async-error bit, -EBUSY: the chip refused to start it).  An
 * immediate command that the chip refuses sets ECMXF_ERR_CMD in the
 * response's error status.  See Documentation/uapi.rst, "Using the uAPI
 * from C".
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <linux/ecmxf.h>

static const char *prog = "ecmxf-sdo-read";

/*
 * Time allowed for each command.  0 would select the driver's default
 * (100 ms for an immediate command, 10 s for INIT_OP and STATE_SET); a
 * loaded machine can need more than 100 ms.
 */
#define IMMEDIATE_TIMEOUT_US	5000000U
#define ASYNC_TIMEOUT_US	20000000U

/* ECAT_STATE_SET parameter: every slave */
#define ALL_SLAVES		0xFF

static void put_le16(__u8 *p, unsigned int v)
{
	p[0] = (__u8)v;
	p[1] = (__u8)(v >> 8);
}

static void put_le32(__u8 *p, unsigned long v)
{
	put_le16(p, (unsigned int)(v & 0xFFFF));
	put_le16(p + 2, (unsigned int)(v >> 16));
}

static unsigned long get_le32(const __u8 *p)
{
	return (unsigned long)p[0] | (unsigned long)p[1] << 8 |
	       (unsigned long)p[2] << 16 | (unsigned long)p[3] << 24;
}

/* A command with its data section; the answer's data goes to rx. */
static void cmd_init(struct ecmxf_cmd *c, unsigned int code, unsigned int param,
		     const __u8 *tx, unsigned int tx_len, __u8 *rx, unsigned int rx_size)
{
	memset(c, 0, sizeof(*c));	/* padding and reserved must be zero */
	c->hdr.code = (__u8)code;
	c->hdr.param = (__u8)param;
	c->hdr.len = (__u16)tx_len;
	c->tx_ptr = (__u64)(uintptr_t)tx;
	c->tx_len = tx_len;
	c->rx_ptr = (__u64)(uintptr_t)rx;
	c->rx_size = rx_size;
}

/*
 * Runs one command.  Returns 0 when the ioctl worked (the command's own
 * outcome is then c->status), -1 after saying why it did not.
 */
static int run(int fd, struct ecmxf_cmd *c, const char *what)
{
	if (ioctl(fd, ECMXF_IOC_CMD, c) < 0) {
		fprintf(stderr, "%s: %s: ioctl ECMXF_IOC_CMD failed: %s\n", prog, what,
			strerror(errno));
		return -1;
	}
	return 0;
}

/* An immediate command; 0 or -1 after saying why it failed. */
static int immediate(int fd, struct ecmxf_cmd *c, const char *what)
{
	/* a refusal left from an earlier command must not read as this one's */
	c->hdr.control |= ECMXF_CTL_CLR_CMD_ERR;
	c->timeout_us = IMMEDIATE_TIMEOUT_US;
	if (run(fd, c, what))
		return -1;
	if (c->status) {
		fprintf(stderr, "%s: %s failed: %s\n", prog, what, strerror(-c->status));
		return -1;
	}
	if (c->rsp.err_status & ECMXF_ERR_CMD) {
		fprintf(stderr,
			"%s: %s: the chip refused the command (error status bit 7: a parameter it does not accept)\n",
			prog, what);
		return -1;
	}
	return 0;
}

/*
 * An async command.  Returns 0, -1 after saying why it failed, or 1 when
 * the chip ran it and it failed (status -EREMOTEIO): the caller explains.
 */
static int async(int fd, struct ecmxf_cmd *c, const char *what)
{
	c->timeout_us = ASYNC_TIMEOUT_US;
	if (run(fd, c, what))
		return -1;
	if (c->status == -EREMOTEIO)
		return 1;
	if (c->status == -EBUSY) {
		fprintf(stderr, "%s: %s: the chip refused to start it (%s)\n", prog, what,
			c->rsp.ecm_status & ECMXF_STS_BUSY ?
			"another async command is running" : "a parameter it does not accept");
		return -1;
	}
	if (c->status) {
		fprintf(stderr, "%s: %s failed: %s\n", prog, what, strerror(-c->status));
		return -1;
	}
	return 0;
}

static const char *state_name(unsigned int state)
{
	switch (state & 0x0F) {
	case ECMXF_ECAT_INIT:
		return "INIT";
	case ECMXF_ECAT_PREOP:
		return "PRE-OP";
	case ECMXF_ECAT_BOOT:
		return "BOOT";
	case ECMXF_ECAT_SAFEOP:
		return "SAFE-OP";
	case ECMXF_ECAT_OP:
		return "OP";
	default:
		return "none";
	}
}

/* ECAT_INIT_OP: scan the network; DC on with a 1 ms SYNC0 cycle, LRW */
static int init_network(int fd)
{
	struct ecmxf_cmd c;
	__u8 d[16] = { 0xFF, 0x81 };	/* bytes 0 and 1 as the manual prescribes */
	int rc;

	put_le16(d + 2, 0x0300);	/* DC AssignActivate: cyclic unit + SYNC0 */
	put_le32(d + 4, 1000000);	/* SYNC0 cycle, ns */
	put_le32(d + 8, 0);		/* SYNC1 cycle, ns */
	put_le32(d + 12, 0);		/* shift time, ns */
	cmd_init(&c, ECMXF_CMD_ECAT_INIT_OP, 0, d, sizeof(d), NULL, 0);
	c.hdr.rsv_word = ECMXF_RSV_LRW;
	rc = async(fd, &c, "ECAT_INIT_OP");
	if (rc == 1)
		fprintf(stderr, "%s: ECAT_INIT_OP: the network scan failed: %s\n", prog,
			!(c.rsp.err_status & ECMXF_ERR_LINK_HW) ? "no Ethernet link" :
			!(c.rsp.err_status & ECMXF_ERR_LINK_SW) ? "the link was lost during the scan" :
			"no slave answered");
	return rc ? -1 : 0;
}

/* ECAT_STATE_SET for every slave */
static int set_state(int fd, unsigned int state)
{
	struct ecmxf_cmd c;
	char what[64];
	int rc;

	snprintf(what, sizeof(what), "ECAT_STATE_SET %s", state_name(state));
	cmd_init(&c, ECMXF_CMD_ECAT_STATE_SET, ALL_SLAVES, NULL, 0, NULL, 0);
	c.hdr.data[0] = (__u8)state;
	rc = async(fd, &c, what);
	if (rc == 1)
		fprintf(stderr, "%s: %s: not every slave reached the state (bus state now %s)\n",
			prog, what, state_name(c.rsp.ecat_state));
	return rc ? -1 : 0;
}

/* Prints the value: an unsigned number for 1, 2, 4 or 8 bytes, else text or bytes. */
static void print_value(unsigned int index, unsigned int sub, unsigned int slave,
			const __u8 *b, unsigned int n)
{
	unsigned int i, text = n > 0;

	printf("0x%04x:%02x of slave %u = ", index, sub, slave);
	if (n == 1 || n == 2 || n == 4 || n == 8) {
		unsigned long long v = 0;

		for (i = n; i > 0; i--)
			v = v << 8 | b[i - 1];
		printf("%llu (0x%llx, %u byte%s)\n", v, v, n, n == 1 ? "" : "s");
		return;
	}
	for (i = 0; i < n; i++)
		if ((b[i] < 0x20 || b[i] > 0x7E) && !(b[i] == 0 && i > 0))
			text = 0;
	if (text) {
		printf("\"%.*s\" (%u bytes)\n", (int)n, (const char *)b, n);
		return;
	}
	for (i = 0; i < n; i++)
		printf("%02x%s", b[i], i + 1 < n ? " " : "");
	printf(" (%u bytes)\n", n);
}

/* Parses a whole unsigned number (decimal, 0x hex or 0 octal) up to max. */
static int parse_num(const char *s, unsigned long max, unsigned long *out)
{
	char *end;

	if (!*s || *s == '-' || *s == '+' || *s == ' ')
		return -1;
	errno = 0;
	*out = strtoul(s, &end, 0);
	if (errno || *end || *out > max)
		return -1;
	return 0;
}

static int usage(void)
{
	fprintf(stderr,
		"usage: %s DEVICE INDEX:SUB [SLAVE]\n"
		"  brings the bus up to OP and reads object INDEX (0..0xffff), subindex SUB\n"
		"  (0..0xff) of the slave at position SLAVE (0..254, default 0)\n"
		"  e.g. %s /dev/ecmxf0 0x2001:0\n", prog, prog);
	return 2;
}

int main(int argc, char **argv)
{
	static __u8 rx[1408];	/* the largest data section */
	struct ecmxf_devinfo info;
	struct ecmxf_cmd c;
	unsigned long index, sub, slave = 0;
	unsigned int count;
	__u32 version = 0;
	__u8 d[12];
	char what[96], *colon;
	int fd, rc;

	if (argc < 3 || argc > 4)
		return usage();
	colon = strchr(argv[2], ':');
	if (!colon) {
		fprintf(stderr, "%s: '%s': expected INDEX:SUB, e.g. 0x2001:0\n", prog, argv[2]);
		return 2;
	}
	*colon = '\0';
	if (parse_num(argv[2], 0xFFFF, &index) || parse_num(colon + 1, 0xFF, &sub)) {
		fprintf(stderr, "%s: '%s:%s': INDEX must be 0..0xffff and SUB 0..0xff\n", prog,
			argv[2], colon + 1);
		return 2;
	}
	if (argc == 4 && parse_num(argv[3], 254, &slave)) {
		fprintf(stderr, "%s: slave position '%s' is not a number 0..254\n", prog, argv[3]);
		return 2;
	}

	/* bus commands need a file opened for writing */
	fd = open(argv[1], O_RDWR | O_CLOEXEC);
	if (fd < 0) {
		fprintf(stderr, "%s: cannot open %s: %s\n", prog, argv[1], strerror(errno));
		return 1;
	}

	/* the same ABI as the header this was built with */
	if (ioctl(fd, ECMXF_IOC_GET_VERSION, &version) < 0) {
		int err = errno;

		fprintf(stderr, "%s: %s: ioctl ECMXF_IOC_GET_VERSION failed: %s%s\n", prog, argv[1],
			strerror(err), err == ENOTTY ? " (not an ecmxf device?)" : "");
		goto fail;
	}
	if (version != ECMXF_UAPI_VERSION) {
		fprintf(stderr, "%s: %s speaks uAPI version %u, this program version %u\n", prog,
			argv[1], version, ECMXF_UAPI_VERSION);
		goto fail;
	}
	memset(&info, 0, sizeof(info));
	if (ioctl(fd, ECMXF_IOC_DEVINFO, &info) < 0) {
		fprintf(stderr, "%s: %s: ioctl ECMXF_IOC_DEVINFO failed: %s\n", prog, argv[1],
			strerror(errno));
		goto fail;
	}
	fprintf(stderr, "%s: %s: uAPI %u, data section %u bytes\n", prog, argv[1], version,
		info.data_size);

	/* bring-up: scan, count, PRE-OP -> SAFE-OP -> OP (one step at a time) */
	if (init_network(fd))
		goto fail;
	cmd_init(&c, ECMXF_CMD_ECAT_SLV_CNT_GET, 0, NULL, 0, NULL, 0);
	if (immediate(fd, &c, "ECAT_SLV_CNT_GET"))
		goto fail;
	count = c.rsp.ret;
	fprintf(stderr, "%s: ECAT_INIT_OP found %u slave%s\n", prog, count, count == 1 ? "" : "s");
	if (slave >= count) {
		fprintf(stderr, "%s: no slave at position %lu: the bus has %u slave%s\n", prog, slave,
			count, count == 1 ? "" : "s");
		goto fail;
	}
	if (set_state(fd, ECMXF_ECAT_PREOP) || set_state(fd, ECMXF_ECAT_SAFEOP) ||
	    set_state(fd, ECMXF_ECAT_OP))
		goto fail;
	cmd_init(&c, ECMXF_CMD_ECAT_STATE_GET, (unsigned int)slave, NULL, 0, NULL, 0);
	if (immediate(fd, &c, "ECAT_STATE_GET"))
		goto fail;
	if ((c.rsp.ret & 0x0F) != ECMXF_ECAT_OP) {
		fprintf(stderr, "%s: slave %lu is in %s, not OP, after ECAT_STATE_SET OP\n", prog,
			slave, state_name(c.rsp.ret));
		goto fail;
	}
	fprintf(stderr, "%s: all slaves in OP\n", prog);

	/*
	 * the upload: ECAT_SDO_REQ with ECAT_SDO_GET as its result fetch, in
	 * one ioctl; the answer and data are the fetch's (ECMXF_CMD_F_FETCHED)
	 */
	snprintf(what, sizeof(what), "ECAT_SDO_REQ upload of 0x%04lx:%02lx from slave %lu", index,
		 sub, slave);
	memset(d, 0, sizeof(d));
	d[0] = 1;			/* 1 upload (read), 0 download */
	d[1] = (__u8)slave;
	put_le16(d + 2, (unsigned int)index);
	d[4] = (__u8)sub;
	put_le16(d + 6, 0);		/* length: 0 = as long as the object */
	put_le32(d + 8, 0);		/* SDO timeout in us: 0 = the chip's */
	cmd_init(&c, ECMXF_CMD_ECAT_SDO_REQ, 0, d, sizeof(d), rx, sizeof(rx));
	c.flags = ECMXF_CMD_F_FETCH;
	c.fetch.code = ECMXF_CMD_ECAT_SDO_GET;
	/* a refusal left from an earlier command must not read as the fetch's */
	c.fetch.control = ECMXF_CTL_CLR_CMD_ERR;
	rc = async(fd, &c, what);
	if (rc == 1) {
		struct ecmxf_cmd a;

		cmd_init(&a, ECMXF_CMD_ECAT_SDO_ABORTCODE_GET, 0, NULL, 0, rx, sizeof(rx));
		if (immediate(fd, &a, "ECAT_SDO_ABORTCODE_GET"))
			goto fail;
		if (a.rx_len < 4) {
			fprintf(stderr, "%s: ECAT_SDO_ABORTCODE_GET: %u data bytes, expected 4\n", prog,
				a.rx_len);
			goto fail;
		}
		fprintf(stderr, "%s: %s failed: SDO abort code 0x%08lx\n", prog, what, get_le32(rx));
		goto fail;
	}
	if (rc)
		goto fail;
	if (!(c.flags & ECMXF_CMD_F_FETCHED) || (c.rsp.err_status & ECMXF_ERR_CMD)) {
		fprintf(stderr, "%s: ECAT_SDO_GET: %s\n", prog,
			!(c.flags & ECMXF_CMD_F_FETCHED) ? "not sent" :
			"the chip refused the command (error status bit 7)");
		goto fail;
	}
	if (c.rx_len >= info.data_size)
		fprintf(stderr, "%s: warning: the answer fills the data section; the object may be longer\n",
			prog);
	print_value((unsigned int)index, (unsigned int)sub, (unsigned int)slave, rx, c.rx_len);
	close(fd);
	return 0;

fail:
	close(fd);
	return 1;
}
