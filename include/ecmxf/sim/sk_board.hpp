// SPDX-License-Identifier: MIT
/**
 * @file sim_board.hpp
 * @brief A simulated ECM-SK board: the starter kit's firmware (slot
 *        protocol, table 1.3) on the simulator's EtherCAT network and its
 *        slave models.
 *
 * The board answers whole 504- or 512-byte frames (exchange()), drives a
 * Busy line (busy()), and runs EtherCAT cycles on the slaves of a
 * sim::Network in virtual time (advance()). Its behaviour, and the
 * decisions taken where the quick start is silent, are in
 * Documentation/ecm-sk.rst, "The simulator".
 *
 * Thread safety: none; one owner calls it from one thread at a time.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <ecmxf/export.hpp>

namespace ecmxf::sim {
class Network;
}

namespace ecmxf::sk {

/// Board settings: the CONFIG pins, the SET_EX setting saved in the
/// board's flash, and what only the simulator has (FIFO depth, timing).
struct ECMXF_EXPORT BoardConfig {
	unsigned slotSize = 12;		///< CONFIG2: 12 (low, floating) or 16 (high)
	bool testMode = false;		///< CONFIG1 high: test mode
	bool fifoAbandon = true;	///< CONFIG3: abandon a command after 100 cycles
	std::uint32_t extensions = 0;	///< SET_EX saved: bit 0 command CRC, bit 1 response CRC
	/// cyclic FIFO entries: 160 (decision, Documentation/ecm-sk.rst, "The
	/// cyclic FIFO"); the SET_FIFO threshold's default and reset value
	unsigned fifoDepth = 160;
	std::chrono::nanoseconds busyTime{ std::chrono::microseconds(20) }; ///< Busy after a frame
	std::uint32_t spiHz = 24'000'000; ///< SCLK: a frame's wire time
	std::uint32_t lioInputs = 0;	///< the ECM IC's inputs 0..5 at power-on
	/// Paced: virtual time never runs ahead of the wall clock (advance()
	/// and the wire time of exchange() sleep until it is reached) and
	/// catches up with it at every exchange, so cycles run at the real
	/// board's rate, as a person (or a test sending a signal) sees it.
	bool paced = false;

	/// Parse "key=value" settings separated by '&' or ',':
	/// slot=12|16, test=0|1, abandon=0|1, ex=0..3, fifo=160..4096,
	/// busy_us=1..100000, spi_hz=100000..50000000, lio=0..63, paced=0|1. Throws
	/// std::invalid_argument naming the key and the value it refused.
	static BoardConfig parse(const std::string &settings);
	/// Applies one setting (the keys of parse()); throws like parse().
	void set(const std::string &key, const std::string &value);
};

/// Counters of what the board saw (tests, `ecmxf-sim` statistics).
struct BoardStats {
	std::uint64_t frames = 0;	  ///< frames processed
	std::uint64_t whileBusy = 0;	  ///< transfers started while Busy was high (ignored)
	std::uint64_t badLength = 0;	  ///< transfers of another length (ignored)
	std::uint64_t crcRefused = 0;	  ///< frames refused for a bad command CRC
	std::uint64_t refused = 0;	  ///< commands refused (state, slot or slave type, value)
	std::uint64_t fifoApplied = 0;	  ///< cyclic commands applied
	std::uint64_t fifoDropped = 0;	  ///< cyclic commands dropped, FIFO full
	std::uint64_t fifoAbandoned = 0;  ///< cyclic commands abandoned after 100 cycles (in the FIFO full count too)
	std::uint64_t cycles = 0;	  ///< EtherCAT cycles run
};

/// A simulated ECM-SK.
class ECMXF_EXPORT SimBoard
{
public:
	/// A board powered on with @p network on its EtherCAT port. Throws
	/// std::invalid_argument for a bad @p config or a network of more
	/// slaves than the frame has slots for (40, or 30 with 16-byte slots).
	SimBoard(sim::Network network, BoardConfig config = {});
	~SimBoard();
	SimBoard(const SimBoard &) = delete;
	SimBoard &operator=(const SimBoard &) = delete;

	[[nodiscard]] const BoardConfig &config() const noexcept;
	/// 504 or 512.
	[[nodiscard]] std::size_t frameSize() const noexcept;

	/// One SPI transfer: @p mosi in, @p miso out, both frameSize() bytes.
	/// Virtual time moves by the wire time at config().spiHz; Busy then
	/// stays high for config().busyTime while the frame is processed. A
	/// transfer started while Busy is high, or of another length, is not
	/// processed: @p miso is all zeros.
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso);
	/// The Busy line: true (high) while a frame is being processed.
	[[nodiscard]] bool busy() const noexcept;
	/// Virtual time since power-on.
	[[nodiscard]] std::chrono::nanoseconds now() const noexcept;
	/// Lets @p dt of virtual time pass (EtherCAT cycles run).
	void advance(std::chrono::nanoseconds dt);
	/// Power off and on: the board restarts (SET_EX's saved setting takes
	/// effect), the slaves are reset.
	void powerCycle();

	// ---- inspection and test hooks ----
	/// Current State (0x01, 0x02, 0x04, 0x08).
	[[nodiscard]] std::uint8_t state() const noexcept;
	/// The cycle time in force (us).
	[[nodiscard]] std::uint32_t cycleUs() const noexcept;
	/// The SET_EX bits in force (those saved take effect at power-on).
	[[nodiscard]] std::uint32_t extensionsInForce() const noexcept;
	/// The SET_EX bits saved for the next power-on.
	[[nodiscard]] std::uint32_t extensionsSaved() const noexcept;
	/// The ECM IC's outputs 0..5 (LIO_WR) and inputs (LIO_RD).
	[[nodiscard]] std::uint32_t lioOutputs() const noexcept;
	void setLioInputs(std::uint32_t inputs);
	/// Entries in the FIFO, the FIFO full count (dropped full or
	/// abandoned), the threshold in force (the depth by default).
	[[nodiscard]] unsigned fifoUsed() const noexcept;
	[[nodiscard]] unsigned fifoFullCount() const noexcept;
	[[nodiscard]] unsigned fifoThreshold() const noexcept;
	/// The board's CRC-error counter (Error Code).
	[[nodiscard]] std::uint8_t crcErrors() const noexcept;
	/// The type SET_AXIS gave slave @p position (1-based), 0xF if none.
	[[nodiscard]] std::uint8_t slaveType(unsigned position) const;
	/// The mode and sync type DRIVE_MODE gave slave @p position.
	[[nodiscard]] std::uint8_t driveMode(unsigned position) const;
	[[nodiscard]] std::uint8_t driveSync(unsigned position) const;
	/// Why the last state change stopped (empty when none did).
	[[nodiscard]] const std::string &lastError() const noexcept;
	[[nodiscard]] const BoardStats &stats() const noexcept;
	[[nodiscard]] sim::Network &network() noexcept;

	/// The time from the start of a transfer to the end of its wire time.
	[[nodiscard]] std::chrono::nanoseconds wireTime() const noexcept;

private:
	struct Impl;
	std::unique_ptr<Impl> d_;
};

} // namespace ecmxf::sk
