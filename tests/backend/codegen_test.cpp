// Code generation from hand-built IR. Expected bytes come from the seed's
// opcode layouts and offset formulas, checked against `nqc -Trcx -L`
// listings where nqc emits the same instruction.
#include <gtest/gtest.h>

#include "backend/branch.h"
#include "backend/codegen.h"
#include "backend/compile.h"
#include "tests/ir/ir_builder.h"
#include "tests/support/compiled.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;
using Bytes = std::vector<std::uint8_t>;

namespace {

Bytes code_of(const Program& p, const std::vector<int>& slots, std::size_t fragment = 0) {
  Diagnostics d;
  auto out = backend::generate(p, slots, d);
  EXPECT_TRUE(out.has_value());
  EXPECT_FALSE(d.has_errors());
  if (!out || out->fragments.size() <= fragment) return {};
  return out->fragments[fragment].code;
}

Bytes fill(std::size_t n) { return Bytes(n, 0x90); }
std::vector<Instr> fillers(std::size_t n) { return std::vector<Instr>(n, filler()); }
Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

}  // namespace

TEST(Codegen, PlainInstructionsThroughTheTable) {
  Builder b;
  VarId v = b.global("x");
  FuncId t = b.function("main");
  b.block(t, {set(v, I(4)), op(rcx::Op::SubtractFromVariable, {V(v), I(1)}), wait(I(100)), wait(V(v))});
  // nqc: setv var[0],4 = 14 00 02 04 00; subv = 34 00 02 01 00; wait 100 = 43 02 64 00
  EXPECT_EQ(code_of(b.p, {0}), (Bytes{0x14, 0x00, 0x02, 0x04, 0x00, 0x34, 0x00, 0x02, 0x01, 0x00, 0x43, 0x02, 0x64,
                                     0x00, 0x43, 0x00, 0x00, 0x00}));
}

TEST(Codegen, SourcePairsTakeTheirArgumentField) {
  Builder b;
  VarId v = b.global("x");
  FuncId t = b.function("main");
  // Set motor power: motors, source, argument (argument is one byte).
  b.block(t, {op(rcx::Op::SetMotorPower, {I(7), I(7)}), set(v, Operand::src(4, 100))});
  EXPECT_EQ(code_of(b.p, {3}), (Bytes{0x13, 0x07, 0x02, 0x07, 0x14, 0x03, 0x04, 0x64, 0x00}));
}

TEST(Codegen, JumpToNextBlockDisappears) {
  Builder b;
  FuncId t = b.function("main");
  b.block(t, {sound(1)}, Jump{1});
  b.block(t, {sound(2)});
  EXPECT_EQ(code_of(b.p, {}), (Bytes{0x51, 0x01, 0x51, 0x02}));
}

TEST(Codegen, BackwardJumpNear) {
  Builder b;
  FuncId t = b.function("main");
  b.block(t, {sound(1)}, Jump{1});
  b.block(t, fillers(14), Jump{1});
  // jmp at 16, offset byte at 17, target 2: 17 - off + 128 = 2 -> off = 143
  EXPECT_EQ(code_of(b.p, {}), cat({{0x51, 0x01}, fill(14), {0x27, 143}}));
}

TEST(Codegen, ForwardJumpNearFarBoundary) {
  // A jump over a body of N filler bytes plus the body's own 2-byte jump
  // back: offset byte at 1, target 2 + N + 2 (near) -> relative N + 3.
  for (std::size_t n : {123u, 124u, 125u, 126u}) {
    Builder b;
    FuncId t = b.function("main");
    b.block(t, {}, Jump{2});
    b.block(t, fillers(n), Jump{1});
    b.block(t, {sound(3)});
    Bytes code = code_of(b.p, {});
    if (n + 3 <= 127) {
      ASSERT_EQ(code[0], 0x27) << n;
      EXPECT_EQ(code[1], n + 3) << n;
    } else {
      // Far: 3 bytes, so the target moves to 3 + N + 2: relative N + 4.
      ASSERT_EQ(code[0], 0x72) << n;
      EXPECT_EQ(code[1] + 128 * code[2], static_cast<int>(n) + 4) << n;
      EXPECT_LT(code[1], 128) << n;
    }
  }
}

TEST(Codegen, BackwardTestAndBranchStaysNear) {
  // do { N filler bytes } while (x != 0): chk at N, offset field at N + 6.
  for (std::size_t n : {121u, 122u, 123u}) {
    Builder b;
    VarId x = b.global("x");
    FuncId t = b.function("main");
    b.block(t, fillers(n), Branch{Cmp::NE, V(x), I(0), 0, 1});
    b.block(t, {});
    Bytes code = code_of(b.p, {5});
    int rel = -static_cast<int>(n) - 6;
    if (rel >= -128) {
      // 85, opsrc1 = NE(2)<<6 | immediate, src2 = variable, arg1 = 0, arg2 = 5
      EXPECT_EQ(Bytes(code.begin() + static_cast<long>(n), code.end()),
                (Bytes{0x85, 0x82, 0x00, 0x00, 0x00, 0x05, static_cast<std::uint8_t>(rel & 0xff)}))
          << n;
    } else {
      EXPECT_EQ(Bytes(code.begin() + static_cast<long>(n), code.end()),
                (Bytes{0x95, 0x82, 0x00, 0x00, 0x00, 0x05, static_cast<std::uint8_t>(rel & 0xff),
                       static_cast<std::uint8_t>((rel >> 8) & 0xff)}))
          << n;
    }
  }
}

TEST(Codegen, StrictLessThanConstantBecomesLessEqual) {
  // do { } while (x < 2000): nqc emits chkl 1999 >= var, i.e. 42 00 cf 07 02.
  Builder b;
  VarId x = b.global("x");
  FuncId t = b.function("main");
  b.block(t, {sound(0)}, Branch{Cmp::LT, V(x), I(2000), 0, 1});
  b.block(t, {});
  Bytes code = code_of(b.p, {2});
  EXPECT_EQ(code, (Bytes{0x51, 0x00, 0x85, 0x42, 0x00, 0xcf, 0x07, 0x02, static_cast<std::uint8_t>(-8 & 0xff)}));
}

TEST(Codegen, StrictComparisonOfVariablesUsesTheNegation) {
  // if (x < y) A else B, A laid out next: branch to B when x >= y.
  Builder b;
  VarId x = b.global("x"), y = b.global("y");
  FuncId t = b.function("main");
  b.block(t, {}, Branch{Cmp::LT, V(x), V(y), 1, 2});
  b.block(t, {sound(1)}, Exit{});
  b.block(t, {sound(2)});
  Bytes code = code_of(b.p, {0, 1});
  // chk x >= y -> B: 85 (GE<<6|var)=0x40 00 00 00 01 off; then A, jmp end, B
  ASSERT_GE(code.size(), 7u);
  EXPECT_EQ(Bytes(code.begin(), code.begin() + 6), (Bytes{0x85, 0x40, 0x00, 0x00, 0x00, 0x01}));
  // A = sound 1 at 7, task exit jmp at 9 to end (13), B at 11.
  EXPECT_EQ(code[6], 11 - 6);
  EXPECT_EQ(Bytes(code.begin() + 7, code.end()), (Bytes{0x51, 0x01, 0x27, 0x03, 0x51, 0x02}));
}

TEST(Codegen, ConstantOnTheRightIsSwappedToTheLeft) {
  // if (SENSOR_1 == 1) A else B: nqc emits chk 1 != Input(0) -> B,
  // 85 82 09 01 00 00 off (NE<<6 | immediate, sensor value 0).
  Builder b;
  FuncId t = b.function("main");
  b.block(t, {}, Branch{Cmp::EQ, Operand::src(9, 0), I(1), 1, 2});
  b.block(t, {sound(1)});
  b.block(t, {sound(2)});
  Bytes code = code_of(b.p, {});
  // A at 7 (2 bytes), the task's exit jump at 9, B at 11: offset 11 - 6.
  EXPECT_EQ(code, (Bytes{0x85, 0x82, 0x09, 0x01, 0x00, 0x00, 0x05, 0x51, 0x01, 0x27, 0x03, 0x51, 0x02}));
}

TEST(Codegen, RepeatWithLoopCounter) {
  // nqc: loops 10 = 82 02 0a; loopc END = 37 off (from the offset byte);
  // body; jmp back to loopc.
  Builder b;
  FuncId t = b.function("main");
  b.block(t, {loopset(I(10))}, Jump{1});
  b.block(t, {}, LoopTest{0, 2, 3});
  b.block(t, {sound(1)}, Jump{1});
  b.block(t, {sound(2)});
  b.fn(t).repeats.push_back(Repeat{0, 1, false, true});
  // 0: 82 02 0a; 3: 37 off -> 9 (4 + 5); 5: 51 01; 7: 27 back to 3 (8 - off + 128 = 3 -> 133); 9: 51 02
  EXPECT_EQ(code_of(b.p, {}), (Bytes{0x82, 0x02, 0x0a, 0x37, 0x05, 0x51, 0x01, 0x27, 133, 0x51, 0x02}));
}

TEST(Codegen, EarlyExits) {
  Builder b;
  VarId x = b.global("x");
  FuncId t = b.function("main");
  FuncId s = b.function("helper", FuncKind::Sub);
  b.block(t, {call(s)}, Branch{Cmp::EQ, V(x), I(0), 1, 2});
  b.block(t, {}, Exit{});
  b.block(t, {sound(1)});
  b.block(s, {}, Branch{Cmp::EQ, V(x), I(0), 1, 2});
  b.block(s, {}, Exit{});
  b.block(s, {sound(1)});
  Diagnostics d;
  auto out = backend::generate(b.p, {0}, d);
  ASSERT_TRUE(out);
  ASSERT_EQ(out->fragments.size(), 2u);
  // Task: call 0 (17 00); chk 0 != x (NE, immediate 0, variable slot 0)
  // -> the sound at 11 (offset field at 8: 3); jmp to the end (13): the
  // offset byte at 10 + 3.
  EXPECT_EQ(out->fragments[0].code,
            (Bytes{0x17, 0x00, 0x85, 0x82, 0x00, 0x00, 0x00, 0x00, 0x03, 0x27, 0x03, 0x51, 0x01}));
  // Sub: the early exit is a return (f6); the final one is the firmware's.
  EXPECT_EQ(out->fragments[1].code[7], 0xf6);
  EXPECT_EQ(out->fragments[1].code.size(), 10u);
}

// if (x == 0) sound 1; else sound 2; in a subroutine laid out with the
// `then` side last: its jump past the other side to the empty exit block
// is a 1-byte return (f6), not a 2-byte jump. In a task it stays a jump.
TEST(Codegen, JumpToTheEndOfASubroutineIsAReturn) {
  Builder b;
  VarId x = b.global("x");
  FuncId t = b.function("main");
  FuncId s = b.function("helper", FuncKind::Sub);
  b.block(t, {call(s)}, Jump{1});
  b.block(t, {}, Branch{Cmp::EQ, V(x), I(0), 3, 2});
  b.block(t, {sound(2)}, Jump{4});
  b.block(t, {sound(1)}, Jump{4});
  b.block(t, {});
  b.block(s, {}, Branch{Cmp::EQ, V(x), I(0), 2, 1});
  b.block(s, {sound(2)}, Jump{3});
  b.block(s, {sound(1)}, Jump{3});
  b.block(s, {});
  Diagnostics d;
  auto out = backend::generate(b.p, {0}, d);
  ASSERT_TRUE(out);
  // Sub: chk 0 == x (0xc2) -> 10, the sound 1 side (offset byte at 6: 4);
  // sound 2; ret; sound 1, then the firmware's own return.
  EXPECT_EQ(out->fragments[1].code,
            (Bytes{0x85, 0xc2, 0x00, 0x00, 0x00, 0x00, 0x04, 0x51, 0x02, 0xf6, 0x51, 0x01}));
  // Task: call; the same test (to 13: offset byte at 8, 5); sound 2; a jump
  // to the end, 15 (offset byte at 12: 3); sound 1.
  EXPECT_EQ(out->fragments[0].code, (Bytes{0x17, 0x00, 0x85, 0xc2, 0x00, 0x00, 0x00, 0x00, 0x05, 0x51, 0x02, 0x27,
                                           0x03, 0x51, 0x01}));
}

TEST(Codegen, ImageHasFragmentsAndSymbols) {
  Builder b;
  VarId x = b.global("count");
  FuncId other = b.function("worker");
  FuncId main = b.function("main");
  FuncId s = b.function("beep", FuncKind::Sub);
  b.block(other, {call(s)});
  b.block(main, {start(other), set(x, I(1))});
  b.block(s, {sound(1)});
  Diagnostics d;
  auto out = backend::generate(b.p, {7}, d);
  ASSERT_TRUE(out);
  const auto& img = out->image;
  ASSERT_EQ(img.fragments.size(), 3u);
  EXPECT_EQ(img.find(rcx::FragmentType::Task, 0)->code, (Bytes{0x71, 0x01, 0x14, 0x07, 0x02, 0x01, 0x00}));
  EXPECT_EQ(img.find(rcx::FragmentType::Task, 1)->code, (Bytes{0x17, 0x00}));
  EXPECT_EQ(img.name_of(rcx::SymbolType::Task, 0), "main");
  EXPECT_EQ(img.name_of(rcx::SymbolType::Task, 1), "worker");
  EXPECT_EQ(img.name_of(rcx::SymbolType::Subroutine, 0), "beep");
  EXPECT_EQ(img.name_of(rcx::SymbolType::Variable, 7), "count");
  EXPECT_EQ(out->slots_used, 1);
}

TEST(Codegen, TooManyTasksIsADiagnostic) {
  Builder b;
  for (int i = 0; i < 11; ++i) b.block(b.function(i == 0 ? "main" : "t" + std::to_string(i)), {sound(0)});
  Diagnostics d;
  EXPECT_FALSE(backend::generate(b.p, {}, d));
  ASSERT_EQ(d.error_count(), 1u);
  EXPECT_NE(d.all()[0].message.find("11 tasks"), std::string::npos);
}

TEST(Codegen, HugeTaskIsADiagnosticNotACrash) {
  Builder b;
  FuncId t = b.function("main");
  b.block(t, std::vector<Instr>(7000, wait(I(1))));
  Diagnostics d;
  EXPECT_FALSE(backend::generate(b.p, {}, d));
  EXPECT_TRUE(d.has_errors());
}

TEST(Branch, FarJumpOffsetsFollowTheSeed) {
  // Backward 300: target = origin - off - 128*ext + 128.
  auto f = backend::offset_fields(rcx::Op::BranchAlwaysFar, 1000, 700);
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(1000 - f[0] - 128 * f[1] + 128, 700);
  EXPECT_GE(f[0], 128);
  // Forward 300: target = origin + off + 128*ext, bit 7 clear.
  f = backend::offset_fields(rcx::Op::BranchAlwaysFar, 1000, 1300);
  EXPECT_EQ(1000 + f[0] + 128 * f[1], 1300);
  EXPECT_LT(f[0], 128);
  EXPECT_FALSE(backend::reaches(rcx::Op::DecrementLoopCounterNear, 10, 9));
  EXPECT_TRUE(backend::reaches(rcx::Op::DecrementLoopCounterNear, 10, 265));
  EXPECT_FALSE(backend::reaches(rcx::Op::DecrementLoopCounterNear, 10, 266));
  EXPECT_EQ(backend::offset_origin(rcx::Op::TestAndBranchNear), 6);
  EXPECT_EQ(backend::offset_origin(rcx::Op::BranchAlwaysNear), 1);
}

// A copy between two variables that slot allocation put in one slot (the
// source dies where the copy begins) is no instruction from -O1 on; -O0
// keeps it, and a copy between different slots stays at every level.
TEST(Codegen, CopyWithinOneSlotIsLeftOut) {
  Builder b;
  FuncId t = b.function("main");
  VarId x = b.temp(), y = b.temp(), z = b.temp();
  b.block(t, {set(x, I(5)), set(y, V(x)), add(y, I(1)), set(z, V(y))});
  const Bytes set_x{0x14, 0x03, 0x02, 0x05, 0x00}, copy_within{0x14, 0x03, 0x00, 0x03, 0x00},
      add_one{0x24, 0x03, 0x02, 0x01, 0x00}, copy_to_4{0x14, 0x04, 0x00, 0x03, 0x00};
  Diagnostics d;
  backend::GenerateOptions options;
  options.drop_self_copies = true;
  auto dropped = backend::generate(b.p, {3, 3, 4}, d, options);
  ASSERT_TRUE(dropped);
  EXPECT_EQ(dropped->fragments[0].code, cat({set_x, add_one, copy_to_4}));
  auto kept = backend::generate(b.p, {3, 3, 4}, d);
  ASSERT_TRUE(kept);
  EXPECT_EQ(kept->fragments[0].code, cat({set_x, copy_within, add_one, copy_to_4}));
}

// `(b & 7) ^ 3` is `(t | 3) - (t & 3)` with t = b & 7: the second use of t
// copies it into a temporary that takes t's slot, as t dies there.
TEST(Codegen, XorOfAMaskedValueCopiesNothingWithinASlot) {
  const char* text = "int b, c;\ntask main() { b = 13; c = (b & 7) ^ 3; }\n";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = rcxc::test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = rcxc::test::run_image(c.out->image, 100);
    EXPECT_EQ(rcxc::test::global_value(m, c.out->image, "c"), 6);
    int self_copies = 0;
    for (const auto& f : c.out->fragments)
      for (const auto& in : f.instrs)
        self_copies += in.bytes.size() == 5 && in.bytes[0] == 0x14 && in.bytes[2] == 0 && in.bytes[1] == in.bytes[3];
    EXPECT_EQ(self_copies, level == ir::OptLevel::O0 ? 1 : 0) << static_cast<int>(level);
  }
}
