/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * ecmxf-vspi-compat.h - the kernel API differences the test-only virtual
 * SPI controller meets between the kernels it is tested on (Debian's 6.1
 * and 6.12, Documentation/kernel-testing.rst, "The kernel matrix").  Every
 * version test of ecmxf-vspi.c is here; the module's own are in
 * kmod/ecmxf-compat.h.
 *
 * Copyright (C) 2026 The ecmxf authors
 */
#ifndef ECMXF_VSPI_COMPAT_H
#define ECMXF_VSPI_COMPAT_H

#include <linux/platform_device.h>
#include <linux/version.h>

/*
 * VSPI_PLATFORM_REMOVE(name, fn) - define the platform_driver.remove
 * callback @name that calls void @fn(pdev): .remove returns void since
 * 6.11, int before (6.3-6.10 also had .remove_new;
 * 6.1 has only the int form).
 */
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 11, 0)
#define VSPI_PLATFORM_REMOVE(name, fn)				\
	static void name(struct platform_device *pdev)		\
	{							\
		fn(pdev);					\
	}
#else
#define VSPI_PLATFORM_REMOVE(name, fn)				\
	static int name(struct platform_device *pdev)		\
	{							\
		fn(pdev);					\
		return 0;					\
	}
#endif

/*
 * VSPI_IRQ_MOVE_PCNTXT - the status flag that lets an interrupt's affinity
 * change at once, from the writer of /proc/irq/N/smp_affinity. Without it,
 * x86 (GENERIC_PENDING_IRQ) defers the change to the next interrupt's
 * acknowledgment by an APIC, which a software irq_chip never gets. 6.13
 * dropped the flag (only IRQCHIP_MOVE_DEFERRED chips defer there).
 */
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 13, 0)
#define VSPI_IRQ_MOVE_PCNTXT 0
#else
#define VSPI_IRQ_MOVE_PCNTXT IRQ_MOVE_PCNTXT
#endif

#endif /* ECMXF_VSPI_COMPAT_H */
