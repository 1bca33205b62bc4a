/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * ecmxf-ring.h - NEXTW ECM-XF: the PDO rings and the PDO pump
 *
 * The rings' memory (ecmxf-ring.c) and the pump that moves their frames
 * to and from the chip's FIFOs (ecmxf-pump.c, with the protocol core's
 * lib/core/ecmxf-pump.c).  &struct ecmxf_dev embeds the pump's command
 * slot; the functions take the device.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_RING_H
#define ECMXF_RING_H

#include <linux/kref.h>
#include <linux/poll.h>
#include <linux/types.h>

#include <linux/ecmxf.h>	/* kmod/uapi -> include/uapi */

#include "ecmxf-proto.h"
#include "ecmxf-pump.h"

struct ecmxf_dev;
struct vm_area_struct;

/**
 * struct ecmxf_ring - one mmap()ed ring (kernel view)
 * @mem: vmalloc_user() memory, @size bytes, mapped by userspace
 * @size: the mapping length (&struct ecmxf_ring_offsets.mmap_size)
 * @off: the layout as reported to userspace
 * @head: consumer index in @mem
 * @tail: producer index in @mem
 * @flags: %ECMXF_RING_S_* word in @mem
 * @dropped: dropped-frames count in @mem
 * @frames: slot 0 in @mem
 * @entries: slots (a power of two)
 * @frame_size: process data bytes per slot
 * @stride: bytes from slot to slot
 * @kidx: the index the kernel moves (the output ring's head, the input
 *	ring's tail), kernel-private
 * @kdropped: the dropped-frames count, kernel-private
 *
 * The indices live in shared memory: the kernel reads the one userspace
 * writes with smp_load_acquire() and never trusts it further than
 * "at most @entries frames apart".  What the kernel writes there (its
 * index, the dropped count) it only writes: it goes by @kidx and
 * @kdropped, so that a process that scribbles on the mapping changes no
 * kernel count (as io_uring and AF_XDP keep kernel-private shadows).
 */
struct ecmxf_ring {
	void *mem;
	size_t size;
	struct ecmxf_ring_offsets off;
	u32 *head;
	u32 *tail;
	u32 *flags;
	u32 *dropped;
	u8 *frames;
	u32 entries;
	u32 frame_size;
	u32 stride;
	u32 kidx;
	u32 kdropped;
};

/**
 * struct ecmxf_rings - the two PDO rings of the claim holder
 * @ref: held by &ecmxf_dev.pdo.rings, by every mapping and by the worker
 *	while a pump command uses them; the memory is freed with the last,
 *	never under &ecmxf_dev.lock (see there)
 * @edev: the device (it outlives the rings: every holder keeps the file,
 *	and so the device, alive)
 * @out: output ring (RxPDO frames, application to chip)
 * @in: input ring (TxPDO frames, chip to application)
 * @status: the status block (&struct ecmxf_ring_status_block) in the
 *	input ring's memory, written only through ecmxf_rings_publish()
 * @cur: the status the kernel keeps; published into @status
 * @status_seq: the latch count last written to @status
 * @setup_flags: %ECMXF_RING_F_* of the setup
 * @pump: the protocol core's pump: frame sizes, fill level, TxFIFO depth
 *	and its bookkeeping of the frames pushed (worker only after setup)
 * @sched: the protocol core's pump schedule: the timer period, the
 *	working counter read period, the next ticks and whether the last
 *	answer left work (worker only after setup)
 * @tx_buf: data sections of the pump's two FIFO commands
 *	(&ecmxf_pump_slot.cmd 0 and 1; %ECMXF_DATA_MAX each)
 * @rx_buf: data sections of their answers (%ECMXF_DATA_MAX each)
 * @wkc_buf: data section of the working counter read's answer
 *	(%ECMXF_DATA_MAX: the two commands are in flight together)
 * @stopped: the pump stopped for good (%ECMXF_RING_S_ERROR); under
 *	&ecmxf_dev.lock
 */
struct ecmxf_rings {
	struct kref ref;
	struct ecmxf_dev *edev;
	struct ecmxf_ring out;
	struct ecmxf_ring in;
	struct ecmxf_ring_status_block *status;
	struct ecmxf_ring_status cur;
	u32 status_seq;
	u32 setup_flags;
	struct ecmxf_pump pump;
	struct ecmxf_pump_sched sched;
	u8 *tx_buf[2];
	u8 *rx_buf[2];
	u8 *wkc_buf;
	bool stopped;
};

/**
 * struct ecmxf_pump_cmd - one of the PDO pump's commands in the engine
 * @x: the command
 * @rings: the rings it serves, a reference held while it is in flight
 *	(&ecmxf_pump_flight.busy)
 */
struct ecmxf_pump_cmd {
	struct ecmxf_xfer x;
	struct ecmxf_rings *rings;
};

/* the pump's commands: two FIFO commands and the working counter read */
#define ECMXF_PUMP_CMDS	ECMXF_PUMP_SLOTS

/**
 * struct ecmxf_pump_slot - the PDO pump's commands (worker only)
 * @cmd: ECAT_PDO_DATA_FIFO_OP in 0 and 1 (one in flight, or two with
 *	%ECMXF_RING_F_FIFO_NEXT: the next one rides in the exchange that
 *	fetches the answer of the one before), ECAT_PDO_WC_GET in
 *	%ECMXF_PUMP_SLOT_WKC (in flight beside a FIFO command, so that it
 *	rides in the exchange that fetches its answer)
 * @flight: the protocol core's record of them: in flight, their plans,
 *	the newest FIFO command; written under &ecmxf_dev.lock when a
 *	command goes into or leaves the engine
 * @pick: what ecmxf_pump_take() chose for ecmxf_pump_submit()
 *	(%ECMXF_PUMP_PICK_FIFO or %ECMXF_PUMP_PICK_WKC)
 * @turn: the pump goes before the files' commands when both are due
 */
struct ecmxf_pump_slot {
	struct ecmxf_pump_cmd cmd[ECMXF_PUMP_CMDS];
	struct ecmxf_pump_flight flight;
	int pick;
	bool turn;
};

/* ecmxf-ring.c: the ring memory */
int ecmxf_rings_create(struct ecmxf_dev *edev, struct ecmxf_ring_setup *rs,
		       const u16 sizes[2], const u8 depths[2],
		       struct ecmxf_rings **out);
void ecmxf_rings_put(struct ecmxf_rings *r);
bool ecmxf_ring_setup_valid(const struct ecmxf_ring_setup *rs);
int ecmxf_rings_mmap(struct ecmxf_rings *r, struct vm_area_struct *vma);
struct ecmxf_rings *ecmxf_rings_teardown(struct ecmxf_dev *edev);
void ecmxf_rings_stop(struct ecmxf_dev *edev, int err);
__poll_t ecmxf_rings_poll(struct ecmxf_dev *edev);
void ecmxf_rings_wake(struct ecmxf_dev *edev, __poll_t mask);
void ecmxf_rings_publish(struct ecmxf_rings *r);
int ecmxf_ring_out_avail(struct ecmxf_rings *r);
void ecmxf_ring_out_copy(struct ecmxf_rings *r, u8 *dst, u32 n);
void ecmxf_ring_out_release(struct ecmxf_rings *r, u32 n, u32 dropped);
u32 ecmxf_ring_in_store(struct ecmxf_rings *r, const u8 *src, u32 n);

/* ecmxf-pump.c: the PDO pump */
struct ecmxf_rings *ecmxf_pump_take(struct ecmxf_dev *edev, u64 now);
int ecmxf_pump_submit(struct ecmxf_dev *edev, struct ecmxf_rings *r,
		      u64 now);
void ecmxf_pump_collect(struct ecmxf_dev *edev,
			struct ecmxf_rings *put[ECMXF_PUMP_CMDS]);
void ecmxf_pump_cancel(struct ecmxf_dev *edev,
		       struct ecmxf_rings *put[ECMXF_PUMP_CMDS]);
bool ecmxf_pump_busy(const struct ecmxf_dev *edev);
bool ecmxf_pump_answer_waits(struct ecmxf_dev *edev);
u64 ecmxf_pump_deadline(struct ecmxf_dev *edev);

#endif /* ECMXF_RING_H */
