// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-ring.c - NEXTW ECM-XF: the mmap()ed PDO rings
 *
 * The claim holder sets up two single-producer/single-consumer rings
 * (ECMXF_IOC_RING_SETUP) and maps them: the output ring carries RxPDO
 * frames from the application to the chip, the input ring TxPDO frames
 * from the chip to the application (Documentation/uapi.rst).  This file
 * owns their memory: allocation, mmap(), the status block, poll(), the
 * stop and the teardown, and the few index operations the pump
 * (ecmxf-pump.c) moves frames with.
 *
 * Lifetime: &struct ecmxf_rings is reference counted.  &ecmxf_dev.pdo.rings
 * holds one reference, every mapping (vm_area) one, and the worker one
 * while a pump command is in the engine; RELEASE, the last close of the
 * file, a new setup or the chip's removal only drop the device's, so a
 * mapping stays valid memory until munmap().
 *
 * Locking: the ring indices are shared with userspace and ordered with
 * acquire/release; everything else is under &ecmxf_dev.lock (a mutex) or
 * belongs to the worker.  No spinlock is taken here.  The worker takes
 * the mutex around every exchange, so nothing that scales with the ring
 * size runs under it: references are detached under the lock and dropped
 * after it (the last one vfree()s the memory, page by page), and the
 * pages are mapped into a vm_area without it.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/log2.h>
#include <linux/mm.h>
#include <linux/poll.h>
#include <linux/slab.h>
#include <linux/vmalloc.h>

#include "ecmxf.h"
#include "ecmxf-latch.h"

/* where things are in each ring's memory (reported as offsets) */
#define ECMXF_RING_HEAD_OFF	0
#define ECMXF_RING_TAIL_OFF	64	/* own cache line: another writer */
#define ECMXF_RING_MASK_OFF	128
#define ECMXF_RING_ENTRIES_OFF	132
#define ECMXF_RING_FLAGS_OFF	136
#define ECMXF_RING_DROPPED_OFF	140
#define ECMXF_RING_STATUS_OFF	256
#define ECMXF_RING_FRAMES_OFF	512

/* pump timer period: default and bounds (microseconds) */
#define ECMXF_POLL_US_DEFAULT	1000
#define ECMXF_POLL_US_MIN	50
#define ECMXF_POLL_US_MAX	100000
/* the longest working counter period (microseconds) */
#define ECMXF_WKC_US_MAX	10000000

static_assert(sizeof(struct ecmxf_ring_status_block) <=
	      ECMXF_RING_FRAMES_OFF - ECMXF_RING_STATUS_OFF);

static void ecmxf_ring_free(struct ecmxf_ring *ring)
{
	vfree(ring->mem);
	ring->mem = NULL;
}

static void ecmxf_rings_release(struct kref *ref)
{
	struct ecmxf_rings *r = container_of(ref, struct ecmxf_rings, ref);

	ecmxf_ring_free(&r->out);
	ecmxf_ring_free(&r->in);
	kfree(r->tx_buf[0]);
	kfree(r->tx_buf[1]);
	kfree(r->rx_buf[0]);
	kfree(r->rx_buf[1]);
	kfree(r->wkc_buf);
	atomic_dec(&r->edev->pdo.alive);
	kfree(r);
}

/**
 * ecmxf_rings_put() - drop a reference to the rings
 * @r: the rings, or NULL
 *
 * The last reference frees the ring memory (vfree(): process context).
 * Never under &ecmxf_dev.lock: the worker would wait for the pages to be
 * freed (lockdep checks it).
 */
void ecmxf_rings_put(struct ecmxf_rings *r)
{
	if (!r)
		return;
	/* the device outlives the rings: each holder keeps the file open */
	lockdep_assert_not_held(&r->edev->lock);
	kref_put(&r->ref, ecmxf_rings_release);
}

/* Allocate and lay out one ring; @status: reserve the status block. */
static int ecmxf_ring_init(struct ecmxf_ring *ring, u32 entries,
			   u32 frame_size, bool status)
{
	struct ecmxf_ring_offsets *o = &ring->off;
	u32 stride = ALIGN(max_t(u32, frame_size, 1), 8);
	size_t size;

	size = PAGE_ALIGN(ECMXF_RING_FRAMES_OFF + (size_t)entries * stride);
	ring->mem = vmalloc_user(size);	/* zeroed */
	if (!ring->mem)
		return -ENOMEM;
	ring->size = size;
	ring->entries = entries;
	ring->frame_size = frame_size;
	ring->stride = stride;
	ring->head = ring->mem + ECMXF_RING_HEAD_OFF;
	ring->tail = ring->mem + ECMXF_RING_TAIL_OFF;
	ring->flags = ring->mem + ECMXF_RING_FLAGS_OFF;
	ring->dropped = ring->mem + ECMXF_RING_DROPPED_OFF;
	ring->frames = ring->mem + ECMXF_RING_FRAMES_OFF;
	*(u32 *)(ring->mem + ECMXF_RING_MASK_OFF) = entries - 1;
	*(u32 *)(ring->mem + ECMXF_RING_ENTRIES_OFF) = entries;
	*ring->flags = ECMXF_RING_S_ACTIVE;

	memset(o, 0, sizeof(*o));
	o->head = ECMXF_RING_HEAD_OFF;
	o->tail = ECMXF_RING_TAIL_OFF;
	o->mask = ECMXF_RING_MASK_OFF;
	o->entries = ECMXF_RING_ENTRIES_OFF;
	o->flags = ECMXF_RING_FLAGS_OFF;
	o->dropped = ECMXF_RING_DROPPED_OFF;
	o->frames = ECMXF_RING_FRAMES_OFF;
	o->frame_size = frame_size;
	o->frame_stride = stride;
	o->mmap_size = (u32)size;
	o->status = status ? ECMXF_RING_STATUS_OFF : 0;
	return 0;
}

static bool ecmxf_entries_valid(u32 n)
{
	return n >= 2 && n <= 4096 && is_power_of_2(n);
}

/**
 * ecmxf_rings_create() - validate a setup and allocate the rings
 * @edev: the device
 * @rs: the caller's setup (inputs checked here; @rs->out and @rs->in
 *	are filled in)
 * @sizes: RxPDO and TxPDO frame bytes (FIFO_PACK_SIZE_GET 0 and 1)
 * @depths: RxFIFO and TxFIFO depths (FIFO_GET_RX_CNT, FIFO_GET_TX_CNT)
 * @out: the new rings, one reference
 *
 * Return: 0, -EINVAL (a bad field), -ENODATA (no PDO frames either way),
 * -EMSGSIZE (a frame does not fit the data section) or -ENOMEM.
 */
int ecmxf_rings_create(struct ecmxf_dev *edev, struct ecmxf_ring_setup *rs,
		       const u16 sizes[2], const u8 depths[2],
		       struct ecmxf_rings **out)
{
	u32 poll_us = rs->poll_us ? rs->poll_us : ECMXF_POLL_US_DEFAULT;
	unsigned int data_size;
	struct ecmxf_rings *r;
	unsigned int i;
	int ret;

	mutex_lock(&edev->lock);
	data_size = edev->chip.data_size;
	mutex_unlock(&edev->lock);
	ret = ecmxf_pump_check(sizes[0], sizes[1], data_size, depths[0],
			       rs->rx_fill);
	if (ret)
		return ret;

	/* released when the last reference goes (ecmxf_rings_release()) */
	if (atomic_inc_return(&edev->pdo.alive) > ECMXF_RINGS_MAX) {
		atomic_dec(&edev->pdo.alive);
		return -EBUSY;
	}
	r = kzalloc(sizeof(*r), GFP_KERNEL);
	if (!r) {
		atomic_dec(&edev->pdo.alive);
		return -ENOMEM;
	}
	kref_init(&r->ref);
	r->edev = edev;
	for (i = 0; i < ARRAY_SIZE(r->tx_buf); i++) {
		r->tx_buf[i] = kzalloc(ECMXF_DATA_MAX, GFP_KERNEL);
		r->rx_buf[i] = kzalloc(ECMXF_DATA_MAX, GFP_KERNEL);
	}
	r->wkc_buf = kzalloc(ECMXF_DATA_MAX, GFP_KERNEL);
	ret = -ENOMEM;
	if (!r->tx_buf[0] || !r->tx_buf[1] || !r->rx_buf[0] ||
	    !r->rx_buf[1] || !r->wkc_buf)
		goto err;
	ret = ecmxf_ring_init(&r->out, rs->out_entries, sizes[0], false);
	if (ret)
		goto err;
	ret = ecmxf_ring_init(&r->in, rs->in_entries, sizes[1], true);
	if (ret)
		goto err;
	r->status = r->in.mem + ECMXF_RING_STATUS_OFF;
	r->setup_flags = rs->flags;
	ecmxf_pump_sched_init(&r->sched,
			      ((rs->flags & ECMXF_RING_F_FIFO_NEXT) ?
			       ECMXF_PUMP_S_FIFO_NEXT : 0) |
			      ((rs->flags & ECMXF_RING_F_WKC_NEXT) ?
			       ECMXF_PUMP_S_WKC_NEXT : 0),
			      (u64)poll_us * NSEC_PER_USEC,
			      (u64)rs->wkc_us * NSEC_PER_USEC);
	ecmxf_pump_init(&r->pump, sizes[0], sizes[1], data_size, depths[0],
			rs->rx_fill, depths[1]);
	rs->out = r->out.off;
	rs->in = r->in.off;
	*out = r;
	return 0;
err:
	ecmxf_rings_put(r);
	return ret;
}

/**
 * ecmxf_ring_setup_valid() - the checks of a setup that need no chip
 * @rs: the caller's setup
 *
 * Return: true when every input field is in range.
 */
bool ecmxf_ring_setup_valid(const struct ecmxf_ring_setup *rs)
{
	if (!ecmxf_entries_valid(rs->out_entries) ||
	    !ecmxf_entries_valid(rs->in_entries))
		return false;
	if (rs->flags & ~(ECMXF_RING_F_POLL_OUT | ECMXF_RING_F_POLL_IN |
			  ECMXF_RING_F_WKC_NEXT | ECMXF_RING_F_FIFO_NEXT))
		return false;
	if (rs->poll_us && (rs->poll_us < ECMXF_POLL_US_MIN ||
			    rs->poll_us > ECMXF_POLL_US_MAX))
		return false;
	if (rs->wkc_us > ECMXF_WKC_US_MAX)
		return false;
	if (rs->reserved[0] || rs->reserved[1])
		return false;
	return true;
}

static void ecmxf_ring_vm_open(struct vm_area_struct *vma)
{
	struct ecmxf_rings *r = vma->vm_private_data;

	kref_get(&r->ref);
}

static void ecmxf_ring_vm_close(struct vm_area_struct *vma)
{
	ecmxf_rings_put(vma->vm_private_data);
}

static const struct vm_operations_struct ecmxf_ring_vm_ops = {
	.open = ecmxf_ring_vm_open,
	.close = ecmxf_ring_vm_close,
};

/**
 * ecmxf_rings_mmap() - map one ring (the vma's offset selects it)
 * @r: the rings of the caller, who holds the claim; a reference that
 *	the caller gave for this mapping
 * @vma: the new mapping
 *
 * Called without &ecmxf_dev.lock: inserting the pages takes time that
 * grows with the ring.
 *
 * Return: 0 (the mapping keeps the reference), or -EINVAL for a bad
 * offset, length or a private mapping (the reference is dropped).
 */
int ecmxf_rings_mmap(struct ecmxf_rings *r, struct vm_area_struct *vma)
{
	unsigned long len = vma->vm_end - vma->vm_start;
	u64 off = (u64)vma->vm_pgoff << PAGE_SHIFT;
	struct ecmxf_ring *ring;
	int ret;

	if (off == ECMXF_RING_OFF_OUT)
		ring = &r->out;
	else if (off == ECMXF_RING_OFF_IN)
		ring = &r->in;
	else
		ring = NULL;
	ret = -EINVAL;
	if (ring && (vma->vm_flags & VM_SHARED) && len <= ring->size)
		ret = remap_vmalloc_range(vma, ring->mem, 0);
	if (ret) {
		ecmxf_rings_put(r);
		return ret;
	}
	vma->vm_private_data = r;
	vma->vm_ops = &ecmxf_ring_vm_ops;
	return 0;
}

/**
 * ecmxf_rings_wake() - wake the claim holder's poll()ers
 * @edev: the device, lock held
 * @mask: the poll bits that became true
 */
void ecmxf_rings_wake(struct ecmxf_dev *edev, __poll_t mask)
{
	lockdep_assert_held(&edev->lock);
	if (edev->claim.holder)
		wake_up_interruptible_poll(&edev->claim.holder->wq, mask);
}

/**
 * ecmxf_rings_teardown() - the claim ends: the kernel lets go of the rings
 * @edev: the device, lock held
 *
 * The flags words lose %ECMXF_RING_S_ACTIVE and the rings are no longer
 * the device's; the memory lives on while mappings (or the worker's
 * command) hold references.  The holder's poll()ers wake: a new setup's
 * rings report their own bits, and without rings a poll() for ring
 * events gets EPOLLERR (&ecmxf_client.rings_lost).
 *
 * Return: the device's reference, or NULL without rings.  The caller
 * drops it with ecmxf_rings_put() after unlocking.
 */
struct ecmxf_rings *ecmxf_rings_teardown(struct ecmxf_dev *edev)
{
	struct ecmxf_rings *r = edev->pdo.rings;
	u32 flags;

	lockdep_assert_held(&edev->lock);
	if (!r)
		return NULL;
	/* the kernel's own state, not what the mapping says now */
	flags = r->stopped ? ECMXF_RING_S_ERROR : 0;
	/* pairs with the application's load-acquire of the flags word */
	smp_store_release(r->out.flags, flags);
	/* the same for the input ring */
	smp_store_release(r->in.flags, flags);
	edev->pdo.rings = NULL;
	if (edev->claim.holder) {
		edev->claim.holder->rings_lost = true;
		wake_up_interruptible_poll(&edev->claim.holder->wq,
					   EPOLLERR | EPOLLOUT | EPOLLRDBAND);
	}
	return r;
}

/**
 * ecmxf_rings_publish() - publish &ecmxf_rings.cur in the status block
 * @r: the rings, &ecmxf_dev.lock held (the one writer)
 *
 * The block is a latch of two copies (&struct ecmxf_ring_status_block,
 * like the kernel's seqcount_latch): the count moves readers to copy 1
 * while copy 0 is rewritten, then back to copy 0 while copy 1 is.  A
 * reader never waits for this writer, even one that preempted it on the
 * same CPU.  The count the kernel goes by is its own (@r->status_seq):
 * what userspace writes into the shared page cannot confuse it.
 */
void ecmxf_rings_publish(struct ecmxf_rings *r)
{
	struct ecmxf_ring_status_block *b = r->status;

	r->cur.generation++;
	ecmxf_latch_write(&b->seq, &r->status_seq, &b->copy[0], &b->copy[1],
			  &r->cur, sizeof(r->cur));
}

/**
 * ecmxf_rings_stop() - the pump stops for good (chip reset, lost link)
 * @edev: the device, lock held
 * @err: the negative errno that stopped it
 *
 * Sets %ECMXF_RING_S_ERROR, clears %ECMXF_RING_S_ACTIVE and wakes the
 * poll()ers with EPOLLERR.  The rings stay until RELEASE, a new setup or
 * the last close of the file.  The chip's removal stops them too, with
 * -ENODEV.
 */
void ecmxf_rings_stop(struct ecmxf_dev *edev, int err)
{
	struct ecmxf_rings *r = edev->pdo.rings;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped)
		return;
	r->stopped = true;
	r->cur.error = (u32)-err;
	ecmxf_rings_publish(r);
	/* pairs with the application's load-acquire of the flags word */
	smp_store_release(r->out.flags, ECMXF_RING_S_ERROR);
	/* the same for the input ring */
	smp_store_release(r->in.flags, ECMXF_RING_S_ERROR);
	dev_warn(&edev->dev, "PDO rings stopped: %d\n", err);
	ecmxf_rings_wake(edev, EPOLLERR);
}

/**
 * ecmxf_rings_poll() - poll() bits of the rings for the claim holder
 * @edev: the device, lock held, caller holds the claim
 *
 * Return: EPOLLRDBAND while the input ring has frames (with
 * %ECMXF_RING_F_POLL_IN; EPOLLIN is the completions' bit), EPOLLOUT |
 * EPOLLWRNORM while the output ring has room (with %ECMXF_RING_F_POLL_OUT),
 * EPOLLERR once the pump stopped.
 */
__poll_t ecmxf_rings_poll(struct ecmxf_dev *edev)
{
	struct ecmxf_rings *r = edev->pdo.rings;
	__poll_t mask = 0;
	u32 head, tail;

	lockdep_assert_held(&edev->lock);
	if (!r)
		return 0;
	if (r->stopped)
		mask |= EPOLLERR;
	if (r->setup_flags & ECMXF_RING_F_POLL_IN) {
		/* pairs with the consumer's store-release of head */
		head = smp_load_acquire(r->in.head);
		tail = r->in.kidx;
		if (head != tail)
			mask |= EPOLLRDBAND;
	}
	if (r->setup_flags & ECMXF_RING_F_POLL_OUT) {
		head = r->out.kidx;
		/* pairs with the producer's store-release of tail */
		tail = smp_load_acquire(r->out.tail);
		if (tail - head < r->out.entries)
			mask |= EPOLLOUT | EPOLLWRNORM;
	}
	return mask;
}

/**
 * ecmxf_ring_out_avail() - output frames ready for the pump
 * @r: the rings
 *
 * Return: the frames between the kernel's head and the application's
 * tail, or -EFAULT when the application moved its tail more than the ring
 * holds away from the head.
 */
int ecmxf_ring_out_avail(struct ecmxf_rings *r)
{
	/* pairs with the producer's store-release: the frames are written */
	u32 tail = smp_load_acquire(r->out.tail);
	u32 avail = tail - r->out.kidx;

	return avail > r->out.entries ? -EFAULT : (int)avail;
}

/**
 * ecmxf_ring_out_copy() - copy the oldest output frames
 * @r: the rings
 * @dst: room for @n frames of the output frame size, back to back
 * @n: frames, at most ecmxf_ring_out_avail()
 */
void ecmxf_ring_out_copy(struct ecmxf_rings *r, u8 *dst, u32 n)
{
	const struct ecmxf_ring *out = &r->out;
	u32 head = out->kidx;
	u32 i;

	for (i = 0; i < n; i++)
		memcpy(dst + i * out->frame_size,
		       out->frames + ((head + i) & (out->entries - 1)) *
				     out->stride,
		       out->frame_size);
}

/**
 * ecmxf_ring_out_release() - the oldest output frames are done with
 * @r: the rings
 * @n: frames to free, at most ecmxf_ring_out_avail()
 * @dropped: of those, frames that never reached the bus (added to the
 *	ring's dropped count)
 */
void ecmxf_ring_out_release(struct ecmxf_rings *r, u32 n, u32 dropped)
{
	r->out.kidx += n;
	/* the slots are read: pairs with the producer's acquire */
	smp_store_release(r->out.head, r->out.kidx);
	if (dropped) {
		r->out.kdropped += dropped;
		WRITE_ONCE(*r->out.dropped, r->out.kdropped);
	}
}

/**
 * ecmxf_ring_in_store() - append input frames to the input ring
 * @r: the rings
 * @src: @n frames of the input frame size, back to back
 * @n: frames
 *
 * The frames the ring has no room for are dropped and counted in the
 * ring's dropped count.
 *
 * Return: the frames stored.
 */
u32 ecmxf_ring_in_store(struct ecmxf_rings *r, const u8 *src, u32 n)
{
	struct ecmxf_ring *in = &r->in;
	u32 tail = in->kidx;
	/* pairs with the consumer's store-release: its slots are free */
	u32 head = smp_load_acquire(in->head);
	u32 i, room, want = n;

	room = tail - head >= in->entries ? 0 : in->entries - (tail - head);
	n = min(n, room);
	for (i = 0; i < n; i++)
		memcpy(in->frames + ((tail + i) & (in->entries - 1)) * in->stride,
		       src + i * in->frame_size, in->frame_size);
	in->kidx = tail + n;
	/* the frames before the index: pairs with the consumer's acquire */
	smp_store_release(in->tail, in->kidx);
	if (n < want) {
		in->kdropped += want - n;
		WRITE_ONCE(*in->dropped, in->kdropped);
	}
	return n;
}
