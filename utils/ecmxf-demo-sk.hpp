// SPDX-License-Identifier: MIT
// ecmxf-demo --board ecm-sk (utils/ecmxf-demo-sk.cpp).
#pragma once

/// The ECM-SK tour; @p fast: do not pace in real time. Exit code.
int ecmxfDemoSk(bool fast);
