// Hand-encoded RCX instructions for emulator tests. Every byte here is taken
// from the firmware reference (seeds/000), independently of the project's
// opcode table, so the tests check the table-driven decoder against the seed.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace vmtest {

using Bytes = std::vector<std::uint8_t>;

inline std::uint8_t lo(int v) { return static_cast<std::uint8_t>(v & 0xff); }
inline std::uint8_t hi(int v) { return static_cast<std::uint8_t>((v >> 8) & 0xff); }

// Concatenates instruction byte lists.
inline Bytes code(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

constexpr int VAR = 0, TIMER = 1, IMM = 2, MOTOR = 3, RANDOM = 4, PROGRAM = 8, SENSOR = 9, SENSTYPE = 10,
              SENSMODE = 11, SENSRAW = 12, SENSBOOL = 13, CLOCK = 14, MESSAGE = 15;

inline Bytes var_op(std::uint8_t op, int var, int src, int arg) { return {op, lo(var), lo(src), lo(arg), hi(arg)}; }
inline Bytes setv(int var, int src, int arg) { return var_op(0x14, var, src, arg); }
inline Bytes set(int var, int value) { return setv(var, IMM, value); }
inline Bytes add(int var, int value) { return var_op(0x24, var, IMM, value); }
inline Bytes sub(int var, int value) { return var_op(0x34, var, IMM, value); }
inline Bytes mul(int var, int value) { return var_op(0x54, var, IMM, value); }
inline Bytes div(int var, int src, int arg) { return var_op(0x44, var, src, arg); }
inline Bytes band(int var, int value) { return var_op(0x84, var, IMM, value); }
inline Bytes bor(int var, int value) { return var_op(0x94, var, IMM, value); }
inline Bytes abs_(int var, int value) { return var_op(0x74, var, IMM, value); }
inline Bytes sgn(int var, int value) { return var_op(0x64, var, IMM, value); }
inline Bytes wait(int ticks) { return {0x43, IMM, lo(ticks), hi(ticks)}; }
inline Bytes waitv(int src, int arg) { return {0x43, lo(src), lo(arg), hi(arg)}; }
inline Bytes out(int code) { return {0x21, lo(code)}; }
inline Bytes dir(int code) { return {0xe1, lo(code)}; }
inline Bytes pwr(int motors, int src, int arg) { return {0x13, lo(motors), lo(src), lo(arg)}; }
// Test and branch near: compare op (0 <=, 1 >=, 2 !=, 3 ==), offset relative to the offset byte.
inline Bytes chk(int op, int src1, int arg1, int src2, int arg2, int offset) {
  return {0x85, lo((op << 6) | src1), lo(src2), lo(arg1), hi(arg1), lo(arg2), lo(offset)};
}
inline Bytes chkl(int op, int src1, int arg1, int src2, int arg2, int offset) {
  return {0x95, lo((op << 6) | src1), lo(src2), lo(arg1), hi(arg1), lo(arg2), lo(offset), hi(offset)};
}
inline Bytes jmp(int offset_byte) { return {0x27, lo(offset_byte)}; }
inline Bytes jmpl(int offset_byte, int extension) { return {0x72, lo(offset_byte), lo(extension)}; }
inline Bytes loops(int src, int arg) { return {0x82, lo(src), lo(arg)}; }
inline Bytes loopc(int offset) { return {0x37, lo(offset)}; }
inline Bytes loopcl(int offset) { return {0x92, lo(offset), hi(offset)}; }
inline Bytes call(int s) { return {0x17, lo(s)}; }
inline Bytes ret() { return {0xf6}; }
inline Bytes start(int t) { return {0x71, lo(t)}; }
inline Bytes stop(int t) { return {0x81, lo(t)}; }
inline Bytes stopall() { return {0x50}; }
inline Bytes deltask(int t) { return {0x61, lo(t)}; }
inline Bytes delsub(int s) { return {0xc1, lo(s)}; }
inline Bytes sound(int n) { return {0x51, lo(n)}; }
inline Bytes tone(int freq, int duration) { return {0x23, lo(freq), hi(freq), lo(duration)}; }
inline Bytes logsize(int n) { return {0x52, lo(n), hi(n)}; }
inline Bytes lognext(int src, int arg) { return {0x62, lo(src), lo(arg)}; }
inline Bytes senstype(int s, int type) { return {0x32, lo(s), lo(type)}; }
inline Bytes sensmode(int s, int code) { return {0x42, lo(s), lo(code)}; }
inline Bytes sensclr(int s) { return {0xd1, lo(s)}; }
inline Bytes timerclr(int t) { return {0xa1, lo(t)}; }
inline Bytes display(int src, int arg) { return {0x33, lo(src), lo(arg), hi(arg)}; }
inline Bytes msgsend(int src, int arg) { return {0xb2, lo(src), lo(arg)}; }
inline Bytes msgclr() { return {0x90}; }
inline Bytes msgset(int v) { return {0xf7, lo(v)}; }
inline Bytes settime(int h, int m) { return {0x22, lo(h), lo(m)}; }
inline Bytes sleepdelay(int m) { return {0xb1, lo(m)}; }
inline Bytes poweroff() { return {0x60}; }
inline Bytes program(int n) { return {0x91, lo(n)}; }

using Fragments = std::initializer_list<std::pair<int, Bytes>>;

inline rcx::Image image(Fragments tasks, Fragments subs = {}) {
  rcx::Image img;
  for (const auto& [i, c] : tasks) img.fragments.push_back({rcx::FragmentType::Task, static_cast<std::uint8_t>(i), c});
  for (const auto& [i, c] : subs) img.fragments.push_back({rcx::FragmentType::Subroutine, static_cast<std::uint8_t>(i), c});
  return img;
}

// 1 ms per instruction keeps the timing arithmetic in tests readable.
inline rcx::Config ms_config() {
  rcx::Config c;
  c.instruction_cost_us = 1000;
  return c;
}

// Loads `img` in slot 0, starts task 0 and runs to the end (or `limit_ms`).
inline rcx::Machine run(const rcx::Image& img, long limit_ms = 10'000, rcx::Config config = ms_config()) {
  rcx::Machine m(config);
  m.load(0, img);
  m.start_program();
  m.run(limit_ms * rcx::kMicrosPerMs);
  return m;
}

inline rcx::Machine run_task(const Bytes& task0, long limit_ms = 10'000) { return run(image({{0, task0}}), limit_ms); }

inline int var(const rcx::Machine& m, int i) { return m.state().vars[static_cast<std::size_t>(i)]; }

inline std::vector<rcx::Event> events_of(const rcx::Machine& m, rcx::EventKind kind) {
  std::vector<rcx::Event> out;
  for (const auto& e : m.state().events)
    if (e.kind == kind) out.push_back(e);
  return out;
}

}  // namespace vmtest
