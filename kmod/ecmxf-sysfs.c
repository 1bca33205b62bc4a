// SPDX-License-Identifier: GPL-2.0-only
/*
 * ecmxf-sysfs.c - NEXTW ECM-XF: attributes of /sys/class/ecmxf/ecmxfN
 *
 *   fw_version     FW_VERSION_GET return value (decimal), "unknown" before
 *   fw_info        its 20 data bytes, hex
 *   data_size      data section size of the packets, bytes (32..1408)
 *   packet_size    whole packet, bytes (data_size + 32)
 *   check_type     fixed, crc8, crc-ccitt or crc32
 *   crc_coverage   which bytes the chip's CRC covers: frame (manual 050),
 *                  valid (NEXTW's example code) or unknown (no answer in a
 *                  CRC type told them apart yet)
 *   int0, int1     "wired" or "absent"
 *   open_count     open file descriptors
 *   claim_pid      process holding the cyclic claim (0: none), in the
 *                  reader's pid namespace
 *   ring_skipped   output frames the PDO pump skipped since probe
 *   ring_failures  PDO pump commands that failed since probe (their
 *                  frames are lost, never sent again)
 *   counters/...   one file per field of struct ecmxf_counters
 *
 * The counters, ring_skipped/ring_failures, data_size, packet_size,
 * check_type and crc_coverage come from the snapshot the worker publishes
 * (ecmxf_get_snap()) and open_count is one word: reading them takes no lock
 * the real-time worker takes, however often a reader reads.  fw_version,
 * fw_info and claim_pid take &ecmxf_dev.lock briefly.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#include <linux/device.h>
#include <linux/stddef.h>
#include <linux/string.h>
#include <linux/sysfs.h>

#include "ecmxf.h"

static struct ecmxf_dev *ecmxf_from_dev(struct device *dev)
{
	return container_of(dev, struct ecmxf_dev, dev);
}

static ssize_t fw_version_show(struct device *dev,
			       struct device_attribute *attr, char *buf)
{
	struct ecmxf_dev *edev = ecmxf_from_dev(dev);
	ssize_t n;

	mutex_lock(&edev->lock);
	n = edev->fw_valid ? sysfs_emit(buf, "%u\n", edev->fw_version) :
			     sysfs_emit(buf, "unknown\n");
	mutex_unlock(&edev->lock);
	return n;
}
static DEVICE_ATTR_RO(fw_version);

static ssize_t fw_info_show(struct device *dev,
			    struct device_attribute *attr, char *buf)
{
	struct ecmxf_dev *edev = ecmxf_from_dev(dev);
	ssize_t n;

	mutex_lock(&edev->lock);
	n = sysfs_emit(buf, "%*phN\n", (int)sizeof(edev->fw_info),
		       edev->fw_info);
	mutex_unlock(&edev->lock);
	return n;
}
static DEVICE_ATTR_RO(fw_info);

/* What the worker published last (ecmxf_get_snap(): no lock taken). */
static void ecmxf_snap_of(struct device *dev, struct ecmxf_snap *v)
{
	ecmxf_get_snap(ecmxf_from_dev(dev), v);
}

static ssize_t data_size_show(struct device *dev,
			      struct device_attribute *attr, char *buf)
{
	struct ecmxf_snap v;

	ecmxf_snap_of(dev, &v);
	return sysfs_emit(buf, "%u\n", v.data_size);
}
static DEVICE_ATTR_RO(data_size);

static ssize_t packet_size_show(struct device *dev,
				struct device_attribute *attr, char *buf)
{
	struct ecmxf_snap v;

	ecmxf_snap_of(dev, &v);
	return sysfs_emit(buf, "%u\n", (unsigned int)ECMXF_PKT_SIZE(v.data_size));
}
static DEVICE_ATTR_RO(packet_size);

static ssize_t check_type_show(struct device *dev,
			       struct device_attribute *attr, char *buf)
{
	struct ecmxf_snap v;

	ecmxf_snap_of(dev, &v);
	return sysfs_emit(buf, "%s\n", ecmxf_check_name(v.check));
}
static DEVICE_ATTR_RO(check_type);

static ssize_t crc_coverage_show(struct device *dev,
				 struct device_attribute *attr, char *buf)
{
	struct ecmxf_snap v;

	ecmxf_snap_of(dev, &v);
	return sysfs_emit(buf, "%s\n", ecmxf_cover_name(v.cover));
}
static DEVICE_ATTR_RO(crc_coverage);

static ssize_t int0_show(struct device *dev, struct device_attribute *attr,
			 char *buf)
{
	return sysfs_emit(buf, "%s\n",
			  ecmxf_from_dev(dev)->int0_irq ? "wired" : "absent");
}
static DEVICE_ATTR_RO(int0);

static ssize_t int1_show(struct device *dev, struct device_attribute *attr,
			 char *buf)
{
	return sysfs_emit(buf, "%s\n",
			  ecmxf_from_dev(dev)->int1_irq ? "wired" : "absent");
}
static DEVICE_ATTR_RO(int1);

static ssize_t open_count_show(struct device *dev,
			       struct device_attribute *attr, char *buf)
{
	/* one word written under the lock: no lock needed to read it */
	return sysfs_emit(buf, "%u\n",
			  READ_ONCE(ecmxf_from_dev(dev)->open_count));
}
static DEVICE_ATTR_RO(open_count);

static ssize_t claim_pid_show(struct device *dev,
			      struct device_attribute *attr, char *buf)
{
	struct ecmxf_dev *edev = ecmxf_from_dev(dev);
	pid_t v;

	mutex_lock(&edev->lock);
	v = edev->claim_pid ? pid_vnr(edev->claim_pid) : 0;
	mutex_unlock(&edev->lock);
	return sysfs_emit(buf, "%d\n", v);
}
static DEVICE_ATTR_RO(claim_pid);

static ssize_t ring_skipped_show(struct device *dev,
				 struct device_attribute *attr, char *buf)
{
	struct ecmxf_snap v;

	ecmxf_snap_of(dev, &v);
	return sysfs_emit(buf, "%llu\n", (unsigned long long)v.ring_skipped);
}
static DEVICE_ATTR_RO(ring_skipped);

static ssize_t ring_failures_show(struct device *dev,
				  struct device_attribute *attr, char *buf)
{
	struct ecmxf_snap v;

	ecmxf_snap_of(dev, &v);
	return sysfs_emit(buf, "%llu\n", (unsigned long long)v.ring_failures);
}
static DEVICE_ATTR_RO(ring_failures);

static struct attribute *ecmxf_attrs[] = {
	&dev_attr_fw_version.attr,
	&dev_attr_fw_info.attr,
	&dev_attr_data_size.attr,
	&dev_attr_packet_size.attr,
	&dev_attr_check_type.attr,
	&dev_attr_crc_coverage.attr,
	&dev_attr_int0.attr,
	&dev_attr_int1.attr,
	&dev_attr_open_count.attr,
	&dev_attr_claim_pid.attr,
	&dev_attr_ring_skipped.attr,
	&dev_attr_ring_failures.attr,
	NULL
};

static const struct attribute_group ecmxf_attr_group = {
	.attrs = ecmxf_attrs,
};

/* counters/<field>: one read-only file per field of struct ecmxf_counters */
static ssize_t ecmxf_counter_show(struct device *dev,
				  struct device_attribute *attr, char *buf)
{
	struct dev_ext_attribute *ea = container_of(attr,
						    struct dev_ext_attribute,
						    attr);
	size_t off = (uintptr_t)ea->var;
	struct ecmxf_counters k;
	u64 v;

	ecmxf_get_counters(ecmxf_from_dev(dev), &k);
	memcpy(&v, (u8 *)&k + off, sizeof(v));
	return sysfs_emit(buf, "%llu\n", (unsigned long long)v);
}

#define ECMXF_COUNTER_ATTR(field)					\
static struct dev_ext_attribute ecmxf_counter_##field = {		\
	.attr = {							\
		.attr = { .name = #field, .mode = 0444 },		\
		.show = ecmxf_counter_show,				\
	},								\
	.var = (void *)offsetof(struct ecmxf_counters, field),		\
}

ECMXF_COUNTER_ATTR(exchanges);
ECMXF_COUNTER_ATTR(bad_not_ready);
ECMXF_COUNTER_ATTR(bad_start);
ECMXF_COUNTER_ATTR(bad_end);
ECMXF_COUNTER_ATTR(bad_check);
ECMXF_COUNTER_ATTR(bad_length);
ECMXF_COUNTER_ATTR(retries);
ECMXF_COUNTER_ATTR(polls);
ECMXF_COUNTER_ATTR(exhausted);
ECMXF_COUNTER_ATTR(timeouts);
ECMXF_COUNTER_ATTR(async_errors);
ECMXF_COUNTER_ATTR(busy_rejects);
ECMXF_COUNTER_ATTR(lost_answers);
ECMXF_COUNTER_ATTR(chip_resets);
ECMXF_COUNTER_ATTR(wkc_errors);
ECMXF_COUNTER_ATTR(out_ring_underruns);
ECMXF_COUNTER_ATTR(in_ring_overruns);
ECMXF_COUNTER_ATTR(rx_fifo_underruns);
ECMXF_COUNTER_ATTR(rx_fifo_overruns);
ECMXF_COUNTER_ATTR(tx_fifo_overruns);
ECMXF_COUNTER_ATTR(int0_irqs);
ECMXF_COUNTER_ATTR(int1_irqs);

static struct attribute *ecmxf_counter_attrs[] = {
	&ecmxf_counter_exchanges.attr.attr,
	&ecmxf_counter_bad_not_ready.attr.attr,
	&ecmxf_counter_bad_start.attr.attr,
	&ecmxf_counter_bad_end.attr.attr,
	&ecmxf_counter_bad_check.attr.attr,
	&ecmxf_counter_bad_length.attr.attr,
	&ecmxf_counter_retries.attr.attr,
	&ecmxf_counter_polls.attr.attr,
	&ecmxf_counter_exhausted.attr.attr,
	&ecmxf_counter_timeouts.attr.attr,
	&ecmxf_counter_async_errors.attr.attr,
	&ecmxf_counter_busy_rejects.attr.attr,
	&ecmxf_counter_lost_answers.attr.attr,
	&ecmxf_counter_chip_resets.attr.attr,
	&ecmxf_counter_wkc_errors.attr.attr,
	&ecmxf_counter_out_ring_underruns.attr.attr,
	&ecmxf_counter_in_ring_overruns.attr.attr,
	&ecmxf_counter_rx_fifo_underruns.attr.attr,
	&ecmxf_counter_rx_fifo_overruns.attr.attr,
	&ecmxf_counter_tx_fifo_overruns.attr.attr,
	&ecmxf_counter_int0_irqs.attr.attr,
	&ecmxf_counter_int1_irqs.attr.attr,
	NULL
};

static const struct attribute_group ecmxf_counter_group = {
	.name = "counters",
	.attrs = ecmxf_counter_attrs,
};

/* The groups of the class device (&ecmxf_dev.dev). */
const struct attribute_group *ecmxf_groups[] = {
	&ecmxf_attr_group,
	&ecmxf_counter_group,
	NULL
};
