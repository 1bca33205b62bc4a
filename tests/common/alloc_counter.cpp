// SPDX-License-Identifier: MIT
// The counting global operator new/delete of alloc_counter.hpp.

#include "alloc_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<std::uint64_t> gAllocs{ 0 };

void *counted(std::size_t n)
{
	gAllocs.fetch_add(1, std::memory_order_relaxed);
	if (void *p = std::malloc(n ? n : 1))
		return p;
	throw std::bad_alloc();
}

void *countedAligned(std::size_t n, std::align_val_t a)
{
	gAllocs.fetch_add(1, std::memory_order_relaxed);
	const auto al = static_cast<std::size_t>(a);
	if (void *p = std::aligned_alloc(al, (n + al - 1) / al * al))
		return p;
	throw std::bad_alloc();
}
} // namespace

void *operator new(std::size_t n)
{
	return counted(n);
}
void *operator new[](std::size_t n)
{
	return counted(n);
}
void *operator new(std::size_t n, const std::nothrow_t &) noexcept
{
	gAllocs.fetch_add(1, std::memory_order_relaxed);
	return std::malloc(n ? n : 1);
}
void *operator new[](std::size_t n, const std::nothrow_t &) noexcept
{
	gAllocs.fetch_add(1, std::memory_order_relaxed);
	return std::malloc(n ? n : 1);
}
void *operator new(std::size_t n, std::align_val_t a)
{
	return countedAligned(n, a);
}
void *operator new[](std::size_t n, std::align_val_t a)
{
	return countedAligned(n, a);
}
void operator delete(void *p) noexcept
{
	std::free(p);
}
void operator delete[](void *p) noexcept
{
	std::free(p);
}
void operator delete(void *p, std::size_t) noexcept
{
	std::free(p);
}
void operator delete[](void *p, std::size_t) noexcept
{
	std::free(p);
}
void operator delete(void *p, std::align_val_t) noexcept
{
	std::free(p);
}
void operator delete[](void *p, std::align_val_t) noexcept
{
	std::free(p);
}
void operator delete(void *p, std::size_t, std::align_val_t) noexcept
{
	std::free(p);
}
void operator delete[](void *p, std::size_t, std::align_val_t) noexcept
{
	std::free(p);
}

std::uint64_t ecmxf_test::allocations() noexcept
{
	return gAllocs.load(std::memory_order_relaxed);
}
