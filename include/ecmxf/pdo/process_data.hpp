// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/pdo/process_data.hpp
 * @brief The process data commands: working counters, the PDO FIFO, the
 *        process image, FIFO setup.
 *
 * Process data: dev.pdo().read()/write()/writeRead() for the image,
 * fifoExchange() for the PDO FIFO, slaveCounts(), workingCounter(), and the
 * fifo*() setup calls (the FIFO keeps its name: a ProcessData holds more
 * than the FIFO). The names before 0.4 (read(), fifoExchange()...)
 * are deprecated aliases, kept for one release.
 *
 * Documentation/process-data.rst. Every call throws ecmxf::Error; an
 * argument out of range is refused with EINVAL before anything is sent; a
 * command the chip refuses (error status bit 7) throws EREMOTEIO naming the
 * command. The raw, allocation-free path is Device::transact().
 *
 * A ProcessData is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::pdo() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_pdo.hpp>

namespace ecmxf {

class Device;

/// The process data commands: working counters, the PDO FIFO, the
/// process image, FIFO setup.
class ECMXF_EXPORT ProcessData
{
public:
	/// The view of @p device's process data.
	explicit ProcessData(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	/// ECAT_PDO_WC_GET parameters 1 and 2: slaves with inputs / outputs.
	[[nodiscard]] PdoSlaveCounts slaveCounts() const;
	/// ECAT_PDO_WC_GET parameter 3: the working counter of the last cycle.
	[[nodiscard]] std::uint32_t workingCounter() const;

	/// ECAT_PDO_DATA_FIFO_OP: pushes @p frames RxPDO frames (@p rxFrames
	/// holds them back to back, frames x RxPDO size bytes; none: no write)
	/// into the RxFIFO, and with @p read pops as many TxPDO frames as fit
	/// in the data section. @p frames 0..255; the bytes must divide evenly
	/// into @p frames and fit the data section.
	PdoFifoResult fifoExchange(std::span<const std::uint8_t> rxFrames, unsigned frames, bool read) const;

	/// ECAT_PDO_DATA_OP, read only: the current input image (TxPDO size).
	[[nodiscard]] std::vector<std::uint8_t> read() const;
	/// ECAT_PDO_DATA_OP, write only: the outputs that go out while the FIFO
	/// is off or empty (pre-load them before FIFO_ENABLE). At most the
	/// RxPDO size is taken; empty @p outputs is refused (EINVAL).
	void write(std::span<const std::uint8_t> outputs) const;
	/// ECAT_PDO_DATA_OP, both: writes @p outputs, returns the inputs.
	[[nodiscard]] std::vector<std::uint8_t> writeRead(std::span<const std::uint8_t> outputs) const;

	/// FIFO_ENABLE: the bus cycle consumes the RxFIFO and fills the TxFIFO
	/// only while enabled (ECAT_INIT_OP disables it).
	void fifoEnable(bool enable) const;
	/// FIFO_PACK_SIZE_GET parameters 0 and 1: the frame sizes.
	[[nodiscard]] FifoPackSizes fifoPackSizes() const;
	/// FIFO_CLR_OP: empties one or both FIFOs.
	void fifoClear(FifoSelect which = FifoSelect::Both) const;
	/// FIFO_GET_TX_CNT / FIFO_GET_RX_CNT: the FIFO depths (frames).
	[[nodiscard]] unsigned fifoTxCount() const;
	[[nodiscard]] unsigned fifoRxCount() const;
	/// FIFO_SET_TX_CNT / FIFO_SET_RX_CNT: one depth, 1..255, such that
	/// RxCount x RxPDO size + TxCount x TxPDO size <= 0x4000 with the other
	/// FIFO's present depth (checked before sending: EINVAL naming both).
	/// Both FIFOs are rebuilt empty.
	void fifoSetTxCount(unsigned count) const;
	void fifoSetRxCount(unsigned count) const;
	/// Both depths at once, in the order the budget allows.
	void fifoSetCounts(unsigned rxCount, unsigned txCount) const;
	/// FIFO_INIT: rebuilds both FIFOs, empty, with the present depths.
	void fifoInit() const;
	/// ECAT_SET_FIFO_TH: the TxFIFO high and RxFIFO low marks.
	void fifoSetThresholds(const FifoThresholds &thresholds) const;

	// ---- the names before 0.4, kept for one release: each forwards to
	// the call above (Documentation/library.rst, "API changes before 0.1.0: one model for two masters")
	[[deprecated("use ProcessData::slaveCounts")]] [[nodiscard]] PdoSlaveCounts pdoSlaveCounts() const
	{
		return slaveCounts();
	}
	[[deprecated("use ProcessData::workingCounter")]] [[nodiscard]] std::uint32_t pdoWorkingCounter() const
	{
		return workingCounter();
	}
	[[deprecated("use ProcessData::fifoExchange")]] PdoFifoResult
	pdoFifoExchange(std::span<const std::uint8_t> rxFrames, unsigned frames, bool read) const
	{
		return fifoExchange(rxFrames, frames, read);
	}
	[[deprecated("use ProcessData::read")]] [[nodiscard]] std::vector<std::uint8_t> pdoRead() const
	{
		return read();
	}
	[[deprecated("use ProcessData::write")]] void pdoWrite(std::span<const std::uint8_t> outputs) const
	{
		write(outputs);
	}
	[[deprecated("use ProcessData::writeRead")]] [[nodiscard]] std::vector<std::uint8_t>
	pdoWriteRead(std::span<const std::uint8_t> outputs) const
	{
		return writeRead(outputs);
	}

private:
	void setDepth(bool tx, unsigned count) const;

	Device *dev_;
};

} // namespace ecmxf
