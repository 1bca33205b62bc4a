// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-netlink.c - NEXTW ECM-XF: the generic netlink family "ecmxf"
 *
 * Events: the link worker feeds every valid response header it sees to
 * the protocol core's event detector (lib/core/ecmxf-events.c, the rules
 * `ecmxf-util monitor` applies to the headers it polls on other
 * transports) and adds what it does itself: async commands that failed,
 * WARM_RESET and link resets, the device coming and going.  The events
 * wait in a small per-device queue; when the worker holds no lock
 * (ecmxf_nl_flush()) it applies the rate limit, numbers them and copies
 * them into the sender's ring (&struct ecmxf_nl_out), and a work item on
 * the unbound workqueue builds the messages and multicasts them on the
 * "events" group (ecmxf_nl_send_work()).  The real-time worker neither
 * allocates an skb nor enters the netlink core: a slow listener, memory
 * reclaim or a socket lock delays the events, never the bus.
 *
 * A state change down or into ERROR first runs an "AL status query":
 * ECAT_SLV_CNT_GET, then for every slave ECAT_STATE_GET and, for the
 * slaves not in OP that answer, ECAT_SLV_INFO_GET code 7 (the AL status
 * code, manual ver. 050).  The query is a client of the worker's queue
 * like an open file: it queues one immediate command at a time (a
 * %ECMXF_REQ_KERNEL request) and takes the next step when the worker
 * finishes it, taking turns with the files' commands, so the event is
 * late by a few exchanges.
 *
 * The unit hooks into the worker with ecmxf_worker_watch() (&struct
 * ecmxf_watch_ops): the worker calls no function of this file by name.
 *
 * While someone listens and the link is otherwise quiet, the worker polls
 * the chip with INFO_UPDATE every event_poll_ms so that changes are seen
 * without user traffic (INT1 wakes it sooner when the chip raises it).
 *
 * Each event type has a token bucket (a burst of 16, then 10 per second);
 * events over it are counted, not sent: the next event of that type
 * carries the count (ECMXF_NL_A_SUPPRESSED) and the counters dump has the
 * total.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/device.h>
#include <linux/ktime.h>
#include <linux/math64.h>
#include <linux/mm.h>
#include <linux/module.h>
#include <linux/moduleparam.h>
#include <linux/slab.h>
#include <net/genetlink.h>

#include <linux/ecmxf_netlink.h>	/* kmod/uapi -> include/uapi */

#include "ecmxf.h"

/* rate limit per event type: a burst of this many, then one per period */
#define ECMXF_NL_RATE_BURST	16
#define ECMXF_NL_RATE_PERIOD_NS	(100 * NSEC_PER_MSEC)
/* attributes of an event without slaves: under 200 bytes */
#define ECMXF_NL_EVENT_SIZE	256
/*
 * time allowed for each command of the AL status query: not the table's
 * 100 ms, which a loaded (or emulated) host exceeded for one exchange
 * pair, losing the slaves of the event; the answer is what it is for
 */
#define ECMXF_NL_QUERY_TIMEOUT_US	(1000 * USEC_PER_MSEC)

/* steps of the AL status query (&ecmxf_nl_dev.q_state) */
enum {
	ECMXF_NLQ_IDLE,
	ECMXF_NLQ_COUNT,
	ECMXF_NLQ_STATE,
	ECMXF_NLQ_AL,
};

static const struct nla_policy ecmxf_nl_policy[ECMXF_NL_A_MAX + 1] = {
	[ECMXF_NL_A_DEV_MINOR] = { .type = NLA_U32 },
};

static int ecmxf_nl_get_counters(struct sk_buff *skb, struct genl_info *info);
static int ecmxf_nl_dump_counters(struct sk_buff *skb,
				  struct netlink_callback *cb);

static const struct genl_small_ops ecmxf_nl_ops[] = {
	{
		.cmd = ECMXF_NL_CMD_GET_COUNTERS,
		.doit = ecmxf_nl_get_counters,
		.dumpit = ecmxf_nl_dump_counters,
	},
};

/*
 * Joining the events group needs CAP_NET_ADMIN: a listener makes the
 * worker poll an idle chip and run AL status queries (bus traffic), which
 * no unprivileged socket may cause.  GET_COUNTERS only reads, so it needs
 * nothing (GENL_ADMIN_PERM would be for ops that change state; there are
 * none).  Kernels whose genetlink predates the flag (before 6.1.64 and
 * 6.7) let anyone join.
 */
static const struct genl_multicast_group ecmxf_nl_mcgrps[] = {
	{
		.name = ECMXF_GENL_MCGRP_EVENTS,
#ifdef GENL_MCAST_CAP_NET_ADMIN
		.flags = GENL_MCAST_CAP_NET_ADMIN,
#endif
	},
};

static struct genl_family ecmxf_nl_family __ro_after_init = {
	.name = ECMXF_GENL_NAME,
	.version = ECMXF_GENL_VERSION,
	.maxattr = ECMXF_NL_A_MAX,
	.policy = ecmxf_nl_policy,
	.module = THIS_MODULE,
	.small_ops = ecmxf_nl_ops,
	.n_small_ops = ARRAY_SIZE(ecmxf_nl_ops),
	.mcgrps = ecmxf_nl_mcgrps,
	.n_mcgrps = ARRAY_SIZE(ecmxf_nl_mcgrps),
};

/* the detector's event types are the uAPI's */
#define ECMXF_NL_SAME(a, b)	static_assert((int)(a) == (int)(b))
ECMXF_NL_SAME(ECMXF_DET_RESET, ECMXF_NL_EV_RESET);
ECMXF_NL_SAME(ECMXF_DET_LINK, ECMXF_NL_EV_LINK);
ECMXF_NL_SAME(ECMXF_DET_STATE, ECMXF_NL_EV_STATE);
ECMXF_NL_SAME(ECMXF_DET_ERROR_STATUS, ECMXF_NL_EV_ERROR_STATUS);
ECMXF_NL_SAME(ECMXF_DET_ECM_STATUS, ECMXF_NL_EV_ECM_STATUS);
ECMXF_NL_SAME(ECMXF_DET_CRC_ERRORS, ECMXF_NL_EV_CRC_ERRORS);
ECMXF_NL_SAME(ECMXF_DET_WKC_BURST, ECMXF_NL_EV_WKC_BURST);
ECMXF_NL_SAME(ECMXF_DET_WKC_BURST_END, ECMXF_NL_EV_WKC_BURST_END);
ECMXF_NL_SAME(ECMXF_DET_FIFO, ECMXF_NL_EV_FIFO);
ECMXF_NL_SAME(ECMXF_DET_FIFO_TX, ECMXF_NL_FIFO_TX);
ECMXF_NL_SAME(ECMXF_DET_FIFO_RX, ECMXF_NL_FIFO_RX);
static_assert(ECMXF_NL_EV_MAX < ECMXF_NL_TYPES);
/* the counter attributes follow struct ecmxf_counters field by field */
static_assert(ECMXF_NL_C_INT1_IRQS - ECMXF_NL_C_EXCHANGES + 1 ==
	      offsetof(struct ecmxf_counters, reserved) / sizeof(__u64));

static bool ecmxf_nl_listening(void)
{
	return genl_has_listeners(&ecmxf_nl_family, &init_net, 0) > 0;
}

/* ---- building and sending ------------------------------------------- */

static int ecmxf_nl_put_dev(struct sk_buff *skb, struct ecmxf_dev *edev)
{
	if (nla_put_u32(skb, ECMXF_NL_A_DEV_MINOR, edev->id) ||
	    nla_put_string(skb, ECMXF_NL_A_DEV_NAME, dev_name(&edev->dev)))
		return -EMSGSIZE;
	return 0;
}

static int ecmxf_nl_put_slaves(struct sk_buff *skb,
			       const struct ecmxf_nl_msg *m)
{
	const struct ecmxf_nl_ev *ev = &m->ev;
	const struct ecmxf_nl_slave *first = NULL;
	struct nlattr *all, *one;
	unsigned int i;

	if (nla_put_u32(skb, ECMXF_NL_A_SLAVE_COUNT, ev->slave_count))
		return -EMSGSIZE;
	if (ev->incomplete && nla_put_flag(skb, ECMXF_NL_A_SLAVES_INCOMPLETE))
		return -EMSGSIZE;
	all = nla_nest_start(skb, ECMXF_NL_A_SLAVES);
	if (!all)
		return -EMSGSIZE;
	for (i = 0; i < ev->n_slaves; i++) {
		const struct ecmxf_nl_slave *s = &m->slaves[i];

		one = nla_nest_start(skb, ECMXF_NL_A_SLAVE);
		if (!one ||
		    nla_put_u16(skb, ECMXF_NL_SA_POSITION, s->pos) ||
		    nla_put_u8(skb, ECMXF_NL_SA_STATE, s->state) ||
		    (s->have_al &&
		     nla_put_u16(skb, ECMXF_NL_SA_AL_STATUS, s->al)))
			return -EMSGSIZE;
		nla_nest_end(skb, one);
		if (!first && s->have_al && s->al)
			first = s;
	}
	nla_nest_end(skb, all);
	if (first && (nla_put_u16(skb, ECMXF_NL_A_AL_STATUS, first->al) ||
		      nla_put_u16(skb, ECMXF_NL_A_AL_SLAVE, first->pos)))
		return -EMSGSIZE;
	return 0;
}

/* The attributes that depend on the event type. */
static int ecmxf_nl_put_event(struct sk_buff *skb,
			      const struct ecmxf_nl_msg *m)
{
	const struct ecmxf_nl_ev *ev = &m->ev;
	const struct ecmxf_det_event *d = &ev->d;
	int bad = 0;

	switch (d->type) {
	case ECMXF_NL_EV_DEVICE:
		bad = nla_put_u32(skb, ECMXF_NL_A_ACTION, ev->action);
		if (ev->action == ECMXF_NL_DEV_ADDED)
			bad = bad ||
			      nla_put_u32(skb, ECMXF_NL_A_NEW, d->new_val) ||
			      nla_put_u8(skb, ECMXF_NL_A_LINK_UP,
					 d->err_status & ECMXF_ERR_LINK_HW) ||
			      nla_put_u8(skb, ECMXF_NL_A_ERR_STATUS,
					 d->err_status) ||
			      nla_put_u8(skb, ECMXF_NL_A_ECM_STATUS,
					 d->ecm_status);
		break;
	case ECMXF_NL_EV_RESET:
		bad = nla_put_u32(skb, ECMXF_NL_A_RESET_REASON,
				  ev->reset_reason) ||
		      nla_put_u32(skb, ECMXF_NL_A_NEW, d->new_val) ||
		      nla_put_u8(skb, ECMXF_NL_A_ECM_STATUS, d->ecm_status);
		break;
	case ECMXF_NL_EV_LINK:
		bad = nla_put_u8(skb, ECMXF_NL_A_LINK_UP, d->new_val) ||
		      nla_put_u8(skb, ECMXF_NL_A_ERR_STATUS, d->err_status);
		break;
	case ECMXF_NL_EV_STATE:
		bad = nla_put_u32(skb, ECMXF_NL_A_OLD, d->old_val) ||
		      nla_put_u32(skb, ECMXF_NL_A_NEW, d->new_val) ||
		      (ev->slaves && ecmxf_nl_put_slaves(skb, m));
		break;
	case ECMXF_NL_EV_ERROR_STATUS:
	case ECMXF_NL_EV_ECM_STATUS:
		bad = nla_put_u32(skb, ECMXF_NL_A_OLD, d->old_val) ||
		      nla_put_u32(skb, ECMXF_NL_A_NEW, d->new_val);
		break;
	case ECMXF_NL_EV_CRC_ERRORS:
	case ECMXF_NL_EV_WKC_BURST:
		bad = nla_put_u32(skb, ECMXF_NL_A_INCREASE, d->increase) ||
		      nla_put_u32(skb, ECMXF_NL_A_COUNT, d->count);
		break;
	case ECMXF_NL_EV_WKC_BURST_END:
		bad = nla_put_u32(skb, ECMXF_NL_A_ERRORS, d->errors) ||
		      nla_put_u64_64bit(skb, ECMXF_NL_A_DURATION_NS,
					d->duration_ns, ECMXF_NL_A_PAD) ||
		      nla_put_u32(skb, ECMXF_NL_A_COUNT, d->count);
		break;
	case ECMXF_NL_EV_FIFO:
		bad = nla_put_u8(skb, ECMXF_NL_A_FIFO, d->fifo) ||
		      nla_put_u32(skb, ECMXF_NL_A_COUNT, d->count) ||
		      nla_put_u32(skb, ECMXF_NL_A_MARK, d->mark) ||
		      nla_put_u8(skb, ECMXF_NL_A_ABOVE, d->above);
		break;
	case ECMXF_NL_EV_PDO_LOSS:
		bad = nla_put_u8(skb, ECMXF_NL_A_LOSS, d->fifo) ||
		      nla_put_u32(skb, ECMXF_NL_A_INCREASE, d->increase) ||
		      nla_put_u64_64bit(skb, ECMXF_NL_A_TOTAL, ev->total,
					ECMXF_NL_A_PAD);
		break;
	case ECMXF_NL_EV_ASYNC_ERROR:
		bad = nla_put_u8(skb, ECMXF_NL_A_CMD_CODE, ev->cmd_code) ||
		      nla_put_s32(skb, ECMXF_NL_A_STATUS, ev->status) ||
		      nla_put_u8(skb, ECMXF_NL_A_ERR_STATUS, d->err_status);
		break;
	default:
		break;
	}
	return bad ? -EMSGSIZE : 0;
}

/*
 * Multicast one event; 0, or why not (-ESRCH: nobody listens).  Called by
 * the sender (ecmxf_nl_send_work()) in process context: the allocation
 * may sleep.
 */
static int ecmxf_nl_send(struct ecmxf_dev *edev, const struct ecmxf_nl_msg *m)
{
	const struct ecmxf_nl_ev *ev = &m->ev;
	struct sk_buff *skb;
	void *hdr;

	/* a state event with its slaves needs up to about 2 KiB */
	skb = genlmsg_new(ev->slaves ? NLMSG_GOODSIZE : ECMXF_NL_EVENT_SIZE,
			  GFP_KERNEL);
	if (!skb)
		return -ENOMEM;
	hdr = genlmsg_put(skb, 0, 0, &ecmxf_nl_family, 0, ECMXF_NL_CMD_EVENT);
	if (!hdr)
		goto too_big;
	if (ecmxf_nl_put_dev(skb, edev) ||
	    nla_put_u32(skb, ECMXF_NL_A_EVENT_TYPE, ev->d.type) ||
	    nla_put_u64_64bit(skb, ECMXF_NL_A_TIMESTAMP_NS, ev->d.time_ns,
			      ECMXF_NL_A_PAD) ||
	    nla_put_u32(skb, ECMXF_NL_A_SEQ, m->seq) ||
	    (m->suppressed &&
	     nla_put_u32(skb, ECMXF_NL_A_SUPPRESSED, m->suppressed)) ||
	    ecmxf_nl_put_event(skb, m))
		goto too_big;
	genlmsg_end(skb, hdr);
	return genlmsg_multicast(&ecmxf_nl_family, skb, 0, 0, GFP_KERNEL);

too_big:
	nlmsg_free(skb);
	return -EMSGSIZE;
}

/**
 * ecmxf_nl_send_work() - the sender: multicast what the worker handed over
 * @work: &ecmxf_nl_out.work
 *
 * Oldest first; a slot is given back to the worker once its message went
 * (or could not).  No listener is not an error.
 */
static void ecmxf_nl_send_work(struct work_struct *work)
{
	struct ecmxf_nl_out *out = container_of(work, struct ecmxf_nl_out,
						work);
	struct ecmxf_dev *edev = out->edev;
	unsigned int head;
	int ret;

	for (;;) {
		spin_lock(&out->lock);
		head = out->head;
		if (!out->count) {
			spin_unlock(&out->lock);
			return;
		}
		spin_unlock(&out->lock);
		ret = ecmxf_nl_listening() ? ecmxf_nl_send(edev, &out->msg[head])
					   : -ESRCH;
		if (ret && ret != -ESRCH)
			atomic64_inc(&edev->nl.events_failed);
		spin_lock(&out->lock);
		out->head = (head + 1) % ECMXF_NL_QUEUE;
		out->count--;
		spin_unlock(&out->lock);
	}
}

/*
 * Hand one event to the sender: copied into a free slot of its ring (with
 * the query's slaves for a state event that has them); 0, or -ENOSPC when
 * the ring is full (or was never allocated).
 */
static int ecmxf_nl_hand_over(struct ecmxf_dev *edev,
			      const struct ecmxf_nl_ev *ev, u32 seq,
			      u32 suppressed)
{
	struct ecmxf_nl_out *out = edev->nl.out;
	struct ecmxf_nl_msg *m;
	unsigned int slot;

	if (!out)
		return -ENOSPC;
	spin_lock(&out->lock);
	slot = (out->head + out->count) % ECMXF_NL_QUEUE;
	if (out->count >= ECMXF_NL_QUEUE) {
		spin_unlock(&out->lock);
		return -ENOSPC;
	}
	spin_unlock(&out->lock);
	/* the slot is free: only the worker writes free slots */
	m = &out->msg[slot];
	m->ev = *ev;
	m->seq = seq;
	m->suppressed = suppressed;
	if (ev->slaves)
		memcpy(m->slaves, edev->nl.slaves,
		       ev->n_slaves * sizeof(m->slaves[0]));
	spin_lock(&out->lock);
	out->count++;
	spin_unlock(&out->lock);
	return 0;
}

/* May an event of @type go now (token bucket)?  Device events always may. */
static bool ecmxf_nl_allow(struct ecmxf_nl_dev *nl, unsigned int type,
			   u64 now)
{
	struct ecmxf_nl_rate *r = &nl->rate[type];
	u64 periods;

	if (type == ECMXF_NL_EV_DEVICE)
		return true;
	if (!r->last_ns) {
		r->tokens = ECMXF_NL_RATE_BURST;
		r->last_ns = now;
	}
	periods = div64_u64(now - r->last_ns, ECMXF_NL_RATE_PERIOD_NS);
	if (periods) {
		r->tokens = (u32)min_t(u64, ECMXF_NL_RATE_BURST,
				       r->tokens + periods);
		r->last_ns += periods * ECMXF_NL_RATE_PERIOD_NS;
	}
	if (!r->tokens)
		return false;
	r->tokens--;
	return true;
}

static void ecmxf_nl_queue(struct ecmxf_dev *edev,
			   const struct ecmxf_nl_ev *ev);

/* The cyclic path's counters, in &enum ecmxf_nl_loss order. */
static void ecmxf_nl_loss_counters(const struct ecmxf_dev *edev,
				   u64 v[ECMXF_NL_LOSS_KINDS])
{
	v[ECMXF_NL_LOSS_OUT_RING_UNDERRUN] = edev->cnt.out_ring_underruns;
	v[ECMXF_NL_LOSS_IN_RING_OVERRUN] = edev->cnt.in_ring_overruns;
	v[ECMXF_NL_LOSS_RX_FIFO_UNDERRUN] = edev->cnt.rx_fifo_underruns;
	v[ECMXF_NL_LOSS_RX_FIFO_OVERRUN] = edev->cnt.rx_fifo_overruns;
	v[ECMXF_NL_LOSS_TX_FIFO_OVERRUN] = edev->cnt.tx_fifo_overruns;
	v[ECMXF_NL_LOSS_OUT_RING_SKIPPED] = edev->cnt.out_ring_skipped;
	v[ECMXF_NL_LOSS_PUMP_FAILURE] = edev->cnt.pump_failures;
}

/* A counter of the cyclic path went up since the last look. */
static bool ecmxf_nl_loss_pending(const struct ecmxf_dev *edev)
{
	u64 v[ECMXF_NL_LOSS_KINDS];
	unsigned int i;

	ecmxf_nl_loss_counters(edev, v);
	for (i = 0; i < ECMXF_NL_LOSS_KINDS; i++)
		if (v[i] != edev->nl.loss_seen[i])
			return true;
	return false;
}

/*
 * At most every ECMXF_NL_LOSS_PERIOD_NS: one %ECMXF_NL_EV_PDO_LOSS event
 * per counter of the cyclic path that went up since the last look.  The
 * rate limit is applied here, not in ecmxf_nl_flush(): a counter whose
 * event it holds back keeps its increase for the next event, so that none
 * is suppressed and the last one always has the final total.  The worker
 * is the only writer of those counters, so it reads them without the lock.
 */
static void ecmxf_nl_losses(struct ecmxf_dev *edev, u64 now)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	u64 v[ECMXF_NL_LOSS_KINDS];
	struct ecmxf_nl_ev ev;
	unsigned int i;

	if (!nl->active || now < nl->next_loss_ns)
		return;
	nl->next_loss_ns = now + ECMXF_NL_LOSS_PERIOD_NS;
	ecmxf_nl_loss_counters(edev, v);
	for (i = 0; i < ECMXF_NL_LOSS_KINDS; i++) {
		if (v[i] <= nl->loss_seen[i]) {
			nl->loss_seen[i] = v[i];
			continue;
		}
		if (!ecmxf_nl_allow(nl, ECMXF_NL_EV_PDO_LOSS, now))
			continue;
		memset(&ev, 0, sizeof(ev));
		ev.d.type = ECMXF_NL_EV_PDO_LOSS;
		ev.d.time_ns = now;
		ev.d.fifo = (u8)i;
		ev.d.increase = (u32)min_t(u64, v[i] - nl->loss_seen[i],
					   U32_MAX);
		ev.total = v[i];
		nl->loss_seen[i] = v[i];
		ecmxf_nl_queue(edev, &ev);
	}
}

/**
 * ecmxf_nl_flush() - hand the events that wait in the device's queue over
 * @edev: the device
 *
 * Worker only, with no lock held: the rate limit, the numbers, then the
 * sender's ring (ecmxf_nl_hand_over()) and a wake-up of the sender; a
 * full ring counts the event as failed.  Nothing is allocated or sent
 * here.
 */
static void ecmxf_nl_flush(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	u64 now = ktime_get_ns();
	bool handed = false;
	unsigned int i;

	ecmxf_nl_losses(edev, now);
	for (i = 0; i < nl->queued; i++) {
		const struct ecmxf_nl_ev *ev = &nl->queue[i];
		struct ecmxf_nl_rate *r = &nl->rate[ev->d.type];
		u32 seq = nl->seq++;

		/* PDO_LOSS events passed the limit when they were queued */
		if (ev->d.type != ECMXF_NL_EV_PDO_LOSS &&
		    !ecmxf_nl_allow(nl, ev->d.type, now)) {
			r->suppressed++;
			atomic64_inc(&nl->events_suppressed);
			continue;
		}
		if (ecmxf_nl_hand_over(edev, ev, seq, r->suppressed))
			atomic64_inc(&nl->events_failed);
		else
			handed = true;
		r->suppressed = 0;
	}
	nl->queued = 0;
	if (handed)
		queue_work(system_unbound_wq, &nl->out->work);
}

static void ecmxf_nl_queue(struct ecmxf_dev *edev, const struct ecmxf_nl_ev *ev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;

	atomic64_inc(&nl->events);
	if (nl->queued >= ARRAY_SIZE(nl->queue)) {
		/* many events between two flushes: counted, not hidden */
		atomic64_inc(&nl->events_failed);
		nl->seq++;
		return;
	}
	nl->queue[nl->queued++] = *ev;
}

/* ---- the AL status query --------------------------------------------- */

static void ecmxf_nl_query_queue(struct ecmxf_dev *edev);

/* The query ends: its state event goes to the queue. */
static void ecmxf_nl_query_end(struct ecmxf_dev *edev, bool incomplete)
{
	struct ecmxf_nl_dev *nl = &edev->nl;

	if (nl->q_state == ECMXF_NLQ_IDLE)
		return;
	if (incomplete)
		nl->q_ev.incomplete = true;
	nl->q_state = ECMXF_NLQ_IDLE;
	ecmxf_nl_queue(edev, &nl->q_ev);
}

/* A state change down or into ERROR asks the slaves why. */
static bool ecmxf_nl_state_went_down(const struct ecmxf_det_event *d)
{
	return (d->new_val & ECMXF_ECAT_ERROR) ||
	       (d->new_val & 0x0F) < (d->old_val & 0x0F);
}

static void ecmxf_nl_state_event(struct ecmxf_dev *edev,
				 const struct ecmxf_nl_ev *ev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;

	if (!ecmxf_nl_state_went_down(&ev->d) || !ecmxf_nl_listening() ||
	    !nl->query) {
		ecmxf_nl_queue(edev, ev);
		return;
	}
	/* a query still running for an earlier change: that one ends now */
	ecmxf_nl_query_end(edev, true);
	nl->q_gen++;	/* an answer still on its way belongs to the old one */
	nl->q_ev = *ev;
	nl->q_ev.slaves = true;
	nl->q_ev.incomplete = false;
	nl->q_ev.slave_count = 0;
	nl->q_ev.n_slaves = 0;
	nl->q_state = ECMXF_NLQ_COUNT;
	nl->q_pos = 0;
	mutex_lock(&edev->lock);
	ecmxf_nl_query_queue(edev);
	mutex_unlock(&edev->lock);
}

/**
 * struct ecmxf_nl_query - the AL status query's client of the worker's queue
 * @client: on &ecmxf_dev.clients while the worker runs; never a file
 * @req: its one request, queued again for every step
 * @busy: @req is queued or in the engine
 * @err_before: error status when @req was queued (a command error the
 *	query causes is cleared again, one that was there is left)
 * @gen: &ecmxf_nl_dev.q_gen when @req was queued
 */
struct ecmxf_nl_query {
	struct ecmxf_client client;
	struct ecmxf_req req;
	bool busy;
	u8 err_before;
	u32 gen;
};

static void ecmxf_nl_query_done(struct ecmxf_dev *edev, struct ecmxf_req *req);

/*
 * Queue the query's command for its current step, unless one is queued
 * or running already (its answer takes the query on); lock held.
 */
static void ecmxf_nl_query_queue(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	struct ecmxf_nl_query *q = nl->query;
	struct ecmxf_req *req;
	struct ecmxf_xfer *x;

	lockdep_assert_held(&edev->lock);
	if (!q || q->busy || nl->q_state == ECMXF_NLQ_IDLE)
		return;
	req = &q->req;
	x = &req->x;
	memset(x, 0, sizeof(*x));
	switch (nl->q_state) {
	case ECMXF_NLQ_COUNT:
		x->hdr.code = ECMXF_CMD_ECAT_SLV_CNT_GET;
		break;
	case ECMXF_NLQ_STATE:
		x->hdr.code = ECMXF_CMD_ECAT_STATE_GET;
		x->hdr.param = (u8)nl->q_pos;
		break;
	default:
		x->hdr.code = ECMXF_CMD_ECAT_SLV_INFO_GET;
		x->hdr.param = (u8)nl->q_pos;
		x->hdr.data[0] = 7;	/* AL status code */
		x->rx_buf = req->rx;
		x->rx_size = 16;
		break;
	}
	x->status = -EINPROGRESS;
	req->kind = ECMXF_REQ_KERNEL;
	req->client = &q->client;
	req->complete = ecmxf_nl_query_done;
	req->state = ECMXF_RS_QUEUED;
	req->deadline_ns = ktime_get_ns() +
			   (u64)ECMXF_NL_QUERY_TIMEOUT_US * NSEC_PER_USEC;
	q->err_before = edev->chip.last.err_status;
	q->gen = nl->q_gen;
	q->busy = true;
	list_add_tail(&req->node, &q->client.queue);
	ecmxf_worker_kick(edev);
}

/* Withdraw the query's command if it is still queued; lock held. */
static void ecmxf_nl_query_unqueue(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_query *q = edev->nl.query;

	lockdep_assert_held(&edev->lock);
	if (!q || !q->busy || q->req.state != ECMXF_RS_QUEUED)
		return;
	list_del_init(&q->req.node);
	q->busy = false;
}

/* The query moves to the next slave, or ends. */
static void ecmxf_nl_query_next(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;

	nl->q_pos++;
	nl->q_state = ECMXF_NLQ_STATE;
	if (nl->q_pos >= nl->q_ev.slave_count)
		ecmxf_nl_query_end(edev, false);
	else if (nl->q_pos >= ECMXF_NL_MAX_SLAVES)
		ecmxf_nl_query_end(edev, true);
}

/*
 * The worker finished the query's command (answered, failed, expired in
 * the queue or cancelled): take the answer and queue the next step.
 * Called by the worker with &ecmxf_dev.lock held (&ecmxf_req.complete).
 */
static void ecmxf_nl_query_done(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	struct ecmxf_nl_query *q = nl->query;
	struct ecmxf_xfer *x = &req->x;
	struct ecmxf_nl_slave *s;
	bool cmd_err;

	lockdep_assert_held(&edev->lock);
	q->busy = false;
	cmd_err = x->rsp.err_status & ECMXF_ERR_CMD;
	/* leave no command error behind that was not there before */
	if (!x->status && cmd_err && !(q->err_before & ECMXF_ERR_CMD))
		ecmxf_engine_clear_errors(&edev->link.e, ECMXF_CTL_CLR_CMD_ERR);
	if (q->gen != nl->q_gen)
		goto next;	/* the answer of a query that ended */
	if ((x->status && x->status != -EMSGSIZE) || cmd_err) {
		ecmxf_nl_query_end(edev, true);
		return;
	}
	switch (nl->q_state) {
	case ECMXF_NLQ_COUNT:
		nl->q_ev.slave_count = x->rsp.ret;
		nl->q_pos = 0;
		nl->q_state = ECMXF_NLQ_STATE;
		if (!nl->q_ev.slave_count)
			ecmxf_nl_query_end(edev, false);
		break;
	case ECMXF_NLQ_STATE:
		if (x->rsp.ret == ECMXF_ECAT_OP) {
			ecmxf_nl_query_next(edev);
			break;
		}
		s = &nl->slaves[nl->q_ev.n_slaves++];
		s->pos = nl->q_pos;
		s->state = x->rsp.ret;
		s->have_al = false;
		s->al = 0;
		/* ERROR alone: the slave does not answer, nothing to ask */
		if (x->rsp.ret == ECMXF_ECAT_ERROR)
			ecmxf_nl_query_next(edev);
		else
			nl->q_state = ECMXF_NLQ_AL;
		break;
	case ECMXF_NLQ_AL:
		s = &nl->slaves[nl->q_ev.n_slaves - 1];
		if (x->rx_len >= 2) {
			s->al = get_unaligned_le16(req->rx);
			s->have_al = true;
		} else {
			nl->q_ev.incomplete = true;
		}
		ecmxf_nl_query_next(edev);
		break;
	default:
		break;
	}
next:
	ecmxf_nl_query_queue(edev);
}

/* ---- what the worker reports ----------------------------------------- */

static void ecmxf_nl_detected(struct ecmxf_dev *edev,
			      const struct ecmxf_det_event *d, unsigned int n)
{
	struct ecmxf_nl_ev ev;
	unsigned int i;

	for (i = 0; i < n; i++) {
		memset(&ev, 0, sizeof(ev));
		ev.d = d[i];
		if (ev.d.type == ECMXF_NL_EV_STATE) {
			ecmxf_nl_state_event(edev, &ev);
			continue;
		}
		if (ev.d.type == ECMXF_NL_EV_RESET) {
			ev.reset_reason = edev->nl.warm_sent ?
					  ECMXF_NL_RESET_WARM :
					  ECMXF_NL_RESET_CHIP;
			edev->nl.warm_sent = false;
			/* the slaves the query was reading are gone */
			ecmxf_nl_query_end(edev, true);
		}
		ecmxf_nl_queue(edev, &ev);
	}
}

/**
 * ecmxf_nl_header() - a valid response header arrived
 * @edev: the device
 * @now_ns: when (ktime_get_ns())
 *
 * Called by ecmxf_exchange() for every exchange that brought a valid
 * header; detects events from the engine's latest header.
 */
static void ecmxf_nl_header(struct ecmxf_dev *edev, u64 now_ns)
{
	struct ecmxf_det_event d[ECMXF_DET_MAX_EVENTS];
	const struct ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&edev->link.e);
	unsigned int n;

	if (!edev->nl.active || !h)
		return;
	n = ecmxf_det_feed(&edev->nl.det, h, now_ns, d);
	ecmxf_nl_detected(edev, d, n);
}

/**
 * ecmxf_nl_req_sent() - a command goes to the engine
 * @edev: the device
 * @x: its transfer
 *
 * Notes a WARM_RESET, so that the reset it causes is reported as such.
 */
static void ecmxf_nl_req_sent(struct ecmxf_dev *edev, const struct ecmxf_xfer *x)
{
	if (x->hdr.code == ECMXF_CMD_WARM_RESET)
		edev->nl.warm_sent = true;
}

/**
 * ecmxf_nl_req_done() - a user command finished
 * @edev: the device
 * @x: its transfer, status final
 *
 * An async command that failed is an event.  Called by the worker with
 * &ecmxf_dev.lock held: the event is only queued.
 */
static void ecmxf_nl_req_done(struct ecmxf_dev *edev, const struct ecmxf_xfer *x)
{
	struct ecmxf_nl_ev ev;

	if (x->hdr.code == ECMXF_CMD_WARM_RESET && x->status)
		edev->nl.warm_sent = false;	/* no reset will follow */
	if (!edev->nl.active || !x->async)
		return;
	if (x->status != -EREMOTEIO && x->status != -EBUSY &&
	    x->status != -ETIMEDOUT)
		return;
	memset(&ev, 0, sizeof(ev));
	ev.d.type = ECMXF_NL_EV_ASYNC_ERROR;
	ev.d.time_ns = ktime_get_ns();
	ev.d.err_status = x->rsp.err_status;
	ev.d.ecm_status = x->rsp.ecm_status;
	ev.cmd_code = x->hdr.code;
	ev.status = x->status;
	ecmxf_nl_queue(edev, &ev);
}

/**
 * ecmxf_nl_link_reset() - the worker resynchronised the link
 * @edev: the device
 *
 * %ECMXF_RESET_F_LINK: the engine starts afresh; the detector takes the
 * next header as its baseline.
 */
static void ecmxf_nl_link_reset(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	const struct ecmxf_rsp_hdr *h;
	struct ecmxf_det_event d;
	struct ecmxf_nl_ev ev;
	u64 now = ktime_get_ns();

	if (!nl->active)
		return;
	mutex_lock(&edev->lock);
	ecmxf_nl_query_unqueue(edev);
	mutex_unlock(&edev->lock);
	ecmxf_nl_query_end(edev, true);
	if (ecmxf_det_rebase(&nl->det, now, &d))
		ecmxf_nl_detected(edev, &d, 1);
	memset(&ev, 0, sizeof(ev));
	ev.d.type = ECMXF_NL_EV_RESET;
	ev.d.time_ns = now;
	h = ecmxf_engine_last_header(&edev->link.e);
	if (h) {
		ev.d.new_val = h->ecat_state;
		ev.d.err_status = h->err_status;
		ev.d.ecm_status = h->ecm_status;
	}
	ev.reset_reason = ECMXF_NL_RESET_LINK;
	ecmxf_nl_queue(edev, &ev);
}

/**
 * ecmxf_nl_poll_due() - should the idle worker poll the chip now
 * @edev: the device
 * @now_ns: current time
 *
 * Also ends a WKC burst whose quiet time has passed.
 *
 * Return: true when someone listens and event_poll_ms has passed since
 * the last poll.
 */
static bool ecmxf_nl_poll_due(struct ecmxf_dev *edev, u64 now_ns)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	unsigned int period = edev->cfg.event_poll_ms;
	struct ecmxf_det_event d;

	if (!nl->active)
		return false;
	if (ecmxf_det_poll(&nl->det, now_ns, &d))
		ecmxf_nl_detected(edev, &d, 1);
	if (!period || now_ns < nl->next_poll_ns)
		return false;
	nl->next_poll_ns = now_ns + (u64)period * NSEC_PER_MSEC;
	return ecmxf_nl_listening();
}

/**
 * ecmxf_nl_wake_at() - when the idle worker must look again
 * @edev: the device
 * @now_ns: current time
 *
 * Return: the next poll, the end of a WKC burst, or when a loss of the
 * cyclic path not reported yet is due (ktime_get_ns() clock), or U64_MAX
 * for "only when kicked".
 */
static u64 ecmxf_nl_wake_at(struct ecmxf_dev *edev, u64 now_ns)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	u64 t = ecmxf_det_deadline(&nl->det);

	if (!nl->active)
		return U64_MAX;
	if (edev->cfg.event_poll_ms && nl->next_poll_ns < t)
		t = max(nl->next_poll_ns, now_ns);
	/* a loss not reported yet: look again when its period is over */
	if (nl->next_loss_ns < t && ecmxf_nl_loss_pending(edev))
		t = max(nl->next_loss_ns, now_ns);
	return t;
}

/**
 * ecmxf_nl_start() - the worker starts: events from now on
 * @edev: the device, link up
 *
 * The header probe read last is the detector's baseline; the "added"
 * event is sent at once (just before probe creates /dev/ecmxfN).  The AL
 * status query's client joins the worker's queue (without memory for it,
 * state events go without their slaves).  Called by the worker itself, no
 * lock held.
 */
static void ecmxf_nl_start(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	const struct ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&edev->link.e);
	struct ecmxf_det_event d[ECMXF_DET_MAX_EVENTS];
	struct ecmxf_nl_query *q;
	struct ecmxf_nl_ev ev;
	u64 now = ktime_get_ns();

	q = kzalloc(sizeof(*q), GFP_KERNEL);
	if (q) {
		q->client.edev = edev;
		INIT_LIST_HEAD(&q->client.queue);
		INIT_LIST_HEAD(&q->client.done);
		init_waitqueue_head(&q->client.wq);
		INIT_LIST_HEAD(&q->req.node);
		init_completion(&q->req.done);
		mutex_lock(&edev->lock);
		list_add_tail(&q->client.node, &edev->clients);
		nl->query = q;
		mutex_unlock(&edev->lock);
	}
	nl->out = kvzalloc(sizeof(*nl->out), GFP_KERNEL);
	if (nl->out) {
		nl->out->edev = edev;
		spin_lock_init(&nl->out->lock);
		INIT_WORK(&nl->out->work, ecmxf_nl_send_work);
	}
	ecmxf_det_init(&nl->det, NULL);
	memset(&ev, 0, sizeof(ev));
	if (h) {
		ecmxf_det_feed(&nl->det, h, now, d);	/* baseline: no events */
		ev.d.new_val = h->ecat_state;
		ev.d.err_status = h->err_status;
		ev.d.ecm_status = h->ecm_status;
	}
	nl->next_poll_ns = now;
	ecmxf_nl_loss_counters(edev, nl->loss_seen);
	nl->next_loss_ns = now;
	nl->active = true;
	ev.d.type = ECMXF_NL_EV_DEVICE;
	ev.d.time_ns = now;
	ev.action = ECMXF_NL_DEV_ADDED;
	ecmxf_nl_queue(edev, &ev);
	ecmxf_nl_flush(edev);
	/* sent before probe goes on to create /dev/ecmxfN */
	if (nl->out)
		flush_work(&nl->out->work);
}

/**
 * ecmxf_nl_stop() - the worker ends: the last events
 * @edev: the device
 *
 * A pending state event is sent without the rest of its query, then the
 * "removed" event.  Called by the worker itself as it ends, after it
 * cancelled what was in the engine, no lock held; the query's client
 * leaves the queue.
 */
static void ecmxf_nl_stop(struct ecmxf_dev *edev)
{
	struct ecmxf_nl_dev *nl = &edev->nl;
	struct ecmxf_nl_query *q;
	struct ecmxf_det_event d;
	struct ecmxf_nl_ev ev;
	u64 now = ktime_get_ns();

	if (!nl->active)
		return;
	q = nl->query;
	if (q) {
		mutex_lock(&edev->lock);
		ecmxf_nl_query_unqueue(edev);
		list_del_init(&q->client.node);
		nl->query = NULL;
		mutex_unlock(&edev->lock);
		/* the worker cancelled what it ran: the request is ours */
		if (!WARN_ON_ONCE(q->busy))
			kfree(q);
	}
	ecmxf_nl_query_end(edev, true);
	if (ecmxf_det_poll(&nl->det, U64_MAX, &d))
		ecmxf_nl_detected(edev, &d, 1);
	memset(&ev, 0, sizeof(ev));
	ev.d.type = ECMXF_NL_EV_DEVICE;
	ev.d.time_ns = now;
	ev.action = ECMXF_NL_DEV_REMOVED;
	ecmxf_nl_queue(edev, &ev);
	ecmxf_nl_flush(edev);
	nl->active = false;
	/* every event sent before the device can go */
	if (nl->out) {
		flush_work(&nl->out->work);
		kvfree(nl->out);
		nl->out = NULL;
	}
}

/* what the link worker tells this unit (ecmxf_worker_watch()) */
static const struct ecmxf_watch_ops ecmxf_nl_watch = {
	.start = ecmxf_nl_start,
	.stop = ecmxf_nl_stop,
	.flush = ecmxf_nl_flush,
	.header = ecmxf_nl_header,
	.req_sent = ecmxf_nl_req_sent,
	.req_done = ecmxf_nl_req_done,
	.link_reset = ecmxf_nl_link_reset,
	.poll_due = ecmxf_nl_poll_due,
	.wake_at = ecmxf_nl_wake_at,
};

/* ---- counters -------------------------------------------------------- */

static int ecmxf_nl_fill_counters(struct sk_buff *skb, struct ecmxf_dev *edev,
				  u32 portid, u32 seq, int flags)
{
	struct ecmxf_counters k;
	const __u64 *v = (const __u64 *)&k;
	struct nlattr *nest;
	unsigned int i, n;
	void *hdr;

	ecmxf_get_counters(edev, &k);
	hdr = genlmsg_put(skb, portid, seq, &ecmxf_nl_family, flags,
			  ECMXF_NL_CMD_GET_COUNTERS);
	if (!hdr)
		return -EMSGSIZE;
	if (ecmxf_nl_put_dev(skb, edev))
		goto cancel;
	nest = nla_nest_start(skb, ECMXF_NL_A_COUNTERS);
	if (!nest)
		goto cancel;
	n = ECMXF_NL_C_INT1_IRQS - ECMXF_NL_C_EXCHANGES + 1;
	for (i = 0; i < n; i++)
		if (nla_put_u64_64bit(skb, ECMXF_NL_C_EXCHANGES + i, v[i],
				      ECMXF_NL_C_PAD))
			goto cancel;
	if (nla_put_u64_64bit(skb, ECMXF_NL_C_EVENTS,
			      atomic64_read(&edev->nl.events), ECMXF_NL_C_PAD) ||
	    nla_put_u64_64bit(skb, ECMXF_NL_C_EVENTS_SUPPRESSED,
			      atomic64_read(&edev->nl.events_suppressed),
			      ECMXF_NL_C_PAD) ||
	    nla_put_u64_64bit(skb, ECMXF_NL_C_EVENTS_FAILED,
			      atomic64_read(&edev->nl.events_failed),
			      ECMXF_NL_C_PAD))
		goto cancel;
	nla_nest_end(skb, nest);
	genlmsg_end(skb, hdr);
	return 0;

cancel:
	genlmsg_cancel(skb, hdr);
	return -EMSGSIZE;
}

/* The device behind minor @minor with a reference, or NULL. */
static struct ecmxf_dev *ecmxf_nl_get_dev(unsigned int minor)
{
	struct device *dev;

	if (minor >= ECMXF_MAX_DEVICES)
		return NULL;
	dev = class_find_device_by_devt(&ecmxf_class,
					MKDEV(MAJOR(ecmxf_devt), minor));
	return dev ? container_of(dev, struct ecmxf_dev, dev) : NULL;
}

static int ecmxf_nl_get_counters(struct sk_buff *skb, struct genl_info *info)
{
	struct ecmxf_dev *edev;
	struct sk_buff *msg;
	int ret;

	if (GENL_REQ_ATTR_CHECK(info, ECMXF_NL_A_DEV_MINOR))
		return -EINVAL;
	edev = ecmxf_nl_get_dev(nla_get_u32(info->attrs[ECMXF_NL_A_DEV_MINOR]));
	if (!edev) {
		GENL_SET_ERR_MSG(info, "no ecmxf device with that minor");
		return -ENODEV;
	}
	msg = genlmsg_new(NLMSG_GOODSIZE, GFP_KERNEL);
	if (!msg) {
		ret = -ENOMEM;
		goto out_put;
	}
	ret = ecmxf_nl_fill_counters(msg, edev, info->snd_portid,
				     info->snd_seq, 0);
	if (ret) {
		nlmsg_free(msg);
		goto out_put;
	}
	ret = genlmsg_reply(msg, info);
out_put:
	put_device(&edev->dev);
	return ret;
}

static int ecmxf_nl_dump_counters(struct sk_buff *skb,
				  struct netlink_callback *cb)
{
	unsigned int minor = cb->args[0];
	struct ecmxf_dev *edev;
	int ret;

	for (; minor < ECMXF_MAX_DEVICES; minor++) {
		edev = ecmxf_nl_get_dev(minor);
		if (!edev)
			continue;
		ret = ecmxf_nl_fill_counters(skb, edev,
					     NETLINK_CB(cb->skb).portid,
					     cb->nlh->nlmsg_seq, NLM_F_MULTI);
		put_device(&edev->dev);
		if (ret)
			break;	/* full: the next call goes on from here */
	}
	cb->args[0] = minor;
	return skb->len;
}

/**
 * ecmxf_nl_register() - register the generic netlink family
 *
 * Return: 0 or a negative errno.
 */
int ecmxf_nl_register(void)
{
	int ret = genl_register_family(&ecmxf_nl_family);

	if (!ret)
		ecmxf_worker_watch(&ecmxf_nl_watch);
	return ret;
}

/**
 * ecmxf_nl_unregister() - unregister it (after every worker stopped)
 */
void ecmxf_nl_unregister(void)
{
	ecmxf_worker_watch(NULL);
	genl_unregister_family(&ecmxf_nl_family);
}
