// SPDX-License-Identifier: MIT
// ecmxf.Cyclic: the cyclic exchange (ecmxf::Cyclic) over the process
// image of Device.bring_up(), the image's bytes through the buffer
// protocol (memoryview, numpy: no copies), typed entries by name or
// index, CiA-402 axes, and the loops that run in C++ (run(), csp_move(),
// run_until_done()) while Python only samples.
//
// cycle() is a plain CPython method (METH_NOARGS), not a pybind11
// function: pybind11's dispatcher allocates its argument vectors on every
// call, and the cyclic path allocates nothing in C++ (tests/python,
// test_alloc.py, counts it).

#include "binding.hpp"

#include <cerrno>
#include <cstdio>
#include <chrono>
#include <thread>

#include <pybind11/stl.h>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

namespace ecmxf::python {

namespace {

/// The process image, shared by the Cyclic, its entries and the buffers
/// Python holds (a memoryview keeps it alive after the Cyclic closes).
struct ImageHolder {
	explicit ImageHolder(std::vector<SlavePdos> pdos) : image(std::move(pdos)) {}
	ProcessImage image;
};

/// The exporter of cyc.outputs / cyc.inputs.
struct ImageBuffer {
	std::shared_ptr<ImageHolder> holder;
	bool output = false;
};

/// A typed entry of the image (cyc.output() / cyc.input()).
struct Entry {
	std::shared_ptr<ImageHolder> holder;
	bool output = false;
	std::uint32_t bit = 0; ///< in the frame
	unsigned bits = 0;
	bool isBool = false;
	ValueType type = ValueType::U32;
	std::string what;
};

} // namespace

/// What a Python Cyclic holds.
class CyclicObject
{
public:
	CyclicObject(std::shared_ptr<Session> s, double period, bool buffered) : session_(std::move(s))
	{
		Device &d = session_->device("Cyclic");
		if (!session_->broughtUp)
			throw py::value_error("Cyclic needs the bus brought up by Device.bring_up() first (the process "
					      "image is built from what it found)");
		CyclicConfig c = buffered ? CyclicConfig::buffered() : CyclicConfig::motion();
		c.period = seconds(period, "period", 125e-6, 1.0);
		holder_ = std::make_shared<ImageHolder>(session_->pdos);
		cyc_ = std::make_unique<Cyclic>(d, holder_->image, c);
		session_->cyclics.push_back(this);
	}
	~CyclicObject()
	{
		if (!cyc_)
			return;
		// collected while another thread runs a call on the device: wait
		// for it (with the GIL released) rather than stop under its feet
		bool expected = false;
		while (!session_->busy.compare_exchange_weak(expected, true, std::memory_order_acquire)) {
			expected = false;
			py::gil_scoped_release nogil;
			std::this_thread::yield();
		}
		release();
		session_->busy.store(false, std::memory_order_release);
	}
	CyclicObject(const CyclicObject &) = delete;
	CyclicObject &operator=(const CyclicObject &) = delete;

	void close()
	{
		if (!cyc_)
			return;
		Use use(*session_);
		release();
	}

private:
	void release() noexcept
	{
		axes_.clear();
		try {
			cyc_->stop();
		} catch (...) { // the device may be gone already: nothing left to stop
		}
		cyc_.reset();
		std::erase(session_->cyclics, this);
	}

public:
	bool closed() const noexcept { return !cyc_; }
	Cyclic &cyc(const char *what) const
	{
		if (!cyc_)
			throwClosed(what);
		return *cyc_;
	}
	Session &session() const noexcept { return *session_; }
	const std::shared_ptr<ImageHolder> &holder() const noexcept { return holder_; }
	Device &device() const { return session_->device("Cyclic"); }

	/// The allocation-free path: cycle() with the GIL released; -1 when
	/// another thread uses the device.
	int cycleNoGil() noexcept
	{
		bool expected = false;
		if (!session_->busy.compare_exchange_strong(expected, true, std::memory_order_acquire))
			return -1;
		int e;
		Py_BEGIN_ALLOW_THREADS
		e = cyc_->cycle().error;
		Py_END_ALLOW_THREADS
		session_->busy.store(false, std::memory_order_release);
		return e;
	}

	std::vector<std::unique_ptr<Cia402Axis>> &axes() noexcept { return axes_; }

private:
	std::shared_ptr<Session> session_;
	std::shared_ptr<ImageHolder> holder_;
	std::unique_ptr<Cyclic> cyc_;
	std::vector<std::unique_ptr<Cia402Axis>> axes_;
};

void Session::close()
{
	if (busy.load(std::memory_order_acquire))
		throwBusy();
	while (!cyclics.empty())
		cyclics.back()->close();
	verbs.reset();
}

namespace {

/// cyc.axis(): a CiA-402 drive on the Cyclic's image (owned by the Cyclic,
/// which the Python Axis keeps alive).
struct AxisObject {
	py::object owner; ///< the Python Cyclic
	CyclicObject *cyc = nullptr;
	Cia402Axis *axis = nullptr;

	Cia402Axis &get() const
	{
		(void)cyc->cyc("Axis");
		return *axis;
	}
};

std::string hex(std::uint16_t index, std::uint8_t sub)
{
	char b[16];
	std::snprintf(b, sizeof b, "0x%04X:%02X", index, sub);
	return b;
}

Entry makeEntry(CyclicObject &c, bool output, std::int64_t pos, const py::object &key, std::int64_t sub,
		const std::optional<std::string> &type)
{
	(void)c.cyc(output ? "output()" : "input()");
	ProcessImage &img = c.holder()->image;
	const std::size_t p = position(pos);
	const bool byName = py::isinstance<py::str>(key);
	if (!byName && !(py::isinstance<py::int_>(key) && !py::isinstance<py::bool_>(key)))
		throw py::type_error(std::string("an entry is named by its name (str) or its object index (int), not ") +
				     Py_TYPE(key.ptr())->tp_name);
	const std::string name = byName ? key.cast<std::string>() : std::string();
	const std::uint16_t idx = byName ? 0 : index16(key.cast<std::int64_t>());
	const std::uint8_t si = sub8(sub);
	const PdoEntryInfo *info = nullptr;
	if (!byName)
		info = output ? &img.outputEntry(p, idx, si) : &img.inputEntry(p, idx, si);
	// the library's lookup and width check: through an OutputVar/InputVar
	// of the type asked for
	auto place = [&](auto tag) {
		using T = decltype(tag);
		if (output) {
			const OutputVar<T> v = byName ? img.output<T>(p, name) : img.output<T>(p, idx, si);
			return std::pair{ v.bitOffset(), v.bitLength() };
		}
		const InputVar<T> v = byName ? img.input<T>(p, name) : img.input<T>(p, idx, si);
		return std::pair{ v.bitOffset(), v.bitLength() };
	};
	Entry e;
	e.holder = c.holder();
	e.output = output;
	std::string t = type.value_or("");
	if (t.empty()) {
		const unsigned bits = byName ? place(std::uint64_t{}).second : info->bitLength;
		t = bits == 1 ? "bool" : bits <= 8 ? "u8" : bits <= 16 ? "u16" : bits <= 32 ? "u32" : "u64";
	}
	std::pair<std::uint32_t, unsigned> pl;
	if (t == "bool") {
		e.isBool = true;
		pl = place(bool{});
	} else {
		e.type = valueType(t);
		switch (e.type) {
		case ValueType::U8: pl = place(std::uint8_t{}); break;
		case ValueType::U16: pl = place(std::uint16_t{}); break;
		case ValueType::U32: pl = place(std::uint32_t{}); break;
		case ValueType::U64: pl = place(std::uint64_t{}); break;
		case ValueType::I8: pl = place(std::int8_t{}); break;
		case ValueType::I16: pl = place(std::int16_t{}); break;
		case ValueType::I32: pl = place(std::int32_t{}); break;
		case ValueType::I64: pl = place(std::int64_t{}); break;
		case ValueType::F32: pl = place(float{}); break;
		case ValueType::F64: pl = place(double{}); break;
		default: throw py::value_error("an image entry is bool, an integer or a real type, not '" + t + "'");
		}
	}
	e.bit = pl.first;
	e.bits = pl.second;
	e.what = std::string(output ? "output" : "input") + " of slave " + std::to_string(p) + " " +
		 (byName ? "'" + name + "'" : hex(idx, si)) + " (" + t + ")";
	return e;
}

const std::uint8_t *entryBase(const Entry &e)
{
	ProcessImage &img = e.holder->image;
	return e.output ? img.outputs().data() : img.inputs().data();
}

py::object entryGet(const Entry &e)
{
	const std::uint64_t raw = detail::readBits(entryBase(e) + e.bit / 8, e.bit % 8, e.bits);
	if (e.isBool)
		return py::bool_(raw != 0);
	switch (e.type) {
	case ValueType::I8: case ValueType::I16: case ValueType::I32: case ValueType::I64:
		return py::int_(detail::decode<std::int64_t>(raw, e.bits));
	case ValueType::F32: return py::float_(static_cast<double>(detail::decode<float>(raw, e.bits)));
	case ValueType::F64: return py::float_(detail::decode<double>(raw, e.bits));
	default: return py::int_(raw);
	}
}

void entrySet(const Entry &e, const py::object &value)
{
	if (!e.output)
		throw py::type_error(e.what + " is an input: read-only");
	std::uint64_t raw;
	if (e.isBool) {
		if (!py::isinstance<py::bool_>(value) && !py::isinstance<py::int_>(value))
			throw py::type_error("a bool entry takes bool or int, not " +
					     std::string(Py_TYPE(value.ptr())->tp_name));
		raw = intBits(value, 1, false, e.what);
	} else {
		if (e.type == ValueType::F32 || e.type == ValueType::F64) {
			const std::vector<std::uint8_t> b = encodeValue(value, e.type);
			raw = 0;
			for (std::size_t i = 0; i < b.size(); i++)
				raw |= std::uint64_t{ b[i] } << (8 * i);
		} else {
			(void)encodeValue(value, e.type); // the type's checks: an int in the type's range
			const bool sgn = e.type == ValueType::I8 || e.type == ValueType::I16 || e.type == ValueType::I32 ||
					 e.type == ValueType::I64;
			raw = intBits(value, e.bits, sgn, e.what);
		}
	}
	ProcessImage &img = e.holder->image;
	detail::writeBits(img.outputs().data() + e.bit / 8, e.bit % 8, e.bits, raw);
}

py::dict resultDict(const CycleResult &r)
{
	py::dict d;
	d["error"] = r.error;
	d["message"] = std::string(r.message);
	d["commands"] = r.commands;
	d["frames_pushed"] = r.framesPushed;
	d["frames_popped"] = r.framesPopped;
	d["inputs_updated"] = r.inputsUpdated;
	d["wkc_read"] = r.wkcRead;
	d["wkc"] = r.wkc;
	d["expected_wkc"] = r.expectedWkc;
	d["wkc_ok"] = r.wkcOk;
	d["ecat_state"] = r.ecatState;
	d["rx_fifo_count"] = r.rxFifoCount;
	d["tx_fifo_count"] = r.txFifoCount;
	return d;
}

py::dict statsDict(const CyclicStats &s)
{
	py::dict d;
	d["cycles"] = s.cycles;
	d["failed_cycles"] = s.failedCycles;
	d["commands"] = s.commands;
	d["frames_pushed"] = s.framesPushed;
	d["frames_popped"] = s.framesPopped;
	d["rx_refusals"] = s.rxRefusals;
	d["tx_overflows"] = s.txOverflows;
	d["wkc_mismatches"] = s.wkcMismatches;
	d["late_cycles"] = s.lateCycles;
	return d;
}

std::vector<Cia402Axis *> axesOf(CyclicObject &c, const std::vector<AxisObject *> &axes)
{
	std::vector<Cia402Axis *> out;
	for (AxisObject *a : axes) {
		if (!a || a->cyc != &c)
			throw py::value_error("an axis of another Cyclic");
		out.push_back(a->axis);
	}
	return out;
}

/// Samples of @p entries, one row per cycle: [time in s, values...].
struct Recorder {
	std::vector<Entry> entries;
	std::vector<double> rows;
	void reserve(std::size_t cycles) { rows.reserve(cycles * (entries.size() + 1)); }
	void sample(double t)
	{
		if (rows.size() + entries.size() + 1 > rows.capacity())
			return; // full: never allocate in the loop
		rows.push_back(t);
		for (const Entry &e : entries) {
			const std::uint64_t raw = detail::readBits(entryBase(e) + e.bit / 8, e.bit % 8, e.bits);
			double v;
			switch (e.type) {
			case ValueType::I8: case ValueType::I16: case ValueType::I32: case ValueType::I64:
				v = static_cast<double>(detail::decode<std::int64_t>(raw, e.bits));
				break;
			case ValueType::F32: v = static_cast<double>(detail::decode<float>(raw, e.bits)); break;
			case ValueType::F64: v = detail::decode<double>(raw, e.bits); break;
			default: v = e.isBool ? (raw ? 1.0 : 0.0) : static_cast<double>(raw); break;
			}
			rows.push_back(v);
		}
	}
	py::list result() const
	{
		py::list out;
		const std::size_t w = entries.size() + 1;
		for (std::size_t i = 0; i + w <= rows.size(); i += w) {
			py::tuple row(w);
			for (std::size_t j = 0; j < w; j++)
				row[j] = py::float_(rows[i + j]);
			out.append(row);
		}
		return out;
	}
};

Recorder recorder(const std::vector<Entry> &entries, std::size_t cycles)
{
	Recorder r;
	r.entries = entries;
	r.reserve(cycles);
	return r;
}

py::list runCycles(CyclicObject &c, std::int64_t cycles, const std::vector<Entry> &sample)
{
	Cyclic &cyc = c.cyc("run()");
	const auto n = static_cast<std::size_t>(checkedRange(cycles, 0, 100'000'000, "cycles"));
	Recorder rec = recorder(sample, n);
	Device &dev = c.device();
	int error = 0;
	const char *message = "";
	{
		Use use(c.session());
		py::gil_scoped_release nogil;
		const auto t0 = dev.link().now();
		for (std::size_t i = 0; i < n; i++) {
			const CycleResult &r = cyc.cycle();
			if (r.error) {
				error = r.error;
				message = r.message;
				break;
			}
			for (auto &a : c.axes())
				a->update();
			rec.sample(std::chrono::duration<double>(dev.link().now() - t0).count());
			(void)cyc.waitNextCycle();
		}
	}
	if (error)
		throw Error(std::string("Cyclic.run(): ") + message, error);
	return rec.result();
}

py::list cspMove(CyclicObject &c, const std::vector<AxisObject *> &axObjs, const std::vector<std::int32_t> &targets,
		 double duration, const std::vector<Entry> &sample, double settle)
{
	Cyclic &cyc = c.cyc("csp_move()");
	std::vector<Cia402Axis *> axes = axesOf(c, axObjs);
	if (axes.empty() || targets.size() != axes.size())
		throw py::value_error("csp_move(): one target per axis (" + std::to_string(axes.size()) + " axes, " +
				      std::to_string(targets.size()) + " targets)");
	const auto d = seconds(duration, "duration", 0.001, 3600.0);
	const auto st = seconds(settle, "settle", 0.0, 60.0);
	std::vector<std::int32_t> from;
	for (Cia402Axis *a : axes)
		from.push_back(a->position());
	const CspTrajectory traj(from, targets, d);
	const auto period = cyc.config().period;
	Recorder rec = recorder(sample, static_cast<std::size_t>((d + st) / period) + 16);
	Device &dev = c.device();
	{
		Use use(c.session());
		py::gil_scoped_release nogil;
		for (Cia402Axis *a : axes)
			a->startCsp();
		const auto t0 = dev.link().now();
		(void)runUntil(cyc, axes, [&] {
			const auto t = dev.link().now() - t0;
			traj.apply(axes, t + period); // the next cycle's target
			rec.sample(std::chrono::duration<double>(t).count());
			return traj.finished(t - st);
		}, d + st + std::chrono::seconds(2), "the CSP move");
	}
	return rec.result();
}

PyObject *cycleMethod(PyObject *self, PyObject *) noexcept
{
	// no pybind11 dispatch: nothing allocated in C++ on this path
	CyclicObject *c = instanceOf<CyclicObject>(self);
	if (!c) {
		PyErr_SetString(PyExc_TypeError, "Cyclic.cycle(): not an initialised ecmxf.Cyclic");
		return nullptr;
	}
	if (c->closed()) {
		PyErr_SetString(exceptionClass("ClosedError").ptr(), "Cyclic.cycle(): the Cyclic is closed");
		return nullptr;
	}
	const int e = c->cycleNoGil();
	if (e < 0) {
		PyErr_SetString(exceptionClass("BusyError").ptr(), kBusyMessage);
		return nullptr;
	}
	return PyLong_FromLong(e);
}

PyMethodDef gCycleDef = {
	"cycle", &cycleMethod, METH_NOARGS,
	"cycle() -> int\n\nOne exchange: the outputs out, the inputs in (ecmxf::Cyclic::cycle()). Releases the "
	"GIL and allocates nothing in C++. Returns 0, or the cycle's errno value (last_result says more); "
	"it does not raise for a failed cycle (ClosedError on a closed Cyclic)."
};

} // namespace

void bindCyclic(py::module_ &m)
{
	auto buffer = py::class_<ImageBuffer>(m, "_ImageBuffer", py::buffer_protocol());
	buffer
		.def_buffer([](ImageBuffer &b) {
			ProcessImage &img = b.holder->image;
			std::span<std::uint8_t> s = b.output ? img.outputs() : img.inputs();
			return py::buffer_info(s.data(), 1, py::format_descriptor<std::uint8_t>::format(), 1,
					       { static_cast<py::ssize_t>(s.size()) }, { py::ssize_t{ 1 } }, !b.output);
		});

	madeByEcmxfOnly(buffer);

	auto entry = py::class_<Entry>(m, "Entry", "One typed entry of the process image (Cyclic.output(), Cyclic.input()).");
	entry
		.def_property("value", &entryGet, &entrySet, "The entry's value (outputs can be set).")
		.def("get", &entryGet)
		.def("set", &entrySet, py::arg("value"))
		.def_readonly("bit_offset", &Entry::bit, "Offset in bits in the outputs or inputs.")
		.def_readonly("bits", &Entry::bits)
		.def("__repr__", [](const Entry &e) { return "<ecmxf.Entry " + e.what + ">"; });

	madeByEcmxfOnly(entry);

	auto axisClass = py::class_<AxisObject>(m, "Axis",
			       "A CiA-402 drive over a Cyclic's process image (ecmxf::Cia402Axis): requests are "
			       "carried out by the cycles (Cyclic.run_until_done(), run(), csp_move()).")
		.def_property_readonly("position", [](const AxisObject &a) { return a.get().position(); },
				       "Position actual value (0x6064).")
		.def_property_readonly("statusword", [](const AxisObject &a) { return a.get().statusword(); })
		.def_property_readonly("state", [](const AxisObject &a) -> py::object {
			const auto s = a.get().state();
			if (!s)
				return py::none();
			return py::str(std::string(cia402StateName(*s)));
		}, "The CiA-402 state's name, None before the first statusword.")
		.def_property_readonly("enabled", [](const AxisObject &a) { return a.get().enabled(); })
		.def_property_readonly("done", [](const AxisObject &a) { return a.get().done(); })
		.def_property_readonly("failed", [](const AxisObject &a) { return a.get().failed(); })
		.def_property_readonly("failure", [](const AxisObject &a) { return a.get().failureMessage(); })
		.def("enable", [](AxisObject &a) { a.get().enable(); }, "Requests OPERATION ENABLED.")
		.def("disable", [](AxisObject &a) { a.get().disable(); }, "Requests SWITCH ON DISABLED.")
		.def("fault_reset", [](AxisObject &a) { a.get().requestState(Cia402State::SwitchOnDisabled); },
		     "Requests SWITCH ON DISABLED, out of FAULT with a fault reset.")
		.def("set_mode", [](AxisObject &a, std::int64_t mode) {
			a.get().setMode(static_cast<std::int8_t>(
				static_cast<std::int64_t>(checkedRange(mode + 128, 0, 255, "mode + 128")) - 128));
		}, py::arg("mode"), "Modes of operation (0x6060): 1 PP, 3 PV, 6 HM, 8 CSP.")
		.def("move_to", [](AxisObject &a, std::int64_t target, bool relative) {
			PpMove mv;
			mv.relative = relative;
			a.get().moveTo(static_cast<std::int32_t>(
					       static_cast<std::int64_t>(checkedRange(target, INT32_MIN, INT32_MAX, "target"))),
				       mv);
		}, py::arg("target"), py::arg("relative") = false, "PP: a set point (mode 1, enabled).")
		.def("set_velocity", [](AxisObject &a, std::int64_t v) {
			a.get().setVelocity(static_cast<std::int32_t>(
				static_cast<std::int64_t>(checkedRange(v, INT32_MIN, INT32_MAX, "velocity"))));
		}, py::arg("velocity"), "PV: the target velocity (mode 3, enabled).")
		.def("home", [](AxisObject &a, std::optional<std::int64_t> method) {
			HomingParams p;
			if (method)
				p.method = static_cast<std::int8_t>(
					static_cast<std::int64_t>(checkedRange(*method, -128, 127, "homing method")));
			a.get().home(p);
		}, py::arg("method") = py::none(), "HM: homing (mode 6, enabled).")
		.def("start_csp", [](AxisObject &a) { a.get().startCsp(); }, "CSP: follow set_csp_target() from now.")
		.def("set_csp_target", [](AxisObject &a, std::int64_t p) {
			a.get().setCspTarget(static_cast<std::int32_t>(
				static_cast<std::int64_t>(checkedRange(p, INT32_MIN, INT32_MAX, "CSP target"))));
		}, py::arg("position"))
		.def("update", [](AxisObject &a) { a.get().update(); },
		     "One step of the request (after each cycle() of a Python loop).");

	madeByEcmxfOnly(axisClass);

	auto cls = py::class_<CyclicObject>(m, "Cyclic",
					    "The cyclic exchange over the process image of Device.bring_up(); a "
					    "context manager. outputs / inputs: memoryviews of the image (no copies).")
		.def_static("__new__", [](const py::object &, const py::object &device, double period, bool buffered) {
			return std::make_unique<CyclicObject>(sessionOf(device), period, buffered);
		}, py::arg("cls"), py::arg("device"), py::arg("period") = 0.001, py::arg("buffered") = false,
		     "A Cyclic over device (brought up with bring_up()). period in s (125 us .. 1 s); buffered: "
		     "a deep RxFIFO (CyclicConfig::buffered) instead of the motion fill level.")
		.def("start", [](CyclicObject &c) { c.cyc("start()").start(); }, "Starts the exchange.")
		.def("stop", [](CyclicObject &c) { c.cyc("stop()").stop(); })
		.def("close", &CyclicObject::close, "Stops and releases the exchange; the buffers stay readable.")
		.def_property_readonly("closed", &CyclicObject::closed)
		.def("__enter__", [](py::object self) { return self; })
		.def("__exit__", [](CyclicObject &c, const py::object &, const py::object &, const py::object &) {
			c.close();
			return false;
		})
		.def("wait_next_cycle", [](CyclicObject &c) {
			Cyclic &cyc = c.cyc("wait_next_cycle()");
			Use use(c.session());
			py::gil_scoped_release nogil;
			return cyc.waitNextCycle();
		}, "Waits for the next cycle boundary (GIL released); 0 or an errno value.")
		.def_property_readonly("outputs", [](CyclicObject &c) {
			(void)c.cyc("outputs");
			return py::memoryview(py::cast(ImageBuffer{ c.holder(), true }));
		}, "The output image, writable memoryview of bytes (numpy.frombuffer() views it without a copy).")
		.def_property_readonly("inputs", [](CyclicObject &c) {
			(void)c.cyc("inputs");
			return py::memoryview(py::cast(ImageBuffer{ c.holder(), false }));
		}, "The input image, read-only memoryview.")
		.def("output_offset", [](const CyclicObject &c, std::int64_t pos) {
			return c.holder()->image.outputOffset(position(pos));
		}, py::arg("position"), "Where the slave's outputs start in outputs.")
		.def("input_offset", [](const CyclicObject &c, std::int64_t pos) {
			return c.holder()->image.inputOffset(position(pos));
		}, py::arg("position"))
		.def("output", [](CyclicObject &c, std::int64_t pos, const py::object &key, std::int64_t sub,
				  const std::optional<std::string> &type) { return makeEntry(c, true, pos, key, sub, type); },
		     py::arg("position"), py::arg("entry"), py::arg("sub") = 0, py::arg("type") = py::none(),
		     "An output entry by name ('Controlword') or index (0x6040, sub); type 'bool', 'u8'..'i64', "
		     "'f32', 'f64' (None: unsigned of the entry's width).")
		.def("input", [](CyclicObject &c, std::int64_t pos, const py::object &key, std::int64_t sub,
				 const std::optional<std::string> &type) { return makeEntry(c, false, pos, key, sub, type); },
		     py::arg("position"), py::arg("entry"), py::arg("sub") = 0, py::arg("type") = py::none(),
		     "An input entry, as output().")
		.def_property_readonly("last_result", [](const CyclicObject &c) {
			return resultDict(c.cyc("last_result").lastResult());
		}, "The last cycle's CycleResult as a dict.")
		.def_property_readonly("stats", [](const CyclicObject &c) { return statsDict(c.cyc("stats").stats()); })
		.def("axis", [](py::object self, std::int64_t pos, const std::vector<std::int64_t> &modes) {
			CyclicObject &c = self.cast<CyclicObject &>();
			(void)c.cyc("axis()");
			Cia402AxisConfig ac;
			for (const std::int64_t md : modes)
				ac.modes.push_back(static_cast<std::int8_t>(
					static_cast<std::int64_t>(checkedRange(md, -128, 127, "mode"))));
			auto axis = std::make_unique<Cia402Axis>(c.device(), c.holder()->image, position(pos), ac);
			AxisObject a{ self, &c, axis.get() };
			c.axes().push_back(std::move(axis));
			return a;
		}, py::arg("position"), py::arg("modes") = std::vector<std::int64_t>{ 8 },
		     "A CiA-402 axis on the drive at position, for the modes given (1 PP, 3 PV, 6 HM, 8 CSP).")
		.def("run", [](CyclicObject &c, std::int64_t cycles, const std::vector<Entry> &sample) {
			return runCycles(c, cycles, sample);
		}, py::arg("cycles"), py::arg("sample") = std::vector<Entry>{},
		     "Runs cycles in C++ (cycle(), the axes' update(), wait_next_cycle()) with the GIL released; "
		     "returns one row per cycle: (time in s, the sample entries' values...).")
		.def("run_until_done", [](CyclicObject &c, const std::vector<AxisObject *> &axObjs, double timeout) {
			Cyclic &cyc = c.cyc("run_until_done()");
			std::vector<Cia402Axis *> axes = axesOf(c, axObjs);
			Use use(c.session());
			py::gil_scoped_release nogil;
			return runUntilDone(cyc, axes, seconds(timeout, "timeout", 0.0, 3600.0));
		}, py::arg("axes"), py::arg("timeout") = 2.0,
		     "Runs cycles in C++ until every axis's request is done (Error if one fails or on timeout); "
		     "the cycles it took.")
		.def("csp_move", &cspMove, py::arg("axes"), py::arg("targets"), py::arg("duration"),
		     py::arg("sample") = std::vector<Entry>{}, py::arg("settle") = 0.05,
		     "A synchronized CSP move of axes to targets in duration s (cosine profile, "
		     "ecmxf::CspTrajectory), run in C++; returns the samples as run() does.");
	constructedByNew(cls);
	// cycle(): a plain CPython method, no pybind11 dispatch
	addMethod(cls, gCycleDef);
}

} // namespace ecmxf::python
