// SPDX-License-Identifier: MIT
// The bus layer's shared helpers (lib/bus/bus_internal.hpp): object names,
// slave labels, argument checks.

#include "bus/bus_internal.hpp"

#include <cerrno>
#include <cstdio>

namespace ecmxf {

namespace bus {

std::string slaveLabel(std::uint8_t slave)
{
	return slave == kAllSlaves ? std::string("all slaves") : "slave " + std::to_string(slave);
}

std::string objName(std::uint16_t index, std::uint8_t sub)
{
	char buf[16];
	std::snprintf(buf, sizeof(buf), "0x%04X:%02X", index, sub);
	return buf;
}

void checkSlave(std::uint8_t slave, const char *what, bool allowAll)
{
	if (slave <= kMaxSlavePosition || (allowAll && slave == kAllSlaves))
		return;
	throw Error(std::string(what).append(": slave ").append(std::to_string(slave)).append(
			    allowAll ? " out of range (0..127, or 0xFF for all slaves)" : " out of range (0..127)"),
		    EINVAL);
}

void checkState(State s, const char *what)
{
	switch (s) {
	case State::Init:
	case State::PreOp:
	case State::Boot:
	case State::SafeOp:
	case State::Op:
		return;
	case State::None:
		break;
	}
	throw Error(std::string(what).append(": state ").append(hex(static_cast<std::uint8_t>(s), 2)).append(
			    " is not one of INIT (1), PRE-OP (2), BOOT (3), SAFE-OP (4), OP (8)"),
		    EINVAL);
}

} // namespace bus
} // namespace ecmxf
