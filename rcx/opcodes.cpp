#include "rcx/opcodes.h"

#include <algorithm>

namespace rcx {
namespace {

using enum FieldType;
using R = Role;

constexpr SourceSet kVarImm = sources({0, 2});
constexpr SourceSet kVarImmRandom = sources({0, 2, 4});
constexpr SourceSet kDatalogSources = sources({0, 1, 9, 14});
constexpr SourceSet kTest1 = kAllSources & ~sources({4, 8});
constexpr SourceSet kTest2 = kAllSources & ~sources({2, 4, 8});
constexpr SourceSet kGetValueSources = kAllSources & ~sources({2, 4});

// "index, source, argument" arithmetic on a variable.
constexpr Operand kVarSrcArg[] = {
    {"index", UByte, R::Variable}, {"source", UByte, R::Source, kVarImm}, {"argument", Short, R::Argument, 0, 1, 1}};
// Set variable takes every source (seed: "All sources are allowed").
constexpr Operand kSetVar[] = {
    {"index", UByte, R::Variable}, {"source", UByte, R::Source, kAllSources}, {"argument", Short, R::Argument, 0, 1, 1}};
constexpr Operand kTestNear[] = {
    {"opsrc1", UByte, R::OpSource, kTest1}, {"src2", UByte, R::Source, kTest2},
    {"arg1", Short, R::Argument, 0, 1, 0},  {"arg2", Byte, R::Argument, 0, 1, 1},
    {"offset", Byte, R::Offset}};
constexpr Operand kTestFar[] = {
    {"opsrc1", UByte, R::OpSource, kTest1}, {"src2", UByte, R::Source, kTest2},
    {"arg1", Short, R::Argument, 0, 1, 0},  {"arg2", Byte, R::Argument, 0, 1, 1},
    {"offset", Short, R::Offset}};
constexpr Operand kBranchNear[] = {{"offset", UByte, R::Offset}};
constexpr Operand kBranchFar[] = {{"offset", UByte, R::Offset}, {"extension", UByte, R::Extension}};
constexpr Operand kLoopNear[] = {{"offset", UByte, R::Offset}};
constexpr Operand kLoopFar[] = {{"offset", UShort, R::Offset}};
constexpr Operand kSetLoop[] = {{"source", UByte, R::Source, kVarImmRandom}, {"argument", UByte, R::Argument, 0, 1, 0}};
constexpr Operand kWait[] = {{"source", UByte, R::Source, kVarImmRandom}, {"argument", Short, R::Argument, 0, 1, 0}};
constexpr Operand kMotorPower[] = {
    {"motors", UByte}, {"source", UByte, R::Source, kVarImmRandom}, {"argument", UByte, R::Argument, 0, 1, 1}};
constexpr Operand kDisplay[] = {{"source", UByte, R::Source, kVarImm}, {"argument", Short, R::Argument, 0, 1, 0}};
constexpr Operand kSendMessage[] = {{"source", UByte, R::Source, kVarImm}, {"argument", UByte, R::Argument, 0, 1, 0}};
constexpr Operand kDatalogNext[] = {{"source", UByte, R::Source, kDatalogSources}, {"argument", UByte, R::Argument, 0, 1, 0}};
constexpr Operand kGetValue[] = {{"source", UByte, R::Source, kGetValueSources}, {"argument", UByte, R::Argument, 0, 1, 0}};

constexpr Operand kSubroutine[] = {{"subroutine", UByte}};
constexpr Operand kTask[] = {{"task", UByte}};
constexpr Operand kSensor[] = {{"sensor", UByte}};
constexpr Operand kTimer[] = {{"timer", UByte}};
constexpr Operand kSound[] = {{"sound", UByte}};
constexpr Operand kCode[] = {{"code", UByte}};
constexpr Operand kMessage[] = {{"message", UByte}};
constexpr Operand kMinutes[] = {{"minutes", UByte}};
constexpr Operand kProgram[] = {{"program", UByte}};
constexpr Operand kRange[] = {{"range", UByte}};
constexpr Operand kTone[] = {{"frequency", Short}, {"duration", UByte}};
constexpr Operand kSensorType[] = {{"sensor", UByte}, {"type", UByte}};
constexpr Operand kSensorMode[] = {{"sensor", UByte}, {"code", UByte}};
constexpr Operand kTime[] = {{"hours", UByte}, {"minutes", UByte}};
constexpr Operand kDatalogSize[] = {{"size", Short}};
constexpr Operand kKey[] = {{"key", UByte, R::Value, 0, 5}};
constexpr Operand kTaskDownload[] = {{"unknown", UByte}, {"task", Short}, {"length", Short}};
constexpr Operand kSubDownload[] = {{"unknown", UByte}, {"subroutine", Short}, {"length", Short}};
constexpr Operand kFirmwareDownload[] = {{"address", UShort}, {"checksum", UShort}, {"unknown", UByte}};
constexpr Operand kTransfer[] = {
    {"index", Short}, {"length", Short, R::Length}, {"data", UByte, R::Data}, {"checksum", UByte, R::Checksum}};
constexpr Operand kUpload[] = {{"first", Short}, {"count", Short}};

constexpr Operand kErrorCode[] = {{"errorcode", UByte}};
constexpr Operand kShortValue[] = {{"value", Short}};
constexpr Operand kMillivolts[] = {{"millivolts", UShort}};
constexpr Operand kVersions[] = {{"rom", ShortBE, R::Value, 0, 2}, {"firmware", ShortBE, R::Value, 0, 2}};
constexpr Operand kMemoryMap[] = {{"map", UShortBE, R::Value, 0, 94}};
constexpr Operand kUnlockReply[] = {{"data", UByte, R::Value, 0, 25}};
// dlrec entries: (type byte, value short) repeated `count` times; the reply
// length comes from the request, so it is described as Data.
constexpr Operand kDatalogReply[] = {{"dlrec", UByte, R::Data}};

constexpr std::span<const Operand> none{};

constexpr Kind C = Kind::Command, Q = Kind::Request, B = Kind::Both;

// name, mnemonic, code, kind, toggles, replies, operands, reply, nqc's listing name
constexpr OpcodeInfo kTable[] = {
    {Op::AbsoluteValue, "Absolute value", "abs", 0x74, B, true, true, kVarSrcArg, none, "absv"},
    {Op::Alive, "Alive", "alive", 0x10, Q, true, true, none, none, "ping"},
    {Op::AddToVariable, "Add to variable", "add", 0x24, B, true, true, kVarSrcArg, none, "sumv"},
    {Op::AndVariable, "And variable", "and", 0x84, B, true, true, kVarSrcArg, none, "andv"},
    {Op::BranchAlwaysFar, "Branch always far", "jmpl", 0x72, C, false, false, kBranchFar, none, "jmpl"},
    {Op::BranchAlwaysNear, "Branch always near", "jmp", 0x27, C, false, false, kBranchNear, none, "jmp"},
    {Op::CallSubroutine, "Call subroutine", "call", 0x17, C, false, false, kSubroutine, none, "calls"},
    {Op::ClearMessage, "Clear message", "msgclr", 0x90, C, false, false, none, none, "msgz"},
    {Op::ClearSensorValue, "Clear sensor value", "sensclr", 0xd1, B, true, true, kSensor, none, "senz"},
    {Op::ClearTimer, "Clear timer", "timerclr", 0xa1, B, true, true, kTimer, none, "tmrz"},
    {Op::DecrementLoopCounterNear, "Decrement loop counter near", "loopdec", 0x37, C, false, false, kLoopNear, none, "loopc"},
    {Op::DeleteAllSubroutines, "Delete all subroutines", "delsubs", 0x70, B, true, true, none, none, "dels"},
    {Op::DeleteAllTasks, "Delete all tasks", "deltasks", 0x40, B, true, true, none, none, "delt"},
    {Op::DatalogNext, "Datalog next", "lognext", 0x62, B, true, true, kDatalogNext, kErrorCode, "log"},
    {Op::DecrementLoopCounterFar, "Decrement loop counter far", "loopdecl", 0x92, C, false, false, kLoopFar, none, "loopcl"},
    {Op::DeleteFirmware, "Delete firmware", "delfirm", 0x65, B, true, true, kKey, none, ""},
    {Op::DeleteSubroutine, "Delete subroutine", "delsub", 0xc1, B, true, true, kSubroutine, none, "dels"},
    {Op::DeleteTask, "Delete task", "deltask", 0x61, B, true, true, kTask, none, "delt"},
    {Op::DivideVariable, "Divide variable", "div", 0x44, B, true, true, kVarSrcArg, none, "divv"},
    {Op::GetMemoryMap, "Get memory map", "memmap", 0x20, Q, true, true, none, kMemoryMap, "memmap"},
    {Op::GetBatteryPower, "Get battery power", "battery", 0x30, Q, true, true, none, kMillivolts, "pollb"},
    {Op::GetValue, "Get value", "getval", 0x12, Q, true, true, kGetValue, kShortValue, "poll"},
    {Op::GetVersions, "Get versions", "versions", 0x15, Q, true, true, kKey, kVersions, "pollp"},
    {Op::MultiplyVariable, "Multiply variable", "mul", 0x54, B, true, true, kVarSrcArg, none, "mulv"},
    {Op::OrVariable, "Or variable", "or", 0x94, B, true, true, kVarSrcArg, none, "orv"},
    {Op::PowerOff, "Power off", "poweroff", 0x60, B, true, true, none, none, "offp"},
    {Op::ReturnFromSubroutine, "Return from subroutine", "ret", 0xf6, C, false, false, none, none, "rets"},
    {Op::PlaySound, "Play sound", "sound", 0x51, B, true, true, kSound, none, "plays"},
    {Op::PlayTone, "Play tone", "tone", 0x23, B, true, true, kTone, none, "playt"},
    {Op::SendMessage, "Send message", "msgsend", 0xb2, C, false, false, kSendMessage, none, "msg"},
    {Op::SetDatalogSize, "Set datalog size", "logsize", 0x52, B, true, true, kDatalogSize, kErrorCode, "logz"},
    {Op::SetDisplay, "Set display", "display", 0x33, B, true, true, kDisplay, none, "view"},
    {Op::SetLoopCounter, "Set loop counter", "loopset", 0x82, C, false, false, kSetLoop, none, "loops"},
    {Op::SetMotorOnOff, "Set motor on/off", "out", 0x21, B, true, true, kCode, none, "out"},
    {Op::SetMessage, "Set message", "msgset", 0xf7, B, false, false, kMessage, none, "msgs"},
    {Op::SetMotorDirection, "Set motor direction", "dir", 0xe1, B, true, true, kCode, none, "dir"},
    {Op::SetMotorPower, "Set motor power", "pwr", 0x13, B, true, true, kMotorPower, none, "pwr"},
    {Op::SetPowerDownDelay, "Set power down delay", "sleepdelay", 0xb1, B, true, true, kMinutes, none, "tout"},
    {Op::SetProgramNumber, "Set program number", "program", 0x91, B, true, true, kProgram, none, "prgm"},
    {Op::SetSensorMode, "Set sensor mode", "sensmode", 0x42, B, true, true, kSensorMode, none, "senm"},
    {Op::SetSensorType, "Set sensor type", "senstype", 0x32, B, true, true, kSensorType, none, "sent"},
    {Op::SetTime, "Set time", "settime", 0x22, B, true, true, kTime, none, "setw"},
    {Op::SetTransmitterRange, "Set transmitter range", "txrange", 0x31, B, true, true, kRange, none, "txs"},
    {Op::SetVariable, "Set variable", "set", 0x14, B, true, true, kSetVar, none, "setv"},
    {Op::SignVariable, "Sign variable", "sgn", 0x64, B, true, true, kVarSrcArg, none, "sgnv"},
    {Op::StartFirmwareDownload, "Start firmware download", "firmdl", 0x75, Q, true, true, kFirmwareDownload, kErrorCode, "_firm"},
    {Op::StartTaskDownload, "Start task download", "taskdl", 0x25, Q, true, true, kTaskDownload, kErrorCode, "_task"},
    {Op::StopAllTasks, "Stop all tasks", "stopall", 0x50, B, true, true, none, none, "stop"},
    {Op::StartSubroutineDownload, "Start subroutine download", "subdl", 0x35, Q, true, true, kSubDownload, kErrorCode, "_sub"},
    {Op::StartTask, "Start task", "start", 0x71, B, true, true, kTask, none, "start"},
    {Op::StopTask, "Stop task", "stop", 0x81, B, true, true, kTask, none, "stop"},
    {Op::SubtractFromVariable, "Subtract from variable", "sub", 0x34, B, true, true, kVarSrcArg, none, "subv"},
    {Op::TestAndBranchFar, "Test and branch far", "chkl", 0x95, C, false, false, kTestFar, none, "chkl"},
    {Op::TransferData, "Transfer data", "xfer", 0x45, Q, true, true, kTransfer, kErrorCode, ""},
    {Op::TestAndBranchNear, "Test and branch near", "chk", 0x85, C, false, false, kTestNear, none, "chk"},
    {Op::UnlockFirmware, "Unlock firmware", "unlock", 0xa5, Q, true, true, kKey, kUnlockReply, "boot"},
    {Op::UploadDatalog, "Upload datalog", "logupload", 0xa4, Q, true, true, kUpload, kDatalogReply, "polld"},
    {Op::Wait, "Wait", "wait", 0x43, C, false, false, kWait, none, "wait"},
};
static_assert(std::size(kTable) == kOpcodeCount, "one row per Op");

constexpr bool rows_in_op_order() {
  for (std::size_t i = 0; i < std::size(kTable); ++i)
    if (static_cast<std::size_t>(kTable[i].op) != i) return false;
  return true;
}
static_assert(rows_in_op_order());

struct ByteIndex {
  std::array<const OpcodeInfo*, 256> command{};
  std::array<const OpcodeInfo*, 256> request{};
};

constexpr ByteIndex build_index() {
  ByteIndex idx{};
  for (const auto& row : kTable) {
    if (row.is_command()) idx.command[row.code] = &row;
    if (row.is_request()) {
      idx.request[row.code] = &row;
      if (row.toggles) idx.request[alternate_form(row.code)] = &row;
    }
  }
  return idx;
}
constexpr ByteIndex kIndex = build_index();

}  // namespace

std::span<const OpcodeInfo> opcodes() { return kTable; }
const OpcodeInfo& info(Op op) { return kTable[static_cast<std::size_t>(op)]; }
const OpcodeInfo* command_at(std::uint8_t code) { return kIndex.command[code]; }
const OpcodeInfo* request_at(std::uint8_t code) { return kIndex.request[code]; }

const OpcodeInfo* by_mnemonic(std::string_view mnemonic) {
  auto it = std::find_if(std::begin(kTable), std::end(kTable),
                         [&](const OpcodeInfo& row) { return row.mnemonic == mnemonic; });
  return it == std::end(kTable) ? nullptr : &*it;
}

std::optional<int> fixed_size(std::span<const Operand> operands) {
  int n = 0;
  for (const auto& o : operands) {
    if (o.role == Role::Data) return std::nullopt;
    n += field_size(o.type) * o.count;
  }
  return n;
}

std::optional<int> command_size(const OpcodeInfo& op) {
  auto n = fixed_size(op.operands);
  return n ? std::optional<int>(*n + 1) : std::nullopt;
}

int read_field(FieldType t, const std::uint8_t* p) {
  switch (t) {
    case FieldType::Byte: return static_cast<std::int8_t>(p[0]);
    case FieldType::UByte: return p[0];
    case FieldType::Short: return static_cast<std::int16_t>(p[0] | (p[1] << 8));
    case FieldType::UShort: return p[0] | (p[1] << 8);
    case FieldType::ShortBE: return static_cast<std::int16_t>((p[0] << 8) | p[1]);
    case FieldType::UShortBE: return (p[0] << 8) | p[1];
  }
  return 0;
}

void write_field(FieldType t, int value, std::uint8_t* p) {
  auto lo = static_cast<std::uint8_t>(value & 0xff);
  auto hi = static_cast<std::uint8_t>((value >> 8) & 0xff);
  switch (t) {
    case FieldType::Byte:
    case FieldType::UByte: p[0] = lo; return;
    case FieldType::Short:
    case FieldType::UShort: p[0] = lo; p[1] = hi; return;
    case FieldType::ShortBE:
    case FieldType::UShortBE: p[0] = hi; p[1] = lo; return;
  }
}

std::string_view source_name(int source) {
  static constexpr std::string_view kNames[16] = {
      "var", "timer", "const", "motor", "random", "reserved5", "reserved6", "reserved7",
      "program", "sensor", "senstype", "sensmode", "sensraw", "sensbool", "clock", "message"};
  return (source >= 0 && source < 16) ? kNames[source] : "?";
}

std::optional<ArgumentRange> source_argument_range(int source) {
  switch (static_cast<Source>(source)) {
    case Source::Variable: return ArgumentRange{0, 31, "variable"};
    case Source::Timer: return ArgumentRange{0, 3, "timer"};
    case Source::MotorState: return ArgumentRange{0, 2, "output"};
    case Source::SensorValue: case Source::SensorType: case Source::SensorMode: case Source::SensorRaw:
    case Source::SensorBool: return ArgumentRange{0, 2, "sensor"};
    case Source::Clock: case Source::Message: return ArgumentRange{0, 0, ""};
    default: return std::nullopt;
  }
}

}  // namespace rcx
