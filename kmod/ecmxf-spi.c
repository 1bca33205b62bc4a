// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-spi.c - NEXTW ECM-XF: spi_driver, INT0/INT1 interrupts
 *
 * Binds to "nextw,ecm-xf" (devicetree), to the SPI modalias "ecm-xf"
 * (board code, software nodes, spi_new_device()) and finds INT0/INT1
 * through fwnode and gpiod calls, so DT, ACPI, software nodes and board
 * code all work (Documentation/devicetree/nextw,ecm-xf.yaml).  Probe
 * brings the link up (ecmxf_link_bringup()), starts the worker and
 * creates /dev/ecmxfN.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/interrupt.h>
#include <linux/irq.h>
#include <linux/kthread.h>
#include <linux/mod_devicetable.h>
#include <linux/module.h>
#include <linux/property.h>
#include <linux/delay.h>
#include <linux/property.h>
#include <linux/regulator/consumer.h>
#include <linux/slab.h>
#include <linux/string.h>

#include "ecmxf.h"

/*
 * INT0 ("ready") and INT1 (event) interrupts.  The handlers only count,
 * record a flag and wake the worker: bounded work that needs no lock and
 * is safe in hard IRQ context, so they run there when the interrupt
 * controller allows it (devm_request_any_context_irq(); no IRQ thread
 * between the edge and the worker) and threaded behind a nested (e.g. I2C
 * expander) controller; PREEMPT_RT threads them anyway.  The worker (or
 * probe, while it owns the link) never depends on an interrupt alone: it
 * bounds every wait, so a lost edge costs time, not correctness.
 *
 * A level-triggered line would fire again as soon as the handler returns,
 * for as long as the chip holds it (INT0 "ready" is high whenever the chip
 * is idle; INT1 stays asserted until the application clears the flag), so
 * its handler also masks it (disable_irq_nosync()).  The worker unmasks it
 * when it wants the next one: INT0 when it waits for "ready", INT1 once a
 * packet with interrupt clear bits reached the chip, or after
 * %ECMXF_INT1_HOLDOFF_NS (ecmxf-worker.c).
 */
static void ecmxf_irq_hold(int irq, bool level, atomic_t *masked)
{
	if (!level)
		return;
	/* disabled before marked: ecmxf_irq_unmask() never unbalances */
	disable_irq_nosync(irq);
	atomic_set(masked, 1);
}

static irqreturn_t ecmxf_int0_irq(int irq, void *data)
{
	struct ecmxf_dev *edev = data;

	ecmxf_irq_hold(irq, edev->irq.int0_level, &edev->irq.int0_masked);
	atomic64_inc(&edev->irq.int0_irqs);
	atomic_set(&edev->irq.int0_flag, 1);
	ecmxf_wake_owner(edev);
	return IRQ_HANDLED;
}

static irqreturn_t ecmxf_int1_irq(int irq, void *data)
{
	struct ecmxf_dev *edev = data;

	ecmxf_irq_hold(irq, edev->irq.int1_level, &edev->irq.int1_masked);
	atomic64_inc(&edev->irq.int1_irqs);
	atomic_set(&edev->irq.int1_flag, 1);
	ecmxf_wake_owner(edev);
	return IRQ_HANDLED;
}

/**
 * ecmxf_irq_unmask() - unmask a level-triggered line its handler masked
 * @edev: the device
 * @irq: the line's IRQ
 * @masked: its &ecmxf_dev.irq.int0_masked or &ecmxf_dev.irq.int1_masked
 *
 * Nothing to do for an edge-triggered line, or one not masked.  Once
 * ecmxf_free_irqs() has begun, it never enables the IRQ again.  Call from
 * the task that owns the link, without &ecmxf_dev.lock.
 */
void ecmxf_irq_unmask(struct ecmxf_dev *edev, int irq, atomic_t *masked)
{
	if (!atomic_read(masked))
		return;
	mutex_lock(&edev->lock);
	if (!edev->irq.irqs_off && atomic_xchg(masked, 0))
		enable_irq(irq);
	mutex_unlock(&edev->lock);
}

static const char *ecmxf_trigger_name(unsigned int type)
{
	switch (type) {
	case IRQ_TYPE_EDGE_RISING:
		return "rising edge";
	case IRQ_TYPE_EDGE_FALLING:
		return "falling edge";
	case IRQ_TYPE_EDGE_BOTH:
		return "both edges";
	case IRQ_TYPE_LEVEL_HIGH:
		return "level high";
	case IRQ_TYPE_LEVEL_LOW:
		return "level low";
	default:
		return "no trigger";
	}
}

/**
 * struct ecmxf_line - where one of INT0/INT1 comes from (probe only)
 * @gpio: the GPIO of the "int0-gpios"/"int1-gpios" form, or NULL
 * @irq: its Linux IRQ, 0 when the line is absent
 * @type: IRQ_TYPE_* the IRQ is requested with
 * @form: "interrupt" or "GPIO", for the probe message
 */
struct ecmxf_line {
	struct gpio_desc *gpio;
	int irq;
	unsigned int type;
	const char *form;
};

/*
 * Find INT0 or INT1 (@name "int0"/"int1"); the first form that is there
 * wins:
 *
 *  1. an interrupt named @name in "interrupt-names" (DT, ACPI _DSD),
 *     triggered as the firmware describes it; for INT0, "ready-gpios"
 *     (the same line as a GPIO), when given, is its level to read;
 *  2. the GPIO "ready-gpios" (INT0 only) or the deprecated "@name-gpios"
 *     (any firmware, gpiod lookup tables), its interrupt triggered on the
 *     edge into the line's active level (the polarity from the GPIO
 *     flags); the worker also reads INT0's level;
 *  3. INT1 only: the device's one unnamed interrupt, when the firmware
 *     has no "interrupt-names" (spi->irq: board code's
 *     spi_board_info.irq, an ACPI GpioInt), triggered as configured.
 *
 * An interrupt without a trigger type is refused: whether the line is
 * level or edge decides how it is handled.
 */
static int ecmxf_find_line(struct ecmxf_dev *edev, const char *name,
			   struct ecmxf_line *l)
{
	struct device *dev = &edev->spi->dev;
	struct fwnode_handle *fwnode = dev_fwnode(dev);
	int idx, irq;

	bool int0 = !strcmp(name, "int0");

	memset(l, 0, sizeof(*l));
	if (int0) {
		l->gpio = devm_gpiod_get_optional(dev, "ready", GPIOD_IN);
		if (IS_ERR(l->gpio))
			return dev_err_probe(dev, PTR_ERR(l->gpio),
					     "cannot get the ready GPIO\n");
	}
	idx = fwnode_property_match_string(fwnode, "interrupt-names", name);
	if (idx >= 0) {
		irq = fwnode_irq_get(fwnode, idx);
		if (irq < 0)
			return dev_err_probe(dev, irq,
					     "cannot get the interrupt \"%s\"\n",
					     name);
		l->irq = irq;
		l->type = irq_get_trigger_type(irq);
		l->form = l->gpio ? "interrupt + ready GPIO" : "interrupt";
	} else {
		if (!l->gpio)
			l->gpio = devm_gpiod_get_optional(dev, name, GPIOD_IN);
		if (IS_ERR(l->gpio))
			return dev_err_probe(dev, PTR_ERR(l->gpio),
					     "cannot get the %s GPIO\n", name);
		if (l->gpio) {
			irq = gpiod_to_irq(l->gpio);
			if (irq < 0)
				return dev_err_probe(dev, irq,
						     "the %s GPIO has no interrupt\n",
						     name);
			l->irq = irq;
			l->type = gpiod_is_active_low(l->gpio) ?
				  IRQ_TYPE_EDGE_FALLING : IRQ_TYPE_EDGE_RISING;
			l->form = "GPIO";
		} else if (!int0 && edev->spi->irq > 0 &&
			   !fwnode_property_present(fwnode, "interrupt-names")) {
			l->irq = edev->spi->irq;
			l->type = irq_get_trigger_type(l->irq);
			l->form = "interrupt";
		}
	}
	if (l->irq && !(l->type & IRQ_TYPE_SENSE_MASK))
		return dev_err_probe(dev, -EINVAL,
				     "the %s interrupt (IRQ %d) has no trigger type\n",
				     name, l->irq);
	return 0;
}

/* Request the IRQ of @l; *@irq_out becomes it once requested. */
static int ecmxf_request_line_irq(struct ecmxf_dev *edev,
				  const struct ecmxf_line *l, const char *name,
				  irq_handler_t handler, int *irq_out)
{
	struct device *dev = &edev->spi->dev;
	int ret;

	*irq_out = 0;
	if (!l->irq)
		return 0;
	ret = devm_request_any_context_irq(dev, l->irq, handler,
					   l->type & IRQ_TYPE_SENSE_MASK, name,
					   edev);
	if (ret < 0)
		return dev_err_probe(dev, ret,
				     "cannot request the %s IRQ %d (%s)\n", name,
				     l->irq, ecmxf_trigger_name(l->type));
	*irq_out = l->irq;
	return 0;
}

/* Probe's summary of one line: "absent", "GPIO, rising edge", ... */
static void ecmxf_line_desc(char *buf, size_t size,
			    const struct ecmxf_line *l, const char *absent)
{
	if (!l->irq)
		strscpy(buf, absent, size);
	else
		snprintf(buf, size, "%s IRQ %d, %s", l->form, l->irq,
			 ecmxf_trigger_name(l->type));
}

/* Free the IRQs before the worker goes: their handlers wake it. */
static void ecmxf_free_irqs(struct ecmxf_dev *edev, struct device *dev)
{
	/* the worker may still run: it must not enable them again */
	mutex_lock(&edev->lock);
	edev->irq.irqs_off = true;
	mutex_unlock(&edev->lock);
	if (edev->irq.int1_irq)
		devm_free_irq(dev, edev->irq.int1_irq, edev);
	if (edev->irq.int0_irq)
		devm_free_irq(dev, edev->irq.int0_irq, edev);
	edev->irq.int0_irq = 0;
	edev->irq.int1_irq = 0;
}

static void ecmxf_dev_release(struct device *dev)
{
	struct ecmxf_dev *edev = container_of(dev, struct ecmxf_dev, dev);

	if (edev->claim.pid)
		put_pid(edev->claim.pid);
	ecmxf_id_free(edev->id);
	kfree(edev->link.txbuf);
	kfree(edev->link.rxbuf);
	kfree(edev);
}

/* the master series, from the compatible or the SPI id (driver_data) */
static const struct ecmxf_variant ecmxf_variant_xf = { .name = "ECM-XF" };
static const struct ecmxf_variant ecmxf_variant_xfl = { .name = "ECM-XFL" };
static const struct ecmxf_variant ecmxf_variant_xm = { .name = "ECM-XM" };
static const struct ecmxf_variant ecmxf_variant_xfu = {
	.name = "ECM-XFU",
	.fixed_size = 992,	/* manual ver. 050: "fixed at 992 bytes" */
};

/*
 * The chip's settings: the series from the match, the packet format from
 * the device's properties ("nextw,data-size", "nextw,check-type": DT,
 * ACPI _DSD, software nodes) where it has them, else from the module
 * parameters, which are only the defaults; the timing from the module
 * parameters, copied so that a running device never sees them change.
 */
static int ecmxf_read_config(struct ecmxf_dev *edev)
{
	struct device *dev = &edev->spi->dev;
	const struct spi_device_id *id = spi_get_device_id(edev->spi);
	const struct ecmxf_variant *v = device_get_match_data(dev);
	const char *check;
	unsigned int i;
	u32 size;
	int ret;

	if (!v && id)
		v = (const struct ecmxf_variant *)id->driver_data;
	edev->cfg.variant = v ? v : &ecmxf_variant_xf;
	edev->cfg.pump_timeout_ms = ecmxf_param_pump_timeout_ms;
	edev->cfg.event_poll_ms = ecmxf_param_event_poll_ms;
	edev->link.want_size = ecmxf_param_data_size;
	edev->link.want_check = ecmxf_param_check_type;

	ret = device_property_read_u32(dev, "nextw,data-size", &size);
	if (!ret) {
		if (!ecmxf_data_size_valid(size))
			return dev_err_probe(dev, -EINVAL,
					     "nextw,data-size = %u: not a data section size (32..1408)\n",
					     size);
		if (edev->cfg.variant->fixed_size &&
		    size != edev->cfg.variant->fixed_size)
			return dev_err_probe(dev, -EINVAL,
					     "nextw,data-size = %u: the %s's data section is fixed at %u bytes\n",
					     size, edev->cfg.variant->name,
					     edev->cfg.variant->fixed_size);
		edev->link.want_size = size;
	} else if (ret != -EINVAL) {
		return dev_err_probe(dev, ret, "cannot read nextw,data-size\n");
	}
	/* the fixed size is the chip's: nothing to set (SPI_RECONFIG_OP) */
	if (edev->cfg.variant->fixed_size)
		edev->link.want_size = 0;

	ret = device_property_read_string(dev, "nextw,check-type", &check);
	if (!ret) {
		for (i = 0; i <= ECMXF_CHECK_CRC32; i++)
			if (!strcmp(check, ecmxf_check_name(i)))
				break;
		if (i > ECMXF_CHECK_CRC32)
			return dev_err_probe(dev, -EINVAL,
					     "nextw,check-type = \"%s\": none of fixed, crc8, crc-ccitt, crc32\n",
					     check);
		edev->link.want_check = i;
	} else if (ret != -EINVAL) {
		return dev_err_probe(dev, ret, "cannot read nextw,check-type\n");
	}
	return 0;
}

/*
 * The supply on, then the chip out of reset, when the firmware names them
 * ("vdd-supply", "reset-gpios"; both optional).  The manuals give no reset
 * timing: the line is held for ECMXF_RESET_US and the chip given
 * ECMXF_BOOT_MS before the first exchange; the probe's bounded tries
 * (ecmxf_link_bringup()) then find it in whatever format it starts.
 */
#define ECMXF_RESET_US	100
#define ECMXF_BOOT_MS	100
static int ecmxf_power_up(struct ecmxf_dev *edev)
{
	struct device *dev = &edev->spi->dev;
	struct gpio_desc *reset;
	int ret;

	ret = devm_regulator_get_enable_optional(dev, "vdd");
	if (ret && ret != -ENODEV)
		return dev_err_probe(dev, ret, "cannot enable the vdd supply\n");
	/* asserted (logical 1) as it is requested */
	reset = devm_gpiod_get_optional(dev, "reset", GPIOD_OUT_HIGH);
	if (IS_ERR(reset))
		return dev_err_probe(dev, PTR_ERR(reset),
				     "cannot get the reset GPIO\n");
	if (!reset)
		return 0;
	fsleep(ECMXF_RESET_US);
	gpiod_set_value_cansleep(reset, 0);
	msleep(ECMXF_BOOT_MS);
	return 0;
}

static int ecmxf_probe(struct spi_device *spi)
{
	struct device *dev = &spi->dev;
	struct ecmxf_line int0, int1;
	struct ecmxf_dev *edev;
	char d0[48], d1[48];
	int id, ret;

	spi->bits_per_word = 8;
	/*
	 * The worker runs SCHED_FIFO and waits in spi_sync(): the
	 * controller's message pump (when a transfer is queued behind
	 * another device's) must not run below it (as mcp251xfd, oa_tc6).
	 */
	spi->rt = true;
	ret = spi_setup(spi);
	if (ret)
		return dev_err_probe(dev, ret, "SPI setup (mode %#x, 8 bits) failed\n",
				     spi->mode);

	id = ecmxf_id_alloc();
	if (id < 0)
		return dev_err_probe(dev, id, "no free /dev/ecmxfN number\n");

	edev = kzalloc(sizeof(*edev), GFP_KERNEL);
	if (!edev) {
		ecmxf_id_free(id);
		return -ENOMEM;
	}
	edev->id = id;
	edev->spi = spi;
	mutex_init(&edev->lock);
	spin_lock_init(&edev->claim.pid_lock);
	INIT_LIST_HEAD(&edev->clients);
	INIT_LIST_HEAD(&edev->resets);
	atomic_set(&edev->irq.int0_flag, 0);
	atomic_set(&edev->irq.int1_flag, 0);
	atomic_set(&edev->irq.int0_masked, 0);
	atomic_set(&edev->irq.int1_masked, 0);
	atomic_set(&edev->link.kick, 0);
	atomic64_set(&edev->irq.int0_irqs, 0);
	atomic64_set(&edev->irq.int1_irqs, 0);

	/* from here on, put_device() frees edev and the id */
	device_initialize(&edev->dev);
	edev->dev.class = &ecmxf_class;
	edev->dev.parent = dev;
	edev->dev.devt = MKDEV(MAJOR(ecmxf_devt), id);
	edev->dev.groups = ecmxf_groups;
	edev->dev.release = ecmxf_dev_release;
	dev_set_drvdata(&edev->dev, edev);
	ret = dev_set_name(&edev->dev, "ecmxf%d", id);
	if (ret)
		goto out_put_device;

	edev->link.txbuf = kzalloc(ECMXF_PKT_MAX, GFP_KERNEL);
	edev->link.rxbuf = kzalloc(ECMXF_PKT_MAX, GFP_KERNEL);
	if (!edev->link.txbuf || !edev->link.rxbuf) {
		ret = -ENOMEM;
		goto out_put_device;
	}

	ret = ecmxf_read_config(edev);
	if (ret)
		goto out_put_device;
	ret = ecmxf_power_up(edev);
	if (ret)
		goto out_put_device;

	ret = ecmxf_find_line(edev, "int0", &int0);
	if (ret)
		goto out_put_device;
	ret = ecmxf_find_line(edev, "int1", &int1);
	if (ret)
		goto out_put_device;
	edev->irq.int0 = int0.gpio;
	edev->irq.int1 = int1.gpio;
	edev->irq.int0_level = int0.type & IRQ_TYPE_LEVEL_MASK;
	edev->irq.int1_level = int1.type & IRQ_TYPE_LEVEL_MASK;
	ret = ecmxf_request_line_irq(edev, &int0, "ecmxf-int0", ecmxf_int0_irq,
				     &edev->irq.int0_irq);
	if (ret)
		goto out_free_irqs;
	ret = ecmxf_request_line_irq(edev, &int1, "ecmxf-int1", ecmxf_int1_irq,
				     &edev->irq.int1_irq);
	if (ret)
		goto out_free_irqs;

	ret = ecmxf_link_bringup(edev);
	if (ret)
		goto out_free_irqs;	/* ecmxf_link_bringup() said why */

	ret = ecmxf_worker_start(edev);
	if (ret) {
		dev_err_probe(dev, ret, "cannot start the link worker\n");
		goto out_free_irqs;
	}

	cdev_init(&edev->cdev, &ecmxf_fops);
	edev->cdev.owner = THIS_MODULE;
	ret = cdev_device_add(&edev->cdev, &edev->dev);
	if (ret) {
		dev_err_probe(dev, ret, "cannot create /dev/%s\n",
			      dev_name(&edev->dev));
		goto out_stop_worker;
	}
	spi_set_drvdata(spi, edev);

	ecmxf_line_desc(d0, sizeof(d0), &int0, "absent (150 us waits)");
	ecmxf_line_desc(d1, sizeof(d1), &int1, "absent");
	dev_info(dev, "/dev/%s: %s, firmware %u, %u-byte data section, %s check word, INT0 %s, INT1 %s\n",
		 dev_name(&edev->dev), edev->cfg.variant->name,
		 edev->chip.fw_version, edev->chip.data_size,
		 ecmxf_check_name(edev->chip.check), d0, d1);
	return 0;

out_stop_worker:
	ecmxf_free_irqs(edev, dev);
	ecmxf_worker_stop(edev);
out_free_irqs:
	/* before put_device(): the handlers use edev */
	ecmxf_free_irqs(edev, dev);
out_put_device:
	put_device(&edev->dev);
	return ret;
}

static void ecmxf_remove(struct spi_device *spi)
{
	struct ecmxf_dev *edev = spi_get_drvdata(spi);

	/* no new opens, no sysfs; open files keep edev alive */
	cdev_device_del(&edev->cdev, &edev->dev);

	mutex_lock(&edev->lock);
	edev->gone = true;
	/*
	 * the PDO rings, before anything that waits: a cyclic loop that
	 * makes no system calls sees %ECMXF_RING_S_ERROR (and -ENODEV in the
	 * status block) before the unbind returns; the pump takes no more
	 * turns, the memory stays until the last munmap()
	 */
	ecmxf_rings_stop(edev, -ENODEV);
	mutex_unlock(&edev->lock);

	ecmxf_free_irqs(edev, &spi->dev);
	ecmxf_worker_stop(edev);
	ecmxf_chrdev_fail_all(edev, -ENODEV);

	mutex_lock(&edev->lock);
	edev->spi = NULL;
	mutex_unlock(&edev->lock);
	put_device(&edev->dev);
}

static const struct of_device_id ecmxf_of_match[] = {
	{ .compatible = "nextw,ecm-xf", .data = &ecmxf_variant_xf },
	{ .compatible = "nextw,ecm-xfl", .data = &ecmxf_variant_xfl },
	{ .compatible = "nextw,ecm-xfu", .data = &ecmxf_variant_xfu },
	{ .compatible = "nextw,ecm-xm", .data = &ecmxf_variant_xm },
	{ }
};
MODULE_DEVICE_TABLE(of, ecmxf_of_match);

static const struct spi_device_id ecmxf_spi_ids[] = {
	{ "ecm-xf", (kernel_ulong_t)&ecmxf_variant_xf },
	{ "ecm-xfl", (kernel_ulong_t)&ecmxf_variant_xfl },
	{ "ecm-xfu", (kernel_ulong_t)&ecmxf_variant_xfu },
	{ "ecm-xm", (kernel_ulong_t)&ecmxf_variant_xm },
	{ }
};
MODULE_DEVICE_TABLE(spi, ecmxf_spi_ids);

static struct spi_driver ecmxf_spi_driver = {
	.driver = {
		.name = ECMXF_DRV_NAME,
		.of_match_table = ecmxf_of_match,
		/*
		 * probe waits for the chip (up to seconds when none answers):
		 * not on the path of the boot or of whoever binds the device
		 */
		.probe_type = PROBE_PREFER_ASYNCHRONOUS,
	},
	.id_table = ecmxf_spi_ids,
	.probe = ecmxf_probe,
	.remove = ecmxf_remove,
};

/**
 * ecmxf_spi_register() - register the spi_driver
 *
 * Return: 0 or a negative errno.
 */
int ecmxf_spi_register(void)
{
	return spi_register_driver(&ecmxf_spi_driver);
}

/**
 * ecmxf_spi_unregister() - unregister the spi_driver (removes every chip)
 */
void ecmxf_spi_unregister(void)
{
	spi_unregister_driver(&ecmxf_spi_driver);
}
