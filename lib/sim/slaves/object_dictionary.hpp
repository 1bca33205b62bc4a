// SPDX-License-Identifier: MIT
//
// object_dictionary.hpp - a CoE object dictionary for the slave models.
//
// Every entry is bound to storage: either a member variable of the model
// (controlword, position actual, ...) or a cell the dictionary owns. The
// binding is what the process-data path copies to and from, so a mapped
// object costs one typed load or store per cycle and nothing else.
//
// SDO access (upload/download, expedited or complete access) checks
// existence, access rights (per AL state for "RW in PRE-OP" objects),
// lengths, value ranges and an optional per-entry check hook, and returns
// the CoE abort codes of ETG.1000.6 / CiA 301.

#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <ecmxf/sim/network.hpp>

namespace ecmxf::sim::slaves {

/// CoE basic data types the models use (ETG.1000.6 data type indices in
/// parentheses, as the dummy-mapping indices 0x0001..0x0007 use them).
enum class DataType : std::uint8_t {
	Bool,   // 0x0001
	I8,     // 0x0002
	I16,    // 0x0003
	I32,    // 0x0004
	U8,     // 0x0005
	U16,    // 0x0006
	U32,    // 0x0007
	I64,    // 0x0015
	U64,    // 0x001B
	String, // 0x0009 VISIBLE_STRING
};

/// What a data type is.
struct TypeInfo {
	unsigned bits;		///< size in bits (strings: 0, their size is their length)
	std::uint8_t coeIndex;	///< ETG.1000.6 data type index (the SII PDO categories)
	bool isSigned;
};
[[nodiscard]] TypeInfo typeInfo(DataType t);

/// Access rights of an entry.
enum class Access : std::uint8_t {
	RO,     ///< read only (SDO download: 0x06010002)
	WO,     ///< write only (SDO upload: 0x06010001)
	RW,     ///< read/write in every mailbox state
	RWPreOp,///< writable only in PRE-OP (PDO configuration; else 0x08000022)
};

/// Which process-data direction an entry may be mapped into.
enum PdoDir : std::uint8_t {
	NoPdo = 0,
	RxPdo = 1, ///< outputs (master -> slave)
	TxPdo = 2, ///< inputs (slave -> master)
};

/// Typed storage of one entry: a pointer and the type it points to.
struct Binding {
	void *ptr = nullptr;
	DataType type = DataType::U8;
};

/// Raw little-endian bits of the bound value, zero-extended.
[[nodiscard]] std::uint64_t loadRaw(const Binding &b);
/// Store the low bits of @p raw into the bound value.
void storeRaw(const Binding &b, std::uint64_t raw);
/// Sign-extend @p raw per @p t (for range checks of signed types).
[[nodiscard]] std::int64_t rawToSigned(DataType t, std::uint64_t raw);

/// One sub-index.
struct Entry {
	std::uint8_t subindex = 0;
	std::string name;
	DataType type = DataType::U8;
	Access access = Access::RO;
	std::uint8_t pdo = NoPdo;     ///< PdoDir bits
	bool storable = false;        ///< saved by "save", reset by "load"
	bool command = false;         ///< writes are commands: not stored
	bool hasRange = false;
	std::int64_t min = 0, max = 0;
	std::uint64_t defaultRaw = 0;
	Binding bind;
	std::string *str = nullptr;   ///< String entries
	/// Called on SDO download with the new raw value before it is stored;
	/// returns 0 or an abort code.
	std::function<std::uint32_t(std::uint64_t)> check;
	/// Called after an SDO download stored the value.
	std::function<void()> after;

	// fluent setup
	Entry &def(std::int64_t v);
	Entry &range(std::int64_t lo, std::int64_t hi);
	Entry &map(std::uint8_t dir);
	Entry &store();
	Entry &onCheck(std::function<std::uint32_t(std::uint64_t)> f);
	Entry &onAfter(std::function<void()> f);
	Entry &asCommand();

	[[nodiscard]] std::size_t byteSize() const;
};

/// Object code.
enum class ObjectCode : std::uint8_t { Var, Array, Record };

struct Object {
	std::uint16_t index = 0;
	std::string name;
	ObjectCode code = ObjectCode::Var;
	std::map<std::uint8_t, Entry> subs;
};

class ObjectDictionary
{
public:
	ObjectDictionary() = default;
	ObjectDictionary(const ObjectDictionary &) = delete;
	ObjectDictionary &operator=(const ObjectDictionary &) = delete;

	/// A VAR object (sub-index 0). @p bound may be null: the dictionary
	/// then owns the storage.
	Entry &var(std::uint16_t index, std::string name, DataType t, Access a,
		   void *bound = nullptr);
	/// A VISIBLE_STRING VAR object bound to @p s (read only).
	Entry &string(std::uint16_t index, std::string name, std::string *s);
	/// A sub-index of an ARRAY/RECORD object; the object (with a read-only
	/// sub-index 0 "number of entries" tracking the highest sub-index) is
	/// created on first use unless @p ownSub0 was given to record().
	Entry &sub(std::uint16_t index, std::uint8_t subindex, std::string name, DataType t,
		   Access a, void *bound = nullptr);
	/// Create a RECORD whose sub-index 0 is bound to @p sub0 (e.g. a PDO
	/// mapping count) with access @p a, instead of the automatic one.
	Entry &record(std::uint16_t index, std::string name, Access a, std::uint8_t *sub0);

	[[nodiscard]] const Entry *find(std::uint16_t index, std::uint8_t subindex) const;
	[[nodiscard]] Entry *find(std::uint16_t index, std::uint8_t subindex);
	[[nodiscard]] const Object *object(std::uint16_t index) const;
	[[nodiscard]] const std::map<std::uint16_t, Object> &objects() const { return objects_; }

	/// SDO upload. @p state decides nothing for reads today but is passed
	/// for symmetry. Returns 0 or an abort code.
	std::uint32_t upload(std::uint16_t index, std::uint8_t subindex, bool complete,
			     std::vector<std::uint8_t> &out) const;
	/// SDO download in AL state @p state. With @p clamp, a value outside the
	/// entry's range is stored clamped to the limit and the abort code is
	/// still returned (EST-584 behaviour: "set to the max value
	/// automatically").
	std::uint32_t download(std::uint16_t index, std::uint8_t subindex, bool complete,
			       std::span<const std::uint8_t> data, AlState state, bool clamp);

	/// Every bound entry back to its default value.
	void resetToDefaults();
	/// Storable entries back to their defaults (restore-defaults command).
	void restoreStorableDefaults();
	/// Snapshot / apply of the storable entries (key index<<8 | sub).
	[[nodiscard]] std::map<std::uint32_t, std::uint64_t> storableValues() const;
	void applyStored(const std::map<std::uint32_t, std::uint64_t> &values);

private:
	std::uint32_t downloadOne(Entry &e, std::span<const std::uint8_t> data, AlState state,
				  bool clamp);
	std::uint32_t downloadComplete(Object &o, std::uint8_t subindex,
				       std::span<const std::uint8_t> data, AlState state, bool clamp);
	Object &obj(std::uint16_t index, std::string name, ObjectCode code);
	Entry &addEntry(Object &o, std::uint8_t subindex, std::string name, DataType t, Access a,
			void *bound);
	void *cell();

	std::map<std::uint16_t, Object> objects_;
	std::deque<std::uint64_t> cells_;     // storage of unbound entries
	std::deque<std::uint8_t> sub0Cells_;  // automatic sub-index 0 values
};

} // namespace ecmxf::sim::slaves
