// SPDX-License-Identifier: MIT
// Typed calls for the chip-level commands: firmware and link format,
// counters, interrupts, resets, GPIO/QEI/DAC/ADC, MDIO, slave EEPROM, raw
// datagrams, FoE, the receive mailbox, emergencies and direct assignment
// (include/ecmxf/device.hpp, "chip" section; Documentation/commands-chip.rst).
//
// Every call builds its command at the offsets of manual ver. 050 (ver. 038
// where only it documents the command), checks its arguments first, and
// turns the chip's refusal (error status bit 7) or an async failure into an
// ecmxf::Error that names the command, the slave or line, and the chip's
// own error code where it has one.

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/bus/status.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>

#include "ecmxf-proto.h"

namespace ecmxf {

namespace {

using std::chrono::microseconds;

constexpr unsigned kMaxSlaves = 128;        // "slave number 0~127" (EEPROM_REQ)
constexpr std::size_t kRawMax = 256;        // RAW_ECAT_FUNC_REQ: n <= 256
constexpr std::size_t kFoeChunk = 256;      // FOE_FUNC_REQ flash read/write: n <= 256
constexpr std::size_t kReqHeader = 20;      // RAW/FOE request header bytes
constexpr unsigned kAdcPolls = 100;

std::string hex(std::uint32_t v, int digits)
{
	char buf[16];
	std::snprintf(buf, sizeof(buf), "0x%0*X", digits, v);
	return buf;
}

std::string cmdName(std::uint8_t code)
{
	if (const auto ci = commandInfo(code))
		return std::string(ci->name);
	return "command " + std::to_string(code);
}

[[noreturn]] void invalid(const std::string &what, const std::string &why)
{
	throw Error(what + ": " + why, EINVAL);
}

void put16(std::vector<std::uint8_t> &d, std::size_t off, std::uint32_t v)
{
	d[off] = static_cast<std::uint8_t>(v);
	d[off + 1] = static_cast<std::uint8_t>(v >> 8);
}

void put32(std::vector<std::uint8_t> &d, std::size_t off, std::uint32_t v)
{
	for (std::size_t i = 0; i < 4; i++)
		d[off + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint16_t le16(const std::vector<std::uint8_t> &d, std::size_t off)
{
	return static_cast<std::uint16_t>(d[off] | d[off + 1] << 8);
}

std::uint32_t le32(const std::vector<std::uint8_t> &d, std::size_t off)
{
	return static_cast<std::uint32_t>(d[off]) | static_cast<std::uint32_t>(d[off + 1]) << 8 |
	       static_cast<std::uint32_t>(d[off + 2]) << 16 | static_cast<std::uint32_t>(d[off + 3]) << 24;
}

Command simple(std::uint8_t code, std::uint8_t param = 0)
{
	Command c;
	c.code = code;
	c.param = param;
	return c;
}

Command withData(std::uint8_t code, std::uint8_t param, std::uint8_t d0, std::uint8_t d1 = 0,
		 std::uint8_t d2 = 0, std::uint8_t d3 = 0)
{
	Command c = simple(code, param);
	c.data = { d0, d1, d2, d3 };
	return c;
}

/// A command whose data section is one little-endian u32 (QEI/DAC/ADC).
Command withWord(std::uint8_t code, std::uint8_t param, std::uint32_t v)
{
	Command c = simple(code, param);
	c.payload.assign(4, 0);
	put32(c.payload, 0, v);
	return c;
}

std::string slaveText(unsigned slave)
{
	return "slave " + std::to_string(slave);
}

void checkSlave(const std::string &what, unsigned slave)
{
	if (slave >= kMaxSlaves)
		invalid(what, "slave position " + std::to_string(slave) + " is out of range (0..127)");
}

/// Rethrows @p e with "@p context: " in front (when there is a context).
[[noreturn]] void rethrowIn(const std::string &context, const Error &e)
{
	if (context.empty())
		throw e;
	throw Error(context + ": " + e.what(), e.errnoValue(), e.errorStatus());
}

/// Clears a command error (bit 7) the chip still shows, so that the next
/// refusal is seen as new. A failure here is left to the next command.
void clearCommandError(Device &d)
{
	Command c = simple(ECMXF_CMD_INFO_UPDATE_OP);
	c.control = ECMXF_CTL_CLR_CMD_ERR;
	try {
		d.command(c);
	} catch (const Error &) {
		// the error being reported matters more; the next command reports
		// a link that is really gone
	}
}

std::string refusal(std::uint8_t code, const std::string &hint)
{
	std::string s = cmdName(code) + ": the chip refused the command (error status bit 7, command error";
	if (!hint.empty())
		s.append(": ").append(hint);
	s.append(")");
	const auto ci = commandInfo(code);
	if (ci && !ci->inV038)
		s.append("; the command exists only in firmware of manual ver. 050");
	return s;
}

/// Runs an immediate command. @p context names the operation for the
/// messages (empty: the command name says it all); @p hint is what a
/// command error most likely means.
Response immediate(Device &d, Command c, const std::string &context = {}, const std::string &hint = {})
{
	// a command error left from before would read as this command's
	c.control = static_cast<std::uint8_t>(c.control | ECMXF_CTL_CLR_CMD_ERR);
	Response r;
	try {
		r = d.command(c);
	} catch (const Error &e) {
		rethrowIn(context, e);
	}
	if (r.header.errStatus & ECMXF_ERR_CMD) {
		clearCommandError(d);
		throw Error((context.empty() ? "" : context + ": ") + refusal(c.code, hint), EINVAL,
			    r.header.errStatus);
	}
	return r;
}

/// Runs an async command to its completion. @p onFailure, when given,
/// explains an async failure (the chip's error code, from its *_GET); it
/// runs after the failure, with the chip free.
Response async(Device &d, const Command &c, const std::string &context, const std::string &hint,
	       const std::function<std::string()> &onFailure = {})
{
	// the engine sees a refusal only as a newly set bit 7
	if (d.lastHeader().errStatus & ECMXF_ERR_CMD)
		clearCommandError(d);
	try {
		return d.command(c);
	} catch (const Error &e) {
		const std::string where = context.empty() ? "" : context + ": ";
		if (e.errnoValue() == EBUSY && e.errorStatus() && !(d.lastHeader().ecmStatus & ECMXF_STS_BUSY))
			// refused, and nothing else runs: its parameters were wrong
			throw Error(where + refusal(c.code, hint), EINVAL, e.errorStatus());
		if (e.errnoValue() == EREMOTEIO && onFailure)
			throw Error(where + cmdName(c.code) + ": the async command failed: " + onFailure(),
				    EREMOTEIO, e.errorStatus());
		rethrowIn(context, e);
	}
}

/// The host's time limit for an async command with a chip-side
/// @p chipTimeout: the table's default, or longer when the chip may take
/// longer.
microseconds hostTimeout(microseconds chipTimeout, std::uint8_t code)
{
	if (chipTimeout <= microseconds::zero())
		return microseconds::zero();
	const auto ci = commandInfo(code);
	const microseconds dflt(static_cast<std::int64_t>(ci ? ci->timeoutMs : 1000u) * 1000);
	return std::max(dflt, chipTimeout + std::chrono::seconds(1));
}

std::uint32_t chipTimeoutField(const std::string &what, microseconds t)
{
	if (t < microseconds::zero() || t.count() > static_cast<std::int64_t>(UINT32_MAX))
		invalid(what, "timeout of " + std::to_string(t.count()) + " us is out of range (0..4294967295 us)");
	return static_cast<std::uint32_t>(t.count());
}

void needData(const std::string &what, const Response &r, std::size_t n)
{
	if (r.data.size() < n)
		throw Error(what + ": the chip answered " + std::to_string(r.data.size()) + " data bytes, expected " +
				    std::to_string(n),
			    EPROTO);
}

std::string gpioLineMaskError(std::uint32_t lines)
{
	return "line mask " + hex(lines, 8) + " names lines above GPIO 19 (the ECM-XF has GPIO 0..19)";
}

std::vector<bool> bitsOf(const std::vector<std::uint8_t> &bytes, unsigned count)
{
	std::vector<bool> out(count);
	for (unsigned p = 0; p < count; p++)
		out[p] = p / 8 < bytes.size() && ((static_cast<unsigned>(bytes[p / 8]) >> (p % 8)) & 1u);
	return out;
}

} // namespace

// ===========================================================================
// the chip, its link
// ===========================================================================

ResponseHeader Device::infoUpdate(const InfoUpdateOptions &options)
{
	const std::string what = "INFO_UPDATE_OP";
	if (options.clearErrorBits & ~ECMXF_ERR_FAULT_MASK)
		invalid(what, "error bits " + hex(options.clearErrorBits, 2) +
				      " include bits 0..2, which cannot be cleared (clearable: bits 3..7 = 0xF8)");
	Command c = simple(ECMXF_CMD_INFO_UPDATE_OP);
	c.control = static_cast<std::uint8_t>(options.clearErrorBits | (options.refreshEcatState ? ECMXF_CTL_REFRESH_STATE : 0u) |
					      (options.clearCrcErrorCount ? ECMXF_CTL_CLR_CRC_CNT : 0u));
	return command(c).header;
}

FirmwareVersion Device::firmwareVersion()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_FW_VERSION_GET));
	FirmwareVersion v;
	v.version = r.ret;
	if (r.data.size() < 4)
		return v; // firmware of manual ver. 038: the return value only
	v.detailed = true;
	v.extendedVersion = r.data[1];
	v.seriesCode = r.data[3];
	if (v.seriesCode <= static_cast<std::uint8_t>(MasterSeries::XM))
		v.series = static_cast<MasterSeries>(v.seriesCode);
	const std::size_t n = std::min<std::size_t>(r.data.size(), 20) - 4;
	std::copy_n(r.data.begin() + 4, n, v.buildIdBytes.begin());
	bool printable = true;
	std::string text;
	for (std::uint8_t b : v.buildIdBytes) {
		if (b == 0)
			break;
		if (b < 0x20 || b > 0x7E)
			printable = false;
		text.push_back(static_cast<char>(b));
	}
	if (printable) {
		v.buildId = text;
	} else {
		for (std::uint8_t b : v.buildIdBytes) {
			char buf[4];
			std::snprintf(buf, sizeof(buf), "%02x", b);
			v.buildId.append(buf);
		}
	}
	return v;
}

ChipInfo Device::info()
{
	ChipInfo i;
	i.firmware = firmwareVersion();
	i.dataSize = queryDataSize();
	i.packetSize = packetSize(i.dataSize);
	i.wkcErrorLimit = wkcErrorLimit();
	try {
		i.wkcContinuousErrors = wkcContinuousErrorCount();
	} catch (const Error &e) {
		// firmware of manual ver. 038 does not know command 130
		if (!(e.errnoValue() == EINVAL && e.errorStatus() && (*e.errorStatus() & ECMXF_ERR_CMD)))
			throw;
	}
	i.checkType = checkType();
	const ResponseHeader h = lastHeader();
	i.ecatState = h.ecatState;
	i.errorStatus = h.errStatus;
	i.ecmStatus = h.ecmStatus;
	i.interruptFlags = h.intFlags;
	i.crcErrors = h.crcErrCnt;
	i.wkcErrors = h.wkcErrCnt;
	return i;
}

std::uint16_t Device::queryDataSize()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_SPI_PACK_SIZE_GET));
	needData("SPI_PACK_SIZE_GET", r, 2);
	return le16(r.data, 0);
}

void Device::setDataSize(std::uint16_t bytes)
{
	if (bytes < kDataMin || bytes > kDataMax)
		invalid("SPI_RECONFIG_OP", "data section size " + std::to_string(bytes) +
						   " is out of range (32..1408 bytes)");
	Command c = simple(ECMXF_CMD_SPI_RECONFIG_OP);
	c.len = bytes;
	immediate(*this, c, {}, "the firmware does not accept this size (an ECM-XFU has a fixed 992)");
}

void Device::setCheckType(CheckType type)
{
	const auto t = static_cast<unsigned>(type);
	if (t > 3)
		invalid("CRC_TYPE_SET", "check type " + std::to_string(t) +
						" is out of range (0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32)");
	immediate(*this, simple(ECMXF_CMD_CRC_TYPE_SET, static_cast<std::uint8_t>(t)), {},
		  "check type " + std::string(checkTypeName(type)) + " is unknown to this firmware");
}

std::uint8_t Device::clearCrcErrorCount()
{
	return immediate(*this, simple(ECMXF_CMD_CRC_ERR_CNT_CLR)).ret;
}

std::uint8_t Device::wkcContinuousErrorCount()
{
	return immediate(*this, simple(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).ret;
}

std::uint8_t Device::wkcErrorLimit()
{
	return immediate(*this, simple(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).ret;
}

void Device::setWkcErrorLimit(std::uint8_t limit)
{
	if (limit == 0)
		invalid("ECAT_WKC_CONTI_ERR_MAX_SET", "limit 0 is out of range (1..254 errors, 255 = no limit)");
	immediate(*this, simple(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, limit));
}

void Device::setInterruptConfig(const InterruptConfig &config)
{
	const std::string what = "ECAT_INT_SET_ENABLE";
	if (config.sources & ~irq::kEnableMask)
		invalid(what, "interrupt sources " + hex(config.sources, 8) +
				      " include bits that cannot be enabled (allowed: bits 31, 25, 24, 23, 22 = " +
				      hex(irq::kEnableMask, 8) + "; the encoder is enabled by the QEI sources)");
	if (config.gpioLines & ~0x0FFFu)
		invalid(what, "GPIO lines " + hex(config.gpioLines, 4) +
				      " include lines above GPIO 11 (GPIO interrupts to INT1: GPIO 0..11)");
	Command c = simple(ECMXF_CMD_ECAT_INT_SET_ENABLE,
			   static_cast<std::uint8_t>((config.int1ActiveHigh ? 1u : 0u) | (config.int0ActiveHigh ? 2u : 0u)));
	c.payload.assign(6, 0);
	put32(c.payload, 0, config.sources);
	c.payload[4] = static_cast<std::uint8_t>(config.gpioLines);
	c.payload[5] = static_cast<std::uint8_t>(((config.gpioLines >> 8) & 0x0Fu) | (config.qeiIndex ? 0x10u : 0u) |
						 (config.qeiCompare ? 0x20u : 0u) | (config.qeiOverflow ? 0x40u : 0u));
	immediate(*this, c);
}

InterruptConfig Device::interruptConfig()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_ECAT_INT_GET_ENABLE));
	needData("ECAT_INT_GET_ENABLE", r, 6);
	InterruptConfig c;
	c.int1ActiveHigh = (r.ret & 1u) != 0;
	c.int0ActiveHigh = (r.ret & 2u) != 0;
	c.sources = le32(r.data, 0);
	c.gpioLines = static_cast<std::uint16_t>(r.data[4] | (r.data[5] & 0x0Fu) << 8);
	c.qeiIndex = (r.data[5] & 0x10u) != 0;
	c.qeiCompare = (r.data[5] & 0x20u) != 0;
	c.qeiOverflow = (r.data[5] & 0x40u) != 0;
	return c;
}

void Device::resetAsyncCommand(std::uint8_t actions)
{
	if (actions == 0 || actions > 7)
		invalid("ASYNCCMD_RESET", "actions " + hex(actions, 2) +
						  " are out of range (bit 0 clear busy, bit 1 skip link wait, bit 2 "
						  "abandon the command: 0x01..0x07)");
	// a link capability: the kernel module sends ASYNCCMD_RESET only
	// through ECMXF_IOC_RESET (ECMXF_IOC_CMD refuses code 75; driver.rst)
	link().reset(LinkReset::AsyncCmd, actions);
}

void Device::warmReset()
{
	// a link capability: the kernel module sends WARM_RESET only through
	// ECMXF_IOC_RESET; an engine link runs it and follows to the power-on
	// format
	link().reset(LinkReset::Warm);
}

// ===========================================================================
// GPIO
// ===========================================================================

void Device::gpioSetMode(std::uint32_t lines, GpioMode mode, GpioPull pull)
{
	const std::string what = "GPIO_CONFIG_SET (GpioSetMode)";
	const auto m = static_cast<unsigned>(mode), p = static_cast<unsigned>(pull);
	if (lines == 0)
		invalid(what, "no GPIO line selected (line mask 0)");
	if (lines >> kGpioLines)
		invalid(what, gpioLineMaskError(lines));
	if (m > 3)
		invalid(what, "mode " + std::to_string(m) +
				      " is out of range (0 input, 1 output, 2 open-drain, 3 quasi-bidirectional)");
	if (p > 2)
		invalid(what, "pull " + std::to_string(p) + " is out of range (0 none, 1 up, 2 down)");
	const auto m8 = static_cast<std::uint8_t>(m), p8 = static_cast<std::uint8_t>(p);
	if (lines & 0xFFFFu)
		immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 0, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8), m8, p8));
	if (lines >> 16)
		immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 8, static_cast<std::uint8_t>(lines >> 16), 0, m8, p8));
}

void Device::gpioSetDebounce(std::uint32_t lines, bool enable)
{
	const std::string what = "GPIO_CONFIG_SET (GpioEnableDebounce)";
	if (lines == 0)
		invalid(what, "no GPIO line selected (line mask 0)");
	if (lines >> kGpioLines)
		invalid(what, gpioLineMaskError(lines));
	const std::uint8_t e = enable ? 1 : 0;
	if (lines & 0xFFFFu)
		immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 2, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8), e));
	if (lines >> 16)
		immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 9, static_cast<std::uint8_t>(lines >> 16), 0, e));
}

void Device::gpioSetDebounceClock(unsigned cycle, DebounceClock clock)
{
	const std::string what = "GPIO_CONFIG_SET (GpioSetDebounceClock)";
	const auto c = static_cast<unsigned>(clock);
	if (cycle > 15)
		invalid(what, "cycle " + std::to_string(cycle) + " is out of range (0..15: 2^cycle clock periods)");
	if (c > 1)
		invalid(what, "clock " + std::to_string(c) + " is out of range (0 192 MHz, 1 10 kHz)");
	immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 3, static_cast<std::uint8_t>(cycle | c << 4)));
}

void Device::gpioSetInterrupt(unsigned line, GpioEdge edge)
{
	const std::string what = "GPIO_CONFIG_SET (GpioIntEnable)";
	const auto e = static_cast<unsigned>(edge);
	if (line >= kGpioLines)
		invalid(what, "GPIO line " + std::to_string(line) + " is out of range (0..19)");
	if (e > 3)
		invalid(what, "interrupt type " + std::to_string(e) +
				      " is out of range (0 disabled, 1 both edges, 2 falling, 3 rising)");
	immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 1, static_cast<std::uint8_t>(line),
				  static_cast<std::uint8_t>(e)),
		  {}, "this firmware has interrupts on GPIO 0..15 only");
}

void Device::gpioClearInterrupts(std::uint32_t lines)
{
	const std::string what = "GPIO_CONFIG_SET (GpioIntClear)";
	if (lines == 0)
		invalid(what, "no GPIO line selected (line mask 0)");
	if (lines >> kGpioLines)
		invalid(what, gpioLineMaskError(lines));
	if (lines >> 16)
		immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 6, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8), static_cast<std::uint8_t>(lines >> 16)));
	else
		immediate(*this, withData(ECMXF_CMD_GPIO_CONFIG_SET, 4, static_cast<std::uint8_t>(lines),
					  static_cast<std::uint8_t>(lines >> 8)));
}

void Device::gpioWrite(std::uint16_t values)
{
	immediate(*this, withData(ECMXF_CMD_GPIO_FUNC_OP, 0, static_cast<std::uint8_t>(values),
				  static_cast<std::uint8_t>(values >> 8)));
}

void Device::gpioWriteAll(std::uint32_t values)
{
	if (values >> kGpioLines)
		invalid("GPIO_FUNC_OP (GpioExtSetValue)",
			"values " + hex(values, 8) + " name lines above GPIO 19 (the ECM-XF has GPIO 0..19)");
	immediate(*this, withData(ECMXF_CMD_GPIO_FUNC_OP, 2, static_cast<std::uint8_t>(values),
				  static_cast<std::uint8_t>(values >> 8), static_cast<std::uint8_t>(values >> 16)));
}

std::uint16_t Device::gpioRead()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_GPIO_FUNC_OP, 1));
	needData("GPIO_FUNC_OP (GpioGetValue)", r, 2);
	return le16(r.data, 0);
}

std::uint32_t Device::gpioReadAll()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_GPIO_FUNC_OP, 3));
	needData("GPIO_FUNC_OP (GpioExtGetValue)", r, 4);
	return le32(r.data, 0);
}

std::uint16_t Device::gpioInterruptFlags()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_GPIO_FUNC_OP, 5));
	needData("GPIO_FUNC_OP (GpioGetIntFlag)", r, 2);
	return le16(r.data, 0);
}

std::uint32_t Device::gpioInterruptFlagsAll()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_GPIO_FUNC_OP, 7));
	needData("GPIO_FUNC_OP (GpioExtGetIntFlag)", r, 4);
	return le32(r.data, 0);
}

// ===========================================================================
// QEI, DAC, ADC
// ===========================================================================

void Device::qeiOpen(QeiMode mode)
{
	const auto m = static_cast<std::uint32_t>(mode);
	if (m & ~0x300u)
		invalid("QEI_FUNC_OP (EncOpen)", "mode " + hex(m, 3) +
							 " is out of range (0x000 X4 free, 0x100 X2 free, 0x200 X4 "
							 "compare, 0x300 X2 compare)");
	immediate(*this, withWord(ECMXF_CMD_QEI_FUNC_OP, 4, m));
}

void Device::qeiStart()
{
	immediate(*this, simple(ECMXF_CMD_QEI_FUNC_OP, 5));
}

void Device::qeiStop()
{
	immediate(*this, simple(ECMXF_CMD_QEI_FUNC_OP, 6));
}

std::uint32_t Device::qeiCount()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_QEI_FUNC_OP, 21));
	needData("QEI_FUNC_OP (EncGetCount)", r, 4);
	return le32(r.data, 0);
}

void Device::dacOpen(DacTrigger trigger)
{
	const auto t = static_cast<std::uint32_t>(trigger);
	switch (t) {
	case 0x0000:
	case 0x0010:
	case 0x0030:
	case 0x1030:
	case 0x2030:
	case 0x3030:
		break;
	default:
		invalid("DAC_FUNC_OP (DacOpen)", "trigger " + hex(t, 4) +
							 " is not one of 0x0000, 0x0010, 0x0030, 0x1030, 0x2030, 0x3030");
	}
	immediate(*this, withWord(ECMXF_CMD_DAC_FUNC_OP, 20, t));
}

void Device::dacClose()
{
	immediate(*this, simple(ECMXF_CMD_DAC_FUNC_OP, 21));
}

void Device::dacSetDelay(std::uint16_t ticks)
{
	if (ticks > 1023)
		invalid("DAC_FUNC_OP (DacSetDelayTime)",
			"delay " + std::to_string(ticks) + " is out of range (0..1023 in 1/96 us)");
	immediate(*this, withWord(ECMXF_CMD_DAC_FUNC_OP, 22, ticks));
}

void Device::dacWrite(std::uint16_t value)
{
	if (value > 4095)
		invalid("DAC_FUNC_OP (DacSetData)",
			"value " + std::to_string(value) + " is out of range (0..4095 = 0..3.3 V)");
	immediate(*this, withWord(ECMXF_CMD_DAC_FUNC_OP, 11, value));
}

void Device::dacStartConversion()
{
	immediate(*this, simple(ECMXF_CMD_DAC_FUNC_OP, 0));
}

void Device::adcOpen(AdcInputMode mode)
{
	const auto m = static_cast<std::uint32_t>(mode);
	if (m != 0x000 && m != 0x100)
		invalid("ADC_FUNC_OP (AdcOpen)",
			"input mode " + hex(m, 3) + " is out of range (0x000 single-ended, 0x100 differential)");
	immediate(*this, withWord(ECMXF_CMD_ADC_FUNC_OP, 40, m));
}

void Device::adcClose()
{
	immediate(*this, simple(ECMXF_CMD_ADC_FUNC_OP, 41));
}

void Device::adcConfigureModule(unsigned module, unsigned channel)
{
	const std::string what = "ADC_FUNC_OP (AdcConfigSampleModule)";
	if (module > 15)
		invalid(what, "sample module " + std::to_string(module) + " is out of range (0..15)");
	if (channel > 15)
		invalid(what, "channel " + std::to_string(channel) + " is out of range (0..15)");
	Command c = simple(ECMXF_CMD_ADC_FUNC_OP, 42);
	c.payload.assign(12, 0);
	put32(c.payload, 0, module);
	put32(c.payload, 4, 0); // trigger source 0: software
	put32(c.payload, 8, channel);
	immediate(*this, c);
}

void Device::adcStart(std::uint16_t moduleMask)
{
	if (moduleMask == 0)
		invalid("ADC_FUNC_OP (AdcStartConv)", "no sample module selected (module mask 0)");
	immediate(*this, withWord(ECMXF_CMD_ADC_FUNC_OP, 12, moduleMask));
}

std::uint16_t Device::adcValidFlags(std::uint16_t moduleMask)
{
	const Response r = immediate(*this, withWord(ECMXF_CMD_ADC_FUNC_OP, 17, moduleMask));
	needData("ADC_FUNC_OP (AdcGetDataValidFlag)", r, 4);
	return static_cast<std::uint16_t>(le32(r.data, 0));
}

std::uint16_t Device::adcRead(unsigned module)
{
	const std::string what = "ADC_FUNC_OP (AdcGetConvData)";
	if (module > 15)
		invalid(what, "sample module " + std::to_string(module) + " is out of range (0..15)");
	const Response r = immediate(*this, withWord(ECMXF_CMD_ADC_FUNC_OP, 15, module));
	needData(what, r, 4);
	return static_cast<std::uint16_t>(le32(r.data, 0));
}

std::uint16_t Device::adcConvert(unsigned module)
{
	if (module > 15)
		invalid("ADC_FUNC_OP (AdcStartConv)", "sample module " + std::to_string(module) + " is out of range (0..15)");
	const auto mask = static_cast<std::uint16_t>(1u << module);
	adcStart(mask);
	for (unsigned i = 0; i < kAdcPolls; i++)
		if (adcValidFlags(mask) & mask)
			return adcRead(module);
	throw Error("ADC_FUNC_OP (AdcGetDataValidFlag): sample module " + std::to_string(module) +
			    " had no valid result after " + std::to_string(kAdcPolls) +
			    " polls (is the ADC open and the module configured?)",
		    ETIMEDOUT);
}

// ===========================================================================
// MDIO
// ===========================================================================

std::uint16_t Device::mdioRead(unsigned phy, unsigned reg)
{
	const std::string what = "MDIO (read)";
	if (phy > 31)
		invalid(what, "PHY address " + std::to_string(phy) + " is out of range (0..31)");
	if (reg > 31)
		invalid(what, "PHY register " + std::to_string(reg) + " is out of range (0..31)");
	const Response r = immediate(*this, withData(ECMXF_CMD_MDIO, 1, static_cast<std::uint8_t>(reg),
						     static_cast<std::uint8_t>(phy)));
	needData(what, r, 2);
	return le16(r.data, 0);
}

void Device::mdioWrite(unsigned phy, unsigned reg, std::uint16_t value)
{
	const std::string what = "MDIO (write)";
	if (phy > 31)
		invalid(what, "PHY address " + std::to_string(phy) + " is out of range (0..31)");
	if (reg > 31)
		invalid(what, "PHY register " + std::to_string(reg) + " is out of range (0..31)");
	immediate(*this, withData(ECMXF_CMD_MDIO, 0, static_cast<std::uint8_t>(reg), static_cast<std::uint8_t>(phy),
				  static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8)));
}

// ===========================================================================
// EEPROM
// ===========================================================================

namespace {

std::string eepromErrorText(unsigned code)
{
	switch (code) {
	case 1:
		return "EEPROM_GET error code 1 (address beyond the slave's EEPROM)";
	case 2:
		return "EEPROM_GET error code 2 (no answer from the slave)";
	default:
		return "EEPROM_GET error code " + std::to_string(code);
	}
}

/// EEPROM_REQ + EEPROM_GET; returns the EEPROM_GET answer.
Response eepromOp(Device &d, unsigned op, unsigned slave, std::uint16_t addr, std::uint16_t value,
		  microseconds timeout)
{
	std::string what = op ? "EEPROM write of " : "EEPROM read of ";
	what.append(slaveText(slave)).append(", word ").append(hex(addr, 4));
	checkSlave(what, slave);
	Command c = simple(ECMXF_CMD_EEPROM_REQ);
	c.payload.assign(12, 0);
	put16(c.payload, 0, op);
	put16(c.payload, 2, slave);
	put16(c.payload, 4, addr);
	put16(c.payload, 6, value);
	put32(c.payload, 8, chipTimeoutField(what, timeout));
	c.timeout = hostTimeout(timeout, ECMXF_CMD_EEPROM_REQ);
	async(d, c, what, slaveText(slave) + " does not exist", [&d] {
		return eepromErrorText(immediate(d, simple(ECMXF_CMD_EEPROM_GET)).ret);
	});
	const Response r = immediate(d, simple(ECMXF_CMD_EEPROM_GET), what);
	if (r.ret != 0)
		throw Error(what + ": EEPROM_REQ completed, but " + eepromErrorText(r.ret), EREMOTEIO,
			    r.header.errStatus);
	return r;
}

} // namespace

std::uint16_t Device::eepromRead(unsigned slave, std::uint16_t wordAddress, microseconds timeout)
{
	const Response r = eepromOp(*this, 0, slave, wordAddress, 0, timeout);
	needData("EEPROM_GET (" + slaveText(slave) + ", word " + hex(wordAddress, 4) + ")", r, 2);
	return le16(r.data, 0);
}

std::vector<std::uint16_t> Device::eepromReadWords(unsigned slave, std::uint16_t wordAddress, std::size_t count)
{
	if (count == 0 || wordAddress + count > 0x10000)
		invalid("EEPROM read of " + slaveText(slave),
			std::to_string(count) + " words from word " + hex(wordAddress, 4) +
				" do not fit the EEPROM's address space (1..65536 words up to word 0xFFFF)");
	std::vector<std::uint16_t> out;
	out.reserve(count);
	for (std::size_t i = 0; i < count; i++)
		out.push_back(eepromRead(slave, static_cast<std::uint16_t>(wordAddress + i)));
	return out;
}

void Device::eepromWrite(unsigned slave, std::uint16_t wordAddress, std::uint16_t value, microseconds timeout)
{
	eepromOp(*this, 1, slave, wordAddress, value, timeout);
}

// ===========================================================================
// raw datagrams
// ===========================================================================

DatagramResult Device::rawDatagram(const Datagram &dg)
{
	const auto op = static_cast<unsigned>(dg.command);
	static constexpr const char *kNames[] = { "",    "APRD", "APWR", "",    "FPRD", "FPWR", "",    "BRD",
						  "BWR", "",     "LRD",  "LWR",  "LRW",  "ARMW", "FRMW" };
	const bool known = op < 15 && kNames[op][0] != '\0';
	std::string what = "RAW_ECAT_FUNC_REQ";
	if (!known)
		invalid(what, "datagram command " + std::to_string(op) +
				      " is not one the chip sends (1 APRD, 2 APWR, 4 FPRD, 5 FPWR, 7 BRD, 8 BWR, 10 "
				      "LRD, 11 LWR, 12 LRW, 13 ARMW, 14 FRMW)");
	what = std::string(kNames[op]) + " ADP " + hex(dg.adp, 4) + " ADO " + hex(dg.ado, 4);
	const std::size_t n = dg.data.size();
	if (n == 0 || n > kRawMax)
		invalid(what, "datagram length " + std::to_string(n) + " is out of range (1..256 bytes)");
	if (kReqHeader + n > dataSize())
		throw Error(what + ": RAW_ECAT_FUNC_REQ: " + std::to_string(n) + " data bytes need a data section of " +
				    std::to_string(kReqHeader + n) + " bytes, the link has " +
				    std::to_string(dataSize()) + " (setDataSize())",
			    EMSGSIZE);
	Command c = simple(ECMXF_CMD_RAW_ECAT_FUNC_REQ);
	c.payload.assign(kReqHeader + n, 0);
	c.payload[0] = static_cast<std::uint8_t>(op);
	put16(c.payload, 2, static_cast<std::uint32_t>(n));
	put16(c.payload, 4, dg.adp);
	put16(c.payload, 6, dg.ado);
	put32(c.payload, 8, dg.logicalAddress);
	put32(c.payload, 12, chipTimeoutField(what, dg.timeout));
	std::copy(dg.data.begin(), dg.data.end(), c.payload.begin() + kReqHeader);
	c.timeout = hostTimeout(dg.timeout, ECMXF_CMD_RAW_ECAT_FUNC_REQ);
	async(*this, c, what, {});
	const Response r = immediate(*this, simple(ECMXF_CMD_RAW_ECAT_FUNC_GET), what);
	needData(what + ": RAW_ECAT_FUNC_GET", r, kReqHeader + n);
	DatagramResult out;
	out.workingCounter = le16(r.data, 16);
	out.data.assign(r.data.begin() + static_cast<long>(kReqHeader),
			r.data.begin() + static_cast<long>(kReqHeader + n));
	return out;
}

// ===========================================================================
// FoE and the chip's staging flash
// ===========================================================================

namespace {

std::string quoted(std::string_view s)
{
	std::string q(1, '"');
	q.append(s).push_back('"');
	return q;
}

std::string foeFailure(Device &d)
{
	const Response r = immediate(d, simple(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET));
	if (r.data.size() < 4)
		return "no error code (ECAT_SDO_ABORTCODE_GET answered " + std::to_string(r.data.size()) + " bytes)";
	const std::uint32_t code = le32(r.data, 0);
	return "FoE error " + hex(code, 8) + " (" + std::string(foeErrorText(code)) + ")";
}

/// FOE_FUNC_REQ header (20 bytes) followed by @p extra bytes.
Command foeRequest(unsigned slave, unsigned op, std::uint32_t password, std::uint32_t length,
		   std::uint32_t timeoutUs, std::uint32_t address, std::span<const std::uint8_t> extra)
{
	Command c = simple(ECMXF_CMD_FOE_FUNC_REQ);
	c.payload.assign(kReqHeader + extra.size(), 0);
	c.payload[0] = static_cast<std::uint8_t>(slave);
	c.payload[2] = static_cast<std::uint8_t>(op);
	put32(c.payload, 4, password);
	put32(c.payload, 8, length);
	put32(c.payload, 12, timeoutUs);
	put32(c.payload, 16, address);
	std::copy(extra.begin(), extra.end(), c.payload.begin() + kReqHeader);
	return c;
}

void checkFoeName(Device &d, const std::string &what, std::string_view name)
{
	if (name.empty())
		invalid(what, "empty file name");
	if (name.find('\0') != std::string_view::npos)
		invalid(what, "the file name contains a NUL byte");
	if (kReqHeader + name.size() > d.dataSize())
		throw Error(what + ": the file name (" + std::to_string(name.size()) +
				    " bytes) does not fit the data section (at most " +
				    std::to_string(d.dataSize() - kReqHeader) + " bytes now; setDataSize())",
			    EMSGSIZE);
}

void checkFlash(const std::string &what, std::uint32_t address, std::uint64_t length)
{
	if (address >= kFoeFlashSize)
		invalid(what, "flash address " + hex(address, 5) + " is out of range (0..0x3FFFF)");
	if (length > kFoeFlashSize - address)
		invalid(what, std::to_string(length) + " bytes from flash address " + hex(address, 5) +
				      " run past the end of the 256 KiB flash (0x40000)");
}

} // namespace

std::uint32_t Device::foeUploadToFlash(unsigned slave, std::string_view name, const FoeOptions &o)
{
	const std::string what = "FoE read of " + quoted(name) + " from " + slaveText(slave);
	checkSlave(what, slave);
	checkFoeName(*this, what, name);
	checkFlash(what, o.flashAddress, 0);
	const std::uint32_t tmo = chipTimeoutField(what, o.timeout);
	Command c = foeRequest(slave, 1, o.password, 0, tmo, o.flashAddress,
			       std::span(reinterpret_cast<const std::uint8_t *>(name.data()), name.size()));
	c.timeout = hostTimeout(o.timeout, ECMXF_CMD_FOE_FUNC_REQ);
	async(*this, c, what, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)",
	      [this] { return foeFailure(*this); });
	const Response r = immediate(*this, simple(ECMXF_CMD_FOE_FUNC_GET), what);
	needData(what + ": FOE_FUNC_GET", r, 4);
	return le32(r.data, 0);
}

void Device::foeDownloadFromFlash(unsigned slave, std::string_view name, std::uint32_t length, const FoeOptions &o)
{
	const std::string what = "FoE write of " + quoted(name) + " to " + slaveText(slave);
	checkSlave(what, slave);
	checkFoeName(*this, what, name);
	checkFlash(what, o.flashAddress, length);
	const std::uint32_t tmo = chipTimeoutField(what, o.timeout);
	Command c = foeRequest(slave, 2, o.password, length, tmo, o.flashAddress,
			       std::span(reinterpret_cast<const std::uint8_t *>(name.data()), name.size()));
	c.timeout = hostTimeout(o.timeout, ECMXF_CMD_FOE_FUNC_REQ);
	async(*this, c, what, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)",
	      [this] { return foeFailure(*this); });
}

std::vector<std::uint8_t> Device::flashRead(std::uint32_t address, std::uint32_t length)
{
	const std::string base = "FOE_FUNC_REQ flash read";
	checkFlash(base, address, length);
	const std::size_t chunk = std::min<std::size_t>(kFoeChunk, dataSize());
	std::vector<std::uint8_t> out;
	out.reserve(length);
	for (std::uint32_t done = 0; done < length;) {
		const auto n = static_cast<std::uint32_t>(std::min<std::size_t>(chunk, length - done));
		const std::uint32_t at = address + done;
		const std::string what = base + " of " + std::to_string(n) + " bytes at " + hex(at, 5);
		async(*this, foeRequest(0, 3, 0, n, 0, at, {}), what, {});
		const Response r = immediate(*this, simple(ECMXF_CMD_FOE_FUNC_GET), what);
		needData(what + ": FOE_FUNC_GET", r, n);
		out.insert(out.end(), r.data.begin(), r.data.begin() + n);
		done += n;
	}
	return out;
}

void Device::flashWrite(std::uint32_t address, std::span<const std::uint8_t> data)
{
	const std::string base = "FOE_FUNC_REQ flash write";
	checkFlash(base, address, data.size());
	const std::size_t chunk = std::min<std::size_t>(kFoeChunk, dataSize() - kReqHeader);
	for (std::size_t done = 0; done < data.size();) {
		const std::size_t n = std::min(chunk, data.size() - done);
		const auto at = static_cast<std::uint32_t>(address + done);
		const std::string what = base + " of " + std::to_string(n) + " bytes at " + hex(at, 5);
		async(*this, foeRequest(0, 4, 0, static_cast<std::uint32_t>(n), 0, at, data.subspan(done, n)), what, {});
		done += n;
	}
}

std::vector<std::uint8_t> Device::foeRead(unsigned slave, std::string_view name, const FoeOptions &o)
{
	const std::uint32_t size = foeUploadToFlash(slave, name, o);
	if (size > kFoeFlashSize - o.flashAddress)
		throw Error("FoE read of " + quoted(name) + " from " + slaveText(slave) + ": FOE_FUNC_GET reports " +
				    std::to_string(size) + " bytes, more than the flash holds from " +
				    hex(o.flashAddress, 5),
			    EPROTO);
	return flashRead(o.flashAddress, size);
}

void Device::foeWrite(unsigned slave, std::string_view name, std::span<const std::uint8_t> data, const FoeOptions &o)
{
	const std::string what = "FoE write of " + quoted(name) + " to " + slaveText(slave);
	checkSlave(what, slave);
	checkFoeName(*this, what, name);
	checkFlash(what, o.flashAddress, data.size());
	flashWrite(o.flashAddress, data);
	foeDownloadFromFlash(slave, name, static_cast<std::uint32_t>(data.size()), o);
}

// ===========================================================================
// emergencies, receive mailbox, direct assignment
// ===========================================================================

std::vector<CoeEmergency> Device::coeEmergencies(unsigned count)
{
	const std::string what = "COE_EMERGENCY";
	if (count == 0 || count > 8)
		invalid(what, "count " + std::to_string(count) + " is out of range (1..8)");
	if (12u * count > dataSize())
		throw Error(what + ": " + std::to_string(count) + " entries need " + std::to_string(12 * count) +
				    " data bytes, the data section has " + std::to_string(dataSize()),
			    EMSGSIZE);
	const Response r = immediate(*this, simple(ECMXF_CMD_COE_EMERGENCY, static_cast<std::uint8_t>(count)));
	needData(what, r, 12u * count);
	std::vector<CoeEmergency> out;
	for (std::size_t i = 0; i < count; i++) {
		const std::size_t o = 12 * i;
		if (r.data[o] == 0xFF)
			continue; // no such emergency
		CoeEmergency e;
		e.entry = r.data[o];
		e.slave = r.data[o + 1];
		e.sequence = le16(r.data, o + 2);
		e.errorCode = le16(r.data, o + 4);
		e.errorRegister = r.data[o + 6];
		std::copy_n(r.data.begin() + static_cast<long>(o + 7), 5, e.data.begin());
		out.push_back(e);
	}
	return out;
}

std::vector<unsigned> Device::mailboxPending()
{
	const Response r = immediate(*this, simple(ECMXF_CMD_MBX_STAT, 0));
	std::vector<unsigned> out;
	for (std::size_t i = 0; i < r.data.size() * 8; i++)
		if ((static_cast<unsigned>(r.data[i / 8]) >> (i % 8)) & 1u)
			out.push_back(static_cast<unsigned>(i));
	return out;
}

void Device::setMailboxPolling(const std::vector<bool> &poll)
{
	const std::string what = "MBX_STAT (set polling)";
	const unsigned n = slaveCount();
	if (poll.size() != n)
		invalid(what, std::to_string(poll.size()) + " polling flags given for " + std::to_string(n) +
				      " slaves (one per slave found by ECAT_INIT_OP)");
	if (n == 0)
		invalid(what, "no slaves (run ECAT_INIT_OP first)");
	Command c = simple(ECMXF_CMD_MBX_STAT, 1);
	c.payload.assign((n + 7) / 8, 0);
	for (unsigned p = 0; p < n; p++)
		if (poll[p])
			c.payload[p / 8] = static_cast<std::uint8_t>(c.payload[p / 8] | 1u << (p % 8));
	immediate(*this, c);
}

std::vector<bool> Device::mailboxPolling()
{
	const unsigned n = slaveCount();
	const Response r = immediate(*this, simple(ECMXF_CMD_MBX_STAT, 2));
	needData("MBX_STAT (polling)", r, (n + 7) / 8);
	return bitsOf(r.data, n);
}

void Device::fetchMailbox(unsigned slave)
{
	const std::string what = "RECV_MAILBOX of " + slaveText(slave);
	checkSlave(what, slave);
	Command c = withData(ECMXF_CMD_RECV_MAILBOX, 0, static_cast<std::uint8_t>(slave));
	async(*this, c, what, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)",
	      [slave] { return slaveText(slave) + " did not answer"; });
}

std::vector<std::uint8_t> Device::readMailbox(std::size_t offset, std::size_t length)
{
	const std::string what = "RECV_MAILBOX (read)";
	if (offset >= 64u * 256u)
		invalid(what, "offset " + std::to_string(offset) + " is out of range (0..16383)");
	if (length == 0 || length > dataSize())
		invalid(what, "length " + std::to_string(length) + " is out of range (1.." +
				      std::to_string(dataSize()) + ", the data section)");
	Command c = withData(ECMXF_CMD_RECV_MAILBOX, 1, static_cast<std::uint8_t>(offset % 64),
			     static_cast<std::uint8_t>(offset / 64), static_cast<std::uint8_t>(length % 64),
			     static_cast<std::uint8_t>(length / 64));
	const Response r = immediate(*this, c);
	needData(what, r, length);
	return std::vector<std::uint8_t>(r.data.begin(), r.data.begin() + static_cast<long>(length));
}

std::vector<std::uint8_t> Device::receiveMailbox(unsigned slave)
{
	fetchMailbox(slave);
	std::vector<std::uint8_t> msg = readMailbox(0, 6);
	const std::size_t total = 6u + le16(msg, 0);
	if (total == 6)
		return {}; // the mailbox was empty
	while (msg.size() < total) {
		const std::size_t n = std::min<std::size_t>(total - msg.size(), dataSize());
		const std::vector<std::uint8_t> part = readMailbox(msg.size(), n);
		msg.insert(msg.end(), part.begin(), part.end());
	}
	return msg;
}

void Device::setDirectAssign(unsigned slave, bool enable)
{
	const std::string what = "DIRECT_ASSIGN (enable) for " + slaveText(slave);
	checkSlave(what, slave);
	immediate(*this, withData(ECMXF_CMD_DIRECT_ASSIGN, 0, static_cast<std::uint8_t>(slave),
				  static_cast<std::uint8_t>(enable ? 1 : 0)),
		  {},
		  slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)");
}

void Device::setDirectAssignLength(unsigned slave, ProcessDataSide side, std::uint16_t bytes)
{
	const std::string what = "DIRECT_ASSIGN (length) for " + slaveText(slave);
	checkSlave(what, slave);
	const auto s = static_cast<unsigned>(side);
	if (s > 1)
		invalid(what, "side " + std::to_string(s) + " is out of range (0 output, 1 input)");
	immediate(*this, withData(ECMXF_CMD_DIRECT_ASSIGN, 1, static_cast<std::uint8_t>(slave),
				  static_cast<std::uint8_t>(s), static_cast<std::uint8_t>(bytes),
				  static_cast<std::uint8_t>(bytes >> 8)),
		  {}, slaveText(slave) + " does not exist or the bus is not initialised (ECAT_INIT_OP)");
}

} // namespace ecmxf
