// SPDX-License-Identifier: MIT
/**
 * @file types_pdo.hpp
 * @brief Value types of the process-data, FIFO and cyclic-exchange calls.
 *
 * See Documentation/process-data.rst.
 */
#pragma once

#include <ecmxf/export.hpp>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ecmxf {

/// The chip's FIFO memory: RxCount x RxPDO size + TxCount x TxPDO size
/// must not exceed it (FIFO_SET_TX_CNT / FIFO_SET_RX_CNT).
inline constexpr std::size_t kFifoBudgetBytes = 0x4000;

/// Slaves with process data, from ECAT_PDO_WC_GET parameters 1 and 2.
struct PdoSlaveCounts {
	std::uint32_t inputSlaves = 0;   ///< slaves with input data (TxPDO)
	std::uint32_t outputSlaves = 0;  ///< slaves with output data (RxPDO)
	/// The working counter of a good cycle: inputs x 1 + outputs x 2
	/// (both manuals, under ECAT_PDO_WC_GET).
	[[nodiscard]] constexpr std::uint32_t expectedWkc() const noexcept
	{
		return inputSlaves + 2 * outputSlaves;
	}
};

/// One FIFO entry each way, from FIFO_PACK_SIZE_GET: the RxPDO frame (all
/// slaves' outputs in bus order) and the TxPDO frame (all inputs).
struct FifoPackSizes {
	std::uint16_t rxPdoBytes = 0;  ///< parameter 0: RxPDO (output) frame size
	std::uint16_t txPdoBytes = 0;  ///< parameter 1: TxPDO (input) frame size
};

/// Which FIFO FIFO_CLR_OP empties (its command parameter).
enum class FifoSelect : std::uint8_t {
	Both = 0,    ///< TxFIFO and RxFIFO
	TxFifo = 1,  ///< only the TxFIFO (inputs not yet read)
	RxFifo = 2,  ///< only the RxFIFO (outputs not yet sent)
};

/// ECAT_SET_FIFO_TH: thresholds that raise interrupt flags (and INT1 when
/// enabled with ECAT_INT_SET_ENABLE).
struct FifoThresholds {
	/// Flag bit 24 when the TxFIFO count goes from txHigh - 1 to txHigh.
	bool txHighEnabled = false;
	std::uint8_t txHigh = 0;
	/// Flag bit 25 when the RxFIFO count goes from rxLow + 1 to rxLow.
	bool rxLowEnabled = false;
	std::uint8_t rxLow = 0;
};

/// The answer to one ECAT_PDO_DATA_FIFO_OP.
struct PdoFifoResult {
	/// Return value bit 0: every RxPDO frame sent was taken into the
	/// RxFIFO (false when some were refused because it was full; then the
	/// chip also set error status bit 5).
	bool allWritten = false;
	/// TxPDO frames read, oldest first (frames x TxPDO size bytes).
	std::vector<std::uint8_t> inputs;
	/// Number of TxPDO frames in @ref inputs.
	std::size_t framesRead = 0;
	std::uint8_t txFifoCount = 0;  ///< response header 0x06 (after the read)
	std::uint8_t rxFifoCount = 0;  ///< response header 0x07 (after the write)
	std::uint8_t errStatus = 0;    ///< response header 0x09
};

} // namespace ecmxf
