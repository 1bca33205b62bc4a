// SPDX-License-Identifier: MIT
//
// sim_network.hpp - the contract between the simulated chip (the EtherCAT master
// inside the ECM-XF) and the slave models on its bus.
//
// The chip model talks to slaves only through this interface: it reads
// their SII EEPROM and ESC registers, writes AL control, moves mailbox
// (CoE SDO, FoE, emergency) traffic, exchanges process data once per bus
// cycle and collects working-counter contributions. Slave models know
// nothing about SPI packets.

#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/export.hpp>

namespace ecmxf::sim {

/// AL states as AL control/status (0x0120/0x0130) encode them.
enum class AlState : std::uint8_t {
	Init = 0x01,
	PreOp = 0x02,
	Boot = 0x03,
	SafeOp = 0x04,
	Op = 0x08,
};

/// AL status codes the slaves produce (AKD2G document, 003_...).
namespace alcode {
inline constexpr std::uint16_t NoError = 0x0000;
inline constexpr std::uint16_t InvalidStateChange = 0x0011;
inline constexpr std::uint16_t UnknownState = 0x0012;
inline constexpr std::uint16_t InvalidMbxBootConfig = 0x0015;
inline constexpr std::uint16_t InvalidMbxConfig = 0x0016;
inline constexpr std::uint16_t MultipleSyncErrors = 0x001A;
inline constexpr std::uint16_t SmWatchdog = 0x001B;
inline constexpr std::uint16_t InvalidOutputConfig = 0x001D;
inline constexpr std::uint16_t InvalidInputConfig = 0x001E;
inline constexpr std::uint16_t InvalidInputMapping = 0x0024;
inline constexpr std::uint16_t InvalidOutputMapping = 0x0025;
inline constexpr std::uint16_t FatalSyncError = 0x002C;
inline constexpr std::uint16_t NoFatalSyncError = 0x002D;
inline constexpr std::uint16_t NoSyncError = 0x002E;
inline constexpr std::uint16_t InvalidDcSync = 0x0030;
inline constexpr std::uint16_t DcPllSyncError = 0x0032;
inline constexpr std::uint16_t TooManyMissedSm2 = 0x0034;
} // namespace alcode

/// CoE SDO abort codes (ETG.1000.6; the table in the ver. 050 manual).
namespace abort {
inline constexpr std::uint32_t Toggle = 0x05030000;
inline constexpr std::uint32_t Timeout = 0x05040000;
inline constexpr std::uint32_t UnknownCommand = 0x05040001;
inline constexpr std::uint32_t OutOfMemory = 0x05040005;
inline constexpr std::uint32_t UnsupportedAccess = 0x06010000;
inline constexpr std::uint32_t WriteOnly = 0x06010001;
inline constexpr std::uint32_t ReadOnly = 0x06010002;
inline constexpr std::uint32_t SubindexCannotBeWritten = 0x06010003;
inline constexpr std::uint32_t CompleteAccessUnsupported = 0x06010004;
inline constexpr std::uint32_t NoObject = 0x06020000;
inline constexpr std::uint32_t NotMappable = 0x06040041;
inline constexpr std::uint32_t PdoLengthExceeded = 0x06040042;
inline constexpr std::uint32_t ParamIncompatible = 0x06040043;
inline constexpr std::uint32_t HardwareError = 0x06060000;
inline constexpr std::uint32_t LengthMismatch = 0x06070010;
inline constexpr std::uint32_t LengthTooHigh = 0x06070012;
inline constexpr std::uint32_t LengthTooLow = 0x06070013;
inline constexpr std::uint32_t NoSubindex = 0x06090011;
inline constexpr std::uint32_t ValueRange = 0x06090030;
inline constexpr std::uint32_t ValueTooHigh = 0x06090031;
inline constexpr std::uint32_t ValueTooLow = 0x06090032;
inline constexpr std::uint32_t GeneralError = 0x08000000;
inline constexpr std::uint32_t CannotTransfer = 0x08000020;
inline constexpr std::uint32_t CannotTransferLocal = 0x08000021;
inline constexpr std::uint32_t CannotTransferState = 0x08000022;
inline constexpr std::uint32_t NoObjectDictionary = 0x08000023;
} // namespace abort

/// Identity of a slave (SII words 0x08..0x0F and object 0x1018).
struct Identity {
	std::uint32_t vendorId = 0;
	std::uint32_t productCode = 0;
	std::uint32_t revision = 0;
	std::uint32_t serial = 0;
	std::string name;	///< device name (SII string, object 0x1008)
};

/// One entry of a PDO mapping (0x16xx/0x1Axx sub-index value).
struct PdoEntry {
	std::uint16_t index = 0;
	std::uint8_t subindex = 0;
	std::uint8_t bits = 0;
};

/// A PDO and its entries.
struct Pdo {
	std::uint16_t index = 0;
	std::vector<PdoEntry> entries;
};

/// A CoE emergency message.
struct Emergency {
	std::uint16_t errorCode = 0;
	std::uint8_t errorRegister = 0;
	std::uint8_t data[5] = {};
};

/// One simulated EtherCAT slave.
class ECMXF_EXPORT Slave
{
public:
	virtual ~Slave() = default;

	// ---- identity, EEPROM ----
	[[nodiscard]] virtual const Identity &identity() const = 0;
	/// Type name as used in network files ("EST-584", "servo", "dio").
	[[nodiscard]] virtual std::string typeName() const = 0;
	/// SII EEPROM contents, 16-bit words (at least the 64-word header).
	[[nodiscard]] virtual std::vector<std::uint16_t> sii() const = 0;
	/// Does the slave have a CoE mailbox (SDO, emergency)? FoE?
	[[nodiscard]] virtual bool hasCoE() const = 0;
	[[nodiscard]] virtual bool hasFoE() const { return false; }
	/// DC AssignActivate the slave needs for OP (0 = none: free run OK).
	[[nodiscard]] virtual std::uint16_t dcAssignActivate() const { return 0; }
	/// Mailbox turnaround: how long one SDO transfer takes on this slave.
	[[nodiscard]] virtual std::chrono::nanoseconds mailboxLatency() const = 0;

	// ---- ESC registers (RAW_ECAT_FUNC, station address, DL status) ----
	[[nodiscard]] virtual std::uint8_t escRead8(std::uint16_t reg) const = 0;
	virtual void escWrite8(std::uint16_t reg, std::uint8_t value) = 0;

	// ---- AL state machine (AKD2G rules) ----
	/// Write AL control (0x0120): requested state in bits 3..0, bit 4
	/// acknowledges an error.
	virtual void alControl(std::uint8_t value) = 0;
	/// AL status (0x0130): state in bits 3..0, bit 4 error indication.
	[[nodiscard]] virtual std::uint8_t alStatus() const = 0;
	/// AL status code (0x0134).
	[[nodiscard]] virtual std::uint16_t alStatusCode() const = 0;
	[[nodiscard]] AlState state() const
	{
		return static_cast<AlState>(alStatus() & 0x0F);
	}

	/// DC configuration written by the master (SYNC0 on/off, cycle).
	virtual void configureDc(std::uint16_t assignActivate, std::uint32_t sync0CycleNs,
				 std::uint32_t sync1CycleNs, std::int32_t shiftNs) = 0;

	// ---- CoE ----
	/// SDO upload. @p complete selects complete access (whole object from
	/// @p subindex on). Returns 0 or an abort code.
	virtual std::uint32_t sdoUpload(std::uint16_t index, std::uint8_t subindex,
					bool complete, std::vector<std::uint8_t> &out) = 0;
	/// SDO download. Returns 0 or an abort code.
	virtual std::uint32_t sdoDownload(std::uint16_t index, std::uint8_t subindex,
					  bool complete, std::span<const std::uint8_t> data) = 0;
	/// Pending emergency, oldest first.
	virtual std::optional<Emergency> popEmergency() = 0;

	// ---- FoE ----
	virtual std::uint32_t foeRead(const std::string &, std::vector<std::uint8_t> &)
	{
		return 0x08000000; // FoE not supported
	}
	virtual std::uint32_t foeWrite(const std::string &, std::span<const std::uint8_t>)
	{
		return 0x08000000;
	}

	// ---- process data ----
	/// Current PDO assignment and mapping (0x1C12/0x1C13, 0x16xx/0x1Axx).
	[[nodiscard]] virtual std::vector<Pdo> rxPdos() const = 0;
	[[nodiscard]] virtual std::vector<Pdo> txPdos() const = 0;
	/// Process data sizes in bytes derived from the mapping.
	[[nodiscard]] virtual std::size_t outputBytes() const = 0;
	[[nodiscard]] virtual std::size_t inputBytes() const = 0;

	/// One bus cycle. @p outputs are this slave's RxPDO bytes (valid only
	/// when @p outputsValid: the master had a frame for this cycle);
	/// @p inputs receives its TxPDO bytes. @p dt is the cycle time; @p sync0
	/// tells whether a SYNC0 event occurred. Returns the working-counter
	/// contribution: +1 when inputs were read, +2 when outputs were
	/// written (AL state permitting).
	virtual unsigned cycle(std::span<const std::uint8_t> outputs, bool outputsValid,
			       std::span<std::uint8_t> inputs, std::chrono::nanoseconds dt,
			       bool sync0) = 0;

	/// Time passes without a bus cycle (no frames on the wire).
	virtual void idle(std::chrono::nanoseconds dt) = 0;

	/// Power-on state (WARM_RESET of the chip does not reset slaves; a
	/// network reset in tests does).
	virtual void reset() = 0;
};

/// A bus of slaves in position order, built from a network description.
class ECMXF_EXPORT Network
{
public:
	Network();
	~Network();
	Network(Network &&) noexcept;
	Network &operator=(Network &&) noexcept;

	/// Parse a network file (Documentation/simulator.rst). Throws
	/// std::runtime_error naming the file, line and what was wrong.
	/// A bare name (no '/') that is no file in the working directory is
	/// looked for, as given and with ".net" added, in each directory of
	/// $ECMXF_NETWORK_PATH (':'-separated), then among the installed
	/// networks: <the program's directory>/../share/ecmxf/networks, then
	/// the networks directory of the prefix the library was built for.
	static Network fromFile(const std::string &path);
	/// The file fromFile() reads for @p path (the lookup above); throws
	/// std::runtime_error naming the directories looked in when there is
	/// none.
	static std::string findFile(const std::string &path);
	static Network fromText(const std::string &text, const std::string &origin = "<text>");
	/// The default network: 2 x EST-584 + 1 x digital I/O.
	static Network defaultNetwork();

	/// Create one slave model by type name ("EST-584", "servo", "dio")
	/// with the key=value options of a network file's "slave" line.
	/// Throws std::invalid_argument for an unknown type or option.
	static std::unique_ptr<Slave> makeSlave(const std::string &type, unsigned position,
						const std::map<std::string, std::string> &options = {});

	/// The network's name ("name" line of the file, or the file name).
	[[nodiscard]] const std::string &name() const;
	void setName(std::string name);

	[[nodiscard]] std::size_t size() const;
	Slave &at(std::size_t position);
	[[nodiscard]] const Slave &at(std::size_t position) const;
	void add(std::unique_ptr<Slave> slave);

	/// Chip options (the file's `chip KEY=VALUE` lines; see
	/// sim::kChipOptions in <ecmxf/sim/chip.hpp>), applied by the Chip
	/// built on this network over the ChipConfig it is given. Sets @p key
	/// to @p value, replacing an earlier value of the key. Throws
	/// std::invalid_argument for an unknown key or a bad value.
	void setChipOption(const std::string &key, const std::string &value);
	/// The chip options in the order they were first set.
	[[nodiscard]] const std::vector<std::pair<std::string, std::string>> &chipOptions() const noexcept
	{
		return chipOptions_;
	}

private:
	/// fromText() without the escaping of its messages.
	static Network parseText(const std::string &text, const std::string &origin);

	std::string name_;
	std::vector<std::unique_ptr<Slave>> slaves_;
	std::vector<std::pair<std::string, std::string>> chipOptions_;
};

} // namespace ecmxf::sim
