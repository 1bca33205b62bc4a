// SPDX-License-Identifier: MIT
// ecmxf-util with an ECM-SK device (utils/ecmxf-util-sk.cpp): the bodies of
// the commands of the one table (utils/ecmxf-util.cpp) on an ECM-SK.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include <ecmxf/verbs.hpp>

#include "ecmxf-util.hpp"

namespace ecmxf_util {

/// Is g.device an ECM-SK URI ("sk-sim:", "sk-unix:", "sk-spidev:")?
bool skDevice(const Globals &g);
/// The help of the commands on an ECM-SK (each one's --help there).
const char *skHelp() noexcept;

// What differs between the masters in the shared bodies (upload, download):

/// The master g.device names (MasterVerbs::open()); --trace on an ECM-SK
/// is a UsageError (traces are of ECM-XF packets).
std::unique_ptr<ecmxf::MasterVerbs> openMaster(const Globals &g);
/// The bus as far up as SDO needs (ECM-XF: ensureBus(PRE-OP) and
/// selectSlave(); ECM-SK: PRE-OP from INIT), @p position checked against
/// its slaves.
std::uint8_t sdoPosition(const Globals &g, ecmxf::MasterVerbs &m, std::uint8_t position);
/// On an ECM-SK, a -t TYPE of other than 1, 2 or 4 bytes: EOPNOTSUPP.
void checkSdoType(const Globals &g, const char *cmd, const std::optional<DataType> &type);

int cmdSkInfo(Globals &g, const Args &args);
int cmdSkSlaves(Globals &g, const Args &args);
int cmdSkStates(Globals &g, const Args &args);
int cmdSkCia402(Globals &g, const Args &args);
int cmdSkIo(Globals &g, const Args &args);
int cmdSkLio(Globals &g, const Args &args);
int cmdSkReset(Globals &g, const Args &args);

} // namespace ecmxf_util
