// SPDX-License-Identifier: MIT
/*
 * ecmxf-util scope, and the plot files of cia402 move --plot
 * (ecmxf-util-scope.cpp).
 */
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "ecmxf-util-cia402-motion.hpp"
#include "ecmxf-util.hpp"

namespace ecmxf_util {

extern const char *const kScopeHelp;
int cmdScope(Globals &g, const Args &args);

/// The bus of a command that runs the cyclic exchange (data, scope): a
/// fresh bus is brought to OP (SYNC0 1 ms; with @p motionPdos as
/// bringUpMotion() does), a bus that is up is rescanned and each slave's
/// mapping read.
struct ProcessDataBus {
	DevicePtr dev;
	std::unique_ptr<ecmxf::Master> master;
	std::vector<ecmxf::SlavePdos> pdos;
};
ProcessDataBus openProcessDataBus(const Globals &g, bool motionPdos);
/// A number for a person: 6 significant digits.
std::string shortNumber(double v);

} // namespace ecmxf_util
