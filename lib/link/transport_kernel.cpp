// SPDX-License-Identifier: MIT
// KernelTransport: /dev/ecmxfN through the ioctls of <linux/ecmxf.h>
// (include/ecmxf/link/kernel_transport.hpp, Documentation/uapi.rst).

#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_transport.hpp>

#include <fcntl.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include "ecmxf-proto.h"
#include "device/lib_text.hpp"
#include "uapi/linux/ecmxf.h"

namespace ecmxf {

static_assert(kKernelUapiVersion == ECMXF_UAPI_VERSION,
	      "kernel_transport.hpp and <linux/ecmxf.h> disagree on the ABI version");

namespace {

std::string quoted(const std::string &s)
{
	std::string q(1, '"');
	q.append(s).push_back('"');
	return q;
}

/// "<path>: <call> failed: <reason>", errno kept.
[[noreturn]] void ioctlFailed(const std::string &path, const char *call, int err)
{
	std::string m = path;
	m.append(": ").append(call).append(" failed: ").append(std::strerror(err));
	if (err == ENOTTY)
		m.append(" (not an ecmxf device?)");
	throw Error(m, err);
}

ResponseHeader fromUapi(const ecmxf_rsp_header &h)
{
	return detail::headerFrom(h);
}

} // namespace

void checkKernelUapiVersion(const std::string &path, std::uint32_t running)
{
	if (running == kKernelUapiVersion)
		return;
	throw Error(path + ": the ecmxf kernel module speaks ABI version " + std::to_string(running) +
			    ", this library ABI version " + std::to_string(kKernelUapiVersion) +
			    " (<linux/ecmxf.h>); use a matching library and module",
		    EPROTO);
}

KernelTransport::KernelTransport(const std::string &path) : CommandTransport(path)
{
	fd_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
	if (fd_ < 0) {
		const int err = errno;
		std::string m = "cannot open " + quoted(path) + ": " + std::strerror(err);
		if (err == ENOENT)
			m.append(" (is the ecmxf kernel module loaded and the chip bound?)");
		throw Error(m, err);
	}
	try {
		__u32 version = 0;
		if (::ioctl(fd_, ECMXF_IOC_GET_VERSION, &version) < 0)
			ioctlFailed(path, "ECMXF_IOC_GET_VERSION", errno);
		checkKernelUapiVersion(path, version);
		info_ = devInfo();
	} catch (...) {
		::close(fd_);
		fd_ = -1;
		throw;
	}
}

KernelTransport::~KernelTransport()
{
	if (fd_ >= 0)
		::close(fd_);
}

bool KernelTransport::refreshFormat() const noexcept
{
	if (!formatStale_)
		return true;
	try {
		(void)devInfo(); // clears formatStale_
		return true;
	} catch (...) {
		return false;
	}
}

std::optional<std::uint8_t> KernelTransport::checkTypeNow() const noexcept
{
	if (!refreshFormat())
		return std::nullopt;
	return checkType_;
}

std::uint16_t KernelTransport::dataSize() const noexcept
{
	refreshFormat(); // on failure: the last value known
	return dataSize_;
}

KernelDevInfo KernelTransport::devInfo() const
{
	ecmxf_devinfo d{};
	if (::ioctl(fd_, ECMXF_IOC_DEVINFO, &d) < 0)
		ioctlFailed(name(), "ECMXF_IOC_DEVINFO", errno);
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
	dataSize_ = i.dataSize;
	checkType_ = i.checkType;
	formatStale_ = false;
	return i;
}

KernelCounters KernelTransport::counters() const
{
	ecmxf_counters k{};
	if (::ioctl(fd_, ECMXF_IOC_COUNTERS, &k) < 0)
		ioctlFailed(name(), "ECMXF_IOC_COUNTERS", errno);
	KernelCounters c;
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

void KernelTransport::reset(KernelReset kind, std::uint32_t param, std::uint32_t timeoutUs)
{
	ecmxf_reset r{};
	switch (kind) {
	case KernelReset::AsyncCmd:
		if (param & ~7u)
			throw Error(name() + ": ASYNCCMD_RESET parameter " + std::to_string(param) +
					    " has bits outside 0..2 (clear busy, skip link, abandon)",
				    EINVAL);
		r.flags = ECMXF_RESET_F_ASYNC_CMD;
		r.param = param;
		break;
	case KernelReset::Warm:
		r.flags = ECMXF_RESET_F_WARM;
		break;
	case KernelReset::Link:
		r.flags = ECMXF_RESET_F_LINK;
		break;
	}
	if (kind != KernelReset::AsyncCmd && param)
		throw Error(name() + ": a reset parameter is only allowed for ASYNCCMD_RESET", EINVAL);
	r.timeout_us = timeoutUs;
	formatStale_ = true; // a warm reset goes back to the power-on format
	if (::ioctl(fd_, ECMXF_IOC_RESET, &r) < 0)
		ioctlFailed(name(), "ECMXF_IOC_RESET", errno);
}

int KernelTransport::doCommand(const RawRequest &req, RawResult &res, const char *&failedCall) noexcept
{
	ecmxf_cmd c{};
	std::copy(req.data.begin(), req.data.end(), c.hdr.data);
	c.hdr.rsv_word = req.reserved;
	c.hdr.control = req.control;
	c.hdr.code = req.code;
	c.hdr.param = req.param;
	c.hdr.len = req.len;
	c.hdr.int_clear = req.intClear;
	c.hdr.gpio_int_clear[0] = req.gpioIntClear[0];
	c.hdr.gpio_int_clear[1] = req.gpioIntClear[1];
	c.hdr.gpio_out[0] = req.gpioOut[0];
	c.hdr.gpio_out[1] = req.gpioOut[1];
	c.tx_ptr = req.tx.empty() ? 0 : reinterpret_cast<std::uintptr_t>(req.tx.data());
	c.tx_len = static_cast<__u32>(req.tx.size());
	c.rx_ptr = req.rx.empty() ? 0 : reinterpret_cast<std::uintptr_t>(req.rx.data());
	c.rx_size = static_cast<__u32>(req.rx.size());
	c.timeout_us = req.timeoutUs;
	c.flags = req.noAutoClear ? ECMXF_CMD_F_NO_AUTO_CLEAR : 0u;
	// the one system call of a command: the format is kept, not asked
	// (dataSize(), checkTypeNow())
	if (::ioctl(fd_, ECMXF_IOC_CMD, &c) < 0) {
		formatStale_ = true;
		failedCall = "ECMXF_IOC_CMD";
		return -errno;
	}
	if (c.status != 0 || req.code == ECMXF_CMD_SPI_RECONFIG_OP || req.code == ECMXF_CMD_CRC_TYPE_SET)
		formatStale_ = true;
	res.status = c.status;
	res.header = fromUapi(c.rsp);
	res.rxLen = std::min<std::size_t>(c.rx_len, req.rx.size());
	return 0;
}

} // namespace ecmxf
