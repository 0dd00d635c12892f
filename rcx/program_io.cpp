#include "rcx/program_io.h"

#include "rcx/decode.h"

namespace rcx {
namespace {

void note_source(ProgramIo& io, int source, int argument) {
  switch (static_cast<Source>(source)) {
    // Type and mode are the program's own settings, not a reading.
    case Source::SensorValue:
    case Source::SensorRaw:
    case Source::SensorBool:
      if (argument >= 0 && argument < static_cast<int>(io.sensors_read.size()))
        io.sensors_read[static_cast<std::size_t>(argument)] = true;
      break;
    case Source::Message: io.message_read = true; break;
    default: break;
  }
}

// The argument operand that goes with source operand `index`, or -1.
int argument_of(const OpcodeInfo& op, const Decoded& d, std::size_t index) {
  for (std::size_t j = 0; j < op.operands.size() && j < d.v.size(); ++j)
    if (op.operands[j].role == Role::Argument && op.operands[j].pairs_with == static_cast<int>(index)) return d.v[j];
  return -1;
}

}  // namespace

ProgramIo program_io(const Image& image) {
  ProgramIo io;
  for (const Fragment& fragment : image.fragments) {
    const int size = static_cast<int>(fragment.code.size());
    for (int at = 0; at < size;) {
      Decoded d = decode_command(fragment.code, at);
      if (d.error != 0) {
        io.complete = false;
        break;
      }
      const OpcodeInfo& op = info(d.op);
      if (d.op == Op::SendMessage) io.message_sent = true;
      // SetSensorType's operands are the sensor and the type.
      if (d.op == Op::SetSensorType && d.v[0] >= 0 && d.v[0] < static_cast<int>(io.sensor_types.size()) &&
          d.v[1] >= 0 && d.v[1] < 8)
        io.sensor_types[static_cast<std::size_t>(d.v[0])] |= static_cast<std::uint8_t>(1u << d.v[1]);
      // Opcodes with sources have one field per operand, so operand i is v[i].
      for (std::size_t i = 0; i < op.operands.size() && i < d.v.size(); ++i) {
        const Operand& o = op.operands[i];
        if (o.role != Role::Source && o.role != Role::OpSource) continue;
        note_source(io, o.role == Role::OpSource ? (d.v[i] & 0x0f) : d.v[i], argument_of(op, d, i));
      }
      at += d.size;
    }
  }
  return io;
}

}  // namespace rcx
