// SPDX-License-Identifier: GPL-2.0-only OR MIT
/*
 * ecmxf-crc32-x86.c - CRC-32 by folding with PCLMULQDQ (userspace x86-64)
 *
 * The method of Gopal et al., "Fast CRC Computation for Generic
 * Polynomials Using PCLMULQDQ Instruction" (Intel, 2009), for the
 * reflected CRC-32 polynomial: four 128-bit lanes are folded 64 bytes at a
 * time, folded into one lane, then reduced to 32 bits (Barrett).  The
 * constants are x^n mod P(x) for the fold distances, bit-reflected:
 *	k1 = x^(4*128+32) mod P, k2 = x^(4*128-32) mod P  (64-byte fold)
 *	k3 = x^(128+32) mod P,   k4 = x^(128-32) mod P    (16-byte fold)
 *	k5 = x^64 mod P; mu = floor(x^64 / P); P' = P reflected.
 * The kernel build never compiles this file; its crc32_le() does the work.
 * tests/core/test_crc.cpp compares it with the table CRC on every length
 * and alignment it handles.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include "ecmxf-crc-simd.h"

#ifdef ECMXF_HAVE_CRC32_CLMUL

#include <immintrin.h>

#define ECMXF_CLMUL_TARGET __attribute__((target("pclmul,sse4.1")))

/**
 * ecmxf_crc32_clmul_usable() - may ecmxf_crc32_clmul() run on this CPU
 *
 * Return: true when the CPU has PCLMULQDQ and SSE4.1.
 */
bool ecmxf_crc32_clmul_usable(void)
{
	static int usable = -1;	/* racy but idempotent */

	if (usable < 0)
		usable = __builtin_cpu_supports("pclmul") &&
			 __builtin_cpu_supports("sse4.1");
	return usable;
}

static inline __m128i ecmxf_fold16(__m128i acc, __m128i k, __m128i next)
	ECMXF_CLMUL_TARGET;
static inline __m128i ecmxf_fold16(__m128i acc, __m128i k, __m128i next)
{
	__m128i lo = _mm_clmulepi64_si128(acc, k, 0x00);
	__m128i hi = _mm_clmulepi64_si128(acc, k, 0x11);

	return _mm_xor_si128(_mm_xor_si128(lo, hi), next);
}

/**
 * ecmxf_crc32_clmul() - advance a CRC-32 state over a block
 * @state: running CRC state (not yet inverted at the end)
 * @p: bytes
 * @len: number of bytes, at least 64 and a multiple of 16
 *
 * Return: the new state.
 */
ECMXF_CLMUL_TARGET
u32 ecmxf_crc32_clmul(u32 state, const u8 *p, size_t len)
{
	const __m128i k1k2 = _mm_set_epi64x(0x1c6e41596LL, 0x154442bd4LL);
	const __m128i k3k4 = _mm_set_epi64x(0x0ccaa009eLL, 0x1751997d0LL);
	const __m128i k5 = _mm_set_epi64x(0, 0x163cd6124LL);
	const __m128i poly = _mm_set_epi64x(0x1f7011641LL, 0x1db710641LL);
	const __m128i mask32 = _mm_set_epi32(0, -1, 0, -1);
	__m128i x0, x1, x2, x3, t;

	x0 = _mm_loadu_si128((const __m128i *)(const void *)p);
	x1 = _mm_loadu_si128((const __m128i *)(const void *)(p + 16));
	x2 = _mm_loadu_si128((const __m128i *)(const void *)(p + 32));
	x3 = _mm_loadu_si128((const __m128i *)(const void *)(p + 48));
	x0 = _mm_xor_si128(x0, _mm_cvtsi32_si128((int)state));
	p += 64;
	len -= 64;

	while (len >= 64) {
		x0 = ecmxf_fold16(x0, k1k2, _mm_loadu_si128((const __m128i *)(const void *)p));
		x1 = ecmxf_fold16(x1, k1k2,
				  _mm_loadu_si128((const __m128i *)(const void *)(p + 16)));
		x2 = ecmxf_fold16(x2, k1k2,
				  _mm_loadu_si128((const __m128i *)(const void *)(p + 32)));
		x3 = ecmxf_fold16(x3, k1k2,
				  _mm_loadu_si128((const __m128i *)(const void *)(p + 48)));
		p += 64;
		len -= 64;
	}

	/* four lanes into one */
	x0 = ecmxf_fold16(x0, k3k4, x1);
	x0 = ecmxf_fold16(x0, k3k4, x2);
	x0 = ecmxf_fold16(x0, k3k4, x3);
	while (len >= 16) {
		x0 = ecmxf_fold16(x0, k3k4, _mm_loadu_si128((const __m128i *)(const void *)p));
		p += 16;
		len -= 16;
	}

	/* 128 -> 64 bits */
	t = _mm_clmulepi64_si128(x0, k3k4, 0x10);
	x0 = _mm_xor_si128(_mm_srli_si128(x0, 8), t);
	/* 64 -> 32 bits */
	t = _mm_srli_si128(x0, 4);
	x0 = _mm_clmulepi64_si128(_mm_and_si128(x0, mask32), k5, 0x00);
	x0 = _mm_xor_si128(x0, t);
	/* Barrett reduction */
	t = _mm_clmulepi64_si128(_mm_and_si128(x0, mask32), poly, 0x10);
	t = _mm_clmulepi64_si128(_mm_and_si128(t, mask32), poly, 0x00);
	x0 = _mm_xor_si128(x0, t);
	return (u32)_mm_extract_epi32(x0, 1);
}

#endif /* ECMXF_HAVE_CRC32_CLMUL */
