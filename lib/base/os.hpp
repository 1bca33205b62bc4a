// SPDX-License-Identifier: MIT
// Internal: the operating system's resources as objects that own them (a
// file descriptor, a memory mapping) and the one way the library turns a
// failed system call into an ecmxf::Error.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

#include <time.h>

#include <chrono>

namespace ecmxf::detail {

/// Throws ecmxf::Error("<what>: <strerror(err)>", err).
[[noreturn]] void throwErrno(const std::string &what, int err);

/// Writes @p data as the file @p path, whole or not at all: into a
/// temporary file beside it (same folder), flushed, then renamed over
/// @p path, so a reader never sees half a file and a failure leaves what
/// was there. A @p path that exists and is not a regular file (a device,
/// /dev/full, a FIFO) is written in place. Throws ecmxf::Error naming
/// @p path and the errno (EACCES, ENOSPC, ENOENT...); the temporary file
/// is removed on a failure.
void writeFileWhole(const std::string &path, std::string_view data);

/// An open file descriptor, closed with the object.
class FileDescriptor
{
public:
	FileDescriptor() noexcept = default;
	explicit FileDescriptor(int fd) noexcept : fd_(fd) {}
	FileDescriptor(FileDescriptor &&o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
	FileDescriptor &operator=(FileDescriptor &&o) noexcept
	{
		if (this != &o)
			reset(std::exchange(o.fd_, -1));
		return *this;
	}
	FileDescriptor(const FileDescriptor &) = delete;
	FileDescriptor &operator=(const FileDescriptor &) = delete;
	~FileDescriptor() { reset(); }

	[[nodiscard]] int get() const noexcept { return fd_; }
	[[nodiscard]] bool valid() const noexcept { return fd_ >= 0; }
	/// Gives the descriptor up without closing it (the caller closed it).
	int release() noexcept { return std::exchange(fd_, -1); }
	/// Closes the descriptor held (if any) and holds @p fd.
	void reset(int fd = -1) noexcept;

private:
	int fd_ = -1;
};

/// A shared memory mapping of a file, unmapped with the object.
class Mapping
{
public:
	Mapping() noexcept = default;
	/// mmap(@p length, PROT_READ | PROT_WRITE, MAP_SHARED, @p fd,
	/// @p offset); throws via throwErrno("<what>") when it fails.
	Mapping(int fd, std::size_t length, long offset, const std::string &what);
	Mapping(Mapping &&o) noexcept
		: addr_(std::exchange(o.addr_, nullptr)), len_(std::exchange(o.len_, 0))
	{
	}
	Mapping &operator=(Mapping &&o) noexcept;
	Mapping(const Mapping &) = delete;
	Mapping &operator=(const Mapping &) = delete;
	~Mapping() { reset(); }

	[[nodiscard]] void *get() const noexcept { return addr_; }
	[[nodiscard]] std::size_t size() const noexcept { return len_; }
	void reset() noexcept;

private:
	void *addr_ = nullptr;
	std::size_t len_ = 0;
};

/// Sleeps until CLOCK_MONOTONIC (std::chrono::steady_clock on Linux) reads
/// @p deadline: one absolute clock_nanosleep() (again after a signal).
/// Returns at once when the deadline has passed.
inline void sleepUntilMonotonic(std::chrono::nanoseconds deadline) noexcept
{
	if (deadline.count() <= 0)
		return;
	timespec ts{};
	ts.tv_sec = static_cast<time_t>(deadline.count() / 1'000'000'000);
	ts.tv_nsec = static_cast<long>(deadline.count() % 1'000'000'000);
	while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
	}
}

} // namespace ecmxf::detail
