// SPDX-License-Identifier: MIT
// Text trace to pcapng: traceToPcapng() (include/ecmxf/trace/trace.hpp,
// Documentation/trace.rst "pcapng"), through the library's one pcapng
// block writer (lib/link/pcapng_writer.hpp) and its one text trace reader
// (lib/trace/trace_reader.hpp).

#include <ecmxf/error.hpp>
#include <ecmxf/trace/trace.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

#include <sys/stat.h>
#include <unistd.h>

#include "link/pcapng_writer.hpp"
#include "trace/trace_reader.hpp"

namespace ecmxf {

namespace {

/// The converter's output buffer: a write(2) per MiB, not per 4 KiB
constexpr std::size_t kOutBuffer = 1u << 20;

/// The temporary file of a conversion: removed unless committed.
class TempName
{
public:
	explicit TempName(std::string name) : name_(std::move(name)) {}
	~TempName()
	{
		if (!name_.empty())
			::unlink(name_.c_str());
	}
	TempName(const TempName &) = delete;
	TempName &operator=(const TempName &) = delete;
	[[nodiscard]] const std::string &name() const noexcept { return name_; }
	void commit(const std::string &to)
	{
		if (std::rename(name_.c_str(), to.c_str()) != 0) {
			const int err = errno;
			throw Error("cannot rename \"" + name_ + "\" to \"" + to + "\": " + std::strerror(err), err);
		}
		name_.clear();
	}

private:
	std::string name_;
};

} // namespace

TraceSummary traceToPcapng(std::istream &in, std::string_view path)
{
	const std::string out(path);
	struct stat st {};
	const bool inPlace = ::stat(out.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
	if (inPlace && S_ISDIR(st.st_mode))
		throw Error("\"" + out + "\" is a directory, not a pcapng file", EISDIR);
	std::optional<TempName> temp;
	if (!inPlace)
		temp.emplace(out + ".part-" + std::to_string(::getpid()));
	TraceSummary sum;
	{
		detail::PcapngWriter w(inPlace ? out : temp->name(), out, kOutBuffer);
		detail::TraceReader reader(in);
		detail::TraceRecord r;
		using L = detail::PcapngWriter::Link;
		while (reader.next(r)) {
			if (r.sk && r.kind != 'F') {
				const bool mosi = r.kind == '>';
				w.packet(L::Sk, r.ns,
					 (mosi ? detail::PcapngWriter::kOutbound : detail::PcapngWriter::kInbound) |
						 (r.skCrcChecked() ? detail::PcapngWriter::kFcsLen1 : 0u),
					 r.bytes);
				(mosi ? sum.commands : sum.responses)++;
				sum.packets++;
				continue;
			}
			switch (r.kind) {
			case '>':
				w.packet(L::Spi, r.ns, detail::PcapngWriter::kOutbound, r.bytes);
				sum.commands++;
				break;
			case '<':
				w.packet(L::Spi, r.ns, detail::PcapngWriter::kInbound, r.bytes);
				sum.responses++;
				break;
			case 'C':
			case 'R': {
				std::uint8_t s[4];
				const auto u = static_cast<std::uint32_t>(r.status);
				for (unsigned i = 0; i < 4; i++)
					s[i] = static_cast<std::uint8_t>(u >> (8 * i));
				const bool rsp = r.kind == 'R';
				w.packet(L::Kernel, r.ns, rsp ? detail::PcapngWriter::kInbound : detail::PcapngWriter::kOutbound,
					 s, r.bytes);
				(rsp ? sum.responses : sum.commands)++;
				break;
			}
			default: // 'F': each packet carries its own check word
				continue;
			}
			sum.packets++;
		}
		w.close();
	}
	if (temp)
		temp->commit(out);
	return sum;
}

} // namespace ecmxf
