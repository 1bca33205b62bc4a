// SPDX-License-Identifier: MIT
/*
 * ecmxf-util pdos - each slave's PDO assignment and mapping, from
 * Master::pdos().
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/master.hpp>

namespace ecmxf_util {

const char *const kPdosHelp =
	"Usage: ecmxf-util [global options] pdos [-p N] [--json | --cstruct | --xml]\n"
	"\n"
	"The PDO assignment and mapping of each slave (or of slave N): per sync\n"
	"manager and direction the PDOs in assignment order, and per PDO its\n"
	"entries (index:subindex, bit length, bit offset within the slave's\n"
	"outputs or inputs, name of common CiA 301/402 objects):\n"
	"\n"
	"  SM2 outputs (RxPDO), 12 bytes\n"
	"    PDO 0x1600\n"
	"      0x6040:00  16 bit  offset    0  Controlword\n"
	"\n"
	"The mapping is read by the library's Master (SDO reads of 0x1C12/0x1C13\n"
	"and 0x16xx/0x1Axx, or the SII's PDO categories for slaves without CoE).\n"
	"The sync manager is SM2/SM3 for slaves with a mailbox (SII word 0x19, the\n"
	"standard receive mailbox size, not 0) and SM0/SM1 without one, the\n"
	"ETG.2000 convention (the chip does not report it). A fresh bus is\n"
	"brought up to PRE-OP by the Master first; a bus that is already up is\n"
	"only read.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  only the slave at bus position N\n"
	"  --json            an array of {position, name, output_bytes,\n"
	"                    input_bytes, sync_managers: [{sm, direction, bytes,\n"
	"                    pdos: [{index, entries: [{index, sub, bit_length,\n"
	"                    bit_offset, name}]}]}]}\n"
	"  --cstruct         the mapping as C structures for IgH's application\n"
	"                    interface (ec_pdo_entry_info_t, ec_pdo_info_t,\n"
	"                    ec_sync_info_t), as IgH's 'ethercat cstruct' prints\n"
	"  --xml             the mapping as EtherCATInfo XML (Vendor, Type,\n"
	"                    RxPdo/TxPdo with their entries), as IgH's\n"
	"                    'ethercat xml' prints\n"
	"  -h, --help        show this help\n";

namespace {

struct Pdo {
	std::uint16_t index = 0;
	std::vector<const ecmxf::PdoEntryInfo *> entries;
};

std::vector<Pdo> groupByPdo(const std::vector<ecmxf::PdoEntryInfo> &entries)
{
	std::vector<Pdo> out;
	for (const ecmxf::PdoEntryInfo &e : entries) {
		if (out.empty() || out.back().index != e.pdo)
			out.push_back({ e.pdo, {} });
		out.back().entries.push_back(&e);
	}
	return out;
}

/// IgH's "ethercat cstruct" for one slave.
void printCstruct(unsigned p, const ecmxf::SlaveInfo &si, unsigned smOut, const ecmxf::SlavePdos &sp)
{
	std::printf("/* Slave %u, \"%s\"\n * Vendor ID:       0x%08x\n * Product code:    0x%08x\n"
		    " * Revision number: 0x%08x\n */\n\n",
		    p, si.name.c_str(), si.vendorId, si.productCode, si.revision);
	const std::vector<Pdo> out = groupByPdo(sp.outputs), in = groupByPdo(sp.inputs);
	std::printf("ec_pdo_entry_info_t slave_%u_pdo_entries[] = {\n", p);
	for (const std::vector<Pdo> *side : { &out, &in })
		for (const Pdo &pdo : *side)
			for (const ecmxf::PdoEntryInfo *x : pdo.entries) {
				std::printf("    {0x%04x, 0x%02x, %u},", x->index, x->sub, x->bitLength);
				if (!x->name.empty())
					std::printf(" /* %s */", x->name.c_str());
				std::printf("\n");
			}
	std::printf("};\n\nec_pdo_info_t slave_%u_pdos[] = {\n", p);
	std::size_t entry = 0;
	for (const std::vector<Pdo> *side : { &out, &in })
		for (const Pdo &pdo : *side) {
			std::printf("    {0x%04x, %zu, slave_%u_pdo_entries + %zu},\n", pdo.index, pdo.entries.size(),
				    p, entry);
			entry += pdo.entries.size();
		}
	std::printf("};\n\nec_sync_info_t slave_%u_syncs[] = {\n", p);
	if (smOut == 2) {
		std::printf("    {0, EC_DIR_OUTPUT, 0, NULL, EC_WD_DISABLE},\n");
		std::printf("    {1, EC_DIR_INPUT, 0, NULL, EC_WD_DISABLE},\n");
	}
	std::printf("    {%u, EC_DIR_OUTPUT, %zu, %s, EC_WD_ENABLE},\n", smOut, out.size(),
		    out.empty() ? "NULL" : ("slave_" + std::to_string(p) + "_pdos + 0").c_str());
	std::printf("    {%u, EC_DIR_INPUT, %zu, %s, EC_WD_DISABLE},\n", smOut + 1, in.size(),
		    in.empty() ? "NULL" : ("slave_" + std::to_string(p) + "_pdos + " + std::to_string(out.size())).c_str());
	std::printf("    {0xff}\n};\n\n");
}

/// "<" and "&" as XML wants them.
std::string xmlText(const std::string &s)
{
	std::string o;
	for (const char c : s) {
		if (c == '<')
			o += "&lt;";
		else if (c == '>')
			o += "&gt;";
		else if (c == '&')
			o += "&amp;";
		else if (c == '"')
			o += "&quot;";
		else
			o += c;
	}
	return o;
}

/// IgH's "ethercat xml" for one slave: an EtherCATInfo element (after
/// the XML declaration when @p document).
void printXml(const ecmxf::SlaveInfo &si, unsigned smOut, const ecmxf::SlavePdos &sp, bool document)
{
	if (document)
		std::printf("<?xml version=\"1.0\" ?>\n");
	std::printf("<EtherCATInfo>\n  <!-- Slave %s -->\n", xmlText(si.name).c_str());
	std::printf("  <Vendor>\n    <Id>%u</Id>\n  </Vendor>\n  <Descriptions>\n    <Devices>\n      <Device>\n",
		    si.vendorId);
	std::printf("        <Type ProductCode=\"#x%08x\" RevisionNo=\"#x%08x\">%s</Type>\n", si.productCode,
		    si.revision, xmlText(si.name).c_str());
	struct Side {
		const char *tag;
		unsigned sm;
		const std::vector<ecmxf::PdoEntryInfo> *entries;
	};
	for (const Side &s : { Side{ "RxPdo", smOut, &sp.outputs }, Side{ "TxPdo", smOut + 1, &sp.inputs } })
		for (const Pdo &pdo : groupByPdo(*s.entries)) {
			std::printf("        <%s Sm=\"%u\" Fixed=\"1\" Mandatory=\"1\">\n          <Index>#x%04x</Index>\n",
				    s.tag, s.sm, pdo.index);
			for (const ecmxf::PdoEntryInfo *x : pdo.entries) {
				std::printf("          <Entry>\n            <Index>#x%04x</Index>\n", x->index);
				if (x->index)
					std::printf("            <SubIndex>%u</SubIndex>\n", x->sub);
				std::printf("            <BitLen>%u</BitLen>\n", x->bitLength);
				if (!x->name.empty())
					std::printf("            <Name>%s</Name>\n", xmlText(x->name).c_str());
				std::printf("          </Entry>\n");
			}
			std::printf("        </%s>\n", s.tag);
		}
	std::printf("      </Device>\n    </Devices>\n  </Descriptions>\n</EtherCATInfo>\n");
}

} // namespace

int cmdPdos(Globals &g, const Args &args)
{
	std::optional<std::string> posText;
	bool cstruct = false, xml = false;
	const auto pos = parseArgs("pdos", args, g, kPdosHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "", "--cstruct", &cstruct, nullptr },
				     { "", "--xml", &xml, nullptr } });
	if (!pos)
		return 0;
	if (!pos->empty())
		throw UsageError("pdos: unexpected argument '" + pos->front() + "' (try 'ecmxf-util pdos --help')");
	if (static_cast<int>(cstruct) + static_cast<int>(xml) + static_cast<int>(g.json) > 1)
		throw UsageError("pdos: --json, --cstruct and --xml exclude each other");
	// none: all slaves; -p 1, -p 0,2, -p 0-3
	const std::optional<Positions> sel = posText ? std::optional(parsePositions("pdos", *posText)) : std::nullopt;
	const bool one = sel && sel->list.size() == 1; // one slave: one document of its own (--xml)

	const DevicePtr dev = openDevice(g);
	ecmxf::Master m(*dev);
	if (busDown(*dev)) {
		ecmxf::MasterConfig mc;
		mc.target = ecmxf::State::PreOp;
		mc.enableFifo = false;
		mc.readPdoMapping = false; // read below, slave by slave, with progress
		m.bringUp(mc);
	} else {
		m.rescan();
	}
	const unsigned count = static_cast<unsigned>(m.slaves().size());
	if (sel)
		checkPositions(*sel, count);

	std::vector<ecmxf::SlavePdos> pdos(count);
	std::vector<bool> mailbox(count);
	// the long part of a big bus (SDO reads of every mapping): progress
	Progress progress(g, "pdos", "slaves");
	const std::size_t wanted = sel ? sel->list.size() : count;
	std::size_t done = 0;
	for (unsigned p = 0; p < count; p++) {
		if (sel && !sel->has(p))
			continue;
		const auto p8 = static_cast<std::uint8_t>(p);
		pdos[p] = m.pdos().size() > p ? m.pdos()[p] : m.readSlavePdos(p8);
		const std::uint16_t mbxSize = dev->slaves().eepromRead(p, 0x19);
		mailbox[p] = mbxSize != 0 && mbxSize != 0xFFFF;
		progress(++done, wanted);
	}

	if (g.json)
		std::printf("[");
	// several slaves: one document, their EtherCATInfo elements in an
	// EtherCATInfoList (ETG's list of ESI), not documents one after another
	if (xml && !one)
		std::printf("<?xml version=\"1.0\" ?>\n<EtherCATInfoList>\n");
	bool first = true;
	for (unsigned p = 0; p < count; p++) {
		if (sel && !sel->has(p))
			continue;
		const ecmxf::SlaveInfo &si = m.slaves()[p];
		const ecmxf::SlavePdos &sp = pdos[p];
		const unsigned smOut = mailbox[p] ? 2 : 0, smIn = smOut + 1;
		if (cstruct || xml) {
			if (cstruct)
				printCstruct(p, si, smOut, sp);
			else
				printXml(si, smOut, sp, one);
			continue;
		}
		struct Side {
			unsigned sm;
			const char *dir;
			const char *kind;
			std::uint32_t bytes;
			const std::vector<ecmxf::PdoEntryInfo> *entries;
		};
		const Side sides[] = { { smOut, "outputs", "RxPDO", sp.outputBytes, &sp.outputs },
				       { smIn, "inputs", "TxPDO", sp.inputBytes, &sp.inputs } };
		if (g.json) {
			std::printf("%s\n  {\"position\": %u, \"name\": %s, \"output_bytes\": %u, \"input_bytes\": %u, "
				    "\"sync_managers\": [",
				    first ? "" : ",", p, jsonString(si.name).c_str(), sp.outputBytes, sp.inputBytes);
			bool firstSm = true;
			for (const Side &s : sides) {
				if (s.entries->empty())
					continue;
				std::printf("%s\n    {\"sm\": %u, \"direction\": \"%s\", \"bytes\": %u, \"pdos\": [",
					    firstSm ? "" : ",", s.sm, s.dir, s.bytes);
				firstSm = false;
				const auto groups = groupByPdo(*s.entries);
				for (std::size_t k = 0; k < groups.size(); k++) {
					std::printf("%s{\"index\": %u, \"entries\": [", k ? ", " : "", groups[k].index);
					for (std::size_t e = 0; e < groups[k].entries.size(); e++) {
						const ecmxf::PdoEntryInfo &x = *groups[k].entries[e];
						std::printf("%s{\"index\": %u, \"sub\": %u, \"bit_length\": %u, "
							    "\"bit_offset\": %u, \"name\": %s}",
							    e ? ", " : "", x.index, x.sub, x.bitLength, x.bitOffset,
							    jsonString(x.name).c_str());
					}
					std::printf("]}");
				}
				std::printf("]}");
			}
			std::printf("%s]}", firstSm ? "" : "\n  ");
			first = false;
			continue;
		}
		std::printf("%sSlave %u (%s)\n", first ? "" : "\n", p, si.name.c_str());
		first = false;
		bool any = false;
		for (const Side &s : sides) {
			if (s.entries->empty())
				continue;
			any = true;
			std::printf("  SM%u %s (%s), %u bytes\n", s.sm, s.dir, s.kind, s.bytes);
			for (const Pdo &pdo : groupByPdo(*s.entries)) {
				std::printf("    PDO 0x%04x\n", pdo.index);
				for (const ecmxf::PdoEntryInfo *x : pdo.entries) {
					std::printf("      0x%04x:%02x  %2u bit  offset %4u", x->index, x->sub, x->bitLength,
						    x->bitOffset);
					if (!x->name.empty())
						std::printf("  %s", x->name.c_str());
					else if (x->index == 0)
						std::printf("  (gap)");
					std::printf("\n");
				}
			}
		}
		if (!any)
			std::printf("  no process data\n");
	}
	if (g.json)
		std::printf("%s]\n", first ? "" : "\n");
	if (xml && !one)
		std::printf("</EtherCATInfoList>\n");
	return 0;
}

const char *const kCstructHelp =
	"Usage: ecmxf-util [global options] cstruct [-p N]\n"
	"\n"
	"The PDO mapping of each slave (or of slave N) as the C structures of\n"
	"IgH's application interface: ec_pdo_entry_info_t, ec_pdo_info_t and\n"
	"ec_sync_info_t, as IgH's 'ethercat cstruct' prints them. The same as\n"
	"'ecmxf-util pdos --cstruct' (see 'ecmxf-util pdos --help').\n"
	"\n"
	"Options:\n"
	"  -p, --position N  only the slave at bus position N\n"
	"  -h, --help        show this help\n";

const char *const kXmlHelp =
	"Usage: ecmxf-util [global options] xml [-p N]\n"
	"\n"
	"The identity and PDO mapping of slave N as an EtherCATInfo document\n"
	"(Vendor, Type, RxPdo/TxPdo and their entries), as IgH's 'ethercat xml'\n"
	"prints it; without -p one document of every slave's EtherCATInfo in an\n"
	"EtherCATInfoList. The same as 'ecmxf-util pdos --xml'.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  only the slave at bus position N\n"
	"  -h, --help        show this help\n";

namespace {

/// IgH's cstruct / xml: pdos with @p form, its own help and name.
int pdosAs(Globals &g, const Args &args, std::string_view name, const char *help, std::string_view form)
{
	for (const std::string_view a : args)
		if (a == "-h" || a == "--help") {
			std::fputs(help, stdout);
			return 0;
		}
	for (const std::string_view a : args)
		if (a.substr(0, 2) == "--" && a != "--position" && a.substr(0, 11) != "--position=")
			throw UsageError(std::string(name) + ": unknown option '" + std::string(a) + "' (try 'ecmxf-util " +
					 std::string(name) + " --help')");
	if (g.json)
		throw UsageError(std::string(name) + ": no --json form (try 'ecmxf-util pdos --json')");
	Args with = args;
	with.push_back(form);
	return cmdPdos(g, with);
}

} // namespace

int cmdCstruct(Globals &g, const Args &args)
{
	return pdosAs(g, args, "cstruct", kCstructHelp, "--cstruct");
}

int cmdXml(Globals &g, const Args &args)
{
	return pdosAs(g, args, "xml", kXmlHelp, "--xml");
}

} // namespace ecmxf_util
