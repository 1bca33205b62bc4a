// SPDX-License-Identifier: MIT
// <linux/ecmxf.h> as a C++20 compiler sees it: the same compile-time
// checks as uapi_c.c against the hand-written uapi_layout.def, then runtime
// checks that every struct is tiled by its fields with no hole, that the C
// and the C++ compiler agree, and that the ioctl numbers and flag bits are
// what Documentation/uapi.rst says; the protocol numbers (command codes,
// header bits, states, interrupt flags) against the manuals' numbers in
// uapi_numbers.def.

#include <catch2/catch.hpp>

#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <linux/ecmxf.h>

#include "uapi_check.h"

static_assert(ECMXF_UAPI_VERSION == UAPI_WANT_VERSION, "ECMXF_UAPI_VERSION changed");
static_assert(ECMXF_IOC_MAGIC == UAPI_WANT_MAGIC, "ECMXF_IOC_MAGIC changed");

// ---- compile-time checks ------------------------------------------------

#define UAPI_STRUCT(s, size)                                                   \
	static_assert(sizeof(s) == (size), "sizeof(struct " #s ") != " #size); \
	static_assert(sizeof(s) % 8 == 0, "sizeof(struct " #s ") is not a multiple of 8");
#define UAPI_FIELD(s, f, off, size)                                            \
	static_assert(offsetof(s, f) == (off), "offsetof(" #s ", " #f ") != " #off); \
	static_assert(sizeof(s::f) == (size), "sizeof(" #s "." #f ") != " #size);
#define UAPI_IOCTL(name, dir, nr, type)                                        \
	static_assert(_IOC_TYPE(name) == UAPI_WANT_MAGIC, #name ": wrong magic"); \
	static_assert(_IOC_NR(name) == (nr), #name ": number != " #nr);        \
	static_assert(_IOC_DIR(name) == UAPI_DIR_##dir, #name ": direction is not " #dir); \
	static_assert(_IOC_SIZE(name) == sizeof(type), #name ": size bits != sizeof(" #type ")");
#define UAPI_IOCTL_NOARG(name, nr)                                             \
	static_assert(_IOC_TYPE(name) == UAPI_WANT_MAGIC, #name ": wrong magic"); \
	static_assert(_IOC_NR(name) == (nr), #name ": number != " #nr);        \
	static_assert(_IOC_DIR(name) == _IOC_NONE, #name ": takes an argument"); \
	static_assert(_IOC_SIZE(name) == 0, #name ": size bits are not 0");
#include "uapi_layout.def"

#define UAPI_NUMBER(group, name, value) static_assert((name) == (value), #name " != " #value);
#include "uapi_numbers.def"

// ecmxf_submit promises the first 56 bytes of ecmxf_cmd (rx_ptr is reserved
// there), so one function can fill both.
#define SAME_PREFIX(f)                                                         \
	static_assert(offsetof(ecmxf_submit, f) == offsetof(ecmxf_cmd, f) &&   \
		      sizeof(ecmxf_submit::f) == sizeof(ecmxf_cmd::f),         \
		      "ecmxf_submit." #f " is not where ecmxf_cmd." #f " is");
SAME_PREFIX(hdr)
SAME_PREFIX(tx_ptr)
static_assert(offsetof(ecmxf_submit, reserved_ptr) == offsetof(ecmxf_cmd, rx_ptr),
	      "ecmxf_submit.reserved_ptr is not where ecmxf_cmd.rx_ptr is");
SAME_PREFIX(tx_len)
SAME_PREFIX(rx_size)
SAME_PREFIX(timeout_us)
SAME_PREFIX(flags)
#undef SAME_PREFIX

namespace {

// ---- the same, as tables ------------------------------------------------

const std::vector<uapi_struct_layout> kStructs = {
#define UAPI_STRUCT(s, size) { #s, sizeof(s), (size) },
#include "uapi_layout.def"
};

const std::vector<uapi_field_layout> kFields = {
#define UAPI_FIELD(s, f, off, size) { #s, #f, offsetof(s, f), sizeof(s::f), (off), (size) },
#include "uapi_layout.def"
};

const std::vector<uapi_ioctl_layout> kIoctls = {
#define UAPI_IOCTL(name, dir, nr, type) { #name, name, sizeof(type), UAPI_DIR_##dir, (nr) },
#define UAPI_IOCTL_NOARG(name, nr) { #name, name, 0, UAPI_DIR_NONE, (nr) },
#include "uapi_layout.def"
};

struct Number {
	std::string group;
	std::string name;
	unsigned long value;
	unsigned long want;
};

const std::vector<Number> kNumbers = {
#define UAPI_NUMBER(group, name, value)                                        \
	{ #group, #name, static_cast<unsigned long>(name), static_cast<unsigned long>(value) },
#include "uapi_numbers.def"
};

std::vector<Number> group(const std::string &g)
{
	std::vector<Number> v;
	for (const auto &n : kNumbers)
		if (n.group == g)
			v.push_back(n);
	return v;
}

template <typename T>
std::vector<T> fromC(const T *(*get)(std::size_t *))
{
	std::size_t n = 0;
	const T *p = get(&n);
	return std::vector<T>(p, p + n);
}

std::size_t structSize(const std::vector<uapi_struct_layout> &structs, const std::string &name)
{
	for (const auto &s : structs)
		if (name == s.name)
			return s.size;
	FAIL("struct " << name << " has fields in uapi_layout.def but no UAPI_STRUCT line");
	return 0;
}

// Fields must follow each other without a gap and end at sizeof: no byte of
// a uAPI struct is an implicit hole, and no field is missing from the list.
void checkTiling(const std::vector<uapi_struct_layout> &structs,
		 const std::vector<uapi_field_layout> &fields)
{
	std::set<std::string> seen;
	std::string cur;
	std::size_t end = 0;
	auto finish = [&]() {
		if (cur.empty())
			return;
		INFO("struct " << cur);
		CHECK(end == structSize(structs, cur));
	};
	for (const auto &f : fields) {
		if (cur != f.strct) {
			finish();
			cur = f.strct;
			INFO("struct " << cur << " is listed in two places");
			CHECK(seen.insert(cur).second);
			end = 0;
		}
		INFO("struct " << f.strct << ", field " << f.field);
		CHECK(f.offset == end);
		end = f.offset + f.size;
	}
	finish();
	CHECK(seen.size() == structs.size());
}

// True when no two masks share a bit and none is zero.
bool disjointBits(std::initializer_list<std::uint64_t> masks)
{
	std::uint64_t all = 0;
	for (std::uint64_t m : masks) {
		if (m == 0 || (all & m) != 0)
			return false;
		all |= m;
	}
	return true;
}

} // namespace

TEST_CASE("uAPI struct sizes are multiples of 8 and match the documented layout", "[uapi]")
{
	REQUIRE(kStructs.size() == 12);
	for (const auto &s : kStructs) {
		INFO("struct " << s.name);
		CHECK(s.size % 8 == 0);
		CHECK(s.size == s.want_size);
	}
	REQUIRE(kFields.size() == 138);
	for (const auto &f : kFields) {
		INFO("struct " << f.strct << ", field " << f.field);
		CHECK(f.offset == f.want_offset);
		CHECK(f.size == f.want_size);
	}
}

TEST_CASE("uAPI fields tile every struct with no implicit hole", "[uapi]")
{
	SECTION("as compiled by C++") { checkTiling(kStructs, kFields); }
	SECTION("as compiled by C") {
		checkTiling(fromC(ecmxf_uapi_c_structs), fromC(ecmxf_uapi_c_fields));
	}
}

TEST_CASE("uAPI layout is the same for the C and the C++ compiler", "[uapi]")
{
	const auto cStructs = fromC(ecmxf_uapi_c_structs);
	REQUIRE(cStructs.size() == kStructs.size());
	for (std::size_t i = 0; i < cStructs.size(); i++) {
		INFO("struct " << kStructs[i].name);
		CHECK(std::string(cStructs[i].name) == kStructs[i].name);
		CHECK(cStructs[i].size == kStructs[i].size);
	}

	const auto cFields = fromC(ecmxf_uapi_c_fields);
	REQUIRE(cFields.size() == kFields.size());
	for (std::size_t i = 0; i < cFields.size(); i++) {
		INFO("struct " << kFields[i].strct << ", field " << kFields[i].field);
		CHECK(std::string(cFields[i].field) == kFields[i].field);
		CHECK(cFields[i].offset == kFields[i].offset);
		CHECK(cFields[i].size == kFields[i].size);
	}

	const auto cIoctls = fromC(ecmxf_uapi_c_ioctls);
	REQUIRE(cIoctls.size() == kIoctls.size());
	for (std::size_t i = 0; i < cIoctls.size(); i++) {
		INFO(kIoctls[i].name);
		CHECK(cIoctls[i].number == kIoctls[i].number);
		CHECK(cIoctls[i].arg_size == kIoctls[i].arg_size);
	}
}

TEST_CASE("uAPI ioctl numbers encode the magic, a unique number, the direction and the argument size",
	  "[uapi]")
{
	REQUIRE(kIoctls.size() == 9);
	std::set<unsigned long> numbers;
	std::set<unsigned int> nrs;
	for (const auto &io : kIoctls) {
		INFO(io.name);
		CHECK(_IOC_TYPE(io.number) == UAPI_WANT_MAGIC);
		CHECK(_IOC_NR(io.number) == io.want_nr);
		CHECK(_IOC_DIR(io.number) == io.want_dir);
		CHECK(_IOC_SIZE(io.number) == io.arg_size);
		CHECK(numbers.insert(io.number).second);
		CHECK(nrs.insert(io.want_nr).second);
		// Everything sits in the block the header reserves.
		CHECK(io.want_nr <= 0x1Fu);
	}
}

TEST_CASE("uAPI flag bits do not overlap and ring mmap offsets are page aligned", "[uapi]")
{
	CHECK(disjointBits({ ECMXF_CMD_F_NO_AUTO_CLEAR, ECMXF_CMD_F_FETCH, ECMXF_CMD_F_FETCHED }));
	CHECK(disjointBits({ ECMXF_DEVINFO_F_INT0, ECMXF_DEVINFO_F_INT1, ECMXF_DEVINFO_F_FW_VERSION,
			     ECMXF_DEVINFO_F_CLAIMED, ECMXF_DEVINFO_F_CLAIM_MINE, ECMXF_DEVINFO_F_RINGS }));
	CHECK(disjointBits({ ECMXF_RESET_F_ASYNC_CMD, ECMXF_RESET_F_WARM, ECMXF_RESET_F_LINK }));
	// These are the ASYNCCMD_RESET parameter bits of the manual: 1, 2, 4.
	CHECK(ECMXF_RESET_ASYNC_CLEAR_BUSY == 1u);
	CHECK(ECMXF_RESET_ASYNC_SKIP_LINK == 2u);
	CHECK(ECMXF_RESET_ASYNC_ABANDON == 4u);
	CHECK(disjointBits({ ECMXF_RING_F_POLL_OUT, ECMXF_RING_F_POLL_IN, ECMXF_RING_F_WKC_NEXT, ECMXF_RING_F_FIFO_NEXT }));
	CHECK(disjointBits({ ECMXF_RING_S_ACTIVE, ECMXF_RING_S_ERROR }));

	// mmap offsets must be multiples of the largest page size in use
	// (64 KiB on some arm64/ppc64 kernels) and must differ.
	CHECK(ECMXF_RING_OFF_OUT % 65536u == 0);
	CHECK(ECMXF_RING_OFF_IN % 65536u == 0);
	CHECK(ECMXF_RING_OFF_OUT != ECMXF_RING_OFF_IN);
	// ... and fit a 32-bit off_t.
	CHECK(ECMXF_RING_OFF_IN <= 0x7FFFFFFFu);
}

TEST_CASE("uAPI protocol numbers are the manuals' and the C compiler sees the same", "[uapi]")
{
	// one line per macro of each group; check_numbers.sh proves that the
	// header has no ECMXF_{CMD,RSV,CTL,ERR,STS,ECAT,INT}_ macro missing here
	CHECK(group("CMD").size() == 67);
	CHECK(group("RSV").size() == 3);
	CHECK(group("CTL").size() == 7);
	CHECK(group("ERR").size() == 7);
	CHECK(group("STS").size() == 6);
	CHECK(group("ECAT").size() == 7);
	CHECK(group("INT").size() == 6);
	for (const auto &n : kNumbers) {
		INFO(n.name);
		CHECK(n.value == n.want);
	}

	std::size_t count = 0;
	const uapi_number *c = ecmxf_uapi_c_numbers(&count);
	REQUIRE(count == kNumbers.size());
	for (std::size_t i = 0; i < count; i++) {
		INFO(kNumbers[i].name);
		CHECK(std::string(c[i].name) == kNumbers[i].name);
		CHECK(c[i].value == kNumbers[i].value);
		CHECK(c[i].want == kNumbers[i].want);
	}
}

TEST_CASE("uAPI command codes are unique, header bits are single bits that do not overlap", "[uapi]")
{
	std::set<unsigned long> codes;
	for (const auto &n : group("CMD")) {
		INFO(n.name);
		CHECK(codes.insert(n.value).second);
		CHECK(n.value <= 0xFFu);
	}
	for (const char *g : { "RSV", "CTL", "ERR", "STS", "INT" }) {
		INFO("group " << g);
		std::uint64_t all = 0;
		for (const auto &n : group(g)) {
			INFO(n.name);
			CHECK(n.value != 0);
			CHECK((n.value & (n.value - 1)) == 0); // one bit
			CHECK((all & n.value) == 0);
			all |= n.value;
		}
	}
	// the check-type field sits below the ECM status bits
	CHECK((ECMXF_STS_CHECK_MASK & (ECMXF_STS_DC_STABLE | ECMXF_STS_ETH_INIT | ECMXF_STS_PDO_CONFIGURED |
				       ECMXF_STS_NOP | ECMXF_STS_FIFO_EN | ECMXF_STS_BUSY)) == 0);
	// each clear bit of the control byte clears the error bit of the same number
	CHECK(ECMXF_CTL_CLR_ASYNC_ERR == ECMXF_ERR_ASYNC);
	CHECK(ECMXF_CTL_CLR_SPI_ERR == ECMXF_ERR_SPI);
	CHECK(ECMXF_CTL_CLR_FIFO_ERR == ECMXF_ERR_FIFO);
	CHECK(ECMXF_CTL_CLR_SPI_CRC_ERR == ECMXF_ERR_SPI_CRC);
	CHECK(ECMXF_CTL_CLR_CMD_ERR == ECMXF_ERR_CMD);
	// the fault mask is the error bits that report a fault, not the link bits
	CHECK(ECMXF_ERR_FAULT_MASK ==
	      (ECMXF_ERR_ASYNC | ECMXF_ERR_SPI | ECMXF_ERR_FIFO | ECMXF_ERR_SPI_CRC | ECMXF_ERR_CMD));
	CHECK((ECMXF_ERR_FAULT_MASK & (ECMXF_ERR_LINK_HW | ECMXF_ERR_LINK_SW)) == 0);
	// the header fields these bits go in
	CHECK(sizeof(ecmxf_cmd_header::rsv_word) == 2);
	CHECK(sizeof(ecmxf_cmd_header::control) == 1);
	CHECK(sizeof(ecmxf_rsp_header::err_status) == 1);
	CHECK(sizeof(ecmxf_rsp_header::ecm_status) == 1);
	CHECK(sizeof(ecmxf_cmd_header::int_clear) == 4);
	CHECK(sizeof(ecmxf_rsp_header::int_flags) == 4);
}
