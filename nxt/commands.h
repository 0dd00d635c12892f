// The one table of NXT commands: the seed's 19 direct commands, the direct
// commands LEGO's firmware has beyond them, and the system commands of the
// NXT Communication Protocol. Each entry gives the request and reply field
// layouts; the encoder, the decoder, the virtual NXT, `rcxc nxt --help` and
// the table in docs/nxt.md all read it (docs_table_test checks the docs).
//
// Layouts are what the firmware does where it departs from the seed
// (docs/nxt.md, "Firmware and seed"): SetOutputState's tacho limit is bytes
// 8-11 and LSRead's data bytes 4-19, for example.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace nxt {

// Byte 0 of a telegram.
inline constexpr std::uint8_t kDirectWithReply = 0x00;
inline constexpr std::uint8_t kSystemWithReply = 0x01;
inline constexpr std::uint8_t kReply = 0x02;
inline constexpr std::uint8_t kNoReplyBit = 0x80;  // 0x80 direct, 0x81 system: no answer wanted

// A direct command telegram is at most 64 bytes with its type byte; file
// names are 15.3 ASCIIZ in 20 bytes; a message is at most 59 bytes with its NUL.
inline constexpr std::size_t kMaxTelegram = 64;
inline constexpr std::size_t kNameField = 20;
inline constexpr std::size_t kMaxMessage = 59;
inline constexpr std::size_t kLsMax = 16;

enum class Group : std::uint8_t { Direct, System };

enum class Origin : std::uint8_t {
  Seed,      // the 19 direct commands of the seed
  Firmware,  // direct commands LEGO's firmware has beyond the seed
  System,    // system commands (spec/nxt.md)
};

enum class FieldKind : std::uint8_t {
  U8,
  S8,
  U16,
  S16,
  U32,
  S32,
  Bool,    // one byte, any non-zero is true
  Text,    // ASCIIZ in `width` bytes (file names: 20)
  Bytes,   // exactly `width` raw bytes (padded data, addresses)
  Rest,    // every remaining byte of the telegram (variable-length data)
};

// How a number is shown in logs and `-v` (the value itself is an integer).
enum class Show : std::uint8_t { Decimal, Hex, SensorType, SensorMode, OutputMode, Regulation, RunState, Status };

struct Field {
  std::string_view name;
  FieldKind kind;
  std::uint8_t width = 0;  // Text and Bytes only
  Show show = Show::Decimal;
  // For a U8 that counts the bytes of the Rest field that follows: the
  // encoder fills it in when no value is given.
  bool counts_rest = false;
  // Text only: the firmware copies `width` bytes of a longer buffer, so text
  // as long as the field comes without its NUL (GetDeviceInfo's 15-byte name
  // of a 15-character brick name).
  bool may_fill = false;
};

struct Command {
  Group group;
  std::uint8_t opcode;
  std::string_view name;
  Origin origin;
  std::span<const Field> request;  // after the opcode byte
  std::span<const Field> reply;    // after the status byte
  std::string_view summary;        // one line for help and docs
};

struct Status {
  std::uint8_t code;
  std::string_view name;
  std::string_view message;
};

struct EnumName {
  std::uint8_t value;
  std::string_view name;
};

std::span<const Command> commands();
const Command* find_command(Group group, std::uint8_t opcode);
const Command* find_command(std::string_view name);  // case-insensitive

std::span<const Status> statuses();
const Status* find_status(std::uint8_t code);
// "0xC0 out of range: data contains out-of-range values", or "unknown status 0x42".
std::string_view status_message(std::uint8_t code);

// Sensor types and modes with the seed's names (SWITCH, BOOLEANMODE, ...).
std::span<const EnumName> sensor_types();
std::span<const EnumName> sensor_modes();
std::span<const EnumName> run_states();
std::span<const EnumName> regulation_modes();
// Looks a name up case-insensitively; a mode also answers to its name
// without "MODE" (BOOLEAN for BOOLEANMODE).
std::optional<std::uint8_t> sensor_type_named(std::string_view name);
std::optional<std::uint8_t> sensor_mode_named(std::string_view name);
std::string_view enum_name(std::span<const EnumName> names, std::uint8_t value);  // "" if none
// SetOutputState's mode byte as its bit names: "MOTORON|BRAKE", "0" for none.
std::string output_mode_names(std::uint8_t mode);

// SetOutputState's mode bits.
inline constexpr std::uint8_t kMotorOn = 0x01;
inline constexpr std::uint8_t kBrake = 0x02;
inline constexpr std::uint8_t kRegulated = 0x04;
inline constexpr std::uint8_t kRunStateIdle = 0x00;
inline constexpr std::uint8_t kRunStateRunning = 0x20;

// Sensor types the firmware treats specially.
inline constexpr std::uint8_t kNoSensor = 0x00;
inline constexpr std::uint8_t kTemperatureSensor = 0x02;  // the RCX temperature sensor (converter cable)
inline constexpr std::uint8_t kSoundDb = 0x07;
inline constexpr std::uint8_t kSoundDba = 0x08;
inline constexpr std::uint8_t kLowSpeed = 0x0A;
inline constexpr std::uint8_t kLowSpeed9V = 0x0B;
inline constexpr std::uint8_t kFirstColourType = 0x0D;
inline constexpr std::uint8_t kLastSensorType = 0x11;

// Status codes the rest of the code names.
namespace status {
inline constexpr std::uint8_t kOk = 0x00;
inline constexpr std::uint8_t kPending = 0x20;
inline constexpr std::uint8_t kQueueEmpty = 0x40;
inline constexpr std::uint8_t kNoMoreHandles = 0x81;
inline constexpr std::uint8_t kNoSpace = 0x82;
inline constexpr std::uint8_t kNoMoreFiles = 0x83;
inline constexpr std::uint8_t kEndOfFile = 0x85;
inline constexpr std::uint8_t kFileNotFound = 0x87;
inline constexpr std::uint8_t kHandleClosed = 0x88;
inline constexpr std::uint8_t kFileBusy = 0x8B;
inline constexpr std::uint8_t kAppendNotPossible = 0x8D;
inline constexpr std::uint8_t kFileFull = 0x8E;
inline constexpr std::uint8_t kFileExists = 0x8F;
inline constexpr std::uint8_t kModuleNotFound = 0x90;
inline constexpr std::uint8_t kOutOfBoundary = 0x91;
inline constexpr std::uint8_t kIllegalFileName = 0x92;
inline constexpr std::uint8_t kIllegalHandle = 0x93;
inline constexpr std::uint8_t kUndefined = 0x8A;
inline constexpr std::uint8_t kUnknownCommand = 0xBE;
inline constexpr std::uint8_t kInsanePacket = 0xBF;
inline constexpr std::uint8_t kOutOfRange = 0xC0;
inline constexpr std::uint8_t kBusError = 0xDD;
inline constexpr std::uint8_t kChannelBusy = 0xE0;
inline constexpr std::uint8_t kNoProgram = 0xEC;
inline constexpr std::uint8_t kIllegalSize = 0xED;
inline constexpr std::uint8_t kIllegalQueue = 0xEE;
inline constexpr std::uint8_t kBadArguments = 0xFF;
}  // namespace status

}  // namespace nxt
