// Instructions and blocks name their place in the source by a SpanId into
// the Program's table (ir.h): lowering adds a statement's span once and
// every instruction it lowers to shares it. Diagnostics and listings read
// the place back through the table, so each instruction must still lead to
// its own statement's line.
#include <gtest/gtest.h>

#include <set>

#include "frontend/frontend.h"
#include "ir/lower.h"

namespace rcxc::ir {
namespace {

TEST(Spans, EachInstructionLeadsToItsStatementsLine) {
  SourceManager sm;
  Diagnostics diags;
  auto ast = frontend::parse_source("spans.nqc", "int x, y;\ntask main() {\n  x = 1;\n  y = x * 3 + 2;\n  x = y;\n}\n", {},
                                    sm, diags);
  ASSERT_TRUE(ast);
  auto p = lower(*ast, diags);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->span(0).begin.line, 0u);  // 0: no place
  const Function& main = p->functions[static_cast<std::size_t>(p->find_function("main"))];
  std::set<std::uint32_t> lines;
  std::set<SpanId> ids_of_line_4;
  for (const Block& b : main.blocks)
    for (const Instr& in : b.instrs) {
      std::uint32_t line = p->span(in.span).begin.line;
      lines.insert(line);
      if (line == 4) ids_of_line_4.insert(in.span);
    }
  // Line 2: main's startup code, which the task's heading stands for.
  EXPECT_EQ(lines, (std::set<std::uint32_t>{2, 3, 4, 5}));
  // y = x * 3 + 2 is three instructions of one statement: one span.
  EXPECT_EQ(ids_of_line_4.size(), 1u);
}

}  // namespace
}  // namespace rcxc::ir
