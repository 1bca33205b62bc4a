// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-ring.c - NEXTW ECM-XF: the mmap()ed PDO rings and the PDO pump
 *
 * The claim holder sets up two single-producer/single-consumer rings
 * (ECMXF_IOC_RING_SETUP) and maps them: the output ring carries RxPDO
 * frames from the application to the chip, the input ring TxPDO frames
 * from the chip to the application (Documentation/uapi.rst).  The pump
 * runs in the link worker (ecmxf-worker.c): while the chip reports its
 * FIFO enabled it sends ECAT_PDO_DATA_FIFO_OP commands that move output
 * frames into the chip's RxFIFO (up to the fill level, a margin of two
 * below the depth because the header's counts lag) and pop the TxFIFO
 * into the input ring; now and then it reads the working counter.  It is
 * woken by INT1 (the FIFO threshold flags), by its own timer and by the
 * work a previous command left.  Its commands take turns with the files'
 * commands.
 *
 * Lifetime: &struct ecmxf_rings is reference counted.  &ecmxf_dev.rings
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

/* where things are in each ring's memory (reported as offsets) */
#define ECMXF_RING_HEAD_OFF	0
#define ECMXF_RING_TAIL_OFF	64	/* own cache line: another writer */
#define ECMXF_RING_MASK_OFF	128
#define ECMXF_RING_ENTRIES_OFF	132
#define ECMXF_RING_FLAGS_OFF	136
#define ECMXF_RING_DROPPED_OFF	140
#define ECMXF_RING_STATUS_OFF	256
#define ECMXF_RING_FRAMES_OFF	512

/*
 * time allowed for each pump command (module parameter pump_timeout_ms,
 * 10..60000): longer than the table's 100 ms, since a frame whose command
 * failed is dropped, never sent again
 */
static unsigned int ecmxf_param_pump_timeout_ms = 500;
module_param_named(pump_timeout_ms, ecmxf_param_pump_timeout_ms, uint, 0644);
MODULE_PARM_DESC(pump_timeout_ms,
		 "time allowed for each PDO pump command, ms (10..60000, default 500)");

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
	kfree(r->tx_buf);
	kfree(r->rx_buf);
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
	u32 max_fill = depths[0] > 2 ? depths[0] - 2u : 1u;
	u32 poll_us = rs->poll_us ? rs->poll_us : ECMXF_POLL_US_DEFAULT;
	unsigned int data_size;
	struct ecmxf_rings *r;
	int ret;

	if (rs->rx_fill > max_fill)
		return -EINVAL;
	if (!sizes[0] && !sizes[1])
		return -ENODATA;
	mutex_lock(&edev->lock);
	data_size = edev->data_size;
	mutex_unlock(&edev->lock);
	if (sizes[0] > data_size || sizes[1] > data_size)
		return -EMSGSIZE;

	r = kzalloc(sizeof(*r), GFP_KERNEL);
	if (!r)
		return -ENOMEM;
	kref_init(&r->ref);
	r->edev = edev;
	r->tx_buf = kzalloc(ECMXF_DATA_MAX, GFP_KERNEL);
	r->rx_buf = kzalloc(ECMXF_DATA_MAX, GFP_KERNEL);
	ret = -ENOMEM;
	if (!r->tx_buf || !r->rx_buf)
		goto err;
	ret = ecmxf_ring_init(&r->out, rs->out_entries, sizes[0], false);
	if (ret)
		goto err;
	ret = ecmxf_ring_init(&r->in, rs->in_entries, sizes[1], true);
	if (ret)
		goto err;
	r->status = r->in.mem + ECMXF_RING_STATUS_OFF;
	r->setup_flags = rs->flags;
	r->poll_ns = (u64)poll_us * NSEC_PER_USEC;
	r->wkc_ns = (u64)rs->wkc_us * NSEC_PER_USEC;
	r->rx_fill = rs->rx_fill ? rs->rx_fill : max_fill;
	r->rx_depth = depths[0];
	r->tx_depth = depths[1];
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
	if (rs->flags & ~(ECMXF_RING_F_POLL_OUT | ECMXF_RING_F_POLL_IN))
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

/* Wake the claim holder's poll()ers; lock held. */
static void ecmxf_rings_wake(struct ecmxf_dev *edev, __poll_t mask)
{
	lockdep_assert_held(&edev->lock);
	if (edev->claim)
		wake_up_interruptible_poll(&edev->claim->wq, mask);
}

/**
 * ecmxf_rings_teardown() - the claim ends: the kernel lets go of the rings
 * @edev: the device, lock held
 *
 * The flags words lose %ECMXF_RING_S_ACTIVE and the rings are no longer
 * the device's; the memory lives on while mappings (or the worker's
 * command) hold references.
 *
 * Return: the device's reference, or NULL without rings.  The caller
 * drops it with ecmxf_rings_put() after unlocking.
 */
struct ecmxf_rings *ecmxf_rings_teardown(struct ecmxf_dev *edev)
{
	struct ecmxf_rings *r = edev->rings;

	lockdep_assert_held(&edev->lock);
	if (!r)
		return NULL;
	WRITE_ONCE(*r->out.flags, READ_ONCE(*r->out.flags) & ~ECMXF_RING_S_ACTIVE);
	WRITE_ONCE(*r->in.flags, READ_ONCE(*r->in.flags) & ~ECMXF_RING_S_ACTIVE);
	edev->rings = NULL;
	return r;
}

/*
 * Publish @r->cur in the mapped status block, a latch of two copies
 * (&struct ecmxf_ring_status_block, like the kernel's seqcount_latch):
 * the count moves readers to copy 1 while copy 0 is rewritten, then back
 * to copy 0 while copy 1 is.  A reader never waits for this writer, even
 * one that preempted it on the same CPU.  The count the kernel goes by is
 * its own (@r->status_seq): what userspace writes into the shared page
 * cannot confuse it.  &ecmxf_dev.lock held (the one writer).
 */
static void ecmxf_status_publish(struct ecmxf_rings *r)
{
	struct ecmxf_ring_status_block *b = r->status;

	r->cur.generation++;
	smp_wmb();	/* copy 1 complete before readers are sent to it */
	WRITE_ONCE(b->seq, ++r->status_seq);
	smp_wmb();	/* readers see the count before copy 0 changes */
	memcpy(&b->copy[0], &r->cur, sizeof(r->cur));
	smp_wmb();	/* copy 0 complete before readers are sent back */
	WRITE_ONCE(b->seq, ++r->status_seq);
	smp_wmb();	/* readers see the count before copy 1 changes */
	memcpy(&b->copy[1], &r->cur, sizeof(r->cur));
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
	struct ecmxf_rings *r = edev->rings;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped)
		return;
	r->stopped = true;
	r->cur.error = (u32)-err;
	ecmxf_status_publish(r);
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
	struct ecmxf_rings *r = edev->rings;
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
		tail = READ_ONCE(*r->in.tail);
		if (head != tail)
			mask |= EPOLLRDBAND;
	}
	if (r->setup_flags & ECMXF_RING_F_POLL_OUT) {
		head = READ_ONCE(*r->out.head);
		/* pairs with the producer's store-release of tail */
		tail = smp_load_acquire(r->out.tail);
		if (tail - head < r->out.entries)
			mask |= EPOLLOUT | EPOLLWRNORM;
	}
	return mask;
}

/*
 * Output frames ready in the ring, or -EFAULT when userspace moved its
 * tail more than the ring holds away from our head.
 */
static int ecmxf_out_avail(struct ecmxf_rings *r)
{
	/* pairs with the producer's store-release: the frames are written */
	u32 tail = smp_load_acquire(r->out.tail);
	u32 avail = tail - READ_ONCE(*r->out.head);

	return avail > r->out.entries ? -EFAULT : (int)avail;
}

/**
 * ecmxf_pump_take() - should the pump send a command now?
 * @edev: the device, lock held
 * @now: ktime_get_ns()
 *
 * Due when rings exist, the pump has not stopped, the chip's FIFO is on
 * (ECM status bit 6 in the last header) and: its timer expired, INT1 fired
 * (the FIFO threshold flags), the last command left work, or the working
 * counter is due.
 *
 * Return: the rings with a reference for the command, or NULL.
 */
struct ecmxf_rings *ecmxf_pump_take(struct ecmxf_dev *edev, u64 now)
{
	struct ecmxf_rings *r = edev->rings;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped || edev->pump.busy)
		return NULL;
	if (!(edev->last.ecm_status & ECMXF_STS_FIFO_EN))
		return NULL;
	if (!r->again && now < r->next_tick_ns &&
	    !atomic_read(&edev->int1_flag) &&
	    !(r->wkc_ns && now >= r->next_wkc_ns))
		return NULL;
	/* this command is the exchange that INT1 asks for */
	atomic_set(&edev->int1_flag, 0);
	kref_get(&r->ref);
	return r;
}

/**
 * ecmxf_pump_deadline() - when the pump wants to run next by its timers
 * @edev: the device, lock held
 *
 * Return: a ktime_get_ns() time, or 0 when the pump has no timer running.
 */
u64 ecmxf_pump_deadline(struct ecmxf_dev *edev)
{
	struct ecmxf_rings *r = edev->rings;
	u64 t;

	lockdep_assert_held(&edev->lock);
	if (!r || r->stopped || !(edev->last.ecm_status & ECMXF_STS_FIFO_EN))
		return 0;
	t = r->next_tick_ns;
	if (r->wkc_ns && r->next_wkc_ns < t)
		t = r->next_wkc_ns;
	return t ? t : 1;
}

/*
 * Build the pump's next command in @edev->pump.x: the working counter
 * when due, else an ECAT_PDO_DATA_FIFO_OP that pushes what the output
 * ring holds (up to the RxFIFO fill level and the data section) and pops
 * TxPDO frames.  Return: false when there is nothing to send.
 */
static bool ecmxf_pump_build(struct ecmxf_dev *edev, struct ecmxf_rings *r,
			     u64 now)
{
	struct ecmxf_pump *p = &edev->pump;
	struct ecmxf_xfer *x = &p->x;
	unsigned int data_size = ecmxf_engine_data_size(&edev->e);
	const struct ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&edev->e);
	u32 level, space, per_write, k = 0, i, head, skip;
	bool after_wkc = p->wkc;
	int avail;

	memset(x, 0, sizeof(*x));
	x->rx_buf = r->rx_buf;
	x->rx_size = ECMXF_DATA_MAX;
	x->tx_data = r->tx_buf;
	x->status = -EINPROGRESS;
	p->pushed = 0;
	p->skipped = 0;
	p->wkc = false;

	/*
	 * the working counter when due, but never twice in a row: on a slow
	 * link (each command longer than wkc_us) it would starve the FIFOs
	 */
	if (r->wkc_ns && now >= r->next_wkc_ns && !after_wkc) {
		x->hdr.code = ECMXF_CMD_ECAT_PDO_WC_GET;
		x->hdr.param = 3;
		x->hdr.control = ECMXF_CTL_CLR_CMD_ERR;
		/*
		 * every wkc_ns from the first read on, not from whenever the
		 * worker woke: late wake-ups must not stretch the period
		 * (a reader counting reads over N periods sees N / period);
		 * after a gap of more than a period, one read, no burst
		 */
		r->next_wkc_ns += r->wkc_ns;
		if (r->next_wkc_ns <= now)
			r->next_wkc_ns = now + r->wkc_ns;
		p->wkc = true;
		return true;
	}

	avail = ecmxf_out_avail(r);
	if (avail < 0)
		return false;	/* ecmxf_pump_submit() stops the rings */
	level = (h ? h->rx_fifo_cnt : 0) + r->unconfirmed;
	space = r->rx_fill > level ? r->rx_fill - level : 0;
	per_write = r->out.frame_size ?
		    min_t(u32, 255, data_size / r->out.frame_size) : 0;
	head = READ_ONCE(*r->out.head);
	/*
	 * Fallen behind (the application produces faster than the chip
	 * takes): skip the oldest frames beyond what the RxFIFO can take now
	 * plus the fill level, so that the newest outputs reach the bus
	 * within about twice the fill level.  Counted, never silent.
	 */
	if ((u32)avail > space + r->rx_fill) {
		skip = (u32)avail - space - r->rx_fill;
		head += skip;
		/* the slots are done with: pairs with the producer's acquire */
		smp_store_release(r->out.head, head);
		WRITE_ONCE(*r->out.dropped, READ_ONCE(*r->out.dropped) + skip);
		p->skipped = skip;
		avail -= (int)skip;
	}
	k = min3((u32)avail, space, per_write);
	if (!k && !r->in.frame_size)
		return false;

	for (i = 0; i < k; i++)
		memcpy(r->tx_buf + i * r->out.frame_size,
		       r->out.frames + ((head + i) & (r->out.entries - 1)) *
				       r->out.stride,
		       r->out.frame_size);
	x->hdr.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
	x->hdr.param = (u8)k;
	x->hdr.data[0] = (k ? 0x01 : 0) | (r->in.frame_size ? 0x02 : 0);
	/* error status bits 5 and 7 then belong to this command alone */
	x->hdr.control = ECMXF_CTL_CLR_CMD_ERR | ECMXF_CTL_CLR_FIFO_ERR;
	/* re-arm the threshold flags that woke us (INT1 is edge-triggered) */
	x->hdr.int_clear = ECMXF_INT_RXFIFO_LOW | ECMXF_INT_TXFIFO_HIGH;
	x->tx_len = (u16)(k * r->out.frame_size);
	p->pushed = k;
	return true;
}

/**
 * ecmxf_pump_submit() - hand the pump's next command to the engine
 * @edev: the device; called by the worker without the lock
 * @r: the rings, with the reference ecmxf_pump_take() took
 * @now: ktime_get_ns()
 *
 * On success the reference travels with the command; otherwise it is
 * dropped here.
 *
 * Return: 0 when a command is in the engine, else a negative errno.
 */
int ecmxf_pump_submit(struct ecmxf_dev *edev, struct ecmxf_rings *r, u64 now)
{
	struct ecmxf_pump *p = &edev->pump;
	int ret;

	r->again = false;
	r->next_tick_ns = now + r->poll_ns;
	if (!ecmxf_pump_build(edev, r, now)) {
		ret = -ENODATA;
		if (ecmxf_out_avail(r) < 0)
			ret = -EFAULT;
		goto drop;
	}
	p->x.timeout_us = clamp(READ_ONCE(ecmxf_param_pump_timeout_ms),
				10U, 60000U) * USEC_PER_MSEC;
	if (!ecmxf_engine_can_submit(&edev->e, &p->x)) {
		ret = -EBUSY;
		goto drop;
	}
	ret = ecmxf_engine_submit(&edev->e, &p->x, now);
	if (ret)
		goto drop;
	mutex_lock(&edev->lock);
	p->rings = r;
	p->busy = true;
	p->turn = false;
	mutex_unlock(&edev->lock);
	return 0;
drop:
	mutex_lock(&edev->lock);
	edev->out_ring_skipped += p->skipped;
	p->skipped = 0;
	if (ret == -EFAULT && edev->rings == r)
		ecmxf_rings_stop(edev, -EFAULT);
	mutex_unlock(&edev->lock);
	ecmxf_rings_put(r);
	return ret;
}

/* Publish the header and the counters in the status block; lock held. */
static void ecmxf_status_update(struct ecmxf_rings *r,
				const struct ecmxf_rsp_hdr *h, int err,
				const u32 deltas[7])
{
	struct ecmxf_ring_status *st = &r->cur;

	st->int_flags = h->int_flags;
	st->crc_err_cnt = h->crc_err_cnt;
	st->wkc_err_cnt = h->wkc_err_cnt;
	st->tx_fifo_cnt = h->tx_fifo_cnt;
	st->rx_fifo_cnt = h->rx_fifo_cnt;
	st->ecat_state = h->ecat_state;
	st->err_status = h->err_status;
	st->ecm_status = h->ecm_status;
	st->error = (u32)-err;
	st->pump_ops += deltas[0];
	st->rx_refusals += deltas[1];
	st->tx_overflows += deltas[2];
	st->rx_underruns += deltas[3];
	st->out_underruns += deltas[4];
	st->out_skipped += deltas[5];
	st->pump_failures += deltas[6];
	ecmxf_status_publish(r);
}

/* The working counter arrived; lock held. */
static void ecmxf_pump_wkc_done(struct ecmxf_rings *r,
				const struct ecmxf_xfer *x)
{
	const u8 *v = r->rx_buf;

	if (x->rsp.err_status & ECMXF_ERR_CMD || x->rx_len < 4)
		return;
	r->cur.wkc = v[0] | v[1] << 8 | v[2] << 16 | (u32)v[3] << 24;
	r->cur.wkc_reads++;
	ecmxf_status_publish(r);
}

/* Store @n TxPDO frames into the input ring; return how many fit. */
static u32 ecmxf_in_store(struct ecmxf_rings *r, const u8 *src, u32 n)
{
	struct ecmxf_ring *in = &r->in;
	u32 tail = READ_ONCE(*in->tail);
	/* pairs with the consumer's store-release: its slots are free */
	u32 head = smp_load_acquire(in->head);
	u32 i, room;

	room = tail - head >= in->entries ? 0 : in->entries - (tail - head);
	n = min(n, room);
	for (i = 0; i < n; i++)
		memcpy(in->frames + ((tail + i) & (in->entries - 1)) * in->stride,
		       src + i * in->frame_size, in->frame_size);
	/* the frames before the index: pairs with the consumer's acquire */
	smp_store_release(in->tail, tail + n);
	return n;
}

/* The FIFO command answered: move the frames, count; lock held. */
static void ecmxf_pump_fifo_done(struct ecmxf_dev *edev,
				 struct ecmxf_rings *r,
				 const struct ecmxf_xfer *x, u32 pushed)
{
	const struct ecmxf_rsp_hdr *h = &x->rsp;
	u32 deltas[7] = { 1, 0, 0, 0, 0, edev->pump.skipped, 0 };
	u32 n = 0, stored, queued;
	__poll_t wake = 0;
	int avail;

	if (h->err_status & ECMXF_ERR_CMD) {
		/* nothing was taken: the frames stay in the ring */
		ecmxf_status_update(r, h, -EREMOTEIO, deltas);
		return;
	}
	if (pushed) {
		/* the slots are read: pairs with the producer's acquire */
		smp_store_release(r->out.head, READ_ONCE(*r->out.head) + pushed);
		r->pushed_any = true;
		if (!(h->ret & 0x01)) {
			/* the RxFIFO was full: some of them were refused */
			WRITE_ONCE(*r->out.dropped, READ_ONCE(*r->out.dropped) + pushed);
			edev->rx_fifo_overruns++;
			deltas[1]++;
		}
		wake |= EPOLLOUT | EPOLLWRNORM;
	}
	r->unconfirmed = pushed;
	if (x->hdr.data[0] & 0x02 && r->in.frame_size) {
		if (x->rx_len % r->in.frame_size) {
			ecmxf_status_update(r, h, -EPROTO, deltas);
			return;
		}
		n = x->rx_len / r->in.frame_size;
		stored = ecmxf_in_store(r, r->rx_buf, n);
		if (stored < n) {
			WRITE_ONCE(*r->in.dropped,
				   READ_ONCE(*r->in.dropped) + n - stored);
			edev->in_ring_overruns += n - stored;
		}
		if (n)
			wake |= EPOLLRDBAND;
		/* what was queued: popped plus left; a full FIFO dropped */
		queued = n + h->tx_fifo_cnt;
		if (r->tx_depth && queued >= r->tx_depth) {
			edev->tx_fifo_overruns++;
			deltas[2]++;
		}
	}
	avail = ecmxf_out_avail(r);
	if (r->pushed_any && r->out.frame_size && !h->rx_fifo_cnt &&
	    (h->ecm_status & ECMXF_STS_FIFO_EN)) {
		edev->rx_fifo_underruns++;
		deltas[3]++;
		if (!avail) {
			edev->out_ring_underruns++;
			deltas[4]++;
		}
	}
	ecmxf_status_update(r, h, 0, deltas);
	/* more queued either way: again at once (if this one moved any) */
	if ((pushed || n) && (h->tx_fifo_cnt || avail > 0))
		r->again = true;
	if (wake)
		ecmxf_rings_wake(edev, wake);
}

/*
 * The command failed after it may have reached the chip (no answer, bad
 * packets): its output frames are dropped and counted, never sent again,
 * because a second copy would reach the bus after newer frames; the input
 * frames its answer carried are lost.  Counted as a pump failure, not as
 * a refusal (the chip may well have taken the frames); lock held.
 */
static void ecmxf_pump_failed(struct ecmxf_dev *edev, struct ecmxf_rings *r,
			      const struct ecmxf_xfer *x, u32 pushed)
{
	u32 deltas[7] = { 0, 0, 0, 0, 0, edev->pump.skipped, 1 };

	edev->pump_failures++;
	if (pushed) {
		/* the slots are read: pairs with the producer's acquire */
		smp_store_release(r->out.head, READ_ONCE(*r->out.head) + pushed);
		WRITE_ONCE(*r->out.dropped, READ_ONCE(*r->out.dropped) + pushed);
		ecmxf_rings_wake(edev, EPOLLOUT | EPOLLWRNORM);
	}
	r->unconfirmed = pushed;
	ecmxf_status_update(r, &x->rsp, x->status, deltas);
}

/**
 * ecmxf_pump_collect() - the pump's command left the engine: finish it
 * @edev: the device, lock held (called by ecmxf_collect())
 *
 * Return: the command's reference to the rings once it is finished, else
 * NULL.  The caller drops it with ecmxf_rings_put() after unlocking.
 */
struct ecmxf_rings *ecmxf_pump_collect(struct ecmxf_dev *edev)
{
	struct ecmxf_pump *p = &edev->pump;
	struct ecmxf_rings *r = p->rings;
	const struct ecmxf_xfer *x = &p->x;

	lockdep_assert_held(&edev->lock);
	if (!p->busy || x->status == -EINPROGRESS)
		return NULL;
	p->busy = false;
	p->rings = NULL;
	edev->out_ring_skipped += p->skipped;
	if (r == edev->rings && !r->stopped) {
		if (x->status == -ECONNRESET)
			ecmxf_rings_stop(edev, x->status);
		else if (x->status)
			ecmxf_pump_failed(edev, r, x, p->pushed);
		else if (p->wkc)
			ecmxf_pump_wkc_done(r, x);
		else
			ecmxf_pump_fifo_done(edev, r, x, p->pushed);
	}
	return r;
}

/**
 * ecmxf_pump_cancel() - the worker stops: withdraw the pump's command
 * @edev: the device, lock held
 *
 * Return: the command's reference to the rings, or NULL when none was
 * in the engine.  The caller drops it with ecmxf_rings_put() after
 * unlocking.
 */
struct ecmxf_rings *ecmxf_pump_cancel(struct ecmxf_dev *edev)
{
	struct ecmxf_pump *p = &edev->pump;
	struct ecmxf_rings *r = p->rings;

	lockdep_assert_held(&edev->lock);
	if (!p->busy)
		return NULL;
	ecmxf_engine_cancel(&edev->e, &p->x);
	p->busy = false;
	p->rings = NULL;
	return r;
}
