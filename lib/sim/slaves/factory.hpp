// SPDX-License-Identifier: MIT
//
// factory.hpp - constructors of the slave models, by type name.
//
// Network files name a slave type and options ("slave EST-584 alias=7");
// Network::makeSlave() dispatches here. Each model validates its own
// options and throws std::invalid_argument naming an unknown or bad one.

#pragma once

#include <map>
#include <memory>
#include <string>

#include <ecmxf/sim/network.hpp>

namespace ecmxf::sim {

/// key=value options of one "slave" line (keys lower-case).
using SlaveOptions = std::map<std::string, std::string>;

std::unique_ptr<Slave> makeEst584(unsigned position, const SlaveOptions &opts);
std::unique_ptr<Slave> makeServo(unsigned position, const SlaveOptions &opts);
std::unique_ptr<Slave> makeDio(unsigned position, const SlaveOptions &opts);
std::unique_ptr<Slave> makeHsp(unsigned position, const SlaveOptions &opts);

} // namespace ecmxf::sim
