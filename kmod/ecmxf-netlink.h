/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * ecmxf-netlink.h - NEXTW ECM-XF: the generic netlink unit's state
 *
 * The per-device state of the events (ecmxf-netlink.c).  &struct
 * ecmxf_dev embeds it; nothing outside ecmxf-netlink.c reads it.  The
 * unit hooks itself into the link worker with ecmxf_worker_watch() and
 * sends its AL status query through the worker's queue like a file.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_NETLINK_H
#define ECMXF_NETLINK_H

#include <linux/atomic.h>
#include <linux/spinlock.h>
#include <linux/types.h>
#include <linux/workqueue.h>

#include "ecmxf-events.h"

struct ecmxf_nl_query;

/* slaves whose AL status codes one state event can carry */
#define ECMXF_NL_MAX_SLAVES	64
/* events that wait in &ecmxf_nl_dev.queue to be sent */
#define ECMXF_NL_QUEUE		32
/* event types (&enum ecmxf_nl_event values) with a rate limit each */
#define ECMXF_NL_TYPES		16
/* the counters a %ECMXF_NL_EV_PDO_LOSS event names (&enum ecmxf_nl_loss) */
#define ECMXF_NL_LOSS_KINDS	7
/* how often the worker looks at them */
#define ECMXF_NL_LOSS_PERIOD_NS	(10 * NSEC_PER_MSEC)

/**
 * struct ecmxf_nl_ev - one event on its way to the "events" group
 * @d: what the detector (or the worker) saw
 * @reset_reason: %ECMXF_NL_EV_RESET: &enum ecmxf_nl_reset_reason
 * @action: %ECMXF_NL_EV_DEVICE: &enum ecmxf_nl_device_action
 * @cmd_code: %ECMXF_NL_EV_ASYNC_ERROR: the command code
 * @status: %ECMXF_NL_EV_ASYNC_ERROR: its negative errno
 * @slaves: %ECMXF_NL_EV_STATE: the AL status query ran (for this event)
 * @incomplete: the query could not read every slave
 * @slave_count: slaves on the bus, from the query
 * @n_slaves: entries of &ecmxf_nl_dev.slaves that belong to the event
 * @total: %ECMXF_NL_EV_PDO_LOSS: the counter since probe (the kind is in
 *	@d.fifo, the increase in @d.increase)
 */
struct ecmxf_nl_ev {
	struct ecmxf_det_event d;
	u8 reset_reason;
	u8 action;
	u8 cmd_code;
	s32 status;
	bool slaves;
	bool incomplete;
	u16 slave_count;
	u16 n_slaves;
	u64 total;
};

/**
 * struct ecmxf_nl_slave - a slave not in OP, for a state event
 * @pos: position on the bus
 * @state: ECAT_STATE_GET return value
 * @have_al: @al is valid (the slave answered SLV_INFO_GET 7)
 * @al: AL status code
 */
struct ecmxf_nl_slave {
	u16 pos;
	u8 state;
	bool have_al;
	u16 al;
};

/**
 * struct ecmxf_nl_msg - one event handed to the sender, self-contained
 * @ev: the event
 * @seq: its number
 * @suppressed: events of its type not sent before it
 * @slaves: %ECMXF_NL_EV_STATE with @ev.slaves: the first @ev.n_slaves
 *	slaves of the query, copied when the event was handed over
 */
struct ecmxf_nl_msg {
	struct ecmxf_nl_ev ev;
	u32 seq;
	u32 suppressed;
	struct ecmxf_nl_slave slaves[ECMXF_NL_MAX_SLAVES];
};

/**
 * struct ecmxf_nl_out - the events on their way from the worker to the
 *	sender (a ring of %ECMXF_NL_QUEUE messages)
 * @edev: the device
 * @lock: protects @head and @count (held for index updates only; the
 *	worker fills a free slot and the sender reads a taken one outside it)
 * @head: the oldest message
 * @count: messages in the ring
 * @work: the sender (ecmxf_nl_send_work()): allocates and multicasts in
 *	process context at normal priority, never in the real-time worker
 * @msg: the ring
 */
struct ecmxf_nl_out {
	struct ecmxf_dev *edev;
	spinlock_t lock;	/* @head and @count */
	unsigned int head;
	unsigned int count;
	struct work_struct work;
	struct ecmxf_nl_msg msg[ECMXF_NL_QUEUE];
};

/**
 * struct ecmxf_nl_rate - rate limit of one event type (a token bucket)
 * @tokens: events that may be sent now
 * @last_ns: when the bucket was last refilled
 * @suppressed: events not sent since the last one sent
 */
struct ecmxf_nl_rate {
	u32 tokens;
	u64 last_ns;
	u32 suppressed;
};

/**
 * struct ecmxf_nl_dev - per-device state of the events (ecmxf-netlink.c)
 * @det: the header event detector of the protocol core
 * @active: the worker runs: headers are fed, events are sent
 * @warm_sent: a WARM_RESET went out; the next reset seen is its result
 * @seq: number of the next event (sent or suppressed)
 * @next_poll_ns: next INFO_UPDATE poll while someone listens
 * @queue: events detected, not yet sent
 * @queued: entries in @queue
 * @rate: rate limit per event type
 * @q_state: AL status query: 0 idle, else the step running
 * @q_pos: slave position the query is at
 * @q_gen: number of the query (an answer of an older one is dropped)
 * @q_ev: the state event that waits for the query
 * @query: the query's client of the worker's queue, and its request
 *	(ecmxf-netlink.c); NULL while the worker does not run
 * @slaves: slaves read by the query
 * @loss_seen: the cyclic path's counters as the last %ECMXF_NL_EV_PDO_LOSS
 *	events reported them (&enum ecmxf_nl_loss order)
 * @next_loss_ns: when the worker looks at those counters again
 * @out: the sender's ring; allocated while the worker runs, NULL before
 *	(or when there was no memory: the events are then counted as failed)
 * @events: events detected (atomic: read by the counters command)
 * @events_suppressed: events not sent because of the rate limit
 * @events_failed: events that could not be sent
 *
 * Everything but the three counters and @out's ring belongs to the worker
 * (and to probe before the worker runs); the counters are atomics, the
 * ring is shared with the sender under its lock (&struct ecmxf_nl_out).  The query's request
 * is queued and finished under &ecmxf_dev.lock, as every request.
 */
struct ecmxf_nl_dev {
	struct ecmxf_det det;
	bool active;
	bool warm_sent;
	u32 seq;
	u64 next_poll_ns;
	struct ecmxf_nl_ev queue[ECMXF_NL_QUEUE];
	unsigned int queued;
	struct ecmxf_nl_rate rate[ECMXF_NL_TYPES];
	u8 q_state;
	u16 q_pos;
	u32 q_gen;
	struct ecmxf_nl_ev q_ev;
	struct ecmxf_nl_query *query;
	struct ecmxf_nl_slave slaves[ECMXF_NL_MAX_SLAVES];
	u64 loss_seen[ECMXF_NL_LOSS_KINDS];
	u64 next_loss_ns;
	struct ecmxf_nl_out *out;
	atomic64_t events;
	atomic64_t events_suppressed;
	atomic64_t events_failed;
};

/* ecmxf-netlink.c */
int ecmxf_nl_register(void);
void ecmxf_nl_unregister(void);

#endif /* ECMXF_NETLINK_H */
