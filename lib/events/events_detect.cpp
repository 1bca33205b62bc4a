// SPDX-License-Identifier: MIT
// EventDetector: the protocol core's header event detector
// (lib/core/ecmxf-events.c) in C++ types, and the names of event types.

#include <ecmxf/events/events.hpp>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/error.hpp>

#include "base/text.hpp"
#include "link/wire_header.hpp"
#include "ecmxf-events.h"

namespace ecmxf {

namespace {

Event fromCore(const ecmxf_det_event &d)
{
	Event e;
	e.type = static_cast<EventType>(d.type);
	e.time = std::chrono::nanoseconds(static_cast<std::int64_t>(d.time_ns));
	e.errStatus = d.err_status;
	e.ecmStatus = d.ecm_status;
	switch (e.type) {
	case EventType::Link:
		e.linkUp = d.new_val != 0;
		break;
	case EventType::Reset:
		e.newValue = d.new_val;
		break;
	case EventType::Fifo:
		e.fifo = d.fifo == ECMXF_DET_FIFO_RX ? FifoId::Rx : FifoId::Tx;
		e.mark = d.mark;
		e.above = d.above;
		break;
	default:
		e.oldValue = d.old_val;
		e.newValue = d.new_val;
		break;
	}
	e.count = d.count;
	e.increase = d.increase;
	e.errors = d.errors;
	e.duration = std::chrono::nanoseconds(static_cast<std::int64_t>(d.duration_ns));
	return e;
}

std::uint64_t ns(std::chrono::nanoseconds t)
{
	return t.count() < 0 ? 0 : static_cast<std::uint64_t>(t.count());
}

std::vector<Event> convert(const ecmxf_det_event *d, unsigned n)
{
	std::vector<Event> out;
	out.reserve(n);
	for (unsigned i = 0; i < n; i++)
		out.push_back(fromCore(d[i]));
	return out;
}

} // namespace

std::string eventTypeName(EventType t)
{
	switch (t) {
	case EventType::Device: return "device";
	case EventType::Reset: return "reset";
	case EventType::Link: return "link";
	case EventType::State: return "state";
	case EventType::ErrorStatus: return "error_status";
	case EventType::EcmStatus: return "ecm_status";
	case EventType::CrcErrors: return "crc_errors";
	case EventType::WkcBurst: return "wkc_burst";
	case EventType::WkcBurstEnd: return "wkc_burst_end";
	case EventType::Fifo: return "fifo";
	case EventType::AsyncError: return "async_error";
	case EventType::PdoLoss: return "pdo_loss";
	}
	return "unknown";
}

std::string lossKindName(LossKind k)
{
	switch (k) {
	case LossKind::OutRingUnderrun: return "out_ring_underrun";
	case LossKind::InRingOverrun: return "in_ring_overrun";
	case LossKind::RxFifoUnderrun: return "rx_fifo_underrun";
	case LossKind::RxFifoOverrun: return "rx_fifo_overrun";
	case LossKind::TxFifoOverrun: return "tx_fifo_overrun";
	case LossKind::OutRingSkipped: return "out_ring_skipped";
	case LossKind::PumpFailure: return "pump_failure";
	}
	return "unknown";
}

bool stateWentDown(const Event &e) noexcept
{
	return e.type == EventType::State &&
	       ((e.newValue & ECMXF_ECAT_ERROR) || (e.newValue & 0x0F) < (e.oldValue & 0x0F));
}

void readSlaveStatus(Device &device, Event &e)
{
	constexpr std::uint8_t kOp = ECMXF_ECAT_OP;
	constexpr std::uint8_t kError = ECMXF_ECAT_ERROR;
	// the kernel's limit (ECMXF_NL_MAX_SLAVES): an event stays one message
	constexpr unsigned kMaxSlaves = 64;
	const Bus bus(device);
	e.haveSlaves = true;
	e.slaves.clear();
	e.alStatus.reset();
	e.alSlave.reset();
	try {
		e.slaveCount = bus.slaveCount();
		for (unsigned pos = 0; pos < e.slaveCount; pos++) {
			if (pos >= kMaxSlaves) {
				e.slavesIncomplete = true;
				return;
			}
			const auto p = static_cast<std::uint8_t>(pos);
			const std::uint8_t st = bus.stateGet(p).raw;
			if (st == kOp)
				continue;
			SlaveAlStatus s;
			s.position = static_cast<std::uint16_t>(pos);
			s.state = st;
			e.slaves.push_back(s);
			// ERROR alone: the slave does not answer, nothing to ask
			if (st == kError)
				continue;
			const std::vector<std::uint8_t> al = bus.slaveInfoRaw(p, SlaveInfoCode::AlStatusCode);
			if (al.size() < 2) {
				e.slavesIncomplete = true;
				continue;
			}
			const auto code = static_cast<std::uint16_t>(al[0] | al[1] << 8);
			e.slaves.back().alStatus = code;
			if (code && !e.alStatus) {
				e.alStatus = code;
				e.alSlave = s.position;
			}
		}
	} catch (const Error &) {
		e.slavesIncomplete = true;
	}
}

struct EventDetector::Impl {
	ecmxf_det det{};
	Device *device = nullptr;
};

EventDetector::EventDetector() : EventDetector(Config{}) {}

EventDetector::EventDetector(Device &device) : EventDetector(device, Config{}) {}

EventDetector::EventDetector(Device &device, const Config &config) : EventDetector(config)
{
	impl_->device = &device;
}

EventDetector::EventDetector(const Config &config) : impl_(std::make_unique<Impl>())
{
	ecmxf_det_cfg cfg{};
	cfg.tx_high = config.txHigh;
	cfg.rx_low = config.rxLow;
	cfg.wkc_quiet_ns = ns(config.wkcQuiet);
	ecmxf_det_init(&impl_->det, &cfg);
}

EventDetector::~EventDetector() = default;
EventDetector::EventDetector(EventDetector &&) noexcept = default;
EventDetector &EventDetector::operator=(EventDetector &&) noexcept = default;

std::vector<Event> EventDetector::feed(const ResponseHeader &header, std::chrono::nanoseconds now)
{
	ecmxf_det_event d[ECMXF_DET_MAX_EVENTS];
	const ecmxf_rsp_hdr h = detail::wireHeader<ecmxf_rsp_hdr>(header);
	std::vector<Event> out = convert(d, ecmxf_det_feed(&impl_->det, &h, ns(now), d));
	if (impl_->device)
		for (Event &e : out)
			if (stateWentDown(e))
				readSlaveStatus(*impl_->device, e);
	return out;
}

std::vector<Event> EventDetector::poll(std::chrono::nanoseconds now)
{
	ecmxf_det_event d[1];
	return convert(d, ecmxf_det_poll(&impl_->det, ns(now), d));
}

std::vector<Event> EventDetector::rebase(std::chrono::nanoseconds now)
{
	ecmxf_det_event d[1];
	return convert(d, ecmxf_det_rebase(&impl_->det, ns(now), d));
}

std::optional<std::chrono::nanoseconds> EventDetector::deadline() const
{
	const std::uint64_t t = ecmxf_det_deadline(&impl_->det);
	if (t == UINT64_MAX)
		return std::nullopt;
	return std::chrono::nanoseconds(static_cast<std::int64_t>(t));
}

} // namespace ecmxf
