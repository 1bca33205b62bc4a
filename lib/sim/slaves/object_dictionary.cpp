// SPDX-License-Identifier: MIT
//
// object_dictionary.cpp - CoE object dictionary of the slave models: typed
// storage bindings, SDO upload/download with the CoE abort codes.

#include "slaves/object_dictionary.hpp"

#include <cstring>
#include <iterator>
#include <stdexcept>

namespace ecmxf::sim::slaves {

namespace {

// The data types in the enum's order.
constexpr TypeInfo kTypes[] = {
	{ 1, 0x01, false },  // Bool
	{ 8, 0x02, true },   // I8
	{ 16, 0x03, true },  // I16
	{ 32, 0x04, true },  // I32
	{ 8, 0x05, false },  // U8
	{ 16, 0x06, false }, // U16
	{ 32, 0x07, false }, // U32
	{ 64, 0x15, true },  // I64
	{ 64, 0x1B, false }, // U64
	{ 0, 0x09, false },  // String (VISIBLE_STRING)
};
static_assert(std::size(kTypes) == static_cast<std::size_t>(DataType::String) + 1);

} // namespace

TypeInfo typeInfo(DataType t)
{
	const auto i = static_cast<std::size_t>(t);
	return i < std::size(kTypes) ? kTypes[i] : TypeInfo{ 0, 0, false };
}

namespace {

// Bytes a bound value occupies in memory (Bool is stored as a byte).
std::size_t storageBytes(DataType t)
{
	return t == DataType::Bool ? 1 : typeInfo(t).bits / 8;
}

// Calls @p f with a value of the first of U, Us... that is @p bytes wide
// (none: nothing).
template <typename U, typename... Us, typename F> void withWidth(std::size_t bytes, F &&f)
{
	if (bytes == sizeof(U))
		f(U{});
	else if constexpr (sizeof...(Us) > 0)
		withWidth<Us...>(bytes, f);
}

// Calls @p f with a value of the unsigned type as wide as a bound value of
// type @p t (nothing for String). The raw value of a signed type is its bits,
// zero-extended, so the unsigned type of its width loads and stores it alike.
template <typename F> void withStorageType(DataType t, F &&f)
{
	withWidth<std::uint8_t, std::uint16_t, std::uint32_t, std::uint64_t>(storageBytes(t), f);
}

} // namespace

std::uint64_t loadRaw(const Binding &b)
{
	if (!b.ptr)
		return 0;
	std::uint64_t raw = 0;
	withStorageType(b.type, [&](auto u) {
		std::memcpy(&u, b.ptr, sizeof u);
		raw = u;
	});
	return b.type == DataType::Bool ? raw & 1u : raw;
}

void storeRaw(const Binding &b, std::uint64_t raw)
{
	if (!b.ptr)
		return;
	if (b.type == DataType::Bool)
		raw &= 1u;
	withStorageType(b.type, [&](auto u) {
		u = static_cast<decltype(u)>(raw);
		std::memcpy(b.ptr, &u, sizeof u);
	});
}

std::int64_t rawToSigned(DataType t, std::uint64_t raw)
{
	const unsigned bits = typeInfo(t).bits;
	if (!typeInfo(t).isSigned || bits == 0 || bits >= 64)
		return static_cast<std::int64_t>(raw);
	const std::uint64_t sign = std::uint64_t{ 1 } << (bits - 1);
	const std::uint64_t mask = (std::uint64_t{ 1 } << bits) - 1;
	raw &= mask;
	return (raw & sign) ? static_cast<std::int64_t>(raw | ~mask) : static_cast<std::int64_t>(raw);
}

// ---- Entry ----

Entry &Entry::def(std::int64_t v)
{
	defaultRaw = static_cast<std::uint64_t>(v);
	storeRaw(bind, defaultRaw);
	return *this;
}

Entry &Entry::range(std::int64_t lo, std::int64_t hi)
{
	hasRange = true;
	min = lo;
	max = hi;
	return *this;
}

Entry &Entry::map(std::uint8_t dir)
{
	pdo = dir;
	return *this;
}

Entry &Entry::store()
{
	storable = true;
	return *this;
}

Entry &Entry::onCheck(std::function<std::uint32_t(std::uint64_t)> f)
{
	check = std::move(f);
	return *this;
}

Entry &Entry::onAfter(std::function<void()> f)
{
	after = std::move(f);
	return *this;
}

Entry &Entry::asCommand()
{
	command = true;
	return *this;
}

std::size_t Entry::byteSize() const
{
	if (type == DataType::String)
		return str ? str->size() : 0;
	return storageBytes(type);
}

// ---- ObjectDictionary ----

void *ObjectDictionary::cell()
{
	cells_.push_back(0);
	return &cells_.back();
}

Object &ObjectDictionary::obj(std::uint16_t index, std::string name, ObjectCode code)
{
	auto it = objects_.find(index);
	if (it != objects_.end())
		return it->second;
	Object o;
	o.index = index;
	o.name = std::move(name);
	o.code = code;
	return objects_.emplace(index, std::move(o)).first->second;
}

Entry &ObjectDictionary::addEntry(Object &o, std::uint8_t subindex, std::string name, DataType t,
				  Access a, void *bound)
{
	if (o.subs.count(subindex))
		throw std::logic_error("object dictionary: duplicate entry");
	Entry e;
	e.subindex = subindex;
	e.name = std::move(name);
	e.type = t;
	e.access = a;
	e.bind = Binding{ bound ? bound : cell(), t };
	return o.subs.emplace(subindex, std::move(e)).first->second;
}

Entry &ObjectDictionary::var(std::uint16_t index, std::string name, DataType t, Access a,
			     void *bound)
{
	Object &o = obj(index, name, ObjectCode::Var);
	return addEntry(o, 0, std::move(name), t, a, bound);
}

Entry &ObjectDictionary::string(std::uint16_t index, std::string name, std::string *s)
{
	Object &o = obj(index, name, ObjectCode::Var);
	Entry &e = addEntry(o, 0, std::move(name), DataType::String, Access::RO, nullptr);
	e.bind = Binding{};
	e.str = s;
	return e;
}

Entry &ObjectDictionary::record(std::uint16_t index, std::string name, Access a,
				std::uint8_t *sub0)
{
	Object &o = obj(index, name, ObjectCode::Record);
	return addEntry(o, 0, "Number of entries", DataType::U8, a, sub0);
}

Entry &ObjectDictionary::sub(std::uint16_t index, std::uint8_t subindex, std::string name,
			     DataType t, Access a, void *bound)
{
	Object &o = obj(index, name, ObjectCode::Record);
	if (!o.subs.count(0)) {
		sub0Cells_.push_back(0);
		addEntry(o, 0, "Number of entries", DataType::U8, Access::RO, &sub0Cells_.back());
		o.subs.at(0).map(NoPdo);
	}
	Entry &e = addEntry(o, subindex, std::move(name), t, a, bound);
	Entry &s0 = o.subs.at(0);
	if (s0.access == Access::RO && subindex > loadRaw(s0.bind))
		s0.def(subindex);
	return e;
}

const Entry *ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) const
{
	auto it = objects_.find(index);
	if (it == objects_.end())
		return nullptr;
	auto s = it->second.subs.find(subindex);
	return s == it->second.subs.end() ? nullptr : &s->second;
}

Entry *ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex)
{
	auto it = objects_.find(index);
	if (it == objects_.end())
		return nullptr;
	auto s = it->second.subs.find(subindex);
	return s == it->second.subs.end() ? nullptr : &s->second;
}

const Object *ObjectDictionary::object(std::uint16_t index) const
{
	auto it = objects_.find(index);
	return it == objects_.end() ? nullptr : &it->second;
}

namespace {

void appendValue(const Entry &e, std::vector<std::uint8_t> &out)
{
	if (e.type == DataType::String) {
		if (e.str)
			out.insert(out.end(), e.str->begin(), e.str->end());
		return;
	}
	const std::uint64_t raw = loadRaw(e.bind);
	for (std::size_t i = 0; i < e.byteSize(); i++)
		out.push_back(static_cast<std::uint8_t>(raw >> (8 * i)));
}

std::uint64_t readLe(std::span<const std::uint8_t> d)
{
	std::uint64_t v = 0;
	for (std::size_t i = 0; i < d.size() && i < 8; i++)
		v |= std::uint64_t{ d[i] } << (8 * i);
	return v;
}

} // namespace

std::uint32_t ObjectDictionary::upload(std::uint16_t index, std::uint8_t subindex, bool complete,
				       std::vector<std::uint8_t> &out) const
{
	out.clear();
	const Object *o = object(index);
	if (!o)
		return abort::NoObject;
	if (complete) {
		if (o->code == ObjectCode::Var)
			return abort::CompleteAccessUnsupported;
		if (subindex > 1)
			return abort::UnsupportedAccess;
		const Entry &s0 = o->subs.at(0);
		const auto n = static_cast<unsigned>(loadRaw(s0.bind));
		if (subindex == 0) {
			out.push_back(static_cast<std::uint8_t>(n));
			out.push_back(0); // sub-index 0 travels as 16 bits
		}
		for (unsigned s = 1; s <= n; s++) {
			auto it = o->subs.find(static_cast<std::uint8_t>(s));
			if (it == o->subs.end())
				continue;
			if (it->second.access == Access::WO) {
				out.clear();
				return abort::WriteOnly;
			}
			appendValue(it->second, out);
		}
		return 0;
	}
	auto it = o->subs.find(subindex);
	if (it == o->subs.end())
		return abort::NoSubindex;
	if (it->second.access == Access::WO)
		return abort::WriteOnly;
	appendValue(it->second, out);
	return 0;
}

std::uint32_t ObjectDictionary::downloadOne(Entry &e, std::span<const std::uint8_t> data,
					    AlState state, bool clamp)
{
	if (e.access == Access::RO || e.type == DataType::String)
		return abort::ReadOnly;
	if (e.access == Access::RWPreOp && state != AlState::PreOp)
		return abort::CannotTransferState;
	if (data.size() != e.byteSize())
		return abort::LengthMismatch;
	std::uint64_t raw = readLe(data);
	std::uint32_t rangeAbort = 0;
	if (e.hasRange) {
		const std::int64_t v = typeInfo(e.type).isSigned ? rawToSigned(e.type, raw)
							: static_cast<std::int64_t>(raw);
		if (v > e.max) {
			rangeAbort = abort::ValueTooHigh;
			raw = static_cast<std::uint64_t>(e.max);
		} else if (v < e.min) {
			rangeAbort = abort::ValueTooLow;
			raw = static_cast<std::uint64_t>(e.min);
		}
		if (rangeAbort && !clamp)
			return rangeAbort;
	}
	if (e.check) {
		if (const std::uint32_t a = e.check(raw))
			return a;
	}
	if (!e.command)
		storeRaw(e.bind, raw);
	if (e.after)
		e.after();
	return rangeAbort;
}

std::uint32_t ObjectDictionary::downloadComplete(Object &o, std::uint8_t subindex,
						 std::span<const std::uint8_t> data, AlState state,
						 bool clamp)
{
	if (o.code == ObjectCode::Var)
		return abort::CompleteAccessUnsupported;
	if (subindex > 1)
		return abort::UnsupportedAccess;
	Entry &s0 = o.subs.at(0);
	const bool sub0Writable = s0.access != Access::RO;
	unsigned n = static_cast<unsigned>(loadRaw(s0.bind));
	std::size_t pos = 0;
	if (subindex == 0) {
		if (data.size() < 2)
			return abort::LengthMismatch;
		if (sub0Writable)
			n = data[0];
		pos = 2;
	}
	const unsigned highest = o.subs.rbegin()->first;
	if (n > highest)
		return abort::ValueTooHigh;
	std::size_t need = pos;
	for (unsigned s = 1; s <= n; s++) {
		auto it = o.subs.find(static_cast<std::uint8_t>(s));
		if (it != o.subs.end())
			need += it->second.byteSize();
	}
	if (need != data.size())
		return abort::LengthMismatch;

	// All or nothing: remember the old values, restore them on failure.
	std::vector<std::pair<Entry *, std::uint64_t>> old;
	for (auto &[s, e] : o.subs)
		old.emplace_back(&e, loadRaw(e.bind));
	auto fail = [&](std::uint32_t code) {
		for (auto &[e, raw] : old)
			storeRaw(e->bind, raw);
		for (auto &[s, e] : o.subs)
			if (e.after) {
				e.after();
				break;
			}
		return code;
	};
	if (subindex == 0 && sub0Writable) {
		const std::uint8_t zero = 0;
		if (const std::uint32_t a = downloadOne(s0, std::span(&zero, 1), state, false))
			return fail(a);
	}
	for (unsigned s = 1; s <= n; s++) {
		auto it = o.subs.find(static_cast<std::uint8_t>(s));
		if (it == o.subs.end())
			continue;
		Entry &e = it->second;
		const auto chunk = data.subspan(pos, e.byteSize());
		pos += e.byteSize();
		if (e.access == Access::RO)
			continue; // read-only entries of a record keep their value
		if (const std::uint32_t a = downloadOne(e, chunk, state, false))
			return fail(a);
	}
	if (subindex == 0 && sub0Writable) {
		const auto count = static_cast<std::uint8_t>(n);
		if (const std::uint32_t a = downloadOne(s0, std::span(&count, 1), state, false))
			return fail(a);
	}
	(void)clamp;
	return 0;
}

std::uint32_t ObjectDictionary::download(std::uint16_t index, std::uint8_t subindex, bool complete,
					 std::span<const std::uint8_t> data, AlState state,
					 bool clamp)
{
	auto it = objects_.find(index);
	if (it == objects_.end())
		return abort::NoObject;
	if (complete)
		return downloadComplete(it->second, subindex, data, state, clamp);
	auto s = it->second.subs.find(subindex);
	if (s == it->second.subs.end())
		return abort::NoSubindex;
	return downloadOne(s->second, data, state, clamp);
}

void ObjectDictionary::resetToDefaults()
{
	for (auto &[i, o] : objects_)
		for (auto &[s, e] : o.subs)
			storeRaw(e.bind, e.defaultRaw);
}

void ObjectDictionary::restoreStorableDefaults()
{
	for (auto &[i, o] : objects_)
		for (auto &[s, e] : o.subs)
			if (e.storable)
				storeRaw(e.bind, e.defaultRaw);
}

std::map<std::uint32_t, std::uint64_t> ObjectDictionary::storableValues() const
{
	std::map<std::uint32_t, std::uint64_t> v;
	for (const auto &[i, o] : objects_)
		for (const auto &[s, e] : o.subs)
			if (e.storable)
				v[std::uint32_t{ i } << 8 | s] = loadRaw(e.bind);
	return v;
}

void ObjectDictionary::applyStored(const std::map<std::uint32_t, std::uint64_t> &values)
{
	for (const auto &[key, raw] : values) {
		Entry *e = find(static_cast<std::uint16_t>(key >> 8),
				static_cast<std::uint8_t>(key & 0xFF));
		if (e && e->storable)
			storeRaw(e->bind, raw);
	}
}

} // namespace ecmxf::sim::slaves
