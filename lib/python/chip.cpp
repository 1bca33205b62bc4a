// SPDX-License-Identifier: MIT
// The ECM-XF's own views from Python (Documentation/python.rst, "The
// chip"): dev.peripherals (ecmxf::Peripherals: GPIO, QEI, DAC, ADC,
// MDIO), dev.chip402 (ecmxf::Chip402, the chip's CiA-402 engine), and on
// Device itself the raw command (Device::command()), raw datagrams, the
// SII EEPROM, FoE and the staging flash (ecmxf::SlaveAccess).
//
// Every Python int is range-checked into its C++ type here (ValueError
// naming it); the library checks what the chip allows (its EINVAL is
// ecmxf.InvalidArgument, also a ValueError, with the library's words).

#include "binding.hpp"

#include <pybind11/stl.h>

#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/chip/chip402.hpp>
#include <ecmxf/chip/peripherals.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/model/types_chip.hpp>
#include <ecmxf/model/types_cia402.hpp>

namespace ecmxf::python {

namespace {

/// dev.peripherals
struct PeripheralsView {
	std::shared_ptr<Session> session;
};

/// dev.chip402
struct Chip402View {
	std::shared_ptr<Session> session;
};

/// One RAW_ECAT_FUNC result (Device.datagram()).
struct DatagramRecord {
	unsigned workingCounter = 0;
	py::bytes data;
};

/// Device.command()'s answer.
struct ResponseRecord {
	ResponseHeader header;
	py::bytes data;
	unsigned ret = 0;
};

std::uint32_t u32(std::int64_t v, const char *what)
{
	return static_cast<std::uint32_t>(checkedRange(v, 0, 0xFFFFFFFF, what));
}

std::uint16_t u16(std::int64_t v, const char *what)
{
	return static_cast<std::uint16_t>(checkedRange(v, 0, 0xFFFF, what));
}

std::uint8_t u8(std::int64_t v, const char *what)
{
	return static_cast<std::uint8_t>(checkedRange(v, 0, 0xFF, what));
}

/// A chip time limit in microseconds (0: the command table's default).
std::chrono::microseconds timeLimit(double s)
{
	return std::chrono::duration_cast<std::chrono::microseconds>(seconds(s, "timeout", 0, 3600));
}

py::bytes toBytes(const std::vector<std::uint8_t> &v)
{
	return py::bytes(reinterpret_cast<const char *>(v.data()), v.size());
}

FoeOptions foeOptions(std::int64_t password, std::int64_t flashAddress, double timeout)
{
	FoeOptions o;
	o.password = u32(password, "password");
	o.flashAddress = static_cast<std::uint32_t>(checkedRange(flashAddress, 0, kFoeFlashSize - 1, "flash_address"));
	o.timeout = timeLimit(timeout);
	return o;
}

/// @p f on the session's Peripherals (GIL released).
template <class F>
auto periph(const PeripheralsView &v, const char *what, F &&f)
{
	return onDevice(*v.session, what, [&](Device &d) { return f(d.peripherals()); });
}

template <class F>
auto engine(const Chip402View &v, const char *what, F &&f)
{
	return onDevice(*v.session, what, [&](Device &d) { return f(d.chip402()); });
}

unsigned motor(std::int64_t v)
{
	return static_cast<unsigned>(checkedRange(v, 0, 127, "motor"));
}

Chip402Flags flags(bool engineOn, bool singleFaultReset, bool autoFaultReset)
{
	Chip402Flags f;
	f.engine = engineOn;
	f.singleFaultReset = singleFaultReset;
	f.autoFaultReset = autoFaultReset;
	return f;
}

ResponseRecord command(Session &s, std::int64_t code, std::int64_t param, const py::object &data,
		       const py::object &payload, const std::optional<std::int64_t> &length, std::int64_t reserved,
		       std::int64_t control, double timeout)
{
	Command c;
	c.code = u8(code, "command code");
	c.param = u8(param, "command parameter");
	const std::vector<std::uint8_t> d = bytesOf(data, "data");
	if (d.size() > c.data.size())
		throw py::value_error("data has " + std::to_string(d.size()) +
				      " bytes: the command header's parametric data is 4 bytes (0x04..0x07)");
	std::copy(d.begin(), d.end(), c.data.begin());
	c.payload = bytesOf(payload, "payload");
	if (length)
		c.len = u16(*length, "length");
	c.reserved = u16(reserved, "reserved");
	c.control = u8(control, "control");
	c.timeout = timeLimit(timeout);
	Response r = onDevice(s, "command()", [&c](Device &dev) { return dev.command(c); });
	ResponseRecord out;
	out.header = r.header;
	out.data = toBytes(r.data);
	out.ret = r.ret;
	return out;
}

DatagramRecord datagram(Session &s, DatagramCommand cmd, std::int64_t adp, std::int64_t ado,
			const py::object &data, const std::optional<std::int64_t> &length, std::int64_t logical,
			double timeout)
{
	Datagram g;
	g.command = cmd;
	g.adp = u16(adp, "adp");
	g.ado = u16(ado, "ado");
	g.logicalAddress = u32(logical, "logical_address");
	g.timeout = timeLimit(timeout);
	if (!data.is_none() && length)
		throw py::value_error("give data (what to send) or length (how many bytes to read), not both");
	if (!data.is_none())
		g.data = bytesOf(data, "data");
	else if (length)
		g.data.assign(static_cast<std::size_t>(checkedRange(*length, 1, 256, "length")), 0);
	else
		throw py::value_error("a datagram needs data (what to send) or length (how many bytes to read)");
	DatagramResult r = onDevice(s, "datagram()", [&g](Device &dev) { return dev.slaves().rawDatagram(g); });
	DatagramRecord out;
	out.workingCounter = r.workingCounter;
	out.data = toBytes(r.data);
	return out;
}

/// A progress callback for the staging of FoE / flash writes, called with
/// the GIL (its exception ends the transfer and is raised).
std::function<void(std::size_t, std::size_t)> progressOf(const py::object &progress)
{
	if (progress.is_none())
		return {};
	if (!PyCallable_Check(progress.ptr()))
		throw py::type_error(std::string("progress must be callable (done, total), not ") +
				     Py_TYPE(progress.ptr())->tp_name);
	// a handle, not a reference: the library may copy the function
	// without the GIL; the caller's argument keeps the callable alive
	const py::handle callable = progress;
	return [callable](std::size_t done, std::size_t total) {
		py::gil_scoped_acquire gil;
		callable(done, total);
	};
}

std::string headerRepr(const ResponseHeader &h)
{
	char b[160];
	std::snprintf(b, sizeof b,
		      "<ecmxf.Header code=%u ret=%u len=%u ecat_state=0x%02x error_status=0x%02x ecm_status=0x%02x>",
		      h.code, h.ret, h.len, h.ecatState, h.errStatus, h.ecmStatus);
	return b;
}

void bindEnums(py::module_ &m)
{
	py::enum_<GpioMode>(m, "GpioMode", "GPIO_CONFIG_SET mode of a GPIO line.")
		.value("INPUT", GpioMode::Input)
		.value("OUTPUT", GpioMode::Output)
		.value("OPEN_DRAIN", GpioMode::OpenDrain)
		.value("QUASI_BIDIRECTIONAL", GpioMode::QuasiBidirectional);
	py::enum_<GpioPull>(m, "GpioPull", "GPIO_CONFIG_SET pull resistor.")
		.value("NONE", GpioPull::None)
		.value("UP", GpioPull::Up)
		.value("DOWN", GpioPull::Down);
	py::enum_<GpioEdge>(m, "GpioEdge", "GPIO interrupt type.")
		.value("DISABLED", GpioEdge::Disabled)
		.value("BOTH", GpioEdge::Both)
		.value("FALLING", GpioEdge::Falling)
		.value("RISING", GpioEdge::Rising);
	py::enum_<DebounceClock>(m, "DebounceClock", "Clock of the GPIO debounce sampler.")
		.value("CORE_192MHZ", DebounceClock::Core192MHz)
		.value("LOW_SPEED_10KHZ", DebounceClock::LowSpeed10kHz);
	py::enum_<QeiMode>(m, "QeiMode", "QEI counting mode (EncOpen).")
		.value("X4_FREE", QeiMode::X4Free)
		.value("X2_FREE", QeiMode::X2Free)
		.value("X4_COMPARE", QeiMode::X4Compare)
		.value("X2_COMPARE", QeiMode::X2Compare);
	py::enum_<DacTrigger>(m, "DacTrigger", "What starts a DAC conversion (DacOpen).")
		.value("SET_DATA", DacTrigger::SetData)
		.value("START_CONV", DacTrigger::StartConv)
		.value("PIN_LOW", DacTrigger::PinLow)
		.value("PIN_HIGH", DacTrigger::PinHigh)
		.value("PIN_RISING", DacTrigger::PinRising)
		.value("PIN_FALLING", DacTrigger::PinFalling);
	py::enum_<AdcInputMode>(m, "AdcInputMode", "ADC input mode (AdcOpen).")
		.value("SINGLE_ENDED", AdcInputMode::SingleEnded)
		.value("DIFFERENTIAL", AdcInputMode::Differential);
	py::enum_<Cia402State>(m, "Cia402State", "The states of the CiA-402 drive state machine.")
		.value("NOT_READY_TO_SWITCH_ON", Cia402State::NotReadyToSwitchOn)
		.value("SWITCH_ON_DISABLED", Cia402State::SwitchOnDisabled)
		.value("READY_TO_SWITCH_ON", Cia402State::ReadyToSwitchOn)
		.value("SWITCHED_ON", Cia402State::SwitchedOn)
		.value("OPERATION_ENABLED", Cia402State::OperationEnabled)
		.value("QUICK_STOP_ACTIVE", Cia402State::QuickStopActive)
		.value("FAULT_REACTION_ACTIVE", Cia402State::FaultReactionActive)
		.value("FAULT", Cia402State::Fault);
	py::enum_<DatagramCommand>(m, "DatagramCommand", "EtherCAT datagram commands of RAW_ECAT_FUNC_REQ.")
		.value("APRD", DatagramCommand::APRD)
		.value("APWR", DatagramCommand::APWR)
		.value("FPRD", DatagramCommand::FPRD)
		.value("FPWR", DatagramCommand::FPWR)
		.value("BRD", DatagramCommand::BRD)
		.value("BWR", DatagramCommand::BWR)
		.value("LRD", DatagramCommand::LRD)
		.value("LWR", DatagramCommand::LWR)
		.value("LRW", DatagramCommand::LRW)
		.value("ARMW", DatagramCommand::ARMW)
		.value("FRMW", DatagramCommand::FRMW);
}

void bindPeripherals(py::module_ &m)
{
	using P = Peripherals;
	auto c = py::class_<PeripheralsView>(
		m, "Peripherals",
		"The chip's peripherals (dev.peripherals, ECM-XF): GPIO (masks name GPIO n with bit n, n = 0..19), "
		"QEI, DAC, ADC and MDIO; the calls of ecmxf::Peripherals (Documentation/commands-chip.rst).");
	c.def("gpio_set_mode", [](const PeripheralsView &v, std::int64_t lines, GpioMode mode, GpioPull pull) {
		const auto l = u32(lines, "lines");
		periph(v, "gpio_set_mode()", [&](const P &p) { p.gpioSetMode(l, mode, pull); });
	}, py::arg("lines"), py::arg("mode"), py::arg("pull") = GpioPull::None, "GpioSetMode of the lines in the mask.")
		.def("gpio_set_debounce", [](const PeripheralsView &v, std::int64_t lines, bool enable) {
			const auto l = u32(lines, "lines");
			periph(v, "gpio_set_debounce()", [&](const P &p) { p.gpioSetDebounce(l, enable); });
		}, py::arg("lines"), py::arg("enable"), "GpioEnableDebounce of the lines in the mask.")
		.def("gpio_set_debounce_clock", [](const PeripheralsView &v, std::int64_t cycle, DebounceClock clock) {
			const auto n = u32(cycle, "cycle");
			periph(v, "gpio_set_debounce_clock()", [&](const P &p) { p.gpioSetDebounceClock(n, clock); });
		}, py::arg("cycle"), py::arg("clock"), "GpioSetDebounceClock: sampling period 2^cycle (0..15) clock periods.")
		.def("gpio_set_interrupt", [](const PeripheralsView &v, std::int64_t line, GpioEdge edge) {
			const auto n = u32(line, "line");
			periph(v, "gpio_set_interrupt()", [&](const P &p) { p.gpioSetInterrupt(n, edge); });
		}, py::arg("line"), py::arg("edge"), "GpioIntEnable: the interrupt type of one line (0..19).")
		.def("gpio_clear_interrupts", [](const PeripheralsView &v, std::int64_t lines) {
			const auto l = u32(lines, "lines");
			periph(v, "gpio_clear_interrupts()", [&](const P &p) { p.gpioClearInterrupts(l); });
		}, py::arg("lines"), "GpioIntClear of the lines in the mask.")
		.def("gpio_write", [](const PeripheralsView &v, std::int64_t values) {
			const auto x = u16(values, "values");
			periph(v, "gpio_write()", [&](const P &p) { p.gpioWrite(x); });
		}, py::arg("values"), "GpioSetValue: the output latches of GPIO 0..15.")
		.def("gpio_write_all", [](const PeripheralsView &v, std::int64_t values) {
			const auto x = u32(values, "values");
			periph(v, "gpio_write_all()", [&](const P &p) { p.gpioWriteAll(x); });
		}, py::arg("values"), "GpioExtSetValue: the output latches of GPIO 0..19.")
		.def("gpio_read", [](const PeripheralsView &v) {
			return periph(v, "gpio_read()", [](const P &p) { return p.gpioRead(); });
		}, "GpioGetValue: GPIO 0..15.")
		.def("gpio_read_all", [](const PeripheralsView &v) {
			return periph(v, "gpio_read_all()", [](const P &p) { return p.gpioReadAll(); });
		}, "GpioExtGetValue: GPIO 0..19.")
		.def("gpio_interrupt_flags", [](const PeripheralsView &v) {
			return periph(v, "gpio_interrupt_flags()", [](const P &p) { return p.gpioInterruptFlags(); });
		}, "GpioGetIntFlag: the interrupt flags of GPIO 0..15.")
		.def("gpio_interrupt_flags_all", [](const PeripheralsView &v) {
			return periph(v, "gpio_interrupt_flags_all()", [](const P &p) { return p.gpioInterruptFlagsAll(); });
		}, "GpioExtGetIntFlag: the interrupt flags of GPIO 0..19.")
		.def("qei_open", [](const PeripheralsView &v, QeiMode mode) {
			periph(v, "qei_open()", [&](const P &p) { p.qeiOpen(mode); });
		}, py::arg("mode"), "EncOpen: the counting mode; stops and clears the counter.")
		.def("qei_start", [](const PeripheralsView &v) { periph(v, "qei_start()", [](const P &p) { p.qeiStart(); }); })
		.def("qei_stop", [](const PeripheralsView &v) { periph(v, "qei_stop()", [](const P &p) { p.qeiStop(); }); })
		.def("qei_count", [](const PeripheralsView &v) {
			return periph(v, "qei_count()", [](const P &p) { return p.qeiCount(); });
		}, "EncGetCount: the 32-bit counter.")
		.def("dac_open", [](const PeripheralsView &v, DacTrigger trigger) {
			periph(v, "dac_open()", [&](const P &p) { p.dacOpen(trigger); });
		}, py::arg("trigger"), "DacOpen with what starts a conversion.")
		.def("dac_close", [](const PeripheralsView &v) { periph(v, "dac_close()", [](const P &p) { p.dacClose(); }); })
		.def("dac_set_delay", [](const PeripheralsView &v, std::int64_t ticks) {
			const auto t = u16(ticks, "ticks");
			periph(v, "dac_set_delay()", [&](const P &p) { p.dacSetDelay(t); });
		}, py::arg("ticks"), "DacSetDelayTime: 0..1023 in 1/96 us.")
		.def("dac_write", [](const PeripheralsView &v, std::int64_t value) {
			const auto x = u16(value, "value");
			periph(v, "dac_write()", [&](const P &p) { p.dacWrite(x); });
		}, py::arg("value"), "DacSetData: 0..4095 = 0..3.3 V.")
		.def("dac_start_conversion", [](const PeripheralsView &v) {
			periph(v, "dac_start_conversion()", [](const P &p) { p.dacStartConversion(); });
		}, "DacStartConv.")
		.def("adc_open", [](const PeripheralsView &v, AdcInputMode mode) {
			periph(v, "adc_open()", [&](const P &p) { p.adcOpen(mode); });
		}, py::arg("mode"), "AdcOpen.")
		.def("adc_close", [](const PeripheralsView &v) { periph(v, "adc_close()", [](const P &p) { p.adcClose(); }); })
		.def("adc_configure_module", [](const PeripheralsView &v, std::int64_t module, std::int64_t channel) {
			const auto mo = u32(module, "module");
			const auto ch = u32(channel, "channel");
			periph(v, "adc_configure_module()", [&](const P &p) { p.adcConfigureModule(mo, ch); });
		}, py::arg("module"), py::arg("channel"),
		   "AdcConfigSampleModule: sample module (0..15) converts channel (0..15), software trigger. The "
		   "manuals' own call is (0, 0).")
		.def("adc_start", [](const PeripheralsView &v, std::int64_t mask) {
			const auto x = u16(mask, "module mask");
			periph(v, "adc_start()", [&](const P &p) { p.adcStart(x); });
		}, py::arg("module_mask"), "AdcStartConv of the modules in the mask (bits 0..15).")
		.def("adc_valid_flags", [](const PeripheralsView &v, std::int64_t mask) {
			const auto x = u16(mask, "module mask");
			return periph(v, "adc_valid_flags()", [&](const P &p) { return p.adcValidFlags(x); });
		}, py::arg("module_mask"), "AdcGetDataValidFlag: the modules of the mask whose result is valid.")
		.def("adc_read", [](const PeripheralsView &v, std::int64_t module) {
			const auto mo = u32(module, "module");
			return periph(v, "adc_read()", [&](const P &p) { return p.adcRead(mo); });
		}, py::arg("module"), "AdcGetConvData: the module's result (0..4095).")
		.def("adc_convert", [](const PeripheralsView &v, std::int64_t module) {
			const auto mo = u32(module, "module");
			return periph(v, "adc_convert()", [&](const P &p) { return p.adcConvert(mo); });
		}, py::arg("module") = kAdcDefaultModule,
		   "adc_start(), adc_valid_flags() until valid (at most 100 polls: Timeout), adc_read().")
		.def("mdio_read", [](const PeripheralsView &v, std::int64_t phy, std::int64_t reg) {
			const auto a = u32(phy, "phy");
			const auto r = u32(reg, "reg");
			return periph(v, "mdio_read()", [&](const P &p) { return p.mdioRead(a, r); });
		}, py::arg("phy"), py::arg("reg"), "Register reg (0..31) of the PHY at address phy (0..31).")
		.def("mdio_write", [](const PeripheralsView &v, std::int64_t phy, std::int64_t reg, std::int64_t value) {
			const auto a = u32(phy, "phy");
			const auto r = u32(reg, "reg");
			const auto x = u16(value, "value");
			periph(v, "mdio_write()", [&](const P &p) { p.mdioWrite(a, r, x); });
		}, py::arg("phy"), py::arg("reg"), py::arg("value"));
	madeByEcmxfOnly(c);
}

void bindChip402(py::module_ &m)
{
	auto st = py::class_<Chip402State>(m, "Chip402State", "402_STATE_GET: the chip's state code and its state.");
	st.def_readonly("code", &Chip402State::code, "The state code as the chip sent it (e.g. 0x27).")
		.def_readonly("state", &Chip402State::state, "The Cia402State, None for a code that is none.")
		.def("__repr__", [](const Chip402State &s) {
			return "<ecmxf.Chip402State code=" + std::to_string(s.code) + " " +
			       (s.state ? std::string(cia402StateName(*s.state)) : std::string("?")) + ">";
		});
	madeByEcmxfOnly(st);
	auto fl = py::class_<Chip402Flags>(m, "Chip402Flags", "The engine's control byte (402_CTL_GET).");
	fl.def_readonly("engine", &Chip402Flags::engine, "Bit 4: the engine drives the controlword.")
		.def_readonly("single_fault_reset", &Chip402Flags::singleFaultReset,
			      "Bit 3: one fault reset (cleared by the chip once done).")
		.def_readonly("auto_fault_reset", &Chip402Flags::autoFaultReset, "Bit 7: every fault reset.")
		.def("__repr__", [](const Chip402Flags &f) {
			return std::string("<ecmxf.Chip402Flags engine=") + (f.engine ? "True" : "False") +
			       " single_fault_reset=" + (f.singleFaultReset ? "True" : "False") +
			       " auto_fault_reset=" + (f.autoFaultReset ? "True" : "False") + ">";
		});
	madeByEcmxfOnly(fl);

	auto c = py::class_<Chip402View>(
		m, "Chip402",
		"The chip's own CiA-402 engine (dev.chip402, ECM-XF; ecmxf::Chip402): motors 0..127, each a drive "
		"whose controlword and statusword the engine finds at byte offsets of its slave's process data "
		"(Documentation/cia402.rst).");
	c.def("configure", [](const Chip402View &v, std::int64_t mo, std::int64_t slave, std::int64_t cwOffset,
			      std::int64_t swOffset, bool engineOn, bool single, bool autoReset) {
		Chip402Config cfg;
		cfg.slave = position(slave);
		cfg.controlwordOffset = u16(cwOffset, "controlword_offset");
		cfg.statuswordOffset = u16(swOffset, "statusword_offset");
		cfg.flags = flags(engineOn, single, autoReset);
		const unsigned n = motor(mo);
		engine(v, "chip402.configure()", [&](const Chip402 &e) { e.configure(n, cfg); });
	}, py::arg("motor"), py::arg("slave"), py::arg("controlword_offset") = 0, py::arg("statusword_offset") = 0,
	   py::arg("engine") = true, py::arg("single_fault_reset") = false, py::arg("auto_fault_reset") = false,
	   "402_CONFIG_SET: motor is the drive at slave, its controlword and statusword at those byte offsets "
	   "of the slave's outputs and inputs. Needs the bus initialised.")
		.def("request_state", [](const Chip402View &v, std::int64_t mo, Cia402State target) {
			const unsigned n = motor(mo);
			engine(v, "chip402.request_state()", [&](const Chip402 &e) { e.requestState(n, target); });
		}, py::arg("motor"), py::arg("state"),
		   "402_STATE_SET: the state the engine walks the motor to (SWITCH_ON_DISABLED, READY_TO_SWITCH_ON, "
		   "SWITCHED_ON, OPERATION_ENABLED or QUICK_STOP_ACTIVE).")
		.def("state", [](const Chip402View &v, std::int64_t mo) {
			const unsigned n = motor(mo);
			return engine(v, "chip402.state()", [&](const Chip402 &e) { return e.state(n); });
		}, py::arg("motor"), "402_STATE_GET: a Chip402State.")
		.def("set_control", [](const Chip402View &v, std::int64_t mo, std::int64_t count, std::int64_t slave,
				       bool engineOn, bool single, bool autoReset) {
			Chip402Control ctl;
			ctl.flags = flags(engineOn, single, autoReset);
			ctl.motorCount = static_cast<unsigned>(checkedRange(count, 1, 128, "motor_count"));
			ctl.slave = position(slave);
			const unsigned n = motor(mo);
			engine(v, "chip402.set_control()", [&](const Chip402 &e) { e.setControl(n, ctl); });
		}, py::arg("motor"), py::arg("motor_count"), py::arg("slave"), py::arg("engine") = true,
		   py::arg("single_fault_reset") = false, py::arg("auto_fault_reset") = false,
		   "402_CTL_SET: the control byte, the total motor count and the motor's slave.")
		.def("control", [](const Chip402View &v, std::int64_t mo) {
			const unsigned n = motor(mo);
			return engine(v, "chip402.control()", [&](const Chip402 &e) { return e.control(n); });
		}, py::arg("motor"), "402_CTL_GET: the control byte as Chip402Flags.")
		.def("statusword", [](const Chip402View &v, std::int64_t mo) {
			const unsigned n = motor(mo);
			return engine(v, "chip402.statusword()", [&](const Chip402 &e) { return e.statusword(n); });
		}, py::arg("motor"), "402_GET_STATUSWORD: the statusword as the chip last read it.")
		.def("await_state", [](const Chip402View &v, std::int64_t mo, Cia402State target, double timeout,
				       double poll) {
			const unsigned n = motor(mo);
			const auto t = seconds(timeout, "timeout", 0, 3600);
			const auto p = seconds(poll, "poll", 1e-6, 10);
			return engine(v, "chip402.await_state()",
				      [&](const Chip402 &e) { return e.awaitState(n, target, t, p); });
		}, py::arg("motor"), py::arg("state"), py::arg("timeout") = 1.0, py::arg("poll") = 0.001,
		   "Polls 402_STATE_GET every poll s (link time) until the motor is in state; Timeout naming the "
		   "state it stays in and its statusword after timeout s.");
	madeByEcmxfOnly(c);
}

void bindRaw(py::module_ &m)
{
	auto h = py::class_<ResponseHeader>(m, "Header", "A response header (Device.last_header, Response.header).");
	h.def_readonly("crc_errors", &ResponseHeader::crcErrCnt, "SPI CRC error count (0x04).")
		.def_readonly("wkc_errors", &ResponseHeader::wkcErrCnt, "WKC error count (0x05).")
		.def_readonly("tx_fifo", &ResponseHeader::txFifoCnt, "TxPDOs in the chip's TxFIFO (0x06).")
		.def_readonly("rx_fifo", &ResponseHeader::rxFifoCnt, "RxPDOs in the chip's RxFIFO (0x07).")
		.def_readonly("ecat_state", &ResponseHeader::ecatState, "EtherCAT state (0x08).")
		.def_readonly("error_status", &ResponseHeader::errStatus, "Error status (0x09).")
		.def_readonly("ecm_status", &ResponseHeader::ecmStatus, "ECM status (0x0A).")
		.def_readonly("index", &ResponseHeader::index, "Index of the command answered (0x0B).")
		.def_readonly("code", &ResponseHeader::code, "Command code answered (0x0C).")
		.def_readonly("ret", &ResponseHeader::ret, "Return value (0x0D).")
		.def_readonly("len", &ResponseHeader::len, "Valid data length (0x0E).")
		.def_readonly("int_flags", &ResponseHeader::intFlags, "Interrupt flags (0x10).")
		.def_property_readonly("gpio_int_flags", [](const ResponseHeader &x) {
			return x.gpioIntFlag[0] | x.gpioIntFlag[1] << 8;
		}, "GPIO interrupt flags (0x14, 0x15), GPIO n at bit n.")
		.def_property_readonly("gpio_in", [](const ResponseHeader &x) { return x.gpioIn[0] | x.gpioIn[1] << 8; },
				       "GPIO inputs (0x16, 0x17), GPIO n at bit n.")
		.def("__repr__", &headerRepr);
	madeByEcmxfOnly(h);

	auto r = py::class_<ResponseRecord>(m, "Response", "The answer to Device.command().");
	r.def_readonly("header", &ResponseRecord::header, "The answering Header (an async command's: the completion's).")
		.def_readonly("data", &ResponseRecord::data, "The answer's data section bytes.")
		.def_readonly("ret", &ResponseRecord::ret, "The return value (header 0x0D).");
	madeByEcmxfOnly(r);

	auto d = py::class_<DatagramRecord>(m, "DatagramResult", "What came back for Device.datagram().");
	d.def_readonly("working_counter", &DatagramRecord::workingCounter)
		.def_readonly("data", &DatagramRecord::data)
		.def("__repr__", [](const DatagramRecord &x) {
			return "<ecmxf.DatagramResult working_counter=" + std::to_string(x.workingCounter) + " " +
			       std::to_string(py::len(x.data)) + " bytes>";
		});
	madeByEcmxfOnly(d);

	m.def("auto_increment_address", [](std::int64_t pos) { return autoIncrementAddress(position(pos)); },
	      py::arg("position"), "The ADP of an auto-increment datagram (APRD...) addressing bus position position.");
}

} // namespace

void bindChip(py::module_ &m, py::class_<DeviceObject> &device)
{
	bindEnums(m);
	bindPeripherals(m);
	bindChip402(m);
	bindRaw(m);

	device.def_property_readonly("peripherals", [](const DeviceObject &d) {
		(void)d.session->device("peripherals");
		return PeripheralsView{ d.session };
	}, "ECM-XF: the chip's GPIO, QEI, DAC, ADC and MDIO (Peripherals).")
		.def_property_readonly("chip402", [](const DeviceObject &d) {
			(void)d.session->device("chip402");
			return Chip402View{ d.session };
		}, "ECM-XF: the chip's CiA-402 engine (Chip402).")
		.def("command", [](DeviceObject &d, std::int64_t code, std::int64_t param, const py::object &data,
				   const py::object &payload, const std::optional<std::int64_t> &length,
				   std::int64_t reserved, std::int64_t control, double timeout) {
			return command(*d.session, code, param, data, payload, length, reserved, control, timeout);
		}, py::arg("code"), py::arg("param") = 0, py::arg("data") = py::bytes(), py::arg("payload") = py::bytes(),
		   py::arg("length") = py::none(), py::arg("reserved") = 0, py::arg("control") = 0,
		   py::arg("timeout") = 0.0,
		   "ECM-XF: one raw command (Device::command()): code and param (header 0x0C, 0x0D), data (up to 4 "
		   "bytes of parametric data, 0x04..0x07), payload (the data section), length (0x0E; None: the "
		   "payload's size), reserved (0x08), control (0x0A), timeout s (0: the command table's). An async "
		   "command is waited for. A Response; failures raise as the typed calls do.")
		.def_property_readonly("last_header", [](const DeviceObject &d) {
			return d.session->device("last_header").lastHeader();
		}, "ECM-XF: the latest response header of any exchange (Header), all zero before the first.")
		.def("datagram", [](DeviceObject &d, DatagramCommand cmd, std::int64_t adp, std::int64_t ado,
				    const py::object &data, const std::optional<std::int64_t> &length,
				    std::int64_t logical, double timeout) {
			return datagram(*d.session, cmd, adp, ado, data, length, logical, timeout);
		}, py::arg("command"), py::arg("adp") = 0, py::arg("ado") = 0, py::arg("data") = py::none(),
		   py::arg("length") = py::none(), py::arg("logical_address") = 0, py::arg("timeout") = 0.0,
		   "ECM-XF: one raw EtherCAT datagram (RAW_ECAT_FUNC_REQ/GET): adp (auto_increment_address() for "
		   "APxx, the station address for FPxx), ado (the ESC register), logical_address (LRD/LWR/LRW); data "
		   "to send (1..256 bytes), or length to read. A DatagramResult (working_counter, data).")
		.def("eeprom_read", [](DeviceObject &d, std::int64_t pos, std::int64_t address) {
			const unsigned p = position(pos);
			const auto a = u16(address, "word address");
			return onDevice(*d.session, "eeprom_read()", [&](Device &dev) { return dev.slaves().eepromRead(p, a); });
		}, py::arg("position"), py::arg("address"), "ECM-XF: one word of the slave's SII EEPROM.")
		.def("eeprom_read_words", [](DeviceObject &d, std::int64_t pos, std::int64_t address, std::int64_t count) {
			const unsigned p = position(pos);
			const auto a = u16(address, "word address");
			const auto n = static_cast<std::size_t>(checkedRange(count, 1, 65536, "count"));
			return onDevice(*d.session, "eeprom_read_words()",
					[&](Device &dev) { return dev.slaves().eepromReadWords(p, a, n); });
		}, py::arg("position"), py::arg("address"), py::arg("count"),
		   "ECM-XF: count words of the SII EEPROM from address on (a list of ints; one EEPROM_REQ each).")
		.def("eeprom_write", [](DeviceObject &d, std::int64_t pos, std::int64_t address, std::int64_t value) {
			const unsigned p = position(pos);
			const auto a = u16(address, "word address");
			const auto x = u16(value, "value");
			onDevice(*d.session, "eeprom_write()", [&](Device &dev) { dev.slaves().eepromWrite(p, a, x); });
		}, py::arg("position"), py::arg("address"), py::arg("value"), "ECM-XF: one word of the SII EEPROM.")
		.def("foe_read", [](DeviceObject &d, std::int64_t pos, const std::string &name, std::int64_t password,
				    std::int64_t flash, double timeout) {
			const unsigned p = position(pos);
			const FoeOptions o = foeOptions(password, flash, timeout);
			return toBytes(onDevice(*d.session, "foe_read()",
						[&](Device &dev) { return dev.slaves().foeRead(p, name, o); }));
		}, py::arg("position"), py::arg("name"), py::arg("password") = 0, py::arg("flash_address") = 0,
		   py::arg("timeout") = 0.0,
		   "ECM-XF: FoE read of file name from the slave, whole (staged in the chip's flash at "
		   "flash_address): bytes.")
		.def("foe_write", [](DeviceObject &d, std::int64_t pos, const std::string &name, const py::object &data,
				     std::int64_t password, std::int64_t flash, double timeout, const py::object &progress) {
			const unsigned p = position(pos);
			const std::vector<std::uint8_t> b = bytesOf(data, "data");
			const FoeOptions o = foeOptions(password, flash, timeout);
			const auto cb = progressOf(progress);
			onDevice(*d.session, "foe_write()", [&](Device &dev) { dev.slaves().foeWrite(p, name, b, o, cb); });
		}, py::arg("position"), py::arg("name"), py::arg("data"), py::arg("password") = 0,
		   py::arg("flash_address") = 0, py::arg("timeout") = 0.0, py::arg("progress") = py::none(),
		   "ECM-XF: FoE write of data as file name (staged in the flash, then FOE_FUNC_REQ download). A slave "
		   "in INIT is refused before anything is staged. progress(done, total) follows the staging; an "
		   "exception it raises ends the transfer (it must not call the device: BusyError).")
		.def("flash_read", [](DeviceObject &d, std::int64_t address, std::int64_t length) {
			const auto a = static_cast<std::uint32_t>(checkedRange(address, 0, kFoeFlashSize - 1, "address"));
			const auto n = static_cast<std::uint32_t>(checkedRange(length, 1, kFoeFlashSize, "length"));
			return toBytes(onDevice(*d.session, "flash_read()",
						[&](Device &dev) { return dev.slaves().flashRead(a, n); }));
		}, py::arg("address"), py::arg("length"), "ECM-XF: bytes of the chip's FoE staging flash.")
		.def("flash_write", [](DeviceObject &d, std::int64_t address, const py::object &data) {
			const auto a = static_cast<std::uint32_t>(checkedRange(address, 0, kFoeFlashSize - 1, "address"));
			const std::vector<std::uint8_t> b = bytesOf(data, "data");
			onDevice(*d.session, "flash_write()", [&](Device &dev) { dev.slaves().flashWrite(a, b); });
		}, py::arg("address"), py::arg("data"), "ECM-XF: bytes into the chip's FoE staging flash.");
}

} // namespace ecmxf::python
