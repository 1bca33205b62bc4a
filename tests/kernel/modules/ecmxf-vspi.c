// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-vspi.c - test-only virtual SPI controller for the ecmxf QEMU tests
 *
 * Registers an spi_controller with one device (modalias "ecm-xf", so that
 * ecmxf.ko binds to it), and a two-line gpio_chip with an irq_chip whose
 * lines are the chip's INT0 ("ready", active high) and INT1 (events,
 * active low), handed to the device through a gpiod lookup table as
 * "int0" and "int1" (the GPIO form of the binding).  With int1=irq-level
 * or int1=irq-edge, INT1 is the device's interrupt instead
 * (spi_board_info.irq, level low or falling edge; the board-code
 * interrupt form; x86 kernels without CONFIG_OF cannot give named
 * interrupts).  The irq_chip emulates level lines too: an unmasked level
 * interrupt fires again for as long as its line is at the active level.
 * Every SPI transfer goes to a bridge process through /dev/ecmxf-vspi
 * (see ecmxf-vspi.h); the bridge also sets the line levels.
 * A transfer the bridge does not answer within timeout_ms fails with
 * -ETIMEDOUT; without a bridge, transfers fail at once with -ENOTCONN.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/completion.h>
#include <linux/fs.h>
#include <linux/gpio/driver.h>
#include <linux/gpio/machine.h>
#include <linux/interrupt.h>
#include <linux/irq.h>
#include <linux/jiffies.h>
#include <linux/miscdevice.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/platform_device.h>
#include <linux/poll.h>
#include <linux/property.h>
#include <linux/slab.h>
#include <linux/spi/spi.h>
#include <linux/string.h>
#include <linux/uaccess.h>
#include <linux/wait.h>
#include <linux/workqueue.h>

#include "ecmxf-vspi.h"
#include "ecmxf-vspi-compat.h"

#define VSPI_NAME	"ecmxf-vspi"
#define VSPI_NLINES	2

static char *int1 = "gpio";
module_param(int1, charp, 0444);
MODULE_PARM_DESC(int1,
		 "INT1 to the device as: gpio (lookup table, default), irq-level (spi_board_info.irq, level low), irq-edge (spi_board_info.irq, falling edge), irq-none (spi_board_info.irq without a trigger type: ecmxf must refuse it)");

static char *modalias = "ecm-xf";
module_param(modalias, charp, 0444);
MODULE_PARM_DESC(modalias,
		 "the SPI device's modalias: ecm-xf (default), ecm-xfl, ecm-xfu, ecm-xm");

static int data_size_prop = -1;
module_param(data_size_prop, int, 0444);
MODULE_PARM_DESC(data_size_prop,
		 "give the device the property nextw,data-size with this value (software node; default -1: none)");

static char *check_type_prop = "";
module_param(check_type_prop, charp, 0444);
MODULE_PARM_DESC(check_type_prop,
		 "give the device the property nextw,check-type with this string (software node; default empty: none)");

static unsigned int timeout_ms = 2000;
module_param(timeout_ms, uint, 0644);
MODULE_PARM_DESC(timeout_ms,
		 "time the bridge has to answer one transfer (default 2000)");

/**
 * enum vspi_state - where the current transfer is
 * @VSPI_IDLE: no transfer
 * @VSPI_PENDING: waiting for the bridge's read()
 * @VSPI_READ: read by the bridge, waiting for its write()
 */
enum vspi_state {
	VSPI_IDLE,
	VSPI_PENDING,
	VSPI_READ,
};

/**
 * struct vspi - the virtual controller
 * @ctlr: the SPI controller
 * @spi: its one device
 * @lookup: the gpiod lookup table of @spi
 * @gc: the INT0/INT1 gpio_chip
 * @misc: /dev/ecmxf-vspi
 * @lock: protects @state, @len, @result, @buf and @open
 * @state: &enum vspi_state
 * @len: length of the current transfer
 * @result: 0, or the error the bridge side ended the transfer with
 * @buf: MOSI bytes, then the MISO bytes of the current transfer
 * @open: a bridge has the device open
 * @bridge_wq: the bridge's read() and poll() wait here
 * @done: completed when the bridge answered (or left)
 * @line_lock: serialises the level changes of the ioctl
 * @levels: line levels, bit n = line n
 * @irq_enabled: bit n: the interrupt of line n is unmasked
 * @irq_type: IRQ_TYPE_* of each line
 * @level_work: raises the interrupts of unmasked level lines that are at
 *	their active level (not from irq_unmask(), which runs under the
 *	descriptor's lock)
 * @props: the device's properties (data_size_prop, check_type_prop), a
 *	terminated list
 * @swnode: the software node that carries @props
 */
struct vspi {
	struct spi_controller *ctlr;
	struct spi_device *spi;
	struct gpiod_lookup_table *lookup;
	struct gpio_chip gc;
	struct miscdevice misc;

	struct mutex lock;	/* protects the transfer fields */
	enum vspi_state state;
	unsigned int len;
	int result;
	u8 *buf;
	bool open;
	wait_queue_head_t bridge_wq;
	struct completion done;

	struct mutex line_lock;	/* serialises SET_LINES */
	unsigned long levels;
	unsigned long irq_enabled;
	unsigned int irq_type[VSPI_NLINES];
	struct work_struct level_work;
	struct property_entry props[3];
	struct software_node swnode;
};

/* ---- the SPI side ---------------------------------------------------- */

static int vspi_transfer_one(struct spi_controller *ctlr,
			     struct spi_device *spi, struct spi_transfer *t)
{
	struct vspi *v = spi_controller_get_devdata(ctlr);
	unsigned long left;
	int ret;

	if (t->len > ECMXF_VSPI_MAX_XFER)
		return -EMSGSIZE;

	mutex_lock(&v->lock);
	if (!v->open) {
		mutex_unlock(&v->lock);
		return -ENOTCONN;
	}
	if (t->tx_buf)
		memcpy(v->buf, t->tx_buf, t->len);
	else
		memset(v->buf, 0, t->len);
	v->len = t->len;
	v->result = 0;
	v->state = VSPI_PENDING;
	reinit_completion(&v->done);
	mutex_unlock(&v->lock);
	wake_up_interruptible(&v->bridge_wq);

	left = wait_for_completion_timeout(&v->done,
					   msecs_to_jiffies(timeout_ms));

	mutex_lock(&v->lock);
	if (!left && v->state != VSPI_IDLE) {
		v->state = VSPI_IDLE;
		ret = -ETIMEDOUT;
		dev_warn_ratelimited(&ctlr->dev,
				     "the bridge did not answer a %u-byte transfer within %u ms\n",
				     t->len, timeout_ms);
	} else {
		ret = v->result;
		if (!ret && t->rx_buf)
			memcpy(t->rx_buf, v->buf, t->len);
	}
	mutex_unlock(&v->lock);
	return ret;
}

static size_t vspi_max_transfer_size(struct spi_device *spi)
{
	return ECMXF_VSPI_MAX_XFER;
}

/* ---- the bridge side ------------------------------------------------- */

static struct vspi *vspi_from_file(struct file *file)
{
	return container_of(file->private_data, struct vspi, misc);
}

static int vspi_open(struct inode *inode, struct file *file)
{
	struct vspi *v = vspi_from_file(file);
	int ret = 0;

	mutex_lock(&v->lock);
	if (v->open)
		ret = -EBUSY;
	else
		v->open = true;
	mutex_unlock(&v->lock);
	return ret;
}

static int vspi_release(struct inode *inode, struct file *file)
{
	struct vspi *v = vspi_from_file(file);

	mutex_lock(&v->lock);
	v->open = false;
	if (v->state != VSPI_IDLE) {
		v->state = VSPI_IDLE;
		v->result = -ENOTCONN;
		complete(&v->done);
	}
	mutex_unlock(&v->lock);
	return 0;
}

static ssize_t vspi_read(struct file *file, char __user *ubuf, size_t count,
			 loff_t *ppos)
{
	struct vspi *v = vspi_from_file(file);
	ssize_t ret;

	for (;;) {
		mutex_lock(&v->lock);
		if (v->state == VSPI_PENDING)
			break;
		mutex_unlock(&v->lock);
		if (file->f_flags & O_NONBLOCK)
			return -EAGAIN;
		ret = wait_event_interruptible(v->bridge_wq,
					       READ_ONCE(v->state) == VSPI_PENDING);
		if (ret)
			return ret;
	}
	/* v->lock held */
	if (count < v->len) {
		ret = -EMSGSIZE;
	} else if (copy_to_user(ubuf, v->buf, v->len)) {
		ret = -EFAULT;
	} else {
		v->state = VSPI_READ;
		ret = v->len;
	}
	mutex_unlock(&v->lock);
	return ret;
}

static ssize_t vspi_write(struct file *file, const char __user *ubuf,
			  size_t count, loff_t *ppos)
{
	struct vspi *v = vspi_from_file(file);
	ssize_t ret;

	mutex_lock(&v->lock);
	if (v->state != VSPI_READ) {
		/* nothing read, or the transfer timed out meanwhile */
		ret = -ETIMEDOUT;
	} else if (count != v->len) {
		ret = -EINVAL;
	} else if (copy_from_user(v->buf, ubuf, count)) {
		ret = -EFAULT;
	} else {
		v->state = VSPI_IDLE;
		v->result = 0;
		complete(&v->done);
		ret = count;
	}
	mutex_unlock(&v->lock);
	return ret;
}

static __poll_t vspi_poll(struct file *file, poll_table *wait)
{
	struct vspi *v = vspi_from_file(file);

	poll_wait(file, &v->bridge_wq, wait);
	return READ_ONCE(v->state) == VSPI_PENDING ? EPOLLIN | EPOLLRDNORM : 0;
}

/* @line is level-triggered and at its active level */
static bool vspi_level_active(struct vspi *v, unsigned int line)
{
	unsigned int type = READ_ONCE(v->irq_type[line]);
	bool high = READ_ONCE(v->levels) & BIT(line);

	return (type == IRQ_TYPE_LEVEL_HIGH && high) ||
	       (type == IRQ_TYPE_LEVEL_LOW && !high);
}

static void vspi_raise(struct vspi *v, unsigned int line)
{
	int ret = generic_handle_domain_irq_safe(v->gc.irq.domain, line);

	if (ret)
		dev_warn_ratelimited(v->misc.this_device,
				     "cannot raise the interrupt of line %u: %d\n",
				     line, ret);
}

/*
 * @line changed to @high: raise its interrupt for an edge it wants, or
 * when a level line became active.
 */
static void vspi_line_edge(struct vspi *v, unsigned int line, bool high)
{
	unsigned int type = READ_ONCE(v->irq_type[line]);

	if (!test_bit(line, &v->irq_enabled))
		return;
	if (type & IRQ_TYPE_LEVEL_MASK) {
		if (vspi_level_active(v, line))
			vspi_raise(v, line);
		return;
	}
	if (!(type & (high ? IRQ_TYPE_EDGE_RISING : IRQ_TYPE_EDGE_FALLING)))
		return;
	vspi_raise(v, line);
}

/* A level line unmasked while active fires again, as in hardware. */
static void vspi_level_work(struct work_struct *work)
{
	struct vspi *v = container_of(work, struct vspi, level_work);
	unsigned int line;

	for (line = 0; line < VSPI_NLINES; line++)
		if (test_bit(line, &v->irq_enabled) &&
		    vspi_level_active(v, line))
			vspi_raise(v, line);
}

static long vspi_set_lines(struct vspi *v, u32 __user *arg)
{
	unsigned long changed;
	unsigned int line;
	u32 val;

	if (get_user(val, arg))
		return -EFAULT;
	if (val & ~(ECMXF_VSPI_LINE_INT0 | ECMXF_VSPI_LINE_INT1))
		return -EINVAL;

	mutex_lock(&v->line_lock);
	changed = READ_ONCE(v->levels) ^ val;
	WRITE_ONCE(v->levels, val);
	for_each_set_bit(line, &changed, VSPI_NLINES)
		vspi_line_edge(v, line, val & BIT(line));
	mutex_unlock(&v->line_lock);
	return 0;
}

static long vspi_ioctl(struct file *file, unsigned int cmd, unsigned long arg)
{
	struct vspi *v = vspi_from_file(file);

	switch (cmd) {
	case ECMXF_VSPI_IOC_SET_LINES:
		return vspi_set_lines(v, (u32 __user *)arg);
	default:
		return -ENOTTY;
	}
}

static const struct file_operations vspi_fops = {
	.owner = THIS_MODULE,
	.open = vspi_open,
	.release = vspi_release,
	.read = vspi_read,
	.write = vspi_write,
	.poll = vspi_poll,
	.unlocked_ioctl = vspi_ioctl,
	.compat_ioctl = compat_ptr_ioctl,
	.llseek = noop_llseek,
};

/* ---- the GPIO lines and their interrupts ----------------------------- */

static int vspi_gpio_get(struct gpio_chip *gc, unsigned int offset)
{
	struct vspi *v = gpiochip_get_data(gc);

	return !!(READ_ONCE(v->levels) & BIT(offset));
}

static int vspi_gpio_get_direction(struct gpio_chip *gc, unsigned int offset)
{
	return GPIO_LINE_DIRECTION_IN;
}

static int vspi_gpio_direction_input(struct gpio_chip *gc, unsigned int offset)
{
	return 0;
}

static void vspi_irq_mask(struct irq_data *d)
{
	struct gpio_chip *gc = irq_data_get_irq_chip_data(d);
	struct vspi *v = gpiochip_get_data(gc);
	irq_hw_number_t hwirq = irqd_to_hwirq(d);

	clear_bit(hwirq, &v->irq_enabled);
	gpiochip_disable_irq(gc, hwirq);
}

static void vspi_irq_unmask(struct irq_data *d)
{
	struct gpio_chip *gc = irq_data_get_irq_chip_data(d);
	struct vspi *v = gpiochip_get_data(gc);
	irq_hw_number_t hwirq = irqd_to_hwirq(d);

	gpiochip_enable_irq(gc, hwirq);
	set_bit(hwirq, &v->irq_enabled);
	if (vspi_level_active(v, hwirq))
		schedule_work(&v->level_work);
}

static int vspi_irq_set_type(struct irq_data *d, unsigned int type)
{
	struct gpio_chip *gc = irq_data_get_irq_chip_data(d);
	struct vspi *v = gpiochip_get_data(gc);

	if (type != IRQ_TYPE_LEVEL_HIGH && type != IRQ_TYPE_LEVEL_LOW &&
	    (type & ~IRQ_TYPE_EDGE_BOTH))
		return -EINVAL;
	WRITE_ONCE(v->irq_type[irqd_to_hwirq(d)], type);
	irq_set_handler_locked(d, type & IRQ_TYPE_LEVEL_MASK ?
			       handle_level_irq : handle_simple_irq);
	return 0;
}

/*
 * The lines' interrupts are raised by the bridge's ioctl on whatever CPU it
 * runs: no CPU to route. Accepting a mask lets /proc/irq/N/smp_affinity
 * place a line's interrupt thread (gpiolib's edge thread, a threaded
 * handler) as a board's GPIO interrupt can be placed (the cyclic bench keeps
 * it on the application's CPU).
 */
static int vspi_irq_set_affinity(struct irq_data *d,
				 const struct cpumask *mask, bool force)
{
	irq_data_update_effective_affinity(d, mask);
	return IRQ_SET_MASK_OK;
}

static const struct irq_chip vspi_irq_chip = {
	.name = VSPI_NAME,
	.irq_mask = vspi_irq_mask,
	.irq_unmask = vspi_irq_unmask,
	.irq_set_type = vspi_irq_set_type,
	.irq_set_affinity = vspi_irq_set_affinity,
	.flags = IRQCHIP_IMMUTABLE | IRQCHIP_SKIP_SET_WAKE,
	GPIOCHIP_IRQ_RESOURCE_HELPERS,
};

static int vspi_add_gpio(struct device *dev, struct vspi *v)
{
	struct gpio_irq_chip *girq;
	unsigned int line;
	int ret;

	v->gc.label = VSPI_NAME;
	v->gc.parent = dev;
	v->gc.owner = THIS_MODULE;
	v->gc.base = -1;
	v->gc.ngpio = VSPI_NLINES;
	v->gc.get = vspi_gpio_get;
	v->gc.get_direction = vspi_gpio_get_direction;
	v->gc.direction_input = vspi_gpio_direction_input;

	girq = &v->gc.irq;
	gpio_irq_chip_set_chip(girq, &vspi_irq_chip);
	girq->handler = handle_simple_irq;
	girq->default_type = IRQ_TYPE_NONE;

	ret = devm_gpiochip_add_data(dev, &v->gc, v);
	if (ret)
		return ret;
	/*
	 * Map both lines now (a line request finds the mapping) so that their
	 * affinity can move at once (vspi_irq_set_affinity()).
	 */
	for (line = 0; line < VSPI_NLINES; line++) {
		unsigned int irq = irq_create_mapping(girq->domain, line);

		if (!irq)
			return -ENOMEM;
		if (VSPI_IRQ_MOVE_PCNTXT)
			irq_set_status_flags(irq, VSPI_IRQ_MOVE_PCNTXT);
	}
	return 0;
}

/* ---- the platform device that holds it all --------------------------- */

static void vspi_lookup_entry(struct gpiod_lookup *e, unsigned int line,
			      const char *con_id, enum gpio_lookup_flags flags)
{
	e->key = VSPI_NAME;
	e->chip_hwnum = line;
	e->con_id = con_id;
	e->idx = 0;
	e->flags = flags;
}

/* int1=irq-level/irq-edge: INT1 as the device's one unnamed interrupt */
static int vspi_int1_irq(struct vspi *v, struct spi_board_info *info)
{
	unsigned int type;
	int irq, ret;

	if (!strcmp(int1, "irq-level"))
		type = IRQ_TYPE_LEVEL_LOW;
	else if (!strcmp(int1, "irq-edge"))
		type = IRQ_TYPE_EDGE_FALLING;
	else if (!strcmp(int1, "irq-none"))
		type = IRQ_TYPE_NONE;
	else
		return -EINVAL;
	irq = irq_create_mapping(v->gc.irq.domain, 1);
	if (!irq)
		return -ENXIO;
	if (type != IRQ_TYPE_NONE) {
		ret = irq_set_irq_type(irq, type);
		if (ret)
			return ret;
	}
	info->irq = irq;
	return 0;
}

static int vspi_probe(struct platform_device *pdev)
{
	struct device *dev = &pdev->dev;
	struct spi_board_info info = {
		.max_speed_hz = 10000000,
		.chip_select = 0,
		.mode = SPI_MODE_0,
	};
	struct spi_controller *ctlr;
	unsigned int nprops = 0;
	struct vspi *v;
	int ret;

	strscpy(info.modalias, modalias, sizeof(info.modalias));

	ctlr = devm_spi_alloc_master(dev, sizeof(*v));
	if (!ctlr)
		return -ENOMEM;
	v = spi_controller_get_devdata(ctlr);
	v->ctlr = ctlr;
	mutex_init(&v->lock);
	mutex_init(&v->line_lock);
	init_waitqueue_head(&v->bridge_wq);
	init_completion(&v->done);
	INIT_WORK(&v->level_work, vspi_level_work);
	/* INT0 "ready" (active high) is high, INT1 (active low) idle high */
	v->levels = ECMXF_VSPI_LINE_INT0 | ECMXF_VSPI_LINE_INT1;
	v->buf = devm_kzalloc(dev, ECMXF_VSPI_MAX_XFER, GFP_KERNEL);
	if (!v->buf)
		return -ENOMEM;
	platform_set_drvdata(pdev, v);

	ret = vspi_add_gpio(dev, v);
	if (ret)
		return dev_err_probe(dev, ret, "cannot add the GPIO chip\n");

	v->misc.minor = MISC_DYNAMIC_MINOR;
	v->misc.name = VSPI_NAME;
	v->misc.fops = &vspi_fops;
	v->misc.parent = dev;
	ret = misc_register(&v->misc);
	if (ret)
		return dev_err_probe(dev, ret, "cannot register /dev/%s\n",
				     VSPI_NAME);

	ctlr->bus_num = -1;
	ctlr->num_chipselect = 1;
	ctlr->mode_bits = SPI_CPOL | SPI_CPHA;
	ctlr->bits_per_word_mask = SPI_BPW_MASK(8);
	ctlr->min_speed_hz = 100000;
	ctlr->max_speed_hz = 50000000;
	ctlr->transfer_one = vspi_transfer_one;
	ctlr->max_transfer_size = vspi_max_transfer_size;
	ret = devm_spi_register_controller(dev, ctlr);
	if (ret) {
		dev_err_probe(dev, ret, "cannot register the SPI controller\n");
		goto out_misc;
	}

	v->lookup = devm_kzalloc(dev, struct_size(v->lookup, table, 3),
				 GFP_KERNEL);
	if (!v->lookup) {
		ret = -ENOMEM;
		goto out_misc;
	}
	v->lookup->dev_id = devm_kasprintf(dev, GFP_KERNEL, "%s.%u",
					   dev_name(&ctlr->dev),
					   info.chip_select);
	if (!v->lookup->dev_id) {
		ret = -ENOMEM;
		goto out_misc;
	}
	/* table[2] (or [1]) stays zero: the terminator */
	vspi_lookup_entry(&v->lookup->table[0], 0, "int0", GPIO_ACTIVE_HIGH);
	if (!strcmp(int1, "gpio")) {
		vspi_lookup_entry(&v->lookup->table[1], 1, "int1",
				  GPIO_ACTIVE_LOW);
	} else {
		ret = vspi_int1_irq(v, &info);
		if (ret)
			goto out_misc;
	}
	gpiod_add_lookup_table(v->lookup);

	/* the per-chip settings as device properties (a software node) */
	if (data_size_prop >= 0)
		v->props[nprops++] = PROPERTY_ENTRY_U32("nextw,data-size",
							data_size_prop);
	if (*check_type_prop)
		v->props[nprops++] = PROPERTY_ENTRY_STRING("nextw,check-type",
							   check_type_prop);
	if (nprops) {
		v->swnode.properties = v->props;
		info.swnode = &v->swnode;
	}

	v->spi = spi_new_device(ctlr, &info);
	if (!v->spi) {
		ret = -ENODEV;
		dev_err(dev, "cannot add the SPI device\n");
		goto out_lookup;
	}
	dev_info(dev, "%s: SPI device %s (modalias %s), INT0/INT1 on %s (INT1 as %s), bridge /dev/%s\n",
		 dev_name(&ctlr->dev), dev_name(&v->spi->dev), info.modalias,
		 VSPI_NAME, int1, VSPI_NAME);
	return 0;

out_lookup:
	gpiod_remove_lookup_table(v->lookup);
out_misc:
	misc_deregister(&v->misc);
	return ret;
}

static void vspi_teardown(struct platform_device *pdev)
{
	struct vspi *v = platform_get_drvdata(pdev);

	spi_unregister_device(v->spi);
	cancel_work_sync(&v->level_work);
	gpiod_remove_lookup_table(v->lookup);
	misc_deregister(&v->misc);
}

VSPI_PLATFORM_REMOVE(vspi_remove, vspi_teardown)

static struct platform_driver vspi_driver = {
	.driver = {
		.name = VSPI_NAME,
	},
	.probe = vspi_probe,
	.remove = vspi_remove,
};

static struct platform_device *vspi_pdev;

static int __init vspi_init(void)
{
	int ret = platform_driver_register(&vspi_driver);

	if (ret)
		return ret;
	vspi_pdev = platform_device_register_simple(VSPI_NAME, -1, NULL, 0);
	if (IS_ERR(vspi_pdev)) {
		platform_driver_unregister(&vspi_driver);
		return PTR_ERR(vspi_pdev);
	}
	return 0;
}
module_init(vspi_init);

static void __exit vspi_exit(void)
{
	platform_device_unregister(vspi_pdev);
	platform_driver_unregister(&vspi_driver);
}
module_exit(vspi_exit);

MODULE_DESCRIPTION("Virtual SPI controller and INT0/INT1 lines for the ecmxf QEMU tests");
MODULE_AUTHOR("The ecmxf authors");
MODULE_LICENSE("GPL");
