// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-chrdev.c - NEXTW ECM-XF: /dev/ecmxfN file operations
 *
 * The uAPI of include/uapi/linux/ecmxf.h (Documentation/uapi.rst and
 * Documentation/driver.rst): commands synchronously (ECMXF_IOC_CMD) or
 * submitted with their completions read() and poll()ed, device info,
 * counters, resets, the cyclic claim and the PDO rings (set up and mapped
 * here, pumped by ecmxf-ring.c).  Every argument is checked here; the
 * commands themselves go to the worker (ecmxf-worker.c) through the
 * file's queue.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/capability.h>
#include <linux/fs.h>
#include <linux/ktime.h>
#include <linux/poll.h>
#include <linux/sched/signal.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/uaccess.h>

#include "ecmxf.h"

/*
 * May @c send something of class @perm (Documentation/uapi.rst,
 * "Permissions")?  Queries: any file.  The rest: a file open for writing;
 * resets and reflashes also CAP_SYS_ADMIN; and while a claim is held, only
 * its holder (-EBUSY; devinfo names the holder): the claim holder owns the
 * machine.  Lock held (for the claim).
 */
static int ecmxf_check_perm(struct ecmxf_client *c, enum ecmxf_perm perm)
{
	struct ecmxf_dev *edev = c->edev;

	lockdep_assert_held(&edev->lock);
	if (perm == ECMXF_PERM_QUERY)
		return 0;
	if (!c->writable)
		return -EPERM;
	if (perm == ECMXF_PERM_ADMIN && !capable(CAP_SYS_ADMIN))
		return -EPERM;
	if (!ecmxf_claim_allows(edev, c, true))
		return -EBUSY;
	return 0;
}

/*
 * The class of a command header's side-effect fields: clearing interrupt
 * flags (the PDO pump waits on them) is process data's; clearing error
 * counts or status bits, GPIO interrupt bits and driving the GPIO outputs
 * change the chip.  The refresh-state bit of the control byte, its clear
 * of the command-error bit (which only makes this command's answer its
 * own: the library sets it on every command, and the kernel clears the
 * bit after any file's failed command anyway) and the INIT_OP bits of the
 * reserved word only ask (or belong to a command of their own class).
 */
static enum ecmxf_perm ecmxf_hdr_perm(const struct ecmxf_cmd_hdr *h)
{
	if (h->int_clear)
		return ECMXF_PERM_PROCESS;
	if ((h->control & ~(ECMXF_CTL_REFRESH_STATE | ECMXF_CTL_CLR_CMD_ERR)) ||
	    h->gpio_int_clear[0] || h->gpio_int_clear[1] ||
	    (h->reserved & ECMXF_RSV_GPIO_OUT) ||
	    h->gpio_out[0] || h->gpio_out[1])
		return ECMXF_PERM_CHIP;
	return ECMXF_PERM_QUERY;
}

/*
 * The result fetch @f of the %ECMXF_CMD_F_FETCH command @h: @h is async
 * and @f its *_GET partner in the command table, with no data.
 */
static int ecmxf_check_fetch(const struct ecmxf_cmd_header *h,
			     const struct ecmxf_cmd_header *f)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(h->code);

	if (!ci || !ecmxf_cmd_is_async(h->code, h->param) ||
	    ci->partner != f->code)
		return -EINVAL;
	if (f->padding || f->reserved || f->len ||
	    !ecmxf_rsv_valid(f->code, f->rsv_word))
		return -EINVAL;
	return 0;
}

/*
 * Checks of a command that do not depend on the device state.  @allowed:
 * the %ECMXF_CMD_F_* input flags of the ioctl; @fetch is the result
 * fetch's header with %ECMXF_CMD_F_FETCH, else must be zero.
 */
static int ecmxf_check_cmd(const struct ecmxf_cmd_header *h, u32 tx_len,
			   u64 tx_ptr, u32 rx_size, u64 rx_ptr, u32 flags,
			   u32 allowed, const struct ecmxf_cmd_header *fetch)
{
	if (h->padding || h->reserved || (flags & ~allowed) ||
	    !ecmxf_rsv_valid(h->code, h->rsv_word))
		return -EINVAL;
	if (flags & ECMXF_CMD_F_FETCH) {
		if (ecmxf_check_fetch(h, fetch))
			return -EINVAL;
	} else if (memchr_inv(fetch, 0, sizeof(*fetch))) {
		return -EINVAL;
	}
	if (tx_len > ECMXF_DATA_MAX || (tx_len && !tx_ptr) ||
	    (rx_size && !rx_ptr))
		return -EINVAL;
	switch (h->code) {
	case ECMXF_CMD_ASYNCCMD_RESET:
	case ECMXF_CMD_WARM_RESET:
		return -EINVAL;		/* ECMXF_IOC_RESET only */
	case ECMXF_CMD_SPI_RECONFIG_OP:
		if (!ecmxf_data_size_valid(h->len) || tx_len > h->len)
			return -EINVAL;
		break;
	case ECMXF_CMD_CRC_TYPE_SET:
		if (h->param > ECMXF_CHECK_CRC32)
			return -EINVAL;
		break;
	default:
		break;
	}
	return 0;
}

/* The engine's header of the command @h from userspace. */
static void ecmxf_hdr_from_user(struct ecmxf_cmd_hdr *d,
				const struct ecmxf_cmd_header *h)
{
	memcpy(d->data, h->data, sizeof(d->data));
	d->reserved = h->rsv_word;
	d->control = h->control;
	d->code = h->code;
	d->param = h->param;
	d->len = h->len;
	d->int_clear = h->int_clear;
	memcpy(d->gpio_int_clear, h->gpio_int_clear, sizeof(d->gpio_int_clear));
	memcpy(d->gpio_out, h->gpio_out, sizeof(d->gpio_out));
}

/* A request for command @h, data copied from @tx_ptr. */
static struct ecmxf_req *ecmxf_req_new(struct ecmxf_client *c,
				       enum ecmxf_req_kind kind,
				       const struct ecmxf_cmd_header *h,
				       u64 tx_ptr, u32 tx_len, u32 rx_size,
				       u32 timeout_us, u32 flags,
				       const struct ecmxf_cmd_header *fetch)
{
	const struct ecmxf_cmd_info *ci = ecmxf_cmd_lookup(h->code);
	struct ecmxf_req *req;
	u64 timeout_ns;

	req = kzalloc(sizeof(*req), GFP_KERNEL);
	if (!req)
		return ERR_PTR(-ENOMEM);
	if (tx_len && copy_from_user(req->tx, u64_to_user_ptr(tx_ptr), tx_len)) {
		kfree(req);
		return ERR_PTR(-EFAULT);
	}
	INIT_LIST_HEAD(&req->node);
	init_completion(&req->done);
	req->client = c;
	req->kind = kind;
	req->state = ECMXF_RS_QUEUED;

	ecmxf_hdr_from_user(&req->x.hdr, h);
	req->x.tx_data = req->tx;
	req->x.tx_len = (u16)tx_len;
	req->x.rx_buf = req->rx;
	req->x.rx_size = (u16)min_t(u32, rx_size, ECMXF_DATA_MAX);
	if (flags & ECMXF_CMD_F_NO_AUTO_CLEAR)
		req->x.flags |= ECMXF_XF_NO_AUTO_CLEAR;
	req->x.status = -EINPROGRESS;
	if (fetch) {
		/* the answer wanted is the fetch's; the command's own is empty */
		ecmxf_hdr_from_user(&req->fx.hdr, fetch);
		req->fx.rx_buf = req->x.rx_buf;
		req->fx.rx_size = req->x.rx_size;
		req->fx.flags = req->x.flags;
		req->fx.status = -EINPROGRESS;
		req->x.rx_buf = NULL;
		req->x.rx_size = 0;
		req->x.fetch = &req->fx;
	}

	/* counted from the ioctl: time in the queue counts too */
	timeout_ns = timeout_us ? (u64)timeout_us * NSEC_PER_USEC :
		     (u64)(ci ? ci->timeout_ms : 100) * NSEC_PER_MSEC;
	req->deadline_ns = ktime_get_ns() + timeout_ns;
	return req;
}

static void ecmxf_rsp_to_user(struct ecmxf_rsp_header *u,
			      const struct ecmxf_rsp_hdr *h)
{
	memset(u, 0, sizeof(*u));
	u->crc_err_cnt = h->crc_err_cnt;
	u->wkc_err_cnt = h->wkc_err_cnt;
	u->tx_fifo_cnt = h->tx_fifo_cnt;
	u->rx_fifo_cnt = h->rx_fifo_cnt;
	u->ecat_state = h->ecat_state;
	u->err_status = h->err_status;
	u->ecm_status = h->ecm_status;
	u->index = h->index;
	u->code = h->code;
	u->ret = h->ret;
	u->len = h->len;
	u->int_flags = h->int_flags;
	memcpy(u->gpio_int_flag, h->gpio_int_flag, sizeof(u->gpio_int_flag));
	memcpy(u->gpio_in, h->gpio_in, sizeof(u->gpio_in));
}

/*
 * Checks that need the device state, then queue @req on its file.
 * Return: 0, or a negative errno (@req is then not queued).
 */
static int ecmxf_queue_req(struct ecmxf_client *c, struct ecmxf_req *req)
{
	struct ecmxf_dev *edev = c->edev;
	const struct ecmxf_cmd_hdr *h = &req->x.hdr;
	enum ecmxf_perm perm[4] = {
		ecmxf_cmd_perm(h->code, h->param, req->tx, req->x.tx_len),
		ecmxf_hdr_perm(h),
	};
	unsigned int i, n = 2;
	int ret = 0;

	/* a result fetch is a command of its own class */
	if (req->x.fetch) {
		perm[n++] = ecmxf_cmd_perm(req->fx.hdr.code, req->fx.hdr.param,
					   NULL, 0);
		perm[n++] = ecmxf_hdr_perm(&req->fx.hdr);
	}
	for (i = 0; i < n; i++)
		if (perm[i] != ECMXF_PERM_QUERY)
			req->exclusive = true;

	mutex_lock(&edev->lock);
	if (edev->gone) {
		ret = -ENODEV;
		goto out_unlock;
	}
	for (i = 0; i < n && !ret; i++)
		ret = ecmxf_check_perm(c, perm[i]);
	if (ret)
		goto out_unlock;
	/* while the rings exist, the pump owns the FIFO exchange */
	if (ecmxf_req_refused(edev, req)) {
		ret = -EBUSY;
		goto out_unlock;
	}
	if (req->x.tx_len > edev->chip.data_size) {
		ret = -EINVAL;
		goto out_unlock;
	}
	if (req->kind == ECMXF_REQ_SUBMIT) {
		if (c->in_flight >= ecmxf_param_queue_depth) {
			ret = -EAGAIN;
			goto out_unlock;
		}
		c->in_flight++;
	}
	list_add_tail(&req->node, &c->queue);
out_unlock:
	mutex_unlock(&edev->lock);
	/* after the unlock: the worker it wakes takes the lock first thing */
	if (!ret)
		ecmxf_worker_kick(edev);
	return ret;
}

/*
 * Wait for a sync or reset request.  On a signal: a request not yet
 * taken by the worker is withdrawn (-ERESTARTSYS: nothing was sent, the
 * call may restart); one already sent is left to the worker to free
 * (-EINTR).  Return: 0 when @req is done and still ours.
 */
static int ecmxf_wait_req(struct ecmxf_dev *edev, struct ecmxf_req *req)
{
	int ret = wait_for_completion_interruptible(&req->done);

	if (!ret)
		return 0;
	mutex_lock(&edev->lock);
	if (req->state == ECMXF_RS_DONE) {
		ret = 0;
	} else if (req->state == ECMXF_RS_QUEUED) {
		list_del_init(&req->node);
		kfree(req);
		ret = -ERESTARTSYS;
	} else {
		req->abandoned = true;
		ret = -EINTR;
	}
	mutex_unlock(&edev->lock);
	return ret;
}

static long ecmxf_ioc_cmd(struct ecmxf_client *c, void __user *argp)
{
	struct ecmxf_dev *edev = c->edev;
	const struct ecmxf_xfer *ans;
	struct ecmxf_req *req;
	struct ecmxf_cmd cmd;
	bool fetch;
	u32 n;
	int ret;

	if (copy_from_user(&cmd, argp, sizeof(cmd)))
		return -EFAULT;
	ret = ecmxf_check_cmd(&cmd.hdr, cmd.tx_len, cmd.tx_ptr, cmd.rx_size,
			      cmd.rx_ptr, cmd.flags,
			      ECMXF_CMD_F_NO_AUTO_CLEAR | ECMXF_CMD_F_FETCH,
			      &cmd.fetch);
	fetch = cmd.flags & ECMXF_CMD_F_FETCH;
	if (ret)
		return ret;
	req = ecmxf_req_new(c, ECMXF_REQ_SYNC, &cmd.hdr, cmd.tx_ptr,
			    cmd.tx_len, cmd.rx_size, cmd.timeout_us, cmd.flags,
			    fetch ? &cmd.fetch : NULL);
	if (IS_ERR(req))
		return PTR_ERR(req);
	ret = ecmxf_queue_req(c, req);
	if (ret) {
		kfree(req);
		return ret;
	}
	ret = ecmxf_wait_req(edev, req);
	if (ret)
		return ret;
	/*
	 * the chip went away while the command waited, or the worker refused
	 * it (a claim taken meanwhile): as when it is queued
	 */
	if (req->x.status == -ENODEV || req->refused) {
		ret = req->x.status;
		kfree(req);
		return ret;
	}

	/* the outcome is the fetch's once it ran (ecmxf_done()) */
	ans = req->fetched ? &req->fx : &req->x;
	n = min_t(u32, ans->rx_len, cmd.rx_size);
	ecmxf_rsp_to_user(&cmd.rsp, &ans->rsp);
	cmd.rx_len = n;
	cmd.status = req->x.status;
	if (req->fetched)
		cmd.flags |= ECMXF_CMD_F_FETCHED;
	ret = 0;
	if (n && copy_to_user(u64_to_user_ptr(cmd.rx_ptr), req->rx, n))
		ret = -EFAULT;
	else if (copy_to_user(argp, &cmd, sizeof(cmd)))
		ret = -EFAULT;
	kfree(req);
	return ret;
}

static long ecmxf_ioc_submit(struct ecmxf_client *c, void __user *argp)
{
	struct ecmxf_submit sub;
	struct ecmxf_req *req;
	bool fetch;
	int ret;

	if (copy_from_user(&sub, argp, sizeof(sub)))
		return -EFAULT;
	ret = ecmxf_check_cmd(&sub.hdr, sub.tx_len, sub.tx_ptr, 0, 0,
			      sub.flags,
			      ECMXF_CMD_F_NO_AUTO_CLEAR | ECMXF_CMD_F_FETCH,
			      &sub.fetch);
	fetch = sub.flags & ECMXF_CMD_F_FETCH;
	if (ret)
		return ret;
	/* the answer travels in the completion record, never to a pointer */
	if (sub.reserved_ptr || sub.rx_size > ECMXF_DATA_SIZE_MAX)
		return -EINVAL;
	req = ecmxf_req_new(c, ECMXF_REQ_SUBMIT, &sub.hdr, sub.tx_ptr,
			    sub.tx_len, sub.rx_size, sub.timeout_us, sub.flags,
			    fetch ? &sub.fetch : NULL);
	if (IS_ERR(req))
		return PTR_ERR(req);
	req->cookie = sub.cookie;
	ret = ecmxf_queue_req(c, req);
	if (ret)
		kfree(req);
	return ret;
}

static long ecmxf_ioc_reset(struct ecmxf_client *c, void __user *argp)
{
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_cmd_header h;
	struct ecmxf_reset r;
	struct ecmxf_req *req;
	enum ecmxf_perm perm;
	int ret;

	if (copy_from_user(&r, argp, sizeof(r)))
		return -EFAULT;
	if (memchr_inv(r.reserved, 0, sizeof(r.reserved)))
		return -EINVAL;
	memset(&h, 0, sizeof(h));
	switch (r.flags) {
	case ECMXF_RESET_F_ASYNC_CMD:
		/* without a bit it asks for nothing (a command error) */
		if (!r.param ||
		    (r.param & ~(ECMXF_RESET_ASYNC_CLEAR_BUSY |
				 ECMXF_RESET_ASYNC_SKIP_LINK |
				 ECMXF_RESET_ASYNC_ABANDON)))
			return -EINVAL;
		h.code = ECMXF_CMD_ASYNCCMD_RESET;
		h.param = (u8)r.param;
		perm = ECMXF_PERM_CHIP;
		break;
	case ECMXF_RESET_F_WARM:
		if (r.param)
			return -EINVAL;
		h.code = ECMXF_CMD_WARM_RESET;
		perm = ECMXF_PERM_ADMIN;
		break;
	case ECMXF_RESET_F_LINK:
		if (r.param)
			return -EINVAL;
		h.code = ECMXF_CMD_INFO_UPDATE_OP;	/* not sent */
		perm = ECMXF_PERM_CHIP;
		break;
	default:
		return -EINVAL;
	}
	req = ecmxf_req_new(c, ECMXF_REQ_RESET, &h, 0, 0, 0, r.timeout_us, 0,
			    NULL);
	if (IS_ERR(req))
		return PTR_ERR(req);
	req->reset_flags = r.flags;
	req->reset_param = r.param;
	req->exclusive = true;

	mutex_lock(&edev->lock);
	ret = edev->gone ? -ENODEV : ecmxf_check_perm(c, perm);
	if (!ret)
		list_add_tail(&req->node, &edev->resets);
	mutex_unlock(&edev->lock);
	if (ret) {
		kfree(req);
		return ret;
	}
	ecmxf_worker_kick(edev);
	ret = ecmxf_wait_req(edev, req);
	if (ret)
		return ret;
	ret = req->x.status;
	kfree(req);
	return ret;
}

static long ecmxf_ioc_devinfo(struct ecmxf_client *c, void __user *argp)
{
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_devinfo d;

	memset(&d, 0, sizeof(d));
	d.uapi_version = ECMXF_UAPI_VERSION;
	mutex_lock(&edev->lock);
	if (edev->irq.int0_irq)
		d.flags |= ECMXF_DEVINFO_F_INT0;
	if (edev->irq.int1_irq)
		d.flags |= ECMXF_DEVINFO_F_INT1;
	if (edev->chip.fw_valid)
		d.flags |= ECMXF_DEVINFO_F_FW_VERSION;
	if (edev->claim.holder)
		d.flags |= ECMXF_DEVINFO_F_CLAIMED;
	if (edev->claim.holder == c)
		d.flags |= ECMXF_DEVINFO_F_CLAIM_MINE;
	if (edev->pdo.rings)
		d.flags |= ECMXF_DEVINFO_F_RINGS;
	d.flags |= ECMXF_DEVINFO_F_CLAIM_EXCLUSIVE;
	d.data_size = edev->chip.data_size;
	d.check_type = edev->chip.check;
	d.fw_version = edev->chip.fw_version;
	memcpy(d.fw_info, edev->chip.fw_info, sizeof(d.fw_info));
	d.slave_count = edev->chip.slave_count;
	d.max_open = ecmxf_param_max_open;
	d.open_count = edev->open_count;
	d.claim_pid = edev->claim.pid ? pid_vnr(edev->claim.pid) : 0;
	d.queue_depth = ecmxf_param_queue_depth;
	d.spi_speed_hz = edev->spi ? edev->spi->max_speed_hz : 0;
	mutex_unlock(&edev->lock);
	return copy_to_user(argp, &d, sizeof(d)) ? -EFAULT : 0;
}

/*
 * The claim's thread group becomes @pid (a reference the device takes
 * over, or NULL); &ecmxf_dev.lock held.  Readers that do not take that
 * lock (sysfs) see the old or the new one whole
 * (ecmxf_claim_pid_vnr()).
 */
static void ecmxf_claim_pid_set(struct ecmxf_dev *edev, struct pid *pid)
{
	struct pid *old;

	lockdep_assert_held(&edev->lock);
	spin_lock(&edev->claim.pid_lock);
	old = edev->claim.pid;
	edev->claim.pid = pid;
	spin_unlock(&edev->claim.pid_lock);
	put_pid(old);
}

/**
 * ecmxf_claim_pid_vnr() - the claim holder's process, without &ecmxf_dev.lock
 * @edev: the device
 *
 * For readers that any local user may run (sysfs): they take the claim's
 * own spinlock, never the mutex the real-time worker takes.
 *
 * Return: its pid in the caller's pid namespace, 0 when none.
 */
pid_t ecmxf_claim_pid_vnr(struct ecmxf_dev *edev)
{
	struct pid *pid;
	pid_t v;

	spin_lock(&edev->claim.pid_lock);
	pid = get_pid(edev->claim.pid);
	spin_unlock(&edev->claim.pid_lock);
	v = pid ? pid_vnr(pid) : 0;
	put_pid(pid);
	return v;
}

static long ecmxf_ioc_claim(struct ecmxf_client *c)
{
	struct ecmxf_dev *edev = c->edev;
	int ret = 0;

	/*
	 * The claim drives the outputs: a read-only opener must not hold it
	 * (nor keep others from it).
	 */
	if (!c->writable)
		return -EPERM;
	mutex_lock(&edev->lock);
	if (edev->claim.holder && edev->claim.holder != c) {
		ret = -EBUSY;
	} else if (!edev->claim.holder) {
		edev->claim.holder = c;
		ecmxf_claim_pid_set(edev, get_pid(task_tgid(current)));
	}
	mutex_unlock(&edev->lock);
	return ret;
}

/*
 * Give the claim back if @c holds it, rings and all; lock held.  *@old
 * gets the rings' reference, to drop with ecmxf_rings_put() after
 * unlocking (NULL when there is none).
 */
static bool ecmxf_unclaim(struct ecmxf_client *c, struct ecmxf_rings **old)
{
	struct ecmxf_dev *edev = c->edev;

	*old = NULL;
	if (edev->claim.holder != c)
		return false;
	*old = ecmxf_rings_teardown(edev);
	edev->claim.holder = NULL;
	ecmxf_claim_pid_set(edev, NULL);
	return true;
}

/*
 * ECMXF_IOC_CLAIM_BREAK: an operator takes the claim from a holder that
 * hangs, to stop the machine.  The holder's rings stop (-ECONNABORTED:
 * %ECMXF_RING_S_ERROR, its poll()ers woken with EPOLLERR) and go; the
 * claim passes to @c in the same critical section, so that the old holder
 * cannot take it back, nor send anything but queries, until @c releases
 * it.  Needs a file open for writing and CAP_SYS_ADMIN.
 */
static long ecmxf_ioc_claim_break(struct ecmxf_client *c)
{
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_rings *old = NULL;
	pid_t was = 0;
	int ret = 0;

	if (!c->writable || !capable(CAP_SYS_ADMIN))
		return -EPERM;
	mutex_lock(&edev->lock);
	if (!edev->claim.holder) {
		ret = -ENOENT;
	} else if (edev->claim.holder != c) {
		was = pid_nr(edev->claim.pid);
		ecmxf_rings_stop(edev, -ECONNABORTED);
		old = ecmxf_rings_teardown(edev);
		edev->claim.holder = c;
		ecmxf_claim_pid_set(edev, get_pid(task_tgid(current)));
	}
	mutex_unlock(&edev->lock);
	ecmxf_rings_put(old);
	if (was)
		dev_warn(&edev->dev, "claim of pid %d broken by pid %d\n", was,
			 task_tgid_nr(current));
	return ret;
}

/*
 * One command from the kernel itself (RING_SETUP's questions), queued on
 * @c like an ECMXF_IOC_CMD.  @rx gets up to @rx_size data bytes.
 * Return: the command's status, -ENODATA for a command error (the chip
 * has no PDO configuration), or the queueing/waiting errno.
 */
static int ecmxf_kernel_cmd(struct ecmxf_client *c, u8 code, u8 param,
			    u8 *rx, u32 rx_size, u8 *ret_val)
{
	struct ecmxf_cmd_header h;
	struct ecmxf_req *req;
	int ret;

	memset(&h, 0, sizeof(h));
	h.code = code;
	h.param = param;
	h.control = ECMXF_CTL_CLR_CMD_ERR;
	req = ecmxf_req_new(c, ECMXF_REQ_SYNC, &h, 0, 0, rx_size, 0, 0, NULL);
	if (IS_ERR(req))
		return PTR_ERR(req);
	ret = ecmxf_queue_req(c, req);
	if (ret) {
		kfree(req);
		return ret;
	}
	ret = ecmxf_wait_req(c->edev, req);
	if (ret)
		return ret;
	ret = req->x.status;
	if (!ret && (req->x.rsp.err_status & ECMXF_ERR_CMD))
		ret = -ENODATA;
	if (!ret && rx_size && req->x.rx_len < rx_size)
		ret = -EPROTO;
	if (!ret) {
		if (rx_size)
			memcpy(rx, req->rx, rx_size);
		*ret_val = req->x.rsp.ret;
	}
	kfree(req);
	return ret;
}

static long ecmxf_ioc_ring_setup(struct ecmxf_client *c, void __user *argp)
{
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_ring_setup rs;
	struct ecmxf_rings *r = NULL, *old = NULL;
	u16 sizes[2];
	u8 depths[2], v[2], rv;
	int ret, i;

	if (copy_from_user(&rs, argp, sizeof(rs)))
		return -EFAULT;
	if (!ecmxf_ring_setup_valid(&rs))
		return -EINVAL;
	mutex_lock(&edev->lock);
	ret = edev->claim.holder != c ? -EPERM : 0;
	mutex_unlock(&edev->lock);
	if (ret)
		return ret;

	/* the frame sizes and depths in force now */
	for (i = 0; i < 2; i++) {
		ret = ecmxf_kernel_cmd(c, ECMXF_CMD_FIFO_PACK_SIZE_GET, (u8)i,
				       v, sizeof(v), &rv);
		if (ret)
			return ret;
		sizes[i] = v[0] | v[1] << 8;
	}
	ret = ecmxf_kernel_cmd(c, ECMXF_CMD_FIFO_GET_RX_CNT, 0, NULL, 0,
			       &depths[0]);
	if (!ret)
		ret = ecmxf_kernel_cmd(c, ECMXF_CMD_FIFO_GET_TX_CNT, 0, NULL,
				       0, &depths[1]);
	if (ret)
		return ret;

	ret = ecmxf_rings_create(edev, &rs, sizes, depths, &r);
	if (ret)
		return ret;
	mutex_lock(&edev->lock);
	/* the claim may have gone meanwhile (RELEASE from another thread) */
	ret = edev->gone ? -ENODEV : edev->claim.holder != c ? -EPERM : 0;
	if (!ret) {
		/* new rings replace the old ones (whose mappings stay memory) */
		old = ecmxf_rings_teardown(edev);
		edev->pdo.rings = r;
		c->rings_lost = false;
		r = NULL;
	}
	mutex_unlock(&edev->lock);
	if (!ret)
		ecmxf_worker_kick(edev);
	/* freed (when nothing maps them) after the lock: &ecmxf_dev.lock */
	ecmxf_rings_put(old);
	if (ret) {
		ecmxf_rings_put(r);
		return ret;
	}
	memset(rs.reserved, 0, sizeof(rs.reserved));
	return copy_to_user(argp, &rs, sizeof(rs)) ? -EFAULT : 0;
}

static long ecmxf_ioctl(struct file *f, unsigned int cmd, unsigned long arg)
{
	struct ecmxf_client *c = f->private_data;
	struct ecmxf_dev *edev = c->edev;
	void __user *argp = (void __user *)arg;
	struct ecmxf_counters k;
	struct ecmxf_rings *old;
	bool gone;
	long ret;

	mutex_lock(&edev->lock);
	gone = edev->gone;
	mutex_unlock(&edev->lock);
	if (gone)
		return -ENODEV;

	switch (cmd) {
	case ECMXF_IOC_GET_VERSION:
		return put_user((u32)ECMXF_UAPI_VERSION, (u32 __user *)argp);
	case ECMXF_IOC_DEVINFO:
		return ecmxf_ioc_devinfo(c, argp);
	case ECMXF_IOC_CMD:
		return ecmxf_ioc_cmd(c, argp);
	case ECMXF_IOC_SUBMIT:
		return ecmxf_ioc_submit(c, argp);
	case ECMXF_IOC_COUNTERS:
		ecmxf_get_counters(edev, &k);
		return copy_to_user(argp, &k, sizeof(k)) ? -EFAULT : 0;
	case ECMXF_IOC_RESET:
		return ecmxf_ioc_reset(c, argp);
	case ECMXF_IOC_CLAIM:
		return ecmxf_ioc_claim(c);
	case ECMXF_IOC_RELEASE:
		mutex_lock(&edev->lock);
		ret = ecmxf_unclaim(c, &old) ? 0 : -EPERM;
		mutex_unlock(&edev->lock);
		ecmxf_rings_put(old);
		return ret;
	case ECMXF_IOC_RING_SETUP:
		return ecmxf_ioc_ring_setup(c, argp);
	case ECMXF_IOC_CLAIM_BREAK:
		return ecmxf_ioc_claim_break(c);
	default:
		return -ENOTTY;
	}
}

/* Take the oldest completion of @c, or NULL; lock held. */
static struct ecmxf_req *ecmxf_take_done(struct ecmxf_client *c)
{
	struct ecmxf_req *req;

	req = list_first_entry_or_null(&c->done, struct ecmxf_req, node);
	if (req)
		list_del_init(&req->node);
	return req;
}

/*
 * Deliver one completion record to @buf, the response data inline (the
 * rest of the data array zeroed): read() writes nothing but its buffer.
 * The outcome is the result fetch's once it ran (ecmxf_done()).  On a
 * fault the record goes back to the head of the list.
 */
static int ecmxf_deliver(struct ecmxf_client *c, struct ecmxf_req *req,
			 char __user *buf)
{
	struct ecmxf_completion __user *u = (void __user *)buf;
	const struct ecmxf_xfer *ans = req->fetched ? &req->fx : &req->x;
	u32 flags = req->fetched ? ECMXF_CMD_F_FETCHED : 0;
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_rsp_header rsp;
	u32 n = ans->rx_len;

	/* field by field: the whole record is too large for the stack */
	ecmxf_rsp_to_user(&rsp, &ans->rsp);
	if (put_user(req->cookie, &u->cookie) ||
	    put_user(req->x.status, &u->status) ||
	    put_user(n, &u->rx_len) ||
	    copy_to_user(&u->rsp, &rsp, sizeof(rsp)) ||
	    put_user(flags, &u->flags) ||
	    clear_user(u->reserved, sizeof(u->reserved)) ||
	    (n && copy_to_user(u->data, req->rx, n)) ||
	    clear_user(u->data + n, sizeof(u->data) - n)) {
		mutex_lock(&edev->lock);
		list_add(&req->node, &c->done);
		mutex_unlock(&edev->lock);
		return -EFAULT;
	}
	mutex_lock(&edev->lock);
	c->in_flight--;
	mutex_unlock(&edev->lock);
	kfree(req);
	return 0;
}

static ssize_t ecmxf_read(struct file *f, char __user *buf, size_t count,
			  loff_t *ppos)
{
	struct ecmxf_client *c = f->private_data;
	struct ecmxf_dev *edev = c->edev;
	const size_t rec = sizeof(struct ecmxf_completion);
	struct ecmxf_req *req;
	ssize_t done = 0;
	bool gone;
	int ret;

	if (count < rec)
		return -EINVAL;
	while (count - done >= rec) {
		mutex_lock(&edev->lock);
		req = ecmxf_take_done(c);
		gone = edev->gone;
		mutex_unlock(&edev->lock);
		if (!req) {
			if (done)
				break;
			if (gone)
				return -ENODEV;
			if (f->f_flags & O_NONBLOCK)
				return -EAGAIN;
			ret = wait_event_interruptible(c->wq,
						       !list_empty_careful(&c->done) ||
						       READ_ONCE(edev->gone));
			if (ret)
				return ret;
			continue;
		}
		ret = ecmxf_deliver(c, req, buf + done);
		if (ret)
			return done ? done : ret;
		done += rec;
	}
	return done;
}

static __poll_t ecmxf_poll(struct file *f, poll_table *wait)
{
	struct ecmxf_client *c = f->private_data;
	struct ecmxf_dev *edev = c->edev;
	__poll_t mask = 0;
	__poll_t ring_events = EPOLLRDBAND | EPOLLOUT | EPOLLWRNORM;

	poll_wait(f, &c->wq, wait);
	mutex_lock(&edev->lock);
	if (!list_empty(&c->done))
		mask |= EPOLLIN | EPOLLRDNORM;
	if (edev->claim.holder == c && edev->pdo.rings)
		mask |= ecmxf_rings_poll(edev);
	else if (c->rings_lost && (poll_requested_events(wait) & ring_events))
		mask |= EPOLLERR;
	if (edev->gone)
		mask |= EPOLLERR | EPOLLHUP;
	mutex_unlock(&edev->lock);
	return mask;
}

/* Files a read-only opener may take (&ecmxf_dev.open_readonly). */
static unsigned int ecmxf_readonly_slots(void)
{
	unsigned int max = ecmxf_param_max_open;

	return max > 2 * ECMXF_WRITER_SLOTS ? max - ECMXF_WRITER_SLOTS :
					       max - max / 2;
}

static int ecmxf_open(struct inode *inode, struct file *f)
{
	struct ecmxf_dev *edev = container_of(inode->i_cdev, struct ecmxf_dev,
					      cdev);
	struct ecmxf_client *c;
	int ret = 0;

	c = kzalloc(sizeof(*c), GFP_KERNEL);
	if (!c)
		return -ENOMEM;
	c->edev = edev;
	INIT_LIST_HEAD(&c->queue);
	INIT_LIST_HEAD(&c->done);
	init_waitqueue_head(&c->wq);
	c->writable = !!(f->f_mode & FMODE_WRITE);

	mutex_lock(&edev->lock);
	if (edev->gone)
		ret = -ENODEV;
	else if (edev->open_count >= ecmxf_param_max_open)
		ret = -EMFILE;
	else if (!c->writable &&
		 edev->open_readonly >= ecmxf_readonly_slots())
		ret = -EMFILE;
	if (!ret) {
		edev->open_count++;
		if (!c->writable)
			edev->open_readonly++;
		list_add_tail(&c->node, &edev->clients);
	}
	mutex_unlock(&edev->lock);
	if (ret) {
		kfree(c);
		return ret;
	}
	f->private_data = c;
	return stream_open(inode, f);
}

static int ecmxf_release(struct inode *inode, struct file *f)
{
	struct ecmxf_client *c = f->private_data;
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_req *req, *tmp;
	struct ecmxf_rings *old;

	mutex_lock(&edev->lock);
	list_del(&c->node);
	edev->open_count--;
	if (!c->writable)
		edev->open_readonly--;
	ecmxf_unclaim(c, &old);
	list_for_each_entry_safe(req, tmp, &c->queue, node) {
		list_del(&req->node);
		kfree(req);
	}
	list_for_each_entry_safe(req, tmp, &c->done, node) {
		list_del(&req->node);
		kfree(req);
	}
	/* in the engine: the worker frees them when they finish */
	if (edev->cur_req && edev->cur_req->client == c)
		edev->cur_req->client = NULL;
	if (edev->async_req && edev->async_req->client == c)
		edev->async_req->client = NULL;
	mutex_unlock(&edev->lock);
	ecmxf_rings_put(old);
	kfree(c);
	return 0;
}

/**
 * ecmxf_chrdev_fail_all() - the chip is gone: end every waiting request
 * @edev: the device, worker stopped
 * @status: the errno the requests finish with (-ENODEV)
 *
 * Queued commands and resets finish with @status; readers and pollers
 * wake up and see the device gone.
 */
void ecmxf_chrdev_fail_all(struct ecmxf_dev *edev, int status)
{
	struct ecmxf_req *req, *tmp;
	struct ecmxf_client *c;

	mutex_lock(&edev->lock);
	list_for_each_entry(c, &edev->clients, node) {
		list_for_each_entry_safe(req, tmp, &c->queue, node) {
			list_del_init(&req->node);
			ecmxf_req_finish(edev, req, status);
		}
	}
	list_for_each_entry_safe(req, tmp, &edev->resets, node) {
		list_del_init(&req->node);
		ecmxf_req_finish(edev, req, status);
	}
	list_for_each_entry(c, &edev->clients, node)
		wake_up_interruptible_poll(&c->wq, EPOLLERR | EPOLLHUP);
	mutex_unlock(&edev->lock);
}

/*
 * mmap() of a ring: the claim holder, MAP_SHARED, offset ECMXF_RING_OFF_OUT
 * or ECMXF_RING_OFF_IN, at most mmap_size bytes.  The pages go in after
 * the lock (&ecmxf_dev.lock), with a reference taken under it: rings
 * replaced or released meanwhile are mapped as they are, like a mapping
 * made just before.
 */
static int ecmxf_mmap(struct file *f, struct vm_area_struct *vma)
{
	struct ecmxf_client *c = f->private_data;
	struct ecmxf_dev *edev = c->edev;
	struct ecmxf_rings *r = NULL;
	int ret = 0;

	mutex_lock(&edev->lock);
	if (edev->gone)
		ret = -ENODEV;
	else if (edev->claim.holder != c)
		ret = -EPERM;
	else if (!edev->pdo.rings)
		ret = -EINVAL;
	else
		r = edev->pdo.rings;
	if (r)
		kref_get(&r->ref);
	mutex_unlock(&edev->lock);
	return r ? ecmxf_rings_mmap(r, vma) : ret;
}

/* The file operations of /dev/ecmxfN. */
const struct file_operations ecmxf_fops = {
	.owner = THIS_MODULE,
	.open = ecmxf_open,
	.release = ecmxf_release,
	.read = ecmxf_read,
	.poll = ecmxf_poll,
	.mmap = ecmxf_mmap,
	.unlocked_ioctl = ecmxf_ioctl,
	.compat_ioctl = compat_ptr_ioctl,
};
