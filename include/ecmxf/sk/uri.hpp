// SPDX-License-Identifier: MIT
/**
 * @file uri.hpp
 * @brief The ECM-SK device URIs: since the shared vocabulary, kinds of
 *        ecmxf::DeviceUri (SkSim, SkUnix, SkSpidev) parsed by
 *        ecmxf::parseDeviceUri() (<ecmxf/device_uri.hpp>, which lists the
 *        forms). This header stays one release for the names it had.
 */
#pragma once

#include <ecmxf/device_uri.hpp>

namespace ecmxf::sk {

using ecmxf::kSkMaxSpeedHz;
using ecmxf::kSkUriForms;

} // namespace ecmxf::sk
