// SPDX-License-Identifier: MIT
/*
 * ecmxf-util foe_read / foe_write - files to and from a slave by FoE
 * (through the chip's staging flash).
 */
#include "ecmxf-util.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/error.hpp>

namespace ecmxf_util {

const char *const kFoeReadHelp =
	"Usage: ecmxf-util [global options] foe_read -p N [-o OUTFILE] [--password P] NAME\n"
	"\n"
	"Read the file NAME from the slave at position N by FoE (FOE_FUNC_REQ:\n"
	"the chip uploads it into its staging flash, then the flash is read) and\n"
	"write it to OUTFILE, or to standard output without -o.\n"
	"\n"
	"A fresh bus is brought up to PRE-OP first (FoE needs a mailbox); a bus\n"
	"that is already up is used as it is. A refused transfer fails with the\n"
	"FoE error code and its text.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  -o, --output FILE where to write the file (default, and '-': standard\n"
	"                    output)\n"
	"  --password P      the FoE password (32 bits, default 0)\n"
	"  -h, --help        show this help\n";

const char *const kFoeWriteHelp =
	"Usage: ecmxf-util [global options] foe_write -p N [-o NAME] [--password P] FILE\n"
	"\n"
	"Write the local FILE to the slave at position N by FoE (the chip's\n"
	"staging flash is written, then FOE_FUNC_REQ downloads it), as the file\n"
	"NAME (default: FILE's base name). Many slaves take firmware files in BOOT\n"
	"only: request it first with 'ecmxf-util states -p N BOOT' (on a real\n"
	"device; the simulator starts from power-on at every call).\n"
	"\n"
	"A fresh bus is brought up to PRE-OP first; a bus that is already up is\n"
	"used as it is. A refused transfer fails with the FoE error code and its\n"
	"text. Prints nothing on success. FILE may hold at most the chip's FoE\n"
	"staging flash, 262144 bytes; a larger one (or /dev/zero) fails.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  -o, --output NAME the file name on the slave\n"
	"  --password P      the FoE password (32 bits, default 0)\n"
	"  -h, --help        show this help\n";

namespace {

ecmxf::FoeOptions foeOptions(std::string_view cmd, const std::optional<std::string> &password)
{
	ecmxf::FoeOptions o;
	if (password)
		o.password = static_cast<std::uint32_t>(parseUnsigned(cmd, "--password", *password, 0xFFFFFFFFu));
	return o;
}

} // namespace

int cmdFoeRead(Globals &g, const Args &args)
{
	std::optional<std::string> posText, out, password;
	const auto pos = parseArgs("foe_read", args, g, kFoeReadHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "-o", "--output", nullptr, &out },
				     { "", "--password", nullptr, &password } });
	if (!pos)
		return 0;
	if (pos->size() != 1)
		throw UsageError(pos->empty() ? "foe_read: which file? (foe_read -p N NAME)"
					      : "foe_read: one NAME only (try 'ecmxf-util foe_read --help')");
	std::uint8_t position = parsePosition("foe_read", posText);
	const ecmxf::FoeOptions opt = foeOptions("foe_read", password);

	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::PreOp));
	const std::vector<std::uint8_t> data = dev->slaves().foeRead(position, pos->front(), opt);
	if (out && *out != "-") { // -o -: standard output, as without -o
		std::ofstream f(*out, std::ios::binary | std::ios::trunc);
		if (!f)
			throw ecmxf::Error("cannot create \"" + *out + "\": " + std::strerror(errno), errno);
		f.write(reinterpret_cast<const char *>(data.data()), static_cast<std::streamsize>(data.size()));
		f.close();
		if (!f)
			throw ecmxf::Error("cannot write \"" + *out + "\"", EIO);
		return 0;
	}
	if (!data.empty() && std::fwrite(data.data(), 1, data.size(), stdout) != data.size())
		throw ecmxf::Error("cannot write to standard output", EIO);
	return 0;
}

int cmdFoeWrite(Globals &g, const Args &args)
{
	std::optional<std::string> posText, name, password;
	const auto pos = parseArgs("foe_write", args, g, kFoeWriteHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "-o", "--output", nullptr, &name },
				     { "", "--password", nullptr, &password } });
	if (!pos)
		return 0;
	if (pos->size() != 1)
		throw UsageError(pos->empty() ? "foe_write: which file? (foe_write -p N FILE)"
					      : "foe_write: one FILE only (try 'ecmxf-util foe_write --help')");
	std::uint8_t position = parsePosition("foe_write", posText);
	const ecmxf::FoeOptions opt = foeOptions("foe_write", password);
	const std::string &file = pos->front();
	std::error_code ec;
	if (std::filesystem::is_directory(file, ec))
		throw ecmxf::Error("\"" + file + "\" is a directory, not a file", EISDIR);
	std::ifstream f(file, std::ios::binary);
	if (!f)
		throw ecmxf::Error("cannot open \"" + file + "\": " + std::strerror(errno), errno);
	// The file goes through the chip's staging flash: no more than it
	// holds is read (a FIFO or /dev/zero would otherwise be read without
	// end).
	std::vector<std::uint8_t> data;
	char buf[65536];
	while (f) {
		f.read(buf, sizeof(buf));
		const auto n = static_cast<std::size_t>(f.gcount());
		if (data.size() + n > ecmxf::kFoeFlashSize)
			throw ecmxf::Error("\"" + file + "\" is larger than the chip's FoE staging flash (" +
						   std::to_string(ecmxf::kFoeFlashSize) + " bytes)",
					   EFBIG);
		data.insert(data.end(), buf, buf + n);
	}
	if (f.bad())
		throw ecmxf::Error("cannot read \"" + file + "\"", EIO);
	const std::string remote = name ? *name : std::filesystem::path(file).filename().string();

	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::PreOp));
	Progress progress(g, "foe_write: staging " + remote, "bytes");
	dev->slaves().foeWrite(position, remote, data, opt,
			       [&](std::size_t done, std::size_t total) { progress(done, total); });
	return 0;
}

} // namespace ecmxf_util
