// SPDX-License-Identifier: MIT
// The Python binding (module ecmxf._ecmxf, Documentation/python.rst): what
// its translation units share. module.cpp: the module, the exceptions,
// the free functions; device.cpp: Device, its SDO view, the slave list,
// the CiA-402 verbs, the events; cyclic.cpp: Cyclic, the process image's
// buffers and entries, Axis; chip.cpp: the ECM-XF's own views (the
// peripherals, the chip's CiA-402 engine, raw commands and datagrams,
// EEPROM, FoE and the staging flash); board.cpp: the ECM-SK's views.
//
// One rule holds everywhere: a Python script cannot crash the
// interpreter. Every argument is range-checked before it reaches the
// library (ValueError naming the argument), every library error becomes
// an ecmxf.Error (or its subclasses), a closed device raises
// ecmxf.ClosedError, and a device is used by one thread at a time (a
// second thread gets ecmxf.BusyError rather than a data race while the
// first one runs with the GIL released).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <pybind11/pybind11.h>

#include <ecmxf/device.hpp>
#include <ecmxf/model/pdo_mapping.hpp>
#include <ecmxf/verbs.hpp>

namespace ecmxf {
struct Event; // <ecmxf/events/events.hpp>
}

namespace ecmxf::python {

namespace py = pybind11;

class CyclicObject;

/// One open master: what a Python Device, its views and its Cyclics
/// share. close() ends it; the views and Cyclics that outlive it then
/// raise ClosedError.
struct Session {
	std::string uri;
	std::unique_ptr<MasterVerbs> verbs;
	/// What Master::bringUp() found (ECM-XF): a Cyclic's image is built
	/// from it.
	std::vector<SlavePdos> pdos;
	bool broughtUp = false;
	/// The Cyclics over this device: closed before the device is.
	std::vector<CyclicObject *> cyclics;
	/// A call in progress with the GIL released (see Use).
	std::atomic<bool> busy{ false };

	/// The verbs, or ClosedError.
	MasterVerbs &open() const;
	/// The ECM-XF Device, or ClosedError / NotSupportedError naming
	/// @p what (an ECM-SK has none).
	Device &device(std::string_view what) const;
	/// Closes the Cyclics, then the master; BusyError while a call runs.
	void close();
};

/// What a Python Device holds.
struct DeviceObject {
	std::shared_ptr<Session> session;
};

/// Marks a session in use for one call that releases the GIL; a second
/// concurrent call gets BusyError instead of a data race.
class Use
{
public:
	explicit Use(Session &s);
	~Use() { s_.busy.store(false, std::memory_order_release); }
	Use(const Use &) = delete;
	Use &operator=(const Use &) = delete;

private:
	Session &s_;
};

/// Runs @p f on the open session's verbs with the GIL released (one
/// thread at a time: BusyError for a second).
template <class F>
auto run(Session &s, F &&f)
{
	MasterVerbs &m = s.open();
	Use use(s);
	py::gil_scoped_release nogil;
	return f(m);
}

/// Runs @p f on the ECM-XF Device of the session with the GIL released
/// (ClosedError, NotSupportedError naming @p what on an ECM-SK, BusyError
/// for a second thread).
template <class F>
auto onDevice(Session &s, std::string_view what, F &&f)
{
	Device &d = s.device(what);
	Use use(s);
	py::gil_scoped_release nogil;
	return f(d);
}

// ---- exceptions (module.cpp)
/// Raises ecmxf.ClosedError ("<what>: the device is closed").
[[noreturn]] void throwClosed(std::string_view what);
/// What ecmxf.BusyError says.
inline constexpr const char *kBusyMessage =
	"the device is busy with another call (one call at a time: another thread's, or one that is calling back "
	"into Python)";
/// Raises ecmxf.BusyError.
[[noreturn]] void throwBusy();
/// The exception class ecmxf.<name>.
py::object exceptionClass(const char *name);

// ---- arguments: Python ints checked into C++ ranges (ValueError naming
// the argument and the range)
std::uint8_t position(std::int64_t v);
std::uint16_t index16(std::int64_t v);
std::uint8_t sub8(std::int64_t v);
std::uint64_t checkedRange(std::int64_t v, std::int64_t lo, std::int64_t hi, const char *what);
/// @p s seconds as nanoseconds (ValueError naming @p what outside lo..hi s).
std::chrono::nanoseconds seconds(double s, const char *what, double lo, double hi);
/// A bytes-like value (bytes, bytearray, memoryview) as bytes (TypeError
/// naming @p what for anything else).
std::vector<std::uint8_t> bytesOf(const py::handle &value, const char *what);

/// The value types the binding converts ("u8" ... "f64", "str", "bytes").
enum class ValueType : std::uint8_t { U8, U16, U32, U64, I8, I16, I32, I64, F32, F64, Str, Bytes };
/// "u8" ... (ValueError for an unknown name).
ValueType valueType(std::string_view name);
/// Bytes of one value of @p t; 0 for str and bytes.
unsigned valueSize(ValueType t) noexcept;
/// A Python int as the low @p bits of a two's-complement value (TypeError
/// for a non-int, ValueError naming @p what when it does not fit).
std::uint64_t intBits(const py::handle &value, unsigned bits, bool sgn, const std::string &what);
/// Little-endian bytes to a Python value of type @p t (ValueError when the
/// size does not fit it).
py::object decodeValue(const std::vector<std::uint8_t> &bytes, ValueType t, std::string_view what);
/// A Python value to little-endian bytes as @p t (TypeError for a value of
/// the wrong kind, ValueError out of range).
std::vector<std::uint8_t> encodeValue(const py::handle &value, ValueType t);

// ---- no half-made instances (module.cpp). pybind11 hands a method of an
// instance made by T.__new__(T) without __init__ uninitialised memory as
// its object; so no class of the module has such instances:
/// Instances of @p cls come only from the module's functions: its __new__
/// raises TypeError.
void madeByEcmxfOnly(const py::handle &cls);
/// Instances of @p cls come whole out of its __new__ (a def_static
/// "__new__" that constructs); its __init__ is then a no-op.
void constructedByNew(const py::handle &cls);

// ---- plain CPython methods (no pybind11 dispatch: the hot paths,
// Cyclic.cycle() and Sdo.upload())
/// The C++ object a pybind11 instance @p self of T holds, or nullptr when
/// it holds none.
template <class T>
T *instanceOf(PyObject *self) noexcept
{
	static py::detail::type_info *const ti = py::detail::get_type_info(typeid(T));
	auto *inst = reinterpret_cast<py::detail::instance *>(self);
	const py::detail::value_and_holder vh = inst->get_value_and_holder(ti, false);
	return vh.inst && vh.holder_constructed() ? vh.value_ptr<T>() : nullptr;
}
/// Sets the Python error of the C++ exception being handled, through
/// the translators pybind11 would use (the module's included); call it in
/// a catch block. Returns nullptr, for `return setPythonError();`.
PyObject *setPythonError() noexcept;
/// Adds @p def to @p cls as a plain CPython method.
void addMethod(const py::handle &cls, PyMethodDef &def);

// ---- the parts of the module
py::class_<DeviceObject> bindDevice(py::module_ &m);
void bindCyclic(py::module_ &m);
/// The ECM-XF's views on @p device (chip.cpp).
void bindChip(py::module_ &m, py::class_<DeviceObject> &device);
/// The ECM-SK's views on @p device (board.cpp).
void bindBoard(py::module_ &m, py::class_<DeviceObject> &device);
/// An ecmxf::Event as the dict Device.events() yields.
py::dict eventDict(const Event &e);
/// The Python Device's session (TypeError for anything else).
std::shared_ptr<Session> sessionOf(const py::handle &device);

} // namespace ecmxf::python
