// SPDX-License-Identifier: MIT
// ProcessData (include/ecmxf/pdo/process_data.hpp), the typed process-data
// and FIFO calls: ECAT_PDO_WC_GET, ECAT_PDO_DATA_FIFO_OP,
// ECAT_PDO_DATA_OP, FIFO_ENABLE, FIFO_PACK_SIZE_GET, FIFO_CLR_OP,
// FIFO_SET/GET_TX/RX_CNT, FIFO_INIT, ECAT_SET_FIFO_TH
// (Documentation/process-data.rst). Every command runs through the one
// command runner (lib/device/runner.hpp); a refusal is EREMOTEIO here.

#include <ecmxf/pdo/process_data.hpp>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>

#include "device/runner.hpp"
#include "ecmxf-proto.h"

namespace ecmxf {

namespace {

/// Runs @p c through the one command runner; a refusal (error status bit
/// 7) throws EREMOTEIO naming the command and @p hint.
Response run(Device &d, const Command &c, std::string_view hint = {})
{
	return detail::immediate(d, c, {}, std::string(hint), EREMOTEIO);
}

std::uint32_t le32(const Response &r, std::string_view name)
{
	if (r.data.size() < 4)
		throw Error(std::string(name) + ": the answer has " + std::to_string(r.data.size()) +
				    " data bytes, 4 expected",
			    EPROTO);
	return static_cast<std::uint32_t>(r.data[0]) | static_cast<std::uint32_t>(r.data[1]) << 8 |
	       static_cast<std::uint32_t>(r.data[2]) << 16 | static_cast<std::uint32_t>(r.data[3]) << 24;
}

std::uint16_t le16(const Response &r, std::string_view name)
{
	if (r.data.size() < 2)
		throw Error(std::string(name) + ": the answer has " + std::to_string(r.data.size()) +
				    " data bytes, 2 expected",
			    EPROTO);
	return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
}

constexpr std::string_view kNoLayout = "no process image yet (ECAT_INIT_OP first)?";

std::uint32_t wcGet(Device &d, std::uint8_t param)
{
	constexpr std::string_view name = "ECAT_PDO_WC_GET";
	return le32(run(d, detail::cmd(ECMXF_CMD_ECAT_PDO_WC_GET, param)), name);
}

/// "FIFO_SET_RX_CNT: 100 x 100-byte RxPDO frames + 64 x 100-byte TxPDO
/// frames = 16400 bytes exceed the FIFO memory of 16384 bytes (0x4000)".
[[noreturn]] void overBudget(std::string_view name, unsigned rx, unsigned rxSize, unsigned tx, unsigned txSize)
{
	std::string msg(name);
	msg.append(": ")
		.append(std::to_string(rx))
		.append(" x ")
		.append(std::to_string(rxSize))
		.append("-byte RxPDO frames + ")
		.append(std::to_string(tx))
		.append(" x ")
		.append(std::to_string(txSize))
		.append("-byte TxPDO frames = ")
		.append(std::to_string(rx * rxSize + tx * txSize))
		.append(" bytes exceed the FIFO memory of 16384 bytes (0x4000)");
	throw Error(msg, EINVAL);
}

void checkDepth(std::string_view name, const char *what, unsigned count)
{
	if (count < 1 || count > 255)
		throw Error(std::string(name) + ": " + what + " count " + std::to_string(count) +
				    " out of range (1..255 frames)",
			    EINVAL);
}

bool fits(unsigned rx, unsigned rxSize, unsigned tx, unsigned txSize)
{
	return std::size_t{ rx } * rxSize + std::size_t{ tx } * txSize <= kFifoBudgetBytes;
}

} // namespace

ProcessData Device::pdo() noexcept
{
	return ProcessData(*this);
}

PdoSlaveCounts ProcessData::slaveCounts() const
{
	PdoSlaveCounts c;
	c.inputSlaves = wcGet(*dev_, 1);
	c.outputSlaves = wcGet(*dev_, 2);
	return c;
}

std::uint32_t ProcessData::workingCounter() const
{
	return wcGet(*dev_, 3);
}

PdoFifoResult ProcessData::fifoExchange(std::span<const std::uint8_t> rxFrames, unsigned frames, bool read) const
{
	constexpr std::string_view name = "ECAT_PDO_DATA_FIFO_OP";
	if (frames > 255)
		throw Error(std::string(name) + ": " + std::to_string(frames) +
				    " RxPDO frames out of range (0..255 per command)",
			    EINVAL);
	if (frames == 0 ? !rxFrames.empty() : rxFrames.size() % frames != 0)
		throw Error(std::string(name) + ": " + std::to_string(rxFrames.size()) +
				    " bytes do not divide into " + std::to_string(frames) + " RxPDO frames",
			    EINVAL);
	if (rxFrames.size() > dev_->pdoDataCapacity())
		throw Error(std::string(name) + ": " + std::to_string(frames) + " RxPDO frames of " +
				    std::to_string(frames ? rxFrames.size() / frames : 0) + " bytes (" +
				    std::to_string(rxFrames.size()) + " bytes) do not fit the data section (" +
				    std::to_string(dev_->pdoDataCapacity()) + " bytes)",
			    EMSGSIZE);
	// the chip takes frames x its RxPDO size from the data section
	// whatever the bytes were meant to be: check them against it first
	const FifoPackSizes s = fifoPackSizes();
	if (frames && rxFrames.size() / frames != s.rxPdoBytes)
		throw Error(std::string(name) + ": RxPDO frames of " + std::to_string(rxFrames.size() / frames) +
				    " bytes given; the chip's RxPDO frame is " + std::to_string(s.rxPdoBytes) +
				    " bytes (FIFO_PACK_SIZE_GET 0)",
			    EINVAL);
	Command c = detail::cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, static_cast<std::uint8_t>(frames));
	c.data[0] = static_cast<std::uint8_t>((frames ? 0x01 : 0x00) | (read ? 0x02 : 0x00));
	c.control = ECMXF_CTL_CLR_FIFO_ERR; // error status bit 5 of this write only
	c.payload.assign(rxFrames.begin(), rxFrames.end());
	const Response r = run(*dev_, c, kNoLayout);
	PdoFifoResult res;
	res.allWritten = (r.ret & 0x01) != 0;
	res.inputs = r.data;
	res.txFifoCount = r.header.txFifoCnt;
	res.rxFifoCount = r.header.rxFifoCnt;
	res.errStatus = r.header.errStatus;
	if (!res.inputs.empty()) {
		if (s.txPdoBytes == 0 || res.inputs.size() % s.txPdoBytes != 0)
			throw Error(std::string(name) + ": " + std::to_string(res.inputs.size()) +
					    " bytes of TxPDO data are not whole frames of " +
					    std::to_string(s.txPdoBytes) + " bytes",
				    EPROTO);
		res.framesRead = res.inputs.size() / s.txPdoBytes;
	}
	return res;
}

std::vector<std::uint8_t> ProcessData::read() const
{
	Command c = detail::cmd(ECMXF_CMD_ECAT_PDO_DATA_OP);
	c.data[0] = 0x06; // bits 0/1 valid, read
	return run(*dev_, c, kNoLayout).data;
}

void ProcessData::write(std::span<const std::uint8_t> outputs) const
{
	if (outputs.empty())
		throw Error("ECAT_PDO_DATA_OP: no output bytes to write", EINVAL);
	Command c = detail::cmd(ECMXF_CMD_ECAT_PDO_DATA_OP);
	c.data[0] = 0x05; // bits 0/1 valid, write
	c.payload.assign(outputs.begin(), outputs.end());
	(void)run(*dev_, c, kNoLayout);
}

std::vector<std::uint8_t> ProcessData::writeRead(std::span<const std::uint8_t> outputs) const
{
	if (outputs.empty())
		throw Error("ECAT_PDO_DATA_OP: no output bytes to write", EINVAL);
	Command c = detail::cmd(ECMXF_CMD_ECAT_PDO_DATA_OP);
	c.data[0] = 0x07; // bits 0/1 valid, write and read
	c.payload.assign(outputs.begin(), outputs.end());
	return run(*dev_, c, kNoLayout).data;
}

void ProcessData::fifoEnable(bool enable) const
{
	(void)run(*dev_, detail::cmd(ECMXF_CMD_FIFO_ENABLE, enable ? 1 : 0));
}

FifoPackSizes ProcessData::fifoPackSizes() const
{
	constexpr std::string_view name = "FIFO_PACK_SIZE_GET";
	FifoPackSizes s;
	s.rxPdoBytes = le16(run(*dev_, detail::cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)), name);
	s.txPdoBytes = le16(run(*dev_, detail::cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1)), name);
	return s;
}

void ProcessData::fifoClear(FifoSelect which) const
{
	const auto p = static_cast<unsigned>(which);
	if (p > 2)
		throw Error("FIFO_CLR_OP: FIFO selector " + std::to_string(p) +
				    " out of range (0 both, 1 TxFIFO, 2 RxFIFO)",
			    EINVAL);
	(void)run(*dev_, detail::cmd(ECMXF_CMD_FIFO_CLR_OP, static_cast<std::uint8_t>(p)));
}

unsigned ProcessData::fifoTxCount() const
{
	return run(*dev_, detail::cmd(ECMXF_CMD_FIFO_GET_TX_CNT)).ret;
}

unsigned ProcessData::fifoRxCount() const
{
	return run(*dev_, detail::cmd(ECMXF_CMD_FIFO_GET_RX_CNT)).ret;
}

void ProcessData::fifoSetTxCount(unsigned count) const
{
	setDepth(true, count);
}

void ProcessData::fifoSetRxCount(unsigned count) const
{
	setDepth(false, count);
}

void ProcessData::setDepth(bool tx, unsigned count) const
{
	const std::string_view name = tx ? "FIFO_SET_TX_CNT" : "FIFO_SET_RX_CNT";
	checkDepth(name, tx ? "TxFIFO" : "RxFIFO", count);
	const FifoPackSizes s = fifoPackSizes();
	// the chip checks the new depth against the other FIFO's present one
	const unsigned rx = tx ? fifoRxCount() : count;
	const unsigned txc = tx ? count : fifoTxCount();
	if (!fits(rx, s.rxPdoBytes, txc, s.txPdoBytes))
		overBudget(name, rx, s.rxPdoBytes, txc, s.txPdoBytes);
	(void)run(*dev_, detail::cmd(tx ? ECMXF_CMD_FIFO_SET_TX_CNT : ECMXF_CMD_FIFO_SET_RX_CNT,
				     static_cast<std::uint8_t>(count)));
}

void ProcessData::fifoSetCounts(unsigned rxCount, unsigned txCount) const
{
	checkDepth("FIFO_SET_RX_CNT", "RxFIFO", rxCount);
	checkDepth("FIFO_SET_TX_CNT", "TxFIFO", txCount);
	const FifoPackSizes s = fifoPackSizes();
	if (!fits(rxCount, s.rxPdoBytes, txCount, s.txPdoBytes))
		overBudget("FIFO_SET_RX_CNT/FIFO_SET_TX_CNT", rxCount, s.rxPdoBytes, txCount, s.txPdoBytes);
	// the chip checks each command against the other FIFO's present
	// depth: change first the one that fits with it (one of the two orders
	// always does when the new pair fits)
	const unsigned txNow = fifoTxCount();
	const auto setRx = detail::cmd(ECMXF_CMD_FIFO_SET_RX_CNT, static_cast<std::uint8_t>(rxCount));
	const auto setTx = detail::cmd(ECMXF_CMD_FIFO_SET_TX_CNT, static_cast<std::uint8_t>(txCount));
	if (fits(rxCount, s.rxPdoBytes, txNow, s.txPdoBytes)) {
		(void)run(*dev_, setRx);
		(void)run(*dev_, setTx);
	} else {
		(void)run(*dev_, setTx);
		(void)run(*dev_, setRx);
	}
}

void ProcessData::fifoInit() const
{
	(void)run(*dev_, detail::cmd(ECMXF_CMD_FIFO_INIT));
}

void ProcessData::fifoSetThresholds(const FifoThresholds &t) const
{
	Command c = detail::cmd(ECMXF_CMD_ECAT_SET_FIFO_TH,
			 static_cast<std::uint8_t>((t.txHighEnabled ? 0x01 : 0) | (t.rxLowEnabled ? 0x02 : 0)));
	c.data[0] = t.txHigh;
	c.data[1] = t.rxLow;
	(void)run(*dev_, c);
}

} // namespace ecmxf
