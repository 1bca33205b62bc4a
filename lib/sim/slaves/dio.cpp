// SPDX-License-Identifier: MIT
//
// dio.cpp - a digital I/O terminal without mailbox (like an EL1859): N
// output bytes in RxPDO 0x1600 (entries 0x7000:01..N, 8 bits each), M input
// bytes in TxPDO 0x1A00 (0x6000:01..M); process data on SM0 (outputs,
// 0x0F00) and SM1 (inputs, 0x1000). Outputs reach the terminals only in OP
// and fall back to 0 when OP is left. SDO requests are answered with abort
// 0x08000023 (no object dictionary).

#include <algorithm>
#include <stdexcept>

#include "slaves/factory.hpp"
#include "slaves/options.hpp"
#include "slaves/slave_base.hpp"

#include <ecmxf/sim/slaves.hpp>

namespace ecmxf::sim {

namespace slaves {
namespace {

constexpr std::int64_t kMaxBytes = 128;

class Dio final : public SlaveBase, public DioModel
{
public:
	Dio(unsigned position, const SlaveOptions &opts);

	[[nodiscard]] std::span<const std::uint8_t> outputs() const override { return outputs_; }
	[[nodiscard]] std::span<const std::uint8_t> inputs() const override { return inputs_; }
	void setInputs(std::span<const std::uint8_t> bytes) override
	{
		std::copy_n(bytes.begin(), std::min(bytes.size(), inputs_.size()), inputs_.begin());
	}
	void setInput(unsigned bit, bool value) override
	{
		if (bit / 8 >= inputs_.size())
			return;
		const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
		auto &b = inputs_[bit / 8];
		b = static_cast<std::uint8_t>(value ? (b | mask) : (b & ~mask));
	}

protected:
	void step(std::chrono::nanoseconds, bool) override
	{
		if (loopback_)
			std::copy_n(outputs_.begin(), std::min(outputs_.size(), inputs_.size()),
				    inputs_.begin());
	}
	void onAlChange(AlState from, AlState to, bool) override
	{
		if (from == AlState::Op && to != AlState::Op)
			std::fill(outputs_.begin(), outputs_.end(), 0); // safe state
	}

private:
	std::vector<std::uint8_t> outputs_, inputs_;
	bool loopback_ = false;
};

Dio::Dio(unsigned position, const SlaveOptions &opts) : SlaveBase(BaseConfig{})
{
	OptionReader o("dio", opts);
	const auto nOut = static_cast<std::size_t>(o.integer("outputs", 0, kMaxBytes).value_or(1));
	const auto nIn = static_cast<std::size_t>(o.integer("inputs", 0, kMaxBytes).value_or(1));
	loopback_ = o.boolean("loopback").value_or(false);
	identify(o, position, model::kDioProduct, model::kDioRevision,
		 "Digital I/O " + std::to_string(nOut * 8) + " out / " + std::to_string(nIn * 8) +
			 " in");
	o.finish();

	cfg_.coe = false;
	cfg_.foe = false;
	cfg_.mailboxLatency = std::chrono::nanoseconds(0);
	cfg_.escType = 0x12;
	cfg_.escFeatures = 0x0000; // no DC
	cfg_.pdiControl = 0x0004;  // digital I/O PDI
	cfg_.pdOutSm = 0;
	cfg_.pdInSm = 1;
	cfg_.pdOutStart = 0x0F00;
	cfg_.pdInStart = 0x1000;
	cfg_.maxEntriesPerPdo = static_cast<unsigned>(std::max<std::size_t>({ nOut, nIn, 1 }));
	cfg_.maxPdoBytes = static_cast<unsigned>(kMaxBytes);
	cfg_.maxOutBytes = static_cast<unsigned>(kMaxBytes);
	cfg_.maxInBytes = static_cast<unsigned>(kMaxBytes);
	cfg_.siiGroup = "DigIO";
	cfg_.siiOrder = "SIM-DIO";

	outputs_.assign(nOut, 0);
	inputs_.assign(nIn, 0);
	std::vector<std::uint32_t> rx, tx;
	for (std::size_t i = 0; i < nOut; i++) {
		const auto sub = static_cast<std::uint8_t>(i + 1);
		od_.sub(0x7000, sub, "Output byte", DataType::U8, Access::RO, &outputs_[i]).map(RxPdo);
		rx.push_back(0x70000008u | std::uint32_t{ sub } << 8);
	}
	for (std::size_t i = 0; i < nIn; i++) {
		const auto sub = static_cast<std::uint8_t>(i + 1);
		od_.sub(0x6000, sub, "Input byte", DataType::U8, Access::RO, &inputs_[i]).map(TxPdo);
		tx.push_back(0x60000008u | std::uint32_t{ sub } << 8);
	}
	if (nOut) {
		addPdoMapping(0x1600, true, rx);
		addPdoAssignment(true, { 0x1600 });
	} else {
		addPdoAssignment(true, {});
	}
	if (nIn) {
		addPdoMapping(0x1A00, false, tx);
		addPdoAssignment(false, { 0x1A00 });
	} else {
		addPdoAssignment(false, {});
	}
	finishSetup();
}

} // namespace
} // namespace slaves

std::unique_ptr<Slave> makeDio(unsigned position, const SlaveOptions &opts)
{
	return std::make_unique<slaves::Dio>(position, opts);
}

} // namespace ecmxf::sim
