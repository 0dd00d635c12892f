// A virtual NXT with LEGO's firmware behaviour as spec/nxt.md describes it:
// every command of the table, a flash file system (15.3 names, 16 handles,
// linear and data files, the file-system error codes), 20 mailbox queues of
// 5 messages that need a running program, a program run state, motors whose
// tacho counts advance with power and time, sensors fed from a scenario, the
// input-valid delay, an I2C ultrasonic sensor, battery, the sleep timer,
// device info, and the firmware's modules, whose UI and loader IO maps hold
// the same volume, sleep limit, Bluetooth state, battery and free flash the
// direct commands see. Deviations from a real brick are listed in docs/nxt.md.
//
// Time is the caller's: `advance_to` moves the brick's clock (virtual in
// tests, the wall clock when served on a pty), so nothing here sleeps.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "nxt/scenario.h"
#include "nxt/telegram.h"

namespace nxt {

using Micros = std::int64_t;

struct Motor {
  std::int8_t power = 0;
  std::uint8_t mode = 0;
  std::uint8_t regulation = 0;
  std::int8_t turn_ratio = 0;
  std::uint8_t run_state = kRunStateIdle;
  std::uint32_t tacho_limit = 0;
  // Degrees, kept fractional so slow motors still move.
  double tacho_count = 0;  // since UpdateResetCount or a program start/stop
  double block_count = 0;  // since ResetMotorPosition relative
  double rotation_count = 0;  // since ResetMotorPosition absolute
  double moved_this_run = 0;  // towards tacho_limit
};

struct Sensor {
  std::uint8_t type = kNoSensor;
  std::uint8_t mode = 0;
  int raw = 1023;  // an open input reads full scale
  Micros valid_at = 0;
  bool boolean = false;  // the firmware's hysteresis state
  int transitions = 0;   // boolean edges since ResetInputScaledValue
  int distance_cm = 255;  // what an ultrasonic sensor on this port sees
  // An RCX rotation sensor on the port (ANGLE): its shaft position in 1/16
  // turns, and the position where ANGLESTEPSMODE's count was last zeroed.
  int rotation = 0;
  int rotation_base = 0;
  // I2C: the transaction in flight and its answer.
  Micros ls_ready_at = -1;
  Bytes ls_answer;
  bool ls_failed = false;
  std::uint8_t us_command = 2;  // ultrasonic register 0x41: continuous
};

struct SoundEvent {
  Micros at_us = 0;
  enum class Kind : std::uint8_t { Tone, File, Stop } kind = Kind::Tone;
  int frequency_hz = 0;
  int duration_ms = 0;
  std::string file;
  bool loop = false;
};

struct StoredFile {
  Bytes data;
  std::uint32_t size = 0;  // declared at OpenWrite
  bool linear = false;
  bool data_file = false;
};

struct Handle {
  enum class Kind : std::uint8_t { Read, Write, Find } kind = Kind::Read;
  std::string name;     // the file (Read, Write) or the pattern (Find)
  std::size_t pos = 0;  // read offset, or the index of the next match
};

// The loader has one module search, apart from the file handles
// (c_loader.c): its handle is 0 in every reply, a second FindFirstModule
// before CloseModuleHandle answers 0x81, and running out of modules does not
// end it.
struct ModuleSearch {
  bool open = false;
  Handle cursor{Handle::Kind::Find, "", 0};
};

struct Module {
  std::string name;
  std::uint32_t id;
  Bytes iomap;
};

// A slot of the Bluetooth contact or connection table (BTGetContactName,
// BTGetConnName): an empty name is an empty slot.
struct BtSlot {
  std::uint8_t device_type = 0;
  std::string name;
};

// The loader matches names without regard to case (it upper-cases both
// sides): "PROG.RXE" is the file "prog.rxe", and cannot be made beside it.
struct FileNameLess {
  bool operator()(const std::string& a, const std::string& b) const;
};

struct VirtualNxt {
  Micros now_us = 0;
  std::string name = "NXT";
  std::array<std::uint8_t, 7> bt_address{0x00, 0x16, 0x53, 0x0A, 0x0B, 0x0C, 0x00};
  int battery_mv = 7800;
  // GetFirmwareVersion's answer: protocol minor, major, firmware minor,
  // major (LEGO's 1.31; tests set leJOS's 2, 1, 3, 1 to see it refused).
  std::array<std::uint8_t, 4> versions{124, 1, 31, 1};
  std::uint8_t volume = 3;
  bool bluetooth_on = true;
  std::uint32_t sleep_minutes = 10;  // the firmware keeps whole minutes
  Micros awake_since_us = 0;         // last KeepAlive or program start
  bool asleep = false;               // a brick that slept is off: it answers nothing
  std::optional<std::string> program;
  std::array<Motor, 3> motors{};
  std::array<Sensor, 4> sensors{};
  std::array<std::deque<Bytes>, 20> queues{};
  std::map<std::string, StoredFile, FileNameLess> files;
  std::array<std::optional<Handle>, 16> handles{};
  std::vector<Module> modules;
  ModuleSearch module_search;
  std::array<BtSlot, 30> contacts{};    // the firmware's table sizes: 30 contacts,
  std::array<BtSlot, 4> connections{};  // 4 connections (0 the master, 1-3 slaves)
  std::vector<SoundEvent> sounds;
  std::uint32_t flash_bytes = 128 * 1024;
  std::vector<ScenarioInput> scenario;
  std::size_t next_input = 0;
  // Where scenario time 0 lies on the brick's clock; none yet: no input is
  // due (serve() sets it at the first telegram, so a host's run and the
  // scenario start together).
  std::optional<Micros> scenario_origin_us = 0;
  struct {
    std::uint64_t requests = 0, replies = 0, ignored = 0;
    std::uint64_t messages_dropped = 0;  // scenario messages while no program ran
  } counters;
};

VirtualNxt make_virtual_nxt(std::vector<ScenarioInput> scenario = {});

// Moves the brick's clock forward: motors turn, scenario inputs arrive, the
// sleep timer runs. Earlier times are ignored.
void advance_to(VirtualNxt& nxt, Micros now_us);

// The brick's answer to one telegram (without Bluetooth framing), or nothing:
// no-reply telegrams, unknown telegram types and a sleeping brick answer nothing.
std::optional<Bytes> answer(VirtualNxt& nxt, std::span<const std::uint8_t> telegram);

std::uint32_t free_flash(const VirtualNxt& nxt);

// A program `name` running, as if started on the brick's own menu: the file
// is made (empty) if it is not there. Mailboxes need a running program.
// The message says why not (not an executable name, no space).
std::optional<std::string> start_program(VirtualNxt& nxt, const std::string& name);

// Serving on a descriptor with Bluetooth framing, in real time. Scenario
// times count from the first telegram that arrives.
struct ServeOptions {
  int stop_fd = -1;  // serving ends when this becomes readable
  std::function<void(const std::string&)> on_log;  // each telegram decoded (-v)
};
struct ServeError {
  std::string message;
};
std::optional<ServeError> serve(VirtualNxt& nxt, int fd, const ServeOptions& options);

}  // namespace nxt
