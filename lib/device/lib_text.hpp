// SPDX-License-Identifier: MIT
// Internal: the words that Device (lib/device/device.cpp) and the command
// transports (lib/link/transport_command.cpp, lib/link/transport_kernel.cpp) share in
// their messages, and the one mapping of a wire response header to
// ecmxf::ResponseHeader.
#pragma once

#include <ecmxf/device.hpp>

#include <cstdint>
#include <string>

namespace ecmxf::detail {

/// The manual name of @p code ("ECAT_SDO_REQ"), or "command 0x4D".
std::string commandName(std::uint8_t code);
/// "0x5A".
std::string hex8(unsigned v);
/// Bit numbers set in @p status: "bit 3" / "bits 3, 7".
std::string bitList(std::uint8_t status);
/// "10000 ms", or "250 us" for times that are not whole milliseconds.
std::string durationUs(std::uint64_t us);

/// The response header fields of the protocol core's struct ecmxf_rsp_hdr
/// or the uAPI's struct ecmxf_rsp_header (same field names).
template <typename Wire>
ResponseHeader headerFrom(const Wire &h) noexcept
{
	ResponseHeader r;
	r.crcErrCnt = h.crc_err_cnt;
	r.wkcErrCnt = h.wkc_err_cnt;
	r.txFifoCnt = h.tx_fifo_cnt;
	r.rxFifoCnt = h.rx_fifo_cnt;
	r.ecatState = h.ecat_state;
	r.errStatus = h.err_status;
	r.ecmStatus = h.ecm_status;
	r.index = h.index;
	r.code = h.code;
	r.ret = h.ret;
	r.len = h.len;
	r.intFlags = h.int_flags;
	r.gpioIntFlag = { h.gpio_int_flag[0], h.gpio_int_flag[1] };
	r.gpioIn = { h.gpio_in[0], h.gpio_in[1] };
	return r;
}

} // namespace ecmxf::detail
