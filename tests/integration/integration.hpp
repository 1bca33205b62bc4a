// SPDX-License-Identifier: MIT
//
// The integration suite's rig: the device under test (ECMXF_TEST_URI, by
// default the simulator with est584x2-io-loopback.net), which transport it
// is, and the bring-up every test case starts from. Only the public API.
//
// The network is the default one (EST-584, EST-584, dio) with the dio's
// inputs looped back to its outputs. Expected values come from the
// manuals and the simulator's documented models (Documentation/
// sim-slaves.rst, sim-peripherals.rst), never from the code's output.
//
// Over /dev/ecmxf0 and spidev the chip outlives a test case (it is the
// bridge's simulated chip in the QEMU guest): every test case opens the
// device afresh, initializes the bus (ECAT_INIT_OP) and switches the
// chip's CiA-402 engine off for both drives (its configuration survives
// INIT_OP), and puts back what it changed outside that (link format,
// interrupt enables, GPIO modes, the WKC limit).

#pragma once

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/chip/chip402.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/spidev_channel.hpp>

#ifndef ECMXF_TEST_DEFAULT_URI
#define ECMXF_TEST_DEFAULT_URI "sim:"
#endif

namespace integ {

using namespace std::chrono_literals;

/// The device under test.
inline std::string uri()
{
	const char *u = std::getenv("ECMXF_TEST_URI");
	return u && *u ? std::string(u) : std::string(ECMXF_TEST_DEFAULT_URI);
}

enum class Kind { Sim, Kernel, Spidev };

inline Kind kindOf(const std::string &u)
{
	switch (ecmxf::parseDeviceUri(u).kind) {
	case ecmxf::DeviceUri::Kind::Kernel:
		return Kind::Kernel;
	case ecmxf::DeviceUri::Kind::Spidev:
		return Kind::Spidev;
	case ecmxf::DeviceUri::Kind::Sim:
	case ecmxf::DeviceUri::Kind::Unix: // an ecmxf-sim server: the simulator, virtual time
	default:			   // the ECM-SK's: Device::open() refuses them
		break;
	}
	return Kind::Sim;
}

/// The check word the chip uses when the test starts: the simulator's
/// chip is fresh (power-on: fixed); ecmxf.ko sets CRC-32 at probe
/// (driver.rst, check_type default 3); over spidev, what the URI says
/// (check=, else the power-on fixed).
inline ecmxf::CheckType startCheckType(const std::string &u)
{
	const ecmxf::DeviceUri p = ecmxf::parseDeviceUri(u);
	switch (p.kind) {
	case ecmxf::DeviceUri::Kind::Kernel:
		return ecmxf::CheckType::Crc32;
	case ecmxf::DeviceUri::Kind::Spidev:
		return p.checkType.value_or(ecmxf::CheckType::Fixed);
	case ecmxf::DeviceUri::Kind::Sim:
	case ecmxf::DeviceUri::Kind::Unix:
	default:
		break;
	}
	return ecmxf::CheckType::Fixed;
}

/// The chip's CiA-402 engine off for both drives (402_CONFIG_SET with
/// control byte 0): its configuration survives ECAT_INIT_OP, and a test
/// case that drives the controlword itself must not share it.
inline void engineOff(ecmxf::Device &d)
{
	for (unsigned m = 0; m < 2; m++)
		d.chip402().configure(m, ecmxf::Chip402Config{ m, 0, 0, {} });
}

/// The EST-584's default PDO assignment (manual 5.4.1): RxPDO 0x1600 =
/// controlword, target position, position offset, touch probe function
/// (12 bytes); TxPDO 0x1A00 = statusword, modes display, position actual,
/// touch probe status, touch probe position 1, digital inputs (17 bytes).
inline ecmxf::SlavePdoAssignment est584DefaultPdos(std::uint8_t slave)
{
	ecmxf::SlavePdoAssignment a;
	a.slave = slave;
	a.rxPdos = std::vector<ecmxf::PdoDef>{
		{ 0x1600, { { 0x6040, 0, 16 }, { 0x607A, 0, 32 }, { 0x60B0, 0, 32 }, { 0x60B8, 0, 16 } } }
	};
	a.txPdos = std::vector<ecmxf::PdoDef>{ { 0x1A00,
						 { { 0x6041, 0, 16 },
						   { 0x6061, 0, 8 },
						   { 0x6064, 0, 32 },
						   { 0x60B9, 0, 16 },
						   { 0x60BA, 0, 32 },
						   { 0x60FD, 0, 32 } } } };
	return a;
}

/// A MasterConfig for the test network that starts from a known state
/// whatever earlier test cases left on the slaves: 3 slaves, SYNC0 1 ms
/// (the EST-584 accepts 1000 us, manual 2.3), the 402 engine off right
/// after the init step, both EST-584s with their default PDO assignment
/// and in CSP (0x6060 = 8, the models' power-on mode) -- the mapping and
/// the mode survive ECAT_INIT_OP on the slaves, as on real drives.
inline ecmxf::MasterConfig masterConfig(ecmxf::Device &d)
{
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = 1'000'000;
	mc.expectedSlaves = 3;
	mc.pdoAssignments = { est584DefaultPdos(0), est584DefaultPdos(1) };
	mc.startupSdos = { { 0, 0x6060, 0, { 8 } }, { 1, 0x6060, 0, { 8 } } };
	mc.onStep = [&d](std::string_view step) {
		if (step == "scan")
			engineOff(d);
	};
	return mc;
}

/// The known state without the rest of the bring-up: masterConfig() up
/// to PRE-OP, then every slave back to INIT (FIFO off).
inline void initBus(ecmxf::Device &d)
{
	ecmxf::Master m(d);
	ecmxf::MasterConfig mc = masterConfig(d);
	mc.target = ecmxf::State::PreOp;
	mc.enableFifo = false;
	mc.readPdoMapping = false;
	m.bringUp(mc);
	d.pdo().fifoEnable(false);
	d.bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::Init);
}

/// The Cyclic settings of the tests: 1 ms application and bus cycle, a
/// small RxFIFO fill. Over a real transport each command may take 1 s
/// (not the table's 100 ms): in the QEMU guest under TCG on a loaded host
/// one round trip can stall beyond 100 ms (seen: ETIMEDOUT of
/// ECAT_PDO_DATA_FIFO_OP at a load average of 7 on 2 cores). Timing is
/// not what these tests check.
inline ecmxf::CyclicConfig cyclicConfig(const std::string &u)
{
	ecmxf::CyclicConfig cc;
	cc.period = 1ms;
	cc.busCycle = 1ms;
	cc.rxFill = 2;
	if (kindOf(u) != Kind::Sim)
		cc.commandTimeout = 5s;
	return cc;
}

/// A time limit of the tests: @p simLimit on the simulator; over a real
/// transport (the QEMU guest under TCG, where a cycle took up to 0.5 s on
/// a loaded host) twelve times as much. The limits catch a hang; timing
/// is not what these tests check.
inline std::chrono::nanoseconds patience(const std::string &u, std::chrono::nanoseconds simLimit)
{
	return kindOf(u) == Kind::Sim ? simLimit : simLimit * 12;
}

/// Cia402Axis settings of the tests: the library's defaults on the
/// simulator, patience() for every wait over a real transport.
inline ecmxf::Cia402AxisConfig axisConfig(const std::string &u, std::vector<std::int8_t> modes)
{
	ecmxf::Cia402AxisConfig c;
	c.modes = std::move(modes);
	c.ackTimeout = patience(u, c.ackTimeout);
	c.modeTimeout = patience(u, c.modeTimeout);
	c.state.timeout = patience(u, c.state.timeout);
	return c;
}

/// @p u opened; over a real transport every command gets at least 5 s
/// (Device::setMinimumTimeout): in the QEMU guest under TCG on a loaded
/// host a round trip stalled beyond the table's 100 ms (seen:
/// FW_VERSION_GET over spidev at a load average of 6 on 2 cores), and on
/// the debug kernel at a load average of 7 a cyclic ECAT_PDO_DATA_FIFO_OP
/// over spidev beyond 2 s. Timing is not what these tests check.
inline std::unique_ptr<ecmxf::Device> opened(const std::string &u, Kind kind)
{
	auto d = ecmxf::Device::open(u);
	if (kind != Kind::Sim)
		d->setMinimumTimeout(std::chrono::seconds(5));
	return d;
}

/// A freshly opened device.
struct Rig {
	std::string u = uri();
	Kind kind = kindOf(u);
	std::unique_ptr<ecmxf::Device> dev = opened(u, kind);

	ecmxf::Device &d() { return *dev; }
	[[nodiscard]] bool isKernel() const { return kind == Kind::Kernel; }
	[[nodiscard]] bool isSpidev() const { return kind == Kind::Spidev; }
	[[nodiscard]] bool isSim() const { return kind == Kind::Sim; }
};

/// Runs @p f, returns the ecmxf::Error (of type E) it throws; fails the
/// test case when it throws none.
template <typename E = ecmxf::Error, typename F>
E thrown(F &&f)
{
	try {
		f();
	} catch (const E &e) {
		return e;
	}
	throw std::runtime_error("expected an exception, none was thrown");
}

} // namespace integ
