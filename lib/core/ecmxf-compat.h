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
/*
 * <linux/unaligned.h> since 6.12, <asm/unaligned.h> before.  The nested
 * test keeps tools without __has_include (sparse 0.6.4) on the old path;
 * the quoted form searches the same include path and is not misread by
 * checkpatch.pl as '<' and '>' operators.
 */
#if defined(__has_include)
#if __has_include("linux/unaligned.h")
#define ECMXF_HAVE_LINUX_UNALIGNED_H
#endif
#endif
#ifdef ECMXF_HAVE_LINUX_UNALIGNED_H
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
