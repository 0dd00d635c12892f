#include "backend/listing.h"

#include <fmt/format.h>

#include "backend/disasm.h"

namespace rcxc::backend {

std::string listing(const Output& out, const SourceManager* sm) {
  std::string text;
  for (const auto& s : out.image.symbols)
    if (s.type == rcx::SymbolType::Variable) text += fmt::format("var {} = {}\n", s.index, s.name);
  if (!text.empty()) text += "\n";
  for (const auto& frag : out.fragments) {
    bool task = frag.type == rcx::FragmentType::Task;
    text += fmt::format("{} {} {} ({} bytes)\n", task ? "task" : "sub", frag.index, frag.name, frag.code.size());
    std::uint32_t last_file = 0, last_line = 0;
    for (const auto& in : frag.instrs) {
      const auto& at = in.span.begin;
      if (sm && at.valid() && at.file < sm->size() && (at.file != last_file || at.line != last_line)) {
        last_file = at.file;
        last_line = at.line;
        text += fmt::format("      // {}:{}: {}\n", sm->path(at.file), at.line, sm->line(at.file, at.line));
      }
      Instruction ins = format_instruction(frag.code, in.address);
      text += format_line(frag.code, ins) + "\n";
    }
    text += "\n";
  }
  text += fmt::format("total: {} bytes of code, {} variable slot{}\n", out.code_bytes, out.slots_used,
                      out.slots_used == 1 ? "" : "s");
  return text;
}

}  // namespace rcxc::backend
