// SPDX-License-Identifier: MIT
// ProcessImage: the output and input frames of a bus and the lookups
// behind its typed accessors (include/ecmxf/pdo/process_image.hpp,
// Documentation/process-data.rst).

#include <ecmxf/error.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include <cerrno>
#include <cstdio>
#include <string>
#include <utility>

namespace ecmxf {

namespace {

/// "0x6040:00"
std::string objectName(std::uint16_t index, std::uint8_t sub)
{
	char buf[16];
	std::snprintf(buf, sizeof(buf), "0x%04X:%02X", index, sub);
	return buf;
}

/// "output 0x6040:00 (Controlword) of slave 0"
std::string describe(bool output, std::size_t position, const PdoEntryInfo &e)
{
	std::string s(output ? "output " : "input ");
	s.append(objectName(e.index, e.sub));
	if (!e.name.empty())
		s.append(" (").append(e.name).append(")");
	s.append(" of slave ").append(std::to_string(position));
	return s;
}

constexpr const char *kWhere = "ProcessImage: ";

/// "ProcessImage: slave N maps no output object 0x6040:00", or "... named
/// \"<name>\"" when @p name is given.
[[noreturn]] void throwNotMapped(bool output, std::size_t position, std::uint16_t index, std::uint8_t sub,
				 std::string_view name)
{
	std::string msg(kWhere);
	msg.append("slave ").append(std::to_string(position)).append(output ? " maps no output object " : " maps no input object ");
	if (name.empty())
		msg.append(objectName(index, sub));
	else
		msg.append("named \"").append(name).append("\"");
	throw Error(msg, EINVAL);
}

} // namespace

ProcessImage::ProcessImage(std::vector<SlavePdos> slaves) : slaves_(std::move(slaves))
{
	std::size_t outBytes = 0, inBytes = 0;
	for (std::size_t pos = 0; pos < slaves_.size(); pos++) {
		const SlavePdos &s = slaves_[pos];
		for (int dir = 0; dir < 2; dir++) {
			const bool output = dir == 0;
			const auto &entries = output ? s.outputs : s.inputs;
			const std::uint64_t limit = std::uint64_t{ output ? s.outputBytes : s.inputBytes } * 8;
			for (const PdoEntryInfo &e : entries) {
				if (e.bitLength < 1 || e.bitLength > 64)
					throw Error(std::string(kWhere) + describe(output, pos, e) + " is " +
							    std::to_string(e.bitLength) +
							    " bits long; entries are 1..64 bits",
						    EINVAL);
				if (std::uint64_t{ e.bitOffset } + e.bitLength > limit) {
					std::string msg(kWhere);
					msg.append(describe(output, pos, e))
						.append(" at bits ")
						.append(std::to_string(e.bitOffset))
						.append("..")
						.append(std::to_string(std::uint64_t{ e.bitOffset } + e.bitLength - 1))
						.append(" lies beyond the slave's ")
						.append(std::to_string(output ? s.outputBytes : s.inputBytes))
						.append(output ? " output bytes" : " input bytes");
					throw Error(msg, EINVAL);
				}
			}
		}
		outOffset_.push_back(outBytes);
		inOffset_.push_back(inBytes);
		outBytes += s.outputBytes;
		inBytes += s.inputBytes;
	}
	out_.assign(outBytes, 0);
	in_.assign(inBytes, 0);
}

ProcessImage::ProcessImage(ProcessImage &&) noexcept = default;
ProcessImage &ProcessImage::operator=(ProcessImage &&) noexcept = default;
ProcessImage::~ProcessImage() = default;

void ProcessImage::checkPosition(std::size_t position) const
{
	if (position >= slaves_.size()) {
		std::string msg(kWhere);
		msg.append("there is no slave ").append(std::to_string(position)).append(" (the image has ");
		if (slaves_.empty())
			msg.append("no slaves)");
		else
			msg.append(std::to_string(slaves_.size()))
				.append(slaves_.size() == 1 ? " slave, position 0)" : " slaves, positions 0..")
				.append(slaves_.size() == 1 ? "" : std::to_string(slaves_.size() - 1) + ")");
		throw Error(msg, EINVAL);
	}
}

const SlavePdos &ProcessImage::slave(std::size_t position) const
{
	checkPosition(position);
	return slaves_[position];
}

std::size_t ProcessImage::outputOffset(std::size_t position) const
{
	checkPosition(position);
	return outOffset_[position];
}

std::size_t ProcessImage::inputOffset(std::size_t position) const
{
	checkPosition(position);
	return inOffset_[position];
}

std::span<std::uint8_t> ProcessImage::slaveOutputs(std::size_t position)
{
	checkPosition(position);
	return std::span<std::uint8_t>(out_).subspan(outOffset_[position], slaves_[position].outputBytes);
}

std::span<const std::uint8_t> ProcessImage::slaveInputs(std::size_t position) const
{
	checkPosition(position);
	return std::span<const std::uint8_t>(in_).subspan(inOffset_[position], slaves_[position].inputBytes);
}

const PdoEntryInfo *ProcessImage::find(bool output, std::size_t position, std::uint16_t index, std::uint8_t sub,
				       std::string_view name) const
{
	checkPosition(position);
	const auto &entries = output ? slaves_[position].outputs : slaves_[position].inputs;
	for (const PdoEntryInfo &e : entries) {
		if (e.index == 0)
			continue; // padding
		if (name.empty() ? (e.index == index && e.sub == sub) : e.name == name)
			return &e;
	}
	return nullptr;
}

const PdoEntryInfo &ProcessImage::outputEntry(std::size_t position, std::uint16_t index, std::uint8_t sub) const
{
	if (const PdoEntryInfo *e = find(true, position, index, sub, {}))
		return *e;
	throwNotMapped(true, position, index, sub, {});
}

const PdoEntryInfo &ProcessImage::inputEntry(std::size_t position, std::uint16_t index, std::uint8_t sub) const
{
	if (const PdoEntryInfo *e = find(false, position, index, sub, {}))
		return *e;
	throwNotMapped(false, position, index, sub, {});
}

ProcessImage::Place ProcessImage::place(bool output, std::size_t position, std::uint16_t index, std::uint8_t sub,
					std::string_view name, TypeTraits t) const
{
	const PdoEntryInfo *e = find(output, position, index, sub, name);
	if (!e)
		throwNotMapped(output, position, index, sub, name);
	const unsigned bits = e->bitLength;
	std::string problem;
	if (t.kind == 1 && bits != 1)
		problem = "bool needs a 1-bit entry";
	else if (t.kind == 2 && bits != t.bits)
		problem = "a " + std::to_string(t.bits) + "-bit floating-point type needs exactly " +
			  std::to_string(t.bits) + " bits";
	else if (t.kind == 0 && bits > t.bits)
		problem = "it does not fit a " + std::to_string(t.bits) + "-bit integer type";
	if (!problem.empty())
		throw Error(std::string(kWhere) + describe(output, position, *e) + " is " + std::to_string(bits) +
				    " bits; " + problem,
			    EINVAL);
	const std::size_t frameBits = 8 * (output ? outOffset_[position] : inOffset_[position]);
	return Place{ static_cast<std::uint32_t>(frameBits + e->bitOffset), bits };
}

} // namespace ecmxf
