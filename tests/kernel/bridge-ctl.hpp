// SPDX-License-Identifier: MIT
// The client side of ecmxf-bridge's control channel (see the comment at the
// top of tests/kernel/bridge.cpp and Documentation/kernel-testing.rst):
// send one command line to the FIFO /tmp/bridge.ctl and wait for the
// bridge's one-line reply on a private FIFO. Header-only, for the bridge's
// own `ctl` mode and for the guest programs.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace ecmxf::ktest {

inline constexpr const char *kBridgeCtlPath = "/tmp/bridge.ctl";

/// Sends @p cmd (no newline, no '@') and waits up to @p timeoutMs for the
/// reply. Returns true when the reply starts with "ok"; @p reply gets the
/// reply line (or why there is none).
inline bool bridgeCtl(const std::string &cmd, std::string &reply, int timeoutMs = 5000)
{
	char rpath[64];
	std::snprintf(rpath, sizeof(rpath), "/tmp/bridge.reply.%d", static_cast<int>(::getpid()));
	::unlink(rpath);
	if (::mkfifo(rpath, 0600) < 0) {
		reply = std::string("mkfifo: ") + std::strerror(errno);
		return false;
	}
	// the reader first, so that the bridge's non-blocking open succeeds;
	// read-write (Linux), so that the bridge closing it is no end of file
	const int rfd = ::open(rpath, O_RDWR | O_NONBLOCK | O_CLOEXEC);
	const int wfd = ::open(kBridgeCtlPath, O_WRONLY | O_NONBLOCK | O_CLOEXEC);
	bool ok = false;
	if (rfd < 0 || wfd < 0) {
		reply = std::string("no bridge control channel: ") + std::strerror(errno);
	} else {
		const std::string line = cmd + " @" + rpath + "\n";
		if (::write(wfd, line.data(), line.size()) != static_cast<ssize_t>(line.size())) {
			reply = std::string("write: ") + std::strerror(errno);
		} else {
			reply.clear();
			for (;;) {
				pollfd p{ rfd, POLLIN, 0 };
				const int n = ::poll(&p, 1, timeoutMs);
				if (n < 0 && errno == EINTR)
					continue;
				if (n <= 0) {
					reply = "no reply from the bridge";
					break;
				}
				char buf[512];
				const ssize_t len = ::read(rfd, buf, sizeof(buf));
				if (len <= 0) {
					if (len < 0 && (errno == EINTR || errno == EAGAIN))
						continue;
					reply = "reading the reply failed";
					break;
				}
				reply.append(buf, static_cast<std::size_t>(len));
				if (!reply.empty() && reply.back() == '\n') {
					reply.pop_back();
					ok = reply.rfind("ok", 0) == 0;
					break;
				}
			}
		}
	}
	if (wfd >= 0)
		::close(wfd);
	if (rfd >= 0)
		::close(rfd);
	::unlink(rpath);
	return ok;
}

} // namespace ecmxf::ktest
