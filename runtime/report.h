// What a run produced, for people and programs: the JSON report, the
// readable timeline, and the trace files (VCD for GTKWave, JSON events).
// Schemas are documented in docs/emulator.md.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "rcx/image.h"
#include "runtime/room.h"
#include "runtime/vm.h"

namespace rcx {

// The names NQC gives the numbers in events (SOUND_DOUBLE_BEEP for sound 1).
// They live in the standard library, which runtime/ does not read: the caller
// fills them (cli/ from stdlib::defined_numbers). A number without a name is
// printed as a number.
struct EventNames {
  std::map<int, std::string> sounds;        // SOUND_*
  std::map<int, std::string> displays;      // DISPLAY_*
  std::map<int, std::string> sensor_types;  // SENSOR_TYPE_*
};

// Variables the program named: the image's variable symbols. An image that
// names no variable at all (hand-made, or from a compiler that writes no
// symbols) gets every slot, since none can be told apart as a temporary.
std::vector<bool> named_variables(const Image& image);
// What a datalog entry recorded, as NQC writes the source: `Timer(0)`,
// `SENSOR_2`, `Watch()`, a variable's name or `var[5]`.
std::string datalog_source(int type, const Image& image);
// `sound 1` as `SOUND_DOUBLE_BEEP` (or the number when unnamed).
std::string name_or_number(const std::map<int, std::string>& names, int value);

// The `--report json` object.
nlohmann::json report_json(const Machine& machine, const Image& image);
// One event as JSON ({t, kind, ...}); the image gives task names.
nlohmann::json event_json(const Event& event, const Image& image);
// Every event (inputs included) as a JSON array: the `--trace F.json` file.
nlohmann::json trace_json(const Machine& machine, const Image& image);
// The same two as text, exactly as `dump(2)` of the objects above with
// invalid UTF-8 replaced, written to `out` event by event: the objects hold
// each event as a tree, about 550 bytes apiece, so a run's 5 000 000 events
// took 3.2 GB for `--report json` where the run itself took 530 MB.
void write_report_json(std::ostream& out, const Machine& machine, const Image& image);
void write_trace_json(std::ostream& out, const Machine& machine, const Image& image);
// Human-readable timeline and final state (what `rcxc run` prints by default):
// the program's own variables only (named_variables), sounds, displays and
// datalog sources by name.
std::string timeline_text(const Machine& machine, const Image& image, const EventNames& names = {});
// The two halves of the timeline, for a room of several bricks
// (runtime/room.h), whose events are shown together: each event's line
// without its time, and the final state from the `stopped:` line on.
struct TimelineLine {
  Micros t_us = 0;
  std::string text;
};
std::vector<TimelineLine> timeline_events(const Machine& machine, const Image& image, const EventNames& names = {});
std::string final_state_text(const Machine& machine, const Image& image);
// A time as the timeline shows it ("1806.000"), and the width of its
// column for times up to `latest`.
std::string time_ms(Micros us);
std::size_t time_column_width(Micros latest);
// Several bricks run together (room.h): each with its label (`1 master`).
struct RoomBrick {
  const Machine* machine = nullptr;
  const Image* image = nullptr;
  std::string label;
};
// One timeline of every brick's events in time order, each line naming its
// brick, with what became of each message on the air that did not arrive
// (lost to another brick's packet, or no program left to hear it); then
// each brick's final state under its label.
std::string room_timeline_text(std::span<const RoomBrick> bricks, std::span<const Transmission> sent,
                               const EventNames& names = {});
// {"bricks": [{"label", "report": the one-brick report}], "messages": [...]}.
nlohmann::json room_report_json(std::span<const RoomBrick> bricks, std::span<const Transmission> sent);

// A Value Change Dump of outputs, sensor inputs, the program's variables
// (named_variables) and sounds. Variable changes appear only if the machine
// ran with trace_variables.
std::string trace_vcd(const Machine& machine, const Image& image);

}  // namespace rcx
