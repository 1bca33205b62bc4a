// SPDX-License-Identifier: MIT
// ecmxf-sim --board ecm-sk (utils/ecmxf-sim-sk.cpp).
#pragma once

/// Does the command line ask for the ECM-SK board (--board ecm-sk)?
bool ecmxfSimWantsSk(int argc, char **argv);
/// ecmxf-sim's main for the ECM-SK; throws std::exception on bad options.
int ecmxfSimSkMain(int argc, char **argv);
