// SPDX-License-Identifier: MIT
//
// sii.cpp - SII EEPROM image builder (ETG.2010).

#include "slaves/sii.hpp"

#include <stdexcept>

namespace ecmxf::sim::slaves {

std::uint8_t siiChecksum(const std::uint16_t *words7)
{
	std::uint8_t crc = 0xFF;
	for (unsigned i = 0; i < 14; i++) {
		const auto byte = static_cast<std::uint8_t>(words7[i / 2] >> (8 * (i % 2)));
		crc ^= byte;
		for (int b = 0; b < 8; b++)
			crc = static_cast<std::uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x07 : crc << 1);
	}
	return crc;
}

namespace {

class Bytes
{
public:
	void u8(unsigned v) { b_.push_back(static_cast<std::uint8_t>(v)); }
	void u16(unsigned v)
	{
		u8(v & 0xFF);
		u8((v >> 8) & 0xFF);
	}
	void pad()
	{
		if (b_.size() % 2)
			b_.push_back(0);
	}
	[[nodiscard]] const std::vector<std::uint8_t> &data() const { return b_; }

private:
	std::vector<std::uint8_t> b_;
};

void category(std::vector<std::uint16_t> &w, std::uint16_t type, Bytes data)
{
	data.pad();
	const auto &b = data.data();
	w.push_back(type);
	w.push_back(static_cast<std::uint16_t>(b.size() / 2));
	for (std::size_t i = 0; i < b.size(); i += 2)
		w.push_back(static_cast<std::uint16_t>(b[i] | b[i + 1] << 8));
}

void put32(std::vector<std::uint16_t> &w, unsigned at, std::uint32_t v)
{
	w[at] = static_cast<std::uint16_t>(v & 0xFFFF);
	w[at + 1] = static_cast<std::uint16_t>(v >> 16);
}

} // namespace

std::vector<std::uint16_t> buildSii(const SiiDescription &d)
{
	std::vector<std::uint16_t> w(siiword::FirstCategory, 0);
	w[siiword::PdiControl] = d.pdiControl;
	w[siiword::PdiConfig] = d.pdiConfig;
	w[siiword::SyncImpulseLen] = d.syncImpulseLen;
	w[siiword::StationAlias] = d.alias;
	w[siiword::Checksum] = siiChecksum(w.data());
	put32(w, siiword::VendorId, d.identity.vendorId);
	put32(w, siiword::ProductCode, d.identity.productCode);
	put32(w, siiword::Revision, d.identity.revision);
	put32(w, siiword::Serial, d.identity.serial);
	w[siiword::BootRxMbxOffset] = d.bootRxOffset;
	w[siiword::BootRxMbxSize] = d.bootRxSize;
	w[siiword::BootTxMbxOffset] = d.bootTxOffset;
	w[siiword::BootTxMbxSize] = d.bootTxSize;
	w[siiword::StdRxMbxOffset] = d.stdRxOffset;
	w[siiword::StdRxMbxSize] = d.stdRxSize;
	w[siiword::StdTxMbxOffset] = d.stdTxOffset;
	w[siiword::StdTxMbxSize] = d.stdTxSize;
	w[siiword::MailboxProtocol] = d.protocols;
	w[siiword::Size] = static_cast<std::uint16_t>(d.sizeWords * 16 / 1024 - 1); // kbit - 1
	w[siiword::Version] = 1;

	// Strings: 1 group, 2 order, 3 name.
	const std::vector<std::string> strings{ d.group, d.order, d.identity.name };
	Bytes s;
	s.u8(static_cast<unsigned>(strings.size()));
	for (const auto &str : strings) {
		const std::size_t n = str.size() > 255 ? 255 : str.size();
		s.u8(static_cast<unsigned>(n));
		for (std::size_t i = 0; i < n; i++)
			s.u8(static_cast<unsigned char>(str[i]));
	}
	category(w, 10, s);

	Bytes g;
	g.u8(1); // group
	g.u8(0); // image
	g.u8(2); // order
	g.u8(3); // name
	g.u8(0);
	g.u8(d.coeDetails);
	g.u8(d.foeDetails);
	g.u8(0); // EoE
	g.u8(0); // SoE channels
	g.u8(d.ds402Channels);
	g.u8(0); // sysman class
	g.u8(0); // flags
	g.u16(0); // current on E-bus
	g.u8(1); // group (again)
	g.u8(0);
	g.u16(0x0011); // physical ports: 0 and 1 MII
	g.u16(0);
	for (int i = 0; i < 12; i++)
		g.u8(0);
	category(w, 30, g);

	if (!d.fmmus.empty()) {
		Bytes f;
		for (auto t : d.fmmus)
			f.u8(t);
		category(w, 40, f);
	}
	if (!d.syncManagers.empty()) {
		Bytes sm;
		for (const auto &m : d.syncManagers) {
			sm.u16(m.start);
			sm.u16(m.length);
			sm.u8(m.control);
			sm.u8(0);
			sm.u8(m.enable ? 1 : 0);
			sm.u8(m.type);
		}
		category(w, 41, sm);
	}
	auto pdos = [&](std::uint16_t type, const std::vector<SiiPdo> &list) {
		if (list.empty())
			return;
		Bytes p;
		for (const auto &pdo : list) {
			p.u16(pdo.index);
			p.u8(static_cast<unsigned>(pdo.entries.size()));
			p.u8(pdo.sm);
			p.u8(0); // synchronization
			p.u8(0); // name
			p.u16(0); // flags
			for (const auto &e : pdo.entries) {
				p.u16(e.index);
				p.u8(e.subindex);
				p.u8(0);
				p.u8(e.dataType);
				p.u8(e.bits);
				p.u16(0);
			}
		}
		category(w, type, p);
	};
	pdos(50, d.txPdos);
	pdos(51, d.rxPdos);
	w.push_back(0xFFFF); // end of categories

	if (w.size() > d.sizeWords)
		throw std::logic_error("SII image larger than the EEPROM");
	w.resize(d.sizeWords, 0xFFFF);
	return w;
}

} // namespace ecmxf::sim::slaves
