/* SPDX-License-Identifier: MIT */
/*
 * uapi_c.c - <linux/ecmxf.h> as a C11 compiler sees it.
 *
 * Every struct size, field offset and field size, and every ioctl number's
 * type, number, direction and size bits, is checked with _Static_assert
 * against uapi_layout.def, so a layout change fails the build.  This file is
 * compiled with -Wpadded -Werror=padded, which turns any implicit hole in a
 * uAPI struct into an error, and (where the compiler can) a second time with
 * -m32 (see CMakeLists.txt) so the same numbers are proven for i386, where a
 * plain __u64 is only 4-aligned inside structs.
 *
 * The protocol numbers (command codes, header bits, EtherCAT states,
 * interrupt flags) are checked the same way against uapi_numbers.def.
 *
 * It also exports the layout and the numbers as tables, which test_uapi.cpp compares at
 * runtime with the layout the C++ compiler sees.
 */
#include <stddef.h>

#include <linux/ecmxf.h>

#include "uapi_check.h"

_Static_assert(ECMXF_UAPI_VERSION == UAPI_WANT_VERSION, "ECMXF_UAPI_VERSION changed");
_Static_assert(ECMXF_IOC_MAGIC == UAPI_WANT_MAGIC, "ECMXF_IOC_MAGIC changed");

#if defined(__i386__)
/* Proof that this really is the i386 ABI the __aligned_u64 fields guard against */
struct uapi_i386_probe {
	__u32 a;
	__u64 b;
};
_Static_assert(offsetof(struct uapi_i386_probe, b) == 4,
	       "-m32 build does not use the i386 ABI (plain __u64 would be 4-aligned)");
#endif

/* ---- compile-time checks ---------------------------------------------- */

#define UAPI_STRUCT(s, size)							\
	_Static_assert(sizeof(struct s) == (size),				\
		       "sizeof(struct " #s ") != " #size);			\
	_Static_assert(sizeof(struct s) % 8 == 0,				\
		       "sizeof(struct " #s ") is not a multiple of 8");
#define UAPI_FIELD(s, f, off, size)						\
	_Static_assert(offsetof(struct s, f) == (off),				\
		       "offsetof(struct " #s ", " #f ") != " #off);		\
	_Static_assert(sizeof(((struct s *)0)->f) == (size),			\
		       "sizeof(struct " #s "." #f ") != " #size);
#define UAPI_IOCTL(name, dir, nr, type)						\
	_Static_assert(_IOC_TYPE(name) == UAPI_WANT_MAGIC, #name ": wrong magic"); \
	_Static_assert(_IOC_NR(name) == (nr), #name ": number != " #nr);	\
	_Static_assert(_IOC_DIR(name) == UAPI_DIR_##dir, #name ": direction is not " #dir); \
	_Static_assert(_IOC_SIZE(name) == sizeof(type), #name ": size bits != sizeof(" #type ")");
#define UAPI_IOCTL_NOARG(name, nr)						\
	_Static_assert(_IOC_TYPE(name) == UAPI_WANT_MAGIC, #name ": wrong magic"); \
	_Static_assert(_IOC_NR(name) == (nr), #name ": number != " #nr);	\
	_Static_assert(_IOC_DIR(name) == _IOC_NONE, #name ": takes an argument"); \
	_Static_assert(_IOC_SIZE(name) == 0, #name ": size bits are not 0");
#include "uapi_layout.def"

/*
 * Each number as the manual gives it, and small enough for the header field
 * it goes in (8-bit code, control, status and state bytes, the 16-bit word
 * at 0x08, the 32-bit interrupt word).
 */
#define UAPI_WIDTH_CMD		0xFFUL
#define UAPI_WIDTH_RSV		0xFFFFUL
#define UAPI_WIDTH_CTL		0xFFUL
#define UAPI_WIDTH_ERR		0xFFUL
#define UAPI_WIDTH_ERRMASK	0xFFUL
#define UAPI_WIDTH_STS		0xFFUL
#define UAPI_WIDTH_STSMASK	0xFFUL
#define UAPI_WIDTH_ECAT		0xFFUL
#define UAPI_WIDTH_INT		0xFFFFFFFFUL
#define UAPI_NUMBER(group, name, value)						\
	_Static_assert((name) == (value), #name " != " #value " (the manual's number)"); \
	_Static_assert((unsigned long)(name) <= UAPI_WIDTH_##group,		\
		       #name " does not fit its header field");
#include "uapi_numbers.def"

/* ---- the same, as tables for the runtime test ------------------------- */

static const struct uapi_struct_layout structs[] = {
#define UAPI_STRUCT(s, size) { #s, sizeof(struct s), (size) },
#include "uapi_layout.def"
};

static const struct uapi_field_layout fields[] = {
#define UAPI_FIELD(s, f, off, size)						\
	{ #s, #f, offsetof(struct s, f), sizeof(((struct s *)0)->f), (off), (size) },
#include "uapi_layout.def"
};

static const struct uapi_ioctl_layout ioctls[] = {
#define UAPI_IOCTL(name, dir, nr, type)						\
	{ #name, name, sizeof(type), UAPI_DIR_##dir, (nr) },
#define UAPI_IOCTL_NOARG(name, nr)						\
	{ #name, name, 0, UAPI_DIR_NONE, (nr) },
#include "uapi_layout.def"
};

static const struct uapi_number numbers[] = {
#define UAPI_NUMBER(group, name, value)						\
	{ #group, #name, (unsigned long)(name), (unsigned long)(value) },
#include "uapi_numbers.def"
};

const struct uapi_struct_layout *ecmxf_uapi_c_structs(size_t *count)
{
	*count = sizeof(structs) / sizeof(structs[0]);
	return structs;
}

const struct uapi_field_layout *ecmxf_uapi_c_fields(size_t *count)
{
	*count = sizeof(fields) / sizeof(fields[0]);
	return fields;
}

const struct uapi_ioctl_layout *ecmxf_uapi_c_ioctls(size_t *count)
{
	*count = sizeof(ioctls) / sizeof(ioctls[0]);
	return ioctls;
}

const struct uapi_number *ecmxf_uapi_c_numbers(size_t *count)
{
	*count = sizeof(numbers) / sizeof(numbers[0]);
	return numbers;
}
