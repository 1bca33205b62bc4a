// SPDX-License-Identifier: MIT
// Board: the ECM-SK's typed commands over the slot protocol core
// (include/ecmxf/sk/board.hpp, Documentation/ecm-sk.rst).

#include <ecmxf/sk/board.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/link/unix_channel.hpp>
#include <ecmxf/sk/sim_channel.hpp>
#include <ecmxf/sk/uri.hpp>

#include "ecmsk-proto.h"

namespace ecmxf::sk {

using namespace std::chrono_literals;

std::string_view stateName(State s) noexcept
{
	switch (s) {
	case State::Init: return "INIT";
	case State::PreOp: return "PRE-OP";
	case State::SafeOp: return "SAFE-OP";
	case State::Op: return "OP";
	}
	return "?";
}

std::string_view slaveTypeName(SlaveType t) noexcept
{
	switch (t) {
	case SlaveType::Drive: return "Drive";
	case SlaveType::Io: return "IO";
	case SlaveType::Hsp: return "HSP";
	case SlaveType::Step: return "STEP";
	case SlaveType::None: return "none";
	}
	return "?";
}

namespace {

std::string hex(std::uint32_t v, int digits)
{
	char b[16];
	std::snprintf(b, sizeof(b), "0x%0*X", digits, v);
	return b;
}

std::string statesText(unsigned mask)
{
	std::string s;
	for (State st : { State::Init, State::PreOp, State::SafeOp, State::Op })
		if (mask & static_cast<unsigned>(st)) {
			if (!s.empty())
				s += ", ";
			s += stateName(st);
		}
	return s;
}

std::uint64_t ns(std::chrono::nanoseconds t)
{
	return t.count() > 0 ? static_cast<std::uint64_t>(t.count()) : 0;
}

} // namespace

struct Board::Link {
	ecmsk_link l{};
	std::vector<std::uint8_t> mosi, miso;
	ecmsk_result res{};
	std::chrono::milliseconds busyTimeout{ 100 };
	std::uint8_t nextIndex = 0;
	// sticky completions, cleared by whoever starts the command
	bool stateDone = false, sdoDone = false, homeDone = false;
	int stateErr = 0, sdoErr = 0, homeErr = 0;
	ecmsk_sdo sdo{};
	// the cyclic path
	std::array<bool, ECMSK_SLAVES_MAX + 1> staged{};
	unsigned stagedCount = 0;
	unsigned inFlight = 0; // cyclic commands of the last frame: not in its response yet
	std::uint16_t lastFull = 0;
};

Board::Board(std::pair<std::unique_ptr<ByteChannel>, SimBoard *> channel, LinkOptions options)
	: channel_(std::move(channel.first)), link_(std::make_unique<Link>()), sim_(channel.second)
{
	if (!channel_)
		throw Error("ECM-SK: no channel", EINVAL);
	std::uint32_t flags = 0;
	if (options.extensions & ~(ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC))
		throw Error("ECM-SK: extension bits " + hex(options.extensions, 2) + " (SET_EX has bits 0 and 1)",
			    EINVAL);
	if (options.extensions & ECMSK_EX_CMD_CRC)
		flags |= ECMSK_LINK_TX_CRC;
	if (options.extensions & ECMSK_EX_RSP_CRC)
		flags |= ECMSK_LINK_RX_CRC;
	if (ecmsk_link_init(&link_->l, options.slotSize, flags))
		throw Error("ECM-SK: slot size " + std::to_string(options.slotSize) +
				    " (12 or 16, the board's CONFIG2)",
			    EINVAL);
	link_->busyTimeout = options.busyTimeout;
	link_->mosi.assign(link_->l.g.frame_size, 0);
	link_->miso.assign(link_->l.g.frame_size, 0);
}

namespace {

// The simulated board behind @p c, known while its type is (simulator()
// then needs no downcast of the channel).
std::pair<std::unique_ptr<ByteChannel>, SimBoard *> withBoard(std::unique_ptr<SimBoardChannel> c)
{
	SimBoard *b = c ? &c->board() : nullptr;
	return { std::move(c), b };
}

} // namespace

Board::Board(std::unique_ptr<SimBoardChannel> channel, LinkOptions options)
	: Board(withBoard(std::move(channel)), options)
{
}

Board::Board(std::unique_ptr<ByteChannel> channel, LinkOptions options)
	: Board(std::pair<std::unique_ptr<ByteChannel>, SimBoard *>(std::move(channel), nullptr), options)
{
}

Board::~Board() = default;

bool Board::isSkUri(std::string_view uri) noexcept
{
	return uri.rfind("sk-", 0) == 0;
}

std::unique_ptr<Board> Board::open(std::string_view uri)
{
	const SkUri u = parseSkUri(uri);
	LinkOptions o;
	o.slotSize = u.slotSize;
	o.extensions = u.extensions;
	std::unique_ptr<ByteChannel> ch;
	switch (u.kind) {
	case SkUri::Kind::Sim:
		try {
			return std::make_unique<Board>(std::make_unique<SimBoardChannel>(u.path, u.board), o);
		} catch (const Error &) {
			throw;
		} catch (const std::exception &e) {
			throw Error(std::string(uri) + ": " + e.what(), EINVAL);
		}
		break;
	case SkUri::Kind::Unix:
		ch = std::make_unique<UnixChannel>(u.path);
		break;
	case SkUri::Kind::Spidev:
		ch = std::make_unique<SpidevChannel>(u.spidev);
		break;
	}
	return std::make_unique<Board>(std::move(ch), o);
}

SimBoard *Board::simulator() noexcept
{
	return sim_;
}

unsigned Board::slotSize() const noexcept { return link_->l.g.slot_size; }
unsigned Board::maxSlaves() const noexcept { return link_->l.g.max_slaves; }
std::size_t Board::frameSize() const noexcept { return link_->l.g.frame_size; }

// One exchange of the frame in link_->mosi; throws on a link failure.
void Board::xfer()
{
	Link &k = *link_;
	if (!channel_->waitReady(k.busyTimeout))
		throw Error(channel_->name() + ": the ECM-SK's Busy line stayed high for " +
				    std::to_string(k.busyTimeout.count()) + " ms",
			    ETIMEDOUT);
	const int pr = ecmsk_link_prepare(&k.l, k.mosi.data(), ns(channel_->now()), 0);
	if (pr) {
		std::fill(k.mosi.begin(), k.mosi.end(), 0);
		k.staged = {};
		k.stagedCount = 0;
		throw Error(channel_->name() + (pr == -EBUSY ? ": an SDO or a GO_HOME is still running"
							     : ": a command in the wrong slot"),
			    -pr);
	}
	channel_->exchange(k.mosi, k.miso);
	std::fill(k.mosi.begin(), k.mosi.end(), 0);
	k.staged = {};
	// the response came out while this frame went in: it shows the FIFO
	// without this frame's cyclic commands
	k.inFlight = k.stagedCount;
	k.stagedCount = 0;
	const int cr = ecmsk_link_complete(&k.l, k.miso.data(), ns(channel_->now()), &k.res);
	if (k.res.state_done) {
		k.stateDone = true;
		k.stateErr = k.res.state_err;
	}
	if (k.res.sdo_done) {
		k.sdoDone = true;
		k.sdoErr = k.res.sdo_err;
		k.sdo = k.res.sdo;
	}
	if (k.res.home_done) {
		k.homeDone = true;
		k.homeErr = k.res.home_err;
	}
	if (cr == 0)
		k.lastFull = k.res.ecm.fifo_full;
	if (cr)
		throw Error(channel_->name() + ": the ECM-SK's response failed its CRC-8", EBADMSG);
}

// The command in the frame, then GET_STATUS: the second response answers it.
void Board::transact()
{
	xfer();
	xfer();
	if (link_->res.refused)
		throw Error(channel_->name() + ": the ECM-SK refused the frame for a bad CRC-8 (it checks command "
					       "CRCs: give ex=1 or ex=3 in the URI)",
			    EBADMSG);
}

BoardStatus Board::status()
{
	xfer();
	BoardStatus s;
	const auto &e = link_->res.ecm;
	s.state = static_cast<State>(e.state);
	s.crcErrors = e.crc_errors;
	s.fifoRemaining = e.fifo_remaining;
	s.fifoFull = e.fifo_full;
	return s;
}

State Board::state() const noexcept
{
	return static_cast<State>(link_->l.state);
}

void Board::require(std::uint16_t cmd, const char *what) const
{
	const unsigned ok = ecmsk_cmd_states(cmd);
	if (!(ok & link_->l.state))
		throw Error(std::string(what) + " is allowed in " + statesText(ok) + "; the ECM-SK is in " +
				    std::string(stateName(state())),
			    EPERM);
}

void Board::checkSlave(unsigned slave, const char *cmd) const
{
	if (slave < 1 || slave > maxSlaves())
		throw Error(std::string(cmd) + ": slave " + std::to_string(slave) + " is outside 1.." +
				    std::to_string(maxSlaves()),
			    EINVAL);
}

void Board::refused(const std::string &cmd, const std::string &why) const
{
	std::string msg = "the ECM-SK refused " + cmd + " in " + std::string(stateName(state())) + ": " + why;
	throw Error(msg, EPERM);
}

void Board::setState(State s, std::chrono::milliseconds timeout)
{
	if (!link_->l.have_rsp)
		status();
	Link &k = *link_;
	ecmsk_ecm_cmd c{ ECMSK_CMD_SET_STATE, 0, static_cast<std::uint32_t>(s), 0, 0 };
	ecmsk_put_ecm(&k.l.g, k.mosi.data(), &c);
	k.stateDone = false;
	const auto end = channel_->now() + timeout;
	xfer();
	while (!k.stateDone) {
		if (channel_->now() >= end) {
			std::string msg = "SET_STATE " + std::string(stateName(s)) + ": the ECM-SK stayed in " +
					  std::string(stateName(state())) + " for " + std::to_string(timeout.count()) +
					  " ms";
			if (auto *sim = simulator(); sim && !sim->lastError().empty())
				msg += " (simulator: " + sim->lastError() + ")";
			k.l.ecm.active = false;
			throw Error(msg, ETIMEDOUT);
		}
		channel_->sleepFor(250us);
		xfer();
	}
	if (k.stateErr)
		throw Error("SET_STATE " + std::string(stateName(s)) + ": the board refused the frame (CRC)",
			    -k.stateErr);
}

unsigned Board::setAxes(std::span<const SlaveType> types)
{
	if (types.size() > maxSlaves())
		throw Error("SET_AXIS: " + std::to_string(types.size()) + " slave types, the frame has " +
				    std::to_string(maxSlaves()) + " slave slots",
			    EINVAL);
	if (!link_->l.have_rsp)
		status();
	require(ECMSK_CMD_SET_AXIS, "SET_AXIS");
	std::vector<std::uint8_t> t(types.size());
	for (std::size_t i = 0; i < types.size(); i++)
		t[i] = static_cast<std::uint8_t>(types[i]);
	unsigned count = 0;
	const unsigned groups = std::max<unsigned>(1, static_cast<unsigned>((t.size() + 7) / 8));
	for (unsigned g = 0; g < groups; g++) {
		std::uint32_t topo = 0;
		if (ecmsk_axis_topology(t.data(), static_cast<unsigned>(t.size()), g, &topo))
			throw Error("SET_AXIS: a slave type other than Drive, IO, HSP or STEP", EINVAL);
		ecmsk_ecm_cmd c{ ECMSK_CMD_SET_AXIS, static_cast<std::uint8_t>(g), topo, 0, 0 };
		ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
		transact();
		if (!ecmsk_link_answered(&link_->l, 0, link_->miso.data()))
			refused("SET_AXIS group " + std::to_string(g), "not allowed now");
		const auto &e = link_->res.ecm;
		if (e.data2) {
			std::string which;
			for (unsigned i = 0; i < 8; i++)
				if (e.data2 & (1u << i)) {
					const unsigned n = g * 8 + i;
					which += (which.empty() ? "" : ", ") + std::to_string(n + 1) + " (" +
						 std::string(slaveTypeName(types[n])) + ")";
				}
			throw Error("SET_AXIS: the ECM-SK refused the types of group " + std::to_string(g) +
					    ": slave " + which + " is not of that type (or not there); " +
					    std::to_string(e.data1) + " slaves detected",
				    EPERM);
		}
		count = e.data1;
	}
	return count;
}

unsigned Board::slaveCount()
{
	return setAxes({});
}

std::vector<SlaveType> Board::detectAxes()
{
	const unsigned count = slaveCount();
	if (state() != State::PreOp)
		throw Error("detecting the slave types needs PRE-OP; the ECM-SK is in " +
				    std::string(stateName(state())),
			    EPERM);
	static constexpr SlaveType kOrder[] = { SlaveType::Drive, SlaveType::Step, SlaveType::Hsp, SlaveType::Io };
	std::vector<SlaveType> types(count, SlaveType::Drive);
	std::vector<unsigned> tried(count, 0);
	for (unsigned g = 0; g * 8 < count; g++) {
		for (;;) {
			std::vector<std::uint8_t> t(types.size());
			for (std::size_t i = 0; i < t.size(); i++)
				t[i] = static_cast<std::uint8_t>(types[i]);
			std::uint32_t topo = 0;
			ecmsk_axis_topology(t.data(), static_cast<unsigned>(t.size()), g, &topo);
			ecmsk_ecm_cmd c{ ECMSK_CMD_SET_AXIS, static_cast<std::uint8_t>(g), topo, 0, 0 };
			ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
			transact();
			if (!ecmsk_link_answered(&link_->l, 0, link_->miso.data()))
				refused("SET_AXIS group " + std::to_string(g), "not allowed now");
			const std::uint32_t bad = link_->res.ecm.data2;
			if (!bad)
				break;
			for (unsigned i = 0; i < 8; i++) {
				if (!(bad & (1u << i)))
					continue;
				const unsigned n = g * 8 + i;
				if (n >= count || ++tried[n] >= 4)
					throw Error("SET_AXIS: slave " + std::to_string(n + 1) +
							    " is none of Drive, STEP, HSP, IO",
						    EPROTO);
				types[n] = kOrder[tried[n]];
			}
		}
	}
	return types;
}

void Board::setCycleTime(std::uint32_t us)
{
	if (!ecmsk_dc_cycle_valid(us))
		throw Error("SET_DC: " + std::to_string(us) + " us is not 250 * 2^n us", EINVAL);
	if (!link_->l.have_rsp)
		status();
	require(ECMSK_CMD_SET_DC, "SET_DC");
	ecmsk_ecm_cmd c{ ECMSK_CMD_SET_DC, 0, us, ECMSK_DC_FIX, 0 };
	ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
	transact();
	if (!ecmsk_link_answered(&link_->l, 0, link_->miso.data()))
		refused("SET_DC " + std::to_string(us) + " us", "cycle time not taken");
}

void Board::setExtensions(std::uint32_t bits)
{
	if (bits > (ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC))
		throw Error("SET_EX: " + hex(bits, 2) + " (bit 0 command CRC, bit 1 response CRC)", EINVAL);
	if (!link_->l.have_rsp)
		status();
	require(ECMSK_CMD_SET_EX, "SET_EX");
	ecmsk_ecm_cmd c{ ECMSK_CMD_SET_EX, 0, bits, 0, 0 };
	ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
	transact();
	if (!ecmsk_link_answered(&link_->l, 0, link_->miso.data()))
		refused("SET_EX", "setting not taken");
}

void Board::slaveCommand(unsigned slave, std::uint8_t cmd, std::uint32_t target, std::uint32_t value)
{
	const char *name = ecmsk_cmd_name(cmd);
	checkSlave(slave, name);
	if (!link_->l.have_rsp)
		status();
	require(cmd, name);
	Link &k = *link_;
	ecmsk_slave_cmd c{ cmd, ++k.nextIndex, target, value, 0 };
	ecmsk_put_slave(&k.l.g, k.mosi.data(), slave, &c);
	transact();
	if (!ecmsk_link_answered(&k.l, slave, k.miso.data()))
		refused(std::string(name) + " for slave " + std::to_string(slave),
			"not a command for that slave's type (SET_AXIS), mode (DRIVE_MODE) or state");
}

void Board::driveMode(unsigned slave, Mode mode, Sync sync)
{
	slaveCommand(slave, ECMSK_CMD_DRIVE_MODE, static_cast<std::uint32_t>(mode), static_cast<std::uint32_t>(sync));
}

void Board::checkSize(std::uint16_t index, std::uint8_t sub, unsigned size, std::size_t want)
{
	if (size != want)
		throw Error("SDO_RD " + hex(index, 4) + ":" + hex(sub, 2).substr(2) + ": the object is " +
				    std::to_string(size) + " byte(s), read as " + std::to_string(want),
			    EMSGSIZE);
}

std::uint32_t Board::sdoRead(unsigned slave, std::uint16_t index, std::uint8_t subindex, unsigned *size)
{
	checkSlave(slave, "SDO_RD");
	if (!link_->l.have_rsp)
		status();
	require(ECMSK_CMD_SDO_RD, "SDO_RD");
	Link &k = *link_;
	ecmsk_sdo c{ ECMSK_CMD_SDO_RD, 0, static_cast<std::uint8_t>(slave), 0, subindex, index, 0 };
	ecmsk_put_sdo(&k.l.g, k.mosi.data(), &c);
	k.sdoDone = false;
	const std::string what = "SDO_RD slave " + std::to_string(slave) + " " + hex(index, 4) + ":" +
				 hex(subindex, 2).substr(2);
	const auto end = channel_->now() + 5s;
	xfer();
	while (!k.sdoDone) {
		if (channel_->now() >= end) {
			k.l.sdo.active = false;
			throw Error(what + ": no answer within 5 s", ETIMEDOUT);
		}
		channel_->sleepFor(250us);
		xfer();
	}
	if (k.sdoErr == -EIO)
		throw SdoError(what + ": aborted, " + hex(k.sdo.value, 8) + " " +
				       std::string(sdoAbortText(k.sdo.value)),
			       EREMOTEIO, k.sdo.value);
	if (k.sdoErr == -EACCES)
		refused(what, "SDO is allowed in PRE-OP, SAFE-OP and OP");
	if (k.sdoErr)
		throw Error(what + ": failed", -k.sdoErr);
	if (size)
		*size = k.sdo.size;
	return k.sdo.value;
}

void Board::sdoWrite(unsigned slave, std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
		     unsigned size)
{
	checkSlave(slave, "SDO_WR");
	const std::string what = "SDO_WR slave " + std::to_string(slave) + " " + hex(index, 4) + ":" +
				 hex(subindex, 2).substr(2);
	if (size != 1 && size != 2 && size != 4)
		throw Error(what + ": size " + std::to_string(size) + " (1, 2 or 4 bytes)", EINVAL);
	if (size < 4 && (value >> (8 * size)))
		throw Error(what + ": " + hex(value, 8) + " does not fit in " + std::to_string(size) + " byte(s)",
			    EINVAL);
	if (!link_->l.have_rsp)
		status();
	require(ECMSK_CMD_SDO_WR, "SDO_WR");
	Link &k = *link_;
	ecmsk_sdo c{ ECMSK_CMD_SDO_WR, 0, static_cast<std::uint8_t>(slave), static_cast<std::uint8_t>(size),
		     subindex, index, value };
	ecmsk_put_sdo(&k.l.g, k.mosi.data(), &c);
	k.sdoDone = false;
	const auto end = channel_->now() + 5s;
	xfer();
	while (!k.sdoDone) {
		if (channel_->now() >= end) {
			k.l.sdo.active = false;
			throw Error(what + ": no answer within 5 s", ETIMEDOUT);
		}
		channel_->sleepFor(250us);
		xfer();
	}
	if (k.sdoErr == -EIO)
		throw SdoError(what + ": aborted, " + hex(k.sdo.value, 8) + " " +
				       std::string(sdoAbortText(k.sdo.value)),
			       EREMOTEIO, k.sdo.value);
	if (k.sdoErr == -EACCES)
		refused(what, "SDO is allowed in PRE-OP, SAFE-OP and OP");
	if (k.sdoErr)
		throw Error(what + ": failed", -k.sdoErr);
}

void Board::servoOn(unsigned slave) { slaveCommand(slave, ECMSK_CMD_SV_ON); }
void Board::servoOff(unsigned slave) { slaveCommand(slave, ECMSK_CMD_SV_OFF); }
void Board::alarmClear(unsigned slave) { slaveCommand(slave, ECMSK_CMD_ALM_CLR); }

void Board::waitEnabled(unsigned slave, std::chrono::milliseconds timeout)
{
	checkSlave(slave, "SV_ON");
	const auto end = channel_->now() + timeout;
	for (;;) {
		xfer();
		const auto a = axis(slave);
		if ((a.statusword & 0x6F) == 0x27)
			return;
		if (channel_->now() >= end)
			throw Error("slave " + std::to_string(slave) + " did not reach Operation enabled within " +
					    std::to_string(timeout.count()) + " ms (statusword " +
					    hex(a.statusword, 4) + ", error code " + hex(a.errorCode, 4) + ")",
				    ETIMEDOUT);
		channel_->sleepFor(500us);
	}
}

std::uint32_t Board::ioRead(unsigned slave)
{
	slaveCommand(slave, ECMSK_CMD_IO_RD);
	return static_cast<std::uint32_t>(axis(slave).position);
}

void Board::ioWrite(unsigned slave, std::uint32_t outputs)
{
	slaveCommand(slave, ECMSK_CMD_IO_WR, outputs);
}

std::uint32_t Board::lioRead()
{
	ecmsk_ecm_cmd c{ ECMSK_CMD_LIO_RD, 0, 0, 0, 0 };
	ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
	transact();
	return link_->res.ecm.data1;
}

void Board::lioWrite(std::uint32_t outputs)
{
	if (outputs > 0x3F)
		throw Error("LIO_WR: " + hex(outputs, 2) + " (the ECM IC has outputs 0..5)", EINVAL);
	ecmsk_ecm_cmd c{ ECMSK_CMD_LIO_WR, 0, outputs, 0, 0 };
	ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
	transact();
	if (!ecmsk_link_answered(&link_->l, 0, link_->miso.data()))
		refused("LIO_WR", "outputs not taken");
}

void Board::home(unsigned slave, std::int8_t method, std::chrono::milliseconds timeout)
{
	checkSlave(slave, "GO_HOME");
	sdoWrite<std::int8_t>(slave, 0x6060, 0, 6);
	sdoWrite<std::int8_t>(slave, 0x6098, 0, method);
	Link &k = *link_;
	k.homeDone = false;
	const auto end = channel_->now() + timeout;
	slaveCommand(slave, ECMSK_CMD_GO_HOME);
	while (!k.homeDone) {
		if (channel_->now() >= end) {
			k.l.home.active = false;
			throw Error("GO_HOME slave " + std::to_string(slave) + ": not homed within " +
					    std::to_string(timeout.count()) + " ms (statusword " +
					    hex(axis(slave).statusword, 4) + ")",
				    ETIMEDOUT);
		}
		channel_->sleepFor(1ms);
		xfer();
	}
	if (k.homeErr == -EIO)
		throw Error("GO_HOME slave " + std::to_string(slave) + ": homing error (statusword bit 13, " +
				    hex(axis(slave).statusword, 4) + ")",
			    EIO);
	if (k.homeErr)
		throw Error("GO_HOME slave " + std::to_string(slave) + ": failed", -k.homeErr);
}

void Board::abortHome(unsigned slave)
{
	slaveCommand(slave, ECMSK_CMD_ABORT_HOME);
}

void Board::reset()
{
	ecmsk_ecm_cmd c{ ECMSK_CMD_SW_RESET, 0, 0, 0, 0 };
	ecmsk_put_ecm(&link_->l.g, link_->mosi.data(), &c);
	xfer();
	if (!channel_->waitReady(1s))
		throw Error(channel_->name() + ": Busy stayed high for 1 s after SW_RESET", ETIMEDOUT);
	ecmsk_link_reset(&link_->l);
	status();
}

AxisStatus Board::axis(unsigned slave) const
{
	checkSlave(slave, "axis");
	ecmsk_slave_rsp r{};
	ecmsk_get_slave(&link_->l.g, link_->miso.data(), slave, &r);
	AxisStatus a;
	a.cmd = r.cmd;
	a.index = r.index;
	a.statusword = r.statusword;
	a.position = static_cast<std::int32_t>(r.position);
	a.torque = static_cast<std::int16_t>(r.torque);
	a.errorCode = r.error_code;
	return a;
}

bool Board::stage(unsigned slave, Mode mode, std::int32_t target, std::uint32_t output) noexcept
{
	Link &k = *link_;
	if (slave < 1 || slave > k.l.g.max_slaves || k.staged[slave])
		return false;
	if (k.l.state != ECMSK_STATE_OP)
		return false;
	if (k.stagedCount + k.inFlight >= k.res.ecm.fifo_remaining)
		return false; // back-pressure: no room as last reported
	const auto cmd = static_cast<std::uint8_t>(ECMSK_CMD_CSP + (static_cast<unsigned>(mode) - ECMSK_MODE_CSP));
	ecmsk_slave_cmd c{ cmd, ++k.nextIndex, static_cast<std::uint32_t>(target), output, 0 };
	if (ecmsk_put_slave(&k.l.g, k.mosi.data(), slave, &c))
		return false;
	k.staged[slave] = true;
	k.stagedCount++;
	return true;
}

bool Board::stage2(unsigned slave, Mode mode, std::int32_t target1, std::int32_t target2, std::uint16_t output1,
		   std::uint16_t output2) noexcept
{
	Link &k = *link_;
	if (k.l.g.slot_size != ECMSK_SLOT16 || mode == Mode::Cst)
		return false;
	if (slave < 1 || slave > k.l.g.max_slaves || k.staged[slave] || k.l.state != ECMSK_STATE_OP)
		return false;
	if (k.stagedCount + k.inFlight >= k.res.ecm.fifo_remaining)
		return false;
	const auto cmd = static_cast<std::uint8_t>(mode == Mode::Csp ? ECMSK_CMD_CSP : ECMSK_CMD_CSV);
	ecmsk_hsp2 c{ cmd, ++k.nextIndex, 0, static_cast<std::uint32_t>(target1), output1,
		      static_cast<std::uint32_t>(target2), output2 };
	if (ecmsk_put_hsp2(&k.l.g, k.mosi.data(), slave, &c))
		return false;
	k.staged[slave] = true;
	k.stagedCount++;
	return true;
}

Hsp2Status Board::hsp2(unsigned slave) const
{
	checkSlave(slave, "hsp2");
	ecmsk_hsp2 r{};
	if (ecmsk_get_hsp2(&link_->l.g, link_->miso.data(), slave, &r))
		throw Error("a 2-channel HSP needs 16-byte slots (the board's CONFIG2 high, slot=16)", EINVAL);
	Hsp2Status h;
	h.cmd = r.cmd;
	h.index = r.index;
	h.statusword = r.statusword;
	h.position1 = static_cast<std::int32_t>(r.pos1);
	h.inputs1 = r.io1;
	h.position2 = static_cast<std::int32_t>(r.pos2);
	h.inputs2 = r.io2;
	return h;
}

CycleResult Board::cycle() noexcept
{
	Link &k = *link_;
	CycleResult r;
	r.staged = k.stagedCount;
	const std::uint16_t before = k.lastFull;
	try {
		if (!channel_->waitReady(k.busyTimeout)) {
			r.status = CycleStatus::Busy;
			return r;
		}
		xfer();
	} catch (const Error &e) {
		r.status = e.errnoValue() == EBADMSG ? CycleStatus::BadResponse : CycleStatus::Link;
		if (r.status == CycleStatus::Link)
			lastError_ = e.what();
		return r;
	} catch (const std::exception &e) {
		lastError_ = e.what();
		r.status = CycleStatus::Link;
		return r;
	}
	r.fifoRemaining = k.res.ecm.fifo_remaining;
	r.fifoFull = k.res.ecm.fifo_full;
	r.dropped = static_cast<std::uint16_t>(r.fifoFull - before);
	if (r.dropped)
		r.status = CycleStatus::FifoOverflow;
	return r;
}

} // namespace ecmxf::sk
