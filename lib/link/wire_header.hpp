// SPDX-License-Identifier: MIT
// Internal: the one mapping each way between the wire's headers (the
// protocol core's and the uAPI's, same field names) and RawRequest /
// ResponseHeader.
#pragma once

#include <ecmxf/link/link.hpp>

#include <cstddef>

namespace ecmxf::detail {

/// The response header's fields: the library's name, the wire's name (one
/// list, read by both directions below).
#define ECMXF_RSP_HEADER_FIELDS(X)                                                                            \
	X(crcErrCnt, crc_err_cnt)                                                                             \
	X(wkcErrCnt, wkc_err_cnt)                                                                             \
	X(txFifoCnt, tx_fifo_cnt)                                                                             \
	X(rxFifoCnt, rx_fifo_cnt)                                                                             \
	X(ecatState, ecat_state)                                                                              \
	X(errStatus, err_status)                                                                              \
	X(ecmStatus, ecm_status)                                                                              \
	X(index, index)                                                                                       \
	X(code, code)                                                                                         \
	X(ret, ret)                                                                                           \
	X(len, len)                                                                                           \
	X(intFlags, int_flags)                                                                                \
	X(gpioIntFlag[0], gpio_int_flag[0])                                                                   \
	X(gpioIntFlag[1], gpio_int_flag[1])                                                                   \
	X(gpioIn[0], gpio_in[0])                                                                              \
	X(gpioIn[1], gpio_in[1])

/// The response header fields of the protocol core's struct ecmxf_rsp_hdr
/// or the uAPI's struct ecmxf_rsp_header (same field names).
template <typename Wire>
ResponseHeader headerFrom(const Wire &h) noexcept
{
	ResponseHeader r;
#define ECMXF_FROM_WIRE(lib, wire) r.lib = h.wire;
	ECMXF_RSP_HEADER_FIELDS(ECMXF_FROM_WIRE)
#undef ECMXF_FROM_WIRE
	return r;
}

/// @p h as the protocol core's struct ecmxf_rsp_hdr (or the uAPI's struct
/// ecmxf_rsp_header): headerFrom() the other way round.
template <typename Wire>
Wire wireHeader(const ResponseHeader &h) noexcept
{
	Wire r{};
#define ECMXF_TO_WIRE(lib, wire) r.wire = h.lib;
	ECMXF_RSP_HEADER_FIELDS(ECMXF_TO_WIRE)
#undef ECMXF_TO_WIRE
	return r;
}

#undef ECMXF_RSP_HEADER_FIELDS

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
