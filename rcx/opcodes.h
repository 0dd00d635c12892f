// The RCX opcode set, declared once.
//
// Every opcode of the firmware reference (seeds/000) is one row of `kOpcodes`:
// its name, mnemonic, opcode byte, whether it runs in programs (command), is
// sent by a host (request) or both, its operand layout with the sources each
// operand allows, and the layout of its reply. The emulator's decoder, the
// backend's encoder and disassembler, and the IR link protocol all read this
// table; nothing else in the project may restate opcode numbers or layouts.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace rcx {

// How one operand is stored. Multi-byte fields are little-endian unless the
// name says BE (the seed gives big-endian for the memory map and versions).
enum class FieldType : std::uint8_t { Byte, UByte, Short, UShort, ShortBE, UShortBE };

// What an operand means, so generic code (disassembly, decoding, encoding)
// can pair sources with their arguments and find branch offsets.
enum class Role : std::uint8_t {
  Value,      // a plain number: an index, a code, a key byte
  Variable,   // a variable index 0..31
  Source,     // a source type (see Source)
  OpSource,   // test-and-branch: bits 0-3 source, bits 6-7 comparison
  Argument,   // the argument of the source operand named by `pairs_with`
  Offset,     // branch offset (formula depends on the opcode)
  Extension,  // far-branch extension byte
  Length,     // length of the following Data operand
  Data,       // `Length` bytes
  Checksum,   // sum of the Data bytes modulo 256
};

// The 16 source types of the seed; 5..7 are Cybermaster-only.
enum class Source : std::uint8_t {
  Variable = 0, Timer = 1, Immediate = 2, MotorState = 3, Random = 4,
  Reserved5 = 5, Reserved6 = 6, Reserved7 = 7, Program = 8, SensorValue = 9,
  SensorType = 10, SensorMode = 11, SensorRaw = 12, SensorBool = 13,
  Clock = 14, Message = 15,
};

// A set of sources as a bit mask (bit n = source n).
using SourceSet = std::uint16_t;
constexpr SourceSet sources(std::initializer_list<int> list) {
  SourceSet s = 0;
  for (int v : list) s = static_cast<SourceSet>(s | (1u << v));
  return s;
}
// Every source type; an opcode's operand narrows this as the reference says.
// The CyberMaster ones (5-7) are allowed wherever the reference allows them
// (nqc emits them for -Trcx) and read 0 on the RCX (docs/emulator.md).
inline constexpr SourceSet kAllSources = 0xFFFF;
constexpr bool allows(SourceSet set, int source) {
  return source >= 0 && source < 16 && ((set >> source) & 1u) != 0;
}

struct Operand {
  std::string_view name;
  FieldType type;
  Role role = Role::Value;
  SourceSet allowed = 0;    // Source / OpSource: the sources the seed allows
  std::uint8_t count = 1;   // repeated fields (keys, memory map)
  std::int8_t pairs_with = -1;  // Argument: index of its Source/OpSource operand
};

enum class Kind : std::uint8_t { Command = 1, Request = 2, Both = 3 };

// Comparison codes of test-and-branch (bits 6-7 of opsrc1).
enum class Compare : std::uint8_t { LessEqual = 0, GreaterEqual = 1, NotEqual = 2, Equal = 3 };

enum class Op : std::uint8_t {
  AbsoluteValue, Alive, AddToVariable, AndVariable, BranchAlwaysFar, BranchAlwaysNear,
  CallSubroutine, ClearMessage, ClearSensorValue, ClearTimer, DecrementLoopCounterNear,
  DeleteAllSubroutines, DeleteAllTasks, DatalogNext, DecrementLoopCounterFar,
  DeleteFirmware, DeleteSubroutine, DeleteTask, DivideVariable, GetMemoryMap,
  GetBatteryPower, GetValue, GetVersions, MultiplyVariable, OrVariable, PowerOff,
  ReturnFromSubroutine, PlaySound, PlayTone, SendMessage, SetDatalogSize, SetDisplay,
  SetLoopCounter, SetMotorOnOff, SetMessage, SetMotorDirection, SetMotorPower,
  SetPowerDownDelay, SetProgramNumber, SetSensorMode, SetSensorType, SetTime,
  SetTransmitterRange, SetVariable, SignVariable, StartFirmwareDownload,
  StartTaskDownload, StopAllTasks, StartSubroutineDownload, StartTask, StopTask,
  SubtractFromVariable, TestAndBranchFar, TransferData, TestAndBranchNear,
  UnlockFirmware, UploadDatalog, Wait,
  Count_
};
inline constexpr std::size_t kOpcodeCount = static_cast<std::size_t>(Op::Count_);

struct OpcodeInfo {
  Op op;
  std::string_view name;      // as the seed names it
  std::string_view mnemonic;  // short form used in listings and asm
  std::uint8_t code;          // the program / first request form
  Kind kind;
  bool toggles;               // has a second request form, code ^ 0x08
  bool replies;               // a request answered with reply code ~request
  std::span<const Operand> operands;
  std::span<const Operand> reply;  // reply payload after the reply opcode
  // What `nqc -L` calls the instruction, or the request an asm block put in
  // a program (empty: nqc lists the byte as `?`); `rcxc nqc -L` prints
  // nqc's layout with it.
  std::string_view nqc_mnemonic;

  constexpr bool is_command() const { return (static_cast<int>(kind) & 1) != 0; }
  constexpr bool is_request() const { return (static_cast<int>(kind) & 2) != 0; }
};

// The table, one row per Op, in Op order.
std::span<const OpcodeInfo> opcodes();
const OpcodeInfo& info(Op op);

// Lookups by byte. `command_at` decodes program bytecode (the program form
// only); `request_at` decodes host requests (either toggle form).
const OpcodeInfo* command_at(std::uint8_t code);
const OpcodeInfo* request_at(std::uint8_t code);
const OpcodeInfo* by_mnemonic(std::string_view mnemonic);

constexpr std::uint8_t reply_code(std::uint8_t request) { return static_cast<std::uint8_t>(~request); }
constexpr std::uint8_t alternate_form(std::uint8_t request) { return request ^ 0x08; }

// Byte size of one field, and of an operand list when every field is fixed
// size (std::nullopt when a Data operand makes the size depend on contents).
constexpr int field_size(FieldType t) {
  return (t == FieldType::Byte || t == FieldType::UByte) ? 1 : 2;
}
std::optional<int> fixed_size(std::span<const Operand> operands);
// Size in bytes of a whole command (opcode + operands), or nullopt if variable.
std::optional<int> command_size(const OpcodeInfo& op);

// Read/write a field at `p` (bounds are the caller's business).
int read_field(FieldType t, const std::uint8_t* p);
void write_field(FieldType t, int value, std::uint8_t* p);

std::string_view source_name(int source);

// The arguments the seed's table of sources gives source `source`: variable
// 0..31, timer 0..3, motor 0..2, sensor value, type, mode, raw and boolean
// 0..2, clock and message 0. nullopt where any value goes (an immediate, a
// random maximum) or the argument is ignored (program, CyberMaster ones).
struct ArgumentRange {
  int lo = 0, hi = 0;
  std::string_view noun;  // "timer", "sensor", ... ("" where only one value goes)
};
std::optional<ArgumentRange> source_argument_range(int source);

}  // namespace rcx
