// SPDX-License-Identifier: MIT
/**
 * @file transport.hpp
 * @brief The link between the library and one ECM-XF chip.
 *
 * There is one Transport interface with two kinds of implementation:
 *
 *  - byte transports move SPI packets and report the chip's INT0 "ready"
 *    line; they know nothing about the protocol. The Device runs the
 *    protocol core (framing, check words, the one-exchange-late answers,
 *    retries, async tracking) on top of them: exchange(), waitReady(),
 *    now(), sleepFor(). Implementations: the in-process simulator
 *    (SimTransport, sim_transport.hpp) and spidev + libgpiod
 *    (SpidevTransport, spidev_transport.hpp).
 *  - command transports run the protocol themselves and take whole
 *    commands (runsProtocol() is true; derive from CommandTransport):
 *    the kernel module's /dev/ecmxfN (KernelTransport,
 *    kernel_transport.hpp). The Device hands each command to
 *    CommandTransport::run() and only maps the outcome to ecmxf::Error.
 *
 * Thread safety: a Transport is not thread-safe; its one owner (a Device)
 * calls it from one thread at a time.
 */
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <ecmxf/device.hpp>
#include <ecmxf/export.hpp>

namespace ecmxf {

/// Abstract link to one chip.
class ECMXF_EXPORT Transport
{
public:
	Transport() = default;
	Transport(const Transport &) = delete;
	Transport &operator=(const Transport &) = delete;
	virtual ~Transport();

	/// true: the transport runs the protocol itself and takes whole
	/// commands (it is a CommandTransport); the byte-level calls below
	/// then throw EOPNOTSUPP. false (the default): a byte transport.
	[[nodiscard]] virtual bool runsProtocol() const noexcept { return false; }

	/// One full-duplex SPI transfer: clocks out @p mosi and fills @p miso
	/// with the bytes clocked in. Both spans have the same size (the
	/// current packet size) and belong to the caller; the transport keeps
	/// no reference to them after returning. Blocks for the duration of the
	/// transfer. Throws ecmxf::Error when the transfer cannot be made at
	/// all (a corrupted transfer is not an error here: the protocol core
	/// detects it from the check word).
	virtual void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) = 0;

	/// Waits until the chip signals "ready" on INT0 (it has processed the
	/// previous packet), for at most @p timeout on the transport's clock.
	/// Returns true at once when the chip is ready, false when @p timeout
	/// passed without it (then now() has moved on by at least @p timeout).
	/// Blocks (real transports) or advances virtual time (simulator).
	[[nodiscard]] virtual bool waitReady(std::chrono::nanoseconds timeout) = 0;

	/// The transport's clock, monotonic, any origin: virtual time for the
	/// simulator, std::chrono::steady_clock otherwise. The protocol core's
	/// deadlines are measured on it.
	[[nodiscard]] virtual std::chrono::nanoseconds now() const = 0;

	/// Lets @p duration pass on the transport's clock: sleeps (real
	/// transports; the default implementation sleeps on the steady clock)
	/// or advances virtual time (simulator). Non-positive durations return
	/// at once.
	virtual void sleepFor(std::chrono::nanoseconds duration);
};

/// One whole command for a CommandTransport: the command header fields
/// the host chooses (packet bytes 0x04..0x17 except the index, which the
/// protocol runner allocates) and the data. Plain data: building one
/// allocates nothing.
struct RawRequest {
	std::array<std::uint8_t, 4> data{};      ///< parametric data 0..3 (0x04..0x07)
	std::uint16_t reserved = 0;              ///< the word at 0x08 (LRW, bus shift, GPIO out valid)
	std::uint8_t control = 0;                ///< control byte (0x0A)
	std::uint8_t code = 0;                   ///< command code (0x0C)
	std::uint8_t param = 0;                  ///< command parameter (0x0D)
	std::uint16_t len = 0;                   ///< data length field (0x0E), sent as given
	std::uint32_t intClear = 0;              ///< interrupt clear (0x10)
	std::array<std::uint8_t, 2> gpioIntClear{}; ///< GPIO interrupt clear low/high (0x14, 0x15)
	std::array<std::uint8_t, 2> gpioOut{};   ///< GPIO outputs low/high (0x16, 0x17)
	std::span<const std::uint8_t> tx;        ///< data section bytes to send (rest zero)
	std::span<std::uint8_t> rx;              ///< where the answer's data goes
	/// Time allowed until the answer (async: until completion), in
	/// microseconds; 0 selects the command table's default.
	std::uint32_t timeoutUs = 0;
	/// Leave the chip's async / command error bits set after a failure
	/// (ECMXF_CMD_F_NO_AUTO_CLEAR).
	bool noAutoClear = false;
};

/// The outcome of a RawRequest.
struct RawResult {
	/// 0, or the command's negative errno as the protocol core reports it
	/// (-ETIMEDOUT, -EBUSY, -EREMOTEIO, -EBADMSG / -EPROTO / -EIO,
	/// -ECONNRESET, -EMSGSIZE, -ECANCELED).
	int status = 0;
	/// The header that answered (for an async command: the one that
	/// ended the busy phase); meaningful when the chip answered.
	ResponseHeader header;
	/// Bytes of answer data written to RawRequest::rx.
	std::size_t rxLen = 0;
};

/// A transport that runs the protocol itself (the kernel module) and
/// takes whole commands. The byte-level calls of Transport throw
/// ecmxf::Error (EOPNOTSUPP); now() is the steady clock.
class ECMXF_EXPORT CommandTransport : public Transport
{
public:
	/// @p name: how messages name the link, e.g. "/dev/ecmxf0".
	explicit CommandTransport(std::string name);
	~CommandTransport() override;

	[[nodiscard]] bool runsProtocol() const noexcept final { return true; }
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) final;
	[[nodiscard]] bool waitReady(std::chrono::nanoseconds timeout) final;
	[[nodiscard]] std::chrono::nanoseconds now() const override;

	/// Runs @p req to its end. Returns 0 when the command went through the
	/// link, with its outcome in @p res.status; or the negative errno of a
	/// failure to hand the command over at all (e.g. the ioctl failed),
	/// then @p failedCall names the call that failed (a static string,
	/// e.g. "ECMXF_IOC_CMD"). Never throws, allocates nothing.
	[[nodiscard]] int run(const RawRequest &req, RawResult &res, const char *&failedCall) noexcept;

	/// The data section size the far side uses now (0 when it cannot
	/// tell). Device::dataSize() reports it for such transports.
	[[nodiscard]] virtual std::uint16_t dataSize() const noexcept { return 0; }
	/// The check word type the far side uses now (0..3), if it can tell;
	/// Device::checkType() reports it for such transports, else the ECM
	/// status bits of the last answer (which lag one command behind
	/// CRC_TYPE_SET and know nothing of a WARM_RESET made since).
	[[nodiscard]] virtual std::optional<std::uint8_t> checkTypeNow() const noexcept { return std::nullopt; }

	/// The header of the latest answer, if any.
	[[nodiscard]] std::optional<ResponseHeader> lastHeader() const noexcept { return last_; }
	/// How messages name the link.
	[[nodiscard]] const std::string &name() const noexcept { return name_; }

protected:
	/// The implementation of run(), same contract.
	[[nodiscard]] virtual int doCommand(const RawRequest &req, RawResult &res,
					    const char *&failedCall) noexcept = 0;

private:
	std::string name_;
	std::optional<ResponseHeader> last_;
};

} // namespace ecmxf
