#include "backend/nqc_listing.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <tuple>

#include "rcx/decode.h"

namespace rcxc::backend {
namespace {

// nqc's names for what an operand reads; types it has no name for are
// written %TYPE(ARG).
std::string source_text(int source, int arg) {
  static constexpr const char* kNames[16] = {nullptr,   "Timer",      "",          "Output",     "Random",
                                             nullptr,   nullptr,      nullptr,     "Program",    "Input",
                                             "SensorType", "SensorMode", "SensorRaw", "SensorBool", "Watch",
                                             "Message"};
  if (source == 0) return fmt::format("var[{}]", arg);
  if (source == 2) return std::to_string(arg);
  if (source > 0 && source < 16 && kNames[source]) return fmt::format("{}({})", kNames[source], arg);
  return fmt::format("%{}({})", source, arg);
}

std::string outputs_text(int bits) {
  std::string s;
  for (int i = 0; i < 3; ++i)
    if (bits & (1 << i)) s += static_cast<char>('A' + i);
  return s;
}

std::string named(int value, std::initializer_list<const char*> names) {
  if (value >= 0 && value < static_cast<int>(names.size())) return names.begin()[value];
  return std::to_string(value);
}

// Each operand's value as a number, in table order (each of a key's five
// bytes): both layouts' form for the instructions they spell no other way.
std::string numbered_operands(const rcx::Decoded& d) {
  std::size_t values = 0;
  for (const rcx::Operand& o : rcx::info(d.op).operands) values += o.count;
  std::string s;
  for (std::size_t i = 0; i < values && i < d.v.size(); ++i)
    s += (i ? ", " : "") + std::to_string(d.v[i]);
  return s;
}

// The download requests as both layouts write them: without the byte the
// seed calls unknown, the firmware's address and checksum as signed.
std::optional<std::string> download_operands(const rcx::Decoded& d) {
  const auto& v = d.v;
  using rcx::Op;
  switch (d.op) {
    case Op::StartTaskDownload: case Op::StartSubroutineDownload: return fmt::format("{}, {}", v[1], v[2]);
    case Op::StartFirmwareDownload:
      return fmt::format("{}, {}", static_cast<std::int16_t>(v[0]), static_cast<std::int16_t>(v[1]));
    default: return std::nullopt;
  }
}

// The operands as nqc writes them, from the decoded values (table order).
std::string operands_text(const rcx::Decoded& d) {
  const auto& v = d.v;
  using rcx::Op;
  switch (d.op) {
    case Op::SetVariable: case Op::AddToVariable: case Op::SubtractFromVariable: case Op::MultiplyVariable:
    case Op::DivideVariable: case Op::AndVariable: case Op::OrVariable: case Op::AbsoluteValue:
    case Op::SignVariable:
      return fmt::format("var[{}], {}", v[0], source_text(v[1], v[2]));
    case Op::SetMotorPower: return fmt::format("{}, {}", outputs_text(v[0]), source_text(v[1], v[2]));
    case Op::SetMotorOnOff:
      return fmt::format("{}, {}", outputs_text(v[0]), (v[0] & 0x80) ? "On" : (v[0] & 0x40) ? "Off" : "Float");
    case Op::SetMotorDirection:
      return fmt::format("{}, {}", outputs_text(v[0]), (v[0] & 0x80) ? "Fwd" : (v[0] & 0x40) ? "Flip" : "Rev");
    case Op::SetSensorType: return fmt::format("{}, {}", v[0], named(v[1], {"None", "Switch", "Temp", "Light", "Angle"}));
    case Op::SetSensorMode:  // "Celcius" is nqc's spelling
      return fmt::format("{}, {}", v[0], named(v[1] >> 5, {"Raw", "Boolean", "Edge", "Pulse", "Percent", "Celcius",
                                                            "Fahrenheit", "Angle"}));
    case Op::Wait: case Op::SetLoopCounter: case Op::SetDisplay: case Op::SendMessage: case Op::DatalogNext:
    case Op::GetValue:
      return source_text(v[0], v[1]);
    case Op::TestAndBranchNear: case Op::TestAndBranchFar: {
      static constexpr const char* kCompare[] = {"<=", ">=", "!=", "=="};
      return fmt::format("{} {} {}, {}", source_text(v[0] & 0x0f, v[2]), kCompare[(v[0] >> 6) & 3],
                         source_text(v[1], v[3]), d.target);
    }
    case Op::BranchAlwaysNear: case Op::BranchAlwaysFar: case Op::DecrementLoopCounterNear:
    case Op::DecrementLoopCounterFar:
      return std::to_string(d.target);
    default: break;
  }
  if (auto download = download_operands(d)) return *download;
  return numbered_operands(d);
}

// A LASM label: the fragment's kind and number, and the address.
std::string lasm_label(rcx::FragmentType type, int index, int address) {
  return fmt::format("{}{:03}{:04}", type == rcx::FragmentType::Task ? 't' : 's', index, address);
}

// The operand fields as LASM takes them: numbers, where the bytes pack two
// fields in one (direction and outputs, mode and slope, comparison and
// source) each on its own, and the test's operands in the SDK's order.
std::string lasm_operands(const rcx::Decoded& d, const std::string& target) {
  const auto& v = d.v;
  using rcx::Op;
  switch (d.op) {
    case Op::SetMotorOnOff: return fmt::format("{}, {}", v[0] & 0x07, (v[0] >> 6) & 3);
    case Op::SetMotorDirection: return fmt::format("{}, {}", (v[0] >> 6) & 3, v[0] & 0x07);
    case Op::SetSensorMode: return fmt::format("{}, {}, {}", v[0], (v[1] >> 5) & 7, v[1] & 0x1f);
    case Op::TestAndBranchNear: case Op::TestAndBranchFar:
      return fmt::format("{}, {}, {}, {}, {}, {}", v[0] & 0x0f, v[2], (v[0] >> 6) & 3, v[1], v[3], target);
    default: break;
  }
  if (rcx::is_branch(d.op)) return target;
  if (auto download = download_operands(d)) return *download;
  return numbered_operands(d);
}

// The instruction at `address`, or the request an asm block put there,
// which nqc lists by name too (error 0 here: it is listed like the rest).
rcx::Decoded decode_listed(const std::vector<std::uint8_t>& code, int address) {
  rcx::Decoded d = rcx::decode_command(code, address);
  if (d.error != static_cast<std::uint8_t>(rcx::DecodeError::NotACommand)) return d;
  auto request = rcx::decode_request(code, address);
  if (!request || request->error != static_cast<std::uint8_t>(rcx::DecodeError::NotACommand)) return d;
  request->error = 0;
  return *request;
}

// Bytes nqc cannot name are listed one at a time as `?`.
bool nameable(const rcx::Decoded& d) { return d.error == 0 && !rcx::info(d.op).nqc_mnemonic.empty(); }

// The line of the instruction at `address`; `size` gets how many bytes it
// listed.
std::string line_text(const std::vector<std::uint8_t>& code, int address, int& size) {
  rcx::Decoded d = decode_listed(code, address);
  std::string mnemonic, operands;
  size = 1;
  if (nameable(d)) {
    mnemonic = rcx::info(d.op).nqc_mnemonic;
    operands = operands_text(d);
    size = d.size;
  } else {
    mnemonic = "?";  // as nqc: one byte it cannot name
  }
  std::string line = fmt::format("{:03} {:<8} {:<33} ", address, mnemonic, operands);
  for (int i = 0; i < size && address + i < static_cast<int>(code.size()); ++i)
    line += fmt::format("{:02x} ", code[static_cast<std::size_t>(address + i)]);
  return line;
}

// A fragment in LASM's layout: a label before every branch target.
std::string lasm_fragment(const rcx::Fragment& frag, const SourceLineAt& source_line) {
  const auto& code = frag.code;
  // A branch may target the end: the task's or subroutine's own end.
  std::vector<bool> targeted(code.size() + 1, false);
  for (int address = 0; address < static_cast<int>(code.size());) {
    rcx::Decoded d = decode_listed(code, address);
    if (!nameable(d)) {
      ++address;
      continue;
    }
    if (rcx::is_branch(d.op) && d.target >= 0 && d.target <= static_cast<int>(code.size()))
      targeted[static_cast<std::size_t>(d.target)] = true;
    address += d.size;
  }
  std::string text;
  for (int address = 0; address < static_cast<int>(code.size());) {
    if (source_line)
      if (std::string line = source_line(frag.type, frag.index, address); !line.empty()) text += line + "\n";
    if (targeted[static_cast<std::size_t>(address)])
      text += lasm_label(frag.type, frag.index, address) + ":\n";
    rcx::Decoded d = decode_listed(code, address);
    if (!nameable(d)) {
      // nqc 3.1 stops listing here and never ends; a comment keeps the
      // text an assembler can read.
      text += fmt::format("\t; {:02x}: not an instruction\n", code[static_cast<std::size_t>(address)]);
      ++address;
      continue;
    }
    text += fmt::format("\t{}\t{} \n", rcx::info(d.op).nqc_mnemonic,
                        lasm_operands(d, lasm_label(frag.type, frag.index, d.target)));
    address += d.size;
  }
  if (targeted.back()) text += lasm_label(frag.type, frag.index, static_cast<int>(code.size())) + ":\n";
  return text;
}

std::string lasm_listing(const rcx::Image& image, const std::vector<const rcx::Fragment*>& order,
                         const SourceLineAt& source_line) {
  std::string text;
  for (const auto& s : image.symbols)
    if (s.type == rcx::SymbolType::Variable) text += fmt::format("; Var {} = {}\n", s.index, rcx::printable_name(s.name));
  std::size_t total = 0;
  for (const rcx::Fragment* frag : order) {
    bool task = frag->type == rcx::FragmentType::Task;
    std::string name = rcx::printable_name(image.name_of(task ? rcx::SymbolType::Task : rcx::SymbolType::Subroutine,
                                                         frag->index));
    text += fmt::format("\n; {} {} = {}, size: {} bytes\n;{}\n\t{}\t{}\n", task ? "Task" : "Sub", frag->index, name,
                        frag->code.size(), name, task ? "task" : "sub", frag->index);
    text += lasm_fragment(*frag, source_line);
    text += task ? "\tendt\n" : "\tends\n";
    total += frag->code.size();
  }
  text += fmt::format("\n;Total size: {} bytes\n", total);
  return text;
}

}  // namespace

std::string nqc_listing(const rcx::Image& image, const SourceLineAt& source_line, ListingStyle style) {
  std::vector<const rcx::Fragment*> order;
  for (const auto& f : image.fragments) order.push_back(&f);
  std::stable_sort(order.begin(), order.end(), [](const rcx::Fragment* a, const rcx::Fragment* b) {
    return std::pair(a->type != rcx::FragmentType::Task, a->index) < std::pair(b->type != rcx::FragmentType::Task, b->index);
  });
  if (style == ListingStyle::Lasm) return lasm_listing(image, order, source_line);
  std::string text;
  for (const auto& s : image.symbols)
    if (s.type == rcx::SymbolType::Variable) text += fmt::format("*** Var {} = {}\n", s.index, rcx::printable_name(s.name));
  std::size_t total = 0;
  for (const rcx::Fragment* frag : order) {
    bool task = frag->type == rcx::FragmentType::Task;
    auto symbol_type = task ? rcx::SymbolType::Task : rcx::SymbolType::Subroutine;
    text += fmt::format("\n*** {} {} = {}, size: {} bytes\n", task ? "Task" : "Sub", frag->index,
                        rcx::printable_name(image.name_of(symbol_type, frag->index)), frag->code.size());
    int address = 0;
    while (address < static_cast<int>(frag->code.size())) {
      if (source_line)
        if (std::string line = source_line(frag->type, frag->index, address); !line.empty()) text += line + "\n";
      int size = 1;
      text += line_text(frag->code, address, size) + "\n";
      address += size;
    }
    total += frag->code.size();
  }
  text += fmt::format("\nTotal size: {} bytes\n", total);
  return text;
}

std::string nqc_listing(const Output& out, const SourceManager* sm, ListingStyle style) {
  if (!sm) return nqc_listing(out.image, {}, style);
  // For each fragment, the line to print above an address: only where the
  // line changes, as nqc does.
  std::map<std::tuple<rcx::FragmentType, int, int>, std::string> lines;
  for (const auto& frag : out.fragments) {
    std::uint32_t last_file = 0, last_line = 0;
    for (const auto& in : frag.instrs) {
      const auto& at = in.span.begin;
      if (!at.valid() || at.file >= sm->size() || (at.file == last_file && at.line == last_line)) continue;
      last_file = at.file;
      last_line = at.line;
      lines[{frag.type, frag.index, in.address}] = std::string(sm->line(at.file, at.line));
    }
  }
  return nqc_listing(
      out.image,
      [&](rcx::FragmentType type, int index, int address) {
        auto it = lines.find({type, index, address});
        return it == lines.end() ? std::string() : it->second;
      },
      style);
}

}  // namespace rcxc::backend
