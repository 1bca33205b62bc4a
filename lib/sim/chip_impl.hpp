// SPDX-License-Identifier: MIT
//
// chip_impl.hpp - the inside of the simulated ECM-XF (Chip::Impl).
//
// One object holds everything the chip keeps: the SPI front end (packet
// size, check type, the response prepared for the next exchange, error
// bits and counters, INT0/INT1), the EtherCAT master (slave records,
// process image layout, bus cycle, FIFOs, working counter), the running
// async command, the mailbox services (SDO, PDO configuration, EEPROM,
// FoE, raw datagrams, emergencies) and the CiA-402 engine. The code is
// split by concern over chip*.cpp; Documentation/simulator.rst describes
// the behaviour.
//
// Time is virtual nanoseconds since power-on (int64). Nothing on the
// per-exchange or per-cycle path allocates or throws.

#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

#include "ecmxf-proto.h"
#include "le.hpp"
#include "periph.hpp"

namespace ecmxf::sim {

/// Virtual time in nanoseconds.
using Nanos = std::int64_t;

inline constexpr Nanos kUs = 1'000;
inline constexpr Nanos kMs = 1'000'000;
inline constexpr Nanos kSec = 1'000'000'000;

/// A FIFO of fixed-size PDO frames in one preallocated buffer.
class FrameFifo
{
public:
	/// Reallocate for @p depth frames of @p frame bytes (empties it).
	void configure(std::size_t depth, std::size_t frame);
	void clear() { head_ = count_ = 0; }
	[[nodiscard]] std::size_t depth() const { return depth_; }
	[[nodiscard]] std::size_t frame() const { return frame_; }
	[[nodiscard]] std::size_t count() const { return count_; }
	[[nodiscard]] bool empty() const { return count_ == 0; }
	[[nodiscard]] bool full() const { return count_ >= depth_; }
	/// Append a frame; false (and nothing stored) when full.
	bool push(const std::uint8_t *src);
	/// Append a frame, dropping the oldest when full; true when one was dropped.
	bool pushDropOldest(const std::uint8_t *src);
	/// Remove the oldest frame into @p dst; false when empty.
	bool pop(std::uint8_t *dst);

private:
	std::vector<std::uint8_t> buf_;
	std::size_t depth_ = 0, frame_ = 0, head_ = 0, count_ = 0;
};

/// What the master knows about one slave (built by INIT_OP).
struct SlaveRec {
	Slave *slave = nullptr;
	std::uint16_t alias = 0;	///< SII word 4
	std::uint32_t vendor = 0, product = 0, revision = 0, serial = 0;
	std::string name;
	bool coe = false;
	bool foe = false;
	// SII mailbox and sync manager description (for the SM registers)
	std::uint16_t mbxOutOff = 0, mbxOutSize = 0, mbxInOff = 0, mbxInSize = 0;
	/// The bootstrap mailbox (SII words 0x14..0x17), set up for BOOT.
	std::uint16_t bootOutOff = 0, bootOutSize = 0, bootInOff = 0, bootInSize = 0;
	struct SmDesc {
		std::uint16_t start = 0, len = 0;
		std::uint8_t control = 0, enable = 0, type = 0;
	};
	std::vector<SmDesc> sms;	///< from the SII SyncM category, by SM number
	std::array<SmDesc, 16> smOverride{};	///< CONFIG_SM
	std::uint16_t smOverrideMask = 0;
	// process image
	std::size_t outOff = 0, outLen = 0, inOff = 0, inLen = 0;
	// DIRECT_ASSIGN
	bool daEnabled = false;
	std::uint16_t daOut = 0, daIn = 0;
	// DC (INIT_OP, DCSYNC)
	std::uint16_t dcAssign = 0;
	std::uint32_t dcSync0 = 0, dcSync1 = 0;
	std::int32_t dcShift = 0;
	bool sync0Active = false;
	// AL status as last read by the master (state | 0x10 error)
	std::uint8_t cachedAl = 0;
	// mailbox polling (MBX_STAT) and the frame read from the slave
	bool mbxPoll = true, mbxPollPending = true;
	std::array<std::uint8_t, 16> mbxFrame{};
	std::uint8_t mbxLen = 0;
};

/// What the bus cycle needs of one slave, packed for the cache.
struct CycleSlot {
	Slave *slave = nullptr;
	std::uint32_t outOff = 0, outLen = 0, inOff = 0, inLen = 0;
	bool sync0 = false;
};

/// One motor of the internal CiA-402 engine.
struct Motor {
	bool configured = false;
	std::uint8_t slave = 0;
	std::uint8_t cwOff = 0;		///< control word offset in the slave's outputs
	std::uint8_t swOff = 0;		///< status word offset in the slave's inputs
	std::uint8_t ctl = 0;		///< bit3 single reset, bit4 enable, bit7 auto reset
	std::uint8_t target = 0x40;	///< requested 402 state code
	std::uint16_t lastCw = 0;	///< control word bits the engine sent last
	bool wasFault = false;
};

/// A logged CoE emergency (COE_EMERGENCY).
struct EmergencyLog {
	std::uint16_t seq = 0;
	std::uint8_t slave = 0;
	Emergency emcy;
};

/// The async command that keeps ECM status bit 7 set.
struct AsyncJob {
	enum class Step { Running, Done, Failed };
	bool active = false;
	bool stuck = false;		///< fault: never completes
	std::uint8_t code = 0;
	Nanos next = 0;			///< when step() runs next
	std::function<Step()> step;
};

/// What an immediate command answers.
struct CmdResult {
	std::uint8_t ret = 0;		///< return value (header 0x0D)
	std::size_t len = 0;		///< data bytes in the response
	bool cmdError = false;		///< bad parameter: error status bit 7

	/// A command refused for a bad parameter: error status bit 7, no data.
	[[nodiscard]] static CmdResult error()
	{
		CmdResult r;
		r.cmdError = true;
		return r;
	}
};

class Chip::Impl
{
public:
	Impl(Network net, ChipConfig cfg);

	// ---- the public API (chip.cpp) ----
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso);
	bool int0();
	bool int1();
	bool ready();
	void advance(Nanos dt);
	Nanos now();
	FaultPlan &faults() { return faults_; }
	Network &network() { return net_; }
	[[nodiscard]] std::size_t dataSize() const { return dataSize_; }
	[[nodiscard]] std::size_t packetSize() const { return ECMXF_PKT_SIZE(dataSize_); }
	const ChipStats &stats() { return stats_; }
	Chip::FifoLevels fifoLevels() const { return { rxFifo_.count(), txFifo_.count() }; }

	// ---- time (chip.cpp) ----
	void syncPaced();
	void advanceTo(Nanos t);

	// ---- SPI front end (chip.cpp) ----
	void powerOn();
	void process(std::span<const std::uint8_t> mosi);
	void badPacket();
	void applyHeader(const ecmxf_cmd_hdr &h);
	void execute(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data);
	void prepare(std::uint8_t index, std::uint8_t code, std::uint8_t ret, std::size_t len);
	void fillHeader(ecmxf_rsp_hdr &r) const;
	void encodePending(std::uint8_t *pkt, std::size_t len) const;
	/// The codec's check argument for @p check with the configured coverage.
	ecmxf_check codecCheck(ecmxf_check check) const;
	std::uint8_t ecatStateByte() const;
	bool int1Asserted() const;

	// ---- commands (chip_commands.cpp) ----
	using Result = CmdResult;
	Result immediate(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
			 std::span<std::uint8_t> out);
	/// Start an async command; false = bad parameters (command error).
	bool startAsync(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in);
	void startJob(std::uint8_t code, Nanos firstStep, std::function<AsyncJob::Step()> step);
	/// A job that runs @p work once, @p after from now, and is done.
	void startJobOnce(std::uint8_t code, Nanos after, std::function<void()> work);
	void stepJob();
	void endJob(bool ok);

	// ---- the EtherCAT master (chip_master.cpp) ----
	void busCycle();
	/// Lock-step (ChipConfig::lockstep): the FIFO is on and the next bus
	/// cycle has no RxPDO frame or no TxFIFO room, so the bus waits.
	[[nodiscard]] bool busWaits() const;
	/// When the next bus cycle runs in lock-step, or -1 (see Chip).
	Nanos nextLockstepCycle();
	bool reachable(std::size_t pos) const;
	void scanNetwork(std::uint16_t assignActivate, std::uint32_t sync0, std::uint32_t sync1,
			 std::int32_t shift);
	void applyDc();
	void buildLayout();
	void buildSlots();
	void writeSm(std::size_t pos, unsigned sm, const SlaveRec::SmDesc &d);
	void writeSyncManagers(std::size_t pos);
	void refreshStates();
	/// One step of waiting for slaves to reach a state: done when
	/// @p reached, failed after the state timeout counted from @p t0.
	AsyncJob::Step stateWaitStep(bool reached, Nanos t0);
	std::uint8_t commonState() const;
	void requestState(std::size_t pos, std::uint8_t state);
	bool startStateSet(std::uint8_t sel, std::uint8_t state, bool check);
	bool startInitOp(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in);
	void stopExchange();
	std::uint16_t expectedWkc() const;
	std::uint8_t regRead(std::size_t pos, std::uint16_t reg) const;
	void regWrite(std::size_t pos, std::uint16_t reg, std::uint8_t v);
	std::uint16_t siiWord(std::size_t pos, std::uint16_t addr,
			      const std::vector<std::uint16_t> &sii) const;

	// ---- FIFOs (chip_fifo.cpp) ----
	void rebuildFifos();
	bool fifoBudgetOk(std::size_t rx, std::size_t tx) const;
	/// FIFO_SET_RX_CNT/FIFO_SET_TX_CNT: both depths (frames) within the
	/// budget, the FIFOs rebuilt; refused over it.
	Result setFifoDepths(std::size_t rx, std::size_t tx);
	void rxPopped(std::size_t before);
	void txPushed(std::size_t before);
	// PDO_DATA_FIFO_OP and PDO_DATA_OP, once the layout is valid (the
	// caller, immediate(), refuses them before)
	Result fifoDataOp(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
			  std::span<std::uint8_t> out);
	Result pdoDataOp(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
			 std::span<std::uint8_t> out);

	// ---- mailbox services (chip_mailbox.cpp) ----
	bool startSdo(std::span<const std::uint8_t> in);
	bool startPdoConfigSet(std::span<const std::uint8_t> in);
	bool startPdoConfigReq(std::span<const std::uint8_t> in);
	bool startEeprom(std::span<const std::uint8_t> in);
	bool startRaw(std::span<const std::uint8_t> in);
	bool startFoe(std::span<const std::uint8_t> in, std::size_t cmdLen);
	bool startRecvMailbox(const ecmxf_cmd_hdr &h);
	std::uint32_t sdoCheck(std::size_t pos) const;
	/// sdoCheck(), else the forced abort @p forced (0: none).
	std::uint32_t sdoCheck(std::size_t pos, std::uint32_t forced) const;
	/// What every SDO job starts with: the last abort code cleared, the
	/// fault plan's one-shot forced abort taken (0: none).
	std::uint32_t startSdoAborts();
	/// The last step of a mailbox job: @p abortCode kept for the
	/// queries, the job failed unless it is 0.
	AsyncJob::Step endMailboxJob(std::uint32_t abortCode);
	void pollEmergencies();
	void logEmergency(std::size_t pos, const Emergency &e);
	void pollEmergency(std::size_t pos);
	Result coeEmergency(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out);
	Result mbxStat(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
		       std::span<std::uint8_t> out);
	Result recvMailboxRead(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out);
	Nanos sdoTime(std::size_t pos, std::size_t bytes) const;

	// ---- CiA-402 engine (chip_402.cpp) ----
	void apply402();
	Result cmd402(const ecmxf_cmd_hdr &h, std::span<std::uint8_t> out);
	static std::uint8_t state402(std::uint16_t statusword);
	std::uint16_t statusword(const Motor &m) const;

	// ================= state =================
	Network net_;
	ChipConfig cfg_;
	FaultPlan faults_;
	ChipStats stats_;
	Peripherals periph_;
	std::chrono::steady_clock::time_point epoch_;

	// time
	Nanos now_ = 0;
	Nanos busyUntil_ = 0;		///< INT0 busy (processing) until

	// SPI front end
	std::size_t dataSize_ = ECMXF_DATA_DEFAULT;
	ecmxf_check check_ = ECMXF_CHECK_FIXED;
	bool havePrev_ = false;
	std::uint8_t prevIndex_ = 0, prevCode_ = 0;
	struct Pending {
		ecmxf_rsp_hdr hdr{};
		std::array<std::uint8_t, ECMXF_DATA_MAX> data{};
		std::size_t len = 0;
		ecmxf_check check = ECMXF_CHECK_FIXED;
	} pending_;
	std::array<std::uint8_t, ECMXF_PKT_MAX> txBuf_{};	///< MISO frame being built
	std::array<std::uint8_t, ECMXF_PKT_MAX> rxBuf_{};	///< MOSI copy (fault injection)
	int pendingCheck_ = -1;		///< CRC_TYPE_SET: the type after this answer
	std::uint8_t crcErrCnt_ = 0;
	std::uint8_t errStatus_ = 0;	///< bits 3..7 (fault bits)
	std::uint32_t intFlags_ = 0;
	std::uint32_t intEnable_ = 0;
	std::uint8_t gpioIntEnable_ = 0, periphIntEnable_ = 0;
	std::uint8_t polarity_ = 0x02;	///< bit1 INT0 active high, bit0 INT1 active high

	// master
	bool initialized_ = false;	///< INIT_OP succeeded (network known)
	bool ethInit_ = false;
	bool linkAtInit_ = false;
	bool lrw_ = true;
	bool busShift_ = false;
	std::uint8_t initParam_ = 0;
	bool initFifoOn_ = false; // INIT_OP byte 1 = 0 on a lenient firmware: the FIFO stays on
	std::vector<SlaveRec> slaves_;
	std::vector<CycleSlot> slots_;	///< hot copy of slaves_ (buildLayout, applyDc)
	/// Configured station address of every bus position (ESC 0x0010),
	/// as the master wrote it (INIT_OP or raw datagrams).
	std::vector<std::uint16_t> stations_;
	std::uint8_t ecatState_ = ECMXF_ECAT_NONE;
	bool opReached_ = false;
	bool cyclesOn_ = false;
	Nanos cycleNs_ = kMs;
	Nanos nextCycle_ = 0;
	bool waiting_ = false; ///< lock-step: the due bus cycle waits (counted once)
	std::uint64_t cycleCount_ = 0;
	unsigned emcyEvery_ = 8;
	bool dcActive_ = false;
	Nanos dcStableAt_ = 0;
	bool layoutValid_ = false;
	bool wkcStopped_ = false;
	std::size_t rxSize_ = 0, txSize_ = 0;	///< RxPDO (outputs) / TxPDO (inputs) bytes
	std::vector<std::uint8_t> outImage_, inImage_;
	unsigned inSlaves_ = 0, outSlaves_ = 0;
	std::uint16_t lastWkc_ = 0;
	std::uint8_t wkcErrCnt_ = 0;
	std::uint8_t wkcConti_ = 0;
	std::uint8_t wkcMax_ = 255;

	// FIFOs
	bool fifoEnabled_ = false;
	std::size_t rxDepth_ = 64, txDepth_ = 64;
	FrameFifo rxFifo_, txFifo_;
	std::uint8_t fifoThEnable_ = 0, txHigh_ = 0, rxLow_ = 0;

	// async command
	AsyncJob job_;
	bool skipLinkWait_ = false;

	// mailbox results
	std::vector<std::uint8_t> sdoData_;
	std::uint32_t abortCode_ = 0;
	std::array<std::uint8_t, 112> pdoCfg_{};
	std::uint8_t eepromRet_ = 0;
	std::vector<std::uint8_t> eepromData_;
	std::vector<std::uint8_t> rawResult_;
	std::vector<std::uint8_t> flash_;	///< FoE staging flash (256 KiB, made at the first FOE_FUNC_REQ)
	std::vector<std::uint8_t> foeResult_;
	std::vector<std::uint8_t> mbxRead_;
	std::vector<EmergencyLog> emcyLog_;	///< ring, newest at emcyHead_-1
	std::size_t emcyHead_ = 0, emcyCount_ = 0;
	std::uint16_t emcySeq_ = 0;
	/// EEPROM words written through EEPROM_REQ, per bus position: the
	/// Slave interface has no SII write, so the chip keeps what it wrote
	/// (it survives WARM_RESET, like the slave's EEPROM would).
	std::map<std::size_t, std::map<std::uint16_t, std::uint16_t>> eepromOverlay_;

	// CiA-402
	std::array<Motor, 128> motors_{};
	std::uint8_t motorTotal_ = 0;
};

} // namespace ecmxf::sim
