// What a task watching a random program's globals could see: every value
// each global takes in a run, for the tests that hold rcxc's code to
// showing, with another task running, only values nqc's code also gives
// a global (the steps of a computation in place included; a task waiting
// for a value would otherwise act where nqc's code never does).
#pragma once

#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace rcxc::test {

// Whether `name` is declared on the program's first line (`int a, b;`):
// the generated programs' globals. Locals and parameters also name slots,
// but what they hold is nobody's business.
inline bool is_global(const std::string& text, const std::string& name) {
  std::string first = text.substr(0, text.find('\n'));
  for (char& ch : first)
    if (ch == ',' || ch == ';') ch = ' ';
  std::istringstream words(first);
  std::string w;
  while (words >> w)
    if (w == name) return true;
  return false;
}

// The slots of the program's globals in `image`, with their names.
inline std::map<int, std::string> global_slots(const rcx::Image& image, const std::string& text) {
  std::map<int, std::string> names;
  for (const auto& sym : image.symbols)
    if (sym.type == rcx::SymbolType::Variable && is_global(text, sym.name)) names[sym.index] = sym.name;
  return names;
}

// The program with a second task started first, which only waits: with
// it, another task could watch every global between any two of main's
// instructions, and the compilers treat the globals as shared.
inline std::string with_a_watching_task(const std::string& text) {
  std::string out = text;
  std::size_t line_end = out.find('\n');
  out.insert(line_end + 1, "task watcher() { while (true) Wait(100); }\n");
  const std::string main_head = "task main() {";
  std::size_t at = out.find(main_head);
  if (at != std::string::npos) out.insert(at + main_head.size(), " start watcher;");
  return out;
}

// Each global's values, as 20 s of a run of `image` wrote them, by name;
// nothing when the brick refuses the image (nqc's code for a long program
// can outgrow the memory rcxc's fits in, and an empty run would make every
// value of the other side look foreign).
inline std::optional<std::map<std::string, std::set<int>>> values_written(const rcx::Image& image,
                                                                          const std::string& text) {
  rcx::Config config;
  config.trace_variables = true;
  rcx::Machine m(config);
  std::map<std::string, std::set<int>> seen;
  if (m.load(0, image)) return std::nullopt;
  m.start_program();
  m.run(20'000 * rcx::kMicrosPerMs);
  const auto names = global_slots(image, text);
  for (const auto& e : m.state().events)
    if (auto it = names.find(e.index); e.kind == rcx::EventKind::Variable && it != names.end())
      seen[it->second].insert(e.value);
  return seen;
}

// The values rcxc's run gave a global that nqc's never did, by global
// ("g: -13 4; h: 7"), or "".
inline std::string foreign_values(const std::map<std::string, std::set<int>>& ours,
                                  const std::map<std::string, std::set<int>>& nqcs) {
  std::string foreign;
  for (const auto& [name, values] : ours) {
    auto theirs = nqcs.find(name);
    std::string here;
    for (int v : values)
      if (theirs == nqcs.end() || !theirs->second.contains(v)) here += fmt::format(" {}", v);
    if (!here.empty()) foreign += fmt::format("{}{}:{}", foreign.empty() ? "" : "; ", name, here);
  }
  return foreign;
}

// foreign_values for rcxc's image `ours` run beside nqc's values.
inline std::string foreign_values(const rcx::Image& ours, const std::map<std::string, std::set<int>>& nqcs,
                                  const std::string& text) {
  auto values = values_written(ours, text);
  return values ? foreign_values(*values, nqcs) : "the brick refuses rcxc's image";
}

}  // namespace rcxc::test
