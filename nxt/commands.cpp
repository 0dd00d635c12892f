#include "nxt/commands.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <string>

#include <fmt/format.h>

namespace nxt {
namespace {

using K = FieldKind;

constexpr Field kNone[] = {{"", K::U8}};  // a placeholder: spans below use size 0
constexpr std::span<const Field> none() { return std::span<const Field>(kNone, 0); }

// Field layouts, shared where commands share them.
constexpr Field kName[] = {{"name", K::Text, 20}};
constexpr Field kLoopName[] = {{"loop", K::Bool}, {"name", K::Text, 20}};
constexpr Field kTone[] = {{"frequency_hz", K::U16}, {"duration_ms", K::U16}};
constexpr Field kSetOutput[] = {{"port", K::U8},
                                {"power", K::S8},
                                {"mode", K::U8, 0, Show::OutputMode},
                                {"regulation", K::U8, 0, Show::Regulation},
                                {"turn_ratio", K::S8},
                                {"run_state", K::U8, 0, Show::RunState},
                                {"tacho_limit", K::U32}};
constexpr Field kSetInput[] = {
    {"port", K::U8}, {"type", K::U8, 0, Show::SensorType}, {"mode", K::U8, 0, Show::SensorMode}};
constexpr Field kPort[] = {{"port", K::U8}};
constexpr Field kOutputState[] = {{"port", K::U8},
                                  {"power", K::S8},
                                  {"mode", K::U8, 0, Show::OutputMode},
                                  {"regulation", K::U8, 0, Show::Regulation},
                                  {"turn_ratio", K::S8},
                                  {"run_state", K::U8, 0, Show::RunState},
                                  {"tacho_limit", K::U32},
                                  {"tacho_count", K::S32},
                                  {"block_tacho_count", K::S32},
                                  {"rotation_count", K::S32}};
constexpr Field kInputValues[] = {{"port", K::U8},
                                  {"valid", K::Bool},
                                  {"calibrated", K::Bool},
                                  {"type", K::U8, 0, Show::SensorType},
                                  {"mode", K::U8, 0, Show::SensorMode},
                                  {"raw", K::U16},
                                  {"normalized", K::U16},
                                  {"scaled", K::S16},
                                  {"calibrated_value", K::S16}};
constexpr Field kMessageWrite[] = {{"inbox", K::U8}, {"size", K::U8, 0, Show::Decimal, true}, {"data", K::Rest}};
constexpr Field kResetMotor[] = {{"port", K::U8}, {"relative", K::Bool}};
constexpr Field kBattery[] = {{"millivolts", K::U16}};
constexpr Field kKeepAlive[] = {{"sleep_limit_ms", K::U32}};
constexpr Field kBytesReady[] = {{"bytes_ready", K::U8}};
constexpr Field kLsWrite[] = {
    {"port", K::U8}, {"tx_length", K::U8, 0, Show::Decimal, true}, {"rx_length", K::U8}, {"tx_data", K::Rest}};
constexpr Field kLsRead[] = {{"bytes_read", K::U8}, {"rx_data", K::Bytes, 16, Show::Hex}};
constexpr Field kMessageRead[] = {{"remote_inbox", K::U8}, {"local_inbox", K::U8}, {"remove", K::Bool}};
constexpr Field kMessageReadReply[] = {{"local_inbox", K::U8}, {"size", K::U8}, {"data", K::Bytes, 59}};
constexpr Field kRemove[] = {{"remove", K::Bool}};
// MAX_DATALOG_SIZE is 60: with its size byte the reply is 64 bytes, as MessageRead's.
constexpr Field kDatalogReply[] = {{"size", K::U8}, {"data", K::Bytes, 60, Show::Hex}};
constexpr Field kSyncTime[] = {{"sync_time", K::U32}};
constexpr Field kCount[] = {{"count", K::U8}};
constexpr Field kIndex[] = {{"index", K::U8}};
constexpr Field kBtName[] = {{"device_type", K::U8}, {"name", K::Text, 17}};
constexpr Field kSetProperty[] = {{"property", K::U8}, {"value", K::Rest, 0, Show::Hex}};
constexpr Field kProperty[] = {{"property", K::U8}};
constexpr Field kPropertyValue[] = {{"value", K::Rest, 0, Show::Hex}};

constexpr Field kNameSize[] = {{"name", K::Text, 20}, {"size", K::U32}};
constexpr Field kHandle[] = {{"handle", K::U8}};
constexpr Field kHandleSize[] = {{"handle", K::U8}, {"size", K::U32}};
constexpr Field kReadRequest[] = {{"handle", K::U8}, {"count", K::U16}};
constexpr Field kHandleCountData[] = {{"handle", K::U8}, {"count", K::U16}, {"data", K::Rest, 0, Show::Hex}};
constexpr Field kHandleData[] = {{"handle", K::U8}, {"data", K::Rest, 0, Show::Hex}};
constexpr Field kHandleCount[] = {{"handle", K::U8}, {"count", K::U16}};
constexpr Field kPattern[] = {{"pattern", K::Text, 20}};
constexpr Field kFound[] = {{"handle", K::U8}, {"name", K::Text, 20}, {"size", K::U32}};
constexpr Field kVersion[] = {
    {"protocol_minor", K::U8}, {"protocol_major", K::U8}, {"firmware_minor", K::U8}, {"firmware_major", K::U8}};
constexpr Field kHandleAvailable[] = {{"handle", K::U8}, {"available", K::U32}};
constexpr Field kModule[] = {
    {"handle", K::U8}, {"name", K::Text, 20}, {"module_id", K::U32, 0, Show::Hex}, {"size", K::U32}, {"iomap_size", K::U16}};
constexpr Field kReadIoMap[] = {{"module_id", K::U32, 0, Show::Hex}, {"offset", K::U16}, {"count", K::U16}};
constexpr Field kIoMapData[] = {{"module_id", K::U32, 0, Show::Hex}, {"count", K::U16}, {"data", K::Rest, 0, Show::Hex}};
constexpr Field kWriteIoMap[] = {
    {"module_id", K::U32, 0, Show::Hex}, {"offset", K::U16}, {"count", K::U16, 0, Show::Decimal, true}, {"data", K::Rest, 0, Show::Hex}};
constexpr Field kIoMapCount[] = {{"module_id", K::U32, 0, Show::Hex}, {"count", K::U16}};
constexpr Field kBoot[] = {{"magic", K::Text, 19}};
constexpr Field kBootReply[] = {{"answer", K::Text, 4}};
constexpr Field kBrickName[] = {{"name", K::Text, 16}};
// The firmware copies 15 bytes of the 16-byte brick name (c_comm.c
// DEVICEINFO): a 15-character name comes without its NUL.
constexpr Field kDeviceInfo[] = {{"name", K::Text, 15, Show::Decimal, false, true},
                                 {"bt_address", K::Bytes, 7, Show::Hex},
                                 {"signal_strength", K::U32},
                                 {"free_flash", K::U32}};
constexpr Field kBuffer[] = {{"buffer", K::U8}};
constexpr Field kBufferCount[] = {{"buffer", K::U8}, {"count", K::U8}};
constexpr Field kBufferCountData[] = {{"buffer", K::U8}, {"count", K::U8}, {"data", K::Rest, 0, Show::Hex}};

constexpr Group D = Group::Direct;
constexpr Group S = Group::System;

const Command kCommands[] = {
    // The seed's direct commands.
    {D, 0x00, "StartProgram", Origin::Seed, kName, none(), "Start a program file (.rxe)"},
    {D, 0x01, "StopProgram", Origin::Seed, none(), none(), "Stop the running program"},
    {D, 0x02, "PlaySoundFile", Origin::Seed, kLoopName, none(), "Play a sound file (.rso), once or looping"},
    {D, 0x03, "PlayTone", Origin::Seed, kTone, none(), "Play a tone (200-14000 Hz; the brick does not check)"},
    {D, 0x04, "SetOutputState", Origin::Seed, kSetOutput, none(), "Drive a motor (the brick does not check ranges)"},
    {D, 0x05, "SetInputMode", Origin::Seed, kSetInput, none(), "Set a sensor port's type and mode"},
    {D, 0x06, "GetOutputState", Origin::Seed, kPort, kOutputState, "Read a motor's state and tacho counts"},
    {D, 0x07, "GetInputValues", Origin::Seed, kPort, kInputValues, "Read a sensor port"},
    {D, 0x08, "ResetInputScaledValue", Origin::Seed, kPort, none(), "Reset a sensor's scaled value (counters)"},
    {D, 0x09, "MessageWrite", Origin::Seed, kMessageWrite, none(), "Put a message in a mailbox (needs a running program)"},
    {D, 0x0A, "ResetMotorPosition", Origin::Seed, kResetMotor, none(), "Reset a motor's block or rotation count"},
    {D, 0x0B, "GetBatteryLevel", Origin::Seed, none(), kBattery, "Battery voltage in mV"},
    {D, 0x0C, "StopSoundPlayback", Origin::Seed, none(), none(), "Stop the sound playing"},
    {D, 0x0D, "KeepAlive", Origin::Seed, none(), kKeepAlive, "Reset the sleep timer; answers the limit in ms"},
    {D, 0x0E, "LSGetStatus", Origin::Seed, kPort, kBytesReady, "I2C: bytes ready to read on a port"},
    {D, 0x0F, "LSWrite", Origin::Seed, kLsWrite, none(), "I2C: write to a device (tx, rx <= 16 bytes)"},
    {D, 0x10, "LSRead", Origin::Seed, kPort, kLsRead, "I2C: read a device's answer (16 bytes, padded)"},
    {D, 0x11, "GetCurrentProgramName", Origin::Seed, none(), kName, "Name of the running program"},
    {D, 0x13, "MessageRead", Origin::Seed, kMessageRead, kMessageReadReply, "Take a message from a mailbox (needs a running program)"},
    // Direct commands of LEGO's firmware beyond the seed.
    {D, 0x12, "GetButtonState", Origin::Firmware, none(), none(), "No handler in the firmware: answers 0xBE"},
    {D, 0x19, "DatalogRead", Origin::Firmware, kRemove, kDatalogReply, "Read the datalog buffer"},
    {D, 0x1A, "DatalogSetTimes", Origin::Firmware, kSyncTime, none(), "Set the datalog sync time"},
    {D, 0x1B, "BTGetContactCount", Origin::Firmware, none(), kCount, "Size of the Bluetooth contact table"},
    {D, 0x1C, "BTGetContactName", Origin::Firmware, kIndex, kBtName, "A Bluetooth contact's device type and name"},
    {D, 0x1D, "BTGetConnCount", Origin::Firmware, none(), kCount, "Size of the Bluetooth connection table"},
    {D, 0x1E, "BTGetConnName", Origin::Firmware, kIndex, kBtName, "A Bluetooth connection's device type and name"},
    {D, 0x1F, "SetProperty", Origin::Firmware, kSetProperty, none(), "Set property 0 BT on/off, 1 volume 0-4, 2 sleep ms (u32)"},
    {D, 0x20, "GetProperty", Origin::Firmware, kProperty, kPropertyValue, "Get property 0 BT on/off, 1 volume, 2 sleep ms (u32)"},
    {D, 0x21, "UpdateResetCount", Origin::Firmware, kPort, none(), "Reset a motor's internal tacho count"},
    // System commands.
    {S, 0x80, "OpenRead", Origin::System, kName, kHandleSize, "Open a file for reading"},
    {S, 0x81, "OpenWrite", Origin::System, kNameSize, kHandle, "Create a file (.rxe/.sys/.rtm are made linear)"},
    {S, 0x82, "Read", Origin::System, kReadRequest, kHandleCountData, "Read from an open file"},
    {S, 0x83, "Write", Origin::System, kHandleData, kHandleCount, "Write to an open file"},
    {S, 0x84, "Close", Origin::System, kHandle, kHandle, "Close a handle"},
    {S, 0x85, "Delete", Origin::System, kName, kName, "Delete a file"},
    {S, 0x86, "FindFirst", Origin::System, kPattern, kFound, "First file matching *.*, x.*, *.ext or x.ext"},
    {S, 0x87, "FindNext", Origin::System, kHandle, kFound, "Next file of a search"},
    {S, 0x88, "GetFirmwareVersion", Origin::System, none(), kVersion, "Protocol and firmware versions"},
    {S, 0x89, "OpenWriteLinear", Origin::System, kNameSize, kHandle, "Create a linear (contiguous) file"},
    {S, 0x8B, "OpenWriteData", Origin::System, kNameSize, kHandle, "Create a data file (refuses .rxe/.sys/.rtm)"},
    {S, 0x8C, "OpenAppendData", Origin::System, kName, kHandleAvailable, "Append to a data file"},
    {S, 0x90, "FindFirstModule", Origin::System, kPattern, kModule, "First firmware module matching a pattern"},
    {S, 0x91, "FindNextModule", Origin::System, kHandle, kModule, "Next module of a search"},
    {S, 0x92, "CloseModuleHandle", Origin::System, kHandle, kHandle, "End a module search"},
    {S, 0x94, "ReadIOMap", Origin::System, kReadIoMap, kIoMapData, "Read a module's IO map"},
    {S, 0x95, "WriteIOMap", Origin::System, kWriteIoMap, kIoMapCount, "Write a module's IO map"},
    {S, 0x97, "Boot", Origin::System, kBoot, kBootReply, "USB only: erase the firmware and enter SAMBA"},
    {S, 0x98, "SetBrickName", Origin::System, kBrickName, none(), "Rename the brick"},
    {S, 0x9B, "GetDeviceInfo", Origin::System, none(), kDeviceInfo, "Name, Bluetooth address, free flash"},
    {S, 0xA0, "DeleteUserFlash", Origin::System, none(), none(), "Delete every file (takes about 3 s)"},
    {S, 0xA1, "PollCommandLength", Origin::System, kBuffer, kBufferCount, "Bytes waiting in a poll buffer"},
    {S, 0xA2, "PollCommand", Origin::System, kBufferCount, kBufferCountData, "Read a poll buffer"},
};

const Status kStatuses[] = {
    {0x00, "success", "success"},
    {0x20, "pending", "pending communication transaction in progress"},
    {0x40, "queue_empty", "specified mailbox queue is empty"},
    {0x81, "no_more_handles", "no more handles"},
    {0x82, "no_space", "no space"},
    {0x83, "no_more_files", "no more files"},
    {0x84, "end_of_file_expected", "end of file expected"},
    {0x85, "end_of_file", "end of file"},
    {0x86, "not_linear", "not a linear file"},
    {0x87, "file_not_found", "file not found"},
    {0x88, "handle_closed", "handle already closed"},
    {0x89, "no_linear_space", "no linear space"},
    {0x8A, "undefined", "undefined error"},
    {0x8B, "file_busy", "file is busy"},
    {0x8C, "no_write_buffers", "no write buffers"},
    {0x8D, "append_not_possible", "append not possible"},
    {0x8E, "file_full", "file is full"},
    {0x8F, "file_exists", "file exists"},
    {0x90, "module_not_found", "module not found"},
    {0x91, "out_of_boundary", "out of boundary"},
    {0x92, "illegal_file_name", "illegal file name"},
    {0x93, "illegal_handle", "illegal handle"},
    {0xBD, "request_failed", "request failed (i.e. specified file not found)"},
    {0xBE, "unknown_command", "unknown command opcode"},
    {0xBF, "insane_packet", "insane packet"},
    {0xC0, "out_of_range", "data contains out-of-range values"},
    {0xDD, "bus_error", "communication bus error"},
    {0xDE, "no_buffer_memory", "no free memory in communication buffer"},
    {0xDF, "channel_invalid", "specified channel/connection is not valid"},
    {0xE0, "channel_busy", "specified channel/connection not configured or busy"},
    {0xEC, "no_program", "no active program"},
    {0xED, "illegal_size", "illegal size specified"},
    {0xEE, "illegal_queue", "illegal mailbox queue ID specified"},
    {0xEF, "invalid_field", "attempted to access invalid field of a structure"},
    {0xF0, "bad_port", "bad input or output specified"},
    {0xFB, "no_memory", "insufficient memory available"},
    {0xFF, "bad_arguments", "bad arguments"},
};

const EnumName kSensorTypes[] = {
    {0x00, "NO_SENSOR"},   {0x01, "SWITCH"},       {0x02, "TEMPERATURE"},   {0x03, "REFLECTION"},
    {0x04, "ANGLE"},       {0x05, "LIGHT_ACTIVE"}, {0x06, "LIGHT_INACTIVE"}, {0x07, "SOUND_DB"},
    {0x08, "SOUND_DBA"},   {0x09, "CUSTOM"},       {0x0A, "LOWSPEED"},       {0x0B, "LOWSPEED_9V"},
    {0x0C, "HIGHSPEED"},   {0x0D, "COLORFULL"},    {0x0E, "COLORRED"},       {0x0F, "COLORGREEN"},
    {0x10, "COLORBLUE"},   {0x11, "COLORNONE"},
};

const EnumName kSensorModes[] = {
    {0x00, "RAWMODE"},          {0x20, "BOOLEANMODE"},  {0x40, "TRANSITIONCNTMODE"}, {0x60, "PERIODCOUNTERMODE"},
    {0x80, "PCTFULLSCALEMODE"}, {0xA0, "CELSIUSMODE"},  {0xC0, "FAHRENHEITMODE"},    {0xE0, "ANGLESTEPSMODE"},
};

const EnumName kRunStates[] = {
    {0x00, "IDLE"}, {0x10, "RAMPUP"}, {0x20, "RUNNING"}, {0x40, "RAMPDOWN"}};
const EnumName kRegulationModes[] = {{0x00, "IDLE"}, {0x01, "MOTOR_SPEED"}, {0x02, "MOTOR_SYNC"}};

bool same_name(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
         });
}

std::optional<std::uint8_t> lookup(std::span<const EnumName> names, std::string_view name) {
  for (const auto& e : names)
    if (same_name(e.name, name)) return e.value;
  return std::nullopt;
}

}  // namespace

std::span<const Command> commands() { return kCommands; }

const Command* find_command(Group group, std::uint8_t opcode) {
  for (const auto& c : kCommands)
    if (c.group == group && c.opcode == opcode) return &c;
  return nullptr;
}

const Command* find_command(std::string_view name) {
  for (const auto& c : kCommands)
    if (same_name(c.name, name)) return &c;
  return nullptr;
}

std::span<const Status> statuses() { return kStatuses; }

const Status* find_status(std::uint8_t code) {
  for (const auto& s : kStatuses)
    if (s.code == code) return &s;
  return nullptr;
}

std::string_view status_message(std::uint8_t code) {
  const Status* s = find_status(code);
  return s ? s->message : std::string_view("unknown status");
}

std::span<const EnumName> sensor_types() { return kSensorTypes; }
std::span<const EnumName> sensor_modes() { return kSensorModes; }
std::span<const EnumName> run_states() { return kRunStates; }
std::span<const EnumName> regulation_modes() { return kRegulationModes; }

std::optional<std::uint8_t> sensor_type_named(std::string_view name) { return lookup(kSensorTypes, name); }

std::optional<std::uint8_t> sensor_mode_named(std::string_view name) {
  if (auto v = lookup(kSensorModes, name)) return v;
  return lookup(kSensorModes, std::string(name) + "MODE");
}

std::string output_mode_names(std::uint8_t mode) {
  std::string s;
  auto add = [&](std::uint8_t bit, const char* name) {
    if (mode & bit) s += (s.empty() ? "" : "|") + std::string(name);
  };
  add(kMotorOn, "MOTORON");
  add(kBrake, "BRAKE");
  add(kRegulated, "REGULATED");
  if (mode & ~0x07) s += fmt::format("{}0x{:02x}", s.empty() ? "" : "|", mode & ~0x07);
  return s.empty() ? "0" : s;
}

std::string_view enum_name(std::span<const EnumName> names, std::uint8_t value) {
  for (const auto& e : names)
    if (e.value == value) return e.name;
  return {};
}

}  // namespace nxt
