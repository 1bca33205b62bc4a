/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * ecmxf.h - NEXTW ECM-XF SPI EtherCAT master: private structures
 *
 * One &struct ecmxf_dev per chip, one &struct ecmxf_client per open file,
 * one &struct ecmxf_req per command on its way to the chip.  The files:
 *
 *   ecmxf-main.c      module init/exit, class, chrdev region, parameters
 *   ecmxf-selftest.c  load-time self-test of the protocol core
 *   ecmxf-spi.c       spi_driver: probe/remove, properties, INT0/INT1
 *   ecmxf-worker.c    the kthread that owns the SPI link and the engine
 *   ecmxf-chrdev.c    /dev/ecmxfN: open/release, ioctls, read, poll
 *   ecmxf-ring.c      the mmap()ed PDO rings (ecmxf-ring.h)
 *   ecmxf-pump.c      the PDO pump (ecmxf-ring.h, lib/core/ecmxf-pump.c)
 *   ecmxf-sysfs.c     attributes of the class device
 *   ecmxf-netlink.c   generic netlink family: events, counters
 *                     (ecmxf-netlink.h)
 *
 * The units depend one way: the file operations, sysfs and netlink on the
 * worker (netlink through &struct ecmxf_watch_ops and a queue client, as
 * a file does), the worker on the rings and the pump, all of them on the
 * protocol core (lib/core).
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_H
#define ECMXF_H

#include <linux/cdev.h>
#include <linux/completion.h>
#include <linux/device.h>
#include <linux/gpio/consumer.h>
#include <linux/kref.h>
#include <linux/list.h>
#include <linux/mutex.h>
#include <linux/pid.h>
#include <linux/sched.h>
#include <linux/spi/spi.h>
#include <linux/spinlock.h>
#include <linux/types.h>
#include <linux/wait.h>

#include <linux/ecmxf.h>	/* kmod/uapi -> include/uapi */

#include "ecmxf-proto.h"
#include "ecmxf-events.h"
#include "ecmxf-ring.h"
#include "ecmxf-netlink.h"

#define ECMXF_DRV_NAME		"ecmxf"
/* minors (and so chips) the module can serve */
#define ECMXF_MAX_DEVICES	64
/* without INT0: the time the chip needs between exchanges */
#define ECMXF_READY_WAIT_US	150
/* with INT0: how long to wait for "ready" before exchanging anyway */
#define ECMXF_READY_TIMEOUT_US	5000
/*
 * a level-triggered INT1 that its handler masked is unmasked at the latest
 * this long after the worker saw it masked (sooner once a packet with
 * interrupt clear bits reached the chip): a line the application never
 * clears then costs one header refresh per period, not an interrupt storm
 */
#define ECMXF_INT1_HOLDOFF_NS	(10 * NSEC_PER_MSEC)
/*
 * open files that only a file opened for writing may take: read-only
 * openers (any member of the device's group, and every query tool) cannot
 * fill max_open and lock the cyclic application out when it restarts
 * (at most half of max_open when it is small)
 */
#define ECMXF_WRITER_SLOTS	8
/*
 * PDO ring sets that may exist at once per device: the current one, the
 * one a new setup replaces (its mappings outlive it) and one more; a setup
 * beyond is -EBUSY until old mappings go, so a loop of setup + mmap cannot
 * pin unbounded kernel memory
 */
#define ECMXF_RINGS_MAX		3
/* how often the worker expires queued (not yet sent) commands */
#define ECMXF_EXPIRE_PERIOD_NS	(1 * NSEC_PER_MSEC)
/*
 * time allowed for each command during probe: a chip answers in
 * microseconds; a slow (emulated, heavily loaded) link may take far longer
 * to be scheduled, and a timeout must not be taken for a wrong format
 */
#define ECMXF_PROBE_TIMEOUT_US	500000
/* probe: FW_VERSION_GETs per packet format while they time out */
#define ECMXF_PROBE_TRIES	3

/**
 * enum ecmxf_req_kind - who waits for a request and how it ends
 * @ECMXF_REQ_SYNC: %ECMXF_IOC_CMD; the ioctl sleeps on &ecmxf_req.done
 * @ECMXF_REQ_SUBMIT: %ECMXF_IOC_SUBMIT; completion read() from the client
 * @ECMXF_REQ_RESET: %ECMXF_IOC_RESET; handled by the worker itself
 * @ECMXF_REQ_KERNEL: a client inside the module (the netlink unit's AL
 *	status query); &ecmxf_req.complete is called when it ends
 */
enum ecmxf_req_kind {
	ECMXF_REQ_SYNC,
	ECMXF_REQ_SUBMIT,
	ECMXF_REQ_RESET,
	ECMXF_REQ_KERNEL,
};

/**
 * enum ecmxf_req_state - where a request is
 * @ECMXF_RS_QUEUED: on its client's queue (or &ecmxf_dev.resets)
 * @ECMXF_RS_ACTIVE: taken by the worker (in the engine, or being reset)
 * @ECMXF_RS_DONE: finished; the result fields are final
 */
enum ecmxf_req_state {
	ECMXF_RS_QUEUED,
	ECMXF_RS_ACTIVE,
	ECMXF_RS_DONE,
};

/**
 * struct ecmxf_req - one command between an ioctl and the chip
 * @node: in &ecmxf_client.queue, &ecmxf_client.done or &ecmxf_dev.resets
 * @client: the file that sent it; NULL once that file is closed (the
 *	worker then frees the request when it finishes)
 * @kind: &enum ecmxf_req_kind
 * @state: &enum ecmxf_req_state
 * @abandoned: %ECMXF_REQ_SYNC only: the waiter left on a signal after the
 *	command was sent; the worker frees the request when it finishes
 * @exclusive: of a class above query (or a reset): while another file
 *	holds the claim it is refused, when queued and again when the worker
 *	takes it (ecmxf_claim_allows())
 * @refused: the worker refused it when it took it (the claim or the rings
 *	changed since it was queued); nothing was sent
 * @deadline_ns: absolute time (ktime_get_ns()) by which it must finish,
 *	counted from the ioctl
 * @cookie: %ECMXF_REQ_SUBMIT: the caller's cookie
 * @reset_flags: %ECMXF_REQ_RESET: %ECMXF_RESET_F_* value
 * @reset_param: %ECMXF_REQ_RESET: %ECMXF_RESET_ASYNC_* bits
 * @done: completed when @state becomes %ECMXF_RS_DONE (sync and reset)
 * @complete: %ECMXF_REQ_KERNEL: called by the worker when @state becomes
 *	%ECMXF_RS_DONE, with &ecmxf_dev.lock held; the request stays its
 *	owner's (it may queue it again)
 * @x: the engine's view of the command, and its result
 * @fx: with %ECMXF_CMD_F_FETCH: the result fetch (@x.fetch points here);
 *	its answer's data goes to @rx
 * @fetched: the fetch ran: the outcome is @fx's (set when it finishes)
 * @tx: data section bytes to send (%ECMXF_DATA_MAX)
 * @rx: response data (%ECMXF_DATA_MAX)
 *
 * All fields except @x, @fx, @tx and @rx are protected by &ecmxf_dev.lock;
 * @x and @fx belong to the worker while @state is %ECMXF_RS_ACTIVE.
 */
struct ecmxf_req {
	struct list_head node;
	struct ecmxf_client *client;
	enum ecmxf_req_kind kind;
	enum ecmxf_req_state state;
	bool abandoned;
	bool exclusive;
	bool refused;
	u64 deadline_ns;
	u64 cookie;
	u32 reset_flags;
	u32 reset_param;
	struct completion done;
	void (*complete)(struct ecmxf_dev *edev, struct ecmxf_req *req);
	struct ecmxf_xfer x;
	struct ecmxf_xfer fx;
	bool fetched;
	u8 tx[ECMXF_DATA_MAX];
	u8 rx[ECMXF_DATA_MAX];
};

/**
 * struct ecmxf_snap - what the worker publishes for lock-free readers
 * @k: the counters (int0_irqs and int1_irqs stay 0: they are atomics the
 *	readers add themselves)
 * @ring_skipped: &ecmxf_dev.cnt.out_ring_skipped
 * @ring_failures: &ecmxf_dev.cnt.pump_failures
 * @data_size: &ecmxf_dev.chip.data_size
 * @check: &ecmxf_dev.chip.check
 * @cover: &ecmxf_dev.chip.cover
 * @fw_valid: &ecmxf_dev.chip.fw_valid
 * @fw_version: &ecmxf_dev.chip.fw_version
 * @fw_info: &ecmxf_dev.chip.fw_info
 */
struct ecmxf_snap {
	struct ecmxf_counters k;
	u64 ring_skipped;
	u64 ring_failures;
	u16 data_size;
	u8 check;
	u8 cover;
	bool fw_valid;
	u8 fw_version;
	u8 fw_info[20];
};

/**
 * struct ecmxf_client - one open file of /dev/ecmxfN, or a client inside
 *	the module (the netlink unit's AL status query)
 * @edev: the device
 * @node: in &ecmxf_dev.clients, whose order is the round-robin order
 * @queue: requests not yet taken by the worker, in submission order
 * @done: finished %ECMXF_REQ_SUBMIT requests, in completion order
 * @in_flight: %ECMXF_REQ_SUBMIT requests queued, running or unread
 * @wq: read() and poll() wait here for @done
 * @writable: opened with FMODE_WRITE
 * @rings_lost: the rings this file had were torn down (RELEASE, or
 *	%ECMXF_IOC_CLAIM_BREAK by another file) and it has set up none
 *	since: a poll() for ring events gets EPOLLERR
 *
 * @queue, @done, @in_flight and the position in &ecmxf_dev.clients are
 * protected by &ecmxf_dev.lock.
 */
struct ecmxf_client {
	struct ecmxf_dev *edev;
	struct list_head node;
	struct list_head queue;
	struct list_head done;
	unsigned int in_flight;
	wait_queue_head_t wq;
	bool writable;
	bool rings_lost;
};

/**
 * struct ecmxf_dev_irq - INT0 and INT1: the lines, their IRQs, what the
 *	handlers tell the worker
 * @int0: the GPIO whose level says "ready" (logical 1 = ready):
 *	"ready-gpios" (or the deprecated "int0-gpios"), or NULL (no level to
 *	read)
 * @int1: the INT1 GPIO of the deprecated "int1-gpios" form (events,
 *	logical 1 = asserted), or NULL
 * @int0_irq: Linux IRQ of INT0 (interrupt or GPIO form), 0 when absent
 * @int1_irq: Linux IRQ of INT1, 0 when absent
 * @int0_level: @int0_irq is level-triggered: its handler masks it, the
 *	worker unmasks it when it waits for "ready"
 * @int1_level: @int1_irq is level-triggered: its handler masks it, the
 *	worker unmasks it after an interrupt clear or a hold-off
 * @int0_masked: the INT0 handler masked @int0_irq (level only)
 * @int1_masked: the INT1 handler masked @int1_irq (level only)
 * @int0_flag: set by the INT0 handler: "ready" since the last exchange
 *	began; cleared by the worker before each exchange
 * @int1_flag: set by the INT1 handler, consumed by the worker
 * @int0_irqs: INT0 interrupts handled (written by the handler, atomic
 *	read and write are enough)
 * @int1_irqs: INT1 interrupts handled (as @int0_irqs)
 * @irqs_off: ecmxf_free_irqs() began: no IRQ is enabled again (under
 *	&ecmxf_dev.lock)
 *
 * Set at probe but for the atomics, which the handlers and the worker
 * share, and @irqs_off.
 */
struct ecmxf_dev_irq {
	struct gpio_desc *int0;
	struct gpio_desc *int1;
	int int0_irq;
	int int1_irq;
	bool int0_level;
	bool int1_level;
	atomic_t int0_masked;
	atomic_t int1_masked;
	atomic_t int0_flag;
	atomic_t int1_flag;
	atomic64_t int0_irqs;
	atomic64_t int1_irqs;
	bool irqs_off;
};

/**
 * struct ecmxf_dev_link - the link worker and what it alone touches
 * @worker: the kthread that owns the link (a reference is held)
 * @owner: the task that waits for INT0 and new work: probe during
 *	bring-up, then @worker; read by the IRQ handlers with READ_ONCE(),
 *	cleared under &ecmxf_dev.lock before @worker is released
 * @kick: set when the worker has new work; consumed by the worker
 * @e: the protocol engine; only the worker (or probe, before the worker
 *	starts) touches it
 * @txbuf: DMA-safe packet buffer, host to chip
 * @rxbuf: DMA-safe packet buffer, chip to host
 * @xfer_end_ns: when the last exchange ended (ktime_get_ns()), 0 before
 *	the first; the wait for "ready" before the next one counts from it
 * @wkc_last: last WKC error count seen
 * @wkc_valid: @wkc_last holds a value
 * @next_expire_ns: next scan for expired queued requests
 * @int1_cleared: the last packet sent carried interrupt clear bits (level
 *	INT1)
 * @int1_rearm_ns: when a masked level INT1 is unmasked at the latest, 0
 *	when not set
 * @want_size: data section size to set at probe; 0 keeps the chip's
 * @want_check: check type to set at probe
 *
 * Worker only (probe before the worker exists), but @owner and @kick.
 */
struct ecmxf_dev_link {
	struct task_struct *worker;
	struct task_struct *owner;
	atomic_t kick;
	struct ecmxf_engine e;
	u8 *txbuf;
	u8 *rxbuf;
	u64 xfer_end_ns;
	u8 wkc_last;
	bool wkc_valid;
	u64 next_expire_ns;
	bool int1_cleared;
	u64 int1_rearm_ns;
	u32 want_size;
	u32 want_check;
};

/**
 * struct ecmxf_dev_claim - who holds the cyclic claim
 * @holder: the file holding it, or NULL (under &ecmxf_dev.lock)
 * @pid: the thread group that took it (written under &ecmxf_dev.lock and
 *	@pid_lock, read under either)
 * @pid_lock: a reader of @pid that must not take &ecmxf_dev.lock (sysfs:
 *	any local user) takes this spinlock instead; the worker never does
 */
struct ecmxf_dev_claim {
	struct ecmxf_client *holder;
	struct pid *pid;
	spinlock_t pid_lock;	/* @pid for readers (above) */
};

/**
 * struct ecmxf_dev_chip - what is known of the chip (under &ecmxf_dev.lock)
 * @data_size: data section size in force (snapshot of the engine's)
 * @check: check type in force (snapshot of the engine's)
 * @cover: &enum ecmxf_cover, the chip's CRC coverage found (snapshot of
 *	the engine's)
 * @fw_valid: @fw_version and @fw_info were read
 * @fw_version: FW_VERSION_GET return value
 * @fw_info: FW_VERSION_GET data bytes
 * @slave_count: return value of the last ECAT_SLV_CNT_GET that succeeded
 *	without a command error; 0 until then and after a warm reset
 * @last: last valid response header
 */
struct ecmxf_dev_chip {
	u16 data_size;
	u8 check;
	u8 cover;
	bool fw_valid;
	u8 fw_version;
	u8 fw_info[20];
	u8 slave_count;
	struct ecmxf_rsp_hdr last;
};

/**
 * struct ecmxf_dev_counters - the counters, and their published copy
 * @stats: counters since probe: @stats_base plus the engine's
 * @stats_base: counts of earlier engine lives (before a re-initialisation)
 * @wkc_errors: increments of the chip's WKC error count
 * @queue_timeouts: requests that timed out before they were sent
 * @out_ring_underruns: &struct ecmxf_counters.out_ring_underruns
 * @in_ring_overruns: &struct ecmxf_counters.in_ring_overruns
 * @rx_fifo_underruns: &struct ecmxf_counters.rx_fifo_underruns
 * @rx_fifo_overruns: &struct ecmxf_counters.rx_fifo_overruns
 * @tx_fifo_overruns: &struct ecmxf_counters.tx_fifo_overruns
 * @out_ring_skipped: output frames the pump skipped (sysfs ring_skipped)
 * @pump_failures: pump commands that failed (sysfs ring_failures)
 * @snap_seq: the count of @snap (ecmxf-latch.h), read without the lock
 * @snap_kseq: the writer's own count
 * @snap: the counters, the link format and the firmware in two copies,
 *	published under &ecmxf_dev.lock after every exchange
 *	(ecmxf_publish()) and read by sysfs, netlink and
 *	%ECMXF_IOC_COUNTERS without any lock: no reader can delay the
 *	real-time worker
 *
 * All but @snap_seq and @snap are under &ecmxf_dev.lock; the worker is
 * their only writer.
 */
struct ecmxf_dev_counters {
	struct ecmxf_engine_stats stats;
	struct ecmxf_engine_stats stats_base;
	u64 wkc_errors;
	u64 queue_timeouts;
	u64 out_ring_underruns;
	u64 in_ring_overruns;
	u64 rx_fifo_underruns;
	u64 rx_fifo_overruns;
	u64 tx_fifo_overruns;
	u64 out_ring_skipped;
	u64 pump_failures;
	u32 snap_seq;
	u32 snap_kseq;
	struct ecmxf_snap snap[2];
};

/**
 * struct ecmxf_dev_pdo - the PDO rings and their pump
 * @rings: the rings of the claim holder, or NULL (a reference held;
 *	under &ecmxf_dev.lock)
 * @alive: ring sets whose memory exists (current, replaced or released
 *	but still mapped); at most %ECMXF_RINGS_MAX
 * @pump: the pump's commands (worker only)
 */
struct ecmxf_dev_pdo {
	struct ecmxf_rings *rings;
	atomic_t alive;
	struct ecmxf_pump_slot pump;
};

/**
 * struct ecmxf_variant - what the compatible (or the SPI id) says
 * @name: the master's series, for messages and sysfs ("ECM-XF", ...)
 * @fixed_size: a data section size the chip cannot change (the ECM-XFU's
 *	992 bytes), 0 when SPI_RECONFIG_OP sets it
 */
struct ecmxf_variant {
	const char *name;
	u16 fixed_size;
};

/**
 * struct ecmxf_dev_cfg - the chip's settings, fixed at probe
 * @variant: the master's series
 * @pump_timeout_ms: time allowed for each PDO pump command (the module
 *	parameter's value at probe)
 * @event_poll_ms: the events' poll period, 0 never (likewise)
 *
 * The packet format wanted (&ecmxf_dev_link.want_size, .want_check) is
 * set beside these, from the device's properties or the module
 * parameters (ecmxf_read_config()).
 */
struct ecmxf_dev_cfg {
	const struct ecmxf_variant *variant;
	u32 pump_timeout_ms;
	u32 event_poll_ms;
};

/**
 * struct ecmxf_dev - one ECM-XF chip
 * @spi: the SPI device; NULL after remove
 * @dev: the class device behind /dev/ecmxfN; its refcount keeps this
 *	structure alive while files are open (cdev_device_add() makes the
 *	cdev hold it)
 * @cdev: the character device
 * @id: N of /dev/ecmxfN
 * @cfg: the settings fixed at probe (&struct ecmxf_dev_cfg)
 * @irq: INT0 and INT1 (&struct ecmxf_dev_irq)
 * @link: the worker's own state (&struct ecmxf_dev_link)
 * @lock: protects the fields below it and those the sub-structures say.
 *	The SCHED_FIFO worker takes it around every exchange, so it is held
 *	for field and list updates only: never across spi_sync(), a wait or
 *	a user copy, and nothing whose cost grows with the PDO rings runs
 *	under it.  Ring memory in particular is never freed under it
 *	(PREEMPT_RT: the worker would wait for vfree() of every page): a
 *	reference to &struct ecmxf_rings is detached under the lock and
 *	dropped with ecmxf_rings_put() after unlocking
 *	(ecmxf_rings_teardown(), ecmxf_pump_collect() and
 *	ecmxf_pump_cancel() hand theirs back to the caller for that), and
 *	mmap() inserts the pages without it.  No reader that any local user
 *	can run (sysfs, netlink GET_COUNTERS) takes it.
 * @gone: the chip was removed; every file operation returns -ENODEV
 * @cur_req: the request in the engine's command slot (written by the
 *	worker under @lock, read by it without)
 * @async_req: the async request the chip runs, or whose result fetch is
 *	still in the engine after it ended (as @cur_req); while it is set no
 *	other async request is taken
 * @clients: open files, in round-robin order
 * @resets: %ECMXF_REQ_RESET requests waiting for the worker
 * @open_count: files open
 * @open_readonly: of those, files opened without FMODE_WRITE
 * @claim: the cyclic claim (&struct ecmxf_dev_claim)
 * @chip: what is known of the chip (&struct ecmxf_dev_chip)
 * @cnt: the counters and their published snapshot
 *	(&struct ecmxf_dev_counters)
 * @pdo: the PDO rings and the pump (&struct ecmxf_dev_pdo)
 * @nl: generic netlink events (ecmxf-netlink.c; worker only, see
 *	&struct ecmxf_nl_dev)
 *
 * Grouped by concern, as mcp251xfd groups its rings: the lines, the
 * worker's own state, then what the lock protects.
 */
struct ecmxf_dev {
	struct spi_device *spi;
	struct device dev;
	struct cdev cdev;
	int id;
	struct ecmxf_dev_cfg cfg;

	struct ecmxf_dev_irq irq;
	struct ecmxf_dev_link link;

	/* protects the fields below; no ring memory freed under it (above) */
	struct mutex lock;
	bool gone;
	struct ecmxf_req *cur_req;
	struct ecmxf_req *async_req;
	struct list_head clients;
	struct list_head resets;
	unsigned int open_count;
	unsigned int open_readonly;
	struct ecmxf_dev_claim claim;
	struct ecmxf_dev_chip chip;
	struct ecmxf_dev_counters cnt;
	struct ecmxf_dev_pdo pdo;

	struct ecmxf_nl_dev nl;
};

/* module parameters (ecmxf-main.c) */
extern unsigned int ecmxf_param_data_size;
extern unsigned int ecmxf_param_check_type;
extern unsigned int ecmxf_param_max_open;
extern unsigned int ecmxf_param_queue_depth;
extern unsigned int ecmxf_param_pump_timeout_ms;
extern unsigned int ecmxf_param_event_poll_ms;

/* ecmxf-main.c */
extern struct class ecmxf_class;
extern dev_t ecmxf_devt;
int ecmxf_id_alloc(void);
void ecmxf_id_free(int id);

/* ecmxf-selftest.c */
int ecmxf_selftest(void);

/* ecmxf-spi.c */
int ecmxf_spi_register(void);
void ecmxf_spi_unregister(void);
void ecmxf_irq_unmask(struct ecmxf_dev *edev, int irq, atomic_t *masked);

/**
 * struct ecmxf_watch_ops - what the link worker reports to its watcher
 * @start: the worker starts (the link is up); called by the worker
 * @stop: the worker ends; nothing is in the engine any more
 * @flush: the worker holds no lock: a moment to send what was found
 * @header: a valid response header arrived (at @now_ns); the engine's
 *	last header is it
 * @req_sent: a file's command goes to the engine
 * @req_done: a file's command finished (&ecmxf_dev.lock held)
 * @link_reset: the worker resynchronised the link (%ECMXF_RESET_F_LINK)
 * @poll_due: the worker is idle: should it refresh the header now?
 * @wake_at: the worker is idle: when it must look again (U64_MAX: only
 *	when kicked)
 *
 * The netlink unit (ecmxf-netlink.c) registers these (every one set) with
 * ecmxf_worker_watch(), so that the worker
 * calls no netlink function by name: netlink depends on the worker, not
 * the other way round.  Every callback runs in the worker thread.
 */
struct ecmxf_watch_ops {
	void (*start)(struct ecmxf_dev *edev);
	void (*stop)(struct ecmxf_dev *edev);
	void (*flush)(struct ecmxf_dev *edev);
	void (*header)(struct ecmxf_dev *edev, u64 now_ns);
	void (*req_sent)(struct ecmxf_dev *edev, const struct ecmxf_xfer *x);
	void (*req_done)(struct ecmxf_dev *edev, const struct ecmxf_xfer *x);
	void (*link_reset)(struct ecmxf_dev *edev);
	bool (*poll_due)(struct ecmxf_dev *edev, u64 now_ns);
	u64 (*wake_at)(struct ecmxf_dev *edev, u64 now_ns);
};

/* ecmxf-worker.c */
int ecmxf_link_bringup(struct ecmxf_dev *edev);
int ecmxf_worker_start(struct ecmxf_dev *edev);
void ecmxf_worker_stop(struct ecmxf_dev *edev);
void ecmxf_worker_kick(struct ecmxf_dev *edev);
void ecmxf_worker_watch(const struct ecmxf_watch_ops *ops);
void ecmxf_wake_owner(struct ecmxf_dev *edev);
void ecmxf_req_finish(struct ecmxf_dev *edev, struct ecmxf_req *req,
		      int status);
void ecmxf_get_counters(struct ecmxf_dev *edev, struct ecmxf_counters *k);
void ecmxf_get_snap(struct ecmxf_dev *edev, struct ecmxf_snap *snap);
pid_t ecmxf_claim_pid_vnr(struct ecmxf_dev *edev);
const char *ecmxf_check_name(unsigned int check);
bool ecmxf_claim_allows(struct ecmxf_dev *edev, const struct ecmxf_client *c,
			bool exclusive);
bool ecmxf_req_refused(struct ecmxf_dev *edev, const struct ecmxf_req *req);

/* ecmxf-chrdev.c */
extern const struct file_operations ecmxf_fops;
void ecmxf_chrdev_fail_all(struct ecmxf_dev *edev, int status);

/* ecmxf-sysfs.c */
extern const struct attribute_group *ecmxf_groups[];

#endif /* ECMXF_H */
