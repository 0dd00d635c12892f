// Sensors a program reads but never sets up (see passes.h).
#include <array>

#include <fmt/format.h>

#include "ir/passes.h"

namespace rcxc::ir {

void warn_unconfigured_sensors(const Program& p, Diagnostics& diags) {
  constexpr std::size_t kSensors = 3;
  std::array<bool, kSensors> configured{}, read{};
  std::array<SpanId, kSensors> first_read{};
  auto note_read = [&](const Operand& o, SpanId span) {
    bool value = o.source == static_cast<int>(rcx::Source::SensorValue) ||
                 o.source == static_cast<int>(rcx::Source::SensorBool);
    if (o.kind != Operand::Kind::Src || !value || o.value < 0 || o.value >= static_cast<int>(kSensors)) return;
    auto s = static_cast<std::size_t>(o.value);
    if (!read[s]) first_read[s] = span;
    read[s] = true;
  };
  for (const Function& f : p.functions)
    for (const Block& b : f.blocks) {
      for (const Instr& in : b.instrs) {
        // asm bytes that may hold a Set sensor type or mode (either toggle
        // form) may set a sensor up: no claim then. Others (UploadDatalog's)
        // set none.
        if (in.raw) {
          for (const Operand& o : in.args)
            if (o.is_imm() && (o.value == 0x32 || o.value == 0x3a || o.value == 0x42 || o.value == 0x4a)) return;
          continue;
        }
        if ((in.op == rcx::Op::SetSensorType || in.op == rcx::Op::SetSensorMode) && !in.args.empty()) {
          const Operand& sensor = in.args[0];
          if (sensor.is_imm() && sensor.value >= 0 && sensor.value < static_cast<int>(kSensors))
            configured[static_cast<std::size_t>(sensor.value)] = true;
        }
        for (const Operand& o : in.args) note_read(o, in.span);
      }
      if (const auto* branch = std::get_if<Branch>(&b.term)) {
        note_read(branch->a, b.span);
        note_read(branch->b, b.span);
      }
    }
  for (std::size_t s = 0; s < kSensors; ++s)
    if (read[s] && !configured[s])
      diags.warning(p.span(first_read[s]), WarningKind::UnconfiguredSensor,
                    fmt::format("SENSOR_{0} is read but never set up (SetSensor(SENSOR_{0}, SENSOR_TOUCH), "
                                "SENSOR_LIGHT, ...): it reads the raw value, 0 to 1023, unless a program run before "
                                "set it up",
                                s + 1));
}

}  // namespace rcxc::ir
