// SPDX-License-Identifier: MIT
// Progress of long transfers (issue 29): foe_write and sii_write show
// bytes/words done, rate and time left on stderr with --progress (or on a
// terminal), nothing when stdout is not a terminal; foe_write refuses a
// slave in INIT before staging the file.

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "cli_run.hpp"
#include "common/sim_server.hpp"

using Catch::Matchers::Contains;
using clitest::run;

namespace {

const std::string kServoNet = std::string(ECMXF_TEST_NETWORK_DIR) + "/servo-io.net";

struct File {
	std::string path;
	explicit File(const ecmxftest::TempDir &d, const std::string &name, std::size_t size)
		: path(d.path + "/" + name)
	{
		std::ofstream f(path, std::ios::binary);
		f << std::string(size, 'x');
	}
};

} // namespace

TEST_CASE("progress: foe_write --progress shows the staging, silent into a pipe", "[cli][progress]")
{
	ecmxftest::TempDir dir;
	const File fw(dir, "firmware.bin", 20000);
	// the servo's firmware.bin is taken in BOOT only: the download fails
	// after the staging, which the progress shows done
	auto r = run("-d sim:" + kServoNet + " --progress foe_write -p 0 " + fw.path);
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("foe_write: staging firmware.bin: 20000/20000 bytes (100%)"));
	CHECK_THAT(r.err, Contains(" bytes/s\n"));
	r = run("-d sim:" + kServoNet + " foe_write -p 0 " + fw.path);
	CHECK(r.status == 1);
	CHECK_THAT(r.err, !Contains("staging"));
}

TEST_CASE("progress: sii_write --progress counts the words, silent into a pipe", "[cli][progress]")
{
	ecmxftest::TempDir dir;
	const std::string img = dir.path + "/sii.bin";
	REQUIRE(run("sii_read -p 0 >" + img).status == 0);
	const auto words = std::filesystem::file_size(img) / 2;
	auto r = run("--progress sii_write -p 1 " + img);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.err, Contains("sii_write: " + std::to_string(words) + "/" + std::to_string(words) +
				   " words (100%)"));
	r = run("sii_write -p 1 " + img);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.err, !Contains("(100%)"));
}

TEST_CASE("progress: foe_write refuses a slave in INIT before staging the file", "[cli][progress][unix]")
{
	ecmxftest::TempDir dir;
	const std::string sock = dir.path + "/sim.sock";
	ecmxftest::SimServer server(sock, { "--network", kServoNet });
	const std::string dev = "-d unix:" + sock + " ";
	REQUIRE(run(dev + "slaves").status == 0);
	REQUIRE(run(dev + "states -p 0 INIT").status == 0);
	const File f(dir, "a.bin", 1000);
	const auto r = run(dev + "--progress foe_write -p 0 " + f.path);
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("the slave is in INIT and has no mailbox"));
	CHECK_THAT(r.err, !Contains("staging")); // nothing staged
}

TEST_CASE("progress: pdos --progress counts the slaves whose mapping it read, silent into a pipe", "[cli][progress]")
{
	auto r = run("--progress pdos");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.err, Contains("pdos: 3/3 slaves (100%)"));
	r = run("--progress pdos -p 0,2");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.err, Contains("pdos: 2/2 slaves (100%)"));
	r = run("pdos");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
}
