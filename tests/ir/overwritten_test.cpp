// Motor commands the next block overwrites at once (ir/overwritten.cpp).
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

// Block 0 runs `first` and jumps to block 1, which runs `then`.
std::size_t kept_of(std::vector<Instr> first, std::vector<Instr> then) {
  Builder b;
  FuncId f = b.function("main");
  b.block(f, std::move(first), Jump{1});
  b.block(f, std::move(then));
  std::size_t before = b.fn(0).blocks[0].instrs.size();
  Log log;
  drop_motor_commands_overwritten_next(b.fn(0), log);
  EXPECT_EQ(log.size(), before - b.fn(0).blocks[0].instrs.size());
  return b.fn(0).blocks[0].instrs.size();
}

// Encoded motor bytes: outputs A=1, B=2, C=4; on 0x80, off 0x40, float
// 0; forward 0x80, reverse 0, flip 0x40.
constexpr int A = 1, C = 4;

}  // namespace

TEST(Overwritten, AnOffBeforeTheSameOffGoes) {
  // if (c) { ...; Off(OUT_A+OUT_C); } Off(OUT_A+OUT_C);
  EXPECT_EQ(kept_of({sound(1), out(0x40 | A | C)}, {out(0x40 | A | C), sound(2)}), 1u);
}

TEST(Overwritten, AnOffBeforeAnOffOfMoreOutputsGoes) {
  EXPECT_EQ(kept_of({out(0x40 | A)}, {out(0x40 | A | C)}), 0u);
}

TEST(Overwritten, AnOffBeforeAnOnStays) {
  // OnFor(OUT_A, t) ending a call before OnRev(OUT_A): the output brakes
  // for the time of a jump, which a program pulsing a lamp may mean.
  EXPECT_EQ(kept_of({out(0x40 | A)}, {dir(A), out(0x80 | A)}), 1u);
  EXPECT_EQ(kept_of({dir(0x80 | A)}, {dir(A)}), 1u);
  EXPECT_EQ(kept_of({pwr(A, 3)}, {pwr(A, 5)}), 1u);
}

TEST(Overwritten, ACommandOnAnOutputTheNextOneLeavesStays) {
  EXPECT_EQ(kept_of({out(0x40 | A | C)}, {out(0x80 | A)}), 1u);
}

TEST(Overwritten, AnotherFieldStays) {
  // A direction does not overwrite an on/off mode, nor a power.
  EXPECT_EQ(kept_of({out(0x40 | A)}, {dir(0x80 | A)}), 1u);
  EXPECT_EQ(kept_of({pwr(A, 3)}, {dir(0x80 | A)}), 1u);
}

TEST(Overwritten, AFlipOrAPowerTheFirmwareMayIgnoreSetsNothingAgain) {
  // A flip reverses what the first command set; a power outside 0..7, or
  // in a variable, has no value known here.
  EXPECT_EQ(kept_of({dir(0x40 | A)}, {dir(0x40 | A)}), 1u);
  EXPECT_EQ(kept_of({pwr(A, 9)}, {pwr(A, 9)}), 1u);
  Builder b;
  VarId x = b.local("x");
  FuncId f = b.function("main");
  b.block(f, {pwr(A, 3)}, Jump{1});
  b.block(f, {op(rcx::Op::SetMotorPower, {I(A), V(x)})});
  Log log;
  drop_motor_commands_overwritten_next(b.fn(0), log);
  EXPECT_EQ(b.fn(0).blocks[0].instrs.size(), 1u);
  EXPECT_EQ(kept_of({pwr(A, 3)}, {pwr(A | C, 3)}), 0u);
}

TEST(Overwritten, AnInstructionBetweenKeepsTheCommand) {
  // The wait would let the output run off for its time.
  EXPECT_EQ(kept_of({out(0x40 | A)}, {wait(I(10)), out(0x80 | A)}), 1u);
}

TEST(Overwritten, AnotherValueOfTheFieldBetweenKeepsTheCommand) {
  // Off(OUT_A+OUT_C) before a loop of On(OUT_A); Off(OUT_A+OUT_B+OUT_C):
  // A goes off, on and off again; without the first off it would not.
  EXPECT_EQ(kept_of({out(0x40 | A | C)}, {out(0x80 | A), out(0x40 | A | 2 | C)}), 1u);
  // Float(OUT_A) before Toggle(OUT_A); Float(OUT_A): the flip is hidden
  // only while A floats.
  EXPECT_EQ(kept_of({out(A)}, {dir(0x40 | A), out(A)}), 1u);
  // A command on another output between changes nothing of A's.
  EXPECT_EQ(kept_of({out(0x40 | A | C)}, {dir(2), out(0x80 | 2), out(0x40 | A | 2 | C)}), 0u);
}
