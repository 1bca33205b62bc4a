// SPDX-License-Identifier: MIT
// The public C++ API spells some of the chip's numbers as its own constants
// (irq::*, async_reset::*, State); <linux/ecmxf.h> is the one list of them, which the
// protocol core uses and tests/uapi checks against the manuals. Here the
// C++ names are pinned to it, so that the two cannot drift. No code.

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/model/types_chip.hpp>

#include "ecmxf-proto.h"

namespace ecmxf {

static_assert(irq::kEcatPacket == ECMXF_INT_ECAT_PKT);
static_assert(irq::kEncoder == ECMXF_INT_ENCODER);
static_assert(irq::kRxFifoLow == ECMXF_INT_RXFIFO_LOW);
static_assert(irq::kTxFifoHigh == ECMXF_INT_TXFIFO_HIGH);
static_assert(irq::kCrcError == ECMXF_INT_CRC_ERR);
static_assert(irq::kWkcError == ECMXF_INT_WKC_ERR);

static_assert(async_reset::kClearBusy == ECMXF_RESET_ASYNC_CLEAR_BUSY);
static_assert(async_reset::kSkipLinkWait == ECMXF_RESET_ASYNC_SKIP_LINK);
static_assert(async_reset::kAbandon == ECMXF_RESET_ASYNC_ABANDON);

static_assert(static_cast<unsigned>(State::None) == ECMXF_ECAT_NONE);
static_assert(static_cast<unsigned>(State::Init) == ECMXF_ECAT_INIT);
static_assert(static_cast<unsigned>(State::PreOp) == ECMXF_ECAT_PREOP);
static_assert(static_cast<unsigned>(State::Boot) == ECMXF_ECAT_BOOT);
static_assert(static_cast<unsigned>(State::SafeOp) == ECMXF_ECAT_SAFEOP);
static_assert(static_cast<unsigned>(State::Op) == ECMXF_ECAT_OP);

} // namespace ecmxf
