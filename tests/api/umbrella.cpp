// SPDX-License-Identifier: MIT
//
// <ecmxf/ecmxf.hpp> alone gives the whole public API: one name from each
// part, with no other include (compiled into ecmxf_public_api).
#include <ecmxf/ecmxf.hpp>

namespace {

[[maybe_unused]] void umbrella(ecmxf::Device &dev)
{
	(void)dev.bus().slaveCount();
	(void)dev.sdo().read<std::uint32_t>(0, 0x1018, 1);
	(void)dev.slaves().mailboxPending();
	(void)dev.chip().firmwareVersion();
	(void)dev.peripherals().gpioRead();
	(void)dev.chip402().state(0);
	(void)dev.pdo().read();
	ecmxf::Master master(dev);
	ecmxf::ProcessImage image(master.pdos());
	ecmxf::Cyclic cyclic(dev, image, ecmxf::CyclicConfig{});
	ecmxf::EventDetector detector(ecmxf::EventDetector::Config{});
	(void)ecmxf::describeErrorStatus(0);
	(void)ecmxf::parseDeviceUri("sim:");
	(void)sizeof(ecmxf::Cia402Axis);
	(void)sizeof(ecmxf::KernelLink);
	(void)sizeof(ecmxf::SpidevChannel);
	(void)sizeof(ecmxf::UnixChannel);
	(void)sizeof(ecmxf::SimChannel);
	(void)sizeof(ecmxf::sim::Chip);
	(void)sizeof(ecmxf::sk::Board);
	(void)sizeof(ecmxf::sk::BoardDrives);
	(void)sizeof(ecmxf::sk::SlotLink);
	(void)ecmxf::masterKindName(ecmxf::MasterKind::EcmSk);
	(void)sizeof(ecmxf::SnapshotExchange);
	(void)sizeof(ecmxf::Error);
}

} // namespace
