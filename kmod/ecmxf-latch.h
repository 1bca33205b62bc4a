/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * ecmxf-latch.h - a value in two copies that readers never wait for
 *
 * The pattern of the kernel's seqcount_latch (and of the rings' status
 * block, &struct ecmxf_ring_status_block): one writer, serialised by the
 * caller, rewrites copy 0 while the count sends readers to copy 1, then
 * copy 1 while it sends them back.  A reader copies the copy the count
 * names and tries again only if the count moved meanwhile: it never
 * blocks, never takes a lock the writer holds, and a writer that preempted
 * it cannot make it wait (only retry once per publication).  For the
 * snapshots the real-time worker publishes and sysfs, netlink and the
 * ioctls read (Documentation/driver.rst, "Locking and PREEMPT_RT").
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_LATCH_H
#define ECMXF_LATCH_H

#include <linux/compiler.h>
#include <linux/string.h>
#include <linux/types.h>
#include <asm/barrier.h>

/**
 * ecmxf_latch_write() - publish @n bytes at @src in both copies
 * @seq: the count readers see (may live in memory userspace maps)
 * @kseq: the writer's own count (what the writer goes by, never read back
 *	from @seq)
 * @copy0: the first copy
 * @copy1: the second copy
 * @src: the new value
 * @n: its size
 */
static inline void ecmxf_latch_write(u32 *seq, u32 *kseq, void *copy0,
				     void *copy1, const void *src, size_t n)
{
	smp_wmb();	/* copy 1 complete before readers are sent to it */
	WRITE_ONCE(*seq, ++*kseq);
	smp_wmb();	/* readers see the count before copy 0 changes */
	memcpy(copy0, src, n);
	smp_wmb();	/* copy 0 complete before readers are sent back */
	WRITE_ONCE(*seq, ++*kseq);
	smp_wmb();	/* readers see the count before copy 1 changes */
	memcpy(copy1, src, n);
}

/**
 * ecmxf_latch_read() - read @n bytes of the copy the count names
 * @seq: the count
 * @copy0: the first copy
 * @copy1: the second copy
 * @dst: the value read
 * @n: its size
 */
static inline void ecmxf_latch_read(const u32 *seq, const void *copy0,
				    const void *copy1, void *dst, size_t n)
{
	u32 s;

	do {
		s = READ_ONCE(*seq);
		smp_rmb();	/* the count before the copy */
		memcpy(dst, (s & 1) ? copy1 : copy0, n);
		smp_rmb();	/* the copy before the count again */
	} while (READ_ONCE(*seq) != s);
}

#endif /* ECMXF_LATCH_H */
