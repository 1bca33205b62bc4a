// SPDX-License-Identifier: MIT
// ecmxf-demo --plot DIR (ecmxf-demo-plot.hpp).
#include "ecmxf-demo-plot.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include <ecmxf/error.hpp>
#include <ecmxf/scope/plot.hpp>

namespace {

[[noreturn]] void fail(const std::string &dir, const std::string &what, int err)
{
	throw ecmxf::Error("--plot " + dir + ": " + what + std::strerror(err), err);
}

} // namespace

void demoPlotDir(const std::string &dir)
{
	if (dir.empty())
		throw ecmxf::Error("--plot: an empty directory name", EINVAL);
	struct stat st{};
	if (::stat(dir.c_str(), &st) != 0) {
		if (errno != ENOENT)
			fail(dir, "", errno);
		if (::mkdir(dir.c_str(), 0777) != 0)
			fail(dir, "cannot make the directory: ", errno);
		return;
	}
	if (!S_ISDIR(st.st_mode))
		fail(dir, "", ENOTDIR);
	if (::access(dir.c_str(), W_OK | X_OK) != 0)
		fail(dir, "", errno);
}

std::vector<std::string> writeDemoPlots(const std::string &dir, const std::vector<DemoAxisPlot> &plots)
{
	// (hidden name, final name) of every file, in the order written
	std::vector<std::pair<std::string, std::string>> files;
	try {
		for (std::size_t n = 0; n < plots.size(); n++) {
			const std::string base = "axis" + std::to_string(n);
			ecmxf::SvgOptions so;
			so.title = plots[n].title;
			files.emplace_back(dir + "/." + base + ".csv.new", dir + "/" + base + ".csv");
			ecmxf::writeCsv(*plots[n].recorder, files.back().first);
			files.emplace_back(dir + "/." + base + ".svg.new", dir + "/" + base + ".svg");
			ecmxf::writeSvg(*plots[n].recorder, files.back().first, so);
		}
		for (const auto &[from, to] : files)
			if (std::rename(from.c_str(), to.c_str()) != 0)
				throw ecmxf::Error("writing " + to + ": " + std::strerror(errno), errno);
	} catch (...) {
		for (const auto &f : files)
			(void)std::remove(f.first.c_str());
		throw;
	}
	std::vector<std::string> written;
	for (const auto &f : files)
		written.push_back(f.second);
	return written;
}
