// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-main.c - NEXTW ECM-XF SPI EtherCAT master: module init and exit
 *
 * Checks the protocol core, creates the "ecmxf" class and the character
 * device region (/dev/ecmxf0, /dev/ecmxf1, ... one per chip), registers
 * the generic netlink family of the events and the spi_driver.  The
 * module parameters set the packet format of every chip at probe: it is
 * configuration, not hardware, so no device property gives it.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/fs.h>
#include <linux/idr.h>
#include <linux/init.h>
#include <linux/module.h>
#include <linux/moduleparam.h>
#include <linux/printk.h>

#include "ecmxf.h"

unsigned int ecmxf_param_data_size;
module_param_named(data_size, ecmxf_param_data_size, uint, 0444);
MODULE_PARM_DESC(data_size,
		 "packet data section size set at probe, 32..1408; 0 keeps the chip's (default 0; a chip's nextw,data-size property wins)");

unsigned int ecmxf_param_check_type = ECMXF_CHECK_CRC32;
module_param_named(check_type, ecmxf_param_check_type, uint, 0444);
MODULE_PARM_DESC(check_type,
		 "check word set at probe: 0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32 (default 3; a chip's nextw,check-type property wins)");

unsigned int ecmxf_param_max_open = 64;
module_param_named(max_open, ecmxf_param_max_open, uint, 0444);
MODULE_PARM_DESC(max_open,
		 "file descriptors that may have one device open at once (default 64)");

/*
 * the pump's and the events' timing: defaults each chip copies at probe
 * (read-only: a running device never sees them change)
 */
unsigned int ecmxf_param_pump_timeout_ms = 500;
module_param_named(pump_timeout_ms, ecmxf_param_pump_timeout_ms, uint, 0444);
MODULE_PARM_DESC(pump_timeout_ms,
		 "time allowed for each PDO pump command, ms (10..60000, default 500)");

unsigned int ecmxf_param_event_poll_ms = 100;
module_param_named(event_poll_ms, ecmxf_param_event_poll_ms, uint, 0444);
MODULE_PARM_DESC(event_poll_ms,
		 "while a netlink listener is subscribed to the events, poll an otherwise idle chip every so many ms; 0 never (default 100)");

unsigned int ecmxf_param_queue_depth = 16;
module_param_named(queue_depth, ecmxf_param_queue_depth, uint, 0444);
MODULE_PARM_DESC(queue_depth,
		 "submitted commands one file descriptor may have in flight (default 16)");

/* The class of /dev/ecmxfN; its devices carry the sysfs attributes. */
struct class ecmxf_class = {
	.name = ECMXF_DRV_NAME,
};

/* First dev_t of the region; minor N is /dev/ecmxfN. */
dev_t ecmxf_devt;

static DEFINE_IDA(ecmxf_ida);

/**
 * ecmxf_id_alloc() - take the lowest free device number
 *
 * Return: 0..%ECMXF_MAX_DEVICES - 1, or a negative errno.
 */
int ecmxf_id_alloc(void)
{
	return ida_alloc_max(&ecmxf_ida, ECMXF_MAX_DEVICES - 1, GFP_KERNEL);
}

/**
 * ecmxf_id_free() - give back a number from ecmxf_id_alloc()
 * @id: the number
 */
void ecmxf_id_free(int id)
{
	ida_free(&ecmxf_ida, id);
}

static int __init ecmxf_init(void)
{
	int ret = ecmxf_selftest();

	if (ret) {
		pr_err("protocol core self-test failed; not loading\n");
		return ret;
	}
	if (ecmxf_param_data_size && !ecmxf_data_size_valid(ecmxf_param_data_size)) {
		pr_err("data_size=%u is out of range (0, or 32..1408)\n",
		       ecmxf_param_data_size);
		return -EINVAL;
	}
	if (ecmxf_param_check_type > ECMXF_CHECK_CRC32) {
		pr_err("check_type=%u is out of range (0..3)\n",
		       ecmxf_param_check_type);
		return -EINVAL;
	}
	if (ecmxf_param_pump_timeout_ms < 10 ||
	    ecmxf_param_pump_timeout_ms > 60000) {
		pr_err("pump_timeout_ms=%u is out of range (10..60000)\n",
		       ecmxf_param_pump_timeout_ms);
		return -EINVAL;
	}
	if (!ecmxf_param_max_open || !ecmxf_param_queue_depth) {
		pr_err("max_open and queue_depth must be at least 1\n");
		return -EINVAL;
	}

	ret = alloc_chrdev_region(&ecmxf_devt, 0, ECMXF_MAX_DEVICES,
				  ECMXF_DRV_NAME);
	if (ret)
		return ret;
	ret = class_register(&ecmxf_class);
	if (ret)
		goto out_unregister_region;
	ret = ecmxf_nl_register();
	if (ret)
		goto out_unregister_class;
	ret = ecmxf_spi_register();
	if (ret)
		goto out_unregister_genl;
	pr_info("protocol core self-test passed; uAPI version %u\n",
		ECMXF_UAPI_VERSION);
	return 0;

out_unregister_genl:
	ecmxf_nl_unregister();
out_unregister_class:
	class_unregister(&ecmxf_class);
out_unregister_region:
	unregister_chrdev_region(ecmxf_devt, ECMXF_MAX_DEVICES);
	return ret;
}
module_init(ecmxf_init);

static void __exit ecmxf_exit(void)
{
	ecmxf_spi_unregister();
	ecmxf_nl_unregister();	/* every worker has stopped */
	class_unregister(&ecmxf_class);
	unregister_chrdev_region(ecmxf_devt, ECMXF_MAX_DEVICES);
	ida_destroy(&ecmxf_ida);
}
module_exit(ecmxf_exit);

MODULE_DESCRIPTION("NEXTW ECM-XF SPI EtherCAT master");
MODULE_AUTHOR("The ecmxf authors");
MODULE_LICENSE("GPL");
