// SPDX-License-Identifier: MIT
// The standard objects' names, data types and units (include/ecmxf/model/objects.hpp),
// after CiA 402 (IEC 61800-7-201), the object dictionary chapters.

#include <ecmxf/model/objects.hpp>

namespace ecmxf {

namespace {

using T = ObjectType;

// CiA 402's units without a factor group: position units are increments,
// velocity and acceleration per second, torque per mille of rated torque
constexpr std::string_view kPos = "inc";
constexpr std::string_view kVel = "inc/s";
constexpr std::string_view kAcc = "inc/s^2";
constexpr std::string_view kTorque = "0.1% rated torque";

constexpr StandardObject kObjects[] = {
	{ 0x603F, 0, "Error code", T::Uint16, {} },
	{ 0x6040, 0, "Controlword", T::Uint16, {} },
	{ 0x6041, 0, "Statusword", T::Uint16, {} },
	{ 0x605A, 0, "Quick stop option code", T::Int16, {} },
	{ 0x6060, 0, "Modes of operation", T::Int8, {} },
	{ 0x6061, 0, "Modes of operation display", T::Int8, {} },
	{ 0x6064, 0, "Position actual value", T::Int32, kPos },
	{ 0x606C, 0, "Velocity actual value", T::Int32, kVel },
	{ 0x6071, 0, "Target torque", T::Int16, kTorque },
	{ 0x6077, 0, "Torque actual value", T::Int16, kTorque },
	{ 0x607A, 0, "Target position", T::Int32, kPos },
	{ 0x607C, 0, "Home offset", T::Int32, kPos },
	{ 0x6081, 0, "Profile velocity", T::Uint32, kVel },
	{ 0x6083, 0, "Profile acceleration", T::Uint32, kAcc },
	{ 0x6084, 0, "Profile deceleration", T::Uint32, kAcc },
	{ 0x6085, 0, "Quick stop deceleration", T::Uint32, kAcc },
	{ 0x6098, 0, "Homing method", T::Int8, {} },
	{ 0x6099, 1, "Speed during search for switch", T::Uint32, kVel },
	{ 0x6099, 2, "Speed during search for zero", T::Uint32, kVel },
	{ 0x609A, 0, "Homing acceleration", T::Uint32, kAcc },
	{ 0x60B0, 0, "Position offset", T::Int32, kPos },
	{ 0x60B8, 0, "Touch probe function", T::Uint16, {} },
	{ 0x60B9, 0, "Touch probe status", T::Uint16, {} },
	{ 0x60BA, 0, "Touch probe 1 positive edge", T::Int32, kPos },
	{ 0x60F4, 0, "Following error actual value", T::Int32, kPos },
	{ 0x60FD, 0, "Digital inputs", T::Uint32, {} },
	{ 0x60FF, 0, "Target velocity", T::Int32, kVel },
};

} // namespace

std::string_view objectTypeName(ObjectType t) noexcept
{
	switch (t) {
	case T::Int8: return "INTEGER8";
	case T::Int16: return "INTEGER16";
	case T::Int32: return "INTEGER32";
	case T::Uint8: return "UNSIGNED8";
	case T::Uint16: return "UNSIGNED16";
	case T::Uint32: return "UNSIGNED32";
	}
	return "?";
}

std::optional<StandardObject> standardObject(std::uint16_t index, std::uint8_t sub) noexcept
{
	for (const StandardObject &o : kObjects)
		if (o.index == index && o.sub == sub)
			return o;
	return std::nullopt;
}

} // namespace ecmxf
