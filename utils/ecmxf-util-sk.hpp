// SPDX-License-Identifier: MIT
// ecmxf-util with an ECM-SK device (utils/ecmxf-util-sk.cpp): the bodies of
// the commands of the one table (utils/ecmxf-util.cpp) on an ECM-SK.
#pragma once

#include "ecmxf-util.hpp"

namespace ecmxf_util {

/// Is g.device an ECM-SK URI ("sk-sim:", "sk-unix:", "sk-spidev:")?
bool skDevice(const Globals &g);
/// The help of the commands on an ECM-SK (each one's --help there).
const char *skHelp() noexcept;

int cmdSkInfo(Globals &g, const Args &args);
int cmdSkSlaves(Globals &g, const Args &args);
int cmdSkStates(Globals &g, const Args &args);
int cmdSkUpload(Globals &g, const Args &args);
int cmdSkDownload(Globals &g, const Args &args);
int cmdSkCia402(Globals &g, const Args &args);
int cmdSkIo(Globals &g, const Args &args);
int cmdSkLio(Globals &g, const Args &args);
int cmdSkReset(Globals &g, const Args &args);

} // namespace ecmxf_util
