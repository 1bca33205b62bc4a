// SPDX-License-Identifier: MIT
// BoardIo: IO_RD / IO_WR and LIO_RD / LIO_WR (include/ecmxf/sk/board_views.hpp).

#include <ecmxf/sk/board_views.hpp>

#include <cerrno>

#include <ecmxf/error.hpp>

#include "slot_link.hpp"

namespace ecmxf::sk {

std::uint32_t BoardIo::read(unsigned slave)
{
	link_->impl().slaveCommand(slave, ECMSK_CMD_IO_RD);
	return static_cast<std::uint32_t>(BoardDrives(*link_).axis(slave).position);
}

void BoardIo::write(unsigned slave, std::uint32_t outputs)
{
	link_->impl().slaveCommand(slave, ECMSK_CMD_IO_WR, outputs);
}

std::uint32_t BoardIo::readLocal()
{
	auto &k = link_->impl();
	k.ecmCommand(ECMSK_CMD_LIO_RD, 0, 0);
	return k.res.ecm.data1;
}

void BoardIo::writeLocal(std::uint32_t outputs)
{
	auto &k = link_->impl();
	if (outputs > 0x3F)
		throw Error("LIO_WR: " + skHex(outputs, 2) + " (the ECM IC has outputs 0..5)", EINVAL);
	k.ecmCommand(ECMSK_CMD_LIO_WR, 0, outputs);
	if (!ecmsk_link_answered(&k.l, 0, k.miso.data()))
		k.refused("LIO_WR", "outputs not taken");
}

} // namespace ecmxf::sk
