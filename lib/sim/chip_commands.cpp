// SPDX-License-Identifier: MIT
//
// chip_commands.cpp - the command dispatch of the simulated ECM-XF: every
// immediate command, and the start of every async one (the work of the
// async commands is in chip_master.cpp and chip_mailbox.cpp).
//
// An immediate handler writes its answer into the response data section
// and returns the return value and data length; cmdError = true sets
// error status bit 7 ("bad parameter") and the answer carries no data.

#include "chip_impl.hpp"

#include <algorithm>
#include <cstring>

namespace ecmxf::sim {

namespace {

using Result = CmdResult;

Result error()
{
	return CmdResult::error();
}

Result ret(unsigned v)
{
	Result r;
	r.ret = static_cast<std::uint8_t>(v);
	return r;
}

Result bytes(std::size_t len, unsigned v = 0)
{
	Result r;
	r.ret = static_cast<std::uint8_t>(v);
	r.len = len;
	return r;
}

/// A 0/1 switch command: @p param sets @p flag (others are refused).
Result setSwitch(bool &flag, unsigned param)
{
	if (param > 1)
		return error();
	flag = param == 1;
	return ret(0);
}

/// Copy @p src into @p out (clipped to the data section).
Result copyOut(const std::vector<std::uint8_t> &src, std::span<std::uint8_t> out, unsigned v = 0)
{
	const std::size_t n = std::min(src.size(), out.size());
	if (n)
		std::memcpy(out.data(), src.data(), n);
	return bytes(n, v);
}

constexpr std::size_t kFifoBudget = 0x4000;

} // namespace

Chip::Impl::Result Chip::Impl::immediate(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in,
					 std::span<std::uint8_t> out)
{
	const std::size_t nSlaves = slaves_.size();
	switch (h.code) {
	case ECMXF_CMD_ECAT_PDO_WC_GET: {
		std::uint32_t v = 0;
		if (h.param == 1)
			v = inSlaves_;
		else if (h.param == 2)
			v = outSlaves_;
		else if (h.param == 3)
			v = lastWkc_;
		else
			return error();
		put32(out.data(), v);
		return bytes(4);
	}
	case ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP:
	case ECMXF_CMD_ECAT_PDO_DATA_OP:
		if (!layoutValid_) // no process data before the layout is built
			return error();
		return h.code == ECMXF_CMD_ECAT_PDO_DATA_OP ? pdoDataOp(h, in, out)
							    : fifoDataOp(h, in, out);
	case ECMXF_CMD_ECAT_PDO_CONFIG_GET: {
		const std::size_t n = std::min(pdoCfg_.size(), out.size());
		std::memcpy(out.data(), pdoCfg_.data(), n);
		return bytes(n);
	}
	case ECMXF_CMD_ECAT_SDO_GET:
		return copyOut(sdoData_, out);
	case ECMXF_CMD_ECAT_STATE_GET:
		if (h.param == 0xFF)
			return ret(ecatStateByte());
		if (!initialized_ || h.param >= nSlaves)
			return error();
		return ret(reachable(h.param) ? slaves_[h.param].cachedAl : ECMXF_ECAT_ERROR);
	case ECMXF_CMD_ECAT_SLV_INFO_GET: {
		if (!initialized_ || h.param >= nSlaves)
			return error();
		const std::size_t pos = h.param;
		const SlaveRec &s = slaves_[pos];
		switch (h.data[0]) {
		case 0:
			put32(out.data(), s.vendor);
			return bytes(4);
		case 1:
			put32(out.data(), s.product);
			return bytes(4);
		case 2:
			put32(out.data(), s.revision);
			return bytes(4);
		case 3: {
			const std::size_t n = std::min({ s.name.size(), out.size(), std::size_t{ 64 } });
			std::memcpy(out.data(), s.name.data(), n);
			return bytes(n);
		}
		case 4:
			put16(out.data(), stations_[pos]);
			return bytes(2);
		case 5:
			put16(out.data(), s.alias);
			return bytes(2);
		case 6:
			if (!reachable(pos))
				return error();
			out[0] = static_cast<std::uint8_t>(s.slave->alStatus() & 0x0F);
			return bytes(1);
		case 7:
			if (!reachable(pos))
				return error();
			put16(out.data(), s.slave->alStatusCode());
			return bytes(2);
		case 8:
			put16(out.data(), static_cast<std::uint16_t>(s.outLen));
			return bytes(2);
		case 9:
			put16(out.data(), static_cast<std::uint16_t>(s.inLen));
			return bytes(2);
		// DC, as the model's ESC registers and the master's configuration
		// have it (Documentation/commands-bus.rst, "Slave information")
		case 10: // has DC: ESC feature register 0x0008 bit 2
			out[0] = (s.slave->escRead8(0x0008) & 0x04) ? 1 : 0;
			return bytes(1);
		case 11: { // DC cycle: SYNC0 cycle time (0x09A0), ns, for a DC slave
			std::uint32_t cycle = 0;
			for (unsigned b = 0; b < 4; b++)
				cycle |= static_cast<std::uint32_t>(s.slave->escRead8(
						 static_cast<std::uint16_t>(0x09A0 + b)))
					 << (8 * b);
			put32(out.data(), s.dcAssign ? cycle : 0);
			return bytes(4);
		}
		case 12: // DC shift: the shift time configured, ns (signed)
			put32(out.data(), s.dcAssign ? static_cast<std::uint32_t>(s.dcShift) : 0);
			return bytes(4);
		case 13: // DC active: SYNC0 on (0x0981 bits 0 and 1)
			out[0] = (s.slave->escRead8(0x0981) & 0x03) == 0x03 ? 1 : 0;
			return bytes(1);
		default:
			return error();
		}
	}
	case ECMXF_CMD_ECAT_SLV_CNT_GET:
		return ret(static_cast<unsigned>(nSlaves));
	case ECMXF_CMD_FIFO_ENABLE:
		return setSwitch(fifoEnabled_, h.param);
	case ECMXF_CMD_FIFO_PACK_SIZE_GET:
		if (h.param > 1)
			return error();
		put16(out.data(), static_cast<std::uint16_t>(h.param == 0 ? rxSize_ : txSize_));
		return bytes(2);
	case ECMXF_CMD_SPI_PACK_SIZE_GET:
		put16(out.data(), static_cast<std::uint16_t>(dataSize_));
		return bytes(2);
	case ECMXF_CMD_SPI_RECONFIG_OP:
		if (!ecmxf_data_size_valid(h.len))
			return error();
		dataSize_ = h.len; // the answer already goes out at the new size
		return ret(0);
	case ECMXF_CMD_CRC_ERR_CNT_CLR: {
		const unsigned was = crcErrCnt_;
		crcErrCnt_ = 0;
		return ret(was);
	}
	case ECMXF_CMD_CRC_TYPE_SET:
		if (h.param > ECMXF_CHECK_CRC32)
			return error();
		pendingCheck_ = h.param;
		return ret(0);
	case ECMXF_CMD_402_CONFIG_SET:
	case ECMXF_CMD_402_STATE_SET:
	case ECMXF_CMD_402_STATE_GET:
	case ECMXF_CMD_402_CTL_SET:
	case ECMXF_CMD_402_CTL_GET:
	case ECMXF_CMD_402_GET_STATUSWORD:
		return cmd402(h, out);
	case ECMXF_CMD_GPIO_CONFIG_SET:
	case ECMXF_CMD_GPIO_FUNC_OP:
	case ECMXF_CMD_QEI_FUNC_OP:
	case ECMXF_CMD_DAC_FUNC_OP:
	case ECMXF_CMD_ADC_FUNC_OP:
	case ECMXF_CMD_MDIO: {
		const Peripherals::Reply p = periph_.handle(h, in, out);
		Result r;
		r.ret = p.ret;
		r.len = std::min(p.len, out.size());
		r.cmdError = p.cmdError;
		return r;
	}
	case ECMXF_CMD_EEPROM_GET:
		return copyOut(eepromData_, out, eepromRet_);
	case ECMXF_CMD_FIFO_CLR_OP:
		if (h.param > 2)
			return error();
		if (h.param != 2) {
			stats_.txCleared += txFifo_.count();
			txFifo_.clear();
		}
		if (h.param != 1) {
			stats_.rxCleared += rxFifo_.count();
			rxFifo_.clear();
		}
		return ret(0);
	case ECMXF_CMD_FIFO_SET_TX_CNT:
		return h.param == 0 ? error() : setFifoDepths(rxDepth_, h.param);
	case ECMXF_CMD_FIFO_GET_TX_CNT:
		return ret(static_cast<unsigned>(txDepth_));
	case ECMXF_CMD_FIFO_SET_RX_CNT:
		return h.param == 0 ? error() : setFifoDepths(h.param, txDepth_);
	case ECMXF_CMD_FIFO_GET_RX_CNT:
		return ret(static_cast<unsigned>(rxDepth_));
	case ECMXF_CMD_FW_VERSION_GET: {
		std::array<std::uint8_t, 20> v{};
		if (cfg_.fwVersionData.empty()) {
			// byte 1 extended version 0, byte 3 series 0 (ECM-XF),
			// bytes 4..19 the build identifier
			static constexpr char kId[] = "ecmxf-simulator";
			std::memcpy(v.data() + 4, kId, sizeof(kId) - 1);
		} else {
			std::copy(cfg_.fwVersionData.begin(), cfg_.fwVersionData.end(), v.begin());
		}
		const std::size_t n = std::min(v.size(), out.size());
		std::memcpy(out.data(), v.data(), n);
		return bytes(n, cfg_.fwVersion);
	}
	case ECMXF_CMD_ECAT_INT_SET_ENABLE:
		if (h.param & ~0x03u)
			return error();
		polarity_ = h.param;
		intEnable_ = le32(in.data());
		gpioIntEnable_ = in[4];
		periphIntEnable_ = in[5];
		return ret(0);
	case ECMXF_CMD_ECAT_INT_GET_ENABLE:
		put32(out.data(), intEnable_);
		out[4] = gpioIntEnable_;
		out[5] = periphIntEnable_;
		return bytes(6, polarity_);
	case ECMXF_CMD_FIFO_INIT:
		rebuildFifos();
		return ret(0);
	case ECMXF_CMD_ECAT_SDO_ABORTCODE_GET:
		put32(out.data(), abortCode_);
		return bytes(4);
	case ECMXF_CMD_ECAT_SET_FIFO_TH:
		if (h.param & ~0x03u)
			return error();
		fifoThEnable_ = h.param;
		txHigh_ = h.data[0];
		rxLow_ = h.data[1];
		return ret(0);
	case ECMXF_CMD_ECAT_CONFIG_SM: {
		const std::size_t pos = in[0];
		const unsigned sm = in[1];
		if (!initialized_ || pos >= nSlaves || sm >= 16)
			return error();
		SlaveRec::SmDesc d;
		d.start = le16(&in[2]);
		d.len = le16(&in[4]);
		d.control = in[6];
		d.enable = in[7];
		slaves_[pos].smOverride[sm] = d;
		slaves_[pos].smOverrideMask = static_cast<std::uint16_t>(slaves_[pos].smOverrideMask | (1u << sm));
		writeSyncManagers(pos);
		return ret(0);
	}
	case ECMXF_CMD_ECAT_CONFIG_FMMU:
		// obsolete: the chip configures the FMMUs itself
		if (!initialized_ || in[0] >= nSlaves)
			return error();
		return ret(0);
	case ECMXF_CMD_ASYNCCMD_RESET:
		if (h.param == 0 || (h.param & ~0x07u))
			return error();
		if (h.param & 0x02)
			skipLinkWait_ = true;
		// bit 0 clears the busy flag, bit 2 abandons the command: in the
		// model both end the running (or stuck) command without an error
		if ((h.param & 0x05) && job_.active)
			job_ = AsyncJob{};
		return ret(0);
	case ECMXF_CMD_DIRECT_ASSIGN: {
		const std::size_t pos = h.data[0];
		if (!initialized_ || pos >= nSlaves || h.data[1] > 1)
			return error();
		SlaveRec &s = slaves_[pos];
		if (h.param == 0) {
			s.daEnabled = h.data[1] == 1;
		} else if (h.param == 1) {
			const std::uint16_t len = le16(&h.data[2]);
			if (h.data[1] == 0)
				s.daOut = len;
			else
				s.daIn = len;
		} else {
			return error();
		}
		return ret(0);
	}
	case ECMXF_CMD_COE_EMERGENCY:
		return coeEmergency(h, out);
	case ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET:
		return ret(wkcConti_);
	case ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET:
		return ret(wkcMax_);
	case ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET:
		if (h.param == 0)
			return error();
		wkcMax_ = h.param;
		return ret(0);
	case ECMXF_CMD_RAW_ECAT_FUNC_GET:
		return copyOut(rawResult_, out);
	case ECMXF_CMD_FOE_FUNC_GET:
		return copyOut(foeResult_, out);
	case ECMXF_CMD_ENABLE_LRW:
		return setSwitch(lrw_, h.param);
	case ECMXF_CMD_RECV_MAILBOX:
		if (h.param != 1)
			return error();
		return recvMailboxRead(h, out);
	case ECMXF_CMD_MBX_STAT:
		return mbxStat(h, in, out);
	default:
		return error();
	}
}

bool Chip::Impl::fifoBudgetOk(std::size_t rx, std::size_t tx) const
{
	return rx * rxSize_ + tx * txSize_ <= kFifoBudget;
}

Chip::Impl::Result Chip::Impl::setFifoDepths(std::size_t rx, std::size_t tx)
{
	if (!fifoBudgetOk(rx, tx))
		return error();
	rxDepth_ = rx;
	txDepth_ = tx;
	rebuildFifos();
	return ret(0);
}

bool Chip::Impl::startAsync(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> in)
{
	const auto n = static_cast<Nanos>(slaves_.size());
	switch (h.code) {
	case ECMXF_CMD_ECAT_INIT_OP:
		return startInitOp(h, in);
	case ECMXF_CMD_ECAT_RECONFIG_OP:
		if (!initialized_)
			return false;
		startJobOnce(h.code, 10 * kMs + n * 500 * kUs, [this] {
			buildLayout();
			// ver. 050: "after command 2 the header's ECAT state is 1;
			// use command 57 for the slaves' real state"
			ecatState_ = ECMXF_ECAT_INIT;
			opReached_ = false;
		});
		return true;
	case ECMXF_CMD_ECAT_INIT_DC_OP:
		if (!initialized_)
			return false;
		startJobOnce(h.code, 20 * kMs, [this] {
			applyDc();
		});
		return true;
	case ECMXF_CMD_ECAT_PDO_CONFIG_SET:
		return startPdoConfigSet(in);
	case ECMXF_CMD_ECAT_PDO_CONFIG_REQ:
		return startPdoConfigReq(in);
	case ECMXF_CMD_ECAT_SDO_REQ:
		return startSdo(in);
	case ECMXF_CMD_ECAT_STATE_SET:
		return startStateSet(h.param, h.data[0], false);
	case ECMXF_CMD_ECAT_STATE_CHECK:
		return startStateSet(h.param, h.data[0], true);
	case ECMXF_CMD_EEPROM_REQ:
		return startEeprom(in);
	case ECMXF_CMD_ECAT_DCSYNC: {
		const unsigned sel = in[0];
		if (!initialized_ || (sel != 0xFF && sel >= slaves_.size()))
			return false;
		const std::uint16_t aa = le16(&in[2]);
		const std::uint32_t s0 = le32(&in[4]), s1 = le32(&in[8]);
		const auto shift = static_cast<std::int32_t>(le32(&in[12]));
		startJobOnce(h.code, kMs, [this, sel, aa, s0, s1, shift] {
			for (std::size_t p = 0; p < slaves_.size(); p++) {
				if (sel != 0xFF && p != sel)
					continue;
				SlaveRec &s = slaves_[p];
				s.dcAssign = aa;
				s.dcSync0 = s0;
				s.dcSync1 = s1;
				s.dcShift = shift;
			}
			// applied to the slaves by ECAT_INIT_DC_OP (manual ver. 050)
		});
		return true;
	}
	case ECMXF_CMD_ECAT_STATE_UPDATE:
		startJobOnce(h.code, 200 * kUs + n * 10 * kUs, [this] {
			refreshStates();
		});
		return true;
	case ECMXF_CMD_ECAT_CONFIG_MAP:
		if (!initialized_)
			return false;
		startJobOnce(h.code, 5 * kMs + n * 200 * kUs, [this] {
			buildLayout();
		});
		return true;
	case ECMXF_CMD_RAW_ECAT_FUNC_REQ:
		return startRaw(in);
	case ECMXF_CMD_FOE_FUNC_REQ:
		return startFoe(in, h.len);
	case ECMXF_CMD_RECV_MAILBOX:
		return startRecvMailbox(h);
	default:
		return false;
	}
}

} // namespace ecmxf::sim
