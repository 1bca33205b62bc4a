// SPDX-License-Identifier: MIT
/*
 * ecmxf-util states - request an EtherCAT state for one slave or all, and
 * print the state each slave is in afterwards.
 */
#include "ecmxf-util.hpp"

#include <cctype>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/master.hpp>

namespace ecmxf_util {

const char *const kStatesHelp =
	"Usage: ecmxf-util [global options] states [-p N] [--no-dc] [--break-claim] [--json] STATE\n"
	"\n"
	"Request STATE (INIT, PREOP, SAFEOP, OP or BOOT, in any case; PRE-OP and\n"
	"SAFE-OP are accepted too) for the slave at position N, or for all slaves\n"
	"without -p, with ECAT_STATE_SET, and print the state of every slave\n"
	"concerned afterwards (ECAT_STATE_UPDATE + ECAT_SLV_INFO_GET):\n"
	"  POSITION  STATE  +/E  AL STATUS CODE  TEXT\n"
	"\n"
	"When the chip has no initialised network (ECAT state NONE, e.g. a fresh\n"
	"simulator) the bus is brought up first: for INIT, PREOP and BOOT with\n"
	"ECAT_INIT_OP (the slaves are then in INIT), for SAFEOP and OP\n"
	"with the library's Master bring-up (INIT_OP with DC SYNC0 1 ms, PRE-OP,\n"
	"PDO mapping; all slaves to STATE, the FIFO enabled for OP; with -p the\n"
	"bus is brought to PRE-OP and only slave N is moved on). A bus that is\n"
	"already up is not re-initialised.\n"
	"\n"
	"Upwards, a slave below STATE is walked through the states in between\n"
	"(INIT -> PRE-OP -> SAFE-OP -> OP) as IgH's master does: states -p N OP\n"
	"from PRE-OP requests SAFE-OP, then OP.\n"
	"\n"
	"A refused transition fails (exit 1) with the slave, the state it stays in\n"
	"and its AL status code and text.\n"
	"\n"
	"--break-claim (/dev/ecmxfN, CAP_SYS_ADMIN): first take the claim from the\n"
	"process that holds it (ECMXF_IOC_CLAIM_BREAK: its PDO rings stop), so that\n"
	"a machine whose cyclic application hangs can be brought to SAFEOP or INIT;\n"
	"while a process holds the claim nobody else may change the machine.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave at bus position N, a list (0,2) or a range\n"
	"                    (0-3) of them (default: all slaves)\n"
	"  --no-dc           bring the bus up without distributed clocks\n"
	"                    (AssignActivate 0): slaves that need SYNC0 refuse OP\n"
	"  --json            {\"requested\": ..., \"slaves\": [{position, state,\n"
	"                    al_state, error, al_status_code, al_status_text}]}\n"
	"  -h, --help        show this help\n";

namespace {

ecmxf::State parseState(const std::string &text)
{
	std::string u;
	for (const char c : text)
		if (c != '-' && c != '_')
			u += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
	// the library's state names (ecmxf::stateName()) without their '-'
	for (const ecmxf::State s : { ecmxf::State::Init, ecmxf::State::PreOp, ecmxf::State::SafeOp,
				      ecmxf::State::Op, ecmxf::State::Boot }) {
		std::string name = ecmxf::stateName(s);
		std::erase(name, '-');
		if (u == name)
			return s;
	}
	if (u == "BOOTSTRAP")
		return ecmxf::State::Boot;
	throw UsageError("states: unknown state '" + text + "' (INIT, PREOP, SAFEOP, OP or BOOT)");
}

struct Row {
	unsigned position;
	std::uint8_t state;
	bool error;
	std::uint16_t code;
};

} // namespace

int cmdStates(Globals &g, const Args &args)
{
	std::optional<std::string> posText;
	bool noDc = false, breakClaim = false;
	const auto pos = parseArgs("states", args, g, kStatesHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "", "--no-dc", &noDc, nullptr },
				     { "", "--break-claim", &breakClaim, nullptr } });
	if (!pos)
		return 0;
	if (pos->size() != 1)
		throw UsageError(pos->empty() ? "states: which state? (INIT, PREOP, SAFEOP, OP or BOOT)"
					      : "states: one STATE only (try 'ecmxf-util states --help')");
	const ecmxf::State want = parseState(pos->front());
	// none: all slaves; -p 1, -p 0,2, -p 0-3
	const std::optional<Positions> sel =
		posText ? std::optional(parsePositions("states", *posText)) : std::nullopt;
	const bool one = sel.has_value();

	const DevicePtr dev = openDevice(g);
	if (breakClaim) {
		// this command's file holds the claim from here until it exits
		const std::optional<std::uint32_t> was = dev->link().breakClaim();
		std::fprintf(stderr, "%s\n",
			     !was ? "states: no claim was held"
			     : *was ? ("states: broke the claim of process " + std::to_string(*was)).c_str()
				    : "states: broke the claim of a process in another pid namespace");
	}
	unsigned count = 0;
	if (busDown(*dev)) {
		ecmxf::InitConfig init;
		if (noDc)
			init.dc.assignActivate = 0;
		if (want == ecmxf::State::SafeOp || want == ecmxf::State::Op) {
			ecmxf::MasterConfig mc;
			mc.init = init;
			mc.target = one ? ecmxf::State::PreOp : want;
			mc.enableFifo = !one && want == ecmxf::State::Op;
			ecmxf::Master m(*dev);
			m.bringUp(mc);
		} else {
			dev->bus().initNetwork(init); // BOOT is entered from INIT (ETG.1000.6)
		}
	}
	count = dev->bus().slaveCount();
	if (one)
		checkPositions(*sel, count);
	else if (count == 0)
		throw ecmxf::Error("no slaves on the bus", ENODEV);

	// Upwards the EtherCAT state machine goes one state at a time: a slave
	// in INIT or PRE-OP refuses OP (AL status 0x0011). As IgH's master
	// does, walk each slave below the requested state through the states
	// in between (INIT -> PRE-OP -> SAFE-OP -> OP); BOOT goes back to INIT
	// first. Downwards and for BOOT the request is sent as it is.
	if (want == ecmxf::State::PreOp || want == ecmxf::State::SafeOp || want == ecmxf::State::Op) {
		dev->bus().stateUpdate();
		const auto rank = [](unsigned st) {
			switch (st & 0x0F) {
			case 1: return 1; // INIT
			case 2: return 2; // PRE-OP
			case 4: return 3; // SAFE-OP
			case 8: return 4; // OP
			default: return 0; // BOOT or unknown: from INIT
			}
		};
		const int wantRank = rank(static_cast<unsigned>(want));
		for (unsigned p = 0; p < count; p++) {
			if (one && !sel->has(p))
				continue;
			const auto p8 = static_cast<std::uint8_t>(p);
			int have = rank(static_cast<unsigned>(dev->bus().slaveInfo(p8).state));
			if (have >= wantRank - 1)
				continue;
			if (have == 0) {
				dev->bus().stateSet(p8, ecmxf::State::Init);
				have = 1;
			}
			for (const ecmxf::State step : { ecmxf::State::PreOp, ecmxf::State::SafeOp }) {
				const int r = rank(static_cast<unsigned>(step));
				if (r > have && r < wantRank)
					dev->bus().stateSet(p8, step);
			}
		}
	}
	if (one)
		for (const unsigned p : sel->list)
			dev->bus().stateSet(static_cast<std::uint8_t>(p), want);
	else
		dev->bus().stateSet(ecmxf::kAllSlaves, want);
	dev->bus().stateUpdate();

	std::vector<Row> rows;
	for (unsigned p = 0; p < count; p++) {
		if (one && !sel->has(p))
			continue;
		const auto p8 = static_cast<std::uint8_t>(p);
		const ecmxf::SlaveInfo si = dev->bus().slaveInfo(p8);
		const ecmxf::StateReading st = dev->bus().stateGet(p8);
		rows.push_back({ p, static_cast<std::uint8_t>(si.state), st.error(), si.alStatusCode });
	}

	if (g.json) {
		std::printf("{\"requested\": %s, \"slaves\": [",
			    jsonString(stateName(static_cast<std::uint8_t>(want))).c_str());
		for (std::size_t i = 0; i < rows.size(); i++) {
			const Row &r = rows[i];
			std::printf("%s\n  {\"position\": %u, \"state\": %s, \"al_state\": %u, \"error\": %s, "
				    "\"al_status_code\": %u, \"al_status_text\": %s}",
				    i ? "," : "", r.position, jsonString(stateName(r.state)).c_str(), r.state,
				    r.error ? "true" : "false", r.code,
				    jsonString(ecmxf::alStatusText(r.code)).c_str());
		}
		std::printf("%s]}\n", rows.empty() ? "" : "\n");
		return 0;
	}
	for (const Row &r : rows) {
		std::printf("%-3u  %-6s %c", r.position, stateName(r.state).c_str(), r.error ? 'E' : '+');
		if (r.code)
			std::printf("  AL status 0x%04x %.*s", r.code,
				    static_cast<int>(ecmxf::alStatusText(r.code).size()),
				    ecmxf::alStatusText(r.code).data());
		std::printf("\n");
	}
	return 0;
}

} // namespace ecmxf_util
