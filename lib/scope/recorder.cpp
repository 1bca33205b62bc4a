// SPDX-License-Identifier: MIT
// The scope's recorder (include/ecmxf/scope/recorder.hpp): signals looked
// up once by their text, then read into a ring of samples every cycle.

#include <ecmxf/scope/recorder.hpp>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>

#include <ecmxf/error.hpp>
#include <ecmxf/model/objects.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/board_views.hpp>

#include "base/text.hpp"

namespace ecmxf {

using detail::hex;
using detail::quoted;

namespace {

constexpr std::size_t kMaxCapacity = 10'000'000;

enum class Kind : std::uint8_t { InS, InU, OutS, OutU, Xf, Sk, SkAxis, Value };

// the cycle figures, in the order of their tables
enum XfField : int { kWkc, kWkcExpected, kWkcErrors, kRxFifo, kTxFifo, kPushed, kPopped, kError };
enum SkField : int { kFifoRemaining, kFifoFull, kDropped, kStaged };
enum AxisField : int { kPosition, kStatusword, kTorque, kErrorCode };

struct Figure {
	std::string_view name;
	std::string_view label;
	std::string_view unit;
	bool numeric;
};

constexpr Figure kXfFigures[] = {
	{ "wkc", "working counter", "", true },
	{ "wkc_expected", "expected working counter", "", true },
	{ "wkc_errors", "bus cycles with a wrong WKC", "", true },
	{ "rx_fifo", "RxFIFO frames", "frames", true },
	{ "tx_fifo", "TxFIFO frames", "frames", true },
	{ "pushed", "RxPDO frames pushed", "frames", true },
	{ "popped", "TxPDO frames popped", "frames", true },
	{ "error", "cycle error (errno)", "", false },
};
constexpr Figure kSkFigures[] = {
	{ "fifo_remaining", "FIFO space left", "entries", true },
	{ "fifo_full", "FIFO full count", "", true },
	{ "dropped", "commands dropped", "", true },
	{ "staged", "commands staged", "", true },
};
constexpr Figure kAxisFigures[] = {
	{ "position", "Position actual value", "inc", true },
	{ "statusword", "Statusword", "", false },
	{ "torque", "Torque actual value", "0.1% rated torque", true },
	{ "error_code", "Error code", "", false },
};

[[noreturn]] void bad(std::string_view text, const std::string &why)
{
	throw Error("scope signal " + quoted(text) + ": " + why, EINVAL);
}

template <std::size_t N>
std::optional<int> figureOf(const Figure (&table)[N], std::string_view name)
{
	for (std::size_t i = 0; i < N; i++)
		if (entryNameMatches(table[i].name, name))
			return static_cast<int>(i);
	return std::nullopt;
}

template <std::size_t N>
std::string figureList(const Figure (&table)[N])
{
	std::string r;
	for (const Figure &f : table)
		r += (r.empty() ? "" : ", ") + std::string(f.name);
	return r;
}

/// @p s as an unsigned number: decimal, or hex with 0x; nullopt otherwise.
std::optional<unsigned long> numberOf(std::string_view s, int base = 10)
{
	if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
		s.remove_prefix(2);
		base = 16;
	}
	unsigned long v = 0;
	const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, base);
	if (s.empty() || ec != std::errc() || p != s.data() + s.size())
		return std::nullopt;
	return v;
}

/// "N:REST" split; the slave checked against @p slaves.
std::pair<unsigned, std::string_view> slaveOf(std::string_view text, std::size_t slaves)
{
	const auto colon = text.find(':');
	const auto n = numberOf(text.substr(0, colon));
	if (!n)
		bad(text, quoted(text.substr(0, colon)) + " is not a slave position (N:NAME or N:INDEX:SUB)");
	if (*n >= slaves)
		bad(text, "slave " + std::to_string(*n) + " does not exist: the bus has " + std::to_string(slaves) +
				  " slaves" + (slaves ? " (0.." + std::to_string(slaves - 1) + ")" : std::string()));
	const std::string_view rest = text.substr(colon + 1);
	if (rest.empty())
		bad(text, "no entry after 'N:'");
	return { static_cast<unsigned>(*n), rest };
}

std::string entryText(const PdoEntryInfo &e)
{
	return hex(e.index, 4) + ":" + hex(e.sub, 2) + (e.name.empty() ? std::string() : " " + e.name);
}

} // namespace

struct Recorder::Source {
	Kind kind = Kind::Value;
	InputVar<std::int64_t> inS;
	InputVar<std::uint64_t> inU;
	OutputVar<std::int64_t> outS;
	OutputVar<std::uint64_t> outU;
	int field = 0;
	sk::Board *board = nullptr;
	unsigned slave = 0;
	const std::int64_t *value = nullptr;
};

Recorder::Recorder(std::size_t capacity) : capacity_(capacity)
{
	if (capacity < 1 || capacity > kMaxCapacity)
		throw Error("scope: a buffer of " + std::to_string(capacity) + " samples: 1.." +
				    std::to_string(kMaxCapacity),
			    EINVAL);
}

Recorder::~Recorder() = default;

void Recorder::checkIdle() const
{
	if (state_ != RecorderState::Idle)
		throw Error("scope: signals are added before arm()", EBUSY);
}

std::size_t Recorder::push(Source s, RecordedSignal sig)
{
	for (const RecordedSignal &o : signals_)
		if (o.name == sig.name)
			bad(sig.name, "added twice");
	sources_.push_back(s);
	signals_.push_back(std::move(sig));
	return signals_.size() - 1;
}

std::size_t Recorder::add(ProcessImage &image, std::string_view text)
{
	checkIdle();
	if (text.find(':') == std::string_view::npos) {
		const auto f = figureOf(kXfFigures, text);
		if (!f)
			bad(text, "no such cycle figure (" + figureList(kXfFigures) +
					  "; or N:NAME, N:INDEX:SUB for process data)");
		const Figure &fig = kXfFigures[*f];
		Source s;
		s.kind = Kind::Xf;
		s.field = *f;
		return push(s, { std::string(text), std::string(fig.label), std::string(fig.unit), fig.numeric });
	}
	const auto [slave, rest] = slaveOf(text, image.slaveCount());
	const SlavePdos &p = image.slave(slave);
	const PdoEntryInfo *found = nullptr;
	bool output = false;
	const auto colon = rest.find(':');
	if (colon != std::string_view::npos) {
		const auto index = numberOf(rest.substr(0, colon), 16);
		const auto sub = numberOf(rest.substr(colon + 1), 16);
		if (!index || !sub || *index > 0xFFFF || *sub > 0xFF)
			bad(text, quoted(rest) + " is not INDEX:SUB (hex, e.g. 0x6064:0)");
		for (const auto *list : { &p.inputs, &p.outputs }) {
			for (const PdoEntryInfo &e : *list)
				if (e.index != 0 && e.index == *index && e.sub == *sub && !found) {
					found = &e;
					output = list == &p.outputs;
				}
		}
	} else {
		for (const auto *list : { &p.inputs, &p.outputs }) {
			for (const PdoEntryInfo &e : *list)
				if (e.index != 0 && entryNameMatches(e.name, rest) && !found) {
					found = &e;
					output = list == &p.outputs;
				}
		}
	}
	if (!found) {
		std::string mapped;
		for (const auto *list : { &p.inputs, &p.outputs })
			for (const PdoEntryInfo &e : *list)
				if (e.index != 0)
					mapped += (mapped.empty() ? "" : ", ") + entryText(e);
		bad(text, "slave " + std::to_string(slave) + " has no mapped entry " + quoted(rest) + " (mapped: " +
				  (mapped.empty() ? std::string("none") : mapped) + ")");
	}
	const PdoEntryInfo &e = *found;
	const auto object = standardObject(e.index, e.sub);
	const bool whole = object && objectTypeSize(object->type) * 8 == e.bitLength;
	const bool isSigned = whole && objectTypeSigned(object->type);
	Source s;
	if (output) {
		s.kind = isSigned ? Kind::OutS : Kind::OutU;
		if (isSigned)
			s.outS = image.output<std::int64_t>(slave, e.index, e.sub);
		else
			s.outU = image.output<std::uint64_t>(slave, e.index, e.sub);
	} else {
		s.kind = isSigned ? Kind::InS : Kind::InU;
		if (isSigned)
			s.inS = image.input<std::int64_t>(slave, e.index, e.sub);
		else
			s.inU = image.input<std::uint64_t>(slave, e.index, e.sub);
	}
	RecordedSignal sig;
	sig.name = std::string(text);
	sig.label = "slave " + std::to_string(slave) + " " +
		    (e.name.empty() ? hex(e.index, 4) + ":" + hex(e.sub, 2) : e.name);
	sig.unit = whole ? std::string(object->unit) : std::string();
	// a standard object without a unit is a word of bits, a code or a mode
	sig.numeric = !(whole && object->unit.empty()) && e.bitLength > 1;
	return push(s, std::move(sig));
}

std::size_t Recorder::add(sk::Board &board, unsigned slaves, std::string_view text)
{
	checkIdle();
	if (text.find(':') == std::string_view::npos) {
		const auto f = figureOf(kSkFigures, text);
		if (!f)
			bad(text, "no such ECM-SK cycle figure (" + figureList(kSkFigures) + "; or N:" +
					  figureList(kAxisFigures) + " for a slave's feedback)");
		const Figure &fig = kSkFigures[*f];
		Source s;
		s.kind = Kind::Sk;
		s.field = *f;
		return push(s, { std::string(text), std::string(fig.label), std::string(fig.unit), fig.numeric });
	}
	const std::size_t count = slaves < board.maxSlaves() ? slaves : board.maxSlaves();
	const auto [slave, rest] = slaveOf(text, count);
	const auto f = figureOf(kAxisFigures, rest);
	if (!f)
		bad(text, "the ECM-SK's feedback slot has no " + quoted(rest) + " (" + figureList(kAxisFigures) + ")");
	const Figure &fig = kAxisFigures[*f];
	Source s;
	s.kind = Kind::SkAxis;
	s.field = *f;
	s.board = &board;
	s.slave = slave + 1; // the board's slots count from 1
	(void)board.drives().axis(s.slave); // checks the slot once, here
	return push(s, { std::string(text), "slave " + std::to_string(slave) + " " + std::string(fig.label),
			 std::string(fig.unit), fig.numeric });
}

std::size_t Recorder::addValue(std::string name, std::string unit, const std::int64_t *source, bool numeric)
{
	checkIdle();
	if (!source)
		bad(name, "no source");
	if (name.empty())
		throw Error("scope: a value needs a name", EINVAL);
	Source s;
	s.kind = Kind::Value;
	s.value = source;
	RecordedSignal sig{ name, name, std::move(unit), numeric };
	return push(s, std::move(sig));
}

void Recorder::arm(const RecorderTrigger &trigger, const RecorderStop &stop)
{
	if (signals_.empty())
		throw Error("scope: no signal to record", EINVAL);
	if (trigger.preSamples >= capacity_)
		throw Error("scope: " + std::to_string(trigger.preSamples) + " pre-trigger samples do not fit a buffer of " +
				    std::to_string(capacity_),
			    EINVAL);
	if (trigger.edge != TriggerEdge::Now) {
		std::size_t i = 0;
		while (i < signals_.size() && signals_[i].name != trigger.signal)
			i++;
		if (i == signals_.size())
			throw Error("scope trigger: " + quoted(trigger.signal) + " is not one of the recorded signals",
				    EINVAL);
		if (!signals_[i].numeric)
			throw Error("scope trigger: " + quoted(trigger.signal) + " (" + signals_[i].label +
					    ") is a word of bits or a code, not a number: no threshold on it",
				    EINVAL);
		if (!std::isfinite(trigger.level))
			throw Error("scope trigger: the level is not a finite number", EINVAL);
		triggerSignal_ = i;
	}
	values_.assign(capacity_ * signals_.size(), 0.0);
	times_.assign(capacity_, 0);
	trigger_ = trigger;
	stop_ = stop;
	head_ = count_ = 0;
	triggerSample_ = kNone;
	triggerTime_ = 0;
	sinceTrigger_ = 0;
	havePrevious_ = false;
	state_ = RecorderState::Armed;
}

RecorderState Recorder::sample(std::chrono::nanoseconds now) noexcept
{
	return record(now, nullptr, nullptr);
}

RecorderState Recorder::sample(std::chrono::nanoseconds now, const CycleResult &cycle) noexcept
{
	return record(now, &cycle, nullptr);
}

RecorderState Recorder::sample(std::chrono::nanoseconds now, const sk::CycleResult &cycle) noexcept
{
	return record(now, nullptr, &cycle);
}

namespace {

double xfFigure(const CycleResult &r, int field) noexcept
{
	switch (field) {
	case kWkc: return r.wkc;
	case kWkcExpected: return r.expectedWkc;
	case kWkcErrors: return r.wkcErrorCount;
	case kRxFifo: return r.rxFifoCount;
	case kTxFifo: return r.txFifoCount;
	case kPushed: return r.framesPushed;
	case kPopped: return r.framesPopped;
	default: return r.error;
	}
}

double skFigure(const sk::CycleResult &r, int field) noexcept
{
	switch (field) {
	case kFifoRemaining: return r.fifoRemaining;
	case kFifoFull: return r.fifoFull;
	case kDropped: return r.dropped;
	default: return r.staged;
	}
}

} // namespace

RecorderState Recorder::record(std::chrono::nanoseconds now, const CycleResult *xf, const sk::CycleResult *skr) noexcept
{
	if (state_ != RecorderState::Armed && state_ != RecorderState::Recording)
		return state_;
	const std::size_t n = signals_.size();
	const std::size_t at = slot(count_);
	double *v = &values_[at * n];
	constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
	for (std::size_t i = 0; i < n; i++) {
		const Source &s = sources_[i];
		switch (s.kind) {
		case Kind::InS: v[i] = static_cast<double>(s.inS.get()); break;
		case Kind::InU: v[i] = static_cast<double>(s.inU.get()); break;
		case Kind::OutS: v[i] = static_cast<double>(s.outS.get()); break;
		case Kind::OutU: v[i] = static_cast<double>(s.outU.get()); break;
		case Kind::Xf: v[i] = xf ? xfFigure(*xf, s.field) : kNan; break;
		case Kind::Sk: v[i] = skr ? skFigure(*skr, s.field) : kNan; break;
		case Kind::SkAxis: {
			// the slot was checked by add(): axis() neither throws nor allocates
			const sk::AxisStatus a = s.board->drives().axis(s.slave);
			v[i] = s.field == kPosition     ? a.position
			       : s.field == kStatusword ? a.statusword
			       : s.field == kTorque     ? a.torque
							: a.errorCode;
			break;
		}
		case Kind::Value: v[i] = static_cast<double>(*s.value); break;
		}
	}
	times_[at] = now.count();
	count_++;
	if (state_ == RecorderState::Armed) {
		bool fire = trigger_.edge == TriggerEdge::Now;
		const double x = v[triggerSignal_];
		if (!fire && havePrevious_ && !std::isnan(x) && !std::isnan(previous_))
			fire = trigger_.edge == TriggerEdge::Rising ? previous_ < trigger_.level && x >= trigger_.level
								    : previous_ > trigger_.level && x <= trigger_.level;
		previous_ = x;
		havePrevious_ = true;
		if (fire) {
			state_ = RecorderState::Recording;
			triggerSample_ = count_ - 1;
			triggerTime_ = now.count();
		} else if (count_ > trigger_.preSamples) {
			head_ = (head_ + 1) % capacity_; // the oldest pre-trigger sample goes
			count_--;
			return state_;
		} else {
			return state_;
		}
	}
	sinceTrigger_++;
	if (count_ == capacity_ || (stop_.cycles && sinceTrigger_ >= stop_.cycles) ||
	    (stop_.time.count() && now.count() - triggerTime_ >= stop_.time.count()))
		state_ = RecorderState::Done;
	return state_;
}

void Recorder::finish() noexcept
{
	if (state_ == RecorderState::Armed || state_ == RecorderState::Recording)
		state_ = RecorderState::Done;
}

std::chrono::nanoseconds Recorder::time(std::size_t i) const noexcept
{
	if (i >= count_)
		return std::chrono::nanoseconds(0);
	const std::int64_t origin = triggerSample_ != kNone ? triggerTime_ : times_[slot(0)];
	return std::chrono::nanoseconds(times_[slot(i)] - origin);
}

double Recorder::value(std::size_t i, std::size_t signal) const noexcept
{
	if (i >= count_ || signal >= signals_.size())
		return std::numeric_limits<double>::quiet_NaN();
	return values_[slot(i) * signals_.size() + signal];
}

std::size_t Recorder::triggerIndex() const noexcept
{
	return triggerSample_ != kNone ? triggerSample_ : count_;
}

} // namespace ecmxf
