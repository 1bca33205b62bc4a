// SPDX-License-Identifier: MIT
//
// periph_mdio.cpp - the MDIO bus and the ECM-XF's Ethernet PHY at address 1
// (IEEE 802.3 clause 22 registers of a 10/100 PHY, link up at 100 Mbit/s
// full duplex).

#include "periph_blocks.hpp"

namespace ecmxf::sim::periph {

namespace {

enum : unsigned { kBmcr = 0, kBmsr = 1, kPhyId1 = 2, kPhyId2 = 3, kAnar = 4, kAnlpar = 5, kAner = 6 };
constexpr std::uint16_t kBmcrReset = 0x8000;

} // namespace

Mdio::Phy Mdio::defaults()
{
	Phy p;
	p.present = true;
	p.regs[kBmcr] = 0x3100;   // 100 Mbit/s, autonegotiation on, full duplex
	p.regs[kBmsr] = 0x786D;   // 10/100 HD/FD, AN complete, link up, ext. caps
	p.regs[kPhyId1] = 0x0243; // OUI of IC Plus (IP101G, as on M480 boards)
	p.regs[kPhyId2] = 0x0C54;
	p.regs[kAnar] = 0x01E1;   // 10/100 HD/FD, IEEE 802.3
	p.regs[kAnlpar] = 0xC5E1; // partner: the same, ACK, next page
	p.regs[kAner] = 0x0003;   // partner AN able, page received
	return p;
}

Mdio::Mdio() { phys_[kChipPhy] = defaults(); }

std::uint16_t Mdio::read(unsigned phy, unsigned reg) const
{
	const Phy &p = phys_[phy];
	return p.present ? p.regs[reg] : kAbsent;
}

void Mdio::write(unsigned phy, unsigned reg, std::uint16_t value)
{
	Phy &p = phys_[phy];
	if (!p.present || reg == kBmsr || reg == kPhyId1 || reg == kPhyId2)
		return;
	if (reg == kBmcr && (value & kBmcrReset) != 0) {
		p = defaults();
		return;
	}
	p.regs[reg] = value;
}

void Mdio::poke(unsigned phy, unsigned reg, std::uint16_t value)
{
	Phy &p = phys_[phy];
	p.present = true;
	p.regs[reg] = value;
}

} // namespace ecmxf::sim::periph
