// SPDX-License-Identifier: MIT
//
// sii.hpp - builds a slave's SII EEPROM image (ETG.2010): the 64-word
// header (ESC configuration with its CRC-8 checksum, identity, mailbox
// configuration, protocols) and the categories strings (10), general (30),
// FMMU (40), SyncManager (41), TxPDO (50) and RxPDO (51).

#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <ecmxf/sim/network.hpp>

namespace ecmxf::sim::slaves {

/// SII word addresses of the header (ETG.2010 table 2).
namespace siiword {
inline constexpr unsigned PdiControl = 0x00;
inline constexpr unsigned PdiConfig = 0x01;
inline constexpr unsigned SyncImpulseLen = 0x02;
inline constexpr unsigned PdiConfig2 = 0x03;
inline constexpr unsigned StationAlias = 0x04;
inline constexpr unsigned Checksum = 0x07;
inline constexpr unsigned VendorId = 0x08;
inline constexpr unsigned ProductCode = 0x0A;
inline constexpr unsigned Revision = 0x0C;
inline constexpr unsigned Serial = 0x0E;
inline constexpr unsigned BootRxMbxOffset = 0x14;
inline constexpr unsigned BootRxMbxSize = 0x15;
inline constexpr unsigned BootTxMbxOffset = 0x16;
inline constexpr unsigned BootTxMbxSize = 0x17;
inline constexpr unsigned StdRxMbxOffset = 0x18;
inline constexpr unsigned StdRxMbxSize = 0x19;
inline constexpr unsigned StdTxMbxOffset = 0x1A;
inline constexpr unsigned StdTxMbxSize = 0x1B;
inline constexpr unsigned MailboxProtocol = 0x1C;
inline constexpr unsigned Size = 0x3E;
inline constexpr unsigned Version = 0x3F;
inline constexpr unsigned FirstCategory = 0x40;
} // namespace siiword

/// Mailbox protocol bits of SII word 0x1C.
namespace mbxproto {
inline constexpr std::uint16_t AoE = 0x0001;
inline constexpr std::uint16_t EoE = 0x0002;
inline constexpr std::uint16_t CoE = 0x0004;
inline constexpr std::uint16_t FoE = 0x0008;
} // namespace mbxproto

/// One SyncManager as the SII SyncM category describes it.
struct SiiSyncManager {
	std::uint16_t start = 0;
	std::uint16_t length = 0;
	std::uint8_t control = 0;
	bool enable = false;
	std::uint8_t type = 0; ///< 1 mbx out, 2 mbx in, 3 outputs, 4 inputs
};

/// One PDO entry for the SII PDO categories.
struct SiiPdoEntry {
	std::uint16_t index = 0;
	std::uint8_t subindex = 0;
	std::uint8_t dataType = 0;
	std::uint8_t bits = 0;
};

struct SiiPdo {
	std::uint16_t index = 0;
	std::uint8_t sm = 0;
	std::vector<SiiPdoEntry> entries;
};

/// Everything the image is built from.
struct SiiDescription {
	std::uint16_t pdiControl = 0x0005; ///< PDI type (low byte) + ESC config (high)
	std::uint16_t pdiConfig = 0;
	std::uint16_t syncImpulseLen = 1000; ///< 10 ns units
	std::uint16_t alias = 0;
	Identity identity;
	std::string group;  ///< e.g. "Drive", "DigIO"
	std::string order;  ///< order number, e.g. "EST-584"
	std::uint16_t bootRxOffset = 0, bootRxSize = 0, bootTxOffset = 0, bootTxSize = 0;
	std::uint16_t stdRxOffset = 0, stdRxSize = 0, stdTxOffset = 0, stdTxSize = 0;
	std::uint16_t protocols = 0;
	std::uint8_t coeDetails = 0; ///< general category byte 5
	std::uint8_t foeDetails = 0; ///< general category byte 6
	std::uint8_t ds402Channels = 0;
	std::vector<std::uint8_t> fmmus; ///< 1 outputs, 2 inputs, 3 mailbox state
	std::vector<SiiSyncManager> syncManagers;
	std::vector<SiiPdo> txPdos, rxPdos;
	unsigned sizeWords = 1024; ///< EEPROM size (2 KiB = 16 kbit)
};

/// CRC-8 of the ESC configuration area (SII words 0..6): polynomial 0x07,
/// initial value 0xFF, no reflection (ETG.2010).
[[nodiscard]] std::uint8_t siiChecksum(const std::uint16_t *words7);

/// Build the image. Unused words are 0xFFFF (erased EEPROM).
[[nodiscard]] std::vector<std::uint16_t> buildSii(const SiiDescription &d);

} // namespace ecmxf::sim::slaves
