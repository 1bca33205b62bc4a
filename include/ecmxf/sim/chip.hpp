// SPDX-License-Identifier: MIT
/**
 * @file sim.hpp
 * @brief The ECM-XF simulator: a byte-exact chip behind an SPI-slave
 *        interface, with an EtherCAT network of slave models.
 *
 * The simulator answers SPI exchanges exactly as the chip documented in the
 * manuals does (ver. 050 where the two versions differ), raises its INT0
 * (ready) and INT1 (event) lines, and runs a bus of slave models (EST-584
 * stepper, AKD2G-like servo, digital I/O) at the DC cycle time. Time is
 * virtual (deterministic, advanced by the caller or by exchanges) or paced to
 * the wall clock.
 *
 * Thread safety: a Chip is not thread-safe; one owner drives it.
 */
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>

namespace ecmxf::sim {

class Network; // include <ecmxf/sim/network.hpp> to use it

/// How the simulator's clock runs.
enum class TimeMode {
	Virtual, ///< time moves only through advance() and exchanges (tests)
	Paced,   ///< time follows the monotonic wall clock (demo)
};

/// Static configuration of a simulated chip.
struct ChipConfig {
	TimeMode timeMode = TimeMode::Virtual;
	/// FW_VERSION_GET: the return value (the version number).
	std::uint8_t fwVersion = 0x30;
	/// FW_VERSION_GET: the 20 data bytes (byte 1 extended version, byte 3
	/// series 'XF'/'XFL'/'XFU'/'XM' code, bytes 4..19 build identifier).
	std::vector<std::uint8_t> fwVersionData;
	/// Chip processing time after each exchange (INT0 busy), virtual ns.
	std::chrono::nanoseconds processingTime{ 50'000 };
	/// Virtual time one SPI exchange takes on the wire is computed from the
	/// packet size at this clock (bits per second).
	std::uint32_t spiClockHz = 48'000'000;
	/// An exchange that starts while the chip is still busy (INT0) is
	/// answered "not ready" (check word 0x87654321) and not taken in, as a
	/// real chip would. false: the chip takes it in anyway and counts it in
	/// ChipStats::busyExchanges (hosts that ignore INT0 still work).
	bool notReadyWhileBusy = false;
	/// Lock-step bus: while the PDO FIFO is on (FIFO_ENABLE 1, in a
	/// configured layout), a bus cycle runs only when the RxFIFO holds its
	/// output frame and the TxFIFO has room for its input frame; otherwise
	/// the bus waits (the due cycle runs once an exchange brought the frame
	/// or made room, and the next one a cycle time after it). So no RxFIFO
	/// underrun and no TxFIFO drop can happen, however late the host is:
	/// a host that exchanges one output frame per input frame sees every
	/// frame exactly once. With the FIFO off, time runs the bus as usual
	/// (bring-up, SDOs, states). Not a feature of the real chip: for tests
	/// on slow hosts (Documentation/simulator.rst, "Lock-step bus").
	bool lockstep = false;

	// ---- firmware variants (Documentation/simulator.rst, "Chip options")

	/// Which bytes the chip's CRC check word covers (every CRC type).
	enum class CrcCoverage {
		Frame, ///< header and the whole data section (manual ver. 050)
		Valid, ///< header and the valid data length rounded up to 4 bytes (NEXTW's example host code)
	};
	CrcCoverage crcCoverage = CrcCoverage::Frame;
	/// CRC_TYPE_SET sent with the fixed word while a CRC is in force:
	/// true, taken in (as NEXTW's example host code sends it, and as every
	/// chip takes SPI_RECONFIG_OP); false, dropped and counted as a CRC
	/// error like any packet with a wrong check word (manual ver. 050).
	bool crcTypeSetFixed = false;
	/// ECAT_INIT_OP's data byte 1. false (strict, manual ver. 050): 0x81
	/// only, anything else is a command error; the FIFO is off afterwards
	/// until FIFO_ENABLE. true (lenient): 0x00 is taken in too and leaves
	/// the RxPDO FIFO on after the scan ("enabled by default", manual ver.
	/// 038), as NEXTW's example host drivers send it and then run the FIFO
	/// without FIFO_ENABLE; 0x81 still leaves it off.
	bool initOpLenient = false;
};

/// The chip options of a network file's `chip KEY=VALUE` lines and of
/// `ecmxf-sim --chip KEY=VALUE`, as "key", "value | value" pairs.
inline constexpr std::string_view kChipOptions =
	"crc32-coverage=frame|valid, crc-type-set-fixed=drop|accept, init-op=strict|lenient";

/// Sets the ChipConfig field named by @p key (kChipOptions) to @p value.
/// Throws std::invalid_argument naming the key, or the value and what the
/// key accepts.
ECMXF_EXPORT void applyChipOption(ChipConfig &config, std::string_view key, std::string_view value);

/// Faults a test can inject. Counts are "the next N".
struct FaultPlan {
	unsigned mosiBitErrors = 0;   ///< corrupt the next N command packets
	unsigned misoBitErrors = 0;   ///< corrupt the next N response packets
	unsigned notReady = 0;        ///< answer the next N exchanges with 0x87654321
	bool int0StuckBusy = false;   ///< INT0 never signals ready
	bool linkLost = false;        ///< all slaves gone: WKC errors, state ERROR
	int slaveDropped = -1;        ///< position of a slave that stopped answering
	std::uint32_t forcedSdoAbort = 0; ///< next SDO fails with this abort code
	bool asyncStuckBusy = false;  ///< the next async command never completes
};

/// Counters of the simulated chip that the header fields do not show
/// (for tests and the demo). All count since power-on; WARM_RESET keeps them.
struct ChipStats {
	std::uint64_t exchanges = 0;   ///< SPI exchanges
	std::uint64_t badPackets = 0;  ///< command packets rejected (unsaturated CRC error count)
	std::uint64_t notReady = 0;    ///< exchanges answered "not ready" (0x87654321)
	std::uint64_t busyExchanges = 0; ///< exchanges that started while INT0 said busy
	std::uint64_t busCycles = 0;   ///< EtherCAT bus cycles run
	std::uint64_t wkcErrors = 0;   ///< bus cycles with a wrong working counter (unsaturated)
	std::uint64_t rxUnderruns = 0; ///< cycles with the FIFO on and the RxFIFO empty (outputs kept)
	std::uint64_t rxRefused = 0;   ///< RxPDO frames refused because the RxFIFO was full
	std::uint64_t txDropped = 0;   ///< TxPDO frames dropped because the TxFIFO was full
	std::uint64_t busWaits = 0;    ///< lock-step: times a due bus cycle waited for the FIFOs
	/// Frame accounting of the PDO FIFOs (the soak's ground truth,
	/// tests/soak): RxPDO frames taken in by ECAT_PDO_DATA_FIFO_OP and
	/// popped by bus cycles; TxPDO frames pushed by bus cycles and read
	/// out by ECAT_PDO_DATA_FIFO_OP; frames FIFO_CLR_OP discarded.
	std::uint64_t rxAccepted = 0;
	std::uint64_t rxPopped = 0;
	std::uint64_t txPushed = 0;
	std::uint64_t txRead = 0;
	std::uint64_t rxCleared = 0;
	std::uint64_t txCleared = 0;
};

/// The simulated chip.
class ECMXF_EXPORT Chip
{
public:
	/// A chip with the network described by @p networkFile (see
	/// Documentation/simulator.rst for the format); an empty path selects
	/// the default network (2 x EST-584 + 1 x digital I/O).
	explicit Chip(const std::string &networkFile = {}, ChipConfig config = {});
	/// A chip with the given network (e.g. built in a test).
	explicit Chip(Network network, ChipConfig config = {});
	~Chip();
	Chip(const Chip &) = delete;
	Chip &operator=(const Chip &) = delete;

	/// One full-duplex SPI exchange: @p mosi in, @p miso (same size) out.
	/// A size that is not the configured packet size is answered with the
	/// bytes the chip would shift out (garbage framing) and counted as a
	/// CRC error, as the real chip would.
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso);
	std::vector<std::uint8_t> exchange(std::span<const std::uint8_t> mosi);

	/// INT0 line level (true = high). Ready is high by default (ver. 050);
	/// the polarity follows ECAT_INT_SET_ENABLE bit 1.
	[[nodiscard]] bool int0() const;
	/// INT1 line level (true = high). Active low by default.
	[[nodiscard]] bool int1() const;
	/// Is the chip ready for the next exchange (independent of polarity).
	[[nodiscard]] bool ready() const;

	/// Advance virtual time (no-op in Paced mode).
	void advance(std::chrono::nanoseconds dt);
	/// Current simulated time since power-on.
	[[nodiscard]] std::chrono::nanoseconds now() const;
	/// Lock-step (ChipConfig::lockstep) with the FIFO on: when the next
	/// bus cycle is due if it can run (its frame is in the RxFIFO and the
	/// TxFIFO has room): the clock reaching that time runs it; a time
	/// already past means it runs at the next advance(). nanoseconds::max()
	/// when it waits for the FIFOs, or outside lock-step (time alone runs
	/// the bus). Lets a driver of the clock run the bus as fast as frames
	/// come (tests/kernel/bridge.cpp --lockstep).
	[[nodiscard]] std::chrono::nanoseconds nextLockstepCycle() const;

	/// Faults to inject from now on.
	FaultPlan &faults();

	/// The EtherCAT network behind the chip (slave models, for inspection
	/// and for scripted events in tests).
	Network &network();

	/// The configured data-section size (32..1408) and packet size.
	[[nodiscard]] std::size_t dataSize() const;
	[[nodiscard]] std::size_t packetSize() const;

	/// Counters (see ChipStats).
	[[nodiscard]] const ChipStats &stats() const;
	/// Frames in the RxFIFO and the TxFIFO now (a response header's counts
	/// are those of when the chip built it), for inspection.
	struct FifoLevels {
		std::size_t rx = 0, tx = 0;
	};
	[[nodiscard]] FifoLevels fifoLevels() const;

private:
	class Impl;
	std::unique_ptr<Impl> impl_;
};

} // namespace ecmxf::sim
