// SPDX-License-Identifier: MIT
// main() of test-integration: Catch2's, plus ECMXF_TEST_SKIP_TAGS.
//
// ECMXF_TEST_SKIP_TAGS="[tag1][tag2]" (or "tag1,tag2") leaves out the test
// cases with any of those tags, for a transport on which they cannot run.
// Each one left out is printed as "SKIPPED: <name> (tag [x]; ECMXF_TEST_SKIP_TAGS)"
// before the run, so a skip is never shown as a pass. Command-line test
// specs still work; the exclusions are added to them.

#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "integration.hpp"

namespace {

/// "[a][b]", "a,b" or "a b" -> {"a", "b"} (lower case, as Catch keeps tags).
std::vector<std::string> skipTags()
{
	std::vector<std::string> tags;
	const char *env = std::getenv("ECMXF_TEST_SKIP_TAGS");
	if (!env)
		return tags;
	std::string cur;
	for (const char *p = env;; ++p) {
		const char c = *p;
		if (c == '\0' || c == '[' || c == ']' || c == ',' || c == ' ') {
			if (!cur.empty())
				tags.push_back(cur);
			cur.clear();
			if (c == '\0')
				break;
			continue;
		}
		cur.push_back(static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c));
	}
	return tags;
}

} // namespace

int main(int argc, char *argv[])
{
	Catch::Session session;
	const std::vector<std::string> skip = skipTags();
	std::string exclude;
	for (const std::string &t : skip)
		exclude += "~[" + t + "]";

	int rc = session.applyCommandLine(argc, argv);
	if (rc != 0)
		return rc;
	const bool listing = session.configData().listTests || session.configData().listTestNamesOnly ||
			     session.configData().listTags || session.configData().listReporters;
	if (!skip.empty() && !listing) {
		std::vector<std::string> specs = session.configData().testsOrTags;
		if (specs.empty()) {
			specs.push_back(exclude);
		} else {
			for (std::string &s : specs)
				s += exclude;
		}
		session.configData().testsOrTags = specs;
		// name what is left out, once, before the run
		for (const Catch::TestCase &tc : Catch::getRegistryHub().getTestCaseRegistry().getAllTests()) {
			for (const std::string &t : skip) {
				bool has = false;
				for (const std::string &tag : tc.lcaseTags)
					has = has || tag == t;
				if (has) {
					std::printf("SKIPPED: %s (tag [%s]; ECMXF_TEST_SKIP_TAGS, not run on %s)\n",
						    tc.name.c_str(), t.c_str(), integ::uri().c_str());
					break;
				}
			}
		}
		std::fflush(stdout);
	}
	if (!listing) {
		std::printf("test-integration: device %s\n", integ::uri().c_str());
		std::fflush(stdout);
	}
	return session.run();
}
