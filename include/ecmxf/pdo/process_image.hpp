// SPDX-License-Identifier: MIT
/**
 * @file process_image.hpp
 * @brief The process image: all slaves' outputs and inputs as the chip
 *        lays them out, with typed, bit-exact accessors.
 *
 * The output frame (RxPDO) is every slave's output bytes concatenated in
 * bus order, the input frame (TxPDO) every slave's input bytes; both are
 * what one FIFO entry of the chip holds (FIFO_PACK_SIZE_GET). The mapping
 * (which object lies at which bit) comes from a std::vector<SlavePdos>
 * (pdo_mapping.hpp), as Master::pdos() reports it.
 *
 * Accessors are looked up once, by object index:sub or name, and throw
 * ecmxf::Error (EINVAL) naming the slave and the object when it is not
 * mapped or the type does not fit its bit length. The handles they return
 * (OutputVar<T>, InputVar<T>) read and write the image without allocating
 * and without throwing: little-endian, any bit offset, signed values sign
 * extended from their bit length. A handle points into its image and is
 * valid as long as the image lives (moving the image keeps it valid).
 *
 * @code
 *   ecmxf::ProcessImage image(master.pdos());
 *   auto cw = image.output<std::uint16_t>(0, 0x6040, 0);
 *   auto pos = image.input<std::int32_t>(0, 0x6064, 0);
 *   cw.set(0x000F);
 *   std::int32_t p = pos.get();
 * @endcode
 *
 * Thread safety: none; one thread reads and writes an image at a time
 * (the one that runs the cyclic exchange over it).
 */
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <type_traits>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/model/pdo_mapping.hpp>

namespace ecmxf {

namespace detail {

/// @p n bits (1..64) starting at bit @p shift (0..7) of @p p, little-endian.
[[nodiscard]] inline std::uint64_t readBits(const std::uint8_t *p, unsigned shift, unsigned n) noexcept
{
	std::uint64_t v = 0;
	if (shift == 0 && (n & 7u) == 0) {
		for (unsigned i = 0; i < n / 8; i++)
			v |= std::uint64_t{ p[i] } << (8 * i);
		return v;
	}
	unsigned got = 0;
	while (got < n) {
		const unsigned take = (8u - shift) < (n - got) ? (8u - shift) : (n - got);
		const unsigned bits = (unsigned{ *p } >> shift) & ((1u << take) - 1u);
		v |= std::uint64_t{ bits } << got;
		got += take;
		++p;
		shift = 0;
	}
	return v;
}

/// Writes the low @p n bits (1..64) of @p v at bit @p shift (0..7) of @p p;
/// the bits around them are kept.
inline void writeBits(std::uint8_t *p, unsigned shift, unsigned n, std::uint64_t v) noexcept
{
	if (shift == 0 && (n & 7u) == 0) {
		for (unsigned i = 0; i < n / 8; i++)
			p[i] = static_cast<std::uint8_t>(v >> (8 * i));
		return;
	}
	unsigned done = 0;
	while (done < n) {
		const unsigned take = (8u - shift) < (n - done) ? (8u - shift) : (n - done);
		const unsigned mask = ((1u << take) - 1u) << shift;
		const unsigned bits = (static_cast<unsigned>(v >> done) << shift) & mask;
		*p = static_cast<std::uint8_t>((unsigned{ *p } & ~mask) | bits);
		done += take;
		++p;
		shift = 0;
	}
}

template <class T>
inline constexpr bool kImageType =
	(std::is_integral_v<T> || std::is_same_v<T, float> || std::is_same_v<T, double>) && !std::is_const_v<T>;

/// The value of @p n raw bits as T: sign-extended for signed T.
template <class T>
[[nodiscard]] inline T decode(std::uint64_t raw, unsigned n) noexcept
{
	if constexpr (std::is_same_v<T, bool>) {
		return raw != 0;
	} else if constexpr (std::is_same_v<T, float>) {
		return std::bit_cast<float>(static_cast<std::uint32_t>(raw));
	} else if constexpr (std::is_same_v<T, double>) {
		return std::bit_cast<double>(raw);
	} else if constexpr (std::is_signed_v<T>) {
		if (n < 64 && ((raw >> (n - 1)) & 1u))
			raw |= ~std::uint64_t{ 0 } << n;
		return static_cast<T>(static_cast<std::int64_t>(raw));
	} else {
		return static_cast<T>(raw);
	}
}

/// The raw bits of @p v (the writer keeps the low bits it needs).
template <class T>
[[nodiscard]] inline std::uint64_t encode(T v) noexcept
{
	if constexpr (std::is_same_v<T, bool>) {
		return v ? 1u : 0u;
	} else if constexpr (std::is_same_v<T, float>) {
		return std::bit_cast<std::uint32_t>(v);
	} else if constexpr (std::is_same_v<T, double>) {
		return std::bit_cast<std::uint64_t>(v);
	} else if constexpr (std::is_signed_v<T>) {
		return static_cast<std::uint64_t>(static_cast<std::int64_t>(v));
	} else {
		return static_cast<std::uint64_t>(v);
	}
}

} // namespace detail

class ProcessImage;

/// A mapped input object of one slave, read from the image's input frame.
/// Default-constructed: unbound, get() returns T{}.
template <class T>
class InputVar
{
	static_assert(detail::kImageType<T>, "InputVar<T>: T must be an integer type, bool, float or double");

public:
	InputVar() = default;

	/// The value in the latest input frame.
	[[nodiscard]] T get() const noexcept
	{
		if (!p_)
			return T{};
		return detail::decode<T>(detail::readBits(p_, shift_, bits_), bits_);
	}
	/// Bit offset in the input frame (all slaves).
	[[nodiscard]] std::uint32_t bitOffset() const noexcept { return bitOffset_; }
	/// Mapped length in bits.
	[[nodiscard]] unsigned bitLength() const noexcept { return bits_; }
	[[nodiscard]] bool bound() const noexcept { return p_ != nullptr; }

private:
	friend class ProcessImage;
	InputVar(const std::uint8_t *frame, std::uint32_t bitOffset, unsigned bits) noexcept
		: p_(frame + bitOffset / 8), bitOffset_(bitOffset), shift_(static_cast<std::uint8_t>(bitOffset % 8)),
		  bits_(static_cast<std::uint8_t>(bits))
	{
	}
	const std::uint8_t *p_ = nullptr;
	std::uint32_t bitOffset_ = 0;
	std::uint8_t shift_ = 0;
	std::uint8_t bits_ = 0;
};

/// A mapped output object of one slave, in the image's output frame.
/// Default-constructed: unbound, get() returns T{} and set() does nothing.
template <class T>
class OutputVar
{
	static_assert(detail::kImageType<T>, "OutputVar<T>: T must be an integer type, bool, float or double");

public:
	OutputVar() = default;

	/// The value in the output frame (as last set).
	[[nodiscard]] T get() const noexcept
	{
		if (!p_)
			return T{};
		return detail::decode<T>(detail::readBits(p_, shift_, bits_), bits_);
	}
	/// Writes the low bitLength() bits of @p v; the bits around are kept.
	void set(T v) noexcept
	{
		if (p_)
			detail::writeBits(p_, shift_, bits_, detail::encode<T>(v));
	}
	/// Bit offset in the output frame (all slaves).
	[[nodiscard]] std::uint32_t bitOffset() const noexcept { return bitOffset_; }
	/// Mapped length in bits.
	[[nodiscard]] unsigned bitLength() const noexcept { return bits_; }
	[[nodiscard]] bool bound() const noexcept { return p_ != nullptr; }

private:
	friend class ProcessImage;
	OutputVar(std::uint8_t *frame, std::uint32_t bitOffset, unsigned bits) noexcept
		: p_(frame + bitOffset / 8), bitOffset_(bitOffset), shift_(static_cast<std::uint8_t>(bitOffset % 8)),
		  bits_(static_cast<std::uint8_t>(bits))
	{
	}
	std::uint8_t *p_ = nullptr;
	std::uint32_t bitOffset_ = 0;
	std::uint8_t shift_ = 0;
	std::uint8_t bits_ = 0;
};

/// The output and input frames of a bus and where each mapped object lies.
class ECMXF_EXPORT ProcessImage
{
public:
	/// An image for @p slaves (bus order). Every entry must lie within its
	/// slave's outputBytes / inputBytes and be 1..64 bits long, else
	/// ecmxf::Error (EINVAL) naming the slave and the object. Both frames
	/// start zeroed.
	explicit ProcessImage(std::vector<SlavePdos> slaves);
	ProcessImage(ProcessImage &&) noexcept;
	ProcessImage &operator=(ProcessImage &&) noexcept;
	ProcessImage(const ProcessImage &) = delete;
	ProcessImage &operator=(const ProcessImage &) = delete;
	~ProcessImage();

	[[nodiscard]] std::size_t slaveCount() const noexcept { return slaves_.size(); }
	/// The mapping of the slave at bus position @p position (EINVAL when
	/// there is none).
	[[nodiscard]] const SlavePdos &slave(std::size_t position) const;

	/// The output frame (RxPDO): all slaves' outputs in bus order.
	[[nodiscard]] std::span<std::uint8_t> outputs() noexcept { return out_; }
	[[nodiscard]] std::span<const std::uint8_t> outputs() const noexcept { return out_; }
	/// The latest input frame (TxPDO): all slaves' inputs in bus order.
	/// Writable for whatever delivers the frames (Cyclic).
	[[nodiscard]] std::span<std::uint8_t> inputs() noexcept { return in_; }
	[[nodiscard]] std::span<const std::uint8_t> inputs() const noexcept { return in_; }

	/// Byte offset of slave @p position's outputs / inputs in the frame.
	[[nodiscard]] std::size_t outputOffset(std::size_t position) const;
	[[nodiscard]] std::size_t inputOffset(std::size_t position) const;
	/// Slave @p position's output / input bytes within the frames.
	[[nodiscard]] std::span<std::uint8_t> slaveOutputs(std::size_t position);
	[[nodiscard]] std::span<const std::uint8_t> slaveInputs(std::size_t position) const;

	/// The mapped output / input entry @p index:@p sub of slave @p position
	/// (the first one when mapped twice); EINVAL when not mapped.
	[[nodiscard]] const PdoEntryInfo &outputEntry(std::size_t position, std::uint16_t index,
						      std::uint8_t sub) const;
	[[nodiscard]] const PdoEntryInfo &inputEntry(std::size_t position, std::uint16_t index,
						     std::uint8_t sub) const;

	/// A handle on output object @p index:@p sub of slave @p position.
	/// Integer types take entries of up to their width (a 12-bit entry
	/// fits std::int16_t), bool takes 1-bit entries, float and double
	/// exactly 32 and 64 bits. Throws ecmxf::Error (EINVAL) naming the
	/// slave and the object when it is not mapped or does not fit T.
	template <class T>
	[[nodiscard]] OutputVar<T> output(std::size_t position, std::uint16_t index, std::uint8_t sub)
	{
		const Place p = place(true, position, index, sub, {}, traits<T>());
		return OutputVar<T>(out_.data(), p.bit, p.bits);
	}
	/// The same, found by the entry's name (PdoEntryInfo::name).
	template <class T>
	[[nodiscard]] OutputVar<T> output(std::size_t position, std::string_view name)
	{
		const Place p = place(true, position, 0, 0, name, traits<T>());
		return OutputVar<T>(out_.data(), p.bit, p.bits);
	}
	/// A handle on input object @p index:@p sub of slave @p position (rules
	/// as for output()).
	template <class T>
	[[nodiscard]] InputVar<T> input(std::size_t position, std::uint16_t index, std::uint8_t sub) const
	{
		const Place p = place(false, position, index, sub, {}, traits<T>());
		return InputVar<T>(in_.data(), p.bit, p.bits);
	}
	template <class T>
	[[nodiscard]] InputVar<T> input(std::size_t position, std::string_view name) const
	{
		const Place p = place(false, position, 0, 0, name, traits<T>());
		return InputVar<T>(in_.data(), p.bit, p.bits);
	}

private:
	/// What a handle's type accepts.
	struct TypeTraits {
		unsigned bits;  ///< width of T
		int kind;       ///< 0 integer, 1 bool, 2 floating point
	};
	template <class T>
	static constexpr TypeTraits traits() noexcept
	{
		static_assert(detail::kImageType<T>, "T must be an integer type, bool, float or double");
		if constexpr (std::is_same_v<T, bool>)
			return { 1, 1 };
		else if constexpr (std::is_floating_point_v<T>)
			return { sizeof(T) * 8, 2 };
		else
			return { sizeof(T) * 8, 0 };
	}
	struct Place {
		std::uint32_t bit;   ///< offset in the frame
		unsigned bits;       ///< length
	};
	/// Finds the entry (by @p name when not empty, else by index:sub) and
	/// checks it against @p t; throws as documented.
	Place place(bool output, std::size_t position, std::uint16_t index, std::uint8_t sub,
		    std::string_view name, TypeTraits t) const;
	const PdoEntryInfo *find(bool output, std::size_t position, std::uint16_t index, std::uint8_t sub,
				 std::string_view name) const;
	void checkPosition(std::size_t position) const;

	std::vector<SlavePdos> slaves_;
	std::vector<std::size_t> outOffset_, inOffset_;
	std::vector<std::uint8_t> out_, in_;
};

} // namespace ecmxf
