// SPDX-License-Identifier: MIT
// The numbers of the generic netlink ABI, written down by hand from
// Documentation/driver.rst ("Events (generic netlink)"), not taken from
// <linux/ecmxf_netlink.h>: test_nl_abi.cpp checks the header against them
// and test_nl_decode.cpp builds its messages with them.
#pragma once

namespace nlabi {

inline constexpr const char *kFamily = "ecmxf";
inline constexpr const char *kGroup = "events";
inline constexpr int kVersion = 1;

enum Cmd { CmdEvent = 1, CmdGetCounters = 2 };

enum Attr {
	Pad = 1,
	DevMinor = 2,
	DevName = 3,
	EventType = 4,
	TimestampNs = 5,
	Seq = 6,
	Suppressed = 7,
	Old = 8,
	New = 9,
	LinkUp = 10,
	ErrStatus = 11,
	EcmStatus = 12,
	Count = 13,
	Increase = 14,
	Errors = 15,
	DurationNs = 16,
	Fifo = 17,
	Mark = 18,
	Above = 19,
	ResetReason = 20,
	CmdCode = 21,
	Status = 22,
	SlaveCount = 23,
	Slaves = 24,
	Slave = 25,
	AlStatus = 26,
	AlSlave = 27,
	SlavesIncomplete = 28,
	Action = 29,
	Counters = 30,
	Loss = 31,
	Total = 32,
};

enum SlaveAttr { SaPosition = 1, SaState = 2, SaAlStatus = 3 };

enum Ev {
	EvDevice = 1,
	EvReset = 2,
	EvLink = 3,
	EvState = 4,
	EvErrorStatus = 5,
	EvEcmStatus = 6,
	EvCrcErrors = 7,
	EvWkcBurst = 8,
	EvWkcBurstEnd = 9,
	EvFifo = 10,
	EvAsyncError = 11,
	EvPdoLoss = 12,
};

enum Loss {
	LossOutRingUnderrun = 0,
	LossInRingOverrun = 1,
	LossRxFifoUnderrun = 2,
	LossRxFifoOverrun = 3,
	LossTxFifoOverrun = 4,
	LossOutRingSkipped = 5,
	LossPumpFailure = 6,
};

enum Counter {
	CPad = 1,
	CExchanges = 2, // .. CInt1Irqs = 23: struct ecmxf_counters in order
	CInt1Irqs = 23,
	CEvents = 24,
	CEventsSuppressed = 25,
	CEventsFailed = 26,
};

} // namespace nlabi
