/* SPDX-License-Identifier: GPL-2.0-only WITH Linux-syscall-note */
/*
 * ecmxf-vspi.h - the test-only virtual SPI controller: bridge interface
 *
 * /dev/ecmxf-vspi is opened by one bridge process at a time.
 *
 *   read()   blocks until the SPI controller has a transfer, then returns
 *            its MOSI bytes (zeros for a receive-only transfer); the
 *            buffer must hold the whole transfer (-EMSGSIZE otherwise)
 *   write()  gives the MISO bytes of the transfer just read, exactly as
 *            many bytes as read() returned (-EINVAL otherwise)
 *   poll()   EPOLLIN while a transfer waits to be read
 *   ioctl ECMXF_VSPI_IOC_SET_LINES  sets the levels of the two GPIO lines
 *            (bit 0 INT0, bit 1 INT1; 1 = high) and raises the interrupts
 *            of the edges this makes
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_VSPI_H
#define ECMXF_VSPI_H

#include <linux/ioctl.h>
#include <linux/types.h>

#define ECMXF_VSPI_DEV		"/dev/ecmxf-vspi"
#define ECMXF_VSPI_MAX_XFER	4096
#define ECMXF_VSPI_LINE_INT0	0x1u
#define ECMXF_VSPI_LINE_INT1	0x2u

#define ECMXF_VSPI_IOC_SET_LINES	_IOW('V', 0x01, __u32)

#endif /* ECMXF_VSPI_H */
