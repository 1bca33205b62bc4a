// SPDX-License-Identifier: MIT
// The file of a packet trace (lib/link/trace_file.hpp).

#include <ecmxf/error.hpp>

#include <cerrno>
#include <cstring>
#include <utility>

#include <stdio.h>

#include "link/trace_file.hpp"

namespace ecmxf::detail {

TraceFile::TraceFile(std::string_view path, std::string_view shownAs, std::size_t bufferSize)
	: path_(shownAs.empty() ? path : shownAs)
{
	f_ = std::fopen(std::string(path).c_str(), "wb");
	if (!f_) {
		const int err = errno;
		std::string m = "cannot create the trace file \"";
		m.append(path_).append("\": ").append(std::strerror(err));
		throw Error(m, err);
	}
	// the C library allocates the buffer at the first write; a failure
	// leaves the default one
	if (bufferSize)
		std::setvbuf(f_, nullptr, _IOFBF, bufferSize);
}

TraceFile::~TraceFile()
{
	if (f_)
		std::fclose(f_);
}

void TraceFile::put(const void *p, std::size_t n) noexcept
{
	if (!f_ || err_)
		return;
	// one thread writes a trace: the stream's lock is not needed
#if defined(__GLIBC__)
	if (::fwrite_unlocked(p, 1, n, f_) != n)
#else
	if (std::fwrite(p, 1, n, f_) != n)
#endif
		err_ = errno ? errno : EIO;
}

void TraceFile::close()
{
	if (!f_)
		return;
	std::FILE *f = std::exchange(f_, nullptr);
	if (std::fclose(f) != 0 && !err_)
		err_ = errno ? errno : EIO;
	if (err_) {
		std::string m = "writing the trace file \"";
		m.append(path_).append("\" failed: ").append(std::strerror(err_));
		throw Error(m, err_);
	}
}

} // namespace ecmxf::detail
