// SPDX-License-Identifier: MIT
// BoardSdo: SDO_RD / SDO_WR through the SDO slot
// (include/ecmxf/sk/board_views.hpp).

#include <ecmxf/sk/board_views.hpp>

#include <cerrno>

#include <ecmxf/error.hpp>

#include "slot_link.hpp"

namespace ecmxf::sk {

namespace {

std::string sdoWhat(const char *cmd, unsigned slave, std::uint16_t index, std::uint8_t sub)
{
	return std::string(cmd) + " " + skSlave(slave) + " " + skHex(index, 4) + ":" +
	       skHex(sub, 2).substr(2);
}

} // namespace

void BoardSdo::checkSize(std::uint16_t index, std::uint8_t sub, unsigned size, std::size_t want)
{
	if (size != want)
		throw Error("SDO_RD " + skHex(index, 4) + ":" + skHex(sub, 2).substr(2) + ": the object is " +
				    std::to_string(size) + " byte(s), read as " + std::to_string(want),
			    EMSGSIZE);
}

std::uint32_t BoardSdo::read(unsigned slave, std::uint16_t index, std::uint8_t subindex, unsigned *size)
{
	auto &k = link_->impl();
	k.checkSlave(slave, "SDO_RD");
	k.knowState();
	k.require(ECMSK_CMD_SDO_RD, "SDO_RD");
	k.sdoRun(ecmsk_sdo{ ECMSK_CMD_SDO_RD, 0, static_cast<std::uint8_t>(slave), 0, subindex, index, 0 },
		 sdoWhat("SDO_RD", slave, index, subindex));
	if (size)
		*size = k.sdo.size;
	return k.sdo.value;
}

void BoardSdo::write(unsigned slave, std::uint16_t index, std::uint8_t subindex, std::uint32_t value, unsigned size)
{
	auto &k = link_->impl();
	k.checkSlave(slave, "SDO_WR");
	const std::string what = sdoWhat("SDO_WR", slave, index, subindex);
	if (size != 1 && size != 2 && size != 4)
		throw Error(what + ": size " + std::to_string(size) + " (1, 2 or 4 bytes)", EINVAL);
	if (size < 4 && (value >> (8 * size)))
		throw Error(what + ": " + skHex(value, 8) + " does not fit in " + std::to_string(size) + " byte(s)",
			    EINVAL);
	k.knowState();
	k.require(ECMSK_CMD_SDO_WR, "SDO_WR");
	k.sdoRun(ecmsk_sdo{ ECMSK_CMD_SDO_WR, 0, static_cast<std::uint8_t>(slave), static_cast<std::uint8_t>(size),
			    subindex, index, value },
		 what);
}

} // namespace ecmxf::sk
