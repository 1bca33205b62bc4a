// SPDX-License-Identifier: MIT
// HidrawChannel: the ECM-SK over USB through Linux's hidraw, and finding
// the board in sysfs (include/ecmxf/link/hidraw_channel.hpp,
// Documentation/ecm-sk.rst "USB").

#include <ecmxf/error.hpp>
#include <ecmxf/link/hidraw_channel.hpp>

#include <dirent.h>
#include <fcntl.h>
#include <linux/hidraw.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "base/os.hpp"
#include "base/text.hpp"

namespace ecmxf {

namespace {

using namespace std::chrono;

constexpr std::uint16_t kBusUsb = 3; // BUS_USB of <linux/input.h>

/// @p s as hex of exactly @p digits digits; false otherwise.
bool hexField(std::string_view s, std::size_t digits, std::uint32_t &v)
{
	if (s.size() != digits)
		return false;
	std::uint32_t r = 0;
	const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), r, 16);
	if (ec != std::errc() || end != s.data() + s.size())
		return false;
	v = r;
	return true;
}

/// "16C0": a USB ID as lsusb writes it (the library's hex, without "0x").
std::string hex4(unsigned v)
{
	return detail::hex(v, 4).substr(2);
}

/// The whole of a small sysfs file; empty when it cannot be read.
std::string readSmall(const std::string &path)
{
	std::ifstream f(path);
	if (!f)
		return {};
	std::ostringstream ss;
	ss << f.rdbuf();
	return ss.str();
}

/// The USB device's sysfs name from the real path of a HID device: the
/// component before the interface ("1-1.2:1.0" -> "1-1.2"), which is the
/// one the interface's name begins with; empty when the HID device does
/// not hang off a USB interface.
std::string usbPathOf(const std::string &hidDevice)
{
	char buf[PATH_MAX];
	if (!::realpath(hidDevice.c_str(), buf))
		return {};
	const std::string p(buf);
	// ".../<usb dev>/<usb dev>:<config>.<intf>/<bus>:<vendor>:<product>.<n>"
	const auto hid = p.rfind('/');
	if (hid == std::string::npos || hid == 0)
		return {};
	const auto intfStart = p.rfind('/', hid - 1);
	if (intfStart == std::string::npos)
		return {};
	const std::string intf = p.substr(intfStart + 1, hid - intfStart - 1);
	const auto colon = intf.find(':');
	if (colon == std::string::npos || colon == 0)
		return {};
	const std::string dev = intf.substr(0, colon);
	// the interface's parent must be that device
	if (intfStart < dev.size() + 1 || p.compare(intfStart - dev.size(), dev.size(), dev) != 0 ||
	    p[intfStart - dev.size() - 1] != '/')
		return {};
	return dev;
}

} // namespace

std::string HidrawDevice::describe() const
{
	std::string s = node + " (" + hex4(vendor) + ":" + hex4(product);
	if (!name.empty())
		s += " " + detail::quoted(detail::printable(name));
	s += usbPath.empty() ? ", not on USB" : ", USB path " + usbPath;
	return s + ")";
}

bool parseHidUevent(std::string_view text, HidrawDevice &out)
{
	std::uint32_t bus = 0, vendor = 0, product = 0;
	bool haveId = false;
	std::string name;
	while (!text.empty()) {
		const auto nl = text.find('\n');
		const std::string_view line = text.substr(0, nl);
		text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
		if (line.starts_with("HID_ID=")) {
			// "0003:000016C0:000005DF": bus (4 digits), vendor, product (8)
			const std::string_view v = line.substr(7);
			if (v.size() != 22 || v[4] != ':' || v[13] != ':' || !hexField(v.substr(0, 4), 4, bus) ||
			    !hexField(v.substr(5, 8), 8, vendor) || !hexField(v.substr(14, 8), 8, product) ||
			    vendor > 0xFFFF || product > 0xFFFF)
				return false;
			haveId = true;
		} else if (line.starts_with("HID_NAME=")) {
			name = std::string(line.substr(9));
		}
	}
	if (!haveId)
		return false;
	out.bus = static_cast<std::uint16_t>(bus);
	out.vendor = static_cast<std::uint16_t>(vendor);
	out.product = static_cast<std::uint16_t>(product);
	out.name = std::move(name);
	return true;
}

std::vector<HidrawDevice> listHidraw(const std::string &sysfs)
{
	std::vector<HidrawDevice> out;
	const std::string cls = sysfs + "/class/hidraw";
	DIR *d = ::opendir(cls.c_str());
	if (!d)
		return out;
	while (const dirent *e = ::readdir(d)) {
		const std::string n = e->d_name;
		if (!n.starts_with("hidraw") || n.size() == 6)
			continue;
		HidrawDevice h;
		if (!parseHidUevent(readSmall(cls + "/" + n + "/device/uevent"), h))
			continue;
		h.node = "/dev/" + n;
		if (h.bus == kBusUsb)
			h.usbPath = usbPathOf(cls + "/" + n + "/device");
		out.push_back(std::move(h));
	}
	::closedir(d);
	std::sort(out.begin(), out.end(), [](const HidrawDevice &a, const HidrawDevice &b) {
		return a.node.size() != b.node.size() ? a.node.size() < b.node.size() : a.node < b.node;
	});
	return out;
}

HidrawDevice findSkUsb(const std::vector<HidrawDevice> &devices, std::string_view usbPath)
{
	std::vector<const HidrawDevice *> match;
	for (const HidrawDevice &h : devices)
		if (h.bus == kBusUsb && h.vendor == kSkUsbVendor && h.product == kSkUsbProduct && !h.usbPath.empty() &&
		    (usbPath.empty() || h.usbPath == usbPath))
			match.push_back(&h);
	const std::string id = "USB ID " + hex4(kSkUsbVendor) + ":" + hex4(kSkUsbProduct);
	if (match.empty()) {
		std::string m = "sk-usb: no ECM-SK (" + id;
		if (!usbPath.empty())
			m += " at USB path " + std::string(usbPath);
		m += ") among the hidraw devices";
		if (devices.empty()) {
			m += ": there are none (is the board plugged in? `lsusb -d 16c0:05df`)";
		} else {
			m += ":";
			for (const HidrawDevice &h : devices)
				m += " " + h.describe() + ";";
			m.pop_back();
		}
		throw Error(m, ENODEV);
	}
	if (match.size() > 1) {
		std::string m = "sk-usb: " + std::to_string(match.size()) + " devices carry the ECM-SK's " + id +
				" (a shared ID, hobby devices use it too), so none is picked:";
		for (const HidrawDevice *h : match)
			m += " " + h->describe() + ";";
		m.pop_back();
		m += "; give one: sk-usb:/dev/hidrawN or sk-usb:?path=<USB path>";
		throw Error(m, EINVAL);
	}
	return *match.front();
}

struct HidrawChannel::Impl {
	Impl(std::string n, milliseconds t) : name(std::move(n)), timeout(t) {}

	/// Throws the error of a read or write that failed with @p err (0:
	/// end of file).
	[[noreturn]] void failed(const char *what, int err) const
	{
		if (err == ENODEV || err == EIO || err == EPIPE || err == ECONNRESET || err == 0)
			throw Error(name + ": the ECM-SK is gone (unplugged?): " + what +
					    (err ? std::string(": ") + std::strerror(err) : std::string(": end of file")),
				    ENODEV);
		detail::throwErrno(name + ": " + what, err);
	}

	detail::FileDescriptor fd;
	std::string name;
	milliseconds timeout;
	std::uint64_t stale = 0;
	/// report ID 0 and the frame; the IN report
	std::vector<std::uint8_t> out = std::vector<std::uint8_t>(kSkUsbReportSize + 1);
	/// the IN report, with room to see a longer one (another device)
	std::vector<std::uint8_t> in = std::vector<std::uint8_t>(4096);
};

HidrawChannel::HidrawChannel(const std::string &node, milliseconds timeout)
	: impl_(std::make_unique<Impl>("sk-usb:" + node, timeout))
{
	Impl &m = *impl_;
	m.fd.reset(::open(node.c_str(), O_RDWR | O_CLOEXEC | O_NONBLOCK));
	if (!m.fd.valid()) {
		const int err = errno;
		if (err == EACCES)
			throw Error(m.name + ": permission denied: the udev rule 60-ecmxf.rules gives the ECM-SK's "
					     "hidraw node to the group \"ecmxf\" (`usermod -aG ecmxf $USER`, then log "
					     "in again; make install-udev installs the rule)",
				    EACCES);
		detail::throwErrno(m.name + ": cannot open", err);
	}
	hidraw_devinfo info{};
	if (::ioctl(m.fd.get(), HIDIOCGRAWINFO, &info) < 0)
		detail::throwErrno(m.name + ": not a hidraw node (HIDIOCGRAWINFO)", errno);
	const auto vendor = static_cast<std::uint16_t>(info.vendor);
	const auto product = static_cast<std::uint16_t>(info.product);
	if (info.bustype != kBusUsb || vendor != kSkUsbVendor || product != kSkUsbProduct)
		throw Error(m.name + ": not an ECM-SK: a HID device " + hex4(vendor) + ":" + hex4(product) +
				    (info.bustype == kBusUsb ? " on USB" : " not on USB") + ", the board is USB " +
				    hex4(kSkUsbVendor) + ":" + hex4(kSkUsbProduct),
			    ENODEV);
}

HidrawChannel::HidrawChannel(int fd, std::string name, milliseconds timeout)
	: impl_(std::make_unique<Impl>(std::move(name), timeout))
{
	Impl &m = *impl_;
	if (fd < 0)
		throw Error(m.name + ": no file descriptor", EBADF);
	m.fd.reset(fd);
	const int fl = ::fcntl(fd, F_GETFL);
	if (fl < 0 || ::fcntl(fd, F_SETFL, fl | O_NONBLOCK) < 0)
		detail::throwErrno(m.name + ": fcntl(O_NONBLOCK)", errno);
}

HidrawChannel::~HidrawChannel() = default;

std::uint64_t HidrawChannel::staleReports() const noexcept
{
	return impl_->stale;
}

void HidrawChannel::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	Impl &m = *impl_;
	const int fd = m.fd.get();
	if (mosi.size() > kSkUsbReportSize || miso.size() != mosi.size())
		throw Error(m.name + ": a frame of " + std::to_string(mosi.size()) + " bytes (at most " +
				    std::to_string(kSkUsbReportSize) + ", and as long as the answer's)",
			    EINVAL);
	// IN reports already queued belong to no exchange of ours
	for (;;) {
		const ssize_t n = ::read(fd, m.in.data(), m.in.size());
		if (n > 0) {
			m.stale++;
			continue;
		}
		if (n == 0)
			m.failed("read", 0);
		if (errno == EINTR)
			continue;
		if (errno == EAGAIN)
			break;
		m.failed("read", errno);
	}
	m.out[0] = 0; // the report ID: the board has none
	std::copy(mosi.begin(), mosi.end(), m.out.begin() + 1);
	std::fill(m.out.begin() + 1 + static_cast<std::ptrdiff_t>(mosi.size()), m.out.end(), 0);
	const auto deadline = now() + m.timeout;
	bool sent = false;
	for (;;) {
		const auto left = duration_cast<milliseconds>(deadline - now());
		pollfd p{ fd, static_cast<short>(sent ? POLLIN : POLLOUT), 0 };
		const int r = ::poll(&p, 1, static_cast<int>(std::max<milliseconds::rep>(left.count(), 0)));
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			detail::throwErrno(m.name + ": poll", errno);
		if (r == 0)
			throw Error(m.name + ": no " + (sent ? "IN report (the answer)" : "room for the OUT report") +
					    " within " + std::to_string(m.timeout.count()) + " ms",
				    ETIMEDOUT);
		if ((p.revents & (POLLERR | POLLHUP | POLLNVAL)) && !(p.revents & POLLIN))
			m.failed(sent ? "read" : "write", (p.revents & POLLNVAL) ? EBADF : ENODEV);
		if (!sent) {
			const ssize_t n = ::write(fd, m.out.data(), m.out.size());
			if (n < 0 && (errno == EINTR || errno == EAGAIN))
				continue;
			if (n < 0)
				m.failed("write", errno);
			if (static_cast<std::size_t>(n) != m.out.size())
				throw Error(m.name + ": the OUT report went out short (" + std::to_string(n) + " of " +
						    std::to_string(m.out.size()) + " bytes)",
					    EIO);
			sent = true;
			continue;
		}
		const ssize_t n = ::read(fd, m.in.data(), m.in.size());
		if (n < 0 && (errno == EINTR || errno == EAGAIN))
			continue;
		if (n <= 0)
			m.failed("read", n == 0 ? 0 : errno);
		if (static_cast<std::size_t>(n) != kSkUsbReportSize)
			throw Error(m.name + ": an IN report of " + std::to_string(n) + " bytes, the ECM-SK's are " +
					    std::to_string(kSkUsbReportSize) + " (another device on the same USB ID?)",
				    EBADMSG);
		std::copy_n(m.in.begin(), miso.size(), miso.begin());
		return;
	}
}

bool HidrawChannel::waitReady(nanoseconds)
{
	return true;
}

nanoseconds HidrawChannel::now() const
{
	return duration_cast<nanoseconds>(steady_clock::now().time_since_epoch());
}

void HidrawChannel::sleepUntil(nanoseconds deadline)
{
	detail::sleepUntilMonotonic(deadline);
}

std::string HidrawChannel::name() const
{
	return impl_->name;
}

} // namespace ecmxf
