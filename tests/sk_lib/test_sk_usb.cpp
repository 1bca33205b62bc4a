// SPDX-License-Identifier: MIT
// The ECM-SK over USB: HidrawChannel's real code against a fake of hidraw
// (one end of a SOCK_SEQPACKET socket pair, which keeps report boundaries
// as hidraw does; the other end served by the simulated board in a
// thread, one IN report per OUT report), and finding the board in a sysfs
// tree made here (Documentation/ecm-sk.rst, "USB").

#include <catch2/catch.hpp>

#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/hidraw_channel.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/sim_channel.hpp>

#include "../common/thrown.hpp"

using namespace ecmxf;
using namespace std::chrono_literals;

namespace {

/// What the fake device does besides answering.
struct FakeUsbFaults {
	std::atomic<bool> silent{ false };  ///< take OUT reports, answer none
	std::atomic<int> shortReport{ 0 };  ///< answer with a report of this many bytes instead
	std::atomic<bool> garbage{ false }; ///< answer with bytes that are no ECM-SK frame
	std::atomic<bool> unplug{ false };  ///< close at the next OUT report
};

/// The board's USB side: OUT reports (report ID 0, then 512 bytes) from
/// the socket, each run through the simulated board as one SPI exchange
/// (its virtual clock kept at the real time passed, waiting out Busy),
/// the MISO bytes back as a 512-byte IN report.
class FakeSkUsb
{
public:
	explicit FakeSkUsb(sk::BoardConfig cfg = {})
		: board(sim::Network::fromText(sk::defaultSkNetwork(), "t"), cfg)
	{
		int sv[2];
		REQUIRE(::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) == 0);
		host_ = sv[0];
		dev_ = sv[1];
		thread_ = std::thread([this] { serve(); });
	}
	~FakeSkUsb()
	{
		stop_ = true;
		::shutdown(dev_, SHUT_RDWR);
		thread_.join();
		::close(dev_);
		if (host_ >= 0)
			::close(host_);
	}
	/// The host's end, for a HidrawChannel (which then owns it).
	int takeHost() { return std::exchange(host_, -1); }
	/// Queues @p n IN reports of 0xA5 bytes now, between exchanges (an
	/// answer that came late, a report the board sent on its own).
	void queueStale(int n)
	{
		const std::vector<std::uint8_t> r(kSkUsbReportSize, 0xA5);
		for (int i = 0; i < n; i++)
			REQUIRE(::send(dev_, r.data(), r.size(), 0) == static_cast<ssize_t>(r.size()));
	}

	sk::SimBoard board;
	FakeUsbFaults faults;
	std::atomic<unsigned> outReports{ 0 };
	std::vector<std::size_t> outSizes; ///< sizes of the OUT reports (under mu)
	std::vector<std::uint8_t> lastOut;  ///< the last OUT report (under mu)
	std::mutex mu;

private:
	void serve()
	{
		std::vector<std::uint8_t> out(4096), in(kSkUsbReportSize);
		auto last = std::chrono::steady_clock::now();
		while (!stop_) {
			const ssize_t n = ::recv(dev_, out.data(), out.size(), 0);
			if (n <= 0)
				return;
			outReports++;
			{
				std::lock_guard<std::mutex> l(mu);
				outSizes.push_back(static_cast<std::size_t>(n));
				lastOut.assign(out.begin(), out.begin() + n);
			}
			if (faults.unplug) {
				::shutdown(dev_, SHUT_RDWR);
				return;
			}
			if (faults.silent)
				continue;
			const auto t = std::chrono::steady_clock::now();
			board.advance(t - last);
			last = t;
			while (board.busy())
				board.advance(1us);
			std::fill(in.begin(), in.end(), 0);
			const std::size_t fs = board.frameSize();
			if (out[0] == 0 && static_cast<std::size_t>(n) == kSkUsbReportSize + 1)
				board.exchange(std::span<const std::uint8_t>(out.data() + 1, fs),
					       std::span<std::uint8_t>(in.data(), fs));
			if (faults.garbage)
				for (std::size_t i = 0; i < in.size(); i++)
					in[i] = static_cast<std::uint8_t>(i * 37 + 11);
			const std::size_t len = faults.shortReport ? static_cast<std::size_t>(faults.shortReport.load())
								   : in.size();
			(void)::send(dev_, in.data(), len, 0);
		}
	}

	int host_ = -1, dev_ = -1;
	std::atomic<bool> stop_{ false };
	std::thread thread_;
};

std::unique_ptr<sk::Board> usbBoard(FakeSkUsb &f, sk::LinkOptions o = {}, std::chrono::milliseconds t = 100ms)
{
	return std::make_unique<sk::Board>(std::make_unique<HidrawChannel>(f.takeHost(), "sk-usb:fake", t), o);
}

bool has(const std::string &s, const std::string &part)
{
	return s.find(part) != std::string::npos;
}

/// A sysfs tree with hidraw nodes, as the kernel lays it out: the class
/// link to the node's directory under its HID device, whose "device" link
/// points back up, the HID device under its USB interface and device.
class FakeSysfs
{
public:
	FakeSysfs()
	{
		char tmpl[] = "/tmp/ecmxf-sysfs-XXXXXX";
		REQUIRE(::mkdtemp(tmpl) != nullptr);
		root = tmpl;
		std::filesystem::create_directories(root + "/class/hidraw");
	}
	~FakeSysfs() { std::filesystem::remove_all(root); }

	/// hidraw<n> of @p hidId ("0003:000016C0:000005DF"), named @p name,
	/// at USB device @p usb (empty: on no USB interface).
	void add(unsigned n, const std::string &hidId, const std::string &name, const std::string &usb)
	{
		const std::string base = usb.empty() ? root + "/devices/virtual/misc/uhid"
						     : root + "/devices/pci0000:00/0000:00:14.0/usb1/" + usb + "/" +
							       usb + ":1.0";
		const std::string hid = base + "/" + hidId.substr(0, 4) + ":" + hidId.substr(9, 4) + ":" +
					hidId.substr(18, 4) + "." + std::to_string(1000 + n);
		const std::string node = hid + "/hidraw/hidraw" + std::to_string(n);
		std::filesystem::create_directories(node);
		std::ofstream(hid + "/uevent") << "DRIVER=hid-generic\nHID_ID=" << hidId << "\nHID_NAME=" << name
					       << "\nHID_PHYS=usb-0000:00:14.0-" << usb << "/input0\n";
		std::filesystem::create_directory_symlink("../..", node + "/device");
		std::filesystem::create_directory_symlink(node, root + "/class/hidraw/hidraw" + std::to_string(n));
	}

	std::string root;
};

constexpr const char *kSkId = "0003:000016C0:000005DF";

} // namespace

TEST_CASE("sk usb: a uevent's HID_ID and HID_NAME, and malformed ones refused")
{
	HidrawDevice h;
	REQUIRE(parseHidUevent("DRIVER=hid-generic\nHID_ID=0003:000016C0:000005DF\nHID_NAME=NEXTW ECM-SK\n"
			       "HID_PHYS=usb-0000:00:14.0-1/input0\n",
			       h));
	CHECK(h.bus == 3);
	CHECK(h.vendor == 0x16C0);
	CHECK(h.product == 0x05DF);
	CHECK(h.name == "NEXTW ECM-SK");
	REQUIRE(parseHidUevent("HID_ID=0005:0000046d:0000b33d", h)); // lower case, no newline
	CHECK(h.bus == 5);
	CHECK(h.vendor == 0x046D);
	CHECK(h.name.empty());

	const char *bad[] = {
		"",					 // nothing
		"HID_NAME=x\n",				 // no HID_ID
		"HID_ID=0003:16C0:05DF\n",		 // short fields
		"HID_ID=0003:000016C0:000005DF0\n",	 // one digit too many
		"HID_ID=0003-000016C0-000005DF\n",	 // separators
		"HID_ID=0003:000016G0:000005DF\n",	 // not hex
		"HID_ID=0003:000116C0:000005DF\n",	 // vendor beyond 16 bits
		"HID_ID=0003:000016C0:100005DF\n",	 // product beyond 16 bits
		"HID_ID=0003:000016C0:000005DF\nHID_ID=x\n", // a bad second line
		" HID_ID=0003:000016C0:000005DF\n",	 // not at the line's start
	};
	for (const char *t : bad) {
		INFO(t);
		HidrawDevice u;
		u.name = "kept";
		CHECK_FALSE(parseHidUevent(t, u));
		CHECK(u.name == "kept");
		CHECK(u.vendor == 0);
	}
}

TEST_CASE("sk usb: the board found in sysfs by its ID, several refused with a list, path= picks one")
{
	FakeSysfs fs;
	CHECK(listHidraw(fs.root).empty());
	auto none = ecmxftest::thrown([&] { (void)findSkUsb(listHidraw(fs.root)); });
	CHECK(none.errnoValue() == ENODEV);
	CHECK(has(none.what(), "16C0:05DF"));
	CHECK(has(none.what(), "there are none"));

	fs.add(0, "0003:0000046D:0000C31C", "Logitech USB Keyboard", "1-2");
	fs.add(3, kSkId, "NEXTW ECM-SK", "1-1.2");
	fs.add(5, kSkId, "uhid look-alike", ""); // the ID, but not on USB
	const auto all = listHidraw(fs.root);
	REQUIRE(all.size() == 3);
	CHECK(all[0].node == "/dev/hidraw0");
	CHECK(all[0].usbPath == "1-2");
	CHECK(all[1].usbPath == "1-1.2");
	CHECK(all[2].usbPath.empty());
	const HidrawDevice one = findSkUsb(all);
	CHECK(one.node == "/dev/hidraw3");
	CHECK(one.name == "NEXTW ECM-SK");
	CHECK(one.describe() == "/dev/hidraw3 (16C0:05DF \"NEXTW ECM-SK\", USB path 1-1.2)");

	fs.add(12, kSkId, "V-USB hobby device", "3-4");
	const auto two = listHidraw(fs.root);
	REQUIRE(two.size() == 4);
	CHECK(two[3].node == "/dev/hidraw12"); // by number, not as text
	auto several = ecmxftest::thrown([&] { (void)findSkUsb(two); });
	CHECK(several.errnoValue() == EINVAL);
	CHECK(has(several.what(), "2 devices carry"));
	CHECK(has(several.what(), "/dev/hidraw3 (16C0:05DF \"NEXTW ECM-SK\", USB path 1-1.2)"));
	CHECK(has(several.what(), "/dev/hidraw12 (16C0:05DF \"V-USB hobby device\", USB path 3-4)"));
	CHECK(has(several.what(), "sk-usb:?path=<USB path>"));
	CHECK_FALSE(has(several.what(), "hidraw0"));
	CHECK(findSkUsb(two, "3-4").node == "/dev/hidraw12");
	CHECK(findSkUsb(two, "1-1.2").node == "/dev/hidraw3");
	auto nowhere = ecmxftest::thrown([&] { (void)findSkUsb(two, "9-9"); });
	CHECK(nowhere.errnoValue() == ENODEV);
	CHECK(has(nowhere.what(), "at USB path 9-9"));
	CHECK(has(nowhere.what(), "/dev/hidraw0 (046D:C31C \"Logitech USB Keyboard\", USB path 1-2)"));

	// a node whose uevent is unreadable or malformed is left out
	std::ofstream(fs.root + "/class/hidraw/hidraw0/device/uevent") << "HID_ID=bad\n";
	CHECK(listHidraw(fs.root).size() == 3);
}

TEST_CASE("sk usb: sk-usb: URIs, and bad ones named")
{
	using K = DeviceUri::Kind;
	auto u = parseDeviceUri("sk-usb:");
	CHECK(u.kind == K::SkUsb);
	CHECK(u.isSk());
	CHECK(u.path.empty());
	CHECK(u.skUsbPath.empty());
	u = parseDeviceUri("sk-usb:/dev/hidraw3?slot=16&ex=3&trace=/tmp/t.txt");
	CHECK(u.path == "/dev/hidraw3");
	CHECK(u.skSlotSize == 16);
	CHECK(u.skExtensions == 3u);
	CHECK(u.trace == "/tmp/t.txt");
	u = parseDeviceUri("sk-usb:?path=1-1.2");
	CHECK(u.path.empty());
	CHECK(u.skUsbPath == "1-1.2");

	const std::pair<const char *, const char *> bad[] = {
		{ "sk-usb:hidraw3", "must be an absolute path" },
		{ "sk-usb:?path=", "bad path value" },
		{ "sk-usb:?path=abc", "bad path value \"abc\"" },
		{ "sk-usb:?path=1", "bad path value \"1\"" },
		{ "sk-usb:?path=1-1/x", "bad path value" },
		{ "sk-usb:/dev/hidraw0?path=1-1", "not both" },
		{ "sk-usb:?busy=gpiochip0:1", "unknown option \"busy\" (sk-usb: takes path, slot, ex and trace)" },
		{ "sk-usb:?slot=13", "the slot size is 12 or 16" },
		{ "sk-usb:?ex=4", "bad ex value" },
		{ "sk-usb:?path=1-1&path=1-2", "given twice" },
	};
	for (const auto &b : bad) {
		INFO(b.first);
		const Error e = ecmxftest::thrown([&] { (void)parseDeviceUri(b.first); });
		CHECK(e.errnoValue() == EINVAL);
		CHECK(has(e.what(), b.second));
		CHECK(has(e.what(), "sk-usb:[/dev/hidrawN]"));
	}
}

TEST_CASE("sk usb: bring-up to OP, an SDO and a CSP move through the USB channel")
{
	FakeSkUsb f;
	auto b = usbBoard(f);
	CHECK(b->channel().name() == "sk-usb:fake");
	b->states().set(ecmxf::State::PreOp);
	const std::vector<sk::SlaveType> types = { sk::SlaveType::Drive, sk::SlaveType::Step, sk::SlaveType::Io };
	CHECK(b->setup().setAxes(types) == 3u);
	unsigned size = 0;
	(void)b->sdo().read(1, 0x6041, 0, &size); // the statusword
	CHECK(size == 2u);
	b->states().set(ecmxf::State::Op);
	b->drives().servoOn(2);
	b->drives().waitEnabled(2);
	b->states().status();
	const auto p = b->drives().axis(2).position;
	for (int i = 1; i <= 100; i++) {
		REQUIRE(b->cyclic().stage(2, sk::Mode::Csp, p + 10 * i));
		REQUIRE(b->cyclic().cycle().status == sk::CycleStatus::Ok);
		std::this_thread::sleep_for(800us);
	}
	// the board runs its FIFO at its own cycle, which the host's loop above
	// did not follow: cycles until it has run the last target
	for (int i = 0; i < 1000 && std::abs(b->drives().axis(2).position - (p + 1000)) > 5; i++) {
		b->cyclic().cycle();
		std::this_thread::sleep_for(1ms);
	}
	CHECK(std::abs(b->drives().axis(2).position - (p + 1000)) <= 5);
	// every frame one 513-byte write (report ID 0, 512 bytes), every one
	// taken by the board, none while it was busy
	std::lock_guard<std::mutex> l(f.mu);
	CHECK(f.outSizes.size() == f.outReports);
	for (const std::size_t n : f.outSizes)
		CHECK(n == kSkUsbReportSize + 1);
	CHECK(f.board.stats().frames == f.outReports);
	CHECK(f.board.stats().whileBusy == 0u);
}

TEST_CASE("sk usb: 504-byte frames (slot 12) go out padded with zeros, 512-byte ones (slot 16) whole")
{
	for (const unsigned slot : { 12u, 16u }) {
		INFO("slot " << slot);
		sk::BoardConfig cfg;
		cfg.slotSize = slot;
		FakeSkUsb f(cfg);
		sk::LinkOptions o;
		o.slotSize = slot;
		auto b = usbBoard(f, o);
		CHECK(b->link().frameSize() == (slot == 12 ? 504u : 512u));
		b->states().set(ecmxf::State::PreOp);
		CHECK(b->state() == ecmxf::State::PreOp);
		std::lock_guard<std::mutex> l(f.mu);
		REQUIRE_FALSE(f.outSizes.empty());
		for (const std::size_t n : f.outSizes)
			CHECK(n == kSkUsbReportSize + 1);
		REQUIRE(f.lastOut.size() == kSkUsbReportSize + 1);
		CHECK(f.lastOut[0] == 0); // the report ID
		if (slot == 12)
			CHECK(std::all_of(f.lastOut.begin() + 505, f.lastOut.end(), [](std::uint8_t v) { return v == 0; }));
	}
}

TEST_CASE("sk usb: stale IN reports are drained and counted before a result is trusted")
{
	FakeSkUsb f;
	auto ch = std::make_unique<HidrawChannel>(f.takeHost(), "sk-usb:fake");
	HidrawChannel *c = ch.get();
	sk::Board b(std::move(ch));
	b.states().set(ecmxf::State::PreOp);
	CHECK(c->staleReports() == 0u);
	f.queueStale(3); // taken for answers, they would say state 0xA5
	CHECK(b.states().status().state == ecmxf::State::PreOp);
	CHECK(c->staleReports() == 3u);
	CHECK(b.state() == ecmxf::State::PreOp);
	const std::vector<sk::SlaveType> types = { sk::SlaveType::Drive, sk::SlaveType::Step, sk::SlaveType::Io };
	CHECK(b.setup().setAxes(types) == 3u);
	f.queueStale(1);
	CHECK(b.setup().setAxes(types) == 3u);
	CHECK(c->staleReports() == 4u);
}

TEST_CASE("sk usb: unplugged mid-run is reported at once, no hang")
{
	FakeSkUsb f;
	// a long timeout: waiting for it would end in ETIMEDOUT, not ENODEV
	auto b = usbBoard(f, {}, 10000ms);
	b->states().set(ecmxf::State::PreOp);
	f.faults.unplug = true;
	const Error e = ecmxftest::thrown([&] { b->states().status(); });
	CHECK(e.errnoValue() == ENODEV);
	CHECK(has(e.what(), "sk-usb:fake: the ECM-SK is gone (unplugged?)"));
	CHECK(b->cyclic().cycle().status == sk::CycleStatus::Link);
	CHECK(has(b->cyclic().lastError(), "gone"));
}

TEST_CASE("sk usb: no answer is a timeout, a report of another length and a foreign device's bytes are errors")
{
	{
		FakeSkUsb f;
		auto b = usbBoard(f, {}, 20ms);
		f.faults.silent = true;
		const Error e = ecmxftest::thrown([&] { b->states().status(); });
		CHECK(e.errnoValue() == ETIMEDOUT);
		CHECK(has(e.what(), "no IN report (the answer) within 20 ms"));
	}
	{
		FakeSkUsb f;
		auto b = usbBoard(f);
		f.faults.shortReport = 64;
		const Error e = ecmxftest::thrown([&] { b->states().status(); });
		CHECK(e.errnoValue() == EBADMSG);
		CHECK(has(e.what(), "an IN report of 64 bytes, the ECM-SK's are 512"));
	}
	{
		// another device on the same ID: with the response CRC in force
		// the check says so, never a wrong value
		sk::BoardConfig cfg;
		cfg.extensions = 2;
		FakeSkUsb f(cfg);
		sk::LinkOptions o;
		o.extensions = 2;
		auto b = usbBoard(f, o);
		f.faults.garbage = true;
		const Error e = ecmxftest::thrown([&] { b->states().status(); });
		CHECK(e.errnoValue() == EBADMSG);
		CHECK(has(e.what(), "CRC-8"));
	}
}

TEST_CASE("sk usb: the channel's bad inputs: no descriptor, a node that is no hidraw, a missing node")
{
	CHECK(ecmxftest::thrown([] { HidrawChannel c(-1, "sk-usb:x"); }).errnoValue() == EBADF);
	const Error notHid = ecmxftest::thrown([] { HidrawChannel c("/dev/null"); });
	CHECK(has(notHid.what(), "sk-usb:/dev/null: not a hidraw node (HIDIOCGRAWINFO)"));
	const Error missing = ecmxftest::thrown([] { HidrawChannel c("/dev/hidraw-none"); });
	CHECK(missing.errnoValue() == ENOENT);
	CHECK(has(missing.what(), "sk-usb:/dev/hidraw-none: cannot open"));
	FakeSkUsb f;
	HidrawChannel c(f.takeHost(), "sk-usb:fake");
	std::vector<std::uint8_t> big(600), small(12);
	CHECK(ecmxftest::thrown([&] { c.exchange(big, big); }).errnoValue() == EINVAL);
	CHECK(ecmxftest::thrown([&] { c.exchange(big, small); }).errnoValue() == EINVAL);
}
