// What a run produced, for people and programs: the JSON report, the
// readable timeline, and the trace files (VCD for GTKWave, JSON events).
// Schemas are documented in docs/emulator.md.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace rcx {

// The `--report json` object.
nlohmann::json report_json(const Machine& machine, const Image& image);
// One event as JSON ({t, kind, ...}); the image gives task names.
nlohmann::json event_json(const Event& event, const Image& image);
// Every event (inputs included) as a JSON array: the `--trace F.json` file.
nlohmann::json trace_json(const Machine& machine, const Image& image);
// Human-readable timeline and final state (what `rcxc run` prints by default).
std::string timeline_text(const Machine& machine, const Image& image);
// A Value Change Dump of outputs, sensor inputs, variables and sounds.
// Variable changes appear only if the machine ran with trace_variables.
std::string trace_vcd(const Machine& machine, const Image& image);

}  // namespace rcx
