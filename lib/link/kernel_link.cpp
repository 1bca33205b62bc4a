// SPDX-License-Identifier: MIT
// KernelLink: /dev/ecmxfN through the ioctls of <linux/ecmxf.h>
// (include/ecmxf/link/kernel_link.hpp, Documentation/uapi.rst), and the
// kernel's PDO rings (lib/link/pdo_rings.hpp). The only file of the library
// that makes ioctl() and mmap() calls on the device.

#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "ecmxf-proto.h"
#include "base/text.hpp"
#include "link/wire_header.hpp"
#include "base/os.hpp"
#include "link/outcome.hpp"
#include "link/pdo_rings.hpp"
#include "link/trace_writer.hpp"
#include "uapi/linux/ecmxf.h"

namespace ecmxf {

static_assert(kKernelUapiVersion == ECMXF_UAPI_VERSION,
	      "kernel_link.hpp and <linux/ecmxf.h> disagree on the ABI version");

namespace {

/// "<path>: <call> failed: <reason>", errno kept.
[[noreturn]] void ioctlFailed(const std::string &path, const char *call, int err)
{
	std::string what = path;
	what.append(": ").append(call).append(" failed");
	if (err == ENOTTY)
		throw Error(what + ": " + std::strerror(err) + " (not an ecmxf device?)", err);
	detail::throwErrno(what, err);
}

/// ioctl(@p fd, @p request, @p arg), throwing as ioctlFailed() when it
/// fails; @p call is the request's name.
void ioctlChecked(int fd, unsigned long request, void *arg, const std::string &path, const char *call)
{
	if (::ioctl(fd, request, arg) < 0)
		ioctlFailed(path, call, errno);
}

} // namespace

class KernelLink::State
{
public:
	/// Reads ECMXF_IOC_DEVINFO into the kept format if it is stale;
	/// false when that ioctl fails.
	bool refreshFormat(const KernelLink &k) const noexcept
	{
		if (!formatStale)
			return true;
		try {
			(void)k.devInfo(); // clears formatStale
			return true;
		} catch (...) {
			return false;
		}
	}

	std::string path;
	detail::FileDescriptor fd;
	KernelDevInfo info;
	std::optional<ResponseHeader> last;
	detail::TraceWriter *trace = nullptr;
	/// the text of the last failed system call (RawResult::linkFailure)
	std::array<char, 256> failure{};
	// the packet format in force as last read (dataSize(), checkType())
	mutable std::uint16_t dataSize = 0;
	mutable std::uint8_t checkType = 0;
	mutable bool formatStale = false;
};

void checkKernelUapiVersion(const std::string &path, std::uint32_t running)
{
	if (running == kKernelUapiVersion)
		return;
	throw Error(path + ": the ecmxf kernel module speaks ABI version " + std::to_string(running) +
			    ", this library ABI version " + std::to_string(kKernelUapiVersion) +
			    " (<linux/ecmxf.h>); use a matching library and module",
		    EPROTO);
}

KernelLink::KernelLink(const std::string &path) : s_(std::make_unique<State>())
{
	s_->path = path;
	s_->fd.reset(::open(path.c_str(), O_RDWR | O_CLOEXEC));
	if (!s_->fd.valid()) {
		const int err = errno;
		if (err == ENOENT)
			throw Error("cannot open " + detail::quoted(path) + ": " + std::strerror(err) +
					    " (is the ecmxf kernel module loaded and the chip bound?)",
				    err);
		detail::throwErrno("cannot open " + detail::quoted(path), err);
	}
	__u32 version = 0;
	ioctlChecked(fd(), ECMXF_IOC_GET_VERSION, &version, path, "ECMXF_IOC_GET_VERSION");
	checkKernelUapiVersion(path, version);
	s_->info = devInfo();
}

KernelLink::~KernelLink() = default;

int KernelLink::fd() const noexcept
{
	return s_->fd.get();
}

std::string KernelLink::name() const
{
	return s_->path;
}

void KernelLink::sleepUntil(std::chrono::nanoseconds deadline)
{
	detail::sleepUntilMonotonic(deadline);
}

const KernelDevInfo &KernelLink::openInfo() const noexcept
{
	return s_->info;
}

std::optional<ResponseHeader> KernelLink::lastHeader() const noexcept
{
	return s_->last;
}

CheckType KernelLink::checkType() const noexcept
{
	if (!s_->refreshFormat(*this))
		return static_cast<CheckType>((s_->last ? s_->last->ecmStatus : 0) & ECMXF_STS_CHECK_MASK);
	return static_cast<CheckType>(s_->checkType & ECMXF_STS_CHECK_MASK);
}

std::uint16_t KernelLink::dataSize() const noexcept
{
	s_->refreshFormat(*this); // on failure: the last value known
	return s_->dataSize;
}

KernelDevInfo KernelLink::devInfo() const
{
	ecmxf_devinfo d{};
	ioctlChecked(fd(), ECMXF_IOC_DEVINFO, &d, name(), "ECMXF_IOC_DEVINFO");
	KernelDevInfo i;
	i.uapiVersion = d.uapi_version;
	i.flags = d.flags;
	i.dataSize = d.data_size;
	i.checkType = d.check_type;
	i.fwVersion = d.fw_version;
	std::copy(std::begin(d.fw_info), std::end(d.fw_info), i.fwInfo.begin());
	i.slaveCount = d.slave_count;
	i.maxOpen = d.max_open;
	i.openCount = d.open_count;
	i.claimPid = d.claim_pid;
	i.queueDepth = d.queue_depth;
	i.spiSpeedHz = d.spi_speed_hz;
	s_->dataSize = i.dataSize;
	s_->checkType = i.checkType;
	s_->formatStale = false;
	return i;
}

LinkCounters KernelLink::counters() const
{
	ecmxf_counters k{};
	ioctlChecked(fd(), ECMXF_IOC_COUNTERS, &k, name(), "ECMXF_IOC_COUNTERS");
	LinkCounters c;
	c.exchanges = k.exchanges;
	c.badNotReady = k.bad_not_ready;
	c.badStart = k.bad_start;
	c.badEnd = k.bad_end;
	c.badCheck = k.bad_check;
	c.badLength = k.bad_length;
	c.retries = k.retries;
	c.polls = k.polls;
	c.exhausted = k.exhausted;
	c.timeouts = k.timeouts;
	c.asyncErrors = k.async_errors;
	c.busyRejects = k.busy_rejects;
	c.lostAnswers = k.lost_answers;
	c.chipResets = k.chip_resets;
	c.wkcErrors = k.wkc_errors;
	c.outRingUnderruns = k.out_ring_underruns;
	c.inRingOverruns = k.in_ring_overruns;
	c.rxFifoUnderruns = k.rx_fifo_underruns;
	c.rxFifoOverruns = k.rx_fifo_overruns;
	c.txFifoOverruns = k.tx_fifo_overruns;
	c.int0Irqs = k.int0_irqs;
	c.int1Irqs = k.int1_irqs;
	return c;
}

void KernelLink::reset(LinkReset kind, std::uint32_t param, std::uint32_t timeoutUs)
{
	detail::checkReset(*this, kind, param);
	ecmxf_reset r{};
	switch (kind) {
	case LinkReset::AsyncCmd:
		r.flags = ECMXF_RESET_F_ASYNC_CMD;
		r.param = param;
		break;
	case LinkReset::Warm:
		r.flags = ECMXF_RESET_F_WARM;
		break;
	case LinkReset::Link:
		r.flags = ECMXF_RESET_F_LINK;
		break;
	}
	r.timeout_us = timeoutUs;
	s_->formatStale = true; // a warm reset goes back to the power-on format
	ioctlChecked(fd(), ECMXF_IOC_RESET, &r, name(), "ECMXF_IOC_RESET");
}

void KernelLink::assumeFormat(std::uint16_t, CheckType)
{
	throw Error(name() + ": the kernel module tracks the chip's packet format itself; it cannot be "
			     "assumed from here",
		    EOPNOTSUPP);
}

std::optional<std::uint32_t> KernelLink::minorOf(const std::string &path)
{
	struct stat st {};
	if (::stat(path.c_str(), &st) != 0 || !S_ISCHR(st.st_mode))
		return std::nullopt;
	return static_cast<std::uint32_t>(minor(st.st_rdev));
}

void KernelLink::attachTrace(detail::TraceWriter *trace) noexcept
{
	s_->trace = trace;
	if (trace)
		trace->comment("kernel link: request and response records");
}

void KernelLink::run(const RawRequest &req, RawResult &res) noexcept
{
	command(req, nullptr, res, nullptr);
}

void KernelLink::runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res, bool) noexcept
{
	const std::size_t n = std::min(reqs.size(), res.size());
	for (std::size_t i = 0; i < n; i++) {
		if (i + 1 < n && reqs[i + 1].fetchesPrevious) {
			command(reqs[i], &reqs[i + 1], res[i], &res[i + 1]);
			i++;
			continue;
		}
		command(reqs[i], nullptr, res[i], nullptr);
	}
}

void KernelLink::command(const RawRequest &req, const RawRequest *fetch, RawResult &res,
			 RawResult *fetchRes) noexcept
{
	res = RawResult{};
	if (fetchRes)
		*fetchRes = RawResult{};
	if (s_->trace) {
		s_->trace->request(static_cast<std::uint64_t>(now().count()), req);
		if (fetch)
			s_->trace->request(static_cast<std::uint64_t>(now().count()), *fetch);
	}
	// the answer wanted is the fetch's, into its buffer
	const RawRequest &ans = fetch ? *fetch : req;
	ecmxf_cmd c{};
	detail::headerTo(req, c.hdr);
	c.hdr.rsv_word = req.reserved;
	c.tx_ptr = req.tx.empty() ? 0 : reinterpret_cast<std::uintptr_t>(req.tx.data());
	c.tx_len = static_cast<__u32>(req.tx.size());
	c.rx_ptr = ans.rx.empty() ? 0 : reinterpret_cast<std::uintptr_t>(ans.rx.data());
	c.rx_size = static_cast<__u32>(ans.rx.size());
	c.timeout_us = req.timeoutUs;
	c.flags = req.noAutoClear ? ECMXF_CMD_F_NO_AUTO_CLEAR : 0u;
	if (fetch) {
		detail::headerTo(*fetch, c.fetch);
		c.fetch.rsv_word = fetch->reserved;
		c.flags |= ECMXF_CMD_F_FETCH;
	}
	// the one system call of a command: the format is kept, not asked
	// (dataSize(), checkType())
	if (::ioctl(fd(), ECMXF_IOC_CMD, &c) < 0) {
		const int err = errno;
		s_->formatStale = true;
		std::snprintf(s_->failure.data(), s_->failure.size(), "%s: ECMXF_IOC_CMD failed: %s", s_->path.c_str(),
			      std::strerror(err));
		res.status = -err;
		res.linkFailure = s_->failure.data();
		if (fetchRes) {
			fetchRes->status = -ECANCELED;
			fetchRes->linkFailure = detail::kFetchNotSent;
		}
		return;
	}
	if (c.status != 0 || req.code == ECMXF_CMD_SPI_RECONFIG_OP || req.code == ECMXF_CMD_CRC_TYPE_SET)
		s_->formatStale = true;
	// with a fetch: its outcome once it ran (the command then ended well),
	// else the command's own, the fetch not sent
	const bool fetched = fetch && (c.flags & ECMXF_CMD_F_FETCHED);
	RawResult &out = fetched ? *fetchRes : res;
	out.status = c.status;
	out.header = detail::headerFrom(c.rsp);
	out.rxLen = std::min<std::size_t>(c.rx_len, (fetched ? ans : req).rx.size());
	if (fetched) {
		// the command's own answer stays in the kernel: it ended well
		res.header = out.header;
	} else if (fetchRes) {
		fetchRes->status = -ECANCELED;
		fetchRes->linkFailure = detail::kFetchNotSent;
	}
	// headers the chip sent: success and the outcomes it reported
	if (out.status == 0 || out.status == -EBUSY || out.status == -EREMOTEIO || out.status == -EMSGSIZE)
		s_->last = out.header;
	if (s_->trace) {
		s_->trace->response(static_cast<std::uint64_t>(now().count()), res,
				    std::span<const std::uint8_t>(req.rx.data(), res.rxLen));
		if (fetchRes)
			s_->trace->response(static_cast<std::uint64_t>(now().count()), *fetchRes,
					    std::span<const std::uint8_t>(ans.rx.data(), fetchRes->rxLen));
	}
}

// ---------------------------------------------------------------------------
// The PDO rings
// ---------------------------------------------------------------------------

std::unique_ptr<detail::PdoRings> KernelLink::openPdoRings()
{
	if (::ioctl(fd(), ECMXF_IOC_CLAIM) < 0) {
		const int err = errno;
		if (err != EBUSY)
			ioctlFailed(name(), "ECMXF_IOC_CLAIM", err);
		std::uint32_t pid = 0;
		try {
			pid = devInfo().claimPid;
		} catch (const Error &) {
			// the pid is a courtesy; EBUSY is the answer
		}
		throw Error(name() + ": the cyclic path (PDO rings) is claimed by " +
				    (pid ? "process " + std::to_string(pid) : std::string("another process")) +
				    " (ECMXF_IOC_CLAIM: EBUSY)",
			    EBUSY);
	}
	return std::make_unique<detail::PdoRings>(fd(), name());
}

std::optional<std::uint32_t> KernelLink::breakClaim()
{
	const std::uint32_t holder = devInfo().claimPid;
	if (::ioctl(fd(), ECMXF_IOC_CLAIM_BREAK) == 0)
		return holder;
	const int err = errno;
	if (err == ENOENT)
		return std::nullopt;
	if (err == EPERM)
		throw Error(name() + ": breaking the claim needs CAP_SYS_ADMIN and the device opened for writing "
				     "(ECMXF_IOC_CLAIM_BREAK: EPERM)",
			    EPERM);
	ioctlFailed(name(), "ECMXF_IOC_CLAIM_BREAK", err);
}

namespace detail {

PdoRings::~PdoRings()
{
	unmap();
	::ioctl(fd_, ECMXF_IOC_RELEASE);
}

void PdoRings::unmap() noexcept
{
	out_ = in_ = PdoRingView();
	outMap_.reset();
	inMap_.reset();
}

void PdoRings::setup(ecmxf_ring_setup &rs)
{
	unmap();
	ioctlChecked(fd_, ECMXF_IOC_RING_SETUP, &rs, name_, "ECMXF_IOC_RING_SETUP");
	outMap_ = Mapping(fd_, rs.out.mmap_size, ECMXF_RING_OFF_OUT, name_ + ": mmap of the output ring failed");
	inMap_ = Mapping(fd_, rs.in.mmap_size, ECMXF_RING_OFF_IN, name_ + ": mmap of the input ring failed");
	out_ = PdoRingView(outMap_.get(), rs.out);
	in_ = PdoRingView(inMap_.get(), rs.in);
}

int PdoRings::wait(std::chrono::nanoseconds timeout) noexcept
{
	const std::int64_t ns = std::max<std::int64_t>(timeout.count(), 0);
	// POLLRDBAND while the input ring holds frames, POLLERR once the pump
	// stopped (POLLIN is the completions' bit)
	pollfd p{ fd_, POLLRDBAND, 0 };
	timespec ts{ static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000) };
	const int n = ::ppoll(&p, 1, &ts, nullptr);
	if (n < 0)
		return errno == EINTR ? 0 : -errno;
	if (n > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL)))
		return 1;
	return 0;
}

} // namespace detail
CrcCoverage KernelLink::crcCoverage() const noexcept
{
	const std::optional<std::uint32_t> n = minorOf(s_->path);
	if (!n)
		return CrcCoverage::Unknown;
	char path[64];
	std::snprintf(path, sizeof(path), "/sys/class/ecmxf/ecmxf%u/crc_coverage", static_cast<unsigned>(*n));
	std::FILE *f = std::fopen(path, "re");
	if (!f)
		return CrcCoverage::Unknown;
	char word[16] = {};
	const bool got = std::fgets(word, sizeof(word), f) != nullptr;
	std::fclose(f);
	const std::string_view w = got ? std::string_view(word) : std::string_view();
	if (w == "frame\n")
		return CrcCoverage::Frame;
	if (w == "valid\n")
		return CrcCoverage::Valid;
	return CrcCoverage::Unknown;
}

} // namespace ecmxf
