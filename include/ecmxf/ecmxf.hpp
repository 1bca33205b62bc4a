// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/ecmxf.hpp
 * @brief The whole public API of libecmxf in one include.
 *
 *   #include <ecmxf/ecmxf.hpp>
 *
 *   auto dev = ecmxf::Device::open("sim:");
 *   dev->bus().initNetwork();
 *   const auto id = dev->sdo().read<std::uint32_t>(0, 0x1018, 1);
 *
 * The device and its URIs, errors, every typed-call view (Bus, Sdo,
 * SlaveAccess, Master, Chip, Peripherals, Chip402, ProcessData), the
 * process image and the cyclic exchange, CiA-402, events, packet traces,
 * the links and byte channels, the simulator, and the ECM-SK starter kit
 * (ecmxf::sk::Board). A program that wants to compile less includes the
 * headers it uses one by one instead; each compiles alone
 * (tests/api). Documentation/library.rst.
 */
#pragma once

// the device, its URIs, errors, protocol numbers
#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>

// the links and byte channels
#include <ecmxf/link/link.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/link/hidraw_channel.hpp>
#include <ecmxf/link/unix_channel.hpp>

// bus: dev.bus(), dev.sdo(), dev.slaves(); Master; status words
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/model/status.hpp>

// chip: dev.chip(), dev.peripherals(), dev.chip402()
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/chip/chip402.hpp>
#include <ecmxf/chip/peripherals.hpp>

// process data: dev.pdo(), ProcessImage, Cyclic
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/model/pdo_mapping.hpp>
#include <ecmxf/model/objects.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/pdo/realtime.hpp>

// CiA-402: the state machine, Cia402Axis
#include <ecmxf/model/cia402.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>

// events, packet traces
#include <ecmxf/events/events.hpp>
#include <ecmxf/trace/trace.hpp>

// the simulator
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>

// the ECM-SK starter kit: sk::Board, its views, its link and simulator
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/board_views.hpp>
#include <ecmxf/sk/sim_channel.hpp>
#include <ecmxf/sk/slot_link.hpp>
#include <ecmxf/sk/uri.hpp>

// the scope: the recorder, its CSV and SVG writers, its terminal text and
// the snapshots a drawing thread draws from
#include <ecmxf/scope/plot.hpp>
#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/scope/snapshot.hpp>
#include <ecmxf/scope/terminal.hpp>

// the verbs both masters have: MasterVerbs over a Device or an sk::Board
#include <ecmxf/verbs.hpp>
