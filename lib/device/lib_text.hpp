// SPDX-License-Identifier: MIT
// Internal: the words the library's messages share, and the one mapping
// each way between the wire's headers and RawRequest / ResponseHeader.
#pragma once

#include <ecmxf/link/link.hpp>

#include <cstdint>
#include <string>
#include <string_view>

namespace ecmxf::detail {

/// The manual name of @p code ("ECAT_SDO_REQ"), or "command 0x4D".
std::string commandName(std::uint8_t code);
/// "0x5A".
std::string hex8(unsigned v);
/// Bit numbers set in @p status: "bit 3" / "bits 3, 7".
std::string bitList(std::uint8_t status);
/// "10000 ms", or "250 us" for times that are not whole milliseconds.
std::string durationUs(std::uint64_t us);
/// @p s in double quotes.
std::string quoted(std::string_view s);

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

/// @p h as the protocol core's struct ecmxf_rsp_hdr (or the uAPI's struct
/// ecmxf_rsp_header): headerFrom() the other way round.
template <typename Wire>
Wire wireHeader(const ResponseHeader &h) noexcept
{
	Wire r{};
	r.crc_err_cnt = h.crcErrCnt;
	r.wkc_err_cnt = h.wkcErrCnt;
	r.tx_fifo_cnt = h.txFifoCnt;
	r.rx_fifo_cnt = h.rxFifoCnt;
	r.ecat_state = h.ecatState;
	r.err_status = h.errStatus;
	r.ecm_status = h.ecmStatus;
	r.index = h.index;
	r.code = h.code;
	r.ret = h.ret;
	r.len = h.len;
	r.int_flags = h.intFlags;
	r.gpio_int_flag[0] = h.gpioIntFlag[0];
	r.gpio_int_flag[1] = h.gpioIntFlag[1];
	r.gpio_in[0] = h.gpioIn[0];
	r.gpio_in[1] = h.gpioIn[1];
	return r;
}

/// The command header fields of @p req into the protocol core's struct
/// ecmxf_cmd_hdr or the uAPI's struct ecmxf_cmd_header (same field names;
/// the reserved word, named differently, is the caller's).
template <typename Wire>
void headerTo(const RawRequest &req, Wire &h) noexcept
{
	for (std::size_t i = 0; i < req.data.size(); i++)
		h.data[i] = req.data[i];
	h.control = req.control;
	h.code = req.code;
	h.param = req.param;
	h.len = req.len;
	h.int_clear = req.intClear;
	h.gpio_int_clear[0] = req.gpioIntClear[0];
	h.gpio_int_clear[1] = req.gpioIntClear[1];
	h.gpio_out[0] = req.gpioOut[0];
	h.gpio_out[1] = req.gpioOut[1];
}

} // namespace ecmxf::detail
