// SPDX-License-Identifier: MIT
// Internal: the file of a packet trace, shared by the text trace writer
// (TraceWriter) and the pcapng block writer (PcapngWriter): created or
// truncated with an error naming it, written without throwing (the first
// failed write remembered), closed with that failure reported.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace ecmxf::detail {

class TraceFile
{
public:
	/// Creates or truncates @p path. Throws ecmxf::Error with @p shownAs
	/// (the name a temporary file stands for; @p path when empty) and the
	/// system's reason. @p bufferSize: the bytes collected before a
	/// write(2), 0 the C library's default (a block, 4 KiB: what a live
	/// trace wants, a short copy in the cycle now and then); a converter
	/// writing a whole file at once gives more.
	explicit TraceFile(std::string_view path, std::string_view shownAs = {}, std::size_t bufferSize = 0);
	~TraceFile();
	TraceFile(const TraceFile &) = delete;
	TraceFile &operator=(const TraceFile &) = delete;

	/// Writes @p n bytes; after the first failure (and after close())
	/// writes nothing more.
	void put(const void *p, std::size_t n) noexcept;
	/// Flushes and closes (once; later calls do nothing); throws
	/// ecmxf::Error when any write or the close failed.
	void close();
	[[nodiscard]] const std::string &path() const noexcept { return path_; }

private:
	std::string path_;
	std::FILE *f_ = nullptr;
	int err_ = 0; ///< first write error (errno), 0: none
};

} // namespace ecmxf::detail
