// compute_liveness solves the data-flow equations one variable at a time
// from each block's summary (what it reads first, what it overwrites). The
// result must satisfy
// the data-flow equations as stepping back through every instruction
// (step_back, which the passes use inside a block) states them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "frontend/frontend.h"
#include "ir/liveness.h"
#include "ir/lower.h"
#include "tests/support/random_programs.h"

namespace rcxc::ir {
namespace {

namespace fs = std::filesystem;

// For every block: live-out is what its successors need (and, at an exit,
// what the function's entry needs: the next run reads it), and live-in is
// live-out stepped back through the terminator's reads and each instruction.
void expect_equations_hold(const std::string& name, const std::string& text) {
  SourceManager sm;
  Diagnostics diags;
  auto ast = frontend::parse_source(name, text, {}, sm, diags);
  if (!ast) return;  // the error tests: nothing to lower
  auto program = lower(*ast, diags);
  if (!program) return;
  CallEffects calls = call_effects(*program);
  for (const Function& f : program->functions) {
    if (f.blocks.empty()) continue;
    Liveness L = compute_liveness(*program, f, calls);
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      const Block& block = f.blocks[b];
      VarSet out;
      for (BlockId s : successors(block.term)) out.merge(L.live_in[static_cast<std::size_t>(s)]);
      if (std::holds_alternative<Exit>(block.term)) out.merge(L.live_in[0]);
      EXPECT_EQ(out, VarSet(L.live_out[b])) << name << " " << f.name << " block " << b;
      VarSet live = out;
      for (VarId v : reads_of(block.term))
        if (program->vars[static_cast<std::size_t>(v)].kind != VarKind::Global) live.add(v);
      for (std::size_t k = block.instrs.size(); k-- > 0;) step_back(*program, block.instrs[k], calls, live);
      EXPECT_EQ(live, VarSet(L.live_in[b])) << name << " " << f.name << " block " << b;
    }
  }
}

TEST(Liveness, BlockSummariesMeetTheEquationsOnEverySemanticTest) {
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(RCXC_SOURCE_DIR) / "tests/semantic")) {
    if (!e.is_regular_file() || e.path().extension() != ".nqc") continue;
    std::ifstream in(e.path(), std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    expect_equations_hold(e.path().string(), s.str());
    ++n;
  }
  EXPECT_GT(n, 300);
}

TEST(Liveness, BlockSummariesMeetTheEquationsOnRandomPrograms) {
  for (unsigned seed = 1; seed <= 40; ++seed) {
    expect_equations_hold("random.nqc", test::Generator(seed).program());
    expect_equations_hold("kept_locals.nqc", test::KeptLocalGenerator(seed).program());
    expect_equations_hold("neighbours.nqc", test::CallNeighbourGenerator(seed).program());
  }
}

}  // namespace
}  // namespace rcxc::ir
