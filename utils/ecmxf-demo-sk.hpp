// SPDX-License-Identifier: MIT
// ecmxf-demo --board ecm-sk (utils/ecmxf-demo-sk.cpp).
#pragma once

#include <string>

/// The ECM-SK tour; @p fast: do not pace in real time; @p plotDir not
/// empty: the CSP move of both axes written there (ecmxf-demo-plot.hpp).
/// Exit code.
int ecmxfDemoSk(bool fast, const std::string &plotDir);
