// compute_liveness solves the data-flow equations one variable at a time
// from each block's summary (what it reads first, what it overwrites). The
// result must satisfy
// the data-flow equations as stepping back through every instruction
// (step_back, which the passes use inside a block) states them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
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

// A long function has more first reads than the comparison sort takes
// (sort_keys): its keys go through the digit passes, whose order the
// equations then depend on.
TEST(Liveness, BlockSummariesMeetTheEquationsInALongFunction) {
  std::string text = "int g;\nvoid step(int n, int &total) { int k = n * 2; if (k > 3) total += k; else total -= n; }\n"
                     "task main() {\n  int local = 1, count = 0;\n";
  for (int i = 0; i < 600; ++i)
    text += "  step(local, count); if (count > " + std::to_string(i) + ") local++; else g = local;\n";
  expect_equations_hold("long.nqc", text + "}\n");
}

// Checked against std::sort on random keys: lists of each size around the
// switch from comparison to digits, of widths that leave a digit unused or
// split one, with repeated keys and with keys sharing their high digits
// (whose passes move nothing).
TEST(SortKeys, SortsAsAComparisonSortDoes) {
  std::mt19937_64 rng(7);
  for (std::size_t size : {std::size_t{0}, std::size_t{1}, std::size_t{1024}, std::size_t{1025}, std::size_t{5000},
                           std::size_t{70000}})
    for (unsigned bits : {1u, 11u, 12u, 33u, 63u, 64u}) {
      const std::uint64_t mask = bits == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
      std::vector<std::uint64_t> keys(size);
      for (auto& k : keys) k = rng() & mask;
      if (size > 2) keys[size / 2] = keys[1];
      std::vector<std::uint64_t> expected = keys;
      std::sort(expected.begin(), expected.end());
      sort_keys(keys, bits);
      EXPECT_EQ(keys, expected) << size << " keys of " << bits << " bits";
      // Only the low digits vary: the high ones are all the same.
      for (auto& k : keys) k = (mask & ~std::uint64_t{0x7ff}) | (rng() & 0x7ff & mask);
      expected = keys;
      std::sort(expected.begin(), expected.end());
      sort_keys(keys, bits);
      EXPECT_EQ(keys, expected) << size << " keys of " << bits << " bits, high digits shared";
    }
}

std::optional<Program> lowered(const std::string& text) {
  SourceManager sm;
  Diagnostics diags;
  auto ast = frontend::parse_source("cache.nqc", text, {}, sm, diags);
  if (!ast) return std::nullopt;
  return lower(*ast, diags);
}

// Whether two liveness results agree on every block.
bool same_liveness(const Liveness& a, const Liveness& b, std::size_t blocks) {
  for (std::size_t i = 0; i < blocks; ++i)
    if (VarSet(a.live_in[i]) != VarSet(b.live_in[i]) || VarSet(a.live_out[i]) != VarSet(b.live_out[i])) return false;
  return true;
}

// The cache must answer what computing afresh answers, after every kind of
// change a pass makes: an instruction removed, an operand rewritten, a
// branch retargeted. It must also compute nothing when nothing changed.
TEST(LivenessCache, AnswersWhatComputingAnswersAfterEachChange) {
  int stale_would_differ = 0;
  for (unsigned seed = 1; seed <= 30; ++seed) {
    for (const std::string& text : {test::Generator(seed).program(), test::KeptLocalGenerator(seed).program(),
                                    test::CallNeighbourGenerator(seed).program()}) {
      auto program = lowered(text);
      ASSERT_TRUE(program);
      Program& p = *program;
      CallEffects calls = call_effects(p);
      LivenessCache cache;
      for (Function& f : p.functions) {
        if (f.blocks.empty()) continue;
        const std::size_t n = f.blocks.size();
        ASSERT_TRUE(same_liveness(cache.of(p, f, calls), compute_liveness(p, f, calls), n));
        std::size_t computed = cache.computations();
        ASSERT_TRUE(same_liveness(cache.of(p, f, calls), compute_liveness(p, f, calls), n));
        EXPECT_EQ(cache.computations(), computed) << "nothing changed, yet it computed again";
        // A constant changes no liveness: folding rewrites them all the time.
        for (Block& block : f.blocks)
          for (Instr& in : block.instrs)
            for (Operand& a : in.args)
              if (a.is_imm()) a.value += 1;
        ASSERT_TRUE(same_liveness(cache.of(p, f, calls), compute_liveness(p, f, calls), n));
        EXPECT_EQ(cache.computations(), computed) << "only constants changed, yet it computed again";
        // Each change in turn; after each the cache must agree with a
        // fresh computation (and a stale answer must have been possible).
        for (std::size_t b = 0; b < n; ++b) {
          Block& block = f.blocks[b];
          Liveness before = compute_liveness(p, f, calls);
          if (!block.instrs.empty()) {
            block.instrs.erase(block.instrs.begin());
          } else if (auto* br = std::get_if<Branch>(&block.term)) {
            std::swap(br->a, br->b);
            br->then = 0;
          } else {
            continue;
          }
          Liveness after = compute_liveness(p, f, calls);
          stale_would_differ += !same_liveness(before, after, n);
          ASSERT_TRUE(same_liveness(cache.of(p, f, calls), after, n)) << "seed " << seed << " block " << b;
        }
      }
    }
  }
  EXPECT_GT(stale_would_differ, 100);
}

// What a call does is part of the answer: other call effects for the same
// code must not be answered from the cache.
TEST(LivenessCache, OtherCallEffectsAreComputedAgain) {
  auto program = lowered(
      "int g;\n"
      "sub s() { g = 1; }\n"
      "task main() { int a = Random(5); int b = a + 1; if (Random(1) == 0) { s(); } g = a + b; }\n");
  ASSERT_TRUE(program);
  Program& p = *program;
  FuncId main = p.find_function("main");
  ASSERT_GE(main, 0);
  const Function& f = p.functions[static_cast<std::size_t>(main)];
  CallEffects calls = call_effects(p);
  LivenessCache cache;
  Liveness plain = cache.of(p, f, calls);
  // Pretend the subroutine overwrote every local of main: none of them is
  // then live across the call.
  CallEffects clobbering = calls;
  FuncId s = p.find_function("s");
  ASSERT_GE(s, 0);
  for (std::size_t v = 0; v < p.vars.size(); ++v)
    if (p.vars[v].kind != VarKind::Global) clobbering.touches[static_cast<std::size_t>(s)].add(static_cast<VarId>(v));
  Liveness fresh = compute_liveness(p, f, clobbering);
  ASSERT_FALSE(same_liveness(plain, fresh, f.blocks.size()));
  EXPECT_TRUE(same_liveness(cache.of(p, f, clobbering), fresh, f.blocks.size()));
  EXPECT_EQ(cache.computations(), 2u);
}

}  // namespace
}  // namespace rcxc::ir
