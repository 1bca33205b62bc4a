// SPDX-License-Identifier: MIT
/**
 * @file engine_link.hpp
 * @brief The engine link: the shared protocol core's exchange engine
 *        (lib/core, Documentation/protocol-core.rst) run over a ByteChannel.
 *
 * Framing, check words, the one-exchange-late answers, retries, async
 * tracking and the format changes (SPI_RECONFIG_OP, CRC_TYPE_SET,
 * WARM_RESET) are the engine's; the channel moves the bytes. The kernel
 * module runs the very same core over its SPI device.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <ecmxf/export.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/link/link.hpp>

namespace ecmxf {

/// A Link that runs the protocol core over a ByteChannel it owns.
class ECMXF_EXPORT EngineLink final : public Link
{
public:
	/// A link over @p channel. The chip is assumed to be in its power-on
	/// format (112-byte data section, fixed check word); assumeFormat()
	/// says otherwise. Throws ecmxf::Error (EINVAL) for a null channel.
	explicit EngineLink(std::unique_ptr<ByteChannel> channel);
	~EngineLink() override;

	void run(const RawRequest &req, RawResult &res) noexcept override;
	void runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res,
		      bool leaveLast = false) noexcept override;
	void settle() noexcept override;
	void setPipelining(bool on) noexcept override;
	[[nodiscard]] bool pipelining() const noexcept override;
	[[nodiscard]] std::uint16_t dataSize() const noexcept override;
	[[nodiscard]] CheckType checkType() const noexcept override;
	[[nodiscard]] std::optional<ResponseHeader> lastHeader() const noexcept override;
	/// The protocol core's finding (ecmxf_engine_cover()).
	[[nodiscard]] CrcCoverage crcCoverage() const noexcept override;
	[[nodiscard]] std::string name() const override;
	[[nodiscard]] std::chrono::nanoseconds now() const override;
	void sleepFor(std::chrono::nanoseconds duration) override;
	void sleepUntil(std::chrono::nanoseconds deadline) override;
	[[nodiscard]] std::chrono::nanoseconds coarseNow() const override;
	void assumeFormat(std::uint16_t dataSize, CheckType check) override;
	void setAsyncPollInterval(std::chrono::nanoseconds interval) noexcept override;
	[[nodiscard]] std::chrono::nanoseconds asyncPollInterval() const noexcept override;
	[[nodiscard]] LinkCounters counters() const override;
	/// The chip of its channel when that is a SimChannel (the "sim:"
	/// URIs), else null.
	[[nodiscard]] sim::Chip *simulator() noexcept override;
	void attachTrace(detail::TraceWriter *trace) noexcept override;

	/// The channel this link owns.
	[[nodiscard]] ByteChannel &channel() noexcept;

private:
	class Engine;
	std::unique_ptr<Engine> e_;
};

} // namespace ecmxf
