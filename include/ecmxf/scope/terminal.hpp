// SPDX-License-Identifier: MIT
/**
 * @file terminal.hpp
 * @brief A signal's samples drawn as text for a terminal: Unicode braille
 *        dots (U+2800..U+28FF), 2 x 4 dots a character cell.
 *
 * terminalText(values, width, height) draws the latest 2 x @p width of
 * @p values (fewer: from the left, the rest blank), one sample per dot
 * column, oldest on the left, in @p height rows of @p width cells.
 * terminalText(recorder, signal, width, height) is the same over a
 * Recorder's signal @p signal: its latest 2 x @p width samples copied out,
 * then drawn by the first. The dot rows (4 x height) span the drawn samples' minimum
 * (bottom row) to maximum (top row): a value v goes to dot row
 * round((v - min) / (max - min) x (4 x height - 1)) counted from the
 * bottom; all drawn values equal: the dot row (4 x height - 1) / 2
 * (rounded down). A figure not sampled (NaN) draws no dot. A cell without
 * a dot is U+2800 (blank braille), so every row is @p width characters.
 *
 * A pure function of the samples: what `ecmxf-util scope`'s live view
 * draws ~10 times a second (Documentation/scope.rst), testable by rows.
 * It allocates: not for the cyclic path. A live view draws in a thread of
 * its own from a RecorderSnapshot (<ecmxf/scope/snapshot.hpp>) that the
 * cycling thread copied: the span overload takes its values(signal).
 */
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/scope/recorder.hpp>

namespace ecmxf {

/// The drawn samples' range (NaN, NaN when none was sampled).
struct TerminalRange {
	double min = 0, max = 0;
};

/// @p height rows (UTF-8) of @p width braille cells drawing the last
/// 2 x @p width of @p values, oldest first (file comment; NaN: no dot).
/// EINVAL: @p width not 1..1000, @p height not 1..100. @p range, when
/// given, gets the drawn range.
[[nodiscard]] ECMXF_EXPORT std::vector<std::string> terminalText(std::span<const double> values, unsigned width,
								 unsigned height, TerminalRange *range = nullptr);

/// The same of the recorder's signal @p signal (its latest 2 x @p width
/// samples). EINVAL: @p signal not one of the recorder's, @p width not
/// 1..1000, @p height not 1..100.
[[nodiscard]] ECMXF_EXPORT std::vector<std::string> terminalText(const Recorder &recorder, std::size_t signal,
								 unsigned width, unsigned height,
								 TerminalRange *range = nullptr);

} // namespace ecmxf
