/* SPDX-License-Identifier: GPL-2.0-only OR MIT */
/*
 * ecmxf-crc-simd.h - CRC-32 with carry-less multiplication (userspace)
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_CRC_SIMD_H
#define ECMXF_CRC_SIMD_H

#include "ecmxf-compat.h"

#if !defined(__KERNEL__) && defined(__x86_64__)
#define ECMXF_HAVE_CRC32_CLMUL 1
bool ecmxf_crc32_clmul_usable(void);
u32 ecmxf_crc32_clmul(u32 state, const u8 *p, size_t len);
#endif

#endif /* ECMXF_CRC_SIMD_H */
