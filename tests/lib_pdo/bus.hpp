// SPDX-License-Identifier: MIT
//
// A simulated bus for the process-data tests: a Device over a SimChannel
// (or over another channel to a simulated chip),
// brought up with raw Device::command() calls (ECAT_INIT_OP, ECAT_STATE_SET
// PRE-OP, SAFE-OP, OP), and the PDO mapping of the default network written
// by hand from the models' default maps (EST-584 manual 5.4.1, dio.cpp).
// It uses no Catch macros, so the allocation test can use it too.

#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/model/pdo_mapping.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/link.hpp>

namespace pdotest {

// command codes (manual ver. 050)
constexpr std::uint8_t kInitOp = 1;
constexpr std::uint8_t kStateSet = 12;
constexpr std::uint8_t kInfoUpdate = 0;
constexpr std::uint8_t kSpiReconfig = 23;
constexpr std::uint8_t kIntSetEnable = 58;

constexpr std::uint8_t kPreOp = 2;
constexpr std::uint8_t kSafeOp = 4;
constexpr std::uint8_t kOp = 8;

inline std::string network(const char *file)
{
	return std::string(ECMXF_PDO_NETWORK_DIR) + "/" + file;
}

inline std::string bundled(const char *file)
{
	return std::string(ECMXF_TEST_NETWORK_DIR) + "/" + file;
}

inline void put16(std::vector<std::uint8_t> &d, std::uint16_t v)
{
	d.push_back(static_cast<std::uint8_t>(v));
	d.push_back(static_cast<std::uint8_t>(v >> 8));
}

inline void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	for (unsigned i = 0; i < 4; i++)
		d.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

struct Bus {
	ecmxf::SimChannel *sim = nullptr;
	std::unique_ptr<ecmxf::Device> dev;

	/// A bus with the network in @p networkFile (empty: the default one).
	explicit Bus(const std::string &networkFile = {})
	{
		auto t = std::make_unique<ecmxf::SimChannel>(networkFile);
		sim = t.get();
		dev = std::make_unique<ecmxf::Device>(std::move(t));
	}

	/// A bus over @p device whose chip is @p chip (e.g. a spidev channel
	/// over a fake backend played by it).
	Bus(std::unique_ptr<ecmxf::Device> device, ecmxf::sim::Chip &chip) : dev(std::move(device)), chip_(&chip) {}

	ecmxf::sim::Chip &chip() { return chip_ ? *chip_ : sim->chip(); }

	ecmxf::Response cmd(std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0)
	{
		ecmxf::Command c;
		c.code = code;
		c.param = param;
		c.data[0] = d0;
		return dev->command(c);
	}

	/// The current response header (a fresh INFO_UPDATE_OP).
	ecmxf::ResponseHeader info() { return cmd(kInfoUpdate).header; }

	/// ECAT_INIT_OP: 0xFF, 0x81, AssignActivate 0x0300, SYNC0 @p sync0Ns,
	/// SYNC1 0, shift 0.
	void init(std::uint32_t sync0Ns = 1'000'000)
	{
		ecmxf::Command c;
		c.code = kInitOp;
		c.payload = { 0xFF, 0x81 };
		put16(c.payload, 0x0300);
		put32(c.payload, sync0Ns);
		put32(c.payload, 0);
		put32(c.payload, 0);
		(void)dev->command(c);
	}

	void state(std::uint8_t st) { (void)cmd(kStateSet, 0xFF, st); }

	/// INIT_OP, then PRE-OP, SAFE-OP, OP for all slaves.
	void toOp(std::uint32_t sync0Ns = 1'000'000)
	{
		init(sync0Ns);
		state(kPreOp);
		state(kSafeOp);
		state(kOp);
		if (info().ecatState != kOp)
			throw std::runtime_error("the bus did not reach OP");
	}

	/// SPI_RECONFIG_OP: a data section of @p size bytes (the engine then
	/// holds off for 100 ms).
	void dataSize(std::uint16_t size)
	{
		ecmxf::Command c;
		c.code = kSpiReconfig;
		c.len = size;
		(void)dev->command(c);
	}

	void run(std::chrono::nanoseconds dt) { dev->link().sleepFor(dt); }

	template <class Model>
	Model &model(std::size_t position)
	{
		return dynamic_cast<Model &>(chip().network().at(position));
	}

private:
	ecmxf::sim::Chip *chip_ = nullptr;
};

inline ecmxf::PdoEntryInfo entry(std::uint16_t pdo, std::uint16_t index, std::uint8_t sub, std::uint8_t bits,
				 std::uint32_t offset, const char *name = "")
{
	ecmxf::PdoEntryInfo e;
	e.pdo = pdo;
	e.index = index;
	e.sub = sub;
	e.bitLength = bits;
	e.bitOffset = offset;
	e.name = name;
	return e;
}

/// EST-584 default maps: RxPDO 0x1600 = 0x6040 (16), 0x607A (32), 0x60B0
/// (32), 0x60B8 (16): 12 bytes; TxPDO 0x1A00 = 0x6041 (16), 0x6061 (8),
/// 0x6064 (32), 0x60B9 (16), 0x60BA (32), 0x60FD (32): 17 bytes.
inline ecmxf::SlavePdos est584()
{
	ecmxf::SlavePdos s;
	s.outputs = { entry(0x1600, 0x6040, 0, 16, 0, "Controlword"),
		      entry(0x1600, 0x607A, 0, 32, 16, "Target position"),
		      entry(0x1600, 0x60B0, 0, 32, 48, "Position offset"),
		      entry(0x1600, 0x60B8, 0, 16, 80, "Touch probe function") };
	s.inputs = { entry(0x1A00, 0x6041, 0, 16, 0, "Statusword"),
		     entry(0x1A00, 0x6061, 0, 8, 16, "Modes of operation display"),
		     entry(0x1A00, 0x6064, 0, 32, 24, "Position actual value"),
		     entry(0x1A00, 0x60B9, 0, 16, 56, "Touch probe status"),
		     entry(0x1A00, 0x60BA, 0, 32, 72, "Touch probe 1 positive edge"),
		     entry(0x1A00, 0x60FD, 0, 32, 104, "Digital inputs") };
	s.outputBytes = 12;
	s.inputBytes = 17;
	return s;
}

/// The digital I/O terminal of the default network, one byte each way,
/// seen as eight 1-bit channels (the chip moves bytes; how the host names
/// the bits is its own business): outputs 0x7000:01..08, inputs
/// 0x6000:01..08.
inline ecmxf::SlavePdos dioBits()
{
	ecmxf::SlavePdos s;
	for (std::uint8_t i = 0; i < 8; i++) {
		s.outputs.push_back(entry(0x1600, 0x7000, static_cast<std::uint8_t>(i + 1), 1, i));
		s.inputs.push_back(entry(0x1A00, 0x6000, static_cast<std::uint8_t>(i + 1), 1, i));
	}
	s.outputBytes = 1;
	s.inputBytes = 1;
	return s;
}

/// A digital I/O terminal of @p bytes each way as one value of 8 x @p bytes
/// bits: 0x7000:01 / 0x6000:01.
inline ecmxf::SlavePdos dioWord(std::uint8_t bytes)
{
	ecmxf::SlavePdos s;
	const auto bits = static_cast<std::uint8_t>(8 * bytes);
	s.outputs.push_back(entry(0x1600, 0x7000, 1, bits, 0, "Outputs"));
	s.inputs.push_back(entry(0x1A00, 0x6000, 1, bits, 0, "Inputs"));
	s.outputBytes = bytes;
	s.inputBytes = bytes;
	return s;
}

/// The default network: 2 x EST-584 + dio (25 output, 35 input bytes).
inline std::vector<ecmxf::SlavePdos> defaultPdos()
{
	return { est584(), est584(), dioBits() };
}

/// loopback.net: 2 x EST-584 + dio 4/4 (28 output, 38 input bytes).
inline std::vector<ecmxf::SlavePdos> loopbackPdos()
{
	return { est584(), est584(), dioWord(4) };
}

/// What the sequence counters a run echoed back show, one per input frame:
/// zeros (the pre-loaded outputs), then 1, 2, 3... each value once, or
/// repeated while the RxFIFO is first filled; never a gap or a step back.
struct Sequence {
	bool found = false;      ///< a non-zero value came
	std::uint32_t first = 0; ///< the first non-zero value
	/// the first frame that is neither the value before nor one more
	/// (seen.size(): none); the counts stop there
	std::size_t badFrame = 0;
	std::size_t distinct = 0; ///< distinct values from the first non-zero one
	int repeated = 0;         ///< of those, values above @p settled that came more than once
};

inline Sequence sequenceOf(const std::vector<std::uint32_t> &seen, std::uint32_t settled)
{
	Sequence q;
	std::size_t k = 0;
	while (k < seen.size() && seen[k] == 0)
		k++;
	q.badFrame = seen.size();
	if (k == seen.size())
		return q;
	q.found = true;
	q.first = seen[k];
	std::map<std::uint32_t, int> count;
	for (std::size_t j = k; j < seen.size(); j++) {
		if (j > k && seen[j] != seen[j - 1] && seen[j] != seen[j - 1] + 1) {
			q.badFrame = j;
			break;
		}
		count[seen[j]]++;
	}
	q.distinct = count.size();
	for (const auto &[value, n] : count)
		if (value > settled && n != 1)
			q.repeated++;
	return q;
}

} // namespace pdotest
