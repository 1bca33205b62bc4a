// SPDX-License-Identifier: MIT
// The ECM-SK's own views from Python (Documentation/python.rst, "The
// ECM-SK board"): dev.board, one object over the calls of the
// ecmxf::sk::Board views that the verbs both masters share (Device's
// request_state(), sdo, drive_enable()...) do not cover: BoardStates'
// status, BoardSetup, BoardDrives, BoardIo's local I/O, BoardCyclic.
// Positions count from 0 as everywhere in the binding (the verbs' rule:
// the frame's slot is ecmxf::boardSlot(), position + 1).

#include "binding.hpp"

#include <pybind11/stl.h>

#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/board_views.hpp>
#include <ecmxf/sk/types_sk.hpp>

namespace ecmxf::python {

namespace {

/// dev.board
struct BoardView {
	std::shared_ptr<Session> session;
};

/// @p f on the session's board with the GIL released (ClosedError,
/// NotSupportedError naming @p what on an ECM-XF, BusyError).
template <class F>
auto onBoard(const BoardView &v, const char *what, F &&f)
{
	MasterVerbs &m = v.session->open();
	sk::Board *b = m.board();
	if (!b)
		throwNotOn(m.kind(), std::string(what) + " is a call of the ECM-SK board");
	Use use(*v.session);
	py::gil_scoped_release nogil;
	return f(*b);
}

std::chrono::milliseconds millis(double s, const char *what)
{
	return std::chrono::duration_cast<std::chrono::milliseconds>(seconds(s, what, 0.001, 3600));
}

std::int32_t i32(std::int64_t v, const char *what)
{
	return static_cast<std::int32_t>(static_cast<std::int64_t>(checkedRange(v, INT32_MIN, INT32_MAX, what)));
}

const char *cycleStatusName(sk::CycleStatus s)
{
	switch (s) {
	case sk::CycleStatus::Ok: return "ok";
	case sk::CycleStatus::FifoOverflow: return "fifo_overflow";
	case sk::CycleStatus::BadResponse: return "bad_response";
	case sk::CycleStatus::Busy: return "busy";
	case sk::CycleStatus::Link: return "link";
	}
	return "?";
}

void bindTypes(py::module_ &m)
{
	py::enum_<sk::SlaveType>(m, "SkSlaveType", "The ECM-SK's slave kinds (SET_AXIS).")
		.value("DRIVE", sk::SlaveType::Drive)
		.value("IO", sk::SlaveType::Io)
		.value("HSP", sk::SlaveType::Hsp)
		.value("STEP", sk::SlaveType::Step)
		.value("NONE", sk::SlaveType::None);
	py::enum_<sk::Mode>(m, "SkMode", "The ECM-SK's modes of operation (DRIVE_MODE, the cyclic commands).")
		.value("CSP", sk::Mode::Csp)
		.value("CSV", sk::Mode::Csv)
		.value("CST", sk::Mode::Cst);
	py::enum_<sk::Sync>(m, "SkSync", "DRIVE_MODE's synchronisation.")
		.value("FREE_RUN", sk::Sync::FreeRun)
		.value("DC_SYNC", sk::Sync::DcSync);

	auto st = py::class_<sk::BoardStatus>(m, "BoardStatus", "Slot 0 of the board's last response.");
	st.def_readonly("state", &sk::BoardStatus::state)
		.def_readonly("crc_errors", &sk::BoardStatus::crcErrors, "The board's count of refused frames.")
		.def_readonly("fifo_remaining", &sk::BoardStatus::fifoRemaining, "In OP: free FIFO entries.")
		.def_readonly("fifo_full", &sk::BoardStatus::fifoFull, "In OP: cyclic commands dropped, FIFO full.");
	madeByEcmxfOnly(st);
	auto ax = py::class_<sk::AxisStatus>(m, "AxisStatus", "A slave's slot of the board's last response.");
	ax.def_readonly("cmd", &sk::AxisStatus::cmd, "The command answered.")
		.def_readonly("index", &sk::AxisStatus::index, "Its command index.")
		.def_readonly("statusword", &sk::AxisStatus::statusword, "0x6041.")
		.def_readonly("position", &sk::AxisStatus::position, "0x6064 (IO_RD: the inputs).")
		.def_readonly("torque", &sk::AxisStatus::torque, "0x6077 (HSP: input status).")
		.def_readonly("error_code", &sk::AxisStatus::errorCode, "0x603F.");
	madeByEcmxfOnly(ax);
	auto h2 = py::class_<sk::Hsp2Status>(m, "Hsp2Status", "A 2-channel HSP's slot (16-byte slots).");
	h2.def_readonly("cmd", &sk::Hsp2Status::cmd)
		.def_readonly("index", &sk::Hsp2Status::index)
		.def_readonly("statusword", &sk::Hsp2Status::statusword)
		.def_readonly("position1", &sk::Hsp2Status::position1)
		.def_readonly("inputs1", &sk::Hsp2Status::inputs1)
		.def_readonly("position2", &sk::Hsp2Status::position2)
		.def_readonly("inputs2", &sk::Hsp2Status::inputs2);
	madeByEcmxfOnly(h2);
}

} // namespace

void bindBoard(py::module_ &m, py::class_<DeviceObject> &device)
{
	bindTypes(m);
	using sk::Board;
	auto c = py::class_<BoardView>(
		m, "Board",
		"The ECM-SK board's own calls (dev.board; ecmxf::sk::Board's views): status, setup, drives, the "
		"ECM IC's local I/O and the cyclic path. Positions count from 0, as Device's (the frame's slot is "
		"position + 1).");
	c.def_property_readonly("slot_size", [](const BoardView &v) {
		return onBoard(v, "slot_size", [](Board &b) { return b.slotSize(); });
	}, "Bytes of a slot (12 or 16).")
		.def_property_readonly("max_slaves", [](const BoardView &v) {
			return onBoard(v, "max_slaves", [](Board &b) { return b.maxSlaves(); });
		}, "Slaves a frame has slots for.")
		.def_property_readonly("frame_size", [](const BoardView &v) {
			return onBoard(v, "frame_size", [](Board &b) { return b.frameSize(); });
		}, "Bytes of a frame.")
		.def("status", [](const BoardView &v) {
			return onBoard(v, "board.status()", [](Board &b) { return b.states().status(); });
		}, "GET_STATUS: a BoardStatus.")
		.def("set_axes", [](const BoardView &v, const std::vector<sk::SlaveType> &types) {
			return onBoard(v, "board.set_axes()", [&](Board &b) { return b.setup().setAxes(types); });
		}, py::arg("types"), "SET_AXIS with one SkSlaveType per slave: the slaves detected.")
		.def("detect_axes", [](const BoardView &v) {
			return onBoard(v, "board.detect_axes()", [](Board &b) { return b.setup().detectAxes(); });
		}, "In PRE-OP: each slave's type found by SET_AXIS (left set): a list of SkSlaveType.")
		.def("set_cycle_time", [](const BoardView &v, std::int64_t us) {
			const auto t = static_cast<std::uint32_t>(checkedRange(us, 0, 0xFFFFFFFF, "cycle time"));
			onBoard(v, "board.set_cycle_time()", [t](Board &b) { b.setup().setCycleTime(t); });
		}, py::arg("microseconds"), "SET_DC: 250 * 2^n us.")
		.def("set_extensions", [](const BoardView &v, std::int64_t bits) {
			const auto x = static_cast<std::uint32_t>(checkedRange(bits, 0, 0xFFFFFFFF, "extension bits"));
			onBoard(v, "board.set_extensions()", [x](Board &b) { b.setup().setExtensions(x); });
		}, py::arg("bits"), "SET_EX (in force from the board's next power-on).")
		.def("set_mode", [](const BoardView &v, std::int64_t slave, sk::Mode mode, sk::Sync sync) {
			const unsigned p = position(slave);
			onBoard(v, "board.set_mode()", [&](Board &b) { b.drives().setMode(boardSlot(b, p), mode, sync); });
		}, py::arg("slave"), py::arg("mode"), py::arg("sync") = sk::Sync::DcSync, "DRIVE_MODE.")
		.def("wait_enabled", [](const BoardView &v, std::int64_t slave, double timeout) {
			const unsigned p = position(slave);
			const auto t = millis(timeout, "timeout");
			onBoard(v, "board.wait_enabled()", [&](Board &b) { b.drives().waitEnabled(boardSlot(b, p), t); });
		}, py::arg("slave"), py::arg("timeout") = 2.0, "GET_STATUS until the drive is in OPERATION ENABLED.")
		.def("halt", [](const BoardView &v, std::int64_t slave, double timeout) {
			const unsigned p = position(slave);
			const auto t = millis(timeout, "timeout");
			return onBoard(v, "board.halt()", [&](Board &b) { return b.drives().halt(boardSlot(b, p), t); });
		}, py::arg("slave"), py::arg("timeout") = 1.0,
		   "SV_OFF, then GET_STATUS until the power stage is off: the AxisStatus (Timeout naming the "
		   "statusword).")
		.def("home", [](const BoardView &v, std::int64_t slave, std::int64_t method, double timeout) {
			const unsigned p = position(slave);
			const auto mth = static_cast<std::int8_t>(
				static_cast<std::int64_t>(checkedRange(method, -128, 127, "homing method")));
			const auto t = millis(timeout, "timeout");
			onBoard(v, "board.home()", [&](Board &b) { b.drives().home(boardSlot(b, p), mth, t); });
		}, py::arg("slave"), py::arg("method"), py::arg("timeout") = 30.0,
		   "Homing: 0x6060 = 6, 0x6098 = method, GO_HOME, then GET_STATUS until done.")
		.def("abort_home", [](const BoardView &v, std::int64_t slave) {
			const unsigned p = position(slave);
			onBoard(v, "board.abort_home()", [&](Board &b) { b.drives().abortHome(boardSlot(b, p)); });
		}, py::arg("slave"), "ABORT_HOME.")
		.def("axis", [](const BoardView &v, std::int64_t slave) {
			const unsigned p = position(slave);
			return onBoard(v, "board.axis()", [&](Board &b) { return b.drives().axis(boardSlot(b, p)); });
		}, py::arg("slave"), "The slave's slot of the last response (no exchange): an AxisStatus.")
		.def("hsp2", [](const BoardView &v, std::int64_t slave) {
			const unsigned p = position(slave);
			return onBoard(v, "board.hsp2()", [&](Board &b) { return b.drives().hsp2(boardSlot(b, p)); });
		}, py::arg("slave"), "A 2-channel HSP's slot of the last response (16-byte slots): an Hsp2Status.")
		.def("read_local", [](const BoardView &v) {
			return onBoard(v, "board.read_local()", [](Board &b) { return b.io().readLocal(); });
		}, "LIO_RD: the ECM IC's own inputs.")
		.def("write_local", [](const BoardView &v, std::int64_t outputs) {
			const auto x = static_cast<std::uint32_t>(checkedRange(outputs, 0, 0xFFFFFFFF, "outputs"));
			onBoard(v, "board.write_local()", [x](Board &b) { b.io().writeLocal(x); });
		}, py::arg("outputs"), "LIO_WR: the ECM IC's own outputs.")
		.def("stage", [](const BoardView &v, std::int64_t slave, sk::Mode mode, std::int64_t target,
				 std::int64_t output) {
			const unsigned p = position(slave);
			const std::int32_t t = i32(target, "target");
			const auto o = static_cast<std::uint32_t>(checkedRange(output, 0, 0xFFFFFFFF, "output"));
			return onBoard(v, "board.stage()", [&](Board &b) { return b.cyclic().stage(boardSlot(b, p), mode, t, o); });
		}, py::arg("slave"), py::arg("mode"), py::arg("target"), py::arg("output") = 0,
		   "Queues a CSP/CSV/CST command for the next cycle(); False (nothing staged) for a slave already "
		   "staged or when the FIFO has no room (back-pressure); InvalidArgument for a position outside the "
		   "frame's slots.")
		.def("stage2", [](const BoardView &v, std::int64_t slave, sk::Mode mode, std::int64_t t1, std::int64_t t2,
				  std::int64_t o1, std::int64_t o2) {
			const unsigned p = position(slave);
			const std::int32_t a = i32(t1, "target1");
			const std::int32_t bb = i32(t2, "target2");
			const auto x1 = static_cast<std::uint16_t>(checkedRange(o1, 0, 0xFFFF, "output1"));
			const auto x2 = static_cast<std::uint16_t>(checkedRange(o2, 0, 0xFFFF, "output2"));
			return onBoard(v, "board.stage2()",
				       [&](Board &b) { return b.cyclic().stage2(boardSlot(b, p), mode, a, bb, x1, x2); });
		}, py::arg("slave"), py::arg("mode"), py::arg("target1"), py::arg("target2"), py::arg("output1") = 0,
		   py::arg("output2") = 0, "As stage(), both channels of a 2-channel HSP (16-byte slots, CSP or CSV).")
		.def("cycle", [](const BoardView &v) {
			std::string error;
			const sk::CycleResult r = onBoard(v, "board.cycle()", [&](Board &b) {
				const sk::CycleResult res = b.cyclic().cycle();
				if (res.status == sk::CycleStatus::Link)
					error = b.cyclic().lastError();
				return res;
			});
			py::dict d(py::arg("status") = cycleStatusName(r.status), py::arg("fifo_remaining") = r.fifoRemaining,
				   py::arg("fifo_full") = r.fifoFull, py::arg("dropped") = r.dropped,
				   py::arg("staged") = r.staged);
			if (!error.empty())
				d["error"] = error;
			return d;
		}, "One cyclic exchange with the staged commands: {'status' ('ok', 'fifo_overflow', 'bad_response', "
		   "'busy', 'link'), 'fifo_remaining', 'fifo_full', 'dropped', 'staged'} and 'error' for 'link'.");
	madeByEcmxfOnly(c);

	device.def_property_readonly("board", [](const DeviceObject &d) {
		MasterVerbs &mv = d.session->open();
		if (!mv.board())
			throwNotOn(mv.kind(), "board is the ECM-SK's (an ECM-XF has Device's own views)");
		return BoardView{ d.session };
	}, "ECM-SK: the board's own calls (Board).");
}

} // namespace ecmxf::python
