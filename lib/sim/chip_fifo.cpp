// SPDX-License-Identifier: MIT
//
// chip_fifo.cpp - the process data FIFOs of the simulated ECM-XF and the
// two process data commands: ECAT_PDO_DATA_FIFO_OP (frames into the
// RxFIFO, frames out of the TxFIFO) and ECAT_PDO_DATA_OP (direct access
// to the process image), plus the FIFO threshold interrupts.

#include "chip_impl.hpp"

#include <algorithm>
#include <cstring>

namespace ecmxf::sim {

namespace {
constexpr std::size_t kFifoBudget = 0x4000;
} // namespace

void Chip::Impl::rebuildFifos()
{
	// RxCount * RxPdoSize + TxCount * TxPdoSize <= 0x4000: when a new
	// layout does not fit the depths, the deeper FIFO gives way first
	while (rxDepth_ * rxSize_ + txDepth_ * txSize_ > kFifoBudget) {
		if (rxDepth_ * rxSize_ >= txDepth_ * txSize_ && rxDepth_ > 1)
			rxDepth_--;
		else if (txDepth_ > 1)
			txDepth_--;
		else
			break; // one frame each does not fit: keep one anyway
	}
	rxFifo_.configure(rxDepth_, rxSize_);
	txFifo_.configure(txDepth_, txSize_);
}

void Chip::Impl::rxPopped(std::size_t before)
{
	// "RxFIFO low mark 10: the interrupt fires when the count goes 11 -> 10"
	if ((fifoThEnable_ & 0x02) && before > rxLow_ && rxFifo_.count() <= rxLow_)
		intFlags_ |= ECMXF_INT_RXFIFO_LOW;
}

void Chip::Impl::txPushed(std::size_t before)
{
	// "TxFIFO high mark 10: the interrupt fires when the count goes 9 -> 10"
	if ((fifoThEnable_ & 0x01) && before < txHigh_ && txFifo_.count() >= txHigh_)
		intFlags_ |= ECMXF_INT_TXFIFO_HIGH;
}

Chip::Impl::Result Chip::Impl::fifoDataOp(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
					  std::span<std::uint8_t> out)
{
	Result r;
	const unsigned op = h.data[0];
	if (op & 0x01) {
		const std::size_t frames = h.param;
		if (frames * rxSize_ > in.size() || (frames && rxSize_ == 0))
			return Result::error();
		bool all = true;
		for (std::size_t f = 0; f < frames; f++) {
			if (!rxFifo_.push(in.data() + f * rxSize_)) {
				// RxFIFO full: the newest frames are refused
				stats_.rxRefused += frames - f;
				errStatus_ |= ECMXF_ERR_FIFO;
				all = false;
				break;
			}
			stats_.rxAccepted++;
		}
		if (all)
			r.ret |= 0x01;
	}
	if (op & 0x02) {
		std::size_t k = 0;
		if (txSize_ > 0) {
			while ((k + 1) * txSize_ <= out.size() && txFifo_.pop(out.data() + k * txSize_))
				k++;
			stats_.txRead += k;
		}
		r.len = k * txSize_;
		if (k)
			r.ret |= 0x02; // TxPDO data in the data section
	}
	return r;
}

Chip::Impl::Result Chip::Impl::pdoDataOp(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
					 std::span<std::uint8_t> out)
{
	Result r;
	const unsigned op = h.data[0];
	// bit 2: bits 0/1 are valid; without it both read and write happen
	const bool valid = op & 0x04;
	const bool wr = valid ? (op & 0x01) : true;
	const bool rd = valid ? (op & 0x02) : true;
	if (wr) {
		const std::size_t n = std::min({ static_cast<std::size_t>(h.len), rxSize_, in.size() });
		if (n) {
			std::memcpy(outImage_.data(), in.data(), n);
			r.ret |= 0x01;
		}
	}
	if (rd) {
		const std::size_t n = std::min(txSize_, out.size());
		if (n)
			std::memcpy(out.data(), inImage_.data(), n);
		r.len = n;
		r.ret |= 0x02;
	}
	r.ret = static_cast<std::uint8_t>(r.ret | (op & 0x04));
	return r;
}

} // namespace ecmxf::sim
