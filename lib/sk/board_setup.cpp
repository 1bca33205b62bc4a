// SPDX-License-Identifier: MIT
// BoardSetup: SET_AXIS, SET_DC, SET_EX (include/ecmxf/sk/board_views.hpp).

#include <ecmxf/sk/board_views.hpp>

#include <algorithm>
#include <cerrno>

#include <ecmxf/error.hpp>

#include "slot_link.hpp"

namespace ecmxf::sk {

namespace {

// SET_AXIS of group @p g with @p types; the mask of the group's slaves
// whose type the board refused (Data2).
std::uint32_t setAxisGroup(SlotLink::Impl &k, const std::vector<std::uint8_t> &types, unsigned g)
{
	std::uint32_t topo = 0;
	if (ecmsk_axis_topology(types.data(), static_cast<unsigned>(types.size()), g, &topo))
		throw Error("SET_AXIS: a slave type other than Drive, IO, HSP or STEP", EINVAL);
	k.ecmCommand(ECMSK_CMD_SET_AXIS, static_cast<std::uint8_t>(g), topo);
	if (!ecmsk_link_answered(&k.l, 0, k.miso.data()))
		k.refused("SET_AXIS group " + std::to_string(g), "not allowed now");
	return k.res.ecm.data2;
}

std::vector<std::uint8_t> codes(std::span<const SlaveType> types)
{
	std::vector<std::uint8_t> t(types.size());
	for (std::size_t i = 0; i < types.size(); i++)
		t[i] = static_cast<std::uint8_t>(types[i]);
	return t;
}

} // namespace

unsigned BoardSetup::setAxes(std::span<const SlaveType> types)
{
	auto &k = link_->impl();
	if (types.size() > link_->maxSlaves())
		throw Error("SET_AXIS: " + std::to_string(types.size()) + " slave types, the frame has " +
				    std::to_string(link_->maxSlaves()) + " slave slots",
			    EINVAL);
	k.knowState();
	k.require(ECMSK_CMD_SET_AXIS, "SET_AXIS");
	const std::vector<std::uint8_t> t = codes(types);
	unsigned count = 0;
	const unsigned groups = std::max<unsigned>(1, static_cast<unsigned>((t.size() + 7) / 8));
	for (unsigned g = 0; g < groups; g++) {
		const std::uint32_t bad = setAxisGroup(k, t, g);
		const auto &e = k.res.ecm;
		if (bad) {
			std::string which;
			for (unsigned i = 0; i < 8; i++)
				if (bad & (1u << i)) {
					const unsigned n = g * 8 + i;
					which += (which.empty() ? "" : ", ") + std::to_string(n) + " (" +
						 std::string(slaveTypeName(types[n])) + ")";
				}
			throw Error("SET_AXIS: the ECM-SK refused the types of group " + std::to_string(g) +
					    ": slave " + which + " is not of that type (or not there); " +
					    std::to_string(e.data1) + " slaves detected",
				    EPERM);
		}
		count = e.data1;
	}
	return count;
}

unsigned BoardSetup::slaveCount()
{
	return setAxes({});
}

std::vector<SlaveType> BoardSetup::detectAxes()
{
	auto &k = link_->impl();
	const unsigned count = slaveCount();
	if (k.state() != ecmxf::State::PreOp)
		throw Error("detecting the slave types needs PRE-OP; the ECM-SK is in " + stateName(k.state()), EPERM);
	static constexpr SlaveType kOrder[] = { SlaveType::Drive, SlaveType::Step, SlaveType::Hsp, SlaveType::Io };
	std::vector<SlaveType> types(count, SlaveType::Drive);
	std::vector<unsigned> tried(count, 0);
	for (unsigned g = 0; g * 8 < count; g++) {
		for (;;) {
			const std::uint32_t bad = setAxisGroup(k, codes(types), g);
			if (!bad)
				break;
			for (unsigned i = 0; i < 8; i++) {
				if (!(bad & (1u << i)))
					continue;
				const unsigned n = g * 8 + i;
				if (n >= count || ++tried[n] >= 4)
					throw Error("SET_AXIS: " + skSlave(n + 1) +
							    " is none of Drive, STEP, HSP, IO",
						    EPROTO);
				types[n] = kOrder[tried[n]];
			}
		}
	}
	return types;
}

void BoardSetup::setCycleTime(std::uint32_t us)
{
	auto &k = link_->impl();
	if (!ecmsk_dc_cycle_valid(us))
		throw Error("SET_DC: " + std::to_string(us) + " us is not 250 * 2^n us", EINVAL);
	k.knowState();
	k.require(ECMSK_CMD_SET_DC, "SET_DC");
	k.ecmCommand(ECMSK_CMD_SET_DC, 0, us, ECMSK_DC_FIX);
	if (!ecmsk_link_answered(&k.l, 0, k.miso.data()))
		k.refused("SET_DC " + std::to_string(us) + " us", "cycle time not taken");
}

void BoardSetup::setExtensions(std::uint32_t bits)
{
	auto &k = link_->impl();
	if (bits > (ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC))
		throw Error("SET_EX: " + skHex(bits, 2) + " (bit 0 command CRC, bit 1 response CRC)", EINVAL);
	k.knowState();
	k.require(ECMSK_CMD_SET_EX, "SET_EX");
	k.ecmCommand(ECMSK_CMD_SET_EX, 0, bits);
	if (!ecmsk_link_answered(&k.l, 0, k.miso.data()))
		k.refused("SET_EX", "setting not taken");
}

} // namespace ecmxf::sk
