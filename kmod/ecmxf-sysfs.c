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
 *   variant        the master's series: ECM-XF, ECM-XFL, ECM-XFU or ECM-XM
 *                  (from the compatible or the SPI id)
 *   counters/...   one file per field of struct ecmxf_counters
 *
 * One table each (the ECMXF_ATTR() and ECMXF_COUNTER_ATTR() lines) makes
 * the files; one show function per table formats them.  Everything but
 * claim_pid comes from the snapshot the worker publishes (ecmxf_get_snap())
 * or is a word set at probe; claim_pid takes the claim's own spinlock
 * (ecmxf_claim_pid_vnr()).  So no reader takes a lock the real-time worker
 * takes, however often it reads.
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

/* the attributes of the class device; ecmxf_attr_show() formats them */
enum ecmxf_attr_id {
	ECMXF_ATTR_FW_VERSION,
	ECMXF_ATTR_FW_INFO,
	ECMXF_ATTR_DATA_SIZE,
	ECMXF_ATTR_PACKET_SIZE,
	ECMXF_ATTR_CHECK_TYPE,
	ECMXF_ATTR_CRC_COVERAGE,
	ECMXF_ATTR_INT0,
	ECMXF_ATTR_INT1,
	ECMXF_ATTR_OPEN_COUNT,
	ECMXF_ATTR_CLAIM_PID,
	ECMXF_ATTR_RING_SKIPPED,
	ECMXF_ATTR_RING_FAILURES,
	ECMXF_ATTR_VARIANT,
};

static ssize_t ecmxf_attr_show(struct device *dev,
			       struct device_attribute *attr, char *buf)
{
	struct dev_ext_attribute *ea = container_of(attr,
						    struct dev_ext_attribute,
						    attr);
	struct ecmxf_dev *edev = ecmxf_from_dev(dev);
	struct ecmxf_snap v;

	ecmxf_get_snap(edev, &v);
	switch ((uintptr_t)ea->var) {
	case ECMXF_ATTR_FW_VERSION:
		if (!v.fw_valid)
			return sysfs_emit(buf, "unknown\n");
		return sysfs_emit(buf, "%u\n", v.fw_version);
	case ECMXF_ATTR_FW_INFO:
		return sysfs_emit(buf, "%*phN\n", (int)sizeof(v.fw_info),
				  v.fw_info);
	case ECMXF_ATTR_DATA_SIZE:
		return sysfs_emit(buf, "%u\n", v.data_size);
	case ECMXF_ATTR_PACKET_SIZE:
		return sysfs_emit(buf, "%u\n",
				  (unsigned int)ECMXF_PKT_SIZE(v.data_size));
	case ECMXF_ATTR_CHECK_TYPE:
		return sysfs_emit(buf, "%s\n", ecmxf_check_name(v.check));
	case ECMXF_ATTR_CRC_COVERAGE:
		return sysfs_emit(buf, "%s\n", ecmxf_cover_name(v.cover));
	case ECMXF_ATTR_INT0:
		return sysfs_emit(buf, "%s\n", edev->irq.int0_irq ? "wired" : "absent");
	case ECMXF_ATTR_INT1:
		return sysfs_emit(buf, "%s\n", edev->irq.int1_irq ? "wired" : "absent");
	case ECMXF_ATTR_OPEN_COUNT:
		/* one word written under the lock: no lock needed to read it */
		return sysfs_emit(buf, "%u\n", READ_ONCE(edev->open_count));
	case ECMXF_ATTR_CLAIM_PID:
		return sysfs_emit(buf, "%d\n", ecmxf_claim_pid_vnr(edev));
	case ECMXF_ATTR_RING_SKIPPED:
		return sysfs_emit(buf, "%llu\n",
				  (unsigned long long)v.ring_skipped);
	case ECMXF_ATTR_RING_FAILURES:
		return sysfs_emit(buf, "%llu\n",
				  (unsigned long long)v.ring_failures);
	case ECMXF_ATTR_VARIANT:
		return sysfs_emit(buf, "%s\n", edev->cfg.variant->name);
	}
	return -EIO;
}

#define ECMXF_ATTR(_name, _id)						\
static struct dev_ext_attribute ecmxf_attr_##_name = {			\
	.attr = __ATTR(_name, 0444, ecmxf_attr_show, NULL),		\
	.var = (void *)(_id),						\
}

ECMXF_ATTR(fw_version, ECMXF_ATTR_FW_VERSION);
ECMXF_ATTR(fw_info, ECMXF_ATTR_FW_INFO);
ECMXF_ATTR(data_size, ECMXF_ATTR_DATA_SIZE);
ECMXF_ATTR(packet_size, ECMXF_ATTR_PACKET_SIZE);
ECMXF_ATTR(check_type, ECMXF_ATTR_CHECK_TYPE);
ECMXF_ATTR(crc_coverage, ECMXF_ATTR_CRC_COVERAGE);
ECMXF_ATTR(int0, ECMXF_ATTR_INT0);
ECMXF_ATTR(int1, ECMXF_ATTR_INT1);
ECMXF_ATTR(open_count, ECMXF_ATTR_OPEN_COUNT);
ECMXF_ATTR(claim_pid, ECMXF_ATTR_CLAIM_PID);
ECMXF_ATTR(ring_skipped, ECMXF_ATTR_RING_SKIPPED);
ECMXF_ATTR(ring_failures, ECMXF_ATTR_RING_FAILURES);
ECMXF_ATTR(variant, ECMXF_ATTR_VARIANT);

static struct attribute *ecmxf_attrs[] = {
	&ecmxf_attr_fw_version.attr.attr,
	&ecmxf_attr_fw_info.attr.attr,
	&ecmxf_attr_data_size.attr.attr,
	&ecmxf_attr_packet_size.attr.attr,
	&ecmxf_attr_check_type.attr.attr,
	&ecmxf_attr_crc_coverage.attr.attr,
	&ecmxf_attr_int0.attr.attr,
	&ecmxf_attr_int1.attr.attr,
	&ecmxf_attr_open_count.attr.attr,
	&ecmxf_attr_claim_pid.attr.attr,
	&ecmxf_attr_ring_skipped.attr.attr,
	&ecmxf_attr_ring_failures.attr.attr,
	&ecmxf_attr_variant.attr.attr,
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

/* every field of struct ecmxf_counters but the reserved words has a file */
static_assert(ARRAY_SIZE(ecmxf_counter_attrs) - 1 ==
	      offsetof(struct ecmxf_counters, reserved) / sizeof(u64));

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
