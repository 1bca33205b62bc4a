// SPDX-License-Identifier: MIT
// <linux/ecmxf_netlink.h> against the numbers written down by hand
// (nl_numbers.hpp): a renumbered attribute, command or event type is an
// ABI break and fails the build.

#include <catch2/catch.hpp>

#include <cstddef>
#include <cstring>

#include <linux/ecmxf.h>
#include <linux/ecmxf_netlink.h>

#include "nl_numbers.hpp"

#define SAME(a, b) static_assert(static_cast<int>(a) == static_cast<int>(b), #a " is not " #b)
static_assert(ECMXF_GENL_VERSION == nlabi::kVersion);
SAME(ECMXF_NL_CMD_EVENT, nlabi::CmdEvent);
SAME(ECMXF_NL_CMD_GET_COUNTERS, nlabi::CmdGetCounters);
SAME(ECMXF_NL_A_PAD, nlabi::Pad);
SAME(ECMXF_NL_A_DEV_MINOR, nlabi::DevMinor);
SAME(ECMXF_NL_A_DEV_NAME, nlabi::DevName);
SAME(ECMXF_NL_A_EVENT_TYPE, nlabi::EventType);
SAME(ECMXF_NL_A_TIMESTAMP_NS, nlabi::TimestampNs);
SAME(ECMXF_NL_A_SEQ, nlabi::Seq);
SAME(ECMXF_NL_A_SUPPRESSED, nlabi::Suppressed);
SAME(ECMXF_NL_A_OLD, nlabi::Old);
SAME(ECMXF_NL_A_NEW, nlabi::New);
SAME(ECMXF_NL_A_LINK_UP, nlabi::LinkUp);
SAME(ECMXF_NL_A_ERR_STATUS, nlabi::ErrStatus);
SAME(ECMXF_NL_A_ECM_STATUS, nlabi::EcmStatus);
SAME(ECMXF_NL_A_COUNT, nlabi::Count);
SAME(ECMXF_NL_A_INCREASE, nlabi::Increase);
SAME(ECMXF_NL_A_ERRORS, nlabi::Errors);
SAME(ECMXF_NL_A_DURATION_NS, nlabi::DurationNs);
SAME(ECMXF_NL_A_FIFO, nlabi::Fifo);
SAME(ECMXF_NL_A_MARK, nlabi::Mark);
SAME(ECMXF_NL_A_ABOVE, nlabi::Above);
SAME(ECMXF_NL_A_RESET_REASON, nlabi::ResetReason);
SAME(ECMXF_NL_A_CMD_CODE, nlabi::CmdCode);
SAME(ECMXF_NL_A_STATUS, nlabi::Status);
SAME(ECMXF_NL_A_SLAVE_COUNT, nlabi::SlaveCount);
SAME(ECMXF_NL_A_SLAVES, nlabi::Slaves);
SAME(ECMXF_NL_A_SLAVE, nlabi::Slave);
SAME(ECMXF_NL_A_AL_STATUS, nlabi::AlStatus);
SAME(ECMXF_NL_A_AL_SLAVE, nlabi::AlSlave);
SAME(ECMXF_NL_A_SLAVES_INCOMPLETE, nlabi::SlavesIncomplete);
SAME(ECMXF_NL_A_ACTION, nlabi::Action);
SAME(ECMXF_NL_A_COUNTERS, nlabi::Counters);
SAME(ECMXF_NL_A_LOSS, nlabi::Loss);
SAME(ECMXF_NL_A_TOTAL, nlabi::Total);
static_assert(ECMXF_NL_A_MAX == nlabi::Total);
SAME(ECMXF_NL_SA_POSITION, nlabi::SaPosition);
SAME(ECMXF_NL_SA_STATE, nlabi::SaState);
SAME(ECMXF_NL_SA_AL_STATUS, nlabi::SaAlStatus);
SAME(ECMXF_NL_EV_DEVICE, nlabi::EvDevice);
SAME(ECMXF_NL_EV_RESET, nlabi::EvReset);
SAME(ECMXF_NL_EV_LINK, nlabi::EvLink);
SAME(ECMXF_NL_EV_STATE, nlabi::EvState);
SAME(ECMXF_NL_EV_ERROR_STATUS, nlabi::EvErrorStatus);
SAME(ECMXF_NL_EV_ECM_STATUS, nlabi::EvEcmStatus);
SAME(ECMXF_NL_EV_CRC_ERRORS, nlabi::EvCrcErrors);
SAME(ECMXF_NL_EV_WKC_BURST, nlabi::EvWkcBurst);
SAME(ECMXF_NL_EV_WKC_BURST_END, nlabi::EvWkcBurstEnd);
SAME(ECMXF_NL_EV_FIFO, nlabi::EvFifo);
SAME(ECMXF_NL_EV_ASYNC_ERROR, nlabi::EvAsyncError);
SAME(ECMXF_NL_EV_PDO_LOSS, nlabi::EvPdoLoss);
static_assert(ECMXF_NL_EV_MAX == nlabi::EvPdoLoss);
SAME(ECMXF_NL_LOSS_OUT_RING_UNDERRUN, nlabi::LossOutRingUnderrun);
SAME(ECMXF_NL_LOSS_IN_RING_OVERRUN, nlabi::LossInRingOverrun);
SAME(ECMXF_NL_LOSS_RX_FIFO_UNDERRUN, nlabi::LossRxFifoUnderrun);
SAME(ECMXF_NL_LOSS_RX_FIFO_OVERRUN, nlabi::LossRxFifoOverrun);
SAME(ECMXF_NL_LOSS_TX_FIFO_OVERRUN, nlabi::LossTxFifoOverrun);
SAME(ECMXF_NL_LOSS_OUT_RING_SKIPPED, nlabi::LossOutRingSkipped);
SAME(ECMXF_NL_LOSS_PUMP_FAILURE, nlabi::LossPumpFailure);
SAME(ECMXF_NL_C_PAD, nlabi::CPad);
SAME(ECMXF_NL_C_EXCHANGES, nlabi::CExchanges);
SAME(ECMXF_NL_C_INT1_IRQS, nlabi::CInt1Irqs);
SAME(ECMXF_NL_C_EVENTS, nlabi::CEvents);
SAME(ECMXF_NL_C_EVENTS_SUPPRESSED, nlabi::CEventsSuppressed);
SAME(ECMXF_NL_C_EVENTS_FAILED, nlabi::CEventsFailed);
SAME(ECMXF_NL_FIFO_TX, 0);
SAME(ECMXF_NL_FIFO_RX, 1);
SAME(ECMXF_NL_RESET_CHIP, 1);
SAME(ECMXF_NL_RESET_WARM, 2);
SAME(ECMXF_NL_RESET_LINK, 3);
SAME(ECMXF_NL_DEV_ADDED, 1);
SAME(ECMXF_NL_DEV_REMOVED, 2);
#undef SAME

// one counter attribute per field of struct ecmxf_counters before reserved[]
static_assert(ECMXF_NL_C_INT1_IRQS - ECMXF_NL_C_EXCHANGES + 1 ==
	      offsetof(struct ecmxf_counters, reserved) / sizeof(__u64));

TEST_CASE("netlink ABI: family and group names", "[netlink][abi]")
{
	CHECK(std::strcmp(ECMXF_GENL_NAME, nlabi::kFamily) == 0);
	CHECK(std::strcmp(ECMXF_GENL_MCGRP_EVENTS, nlabi::kGroup) == 0);
	// GENL_NAMSIZ is 16 with the NUL
	CHECK(std::strlen(ECMXF_GENL_NAME) < 16);
	CHECK(std::strlen(ECMXF_GENL_MCGRP_EVENTS) < 16);
}
