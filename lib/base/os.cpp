// SPDX-License-Identifier: MIT
// The OS resources as objects (lib/base/os.hpp).

#include <ecmxf/error.hpp>

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

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

} // namespace ecmxf::detail
