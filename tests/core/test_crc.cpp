// SPDX-License-Identifier: MIT
// Check values of the four check word types, and the slice-by-8 CRC-32
// against a bit-at-a-time reference written here from the polynomial.

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "ecmxf-proto.h"

namespace {

const char kCheck[] = "123456789";

// Reference: reflected CRC-32, one bit at a time, straight from the definition.
std::uint32_t crc32Bitwise(const std::uint8_t *p, std::size_t n)
{
	std::uint32_t crc = 0xFFFFFFFFu;
	for (std::size_t i = 0; i < n; i++) {
		crc ^= p[i];
		for (int b = 0; b < 8; b++)
			crc = (crc & 1u) ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
	}
	return ~crc;
}

std::uint8_t crc8Bitwise(const std::uint8_t *p, std::size_t n)
{
	std::uint8_t crc = 0;
	for (std::size_t i = 0; i < n; i++) {
		crc = static_cast<std::uint8_t>(crc ^ p[i]);
		for (int b = 0; b < 8; b++) {
			const unsigned c = crc;
			crc = static_cast<std::uint8_t>((c & 0x80u) ? (c << 1) ^ 0x07u : c << 1);
		}
	}
	return crc;
}

std::uint16_t ccittBitwise(const std::uint8_t *p, std::size_t n)
{
	std::uint16_t crc = 0xFFFF;
	for (std::size_t i = 0; i < n; i++) {
		crc = static_cast<std::uint16_t>(crc ^ (p[i] << 8));
		for (int b = 0; b < 8; b++) {
			const unsigned c = crc;
			crc = static_cast<std::uint16_t>((c & 0x8000u) ? (c << 1) ^ 0x1021u : c << 1);
		}
	}
	return crc;
}

} // namespace

TEST_CASE("CRC-32 check value of \"123456789\" is 0xCBF43926", "[crc]")
{
	CHECK(ecmxf_crc32(kCheck, 9) == 0xCBF43926u);
	CHECK(ecmxf_check_word(ECMXF_CHECK_CRC32, kCheck, 9) == 0xCBF43926u);
}

TEST_CASE("CRC-8 check value of \"123456789\" is 0xF4", "[crc]")
{
	CHECK(ecmxf_crc8(kCheck, 9) == 0xF4u);
	CHECK(ecmxf_check_word(ECMXF_CHECK_CRC8, kCheck, 9) == 0xF4u);
}

TEST_CASE("CRC-CCITT-FALSE check value of \"123456789\" is 0x29B1", "[crc]")
{
	CHECK(ecmxf_crc_ccitt(kCheck, 9) == 0x29B1u);
	CHECK(ecmxf_check_word(ECMXF_CHECK_CCITT, kCheck, 9) == 0x29B1u);
}

TEST_CASE("fixed check word is 0x12345678 whatever the bytes", "[crc]")
{
	CHECK(ecmxf_check_word(ECMXF_CHECK_FIXED, kCheck, 9) == 0x12345678u);
	CHECK(ecmxf_check_word(ECMXF_CHECK_FIXED, "", 0) == 0x12345678u);
}

TEST_CASE("CRCs of empty input are their init values, finalised", "[crc]")
{
	CHECK(ecmxf_crc32("", 0) == 0u);
	CHECK(ecmxf_crc8("", 0) == 0u);
	CHECK(ecmxf_crc_ccitt("", 0) == 0xFFFFu);
}

TEST_CASE("CRC-32 (carry-less multiply path where the CPU has it) agrees with the bitwise CRC "
	  "for every length 0..1600 and every alignment", "[crc]")
{
	std::mt19937 rng(777);
	std::vector<std::uint8_t> buf(1600 + 16);
	for (auto &b : buf)
		b = static_cast<std::uint8_t>(rng());
	for (std::size_t off = 0; off < 16; off += 3) {
		for (std::size_t len = 0; len <= 1600; len++) {
			const std::uint8_t *p = buf.data() + off;
			const std::uint32_t want = crc32Bitwise(p, len);
			if (ecmxf_crc32(p, len) != want) {
				FAIL("offset " << off << " length " << len);
			}
		}
	}
	SUCCEED();
}

TEST_CASE("table CRCs agree with bit-at-a-time CRCs at every length and alignment", "[crc]")
{
	std::mt19937 rng(12345);
	std::vector<std::uint8_t> buf(1500 + 8);
	for (auto &b : buf)
		b = static_cast<std::uint8_t>(rng());

	for (std::size_t off = 0; off < 8; off++) {
		for (std::size_t len : {0u, 1u, 7u, 8u, 9u, 15u, 16u, 17u, 63u, 64u, 65u, 136u, 1432u, 1500u}) {
			const std::uint8_t *p = buf.data() + off;
			INFO("offset " << off << " length " << len);
			CHECK(ecmxf_crc32(p, len) == crc32Bitwise(p, len));
			CHECK(ecmxf_crc8(p, len) == crc8Bitwise(p, len));
			CHECK(ecmxf_crc_ccitt(p, len) == ccittBitwise(p, len));
		}
	}
}
