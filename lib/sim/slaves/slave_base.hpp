// SPDX-License-Identifier: MIT
//
// slave_base.hpp - what every slave model shares: the ESC register model
// (station address, alias, DL status, AL control/status/code, SII EEPROM
// interface, SM watchdog, DC registers), the AL state machine of the AKD2G
// document (003_...), CoE SDO access through an object dictionary, the PDO
// configuration objects (0x1C12/0x1C13, 0x16xx/0x1Axx) with precomputed
// mapping tables for the cycle, and the emergency queue.
//
// A model derives from SlaveBase, fills the object dictionary and the PDO
// configuration in its constructor, calls finishSetup(), and implements
// step() (its physics for a time step) and, if needed, checkTransition()
// (model-specific AL checks such as DC SYNC0) and onAlChange().

#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/sim/network.hpp>

#include "slaves/object_dictionary.hpp"
#include "slaves/sii.hpp"

namespace ecmxf::sim::slaves {

class OptionReader;

/// ESC register addresses the models implement.
namespace esc {
inline constexpr std::uint16_t Type = 0x0000;
inline constexpr std::uint16_t Revision = 0x0001;
inline constexpr std::uint16_t Build = 0x0002;
inline constexpr std::uint16_t FmmusSupported = 0x0004;
inline constexpr std::uint16_t SmsSupported = 0x0005;
inline constexpr std::uint16_t RamSize = 0x0006;
inline constexpr std::uint16_t PortDescriptor = 0x0007;
inline constexpr std::uint16_t Features = 0x0008;
inline constexpr std::uint16_t StationAddress = 0x0010;
inline constexpr std::uint16_t StationAlias = 0x0012;
inline constexpr std::uint16_t DlControl = 0x0100;
inline constexpr std::uint16_t DlStatus = 0x0110;
inline constexpr std::uint16_t AlControl = 0x0120;
inline constexpr std::uint16_t AlStatus = 0x0130;
inline constexpr std::uint16_t AlStatusCode = 0x0134;
inline constexpr std::uint16_t PdiControl = 0x0140;
inline constexpr std::uint16_t EscConfig = 0x0141;
inline constexpr std::uint16_t PdiConfig = 0x0150;
inline constexpr std::uint16_t WdDivider = 0x0400;
inline constexpr std::uint16_t WdTimePdi = 0x0410;
inline constexpr std::uint16_t WdTimePd = 0x0420;
inline constexpr std::uint16_t WdStatusPd = 0x0440;
inline constexpr std::uint16_t SiiConfig = 0x0500;
inline constexpr std::uint16_t SiiControl = 0x0502;
inline constexpr std::uint16_t SiiAddress = 0x0504;
inline constexpr std::uint16_t SiiData = 0x0508;
inline constexpr std::uint16_t Fmmu0 = 0x0600;
inline constexpr std::uint16_t Sm0 = 0x0800;
inline constexpr std::uint16_t DcSystemTime = 0x0910;
inline constexpr std::uint16_t DcCyclicUnitControl = 0x0980;
inline constexpr std::uint16_t DcActivation = 0x0981;
inline constexpr std::uint16_t DcStartTime = 0x0990;
inline constexpr std::uint16_t DcSync0Cycle = 0x09A0;
inline constexpr std::uint16_t DcSync1Cycle = 0x09A4;
inline constexpr std::size_t Size = 0x1000; // registers; process RAM is not modelled
} // namespace esc

/// Static description of a model, given by its constructor.
struct BaseConfig {
	std::string typeName;
	Identity identity;
	std::uint16_t alias = 0;           ///< SII word 0x04
	bool coe = true;
	bool foe = false;
	bool bootMailbox = false;          ///< I->B allowed (else 0x0015)
	std::chrono::nanoseconds mailboxLatency{ 1'000'000 };
	bool clampOnRange = false;         ///< SDO range errors store the limit
	std::uint8_t escType = 0x11;
	std::uint16_t escFeatures = 0x000C; ///< DC supported, 64-bit DC
	// Mailbox SyncManagers (standard and bootstrap).
	std::uint16_t mbxOutStart = 0x1000, mbxOutLen = 128;
	std::uint16_t mbxInStart = 0x1080, mbxInLen = 128;
	std::uint16_t bootOutStart = 0x1000, bootOutLen = 512;
	std::uint16_t bootInStart = 0x1200, bootInLen = 512;
	// Process-data SyncManagers.
	std::uint8_t pdOutSm = 2, pdInSm = 3;
	std::uint16_t pdOutStart = 0x1100, pdInStart = 0x1400;
	// PDO limits.
	unsigned maxEntriesPerPdo = 8;
	unsigned maxPdoBytes = 32;         ///< one PDO (SDO sub-index 0 check)
	unsigned maxOutBytes = 64;         ///< all RxPDOs (P->S check, 0x0025)
	unsigned maxInBytes = 64;          ///< all TxPDOs (P->S check, 0x0024)
	// SII extras.
	std::uint16_t pdiControl = 0x0005;
	std::string siiGroup;
	std::string siiOrder;
	std::uint8_t coeDetails = 0;
	std::uint8_t ds402Channels = 0;
};

class SlaveBase : public Slave
{
public:
	~SlaveBase() override;

	// ---- Slave ----
	[[nodiscard]] const Identity &identity() const override { return cfg_.identity; }
	[[nodiscard]] std::string typeName() const override { return cfg_.typeName; }
	[[nodiscard]] std::vector<std::uint16_t> sii() const override { return eeprom_; }
	[[nodiscard]] bool hasCoE() const override { return cfg_.coe; }
	[[nodiscard]] bool hasFoE() const override { return cfg_.foe; }
	[[nodiscard]] std::chrono::nanoseconds mailboxLatency() const override
	{
		return cfg_.mailboxLatency;
	}
	[[nodiscard]] std::uint8_t escRead8(std::uint16_t reg) const override;
	void escWrite8(std::uint16_t reg, std::uint8_t value) override;
	void alControl(std::uint8_t value) override;
	[[nodiscard]] std::uint8_t alStatus() const override;
	[[nodiscard]] std::uint16_t alStatusCode() const override { return alCode_; }
	void configureDc(std::uint16_t assignActivate, std::uint32_t sync0CycleNs,
			 std::uint32_t sync1CycleNs, std::int32_t shiftNs) override;
	std::uint32_t sdoUpload(std::uint16_t index, std::uint8_t subindex, bool complete,
				std::vector<std::uint8_t> &out) override;
	std::uint32_t sdoDownload(std::uint16_t index, std::uint8_t subindex, bool complete,
				  std::span<const std::uint8_t> data) override;
	std::optional<Emergency> popEmergency() override;
	[[nodiscard]] std::vector<Pdo> rxPdos() const override;
	[[nodiscard]] std::vector<Pdo> txPdos() const override;
	[[nodiscard]] std::size_t outputBytes() const override { return outBytes_; }
	[[nodiscard]] std::size_t inputBytes() const override { return inBytes_; }
	unsigned cycle(std::span<const std::uint8_t> outputs, bool outputsValid,
		       std::span<std::uint8_t> inputs, std::chrono::nanoseconds dt,
		       bool sync0) override;
	void idle(std::chrono::nanoseconds dt) override;
	void reset() override;

	/// The SM watchdog time now in force (0x0400 divider, 0x0420 time).
	[[nodiscard]] std::chrono::nanoseconds smWatchdogTime() const { return wdTime_; }

protected:
	explicit SlaveBase(BaseConfig cfg);

	/// Build the SII image and go to the power-on state. Call at the end
	/// of the most derived constructor.
	void finishSetup();
	/// The NEXTW identity of the model: the type name (@p o's), vendor,
	/// @p product and @p revision, then the options every model takes
	/// (OptionReader::common(), name default @p defaultName).
	void identify(OptionReader &o, unsigned position, std::uint32_t product,
		      std::uint32_t revision, const std::string &defaultName);
	/// The mailbox latency option mailbox_latency_us (default @p defaultUs).
	void readMailboxLatency(OptionReader &o, std::int64_t defaultUs);

	/// Define the identity object 0x1018 (from the configured identity) and
	/// the sync manager types 0x1C00 (mailbox out/in, process data out/in).
	void addIdentityObjects();
	/// Define a PDO mapping object with its default entries (0xIIIISSBB).
	void addPdoMapping(std::uint16_t index, bool rx, const std::vector<std::uint32_t> &defaults);
	/// Define 0x1C12 (@p rx) or 0x1C13 with the default assignment. Call
	/// after every addPdoMapping() of that direction.
	void addPdoAssignment(bool rx, const std::vector<std::uint16_t> &defaults);

	/// The model's physics and logic for @p dt (every cycle() and idle()).
	/// @p outputsApplied: this step follows freshly applied outputs.
	virtual void step(std::chrono::nanoseconds dt, bool outputsApplied) = 0;
	/// Model-specific checks of an upward transition (P->S, S->O; e.g. DC).
	/// Returns 0 or an AL status code. Also asked with (SafeOp, Op) while in
	/// OP when the DC configuration changes.
	virtual std::uint16_t checkTransition(AlState from, AlState to);
	/// The AL state changed (@p error: because of an error, e.g. watchdog).
	virtual void onAlChange(AlState from, AlState to, bool error);
	/// Power-on of the model after the dictionary was reset (and stored
	/// parameters applied).
	virtual void onPowerOn();
	/// The alias register value at power-on; @p eepromAlias is SII word 4
	/// (0 if the EEPROM checksum is wrong).
	virtual std::uint16_t powerOnAlias(std::uint16_t eepromAlias) { return eepromAlias; }

	[[nodiscard]] AlState alState() const { return state_; }
	[[nodiscard]] bool sync0Active() const;
	[[nodiscard]] std::uint32_t sync0CycleNs() const;
	void pushEmergency(const Emergency &e);
	/// "save": remember the storable parameters (survive reset()).
	void saveParameters();
	/// "load": @p immediate: storable parameters back to defaults now;
	/// always: forget the saved ones.
	void restoreDefaults(bool immediate);
	/// Rebuild the mapping tables (after the dictionary changed).
	void rebuildMapping();

	BaseConfig cfg_;
	ObjectDictionary od_;

private:
	struct PdoMap {
		std::uint16_t index = 0;
		bool rx = true;
		std::uint8_t count = 0;
		std::vector<std::uint32_t> entries;
	};
	struct PdoAssign {
		std::uint8_t count = 0;
		std::vector<std::uint16_t> pdos;
	};
	struct Slot {
		Binding bind;          // ptr null: padding
		std::uint32_t bitOffset = 0;
		std::uint32_t bits = 0;
		std::uint32_t bytes = 0; // direct: copy this many bytes as they are
		bool direct = false;     // byte-aligned, whole value, little-endian host
	};

	std::uint32_t checkMapEntry(bool rx, std::uint32_t value) const;
	std::uint32_t checkMapCount(const PdoMap &m, std::uint64_t count) const;
	std::uint32_t checkAssignCount(bool rx, std::uint64_t count) const;
	[[nodiscard]] const PdoMap *findMap(std::uint16_t index) const;
	[[nodiscard]] std::vector<Pdo> pdos(bool rx) const;
	std::uint16_t checkMailboxSm(bool boot) const;
	std::uint16_t checkProcessDataSm() const;
	std::uint16_t checkMappingLimits() const;
	void publishAl();
	void enterState(AlState to);
	void alError(AlState to, std::uint16_t code);
	void advanceTime(std::chrono::nanoseconds dt, bool outputsValid);
	void updateWatchdogTime();
	void siiCommand(std::uint8_t cmd);
	[[nodiscard]] std::uint16_t reg16(std::uint16_t at) const;
	[[nodiscard]] std::uint32_t reg32(std::uint16_t at) const;
	void setReg16(std::uint16_t at, std::uint16_t v);

	// Hot: touched by every cycle().
	AlState state_ = AlState::Init;
	bool alErr_ = false;
	bool pendingOp_ = false;
	bool outputsSeen_ = false;
	bool wdExpired_ = false;
	std::uint16_t alCode_ = 0;
	std::uint64_t localTimeNs_ = 0;
	std::chrono::nanoseconds pendingFor_{};
	std::chrono::nanoseconds sinceOutputs_{};
	std::chrono::nanoseconds wdTime_{};
	std::size_t outBytes_ = 0, inBytes_ = 0;
	std::vector<Slot> rxSlots_, txSlots_;
	std::uint32_t rxBits_ = 0, txBits_ = 0;
	bool rxMapValid_ = true, txMapValid_ = true;
	std::int32_t dcShiftNs_ = 0;

	// Cold.
	std::unique_ptr<std::uint8_t[]> reg_;   // ESC registers 0x0000..0x0FFF
	std::vector<std::uint16_t> eeprom_;     // non-volatile
	std::map<std::uint32_t, std::uint64_t> stored_; // non-volatile ("save")
	std::deque<PdoMap> maps_;
	PdoAssign rxAssign_, txAssign_;
	std::deque<Emergency> emcy_;
};

} // namespace ecmxf::sim::slaves
