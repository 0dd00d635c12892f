// Compiling a program text and running its image on the emulator, for the
// backend tests that check a transformation by what the program then does.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

#include "backend/compile.h"
#include "verify/compare.h"
#include "runtime/vm.h"

namespace rcxc::test {

struct Compiled {
  std::optional<backend::Output> out;
  ir::Log log;  // what -v would print
};

// Compiles with the RCX API; a program with errors fails the calling test.
inline Compiled compile_program(const std::string& text, ir::OptLevel level = ir::OptLevel::Os) {
  Compiled c;
  SourceManager sm;
  Diagnostics diags;
  c.out = backend::compile_source("test.nqc", text, frontend::Options{}, level, sm, diags, c.log);
  EXPECT_FALSE(diags.has_errors());
  return c;
}

// Whether some line of the log contains `text`.
inline bool logged(const ir::Log& log, std::string_view text) {
  return std::any_of(log.begin(), log.end(), [&](const std::string& l) { return l.find(text) != l.npos; });
}

// Runs program 1's image for `ms` of brick time.
inline rcx::Machine run_image(const rcx::Image& image, std::int64_t ms, std::uint64_t seed = 1) {
  rcx::Machine m(rcx::Config{.seed = seed});
  EXPECT_FALSE(m.load(0, image).has_value());
  m.start_program();
  m.run(ms * rcx::kMicrosPerMs);
  return m;
}

// A global's value by name, through the image's symbols.
inline int global_value(const rcx::Machine& m, const rcx::Image& image, const std::string& name) {
  for (const auto& s : image.symbols)
    if (s.type == rcx::SymbolType::Variable && s.name == name) return m.state().vars[s.index];
  ADD_FAILURE() << "no variable " << name;
  return 0;
}

// Compiles `src` at -Os and -O1 and expects the runs to match, as `rcxc
// compare` judges them, for random seeds 1..seeds. Returns the -Os result.
inline Compiled expect_same_as_o1(const std::string& src, int seeds = 1, std::int64_t ms = 20'000) {
  auto os = compile_program(src);
  auto o1 = compile_program(src, ir::OptLevel::O1);
  EXPECT_TRUE(os.out && o1.out);
  if (!os.out || !o1.out) return os;
  for (int seed = 1; seed <= seeds; ++seed) {
    auto a = run_image(os.out->image, ms, static_cast<std::uint64_t>(seed));
    auto b = run_image(o1.out->image, ms, static_cast<std::uint64_t>(seed));
    auto cmp = rcx::compare_runs({&a, &os.out->image, "-Os"}, {&b, &o1.out->image, "-O1"});
    EXPECT_TRUE(cmp.same) << "seed " << seed << "\n" << cmp.side_by_side;
  }
  return os;
}

}  // namespace rcxc::test
