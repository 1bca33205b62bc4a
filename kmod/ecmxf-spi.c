// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-spi.c - NEXTW ECM-XF: spi_driver, device properties, INT0/INT1
 *
 * Binds to "nextw,ecm-xf" (devicetree), to the SPI modalias "ecm-xf"
 * (board code, software nodes, spi_new_device()) and reads everything
 * through device_property_*() and gpiod, so DT, ACPI and software nodes
 * all work.  Probe brings the link up (ecmxf_link_bringup()), starts the
 * worker and creates /dev/ecmxfN.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/interrupt.h>
#include <linux/kthread.h>
#include <linux/mod_devicetable.h>
#include <linux/module.h>
#include <linux/property.h>
#include <linux/slab.h>

#include "ecmxf.h"

/*
 * INT0 ("ready") and INT1 (event) interrupts.  The handlers only count,
 * record a flag and wake the worker: bounded work that needs no lock and
 * is safe in hard IRQ context, so they run there when the GPIO controller
 * allows it (devm_request_any_context_irq(); no IRQ thread between the
 * edge and the worker) and threaded behind a nested (e.g. I2C expander)
 * controller; PREEMPT_RT threads them anyway.  The worker (or probe,
 * while it owns the link) never depends on an edge: it also reads the
 * line level and bounds every wait, so a lost edge costs time, not
 * correctness.
 */
static irqreturn_t ecmxf_int0_irq(int irq, void *data)
{
	struct ecmxf_dev *edev = data;

	atomic64_inc(&edev->int0_irqs);
	atomic_set(&edev->int0_flag, 1);
	ecmxf_wake_owner(edev);
	return IRQ_HANDLED;
}

static irqreturn_t ecmxf_int1_irq(int irq, void *data)
{
	struct ecmxf_dev *edev = data;

	atomic64_inc(&edev->int1_irqs);
	atomic_set(&edev->int1_flag, 1);
	ecmxf_wake_owner(edev);
	return IRQ_HANDLED;
}

/*
 * The interrupt of an optional GPIO line, triggered on the edge into the
 * line's active (logical 1) level: the polarity comes from the GPIO flags
 * (GPIO_ACTIVE_LOW in DT, or the ACPI/software-node equivalent).
 */
static int ecmxf_request_line_irq(struct ecmxf_dev *edev,
				  struct gpio_desc *desc, const char *name,
				  irq_handler_t handler, int *irq_out)
{
	struct device *dev = &edev->spi->dev;
	unsigned long trigger;
	int irq, ret;

	*irq_out = 0;
	if (!desc)
		return 0;
	irq = gpiod_to_irq(desc);
	if (irq < 0)
		return dev_err_probe(dev, irq, "%s GPIO has no interrupt\n",
				     name);
	trigger = gpiod_is_active_low(desc) ? IRQF_TRIGGER_FALLING :
					      IRQF_TRIGGER_RISING;
	ret = devm_request_any_context_irq(dev, irq, handler, trigger, name,
					   edev);
	if (ret < 0)
		return dev_err_probe(dev, ret, "cannot request the %s IRQ %d\n",
				     name, irq);
	*irq_out = irq;
	return 0;
}

/* Free the IRQs before the worker goes: their handlers wake it. */
static void ecmxf_free_irqs(struct ecmxf_dev *edev, struct device *dev)
{
	if (edev->int1_irq)
		devm_free_irq(dev, edev->int1_irq, edev);
	if (edev->int0_irq)
		devm_free_irq(dev, edev->int0_irq, edev);
	edev->int0_irq = 0;
	edev->int1_irq = 0;
}

static void ecmxf_dev_release(struct device *dev)
{
	struct ecmxf_dev *edev = container_of(dev, struct ecmxf_dev, dev);

	if (edev->claim_pid)
		put_pid(edev->claim_pid);
	ecmxf_id_free(edev->id);
	kfree(edev->txbuf);
	kfree(edev->rxbuf);
	kfree(edev);
}

/* Packet format wanted at probe: device property, else module parameter. */
static int ecmxf_read_properties(struct ecmxf_dev *edev)
{
	struct device *dev = &edev->spi->dev;
	u32 val;

	edev->want_size = ecmxf_param_data_size;
	edev->want_check = ecmxf_param_check_type;
	if (!device_property_read_u32(dev, "nextw,data-size", &val)) {
		if (!ecmxf_data_size_valid(val))
			return dev_err_probe(dev, -EINVAL,
					     "nextw,data-size = %u is out of range (32..1408)\n",
					     val);
		edev->want_size = val;
	}
	if (!device_property_read_u32(dev, "nextw,check-type", &val)) {
		if (val > ECMXF_CHECK_CRC32)
			return dev_err_probe(dev, -EINVAL,
					     "nextw,check-type = %u is out of range (0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32)\n",
					     val);
		edev->want_check = val;
	}
	return 0;
}

static int ecmxf_probe(struct spi_device *spi)
{
	struct device *dev = &spi->dev;
	struct ecmxf_dev *edev;
	int id, ret;

	spi->bits_per_word = 8;
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
	INIT_LIST_HEAD(&edev->clients);
	INIT_LIST_HEAD(&edev->resets);
	atomic_set(&edev->int0_flag, 0);
	atomic_set(&edev->int1_flag, 0);
	atomic_set(&edev->kick, 0);
	atomic64_set(&edev->int0_irqs, 0);
	atomic64_set(&edev->int1_irqs, 0);

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

	edev->txbuf = kzalloc(ECMXF_PKT_MAX, GFP_KERNEL);
	edev->rxbuf = kzalloc(ECMXF_PKT_MAX, GFP_KERNEL);
	if (!edev->txbuf || !edev->rxbuf) {
		ret = -ENOMEM;
		goto out_put_device;
	}

	ret = ecmxf_read_properties(edev);
	if (ret)
		goto out_put_device;

	edev->int0 = devm_gpiod_get_optional(dev, "int0", GPIOD_IN);
	if (IS_ERR(edev->int0)) {
		ret = dev_err_probe(dev, PTR_ERR(edev->int0),
				    "cannot get the INT0 (ready) GPIO\n");
		goto out_put_device;
	}
	edev->int1 = devm_gpiod_get_optional(dev, "int1", GPIOD_IN);
	if (IS_ERR(edev->int1)) {
		ret = dev_err_probe(dev, PTR_ERR(edev->int1),
				    "cannot get the INT1 (event) GPIO\n");
		goto out_put_device;
	}
	ret = ecmxf_request_line_irq(edev, edev->int0, "ecmxf-int0",
				     ecmxf_int0_irq, &edev->int0_irq);
	if (ret)
		goto out_put_device;
	ret = ecmxf_request_line_irq(edev, edev->int1, "ecmxf-int1",
				     ecmxf_int1_irq, &edev->int1_irq);
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

	dev_info(dev, "/dev/%s: firmware %u, %u-byte data section, %s check word, INT0 %s, INT1 %s\n",
		 dev_name(&edev->dev), edev->fw_version, edev->data_size,
		 ecmxf_check_name(edev->check),
		 edev->int0 ? "wired" : "absent (150 us waits)",
		 edev->int1 ? "wired" : "absent");
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
	{ .compatible = "nextw,ecm-xf" },
	{ }
};
MODULE_DEVICE_TABLE(of, ecmxf_of_match);

static const struct spi_device_id ecmxf_spi_ids[] = {
	{ "ecm-xf" },
	{ }
};
MODULE_DEVICE_TABLE(spi, ecmxf_spi_ids);

static struct spi_driver ecmxf_spi_driver = {
	.driver = {
		.name = ECMXF_DRV_NAME,
		.of_match_table = ecmxf_of_match,
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
