// SPDX-License-Identifier: MIT
/*
 * ecmxf-util's safe stop: SIGINT, SIGTERM and SIGHUP while a command
 * enables or moves a drive. The handler only records the signal (async-
 * signal-safe); the command's loops look at it every cycle and bring the
 * drive to a halt in normal context (Documentation/cli.rst, "Stopping a
 * drive").
 */
#include "ecmxf-util.hpp"

#include <csignal>

namespace ecmxf_util {

namespace {

volatile std::sig_atomic_t gSignal = 0;

extern "C" void onStopSignal(int sig)
{
	if (gSignal == 0)
		gSignal = sig;
}

constexpr int kStopSignals[] = { SIGINT, SIGTERM, SIGHUP };

} // namespace

StopSignals::StopSignals()
{
	gSignal = 0;
	struct sigaction sa {};
	sa.sa_handler = onStopSignal;
	sigemptyset(&sa.sa_mask);
	// restarted system calls: an exchange with the chip is finished, then
	// the loop sees the flag
	sa.sa_flags = SA_RESTART;
	for (std::size_t i = 0; i < std::size(kStopSignals); i++)
		sigaction(kStopSignals[i], &sa, &old_[i]);
}

StopSignals::~StopSignals()
{
	for (std::size_t i = 0; i < std::size(kStopSignals); i++)
		sigaction(kStopSignals[i], &old_[i], nullptr);
}

int StopSignals::pending() noexcept
{
	return gSignal;
}

void StopSignals::check()
{
	if (const int sig = gSignal)
		throw Interrupted(sig);
}

std::string_view signalName(int sig) noexcept
{
	switch (sig) {
	case SIGINT: return "SIGINT";
	case SIGTERM: return "SIGTERM";
	case SIGHUP: return "SIGHUP";
	default: return "a signal";
	}
}

Interrupted::Interrupted(int sig) : std::runtime_error("interrupted by " + std::string(signalName(sig))), sig_(sig) {}

} // namespace ecmxf_util
