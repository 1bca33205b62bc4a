// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/bus/sdo.hpp
 * @brief SDO transfers through the chip (ECAT_SDO_REQ / ECAT_SDO_GET).
 *
 * SDO transfers: dev.sdo().read<T>()/write() for typed values,
 * readString()/writeString(), upload()/download() for bytes. Failures on
 * the bus throw SdoError with the abort code and its text
 * (Documentation/sdo.rst). The names before 0.4 (sdoRead(), sdoWrite(),
 * sdoUpload()...) are deprecated aliases, kept for one release.
 *
 * A Sdo is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::sdo() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_bus.hpp>

namespace ecmxf {

class Device;

/// SDO transfers through the chip (ECAT_SDO_REQ / ECAT_SDO_GET).
class ECMXF_EXPORT Sdo
{
public:
	/// The view of @p device's SDO transfers.
	explicit Sdo(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	/// ECAT_SDO_REQ (10) read + ECAT_SDO_GET (11): upload an object.
	/// Failure: SdoError with the abort code (ECAT_SDO_ABORTCODE_GET) and
	/// its text. At most kSdoMaxBytes per request and at most the data
	/// section (EMSGSIZE otherwise).
	[[nodiscard]] std::vector<std::uint8_t> upload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
						     const SdoOptions &options = {}) const;
	/// ECAT_SDO_REQ (10) write: download @p data (1..256 bytes, and
	/// 12 + size within the data section).
	void download(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::span<const std::uint8_t> data,
		      const SdoOptions &options = {}) const;
	/// A visible string (trailing NULs dropped).
	[[nodiscard]] std::string readString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
					     const SdoOptions &options = {}) const;
	void writeString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::string_view value,
			 const SdoOptions &options = {}) const;

	/// Upload an integer or real (little-endian on the bus); the object
	/// must have exactly sizeof(T) bytes (EPROTO otherwise).
	template <typename T>
		requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
	[[nodiscard]] T read(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
			     const SdoOptions &options = {}) const
	{
		SdoOptions o = options;
		if (o.length == 0)
			o.length = sizeof(T);
		const std::vector<std::uint8_t> b = upload(slave, index, sub, o);
		if (b.size() != sizeof(T))
			detail::throwSdoSizeMismatch(slave, index, sub, b.size(), sizeof(T));
		using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
			  std::conditional_t<sizeof(T) == 2, std::uint16_t,
			  std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
		U u = 0;
		for (std::size_t i = 0; i < sizeof(T); i++)
			u = static_cast<U>(u | static_cast<U>(static_cast<U>(b[i]) << (8 * i)));
		return std::bit_cast<T>(u);
	}
	/// Download an integer or real (little-endian on the bus).
	template <typename T>
		requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
	void write(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, T value,
		   const SdoOptions &options = {}) const
	{
		using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
			  std::conditional_t<sizeof(T) == 2, std::uint16_t,
			  std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
		const U u = std::bit_cast<U>(value);
		std::array<std::uint8_t, sizeof(T)> b{};
		for (std::size_t i = 0; i < sizeof(T); i++)
			b[i] = static_cast<std::uint8_t>(u >> (8 * i));
		download(slave, index, sub, std::span<const std::uint8_t>(b.data(), b.size()), options);
	}

	// ---- the names before 0.4, kept for one release: each forwards to
	// the call above (Documentation/library.rst, "API changes before 0.1.0: one model for two masters")
	[[deprecated("use Sdo::upload")]] [[nodiscard]] std::vector<std::uint8_t>
	sdoUpload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, const SdoOptions &options = {}) const
	{
		return upload(slave, index, sub, options);
	}
	[[deprecated("use Sdo::download")]] void sdoDownload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
							     std::span<const std::uint8_t> data,
							     const SdoOptions &options = {}) const
	{
		download(slave, index, sub, data, options);
	}
	[[deprecated("use Sdo::readString")]] [[nodiscard]] std::string
	sdoReadString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, const SdoOptions &options = {}) const
	{
		return readString(slave, index, sub, options);
	}
	[[deprecated("use Sdo::writeString")]] void sdoWriteString(std::uint8_t slave, std::uint16_t index,
								   std::uint8_t sub, std::string_view value,
								   const SdoOptions &options = {}) const
	{
		writeString(slave, index, sub, value, options);
	}
	template <typename T>
		requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
	[[deprecated("use Sdo::read")]] [[nodiscard]] T sdoRead(std::uint8_t slave, std::uint16_t index,
								std::uint8_t sub, const SdoOptions &options = {}) const
	{
		return read<T>(slave, index, sub, options);
	}
	template <typename T>
		requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
	[[deprecated("use Sdo::write")]] void sdoWrite(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
						       T value, const SdoOptions &options = {}) const
	{
		write(slave, index, sub, value, options);
	}

private:
	Device *dev_;
};

} // namespace ecmxf
