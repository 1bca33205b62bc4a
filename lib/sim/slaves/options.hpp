// SPDX-License-Identifier: MIT
//
// options.hpp - reads the key=value options of a network file's "slave"
// line for one model, and rejects unknown ones.

#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include "slaves/factory.hpp"

namespace ecmxf::sim::slaves {

class OptionReader
{
public:
	OptionReader(std::string type, const SlaveOptions &opts) : type_(std::move(type)), opts_(opts)
	{
	}

	/// An integer option in [lo, hi] (decimal, or 0x hex; a leading '-'
	/// allowed). Throws std::invalid_argument naming the option.
	std::optional<std::int64_t> integer(const std::string &key, std::int64_t lo,
					    std::int64_t hi);
	/// A boolean option: 1/0, true/false, yes/no, on/off.
	std::optional<bool> boolean(const std::string &key);
	std::optional<std::string> string(const std::string &key);

	/// The options every model takes: serial (default: position + 1), name
	/// (default: @p defaultName) and alias (default 0), written into
	/// @p identity and @p alias.
	void common(unsigned position, Identity &identity, std::uint16_t &alias,
		    const std::string &defaultName);

	/// The model type the options are for.
	[[nodiscard]] const std::string &type() const { return type_; }

	/// Throws std::invalid_argument if an option was not read by the model,
	/// listing the ones it knows.
	void finish() const;

private:
	std::string type_;
	const SlaveOptions &opts_;
	std::set<std::string> known_;
};

} // namespace ecmxf::sim::slaves
