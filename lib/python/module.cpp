// SPDX-License-Identifier: MIT
// ecmxf._ecmxf: the module, its exception hierarchy (the library's errors
// mapped one to one), the argument checks and value conversions the
// views share, and the free functions (Documentation/python.rst).

#include "binding.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <pybind11/stl.h>

#include <ecmxf/error.hpp>
#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/trace/trace.hpp>

namespace ecmxf::python {

namespace {

// The exception classes, created once at import (module-lifetime
// references: the module object keeps them alive too).
struct Exceptions {
	PyObject *error = nullptr;
	PyObject *sdoAbort = nullptr;
	PyObject *alStatus = nullptr;
	PyObject *timeout = nullptr;
	PyObject *invalid = nullptr;
	PyObject *notSupported = nullptr;
	PyObject *closed = nullptr;
	PyObject *busy = nullptr;
} gExc;

PyObject *newException(py::module_ &m, const char *name, PyObject *bases, const char *doc)
{
	const std::string full = std::string("ecmxf.") + name;
	PyObject *cls = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases, nullptr);
	if (!cls)
		throw py::error_already_set();
	m.add_object(name, py::handle(cls)); // steals nothing: add_object increfs
	return cls;
}

PyObject *tuple2(PyObject *a, PyObject *b)
{
	return py::make_tuple(py::handle(a), py::handle(b)).release().ptr();
}

// Raises @p cls(message) with the library error's fields as attributes.
void raise(PyObject *cls, const Error &e)
{
	py::object exc = py::reinterpret_borrow<py::object>(cls)(e.what());
	exc.attr("errno") = e.errnoValue();
	if (e.errorStatus())
		exc.attr("error_status") = *e.errorStatus();
	else
		exc.attr("error_status") = py::none();
	if (const auto *s = dynamic_cast<const SdoError *>(&e)) {
		exc.attr("code") = s->abortCode();
		exc.attr("text") = std::string(sdoAbortText(s->abortCode()));
	}
	if (const auto *a = dynamic_cast<const AlStatusError *>(&e)) {
		exc.attr("code") = a->alStatusCode();
		exc.attr("text") = std::string(alStatusText(a->alStatusCode()));
		exc.attr("slave") = a->slave();
		exc.attr("requested") = stateName(a->requested());
		exc.attr("reached") = stateName(a->reached());
	}
	PyErr_SetObject(cls, exc.ptr());
}

void translate(std::exception_ptr p)
{
	try {
		std::rethrow_exception(p);
	} catch (const SdoError &e) {
		raise(gExc.sdoAbort, e);
	} catch (const AlStatusError &e) {
		raise(gExc.alStatus, e);
	} catch (const Error &e) {
		switch (e.errnoValue()) {
		case ETIMEDOUT:
			raise(gExc.timeout, e);
			break;
		case EINVAL:
			raise(gExc.invalid, e);
			break;
		case ENOTSUP:
			raise(gExc.notSupported, e);
			break;
		default:
			raise(gExc.error, e);
			break;
		}
	}
}

const struct {
	const char *name;
	ValueType type;
	unsigned size;
} kValueTypes[] = {
	{ "u8", ValueType::U8, 1 },   { "u16", ValueType::U16, 2 }, { "u32", ValueType::U32, 4 },
	{ "u64", ValueType::U64, 8 }, { "i8", ValueType::I8, 1 },   { "i16", ValueType::I16, 2 },
	{ "i32", ValueType::I32, 4 }, { "i64", ValueType::I64, 8 }, { "f32", ValueType::F32, 4 },
	{ "f64", ValueType::F64, 8 }, { "str", ValueType::Str, 0 }, { "bytes", ValueType::Bytes, 0 },
};

bool isSigned(ValueType t) noexcept
{
	return t == ValueType::I8 || t == ValueType::I16 || t == ValueType::I32 || t == ValueType::I64;
}

std::string traceDecode(const std::string &path)
{
	std::ifstream in(path);
	if (!in)
		throw Error("cannot open the trace '" + path + "': " + std::strerror(errno), errno ? errno : EIO);
	std::ostringstream out;
	(void)decodeTrace(in, out);
	return out.str();
}

} // namespace

// ---------------------------------------------------------------- helpers

[[noreturn]] void throwClosed(std::string_view what)
{
	PyErr_SetString(gExc.closed, (std::string(what) + ": the device is closed").c_str());
	throw py::error_already_set();
}

[[noreturn]] void throwBusy()
{
	PyErr_SetString(gExc.busy, kBusyMessage);
	throw py::error_already_set();
}

PyObject *setPythonError() noexcept
{
	try {
		if (py::detail::apply_exception_translators(
			    py::detail::get_local_internals().registered_exception_translators))
			return nullptr;
		if (py::detail::apply_exception_translators(py::detail::get_internals().registered_exception_translators))
			return nullptr;
		PyErr_SetString(PyExc_SystemError, "ecmxf: a C++ exception no translator knows");
	} catch (...) {
		PyErr_SetString(PyExc_SystemError, "ecmxf: translating a C++ exception failed");
	}
	return nullptr;
}

void addMethod(const py::handle &cls, PyMethodDef &def)
{
	PyObject *descr = PyDescr_NewMethod(reinterpret_cast<PyTypeObject *>(cls.ptr()), &def);
	if (!descr)
		throw py::error_already_set();
	cls.attr(def.ml_name) = py::reinterpret_steal<py::object>(descr);
}

py::object exceptionClass(const char *name)
{
	return py::module_::import("ecmxf._ecmxf").attr(name);
}

void madeByEcmxfOnly(const py::handle &cls)
{
	const std::string name = py::str(cls.attr("__name__"));
	cls.attr("__new__") = py::staticmethod(py::cpp_function([name](const py::args &, const py::kwargs &) -> py::object {
		throw py::type_error("ecmxf." + name + " objects are made by ecmxf (e.g. Device.slaves(), "
							"Cyclic.output()), not directly");
	}));
}

void constructedByNew(const py::handle &cls)
{
	// after __new__ has constructed the object, Python calls __init__ with
	// the same arguments: nothing is left to do (named otherwise: pybind11
	// gives a function named __init__ a constructor's dispatch)
	cls.attr("__init__") = py::cpp_function([](const py::args &, const py::kwargs &) {},
						py::name("_constructed_by_new"), py::is_method(cls),
						"The object was made whole by __new__: nothing to do.");
}

std::uint64_t checkedRange(std::int64_t v, std::int64_t lo, std::int64_t hi, const char *what)
{
	if (v < lo || v > hi)
		throw py::value_error(std::string(what) + " " + std::to_string(v) + " is outside " +
				      std::to_string(lo) + ".." + std::to_string(hi));
	return static_cast<std::uint64_t>(v);
}

std::chrono::nanoseconds seconds(double s, const char *what, double lo, double hi)
{
	if (!(s >= lo && s <= hi))
		throw py::value_error(std::string(what) + " " + std::to_string(s) + " s is outside " +
				      std::to_string(lo) + ".." + std::to_string(hi) + " s");
	return std::chrono::nanoseconds(static_cast<std::int64_t>(s * 1e9));
}

std::vector<std::uint8_t> bytesOf(const py::handle &value, const char *what)
{
	if (!py::isinstance<py::bytes>(value) && !py::isinstance<py::bytearray>(value) &&
	    !py::isinstance<py::memoryview>(value))
		throw py::type_error(std::string(what) + " must be bytes, bytearray or memoryview, not " +
				     Py_TYPE(value.ptr())->tp_name);
	const std::string s = py::bytes(py::reinterpret_borrow<py::object>(value));
	return { s.begin(), s.end() };
}

std::uint8_t position(std::int64_t v)
{
	return static_cast<std::uint8_t>(checkedRange(v, 0, kMaxSlavePosition, "slave position"));
}

std::uint16_t index16(std::int64_t v)
{
	return static_cast<std::uint16_t>(checkedRange(v, 0, 0xFFFF, "object index"));
}

std::uint8_t sub8(std::int64_t v)
{
	return static_cast<std::uint8_t>(checkedRange(v, 0, 0xFF, "subindex"));
}

ValueType valueType(std::string_view name)
{
	std::string names;
	for (const auto &t : kValueTypes) {
		if (name == t.name)
			return t.type;
		names.append(names.empty() ? "" : ", ").append(t.name);
	}
	throw py::value_error("unknown value type '" + std::string(name) + "' (one of " + names + ")");
}

unsigned valueSize(ValueType t) noexcept
{
	for (const auto &v : kValueTypes)
		if (v.type == t)
			return v.size;
	return 0;
}

py::object decodeValue(const std::vector<std::uint8_t> &bytes, ValueType t, std::string_view what)
{
	if (t == ValueType::Bytes)
		return py::bytes(reinterpret_cast<const char *>(bytes.data()), bytes.size());
	if (t == ValueType::Str) {
		std::size_t n = bytes.size();
		while (n > 0 && bytes[n - 1] == 0)
			n--;
		PyObject *s = PyUnicode_DecodeUTF8(reinterpret_cast<const char *>(bytes.data()),
						   static_cast<Py_ssize_t>(n), "replace");
		if (!s)
			throw py::error_already_set();
		return py::reinterpret_steal<py::object>(s);
	}
	const unsigned size = valueSize(t);
	if (bytes.size() != size)
		throw py::value_error(std::string(what) + " has " + std::to_string(bytes.size()) +
				      (bytes.size() == 1 ? " byte" : " bytes") + ", not the " + std::to_string(size) +
				      " of the type asked for");
	std::uint64_t u = 0;
	for (unsigned i = 0; i < size; i++)
		u |= std::uint64_t{ bytes[i] } << (8 * i);
	if (t == ValueType::F32) {
		float f;
		const auto u32 = static_cast<std::uint32_t>(u);
		std::memcpy(&f, &u32, sizeof f);
		return py::float_(static_cast<double>(f));
	}
	if (t == ValueType::F64) {
		double d;
		std::memcpy(&d, &u, sizeof d);
		return py::float_(d);
	}
	if (isSigned(t)) {
		const unsigned bits = 8 * size;
		if (bits < 64 && ((u >> (bits - 1)) & 1u))
			u |= ~std::uint64_t{ 0 } << bits;
		return py::int_(static_cast<std::int64_t>(u));
	}
	return py::int_(u);
}

std::uint64_t intBits(const py::handle &value, unsigned bits, bool sgn, const std::string &what)
{
	int overflow = 0;
	const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
	if (v == -1 && PyErr_Occurred())
		throw py::error_already_set();
	bool fits;
	std::uint64_t u = 0;
	if (overflow > 0 && !sgn && bits == 64) {
		const unsigned long long uu = PyLong_AsUnsignedLongLong(value.ptr());
		fits = !(uu == static_cast<unsigned long long>(-1) && PyErr_Occurred());
		PyErr_Clear();
		u = uu;
	} else if (overflow) {
		fits = false;
	} else if (sgn) {
		const long long lo = bits >= 64 ? INT64_MIN : -(1LL << (bits - 1));
		const long long hi = bits >= 64 ? INT64_MAX : (1LL << (bits - 1)) - 1;
		fits = v >= lo && v <= hi;
		u = static_cast<std::uint64_t>(v);
	} else {
		fits = v >= 0 && (bits >= 64 || static_cast<unsigned long long>(v) < (1ULL << bits));
		u = static_cast<std::uint64_t>(v);
	}
	if (!fits)
		throw py::value_error("value " + py::repr(value).cast<std::string>() + " is outside " + what + " (" +
				      (sgn ? "signed" : "unsigned") + ", " + std::to_string(bits) + " bits)");
	if (bits < 64)
		u &= (std::uint64_t{ 1 } << bits) - 1;
	return u;
}

std::vector<std::uint8_t> encodeValue(const py::handle &value, ValueType t)
{
	if (t == ValueType::Bytes)
		return bytesOf(value, "a 'bytes' value");
	if (t == ValueType::Str) {
		if (!py::isinstance<py::str>(value))
			throw py::type_error(std::string("a 'str' value must be str, not ") + Py_TYPE(value.ptr())->tp_name);
		const std::string s = value.cast<std::string>();
		return { s.begin(), s.end() };
	}
	const unsigned size = valueSize(t);
	std::uint64_t u = 0;
	if (t == ValueType::F32 || t == ValueType::F64) {
		if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value))
			throw py::type_error(std::string("a real value must be float or int, not ") +
					     Py_TYPE(value.ptr())->tp_name);
		const double d = value.cast<double>();
		if (t == ValueType::F32) {
			const auto f = static_cast<float>(d);
			std::uint32_t u32;
			std::memcpy(&u32, &f, sizeof u32);
			u = u32;
		} else {
			std::memcpy(&u, &d, sizeof u);
		}
	} else {
		if (!py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value))
			throw py::type_error(std::string("an integer value must be int, not ") +
					     Py_TYPE(value.ptr())->tp_name);
		u = intBits(value, 8 * size, isSigned(t),
			    std::string("the range of ") + kValueTypes[static_cast<unsigned>(t)].name);
	}
	std::vector<std::uint8_t> b(size);
	for (unsigned i = 0; i < size; i++)
		b[i] = static_cast<std::uint8_t>(u >> (8 * i));
	return b;
}

} // namespace ecmxf::python

PYBIND11_MODULE(_ecmxf, m)
{
	using namespace ecmxf::python;
	m.doc() = "The C++ core of the ecmxf package (import ecmxf, not this).";

	gExc.error = newException(m, "Error", PyExc_Exception,
				  "A failure the library reports (ecmxf::Error): .errno (a positive errno value, "
				  "e.g. errno.ETIMEDOUT) and .error_status (the chip's error-status byte, or None).");
	gExc.sdoAbort = newException(m, "SdoAbort", gExc.error,
				     "An SDO transfer the slave aborted: .code (the CoE abort code, e.g. "
				     "0x06020000) and .text (its description).");
	gExc.alStatus = newException(m, "AlStatusError", gExc.error,
				     "A state change a slave refused: .code (the AL status code), .text, .slave, "
				     ".requested, .reached.");
	gExc.timeout = newException(m, "Timeout", tuple2(gExc.error, PyExc_TimeoutError),
				    "No answer or no completion in time (errno ETIMEDOUT); also a TimeoutError.");
	gExc.invalid = newException(m, "InvalidArgument", tuple2(gExc.error, PyExc_ValueError),
				    "The library refused an argument (errno EINVAL), e.g. a bad device URI; "
				    "also a ValueError.");
	gExc.notSupported = newException(m, "NotSupportedError", tuple2(gExc.error, PyExc_NotImplementedError),
					 "Not on this master (errno ENOTSUP), e.g. an ECM-XF call on an ECM-SK.");
	gExc.closed = newException(m, "ClosedError", tuple2(gExc.error, PyExc_ValueError),
				   "The device (or the Cyclic) was closed; also a ValueError, as for a closed file.");
	gExc.busy = newException(m, "BusyError", tuple2(gExc.error, PyExc_RuntimeError),
				 "The device is busy with another call: another thread's, or the one calling back into "
				 "Python (a device serves one call at a time).");
	py::register_exception_translator(&translate);

	py::enum_<ecmxf::State>(m, "State", "EtherCAT (AL) states as the chip encodes them.")
		.value("NONE", ecmxf::State::None)
		.value("INIT", ecmxf::State::Init)
		.value("PREOP", ecmxf::State::PreOp)
		.value("BOOT", ecmxf::State::Boot)
		.value("SAFEOP", ecmxf::State::SafeOp)
		.value("OP", ecmxf::State::Op);

	m.def("sdo_abort_text", [](std::int64_t code) {
		return std::string(ecmxf::sdoAbortText(static_cast<std::uint32_t>(
			checkedRange(code, 0, 0xFFFFFFFF, "abort code"))));
	}, py::arg("code"), "The text of an SDO abort code, e.g. 0x06020000 'Object not existing'.");
	m.def("al_status_text", [](std::int64_t code) {
		return std::string(
			ecmxf::alStatusText(static_cast<std::uint16_t>(checkedRange(code, 0, 0xFFFF, "AL status code"))));
	}, py::arg("code"), "The text of an AL status code.");
	m.def("decode_trace", &traceDecode, py::arg("path"),
	      "Decodes a packet trace (Device.start_trace(), Documentation/trace.rst) to text, one line per "
	      "exchange, as `ecmxf-util decode` prints it.");

	auto device = bindDevice(m);
	bindCyclic(m);
	bindChip(m, device);
	bindBoard(m, device);
}
