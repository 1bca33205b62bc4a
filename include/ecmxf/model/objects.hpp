// SPDX-License-Identifier: MIT
/**
 * @file objects.hpp
 * @brief The standard objects (CiA 301 / CiA 402) the tools know by name
 *        and data type.
 *
 * The ECM-XF has no SDO information service, so a host cannot ask a slave
 * for an object's type. For the standard objects of drives that the tools
 * name (PDO listings) and write (ecmxf-util download), the data type is
 * the one CiA 402 fixes; anything else is known by its size only.
 */
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include <ecmxf/export.hpp>

namespace ecmxf {

/// The data types of the standard objects here (CiA 301 names).
enum class ObjectType : std::uint8_t { Int8, Int16, Int32, Uint8, Uint16, Uint32 };

/// "INTEGER8" ... "UNSIGNED32".
[[nodiscard]] ECMXF_EXPORT std::string_view objectTypeName(ObjectType t) noexcept;
/// Bytes of @p t.
[[nodiscard]] constexpr unsigned objectTypeSize(ObjectType t) noexcept
{
	return t == ObjectType::Int8 || t == ObjectType::Uint8	   ? 1
	       : t == ObjectType::Int16 || t == ObjectType::Uint16 ? 2
								   : 4;
}
/// INTEGER8/16/32.
[[nodiscard]] constexpr bool objectTypeSigned(ObjectType t) noexcept
{
	return t == ObjectType::Int8 || t == ObjectType::Int16 || t == ObjectType::Int32;
}

/// A standard object: its name, data type and unit.
struct StandardObject {
	std::uint16_t index = 0;
	std::uint8_t sub = 0;
	std::string_view name;
	ObjectType type = ObjectType::Uint8;
	/// The unit of its value, as CiA 402 gives it without a factor group
	/// (0x608F..0x60A2 not read): "inc" (position units), "inc/s",
	/// "inc/s^2", "0.1% rated torque" (per mille of 0x6076); empty for a
	/// word of bits, a code or a count.
	std::string_view unit;
};

/// Object @p index, @p sub when it is one of the standard objects here
/// (0x603F..0x60FF of CiA 402 that drives map or tools write: controlword,
/// statusword, modes, positions, velocities, torques, profile and homing
/// parameters, touch probe), else std::nullopt.
[[nodiscard]] ECMXF_EXPORT std::optional<StandardObject> standardObject(std::uint16_t index,
									std::uint8_t sub) noexcept;

} // namespace ecmxf
