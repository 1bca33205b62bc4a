// SPDX-License-Identifier: MIT
// The OS resources as objects (lib/base/os.hpp).

#include <ecmxf/error.hpp>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "base/os.hpp"

namespace ecmxf::detail {

void throwErrno(const std::string &what, int err)
{
	std::string m = what;
	m.append(": ").append(std::strerror(err));
	throw Error(m, err);
}

void FileDescriptor::reset(int fd) noexcept
{
	if (fd_ >= 0)
		::close(fd_);
	fd_ = fd;
}

Mapping::Mapping(int fd, std::size_t length, long offset, const std::string &what)
{
	void *p = ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset);
	if (p == MAP_FAILED)
		throwErrno(what, errno);
	addr_ = p;
	len_ = length;
}

Mapping &Mapping::operator=(Mapping &&o) noexcept
{
	if (this != &o) {
		reset();
		addr_ = std::exchange(o.addr_, nullptr);
		len_ = std::exchange(o.len_, 0);
	}
	return *this;
}

void Mapping::reset() noexcept
{
	if (addr_)
		::munmap(addr_, len_);
	addr_ = nullptr;
	len_ = 0;
}

namespace {

/// All of @p data to @p fd; the errno of the first failure, else 0.
int writeAll(int fd, std::string_view data) noexcept
{
	while (!data.empty()) {
		const ssize_t n = ::write(fd, data.data(), data.size());
		if (n < 0) {
			if (errno == EINTR)
				continue;
			return errno;
		}
		if (n == 0)
			return ENOSPC;
		data.remove_prefix(static_cast<std::size_t>(n));
	}
	return 0;
}

} // namespace

void writeFileWhole(const std::string &path, std::string_view data)
{
	struct stat st{};
	if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
		// a device or a FIFO: no rename over it, written in place
		FileDescriptor fd(::open(path.c_str(), O_WRONLY | O_CLOEXEC));
		if (!fd.valid())
			throwErrno("writing " + path, errno);
		if (const int err = writeAll(fd.get(), data))
			throwErrno("writing " + path, err);
		const int c = ::close(fd.get());
		const int err = c ? errno : 0;
		(void)fd.release();
		if (c && err != EINTR)
			throwErrno("writing " + path, err);
		return;
	}
	std::string tmpl = path + ".XXXXXX";
	std::vector<char> name(tmpl.begin(), tmpl.end());
	name.push_back('\0');
	FileDescriptor fd(::mkostemp(name.data(), O_CLOEXEC));
	if (!fd.valid())
		throwErrno("writing " + path, errno);
	const std::string tmp(name.data());
	int err = writeAll(fd.get(), data);
	if (!err && ::fchmod(fd.get(), 0644) != 0)
		err = errno;
	if (!err && ::fsync(fd.get()) != 0 && errno != EINVAL && errno != EROFS)
		err = errno;
	const int c = ::close(fd.get());
	(void)fd.release();
	if (!err && c != 0 && errno != EINTR)
		err = errno;
	if (!err && ::rename(tmp.c_str(), path.c_str()) != 0)
		err = errno;
	if (err) {
		(void)::unlink(tmp.c_str());
		throwErrno("writing " + path, err);
	}
}

} // namespace ecmxf::detail
