// SPDX-License-Identifier: MIT
/**
 * @file hidraw_channel.hpp
 * @brief The ECM-SK's USB channel: one HID report each way per frame,
 *        through Linux's hidraw (the kernel's HID driver binds the board;
 *        nothing to detach, no library beyond libc).
 *
 * URI: "sk-usb:" (the one board of USB ID 16C0:05DF), "sk-usb:/dev/hidrawN"
 * or "sk-usb:?path=<USB path>" (device_uri.hpp, Documentation/ecm-sk.rst,
 * "USB"). What NEXTW publishes (the EC-01M datasheet rev 1.00: a HID class
 * device, Interrupt IN and OUT reports of 512 bytes, "the data structure
 * is same as the SPI communication"; NEXTW's NEXTWUSBLib.dll: report ID 0,
 * then the frame, one write and one read per frame) makes an exchange one
 * OUT report (the frame, a 504-byte one padded with zeros to 512) and the
 * one IN report the board answers it with, which carries what MISO carries
 * over SPI: the answer to the previous frame. So the slot link runs over
 * it unchanged (results fetched by GET_STATUS, one exchange late). USB has
 * no Busy line: its flow control paces the writes, and waitReady() is
 * always true. Before each write the channel drains IN reports already
 * queued (an answer that came after its exchange timed out, a report the
 * board sent on its own), so that the report read is this exchange's; the
 * reports drained are counted (staleReports()).
 *
 * Errors name what failed: EACCES with the group and the udev rule that
 * give the node, ENODEV at once when the board was unplugged (a read or
 * write that fails with ENODEV/EIO/EPIPE, or end of file), ETIMEDOUT when
 * no IN report came within the timeout, EBADMSG for a report that is not
 * 512 bytes (another device on the same shared ID).
 *
 * Thread safety: none (a ByteChannel).
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>

namespace ecmxf {

/// The ECM-SK's USB ID (the EC-01M's; V-USB's shared HID ID, which hobby
/// devices use too: a board is never found by the ID alone when several
/// devices carry it).
inline constexpr std::uint16_t kSkUsbVendor = 0x16C0;
inline constexpr std::uint16_t kSkUsbProduct = 0x05DF;
/// The board's report length each way (EC-01M datasheet rev 1.00).
inline constexpr std::size_t kSkUsbReportSize = 512;

/// One hidraw node as sysfs describes it.
struct HidrawDevice {
	std::string node;	 ///< "/dev/hidraw3"
	std::uint16_t bus = 0;	 ///< HID bus type: 3 USB, 5 Bluetooth, 6 virtual...
	std::uint16_t vendor = 0;
	std::uint16_t product = 0;
	std::string name;	 ///< HID_NAME, e.g. "NEXTW ECM-SK" (may be empty)
	std::string usbPath;	 ///< the USB device's sysfs name, e.g. "1-1.2" (empty: not on USB)

	/// "/dev/hidraw3 (16C0:05DF "name", USB path 1-1.2)"
	[[nodiscard]] std::string describe() const;
};

/// Parses one HID device's uevent text (sysfs
/// /sys/class/hidraw/hidrawN/device/uevent: "HID_ID=0003:000016C0:000005DF",
/// "HID_NAME=...", other lines ignored) into @p out's bus, vendor, product
/// and name. Returns false, touching nothing, when HID_ID is missing or
/// malformed (three hex fields of 4, 8 and 8 digits, IDs of 16 bits).
[[nodiscard]] ECMXF_EXPORT bool parseHidUevent(std::string_view text, HidrawDevice &out);

/// Every hidraw node under @p sysfs (the sysfs mount, "/sys"; tests give a
/// tree of their own) with its ID, name and USB path, by node name. A node
/// whose uevent cannot be read or parsed is left out.
[[nodiscard]] ECMXF_EXPORT std::vector<HidrawDevice> listHidraw(const std::string &sysfs = "/sys");

/// Picks the board among @p devices: those of kSkUsbVendor:kSkUsbProduct
/// on a USB interface (a HID device that only claims the USB bus, as uhid
/// can, is not one), and of them the one at @p usbPath when it is not
/// empty. Throws
/// ecmxf::Error: ENODEV when none matches (saying so, and naming the
/// hidraw nodes seen), EINVAL when several match, listing each
/// (HidrawDevice::describe()) and how to pick one.
[[nodiscard]] ECMXF_EXPORT HidrawDevice findSkUsb(const std::vector<HidrawDevice> &devices,
						  std::string_view usbPath = {});

/// The USB channel to one ECM-SK.
class ECMXF_EXPORT HidrawChannel : public ByteChannel
{
public:
	/// How long an exchange waits for its IN report (NEXTW's DLL waits
	/// 100 ms for each transfer).
	static constexpr std::chrono::milliseconds kDefaultTimeout{ 100 };

	/// Opens @p node read/write and checks with HIDIOCGRAWINFO that it is
	/// a USB HID device of the board's ID. Throws ecmxf::Error naming the
	/// node: EACCES (with the group and udev rule), ENOENT, ENODEV (another
	/// device: its ID), others with the system's reason.
	explicit HidrawChannel(const std::string &node, std::chrono::milliseconds timeout = kDefaultTimeout);
	/// Over @p fd, which the channel then owns: a descriptor whose reads
	/// and writes keep report boundaries (a hidraw node opened elsewhere,
	/// or a SOCK_SEQPACKET socket, the tests' seam), named @p name in
	/// messages. No ID check. Throws ecmxf::Error (EBADF) for fd < 0.
	HidrawChannel(int fd, std::string name, std::chrono::milliseconds timeout = kDefaultTimeout);
	~HidrawChannel() override;

	/// One OUT report with @p mosi (504 or 512 bytes; padded to 512), then
	/// the IN report, whose first mosi.size() bytes go to @p miso.
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override;
	/// Always true: USB has no Busy line (its flow control paces writes).
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) override;
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	void sleepUntil(std::chrono::nanoseconds deadline) override;
	/// "sk-usb:/dev/hidraw3" (or the name given with the descriptor)
	[[nodiscard]] std::string name() const override;

	/// IN reports drained before a write since the channel opened.
	[[nodiscard]] std::uint64_t staleReports() const noexcept;

private:
	struct Impl;
	std::unique_ptr<Impl> impl_;
};

} // namespace ecmxf
