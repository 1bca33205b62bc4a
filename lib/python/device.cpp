// SPDX-License-Identifier: MIT
// ecmxf.Device: one master (ECM-XF or ECM-SK) from a URI, through the
// verbs both have (MasterVerbs, <ecmxf/verbs.hpp>) and, on an ECM-XF, the
// Device's views; its SDO view; the slave list; the CiA-402 verbs.

#include "binding.hpp"

#include <cerrno>

#include <pybind11/stl.h>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/events/events.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/model/status.hpp>
#include <ecmxf/sk/board.hpp>

#include <deque>

namespace ecmxf::python {

// ---------------------------------------------------------------- Session

MasterVerbs &Session::open() const
{
	if (!verbs)
		throwClosed(uri);
	return *verbs;
}

Device &Session::device(std::string_view what) const
{
	MasterVerbs &m = open();
	Device *d = m.device();
	if (!d)
		throwNotOn(m.kind(), std::string(what) + " is a call of the ECM-XF");
	return *d;
}

Use::Use(Session &s) : s_(s)
{
	bool expected = false;
	if (!s.busy.compare_exchange_strong(expected, true, std::memory_order_acquire))
		throwBusy();
}

namespace {

/// dev.sdo
struct SdoView {
	std::shared_ptr<Session> session;
};

/// One entry of the slave list.
struct SlaveRecord {
	unsigned position = 0;
	std::optional<std::uint32_t> vendor, product, revision;
	std::string name;
	State state = State::None;
	std::optional<std::uint16_t> alStatus;
};

py::object upload(Session &s, std::int64_t pos, std::int64_t index, std::int64_t sub,
		  const std::optional<std::string> &type)
{
	const unsigned p = position(pos);
	const std::uint16_t i = index16(index);
	const std::uint8_t si = sub8(sub);
	std::optional<ValueType> t;
	if (type)
		t = valueType(*type);
	const std::vector<std::uint8_t> b = run(s, [&](MasterVerbs &m) { return m.upload(p, i, si); });
	if (!t) {
		switch (b.size()) {
		case 1: t = ValueType::U8; break;
		case 2: t = ValueType::U16; break;
		case 4: t = ValueType::U32; break;
		case 8: t = ValueType::U64; break;
		default: t = ValueType::Bytes; break;
		}
	}
	return decodeValue(b, *t, "object");
}

void download(Session &s, std::int64_t pos, std::int64_t index, std::int64_t sub, const py::object &value,
	      const std::optional<std::string> &type)
{
	const unsigned p = position(pos);
	const std::uint16_t i = index16(index);
	const std::uint8_t si = sub8(sub);
	ValueType t;
	if (type) {
		t = valueType(*type);
	} else if (py::isinstance<py::str>(value)) {
		t = ValueType::Str;
	} else if (py::isinstance<py::bytes>(value) || py::isinstance<py::bytearray>(value) ||
		   py::isinstance<py::memoryview>(value)) {
		t = ValueType::Bytes;
	} else if ((py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value)) ||
		   py::isinstance<py::float_>(value)) {
		// the type from the object's size: read it first
		const std::size_t n = run(s, [&](MasterVerbs &m) { return m.upload(p, i, si).size(); });
		const bool real = py::isinstance<py::float_>(value);
		const bool negative = !real && value.cast<py::int_>() < py::int_(0);
		switch (n) {
		case 1: t = negative ? ValueType::I8 : ValueType::U8; break;
		case 2: t = negative ? ValueType::I16 : ValueType::U16; break;
		case 4: t = real ? ValueType::F32 : negative ? ValueType::I32 : ValueType::U32; break;
		case 8: t = real ? ValueType::F64 : negative ? ValueType::I64 : ValueType::U64; break;
		default:
			throw py::value_error("the object has " + std::to_string(n) +
					      " bytes: give the type (type='u32', 'bytes'...)");
		}
		if (real && n != 4 && n != 8)
			throw py::value_error("a float goes to an object of 4 or 8 bytes, not " + std::to_string(n));
	} else {
		throw py::type_error(std::string("an SDO value is int, float, str or bytes, not ") +
				     Py_TYPE(value.ptr())->tp_name);
	}
	const std::vector<std::uint8_t> b = encodeValue(value, t);
	if (b.empty())
		throw py::value_error("an SDO download carries at least one byte");
	run(s, [&](MasterVerbs &m) { m.download(p, i, si, b); });
}

py::list uploadObject(Session &s, std::int64_t pos, std::int64_t index)
{
	const py::object count = upload(s, pos, index, 0, std::string("u8"));
	py::list out;
	out.append(count);
	const auto n = count.cast<unsigned>();
	for (unsigned sub = 1; sub <= n; sub++)
		out.append(upload(s, pos, index, sub, std::nullopt));
	return out;
}

std::vector<SlaveRecord> slaves(Session &s)
{
	return run(s, [](MasterVerbs &m) {
		std::vector<SlaveRecord> out;
		if (Device *d = m.device()) {
			const unsigned n = d->bus().slaveCount();
			for (unsigned i = 0; i < n; i++) {
				const SlaveInfo info = d->bus().slaveInfo(static_cast<std::uint8_t>(i));
				SlaveRecord r;
				r.position = i;
				r.vendor = info.vendorId;
				r.product = info.productCode;
				r.revision = info.revision;
				r.name = info.name;
				r.state = info.state;
				r.alStatus = info.alStatusCode;
				out.push_back(std::move(r));
			}
			return out;
		}
		for (const SlaveSummary &sum : m.slaves()) {
			SlaveRecord r;
			r.position = sum.position;
			r.vendor = sum.vendorId;
			r.product = sum.productCode;
			r.name = sum.kind;
			r.state = sum.state;
			out.push_back(std::move(r));
		}
		return out;
	});
}

std::shared_ptr<Session> openSession(const std::string &uri, bool bringUp)
{
	auto s = std::make_shared<Session>();
	s->uri = uri;
	{
		py::gil_scoped_release nogil;
		s->verbs = MasterVerbs::open(uri);
		if (bringUp) {
			if (Device *d = s->verbs->device())
				(void)ensureBusUp(*d, true);
			else if (s->verbs->state() == State::Init)
				s->verbs->requestState(State::PreOp);
		}
	}
	return s;
}

void bringUp(Session &s, State target, const std::vector<std::int64_t> &motion, std::int64_t cycleUs)
{
	MasterConfig mc;
	for (const std::int64_t p : motion)
		mc.pdoAssignments.push_back(est584MotionPdos(position(p)));
	mc.init.dc.sync0Ns = static_cast<std::uint32_t>(checkedRange(cycleUs, 125, 100000, "cycle_us") * 1000);
	mc.target = target;
	MasterVerbs &mv = s.open();
	if (sk::Board *b = mv.board()) {
		if (!motion.empty() || cycleUs != 1000)
			throwNotOn(MasterKind::EcmSk, "bring_up(motion=, cycle_us=) are the ECM-XF's (the ECM-SK's drives run "
						      "CSP from its own PDOs)");
		Use use(s);
		py::gil_scoped_release nogil;
		if (target == State::Op)
			sk::bringUpToOp(*b);
		else
			mv.requestState(target);
		return;
	}
	Device &d = s.device("bring_up()");
	Use use(s);
	py::gil_scoped_release nogil;
	Master master(d);
	master.bringUp(mc);
	s.pdos = master.pdos();
	s.broughtUp = true;
}

py::dict pdoMapping(Session &s, std::int64_t pos)
{
	const std::uint8_t p = position(pos);
	Device &d = s.device("pdo_mapping()");
	SlavePdos pdos;
	{
		Use use(s);
		py::gil_scoped_release nogil;
		Master master(d);
		master.rescan();
		pdos = master.readSlavePdos(p);
	}
	auto list = [](const std::vector<PdoEntryInfo> &v) {
		py::list l;
		for (const PdoEntryInfo &e : v)
			l.append(py::dict(py::arg("pdo") = e.pdo, py::arg("index") = e.index, py::arg("sub") = e.sub,
					  py::arg("bits") = e.bitLength, py::arg("bit_offset") = e.bitOffset,
					  py::arg("name") = e.name));
		return l;
	};
	return py::dict(py::arg("outputs") = list(pdos.outputs), py::arg("inputs") = list(pdos.inputs),
			py::arg("output_bytes") = pdos.outputBytes, py::arg("input_bytes") = pdos.inputBytes);
}

/// dev.events(): the chip's events as an iterator. Over /dev/ecmxfN the
/// kernel's (ecmxf::EventSubscriber over generic netlink, the events of
/// that minor, wall time); over every other link an ecmxf::EventDetector
/// over the response headers of INFO_UPDATE polls (link time).
struct EventsObject {
	std::shared_ptr<Session> session; ///< null: ecmxf.kernel_events()
	std::unique_ptr<EventDetector> detector;
	std::unique_ptr<EventSubscriber> subscriber;
	std::uint32_t minor = 0;
	std::chrono::nanoseconds interval{ 0 };
	std::chrono::nanoseconds end{ 0 }; ///< link time (detector) or steady clock (subscriber) of the end
	std::deque<Event> pending;
	bool closed = false;
};

void closeEvents(EventsObject &ev)
{
	ev.closed = true;
	ev.subscriber.reset();
	ev.detector.reset();
	ev.pending.clear();
}

std::chrono::nanoseconds steadyNow()
{
	return std::chrono::steady_clock::now().time_since_epoch();
}

/// The kernel's events of the character device @p path (its minor).
EventsObject subscribe(const std::string &path, std::chrono::nanoseconds duration)
{
	const std::optional<std::uint32_t> minor = KernelLink::minorOf(path);
	if (!minor)
		throw py::value_error("'" + path + "' is not a character device (the kernel's events are those of a "
				      "/dev/ecmxfN)");
	EventsObject ev;
	ev.minor = *minor;
	{
		py::gil_scoped_release nogil;
		ev.subscriber = std::make_unique<EventSubscriber>();
	}
	ev.end = steadyNow() + duration;
	return ev;
}

EventsObject makeEvents(const std::shared_ptr<Session> &s, double duration, double interval)
{
	const auto span = seconds(duration, "duration", 0, 86400);
	const auto every = seconds(interval, "poll_interval", 0.0001, 10);
	Device &d = s->device("events()");
	if (const DeviceUri uri = parseDeviceUri(s->uri); uri.kind == DeviceUri::Kind::Kernel) {
		EventsObject ev = subscribe(uri.path, span);
		ev.session = s;
		return ev;
	}
	EventsObject ev;
	ev.session = s;
	ev.interval = every;
	Use use(*s);
	py::gil_scoped_release nogil;
	ev.detector = std::make_unique<EventDetector>(d);
	const auto now = d.link().now();
	(void)ev.detector->feed(d.chip().infoUpdate(), now); // the baseline
	ev.end = now + span;
	return ev;
}

/// The next event of the kernel's: false when the time is up.
bool nextKernelEvent(EventsObject &ev)
{
	for (;;) {
		const auto left = ev.end - steadyNow();
		if (left <= std::chrono::nanoseconds(0))
			return false;
		std::optional<Event> e;
		{
			py::gil_scoped_release nogil;
			// woken at least every 200 ms for Python's signals (Ctrl-C)
			e = ev.subscriber->next(std::min(std::chrono::duration_cast<std::chrono::milliseconds>(left) +
								 std::chrono::milliseconds(1),
							 std::chrono::milliseconds(200)));
		}
		if (PyErr_CheckSignals() != 0)
			throw py::error_already_set();
		if (e && e->minor == ev.minor) {
			ev.pending.push_back(std::move(*e));
			return true;
		}
	}
}

/// The next events of the detector: false when the time is up.
bool nextPolledEvents(EventsObject &ev)
{
	Device &d = ev.session->device("events");
	Use use(*ev.session);
	py::gil_scoped_release nogil;
	for (;;) {
		const auto now = d.link().now();
		for (Event &e : ev.detector->feed(d.chip().infoUpdate(), now))
			ev.pending.push_back(std::move(e));
		for (Event &e : ev.detector->poll(now))
			ev.pending.push_back(std::move(e));
		if (!ev.pending.empty())
			return true;
		if (now >= ev.end)
			return false;
		d.link().sleepFor(std::min(ev.interval, ev.end - now));
	}
}

py::dict nextEvent(EventsObject &ev)
{
	if (ev.closed)
		throwClosed("events");
	if (ev.session)
		(void)ev.session->open(); // ClosedError once the device is closed
	while (ev.pending.empty())
		if (!(ev.subscriber ? nextKernelEvent(ev) : nextPolledEvents(ev)))
			throw py::stop_iteration();
	const Event e = std::move(ev.pending.front());
	ev.pending.pop_front();
	return eventDict(e);
}

/// One argument of a METH_FASTCALL call: positional @p i, else keyword
/// @p name, else nullptr.
PyObject *argument(PyObject *const *args, Py_ssize_t nargs, PyObject *kwnames, Py_ssize_t i, const char *name)
{
	if (i < nargs)
		return args[i];
	const Py_ssize_t nk = kwnames ? PyTuple_GET_SIZE(kwnames) : 0;
	for (Py_ssize_t k = 0; k < nk; k++)
		if (PyUnicode_CompareWithASCIIString(PyTuple_GET_ITEM(kwnames, k), name) == 0)
			return args[nargs + k];
	return nullptr;
}

/// An int argument (TypeError naming it for anything else; ValueError
/// beyond 64 bits).
std::int64_t intArgument(PyObject *o, const char *name)
{
	if (!PyLong_Check(o))
		throw py::type_error(std::string("Sdo.upload(): ") + name + " must be int, not " + Py_TYPE(o)->tp_name);
	int overflow = 0;
	const long long v = PyLong_AsLongLongAndOverflow(o, &overflow);
	if (overflow)
		throw py::value_error(std::string("Sdo.upload(): ") + name + " is out of range");
	return v;
}

/// Sdo.upload(position, index, sub, type=None) as a METH_FASTCALL |
/// METH_KEYWORDS method: the call an SDO script makes most, without
/// pybind11's dispatcher (its argument vectors and type lookups are a
/// third of what the binding adds to an upload on sim:; Documentation/
/// python.rst, "Performance"). The checks and the conversion are
/// upload()'s, as for every other call.
PyObject *uploadMethod(PyObject *self, PyObject *const *args, Py_ssize_t nargs, PyObject *kwnames) noexcept
{
	static const char *const kNames[] = { "position", "index", "sub", "type" };
	try {
		const SdoView *v = instanceOf<SdoView>(self);
		if (!v)
			throw py::type_error("Sdo.upload(): not an ecmxf.Sdo");
		const Py_ssize_t given = nargs + (kwnames ? PyTuple_GET_SIZE(kwnames) : 0);
		if (nargs > 4 || given > 4)
			throw py::type_error("Sdo.upload() takes position, index, sub and type (" + std::to_string(given) +
					     " arguments given)");
		for (Py_ssize_t k = 0; kwnames && k < PyTuple_GET_SIZE(kwnames); k++) {
			bool known = false;
			for (Py_ssize_t i = nargs; i < 4; i++)
				known = known || PyUnicode_CompareWithASCIIString(PyTuple_GET_ITEM(kwnames, k), kNames[i]) == 0;
			if (!known)
				throw py::type_error("Sdo.upload(): unexpected or repeated keyword argument '" +
						     py::str(PyTuple_GET_ITEM(kwnames, k)).cast<std::string>() + "'");
		}
		std::int64_t n[3];
		for (Py_ssize_t i = 0; i < 3; i++) {
			PyObject *o = argument(args, nargs, kwnames, i, kNames[i]);
			if (!o)
				throw py::type_error(std::string("Sdo.upload(): missing argument '") + kNames[i] + "'");
			n[i] = intArgument(o, kNames[i]);
		}
		std::optional<std::string> type;
		if (PyObject *t = argument(args, nargs, kwnames, 3, kNames[3]); t && t != Py_None) {
			if (!PyUnicode_Check(t))
				throw py::type_error(std::string("Sdo.upload(): type must be str or None, not ") +
						     Py_TYPE(t)->tp_name);
			type = py::handle(t).cast<std::string>();
		}
		return upload(*v->session, n[0], n[1], n[2], type).release().ptr();
	} catch (...) {
		return setPythonError();
	}
}

PyMethodDef gUploadDef = {
	"upload", reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&uploadMethod)),
	METH_FASTCALL | METH_KEYWORDS,
	"upload($self, /, position, index, sub, type=None)\n--\n\n"
	"Uploads object index:sub from the slave at position. type: 'u8' 'u16' 'u32' 'u64' 'i8' 'i16' 'i32' "
	"'i64' 'f32' 'f64' 'str' 'bytes'; None: an unsigned int for objects of 1, 2, 4 or 8 bytes, else bytes. "
	"Raises SdoAbort (.code, .text) when the slave aborts."
};

std::string slaveRepr(const SlaveRecord &r)
{
	char id[64];
	std::snprintf(id, sizeof id, "vendor=0x%08x product=0x%08x", r.vendor.value_or(0), r.product.value_or(0));
	return "<ecmxf.Slave " + std::to_string(r.position) + " " + stateName(r.state) + " " +
	       (r.vendor ? std::string(id) : std::string("identity=?")) + " name='" + r.name + "'>";
}

} // namespace

py::dict eventDict(const Event &e)
{
	auto optional = [](const std::optional<std::uint16_t> &v) { return v ? py::object(py::int_(*v)) : py::none(); };
	py::dict d;
	d["type"] = eventTypeName(e.type);
	d["time"] = std::chrono::duration<double>(e.time).count();
	if (e.type == EventType::State) {
		d["old"] = ecatStateName(static_cast<std::uint8_t>(e.oldValue));
		d["new"] = ecatStateName(static_cast<std::uint8_t>(e.newValue));
	} else {
		d["old"] = e.oldValue;
		d["new"] = e.newValue;
	}
	d["link_up"] = e.linkUp;
	d["error_status"] = e.errStatus;
	d["count"] = e.count;
	d["increase"] = e.increase;
	py::list slaves;
	for (const SlaveAlStatus &st : e.slaves)
		slaves.append(py::make_tuple(st.position, optional(st.alStatus)));
	d["slaves"] = slaves;
	d["al_status"] = optional(e.alStatus);
	// what only the kernel's events say (netlink): None from a detector
	const bool kernel = !e.device.empty();
	d["device"] = kernel ? py::object(py::str(e.device)) : py::none();
	d["seq"] = kernel ? py::object(py::int_(e.seq)) : py::none();
	d["suppressed"] = e.suppressed;
	if (e.type == EventType::PdoLoss) {
		d["loss"] = lossKindName(e.loss);
		d["total"] = e.total;
	}
	if (e.type == EventType::WkcBurstEnd) {
		d["errors"] = e.errors;
		d["duration"] = std::chrono::duration<double>(e.duration).count();
	}
	if (e.type == EventType::Fifo) {
		d["fifo"] = e.fifo == FifoId::Tx ? "tx" : "rx";
		d["mark"] = e.mark;
		d["above"] = e.above;
	}
	if (e.type == EventType::AsyncError) {
		d["command"] = e.cmdCode;
		d["status"] = e.status;
	}
	return d;
}

std::shared_ptr<Session> sessionOf(const py::handle &device)
{
	if (!py::isinstance<DeviceObject>(device))
		throw py::type_error(std::string("expected an ecmxf.Device, not ") + Py_TYPE(device.ptr())->tp_name);
	return device.cast<DeviceObject &>().session;
}

py::class_<DeviceObject> bindDevice(py::module_ &m)
{
	auto slave = py::class_<SlaveRecord>(m, "Slave", "One slave of the bus, as Device.slaves() lists it.");
	slave
		.def_readonly("position", &SlaveRecord::position, "Bus position, from 0.")
		.def_readonly("vendor", &SlaveRecord::vendor, "Vendor ID (0x1018:01 / SII), None when unknown.")
		.def_readonly("product", &SlaveRecord::product, "Product code, None when unknown.")
		.def_readonly("revision", &SlaveRecord::revision, "Revision (ECM-XF), None when unknown.")
		.def_readonly("name", &SlaveRecord::name,
			      "SII device name (ECM-XF); the SET_AXIS type (ECM-SK).")
		.def_readonly("state", &SlaveRecord::state,
			      "EtherCAT state (ECM-SK: the bus's: it has no per-slave states).")
		.def_readonly("al_status", &SlaveRecord::alStatus,
			      "AL status code (register 0x0134, ECM-XF), None on the ECM-SK.")
		.def("__repr__", &slaveRepr);

	madeByEcmxfOnly(slave);

	auto sdo = py::class_<SdoView>(m, "Sdo", "SDO transfers of a Device (dev.sdo).");
	sdo
		.def("download", [](const SdoView &v, std::int64_t pos, std::int64_t index, std::int64_t sub,
				    const py::object &value, const std::optional<std::string> &type) {
			download(*v.session, pos, index, sub, value, type);
		}, py::arg("position"), py::arg("index"), py::arg("sub"), py::arg("value"), py::arg("type") = py::none(),
		     "Downloads value to index:sub. type as for upload(); None: str and bytes as they are, an int "
		     "or float in the object's size (read first).")
		.def("upload_object", [](const SdoView &v, std::int64_t pos, std::int64_t index) {
			return uploadObject(*v.session, pos, index);
		}, py::arg("position"), py::arg("index"),
		     "A whole object, subindex by subindex: [count, sub 1, ..., sub count] (each as upload() "
		     "with type None).");

	madeByEcmxfOnly(sdo);
	addMethod(sdo, gUploadDef); // upload(): a plain CPython method, no pybind11 dispatch

	auto device = py::class_<DeviceObject>(m, "Device",
				 "One master, ECM-XF or ECM-SK, from a device URI: 'sim:', 'sim:<network>', "
				 "'unix:PATH', 'spidev:...', '/dev/ecmxfN', 'sk-sim:', 'sk-unix:PATH', 'sk-spidev:...', 'sk-usb:'. "
				 "A context manager: closed at the end of the with block.")
		.def_static("__new__", [](const py::object &, const std::string &uri, bool bringUpBus) {
			return DeviceObject{ openSession(uri, bringUpBus) };
		}, py::arg("cls"), py::arg("uri"), py::arg("bring_up") = true,
		     "Opens the master uri names. bring_up: a bus no one has initialised is brought to PRE-OP "
		     "(ECM-XF: ECAT_INIT_OP and PRE-OP; ECM-SK: INIT to PRE-OP), as ecmxf-util does.")
		.def("close", [](DeviceObject &d) { d.session->close(); },
		     "Closes the device (and its Cyclics); later calls raise ClosedError. Closing twice is fine.")
		.def_property_readonly("closed", [](const DeviceObject &d) { return !d.session->verbs; })
		.def("__enter__", [](py::object self) { return self; })
		.def("__exit__", [](DeviceObject &d, const py::object &, const py::object &, const py::object &) {
			d.session->close();
			return false;
		})
		.def_property_readonly("uri", [](const DeviceObject &d) { return d.session->uri; })
		.def_property_readonly("kind", [](const DeviceObject &d) {
			return std::string(masterKindName(d.session->open().kind()));
		}, "'ECM-XF' or 'ECM-SK'.")
		.def_property_readonly("sdo", [](const DeviceObject &d) {
			(void)d.session->open();
			return SdoView{ d.session };
		}, "The SDO transfers (Sdo).")
		.def_property_readonly("state", [](DeviceObject &d) {
			return run(*d.session, [](MasterVerbs &mv) { return mv.state(); });
		}, "The bus's EtherCAT state (State).")
		.def("request_state", [](DeviceObject &d, State s) {
			run(*d.session, [s](MasterVerbs &mv) { mv.requestState(s); });
		}, py::arg("state"), "Requests state for the whole bus and waits for it (AlStatusError on refusal).")
		.def("bring_up", [](DeviceObject &d, State target, const std::vector<std::int64_t> &motion,
				    std::int64_t cycleUs) { bringUp(*d.session, target, motion, cycleUs); },
		     py::arg("state") = State::Op, py::arg("motion") = std::vector<std::int64_t>{},
		     py::arg("cycle_us") = 1000,
		     "ECM-XF: the documented bring-up (ecmxf::Master): init with DC at cycle_us, scan, PDO "
		     "configuration (the motion PDOs of est584MotionPdos() on each position in motion), up to "
		     "state, FIFO on. What a Cyclic is built from. ECM-SK: to OP with ecmxf::sk::bringUpToOp() "
		     "(axes detected, drives in CSP), to another state with request_state().")
		.def_property_readonly("slave_count", [](DeviceObject &d) {
			return run(*d.session, [](MasterVerbs &mv) { return mv.slaveCount(); });
		})
		.def("slaves", [](DeviceObject &d) { return slaves(*d.session); }, "The slave list (Slave objects).")
		.def("pdo_mapping", [](DeviceObject &d, std::int64_t pos) { return pdoMapping(*d.session, pos); },
		     py::arg("position"),
		     "ECM-XF: the slave's PDO mapping as read from it: {'outputs': [...], 'inputs': [...], "
		     "'output_bytes', 'input_bytes'}, each entry {'pdo', 'index', 'sub', 'bits', 'bit_offset', "
		     "'name'}.")
		.def("drive_enable", [](DeviceObject &d, std::int64_t pos) {
			const unsigned p = position(pos);
			return run(*d.session, [p](MasterVerbs &mv) { return mv.driveEnable(p); });
		}, py::arg("position"), "CiA-402: the drive to OPERATION ENABLED; the statusword after.")
		.def("drive_disable", [](DeviceObject &d, std::int64_t pos) {
			const unsigned p = position(pos);
			return run(*d.session, [p](MasterVerbs &mv) { return mv.driveDisable(p); });
		}, py::arg("position"), "CiA-402: the drive to SWITCH ON DISABLED; the statusword after.")
		.def("fault_reset", [](DeviceObject &d, std::int64_t pos) {
			const unsigned p = position(pos);
			return run(*d.session, [p](MasterVerbs &mv) { return mv.driveAlarmClear(p); });
		}, py::arg("position"), "CiA-402: the drive out of FAULT; the statusword after.")
		.def("io_read", [](DeviceObject &d, std::int64_t pos) {
			const unsigned p = position(pos);
			return run(*d.session, [p](MasterVerbs &mv) { return mv.ioRead(p); });
		}, py::arg("position"), "ECM-SK: the first 4 input bytes of an I/O slave (ECM-XF: use a Cyclic).")
		.def("io_write", [](DeviceObject &d, std::int64_t pos, std::int64_t value) {
			const unsigned p = position(pos);
			const auto v = static_cast<std::uint32_t>(checkedRange(value, 0, 0xFFFFFFFF, "outputs"));
			run(*d.session, [p, v](MasterVerbs &mv) { mv.ioWrite(p, v); });
		}, py::arg("position"), py::arg("outputs"), "ECM-SK: the first 4 output bytes of an I/O slave.")
		.def("reset", [](DeviceObject &d) { run(*d.session, [](MasterVerbs &mv) { mv.reset(); }); },
		     "Restarts the master (ECM-XF: WARM_RESET; ECM-SK: SW_RESET).")
		.def("firmware_version", [](DeviceObject &d) {
			const FirmwareVersion v = onDevice(*d.session, "firmware_version()",
							   [](Device &dev) { return dev.chip().firmwareVersion(); });
			return py::dict(py::arg("version") = v.version, py::arg("extended") = v.extendedVersion,
					py::arg("series_code") = v.seriesCode, py::arg("build_id") = v.buildId);
		}, "ECM-XF: the chip's firmware version (FIRM_VER_GET): {'version', 'extended', 'series_code', "
		   "'build_id'}.")
		.def("set_data_size", [](DeviceObject &d, std::int64_t size) {
			const auto n = static_cast<std::uint16_t>(checkedRange(size, 32, 1408, "data section size"));
			onDevice(*d.session, "set_data_size()", [n](Device &dev) { dev.chip().setDataSize(n); });
		}, py::arg("size"),
		     "ECM-XF: the SPI data section in bytes (SPI_RECONFIG_OP, 32..1408; 112 at power-on): "
		     "large process images need more than 112 bytes per exchange.")
		.def("start_trace", [](DeviceObject &d, const std::string &path) {
			onDevice(*d.session, "start_trace()", [&path](Device &dev) { dev.startTrace(path); });
		}, py::arg("path"), "ECM-XF: records every exchange to path (decode_trace() reads it).")
		.def("stop_trace", [](DeviceObject &d) {
			onDevice(*d.session, "stop_trace()", [](Device &dev) { dev.stopTrace(); });
		})
		.def("__repr__", [](const DeviceObject &d) {
			return "<ecmxf.Device '" + d.session->uri + "'" + (d.session->verbs ? "" : " closed") + ">";
		});

	constructedByNew(device);

	auto events = py::class_<EventsObject>(m, "Events",
					       "The chip's events as an iterator (Device.events()): dicts with 'type' "
					       "('state', 'link', 'error_status', 'wkc_burst', 'fifo', ...), 'time' (s, link "
					       "time), 'old', 'new', 'link_up', 'error_status', 'count', 'increase', "
					       "'slaves' ((position, AL status) of the slaves not in OP, for a state that "
					       "went down) and 'al_status'.");
	events.def("__iter__", [](py::object self) { return self; })
		.def("__next__", &nextEvent)
		.def("close", [](EventsObject &ev) { closeEvents(ev); },
		     "Ends the iteration now: the netlink socket (over /dev/ecmxfN) closes, next() raises "
		     "ClosedError. Closing twice is fine.")
		.def_property_readonly("closed", [](const EventsObject &ev) { return ev.closed; })
		.def("__enter__", [](py::object self) { return self; })
		.def("__exit__", [](EventsObject &ev, const py::object &, const py::object &, const py::object &) {
			closeEvents(ev);
			return false;
		});
	madeByEcmxfOnly(events);
	device.def("events", [](DeviceObject &d, double duration, double interval) {
		return makeEvents(d.session, duration, interval);
	}, py::arg("duration"), py::arg("poll_interval") = 0.01,
		   "ECM-XF: the chip's events for duration s, as an iterator that ends when the time is up. Over "
		   "/dev/ecmxfN the kernel's (generic netlink, ecmxf::EventSubscriber: the events of that device, "
		   "wall time; poll_interval is not used); over any other link ecmxf::EventDetector over INFO_UPDATE "
		   "polls every poll_interval s of link time, the slaves' AL status codes read for a state that "
		   "went down.");

	m.def("decode_event_message", [](const py::object &msg) {
		const std::vector<std::uint8_t> b = bytesOf(msg, "msg");
		return eventDict(decodeEventMessage(b));
	}, py::arg("msg"),
	      "One whole netlink message of the kernel module's family 'ecmxf' (nlmsghdr, genlmsghdr, "
	      "attributes; ecmxf::decodeEventMessage()) as the event dict Device.events() yields, for "
	      "messages caught by other means (e.g. pyroute2). ecmxf.Error (errno EPROTO) for one that is not "
	      "an event or is malformed.");
	m.def("kernel_events", [](const std::string &path, double duration) {
		return subscribe(path, seconds(duration, "duration", 0, 86400));
	}, py::arg("path"), py::arg("duration"),
	      "The kernel module's events of the device at path (/dev/ecmxfN) for duration s of wall time, "
	      "without opening it (joining the netlink group needs no access to the device): as "
	      "Device.events() over /dev/ecmxfN. ecmxf.Error with errno ENOENT when ecmxf.ko is not loaded.");

	m.def("open", [](const std::string &uri, bool bringUpBus) { return DeviceObject{ openSession(uri, bringUpBus) }; },
	      py::arg("uri"), py::arg("bring_up") = true, "ecmxf.Device(uri): with ecmxf.open('sim:') as dev: ...");
	return device;
}

} // namespace ecmxf::python
