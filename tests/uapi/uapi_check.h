/* SPDX-License-Identifier: MIT */
/*
 * uapi_check.h - what uapi_c.c (compiled as C11) hands to test_uapi.cpp
 * (compiled as C++20): the layout of <linux/ecmxf.h> as the C compiler sees
 * it, next to the numbers written down in uapi_layout.def.
 */
#ifndef ECMXF_TEST_UAPI_CHECK_H
#define ECMXF_TEST_UAPI_CHECK_H

#include <stddef.h>
#include <linux/ioctl.h>

/* Written down by hand, like the numbers in uapi_layout.def */
#define UAPI_WANT_MAGIC		0xE9
#define UAPI_WANT_VERSION	4

/* The dir argument of UAPI_IOCTL() in uapi_layout.def */
#define UAPI_DIR_NONE		_IOC_NONE
#define UAPI_DIR_R		_IOC_READ
#define UAPI_DIR_W		_IOC_WRITE
#define UAPI_DIR_RW		(_IOC_READ | _IOC_WRITE)

#ifdef __cplusplus
extern "C" {
#endif

struct uapi_struct_layout {
	const char *name;
	size_t size;		/* sizeof as compiled */
	size_t want_size;	/* from uapi_layout.def */
};

struct uapi_field_layout {
	const char *strct;
	const char *field;
	size_t offset;		/* offsetof as compiled */
	size_t size;		/* sizeof the member as compiled */
	size_t want_offset;	/* from uapi_layout.def */
	size_t want_size;
};

struct uapi_ioctl_layout {
	const char *name;
	unsigned long number;	/* the ioctl request number as compiled */
	size_t arg_size;	/* sizeof its argument type, 0 for none */
	unsigned int want_dir;	/* from uapi_layout.def */
	unsigned int want_nr;
};

/* One line of uapi_numbers.def */
struct uapi_number {
	const char *group;
	const char *name;
	unsigned long value;	/* the macro's value as compiled */
	unsigned long want;	/* from uapi_numbers.def */
};

const struct uapi_struct_layout *ecmxf_uapi_c_structs(size_t *count);
const struct uapi_field_layout *ecmxf_uapi_c_fields(size_t *count);
const struct uapi_ioctl_layout *ecmxf_uapi_c_ioctls(size_t *count);
const struct uapi_number *ecmxf_uapi_c_numbers(size_t *count);

#ifdef __cplusplus
}
#endif

#endif /* ECMXF_TEST_UAPI_CHECK_H */
