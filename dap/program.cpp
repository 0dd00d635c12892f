#include "dap/program.h"

#include <algorithm>
#include <filesystem>

#include "backend/compile.h"
#include "frontend/parse.h"
#include "ir/lower.h"
#include "rcx/opcodes.h"

namespace rcxc::dap {
namespace {

std::string normal_path(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::absolute(path, ec);
  if (ec) p = path;
  return p.lexically_normal().string();
}

// Where the user's text is: a token from a macro's body counts at the
// macro's use, and the standard library's text at no place of the user's.
Place user_place(SourceLoc loc, const SourceManager& sm) {
  for (int guard = 0; loc.expansion != 0 && guard < 1000; ++guard) {
    if (loc.expansion > sm.expansion_count()) return {};
    loc = sm.expansion(loc.expansion).site.begin;
  }
  if (!loc.valid() || loc.file >= sm.size() || sm.is_library(loc.file)) return {};
  return {static_cast<int>(loc.file), static_cast<int>(loc.line)};
}

bool inside(const SourceLoc& at, const SourceLoc& begin, const SourceLoc& end) {
  return at.file == begin.file && at.file == end.file && !before(at, begin) && before(at, end);
}

struct Extent {
  std::string name;
  SourceLoc begin, end;
};

// The tasks' and subroutines' text, from their names to their closing braces.
std::vector<Extent> extents(const ast::Program& program) {
  std::vector<Extent> out;
  for (const auto& t : program.tasks) out.push_back({t.name, t.span.begin, t.body.span.end});
  for (const auto& s : program.subs) out.push_back({s.name, s.span.begin, s.body.span.end});
  return out;
}

// The slot of every variable, as backend::compile chose them: the same
// passes and allocation run on a copy. Trusted only if it names the slots
// exactly as the image's symbols do (it would not for -Os's rerolled code).
struct Slots {
  std::vector<int> of;          // by VarId
  std::vector<ir::Var> vars;    // the declarations, by VarId
};
std::optional<Slots> slots_of(ir::Program copy, ir::OptLevel level, const rcx::Image& image) {
  Diagnostics scratch;
  ir::Log log;
  if (!ir::optimize(copy, level, scratch, log)) return std::nullopt;
  std::vector<int> slots = ir::allocate_slots(copy, scratch);
  if (scratch.has_errors()) return std::nullopt;
  std::vector<std::pair<int, std::string>> named, expected;
  std::vector<bool> taken(32, false);
  for (std::size_t v = 0; v < copy.vars.size() && v < slots.size(); ++v) {
    int s = slots[v];
    if (s < 0 || s >= 32 || taken[static_cast<std::size_t>(s)] || copy.vars[v].name.empty() ||
        copy.vars[v].kind == ir::VarKind::Temp)
      continue;
    taken[static_cast<std::size_t>(s)] = true;
    named.emplace_back(s, copy.vars[v].name);
  }
  for (const auto& sym : image.symbols)
    if (sym.type == rcx::SymbolType::Variable) expected.emplace_back(sym.index, sym.name);
  if (named != expected) return std::nullopt;
  return Slots{std::move(slots), std::move(copy.vars)};
}

}  // namespace

const FragmentLines* DebugProgram::fragment(int task, int sub) const {
  bool want_task = sub < 0;
  int index = want_task ? task : sub;
  for (const auto& f : fragments)
    if ((f.type == rcx::FragmentType::Task) == want_task && f.index == index) return &f;
  return nullptr;
}

Place DebugProgram::place_at(const FragmentLines& f, int pc) const {
  auto it = std::upper_bound(f.addresses.begin(), f.addresses.end(), pc);
  if (it == f.addresses.begin() || pc >= f.code_size) return f.end;
  return f.places[static_cast<std::size_t>(it - f.addresses.begin() - 1)];
}

bool DebugProgram::starts_statement(const FragmentLines& f, int pc) const {
  if (pc >= f.code_size) return true;
  auto it = std::lower_bound(f.addresses.begin(), f.addresses.end(), pc);
  return it != f.addresses.end() && *it == pc && f.starts[static_cast<std::size_t>(it - f.addresses.begin())];
}

int DebugProgram::file_index(const std::string& path) const {
  std::string want = normal_path(path);
  for (std::size_t i = 0; i < files.size(); ++i)
    if (files[i] == want) return static_cast<int>(i);
  return -1;
}

CompileOutcome compile_for_debug(const std::string& path, const frontend::Options& options, ir::OptLevel level) {
  SourceManager sm;
  Diagnostics diags;
  CompileOutcome out;
  std::optional<backend::Output> code;
  std::vector<Extent> bodies;
  std::optional<ir::Program> lowered_copy;
  {
    auto parsed = frontend::parse_program(path, options, sm, diags);
    if (parsed) {
      bodies = extents(*parsed);
      if (auto lowered = ir::lower(*parsed, diags)) {
        lowered_copy = *lowered;
        ir::Log log;
        code = backend::compile(std::move(*lowered), level, diags, log);
      }
    }
  }
  out.messages = render_all(diags, sm, RenderOptions{});
  if (!code || diags.has_errors()) return out;

  DebugProgram p;
  p.image = code->image;
  for (std::size_t i = 0; i < sm.size(); ++i) p.files.push_back(normal_path(sm.path(static_cast<std::uint32_t>(i))));
  for (const auto& b : bodies) {
    Function fn;
    fn.name = b.name;
    fn.begin = user_place(b.begin, sm);
    fn.end = user_place(b.end, sm);
    p.functions.push_back(std::move(fn));
  }
  for (const auto& frag : code->fragments) {
    FragmentLines f;
    f.type = frag.type;
    f.index = frag.index;
    f.name = frag.name;
    f.code_size = static_cast<int>(frag.code.size());
    for (std::size_t i = 0; i < p.functions.size(); ++i)
      if (p.functions[i].name == frag.name) f.function = static_cast<int>(i);
    for (const auto& in : frag.instrs) {
      f.addresses.push_back(in.address);
      f.places.push_back(user_place(in.span.begin, sm));
    }
    // Library and line-less instructions belong to the statement before
    // them (leading ones to the first that has a line).
    Place last;
    for (auto& place : f.places) {
      if (place.valid()) last = place; else place = last;
    }
    auto first = std::find_if(f.places.begin(), f.places.end(), [](const Place& q) { return q.valid(); });
    if (first != f.places.end()) std::fill(f.places.begin(), first, *first);
    for (std::size_t i = 0; i < f.places.size(); ++i) f.starts.push_back(i == 0 || !(f.places[i] == f.places[i - 1]));
    // A loop's jump back is placed at a line of the loop (`repeat`'s at the
    // body's last line): as a start of its own, a breakpoint there would
    // stop twice an iteration and `next` would show the line again before
    // the loop's head. A lone jump is a statement only where its line has
    // no other start (`break;`, `continue;`).
    auto lone_jump = [&](std::size_t i) {
      if (!f.starts[i] || (i + 1 < f.places.size() && !f.starts[i + 1])) return false;
      const auto& bytes = frag.instrs[i].bytes;
      const rcx::OpcodeInfo* op = bytes.empty() ? nullptr : rcx::command_at(bytes[0]);
      return op && (op->op == rcx::Op::BranchAlwaysNear || op->op == rcx::Op::BranchAlwaysFar);
    };
    std::vector<bool> lone(f.places.size());
    for (std::size_t i = 0; i < f.places.size(); ++i) lone[i] = lone_jump(i);
    for (std::size_t i = 0; i < f.places.size(); ++i) {
      if (!lone[i]) continue;
      for (std::size_t j = 0; j < f.places.size(); ++j)
        if (j != i && f.starts[j] && !lone[j] && f.places[j] == f.places[i]) {
          f.starts[i] = false;
          break;
        }
    }
    f.end = f.function >= 0 && p.functions[static_cast<std::size_t>(f.function)].end.valid()
                ? p.functions[static_cast<std::size_t>(f.function)].end
                : (f.places.empty() ? Place{} : f.places.back());
    p.fragments.push_back(std::move(f));
  }

  auto slots = lowered_copy ? slots_of(std::move(*lowered_copy), level, p.image) : std::nullopt;
  if (!slots) {
    // Only what the image says: every named slot, as a global.
    p.slots_exact = false;
    for (const auto& sym : p.image.symbols)
      if (sym.type == rcx::SymbolType::Variable) p.globals.push_back({sym.name, sym.index});
  } else {
    for (std::size_t v = 0; v < slots->vars.size() && v < slots->of.size(); ++v) {
      const auto& var = slots->vars[v];
      int s = slots->of[v];
      if (s < 0 || var.name.empty() || var.kind == ir::VarKind::Temp) continue;
      if (var.kind == ir::VarKind::Global) {
        p.globals.push_back({var.name, s});
        continue;
      }
      for (std::size_t b = 0; b < bodies.size(); ++b)
        if (inside(var.span.begin, bodies[b].begin, bodies[b].end)) p.functions[b].locals.push_back({var.name, s});
    }
  }
  std::sort(p.globals.begin(), p.globals.end(), [](const Variable& a, const Variable& b) { return a.name < b.name; });
  out.program = std::move(p);
  return out;
}

}  // namespace rcxc::dap
