// SPDX-License-Identifier: MIT
// A signal's samples as braille text (include/ecmxf/scope/terminal.hpp):
// one drawing over a span of values; the Recorder overload copies a
// signal's latest samples out and draws them with it.

#include <ecmxf/scope/terminal.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>

#include <ecmxf/error.hpp>

namespace ecmxf {

namespace {

/// The braille dot bit of (column 0..1, row 0..3 from the top) in a cell:
/// dots 1 2 3 7 down the left, 4 5 6 8 down the right (Unicode's order).
constexpr std::uint8_t kDot[2][4] = { { 0x01, 0x02, 0x04, 0x40 }, { 0x08, 0x10, 0x20, 0x80 } };

/// U+2800 + @p bits as UTF-8 (three bytes: E2 A0..A3 80..BF).
void appendBraille(std::string &s, std::uint8_t bits)
{
	const unsigned cp = 0x2800u + bits;
	s += static_cast<char>(0xE0 | (cp >> 12));
	s += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
	s += static_cast<char>(0x80 | (cp & 0x3F));
}

} // namespace

std::vector<std::string> terminalText(std::span<const double> values, unsigned width, unsigned height,
				      TerminalRange *range)
{
	if (width < 1 || width > 1000)
		throw Error("terminalText: width " + std::to_string(width) + ": 1..1000 cells", EINVAL);
	if (height < 1 || height > 100)
		throw Error("terminalText: height " + std::to_string(height) + ": 1..100 rows", EINVAL);
	const std::size_t columns = 2 * std::size_t{ width };
	if (values.size() > columns)
		values = values.last(columns); // the latest, one per dot column
	double lo = NAN, hi = NAN;
	for (const double v : values) {
		if (std::isnan(v))
			continue;
		lo = std::isnan(lo) ? v : std::min(lo, v);
		hi = std::isnan(hi) ? v : std::max(hi, v);
	}
	if (range)
		*range = { lo, hi };
	const unsigned dotRows = 4 * height;
	std::vector<std::uint8_t> cells(std::size_t{ width } * height, 0);
	for (std::size_t x = 0; x < values.size(); x++) {
		const double v = values[x];
		if (std::isnan(v))
			continue;
		const unsigned up = hi > lo ? static_cast<unsigned>(std::lround((v - lo) / (hi - lo) * (dotRows - 1)))
					    : (dotRows - 1) / 2;
		const unsigned row = dotRows - 1 - std::min(up, dotRows - 1); // from the top
		cells[row / 4 * width + x / 2] |= kDot[x % 2][row % 4];
	}
	std::vector<std::string> rows(height);
	for (unsigned r = 0; r < height; r++) {
		rows[r].reserve(3 * std::size_t{ width });
		for (unsigned c = 0; c < width; c++)
			appendBraille(rows[r], cells[r * width + c]);
	}
	return rows;
}

std::vector<std::string> terminalText(const Recorder &rec, std::size_t signal, unsigned width, unsigned height,
				      TerminalRange *range)
{
	if (signal >= rec.signals().size())
		throw Error("terminalText: signal " + std::to_string(signal) + " does not exist: the recorder has " +
				    std::to_string(rec.signals().size()),
			    EINVAL);
	// the latest samples the drawing can show (at most 2 x width: a width
	// out of range copies little and is refused by the drawing)
	const std::size_t n = std::min(rec.size(), 2 * std::size_t{ width });
	std::vector<double> values(n);
	for (std::size_t i = 0; i < n; i++)
		values[i] = rec.value(rec.size() - n + i, signal);
	return terminalText(values, width, height, range);
}

} // namespace ecmxf
