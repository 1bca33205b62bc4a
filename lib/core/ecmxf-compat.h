/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmxf-compat.h - what the protocol core needs from its platform
 *
 * In the kernel the core uses <linux/...> headers and crc32_le(); in
 * userspace it uses the C library's fixed-width types and its own CRC
 * tables.  Nothing else differs between the two builds.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_COMPAT_H
#define ECMXF_COMPAT_H

#ifdef __KERNEL__
#include <linux/types.h>
#include <linux/errno.h>
#include <linux/kernel.h>
#include <linux/string.h>
#include <linux/version.h>
/*
 * The kernel API differences between the kernels ecmxf.ko is tested on
 * (Debian's 6.1 and 6.12, amd64 and arm64: Documentation/kernel-testing.rst,
 * "The kernel matrix").  Every kernel version test of the module is here;
 * every kmod/ file reaches this header through ecmxf.h and ecmxf-proto.h.
 *
 * <linux/unaligned.h> since 6.12, <asm/unaligned.h> before.  A version
 * test, not __has_include: sparse 0.6.4 has no __has_include and must see
 * the same header as the compiler.
 */
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 12, 0)
#include <linux/unaligned.h>
#else
#include <asm/unaligned.h>
#endif
#else
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <errno.h>

typedef uint8_t u8;
typedef uint16_t u16;
typedef uint32_t u32;
typedef uint64_t u64;
typedef int16_t s16;

#ifndef __cplusplus	/* helpers for the C sources only */
#ifndef ARRAY_SIZE
#define ARRAY_SIZE(a)	(sizeof(a) / sizeof((a)[0]))
#endif

static inline u16 get_unaligned_le16(const void *p)
{
	const u8 *b = (const u8 *)p;

	return (u16)(b[0] | (b[1] << 8));
}

static inline u32 get_unaligned_le32(const void *p)
{
	const u8 *b = (const u8 *)p;

	return (u32)b[0] | ((u32)b[1] << 8) | ((u32)b[2] << 16) |
	       ((u32)b[3] << 24);
}

static inline void put_unaligned_le16(u16 v, void *p)
{
	u8 *b = (u8 *)p;

	b[0] = (u8)v;
	b[1] = (u8)(v >> 8);
}

static inline void put_unaligned_le32(u32 v, void *p)
{
	u8 *b = (u8 *)p;

	b[0] = (u8)v;
	b[1] = (u8)(v >> 8);
	b[2] = (u8)(v >> 16);
	b[3] = (u8)(v >> 24);
}
#endif
#endif /* __KERNEL__ */

#endif /* ECMXF_COMPAT_H */
