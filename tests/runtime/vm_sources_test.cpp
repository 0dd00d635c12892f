// The 13 RCX sources and the sensor modes, computed from raw values as the
// firmware reference says (hysteresis 460/562, slope rule, edge/pulse counts,
// percent, temperature, rotation).
#include <gtest/gtest.h>

#include "runtime/sensors.h"
#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;
using rcx::kMicrosPerMs;

namespace {

// A machine with no program, for feeding sensor inputs and reading values.
struct Bench {
  rcx::Machine m{ms_config()};
  long t_ms = 0;
  void raw(int sensor, int value) { feed(rcx::SensorRawInput{sensor, value}); }
  void rotation(int sensor, int position) { feed(rcx::RotationInput{sensor, position}); }
  void feed(rcx::Input in) {
    t_ms += 10;
    m.schedule({t_ms * kMicrosPerMs, in});
    m.run_until(t_ms * kMicrosPerMs + 1);
  }
  void direct(Bytes b) { ASSERT_TRUE(m.execute_direct(b).ok); }
  int get(int source, int arg) { return m.get_value(source, arg); }
};

}  // namespace

TEST(VmSources, VariableImmediateProgramMessage) {
  rcx::Machine m(ms_config());
  m.load(2, image({{0, code({set(4, -12), setv(0, VAR, 4), setv(1, IMM, 321), setv(2, PROGRAM, 0), setv(3, MESSAGE, 0)})}}));
  m.select_program(2);
  m.schedule({0, rcx::MessageInput{42}});
  m.start_program();
  m.run(10'000 * kMicrosPerMs);
  EXPECT_EQ(var(m, 0), -12);
  EXPECT_EQ(var(m, 1), 321);
  EXPECT_EQ(var(m, 2), 2);
  EXPECT_EQ(var(m, 3), 42);
}

TEST(VmSources, TimerReadsTenthsSinceCleared) {
  // The firmware's timers have 100 ms resolution, not the seed's 1/100 s
  // (docs/emulator.md). timerclr at 0 ms, wait at 1 ms until 1501 ms: 15.
  // 1593 ms still reads 15 (truncated), 1604 ms reads 16.
  auto m = run_task(code({timerclr(0), wait(150), setv(0, TIMER, 0), setv(1, TIMER, 3), wait(9), setv(2, TIMER, 0),
                          wait(1), setv(3, TIMER, 0)}));
  EXPECT_EQ(var(m, 0), 15);
  EXPECT_EQ(var(m, 1), 15);  // timer 3 counts from power-on (0 ms)
  EXPECT_EQ(var(m, 2), 15);
  EXPECT_EQ(var(m, 3), 16);
}

TEST(VmSources, TimerWrapsAsASigned16BitCountOfTenths) {
  rcx::Machine m(ms_config());
  m.run_until(std::int64_t{3'276'800} * kMicrosPerMs);  // 32768 tenths
  EXPECT_EQ(m.timer_value(0), -32768);
}

TEST(VmSources, SetVariableFromTheCybermasterSourcesReadsZero) {
  // Sources 5-7 exist only on the Cybermaster; Set variable allows every
  // source (seed) and the firmware has no fault state, so the RCX stores 0.
  auto m = run_task(code({set(0, 9), set(1, 9), set(2, 9), setv(0, 5, 0), setv(1, 6, 1), setv(2, 7, 2), set(3, 1)}));
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_EQ(var(m, 2), 0);
  EXPECT_EQ(var(m, 3), 1);
}

TEST(VmSources, RandomIsInRangeAndReproducibleBySeed) {
  Bytes c;
  for (int i = 0; i < 20; ++i) c = code({c, setv(i, RANDOM, 10)});
  auto a = run_task(c);
  auto b = run_task(c);
  rcx::Config other = ms_config();
  other.seed = 99;
  auto d = run(image({{0, c}}), 10'000, other);
  bool differs = false;
  for (int i = 0; i < 20; ++i) {
    EXPECT_GE(var(a, i), 0);
    EXPECT_LE(var(a, i), 10);
    EXPECT_EQ(var(a, i), var(b, i));
    differs = differs || var(a, i) != var(d, i);
  }
  EXPECT_TRUE(differs);
}

TEST(VmSources, MotorStateByte) {
  // A on fwd power 7 = 0x87; B off rev power 3 = 0x40|0x08|3; C float fwd 7 = 7.
  auto m = run_task(code({out(0x81), pwr(0x02, IMM, 3), dir(0x02), out(0x42), setv(0, MOTOR, 0), setv(1, MOTOR, 1),
                          setv(2, MOTOR, 2)}));
  EXPECT_EQ(var(m, 0), 0x87);
  EXPECT_EQ(var(m, 1), 0x4b);
  EXPECT_EQ(var(m, 2), 0x07);
}

TEST(VmSources, ClockInMinutesFromSetTime) {
  // set time 1:30 at 0 ms; wait at 1 ms for 60 s; the clock then reads 91.
  auto m = run_task(code({settime(1, 30), wait(6000), setv(0, CLOCK, 0), settime(24, 0), setv(1, CLOCK, 0)}), 70'000);
  EXPECT_EQ(var(m, 0), 91);
  EXPECT_EQ(var(m, 1), 91);  // hour 24 is invalid: ignored
}

TEST(VmSources, SensorTypeSetsDefaultMode) {
  auto m = run_task(code({senstype(0, 1), senstype(1, 2), senstype(2, 3), setv(0, SENSMODE, 0), setv(1, SENSMODE, 1),
                          setv(2, SENSMODE, 2), setv(3, SENSTYPE, 2), senstype(0, 4), setv(4, SENSMODE, 0),
                          senstype(0, 0), setv(5, SENSMODE, 0), senstype(0, 9), setv(6, SENSTYPE, 0)}));
  EXPECT_EQ(var(m, 0), 1 << 5);  // touch: boolean
  EXPECT_EQ(var(m, 1), 5 << 5);  // temperature: Celsius
  EXPECT_EQ(var(m, 2), 4 << 5);  // light: percent
  EXPECT_EQ(var(m, 3), 3);
  EXPECT_EQ(var(m, 4), 7 << 5);  // rotation: angle
  EXPECT_EQ(var(m, 5), 0);       // raw
  EXPECT_EQ(var(m, 6), 0);       // type 9 ignored
}

TEST(VmSensor, BooleanHysteresis460And562) {
  Bench b;
  EXPECT_EQ(b.get(SENSBOOL, 0), 0);  // open input reads 1023: 0
  b.raw(0, 500);
  EXPECT_EQ(b.get(SENSBOOL, 0), 0);  // between the thresholds: unchanged
  b.raw(0, 460);
  EXPECT_EQ(b.get(SENSBOOL, 0), 0);  // not below 460
  b.raw(0, 459);
  EXPECT_EQ(b.get(SENSBOOL, 0), 1);
  b.raw(0, 562);
  EXPECT_EQ(b.get(SENSBOOL, 0), 1);  // not above 562
  b.raw(0, 563);
  EXPECT_EQ(b.get(SENSBOOL, 0), 0);
  EXPECT_EQ(b.get(SENSRAW, 0), 563);
}

TEST(VmSensor, SlopeRule) {
  Bench b;
  b.direct({0x42, 0, (1 << 5) | 10});  // boolean mode, slope 10
  b.raw(0, 1015);                      // down 8: no change
  EXPECT_EQ(b.get(SENSOR, 0), 0);
  b.raw(0, 1000);                      // down 15 > 10: 1
  EXPECT_EQ(b.get(SENSOR, 0), 1);
  b.raw(0, 1005);                      // up 5: no change
  EXPECT_EQ(b.get(SENSOR, 0), 1);
  b.raw(0, 1020);                      // up 15 > 10: 0
  EXPECT_EQ(b.get(SENSOR, 0), 0);
}

TEST(VmSensor, EdgeAndPulseCountsAndClear) {
  Bench b;
  b.direct({0x42, 1, 2 << 5});  // sensor 2: edge count
  b.direct({0x42, 2, 3 << 5});  // sensor 3: pulse count
  for (int raw : {100, 1000, 100, 1000, 100}) {
    b.raw(1, raw);
    b.raw(2, raw);
  }
  EXPECT_EQ(b.get(SENSOR, 1), 5);
  EXPECT_EQ(b.get(SENSOR, 2), 2);
  b.direct({0xd1, 1});
  EXPECT_EQ(b.get(SENSOR, 1), 0);
}

TEST(VmSensor, PercentFromRaw) {
  EXPECT_EQ(rcx::percent_of_raw(1023), 0);
  EXPECT_EQ(rcx::percent_of_raw(700), (1023 - 700) * 25 / 156);
  EXPECT_EQ(rcx::percent_of_raw(391), 101);  // the firmware's own quirk
  EXPECT_EQ(rcx::percent_of_raw(390), 100);
  EXPECT_EQ(rcx::percent_of_raw(0), 100);
  Bench b;
  b.direct({0x32, 0, 3});  // light
  b.raw(0, 700);
  EXPECT_EQ(b.get(SENSOR, 0), 51);
}

TEST(VmSensor, TemperatureRangeMatchesTheSeed) {
  // The seed: -19.8..69.5 °C and -3.6..157.1 °F, in tenths.
  EXPECT_EQ(rcx::celsius_tenths_of_raw(290), 695);
  EXPECT_EQ(rcx::celsius_tenths_of_raw(928), -198);
  EXPECT_EQ(rcx::fahrenheit_tenths_of_raw(290), 1571);
  EXPECT_EQ(rcx::fahrenheit_tenths_of_raw(928), -36);
  EXPECT_EQ(rcx::celsius_tenths_of_raw(500), (500 * -123 + 93600) / 100);
  EXPECT_EQ(rcx::celsius_tenths_of_raw(289), 0x7fff);
  EXPECT_EQ(rcx::celsius_tenths_of_raw(929), 0x7fff);
  Bench b;
  b.direct({0x32, 0, 2});        // temperature: Celsius
  b.direct({0x32, 1, 2});
  b.direct({0x42, 1, 6 << 5});   // Fahrenheit
  b.raw(0, 290);
  b.raw(1, 290);
  EXPECT_EQ(b.get(SENSOR, 0), 695);
  EXPECT_EQ(b.get(SENSOR, 1), 1571);
}

TEST(VmSensor, RotationInSixteenthsClearedBySensorClear) {
  Bench b;
  b.direct({0x32, 2, 4});  // rotation
  b.rotation(2, 16);
  EXPECT_EQ(b.get(SENSOR, 2), 16);
  b.direct({0xd1, 2});
  EXPECT_EQ(b.get(SENSOR, 2), 0);
  b.rotation(2, 20);
  EXPECT_EQ(b.get(SENSOR, 2), 4);
  b.rotation(2, 9);
  EXPECT_EQ(b.get(SENSOR, 2), -7);
}

TEST(VmSensor, SetModeClearsTheValue) {
  Bench b;
  b.direct({0x42, 0, 2 << 5});
  b.raw(0, 100);
  EXPECT_EQ(b.get(SENSOR, 0), 1);
  b.direct({0x42, 0, 2 << 5});
  EXPECT_EQ(b.get(SENSOR, 0), 0);
}

TEST(VmSensor, ProgramSeesScheduledInputs) {
  // until (SENSOR_1 == 1) with a touch sensor; pressed at 500 ms.
  rcx::Machine m(ms_config());
  // 0 senstype; 3 var31 = 1; 8 chk sensor == var31 -> 17 (14 + 3); 15 jmp back to 8 (16 - 136 + 128); 17 out.
  m.load(0, image({{0, code({senstype(0, 1), set(31, 1), chk(3, SENSOR, 0, VAR, 31, 3), jmp(136), out(0x81)})}}));
  m.schedule({500 * kMicrosPerMs, rcx::SensorRawInput{0, 50}});
  m.start_program();
  m.run(5'000 * kMicrosPerMs);
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_GE(outs[0].t_us, 500 * kMicrosPerMs);
  EXPECT_LE(outs[0].t_us, 510 * kMicrosPerMs);
}
