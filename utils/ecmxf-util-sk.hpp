// SPDX-License-Identifier: MIT
// ecmxf-util with an ECM-SK device (utils/ecmxf-util-sk.cpp).
#pragma once

#include <string_view>

#include "ecmxf-util.hpp"

namespace ecmxf_util {

/// Is g.device an ECM-SK URI ("sk-sim:", "sk-unix:", "sk-spidev:")?
bool skDevice(const Globals &g);
/// Runs command @p name with @p args on the ECM-SK; -1 when the command is
/// the common one (version). Commands the board cannot do throw with why.
int skRun(Globals &g, std::string_view name, const Args &args);

} // namespace ecmxf_util
